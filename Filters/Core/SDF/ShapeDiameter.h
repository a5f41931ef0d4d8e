// SPDX-License-Identifier: BSD-3-Clause
// ShapeDiameter: the shape diameter function f_v of Shapira, Shamir & Cohen-Or 2008, Sect. 3.
//
// Entry points: ComputeShapeDiameter and ComputeFaceShapeDiameter (SDF.h) run this file's
// ComputeExactShapeDiameter or, in ShapeDiameterMode::Adaptive, ComputeAdaptiveShapeDiameter
// (AdaptiveShapeDiameter.h). This file holds the Exact mode and what both modes share.
//
// What it computes
//   For each origin p (a face centre by default, or a vertex) with outward unit normal n:
//   1. cast NumberOfRays rays from p inside the cone of full opening angle ConeAngle
//      around the inward normal -n (pattern and frame: ConeSampling.h);
//   2. keep each ray's VALID hit under options.Rule (RayCaster.h; p's own face is never hit):
//      HitRule::FirstHitLeaving (the default) takes the ray's first hit and keeps it only when
//      the ray leaves the volume there; HitRule::SkipSameFacing ignores hits on triangles
//      facing the same way as n and goes on to the next surface. A ray with no valid hit is
//      dropped ("the outliers removal method removes rays with no intersection at all");
//   3. of the remaining lengths L_i, keep those with |L_i - median| <= sigma, where median is
//      the usual median (mean of the two middle values for an even count) and sigma is the
//      population standard deviation of the L_i about their MEAN (divide by the count). The
//      paper says "within one standard deviation from the median" without saying about what
//      the deviation is taken; the ordinary standard deviation is our reading. Mathematically
//      sigma >= half the gap between the two middle values, so at least one ray is always
//      kept; the threshold is max(sigma, that half gap) to keep this true under rounding;
//   4. f_v(p) = sum(w_i L_i) / sum(w_i) over the kept rays, w_i = 1 / angle(ray_i, axis)
//      (ConeSampling.h defines the floor for a ray on the axis).
//   Outputs per origin: Values (length units of the mesh) and ValidRays (rays kept in step 3).
//
// Parameters (ShapeDiameterOptions)
//   NumberOfRays      default 30 (paper), range [1, 4096].
//   ConeAngle  default 120 (paper, full opening angle), range [1, 179] (the filter's; the
//                     cone sampling alone accepts (0, 180)).
//   VertexOriginOffset default 1e-6, range [0, 1e-2], RELATIVE TO THE MESH BOUNDING-BOX
//                     DIAGONAL: origins without a source triangle (vertices) ignore hits
//                     closer than this (Embree's tnear), because a vertex lies on all its
//                     incident triangles and must not hit them at t ~ 0. Face origins use 0:
//                     their own triangle is excluded by index instead.
//   OriginsPerChunk   default 256, >= 1: unit of work given to the ParallelFor and of
//                     progress/abort checks. Does not change any result.
//   Mode              default Exact: every origin casts its cone (the paper). Adaptive casts
//                     a subset whose spacing follows the local SDF and interpolates the
//                     rest over the surface (AdaptiveShapeDiameter.h); it needs the origins'
//                     neighbours (RayOrigins::NeighborOffsets / Neighbors).
//   Tolerance         default 0.15, range [0.001, 1]: Adaptive only, relative SDF difference
//                     between neighbouring cast origins above which more origins are cast.
//   SpacingFraction   default 0.5, range (0, 8]: Adaptive only, spacing of the cast
//                     origins as a fraction of the local SDF.
//
// Consequences of the two readings of the paper's validity rule
//   FirstHitLeaving (default) tests the hit normal against the RAY: from inside a closed
//   body every first hit is a leaving one, so the whole cone counts, and a ray whose first
//   hit enters the volume (it started in a fold, or another part crosses in front of it) is
//   dropped rather than carried on into that part, which is what makes the value depend less
//   on the pose (docs/sdf.md).
//   SkipSameFacing tests it against the ORIGIN normal. On a round body a ray theta off the
//   inward normal lands where the normal is 180 - 2 theta degrees from the origin normal, so
//   on a sphere every ray with theta >= 45 degrees is skipped and goes on (out of the body,
//   possibly into another part): the default 120-degree cone acts like a 90-degree one (18 of
//   the 30 default rays count), and its values on round bodies are larger than
//   FirstHitLeaving's. On a cylinder only the angle within the cross-section counts, so more
//   rays survive; between flat parallel walls all 30 do. A skipped ray that leaves the body
//   can reach the far wall of another part or component, which is valid under this reading;
//   the median +- sigma filter usually, not always, removes it.
//
// Deviations from the paper (which leaves these open)
//   - The validity rule is read as FirstHitLeaving by default (CGAL's reading); the paper's
//     "ignore and continue" reading is HitRule::SkipSameFacing.
//   - The ray pattern (golden-angle spiral, uniform in solid angle) and the weight of a ray
//     on the axis: ConeSampling.h.
//   - sigma is taken about the mean (see step 3).
//   - Origins buried inside another part get no value and are filled (see "Buried origins").
//   - "Angle difference less than 90 degrees" includes a 1e-6 tolerance on the cosine (both
//     rules) so that walls exactly perpendicular to the test direction are decided the same
//     way whatever the rounding (RayCaster.h); this keeps symmetric meshes invariant under
//     rigid motions.
//   - The paper computes f_v at face centres and says nothing about faces without a valid
//     ray; FillFromNeighbors is our documented fill. Vertex origins are an option.
//
// Buried origins (ours; IgnoreBuriedFaces, default on)
//   Posed characters often self-intersect (a paw pushed into the torso, skinning folds at a
//   joint). A face inside another part's volume has no thickness of its own to measure: its
//   rays leave the enclosing part's surface first, a short distance away, so its value
//   collapses in the poses where it is buried and not in the others (measurements on pose
//   families: docs/sdf.md, "Buried faces"). One extra ray per origin, along the outward normal from
//   the origin: when the first surface it meets is LEFT (FirstHitLeaving finds a hit), the
//   point just outside the surface is inside the volume, and the origin gets value 0 and
//   ValidRays 0 like an origin without a valid ray, so FillFromNeighbors gives it its
//   unburied neighbours' values (a buried origin casts no cone). A watertight mesh without
//   self-intersections has no buried origin. A closed component lying wholly inside another
//   (an eyeball in a closed head) is buried everywhere and gets FillFromNeighbors' fallback,
//   the median of the mesh. Cost: 1 ray beside the cone's NumberOfRays.
//
// Degenerate cases
//   - An origin listed in Skip, or with a non-finite point or a zero/non-finite normal, is not
//     cast: value 0, ValidRays 0. MakeFaceOrigins marks zero-area faces this way.
//   - An origin whose rays all miss (open mesh, inverted orientation, ...) gets value 0 and
//     ValidRays 0. FillFromNeighbors then replaces every validRays == 0 value (see below).
//   - Inverted (inward-facing) triangles: the cone points outward. On a convex component no
//     ray hits anything, the whole component becomes invalid and receives the fallback of
//     FillFromNeighbors; on a non-convex one the rays measure the gaps between parts. The
//     core does not re-orient meshes; the adapter does (AutoOrient).
//   - No NaN or Inf is ever written to values.
//
// Threads and determinism: the loop runs over chunks of origins through the given
// ParallelFor; every origin's result depends on that origin only, so SerialFor and any
// ThreadedFor give bit-identical results. The ProgressCallback is called once per finished
// chunk (possibly from a worker thread, never concurrently; it must not throw) with the
// fraction done; returning false aborts: the remaining chunks are skipped, Aborted is set and
// unprocessed origins keep value 0 / ValidRays 0.
#pragma once

#include "Errors.h"
#include "Mesh/MeshTypes.h"
#include "Parallel.h"
#include "RayCasting/ConeSampling.h"
#include "RayCasting/RayCaster.h"

#include <cstdint>
#include <stdexcept>
#include <vector>

namespace shapediameter
{

/// How ComputeShapeDiameter (SDF.h) evaluates the origins.
enum class ShapeDiameterMode
{
  Exact,   ///< every origin casts its cone (the paper)
  Adaptive ///< a subset casts, the rest is interpolated (AdaptiveShapeDiameter.h)
};

struct ShapeDiameterOptions
{
  int NumberOfRays = 30;            ///< rays per cone (paper: 30), NumberOfRaysRange [1, 4096]
  double ConeAngle = 120.0;  ///< full opening angle (paper: 120 degrees), ConeAngleRange [1, 179]
  double VertexOriginOffset = 1e-6; ///< tnear for origins without a source triangle, x bbox diagonal
  /// Which hit a ray measures (RayCaster.h; step 2 above). Default FirstHitLeaving: the
  /// normalised SDF changes less between poses than with SkipSameFacing (docs/sdf.md).
  HitRule Rule = HitRule::FirstHitLeaving;
  std::size_t OriginsPerChunk = 256;
  ShapeDiameterMode Mode = ShapeDiameterMode::Exact;
  /// Adaptive: relative SDF difference between neighbouring cast origins that triggers
  /// refinement, ToleranceRange [0.001, 1].
  double Tolerance = 0.15;
  /// Adaptive: spacing of cast origins as a fraction of the local SDF, SpacingFractionRange (0, 8].
  double SpacingFraction = 0.5;
  /// An origin buried inside another part of a self-intersecting mesh gets no value
  /// (ValidRays 0, left for FillFromNeighbors); see "Buried origins" above. Default on.
  bool IgnoreBuriedFaces = true;
};

// The ranges of the user-facing options, checked by CheckShapeDiameterOptions (whatever Mode);
// vtkShapeDiameterFilter's vtkSetClampMacro and Plugin/ShapeDiameter.xml repeat these numbers
// (Testing/Filters/TestParameterRanges.cxx). NumberOfRays: NumberOfRaysRange (ConeSampling.h).
/// ConeAngle, degrees. MakeConePattern alone accepts any cone, (0, 180) (its tests use 179.9);
/// the options keep [1, 179], the filter's range. Was (0, 180) for the options before.
inline constexpr Range<double> ConeAngleRange{ 1.0, 179.0 };
/// Tolerance (Adaptive). Was (0, 1] in the core before; the filter has always clamped to
/// [0.001, 1] (below that every origin refines: the exact mode, slower).
inline constexpr Range<double> ToleranceRange{ 0.001, 1.0 };
/// SpacingFraction (Adaptive; not a filter property), (0, 8].
inline constexpr Range<double> SpacingFractionRange{ 0.0, 8.0, true };
/// VertexOriginOffset (not a filter property), x bbox diagonal.
inline constexpr Range<double> VertexOriginOffsetRange{ 0.0, 1e-2 };

/// Where the cones start. All matrices have one row per origin (n rows), except FirstAxes and
/// the vectors, which may be empty.
struct RayOrigins
{
  PointMatrix Points;
  /// Outward unit normals (normalised again internally); the cone axis is -normal.
  PointMatrix Normals;
  /// Direction that fixes the pattern's rotation about the axis (projected onto the tangent
  /// plane), e.g. the face's first edge; 0 rows = derived from the normal (ConeSampling.h).
  PointMatrix FirstAxes;
  /// The triangle each origin lies on, never hit from that origin; empty = none (vertex
  /// origins, which then use VertexOriginOffset). -1 entries = none for that origin.
  std::vector<std::int64_t> SourceTriangles;
  /// Nonzero = do not cast from this origin (value 0, ValidRays 0); empty = cast from all.
  std::vector<std::uint8_t> Skip;
  /// Neighbors of each origin over the surface, CSR (neighbours of i: Neighbors[
  /// NeighborOffsets[i] .. NeighborOffsets[i + 1])), e.g. the triangle adjacency of face
  /// origins. Needed by ShapeDiameterMode::Adaptive only; empty otherwise.
  std::vector<std::int64_t> NeighborOffsets;
  std::vector<std::int64_t> Neighbors;
};

/// One origin per triangle: centroid, unit right-hand-rule normal, first edge (v1 - v0) as
/// FirstAxes, source triangle = its own index. Triangles with zero area or a non-finite
/// normal are marked in Skip. Throws Error on a vertex index out of range.
RayOrigins MakeFaceOrigins(const PointsView& points, const TrianglesView& triangles);

/// One origin per point with the caller's normals (n x 3, e.g. area-weighted vertex
/// normals), no source triangle, frame from the normal only. Points whose normal is zero or
/// not finite are marked in Skip. Throws Error if the row counts differ.
RayOrigins MakeVertexOrigins(const PointsView& points, const PointsView& normals);

struct ShapeDiameterResult
{
  std::vector<double> Values; ///< SDF per origin, finite; 0 where ValidRays == 0
  /// Rays kept by the median +- sigma filter; 0 = no value. In Adaptive mode an origin that
  /// was not cast carries the count of the cast origin its value comes from.
  std::vector<int> ValidRays;
  bool Aborted = false;       ///< the ProgressCallback asked to stop
  std::size_t CastCount = 0;  ///< origins evaluated: cone cast or found buried (all castable ones in Exact mode)
  std::size_t BuriedCount = 0; ///< cast origins found buried (IgnoreBuriedFaces), value 0
};

/// True when the origin lies inside the volume of another part of the mesh: the first surface
/// a ray along its outward normal meets is one the ray leaves (see "Buried origins" above).
bool IsBuried(const RayCaster& caster, const RayOrigin& origin);

/// The checks both modes make before any work. Throws Error on an option out of
/// its range (those of either mode, whatever options.Mode) or an unknown Mode.
void CheckShapeDiameterOptions(const ShapeDiameterOptions& options);

/// Throws Error when the origins' arrays do not have one row / entry per origin
/// (or none, where allowed). The neighbour graph is checked by the Adaptive mode only.
void CheckRayOrigins(const RayOrigins& origins);

/// The Exact mode: every origin casts its cone, whatever options.Mode (ComputeShapeDiameter,
/// SDF.h, chooses the mode). Throws Error on bad options or inconsistent sizes.
ShapeDiameterResult ComputeExactShapeDiameter(const RayCaster& caster, const RayOrigins& origins,
  const ShapeDiameterOptions& options, const ParallelFor& parallelFor,
  const ProgressCallback& progress = ProgressCallback());

/// Casts the cones of the origins listed in `subset` (distinct indices; nullptr = all) into
/// result.Values / ValidRays (sized by the caller), as ComputeExactShapeDiameter does for
/// each of them; adds the casts to result.CastCount. Progress as ComputeExactShapeDiameter's,
/// over the listed origins. Returns false when aborted. Used by the Adaptive mode.
bool CastShapeDiameterCones(const RayCaster& caster, const RayOrigins& origins,
  const ShapeDiameterOptions& options, const std::vector<std::size_t>* subset,
  ShapeDiameterResult& result, const ParallelFor& parallelFor, const ProgressCallback& progress);

/// Steps 3-4 above for one origin: lengths (+inf = no hit, dropped) and their weights.
/// Returns the weighted mean of the kept lengths and sets keptCount (0 and value 0 when no
/// length is finite). Exposed for tests.
double RobustWeightedMean(
  const std::vector<double>& lengths, const std::vector<double>& weights, int& keptCount);

struct FillFromNeighborsSummary
{
  std::size_t FilledFromNeighbors = 0; ///< invalid entries reached from a valid one
  std::size_t FilledWithFallback = 0;   ///< entries in components with no valid value
  double FallbackValue = 0;             ///< median of all valid values, 0 when there is none
};

/// Replaces every value whose validRays is 0 (or whose value is not finite) using the face
/// adjacency given as CSR (neighbours of i: adjacencyIndices[adjacencyOffsets[i] ..
/// adjacencyOffsets[i + 1])). Breadth-first in layers: every invalid entry with at least one
/// known neighbour takes the plain mean of its known neighbours' values, where "known" means
/// valid or filled in an EARLIER layer (so the result does not depend on the order in which
/// a layer is visited); repeat until nothing changes. Entries never reached (a component without any
/// valid value, an isolated face) get the fallback: the median of all valid values in the
/// whole input (mean of the two middle ones for an even count), or 0 if there is none.
/// validRays is not modified (0 still marks a filled value). Self-loops and duplicate
/// neighbours are allowed. Throws Error on inconsistent sizes or an index out of
/// range.
FillFromNeighborsSummary FillFromNeighbors(std::vector<double>& values,
  const std::vector<int>& validRays, const std::vector<std::int64_t>& adjacencyOffsets,
  const std::vector<std::int64_t>& adjacencyIndices);

} // namespace shapediameter
