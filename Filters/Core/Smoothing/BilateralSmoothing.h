// SPDX-License-Identifier: BSD-3-Clause
// Bilateral smoothing of a per-face scalar field (the SDF) on small mesh neighbourhoods.
//
// Paper: Shapira, Shamir, Cohen-Or 2008, "Consistent mesh partitioning and skeletonisation
// using the shape diameter function", section 3, implemented as written:
//
//   f^0(x)     = f(x)
//   f^{i+1}(x) = (f^i(x) + sum_y c(|f^i(x) - f(y)|) w_x(y) f(y)) / (1 + sum_y c(|f^i(x) - f(y)|) w_x(y))
//
//   The centre keeps weight 1 and uses its current value f^i(x); the neighbours y contribute
//   their ORIGINAL values f(y). w_x(y) = exp(-d(x, y)^2 / (2 sigma^2)) with d the geodesic
//   distance between face centres; c(x) = 1 for x <= t, 0 above (the paper's clamp).
//
// Consequences of the paper's form that the implementation exploits
//   - f^{i+1}(x) depends only on f^i(x) and the original field, so every face iterates on
//     its own: each neighbourhood is computed once and reused by all iterations, nothing of
//     size (faces x neighbours) is stored, and the result is independent of the order and
//     of the thread split (bit-identical for any ParallelFor).
//   - Evaluated as f^i(x) + sum_y (c w / (1 + sum c w)) (f(y) - f^i(x)), algebraically the
//     same; it keeps a constant field bit-exactly constant and cannot overflow.
//
// Neighbourhood (the paper: "small mesh neighborhoods")
//   d is approximated by Dijkstra over the dual graph (DualGeodesicSearch in FaceGraph.h):
//   the faces within dual distance radius of x, nearest first, at most MaxNeighbors.
//
// Parameters (BilateralSmoothingOptions; default, valid range)
//   NumberOfIterations  i          3,    [0, 100]; 0 returns the input unchanged.
//   SpatialSigma        sigma      1.0,  [0.01, 100] in units of the mesh's mean edge length
//                                  (FaceGraph::MeanEdgeLength): the smoothing acts on the
//                                  noise scale of the face-wise SDF, on any mesh scale.
//   NeighborhoodRadius             2.0,  [0, 10] in units of sigma (Gaussian cut at 2 sigma,
//                                  weight e^-2 = 0.14 at the rim); a few tens of faces on a
//                                  regular mesh, capped by MaxNeighbors.
//   MaxNeighbors                   24,   [0, inf): the cost cap on meshes whose triangles are
//                                  far smaller than the mean (nearest kept).
//   RangeThreshold      t          0.1,  [0, 10] as a fraction of the input's robust spread
//                                  Q(0.98) - Q(0.02) (Q: quantile of the face values, nearest
//                                  rank; max - min when that spread is 0). Differences larger
//                                  than t are edges of the field and are kept sharp. A t
//                                  above max - min is capped there (the same result).
//   The ranges are the Range constants below the options, the filter's (vtkSDFBilateralSmooth)
//   clamps; before they were the core's own, wider ones: NumberOfIterations [0, 1000],
//   SpatialSigma (0, inf), NeighborhoodRadius and RangeThreshold [0, inf).
//
// Degenerate cases, all defined
//   - Faces without neighbours (isolated faces, zero radius) keep their value.
//   - Several components: neighbourhoods never cross components.
//   - Open boundaries: boundary faces just have fewer neighbours.
//   - Non-manifold edges: all faces around such an edge are neighbours (FaceGraph).
//   - A constant field (or a mesh whose mean edge length is 0) is returned unchanged.
//   - Empty input: empty output.
// Bad input (throws Error): values.size() != face count, a non-finite
// value, an option outside its range, max - min overflowing a double.
//
// Progress and abort: with a callback, the faces are processed in 20 blocks (each one
// ParallelFor call); after each block progress(fraction) is called from the calling
// thread. When it returns false, the remaining faces keep their input value and the
// result says Aborted. Without a callback: one ParallelFor call over all faces.
//
// Cost: per face one bounded Dijkstra (at most MaxNeighbors settled faces) and
// NumberOfIterations passes over its neighbours: linear in the faces (measurements:
// docs/performance.md).
// No per-mesh scratch memory beyond the output.
//
// Deviations from the paper
//   - The paper does not define the neighbourhood size, sigma or t; the defaults above are
//     ours (relative to mesh resolution and SDF spread so they transfer between meshes).
//   - Geodesic distance between face centres is the dual-graph approximation (see above).
//   - The smoothing section speaks of neighbourhoods "around each vertex"; the field is
//     per face here (as the paper's partitioning uses it), so neighbourhoods are of faces.
#pragma once

#include "Errors.h"
#include "Mesh/FaceGraph.h"
#include "Parallel.h"
#include "ProcessGroup.h"

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace shapediameter
{

struct BilateralSmoothingOptions
{
  /// Number of iterations of the update (paper: "a small number"). SmoothingIterationsRange [0, 100].
  int NumberOfIterations = 3;
  /// sigma of the spatial Gaussian w_x(y), in mean edge lengths. SpatialSigmaRange [0.01, 100].
  double SpatialSigma = 1.0;
  /// Geodesic neighbourhood radius, in units of SpatialSigma. NeighborhoodRadiusRange [0, 10].
  double NeighborhoodRadius = 2.0;
  /// At most this many (nearest) neighbours per face. Range [0, inf) (not a filter property,
  /// any std::size_t; not checked).
  std::size_t MaxNeighbors = 24;
  /// Range clamp t of c(x), as a fraction of the robust spread Q(0.98) - Q(0.02).
  /// RangeThresholdRange [0, 10].
  double RangeThreshold = 0.1;
};

// The ranges of the user-facing options, checked by SmoothBilateral; vtkSDFBilateralSmooth's
// vtkSetClampMacro repeats these numbers (Testing/Filters/TestParameterRanges.cxx).
/// NumberOfIterations. Was [0, 1000] in the core before; the filter has always clamped to [0, 100].
inline constexpr Range<int> SmoothingIterationsRange{ 0, 100 };
/// SpatialSigma, mean edge lengths. Was (0, inf) in the core before; the filter's [0.01, 100].
inline constexpr Range<double> SpatialSigmaRange{ 0.01, 100.0 };
/// NeighborhoodRadius, sigmas. Was [0, inf) in the core before; the filter's [0, 10].
inline constexpr Range<double> NeighborhoodRadiusRange{ 0.0, 10.0 };
/// RangeThreshold, robust spreads. Was [0, inf) in the core before; the filter's [0, 10] (any t
/// of at least (max - min) / spread is capped to the same result).
inline constexpr Range<double> RangeThresholdRange{ 0.0, 10.0 };

struct BilateralSmoothingResult
{
  /// Smoothed value per face, all finite.
  std::vector<double> Values;
  /// The progress callback asked to stop; unprocessed faces keep their input value.
  bool Aborted = false;
  /// The absolute parameters used (value units and length units).
  double RangeThreshold = 0.0;
  double SpatialSigma = 0.0;
  double NeighborhoodRadius = 0.0;
};

/// The robust spread used to scale t: Q(0.98) - Q(0.02), or max - min when that is 0.
double RobustSpread(const std::vector<double>& values);

/// The absolute neighbourhood radius the options give on a surface of this mean edge length:
/// NeighborhoodRadius x (SpatialSigma x meanEdgeLength), as SmoothBilateral uses it (the halo
/// of a distributed run is sized and checked with the same number).
inline double NeighborhoodRadiusOf(const BilateralSmoothingOptions& options, double meanEdgeLength)
{
  return options.NeighborhoodRadius * (options.SpatialSigma * meanEdgeLength);
}

/// RobustSpread of the union of every process's `values` (each process passes its own faces'),
/// the same on every process and equal to RobustSpread of all the values in one vector.
/// Collective (ProcessGroup.h).
double RobustSpreadOverProcesses(const std::vector<double>& values, const ProcessGroup& group);

/**
 * A distributed run's part of the surface: `graph` holds this process's faces and a halo of
 * their neighbours (every face within the neighbourhood radius of one of its own), and the
 * scales come from the whole surface instead of the graph. Only the faces with Own[f] != 0
 * are smoothed (the others keep their value); with the whole surface's measures and a halo
 * that wide, each is smoothed exactly as in a serial run on the whole surface.
 */
struct SmoothingShare
{
  /// One flag per face of the graph: 1 = smoothed here.
  const std::vector<std::uint8_t>& Own;
  /// FaceGraph::MeanEdgeLength of the whole surface.
  double MeanEdgeLength = 0.0;
  /// RobustSpread, minimum and maximum of the whole surface's values.
  double Spread = 0.0;
  double Minimum = 0.0;
  double Maximum = 0.0;
};

/// Smooths one value per face of `graph` (see the header comment); with a `share`, only its
/// own faces, scaled by its whole-surface measures.
BilateralSmoothingResult SmoothBilateral(const FaceGraph& graph, const std::vector<double>& values,
  const BilateralSmoothingOptions& options = {}, const ParallelFor& parallelFor = SerialFor,
  const ProgressCallback& progress = nullptr, const SmoothingShare* share = nullptr);

} // namespace shapediameter
