// SPDX-License-Identifier: BSD-3-Clause
// Bilateral smoothing and log normalisation of the per-face SDF, as one call.
//
// What it computes
//   The smoothed and the normalised shape diameter of every face of a polygon surface: the
//   paper's bilateral smoothing of the SDF (section 3) and its log normalisation to [0, 1]
//   with alpha = 4 (section 4, before the partition's clustering), in three steps:
//     1. SharedFaceGraph       - the dual graph: neighbourhoods and mean edge length (FaceGraph.h;
//                                reused when a graph of the same surface is still held)
//     2. SmoothBilateral       - the paper's bilateral filter over geodesic face neighbourhoods
//                                (BilateralSmoothing.h)
//     3. NormalizeLogarithmic  - nsdf = log((f - min) / (max - min) alpha + 1) / log(alpha + 1),
//                                over a range of the faces only, and the [min, max] it used
//                                (NormalizationRange; Normalization.h)
//   Each step's own header documents its method, parameters, degenerate cases and deviations
//   from the paper; this file only chains them and times the steps.
//
// Reference
//   Shapira, Shamir, Cohen-Or 2008, "Consistent mesh partitioning and skeletonisation using
//   the shape diameter function", The Visual Computer 24(4), sections 3 and 4.
//
// Input (SmoothAndNormalizeInput; views of the caller's arrays, which must outlive the call)
//   Points, FaceOffsets, FaceConnectivity  the polygons in CSR form, as BuildFaceGraph takes
//                                          them (any polygon size; a face without corners has
//                                          no neighbour and keeps its value).
//   FaceValues      one SDF value per face, finite (VTK: `SDF`).
//   NormalizedFirst, NormalizedLast  the faces [first, last) that are normalised, and whose
//                   min and max define the range: the VTK adapter passes its polygon cells, so
//                   that vertices, lines and strips (whose values are fill values) do not drag
//                   min and max. The triangle overload normalises every face.
//
// Parameters (SmoothAndNormalizeOptions; defaults and valid ranges in the steps' headers)
//   Smoothing       BilateralSmoothingOptions: NumberOfIterations 3 [0, 100], SpatialSigma
//                   sigma 1.0 [0.01, 100] mean edge lengths, NeighborhoodRadius 2.0 [0, 10]
//                   sigmas, MaxNeighbors 24, RangeThreshold t 0.1 [0, 10] of the robust spread.
//   Normalization   NormalizationOptions: Alpha 4 [0.001, 1000] (AlphaRange, checked here before
//                   any work; NormalizeLogarithmic alone accepts (0, DBL_MAX]) (the paper's
//                   value), and an optional given range [RangeMinimum, RangeMaximum] for a family
//                   of meshes.
//   These ranges are the Range constants of the two steps' headers and the filter's clamps.
//
// Errors
//   NormalizedFirst > NormalizedLast or NormalizedLast > face count -> Error.
//   The steps throw Error (Errors.h) with a one-line reason on what they cannot process
//   (smoothing: values of another size than the face count, a non-finite value, an option out
//   of range; normalisation: a given range out of range). Alpha outside AlphaRange -> Error before
//   any work. No faces: empty result, not
//   an error.
//
// Threading and determinism
//   parallelFor runs the face graph and the smoothing; the result is bit-identical for any
//   ParallelFor. With a FaceShare (distributed runs) every process must call it with its own
//   share; bad input throws before the first collective, and an abort on one process aborts
//   all (no process returns early without joining the others). progress receives [0, 1] (0.1 after the face graph, the smoothing in
//   [0.1, 0.95], 1 at the end); returning false after the face graph or during the smoothing
//   aborts: the result is then empty with Aborted = true.
#pragma once

#include "Errors.h"
#include "Smoothing/BilateralSmoothing.h"
#include "Mesh/FaceGraph.h"
#include "Mesh/MeshTypes.h"
#include "Smoothing/Normalization.h"
#include "Parallel.h"
#include "ProcessGroup.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <vector>

namespace shapediameter
{

struct SmoothAndNormalizeOptions
{
  /// The bilateral filter (BilateralSmoothing.h).
  BilateralSmoothingOptions Smoothing;
  /// The log normalisation, alpha and an optional family range (Normalization.h).
  NormalizationOptions Normalization;
};

/**
 * A distributed run's part of the surface (SmoothAndNormalizeInput::Share): the input holds
 * this process's own faces and a halo, every face within the smoothing's neighbourhood radius
 * (NeighborhoodRadius x SpatialSigma x the whole surface's mean edge length, dual distance) of
 * an own face, with the faces and points in the order of the whole surface (e.g. sorted by
 * global id). Each process of `Group` calls SmoothAndNormalize with its own share at the same
 * time: the mean edge length, the robust spread, the value range and the normalisation range
 * are then the whole surface's (ProcessGroup.h), and each own face gets exactly the values a
 * serial run on the whole surface gives it. Halo faces are read only; their results are
 * meaningless (their own process computes them).
 */
struct FaceShare
{
  /// One flag per face of the input: 1 = this process's face (smoothed and normalised here).
  const std::vector<std::uint8_t>& Own;
  const ProcessGroup& Group;
  /// One flag per face: 1 = counted in the whole surface's measures by this process. A face
  /// that several processes own must be counted by one of them only; null: Own.
  const std::vector<std::uint8_t>* Counted = nullptr;
  /// The distance around the own faces the halo covers, when known (0: not checked). A
  /// neighbourhood radius above it, known once the whole surface's mean edge length is,
  /// throws HaloTooNarrowError on every process.
  double HaloWidth = 0.0;
};

/// What is smoothed and normalised; see the header comment.
struct SmoothAndNormalizeInput
{
  PointsView Points;
  const std::vector<std::int64_t>& FaceOffsets;
  const std::vector<std::int64_t>& FaceConnectivity;
  const std::vector<double>& FaceValues;
  /// The faces [NormalizedFirst, NormalizedLast) are normalised.
  std::size_t NormalizedFirst = 0;
  std::size_t NormalizedLast = 0;
  /// A distributed run's part of the surface (FaceShare); null: the input is the whole surface.
  const FaceShare* Share = nullptr;
};

/// Wall-clock time of each step in ms (for benchmarks; not part of the result's meaning).
struct SmoothAndNormalizeTimings
{
  double FaceGraphMs = 0.0;
  double SmoothingMs = 0.0;
  /// The normalisation and its range.
  double NormalizationMs = 0.0;
};

struct SmoothAndNormalizeResult
{
  /// Smoothed value of every face, finite (`SDFSmoothed`).
  std::vector<double> Smoothed;
  /// nsdf in [0, 1] of the faces [NormalizedFirst, NormalizedLast), in that order
  /// (`SDFNormalized`).
  std::vector<double> Normalized;
  /// The [min, max] mapped to [0, 1]: the given range or the normalised faces' own (0, 0 when
  /// none is normalised) (`SDFNormalizationRange`).
  double RangeMinimum = 0.0;
  double RangeMaximum = 0.0;
  SmoothAndNormalizeTimings Timings;
  /// The face graph used (SharedFaceGraph): holding it lets the next step of the chain that
  /// gets the same surface, such as the partition, reuse it instead of building its own.
  std::shared_ptr<const FaceGraph> Graph;
  /// True if the progress callback aborted the computation (the other members are then empty).
  bool Aborted = false;
};

/// The smoothing and normalisation of sections 3-4. See the header comment.
SmoothAndNormalizeResult SmoothAndNormalize(const SmoothAndNormalizeInput& input,
  const SmoothAndNormalizeOptions& options = {}, const ParallelFor& parallelFor = SerialFor,
  const ProgressCallback& progress = {});

/// Convenience: a triangle mesh, every face normalised.
SmoothAndNormalizeResult SmoothAndNormalize(PointsView points, TrianglesView triangles,
  const std::vector<double>& faceValues, const SmoothAndNormalizeOptions& options = {},
  const ParallelFor& parallelFor = SerialFor, const ProgressCallback& progress = {});

} // namespace shapediameter
