// SPDX-License-Identifier: BSD-3-Clause
// AdaptiveShapeDiameter: the SDF of ShapeDiameter.h at a cost that follows the shape, not the
// number of origins (ShapeDiameterMode::Adaptive).
//
// Why it works
//   The SDF (Shapira, Shamir & Cohen-Or 2008, Sect. 3) is a volumetric quantity: it varies on
//   the scale of the local thickness, not of the triangulation. On a fine mesh neighbouring
//   faces cast nearly the same cone into the same volume, and the chain smooths the result
//   anyway (bilateral smoothing, Sect. 3). So only a subset of origins is cast, spaced at a
//   fraction of the local SDF, and the others are interpolated over the surface.
//
// What it computes (every cast origin gets exactly the value of the Exact mode)
//   Let E be the mean distance between neighbouring origins (over RayOrigins' neighbour
//   graph) and h_k = E 2^k the cell size of level k, k = 0..K with h_K ~ diagonal / 32. When
//   K = 0 (a coarse mesh: the origins are no denser than the coarsest cells) every origin
//   would be cast, and the Exact mode runs instead.
//   1. Coarse pass: every origin has level K. Selection at a level: origins are binned by
//      (level, cell of size h_level, dominant axis and sign of the normal, so that the two
//      sides of a thin plate never share a sample); in each bin the origin closest to the
//      cell centre is cast (ties: lowest index). At level 0 every candidate is cast.
//   2. Regions: a breadth-first search over the neighbour graph from all cast origins with a
//      valid value gives every origin its owner (the cast origin that reached it first, layer
//      by layer, in a fixed order) and its depth in hops. After later casts only the origins
//      that a new cast reaches in strictly fewer hops change owner (a search from the new
//      casts alone: the same hop distances, a cost that follows the change).
//   3. Spacing from the estimate: after the coarse pass each origin's level becomes the
//      largest k with h_k <= SpacingFraction x (its owner's SDF), and at least 2 E; origins
//      whose level dropped are selected again (step 1, among them only).
//   4. Refinement, repeated until nothing new is cast (at most K + 8 rounds): the origins of
//      a region are selected again one level finer when
//      - across a neighbour edge its owner's value and the neighbouring owner's differ by
//        more than Tolerance x the larger one (the thickness jumps between them), or
//      - one of its origins is deeper than 2 * 2^level + 2 hops (a region that reached
//        round a corner or onto a sheet no cell gave a sample of);
//      origins no region reached are selected again one level finer too.
//   4b.Extremes: the normalisation (Normalization.h) maps the smoothed SDF's minimum and
//      maximum to 0 and 1, so a missed extreme shifts every normalised value. The regions
//      whose owner is among the lowest or highest 1 % of the cast values are selected again
//      two levels finer (once).
//   5. Interpolation: an origin that was not cast (or cast without a valid ray) takes its
//      owner's value, then 8 Jacobi sweeps average it with its neighbours (cast origins stay
//      fixed), not across concave creases: an edge where the normals differ by more than 60
//      degrees and the neighbour lies on the outer side of the origin's tangent plane (where
//      the partition cuts). ValidRays of such an origin is its owner's. Origins no region
//      reached keep value 0 / ValidRays 0 (the adapter's FillFromNeighbors fills them).
//
// Options: Tolerance and SpacingFraction are in ShapeDiameterOptions (defaults 0.15 and 0.5);
//   the rest are fixed here: K from a coarse cell of 1/32 of the bounding-box diagonal, 8
//   sweeps, crease angle 60 degrees, extremes 1 % refined two levels finer.
//
// Cost: the casts follow the variation of the SDF, not the face count, except where the exact
//   field jumps between neighbouring faces (the refinement follows such jumps to the finest
//   level); plus a part linear in the faces (the adapter's triangulation, adjacency,
//   orientation and BVH, the per-face bookkeeping). When K = 0 the Exact mode runs.
//
// Design choices (the measurements and the alternatives that lost: docs/adaptive-sdf.md)
//   - Tolerance 0.15: smaller casts more faces and is more accurate; 0.2 misses the p99
//     accuracy aim on the largest benchmark mesh.
//   - SpacingFraction 0.5: refinement, not the first spacing, decides the cast count.
//   - No floor on the refinement (no minimum spacing relative to the SDF): every floor tried
//     broke the accuracy aim, mostly by missing the SDF's maximum, which shifts every
//     normalised value; step 4b exists for the same reason. Casting the extreme regions
//     completely instead of two levels finer costs several times the casts for the same
//     accuracy.
//   - Interpolation: owner value + 8 Jacobi sweeps; 8 give nearly all of 32's gain, and a
//     partition-of-unity blend of neighbouring regions gained nothing measurable. The
//     remaining error is where the exact field has structure finer than the spacing.
//   - Regions are updated incrementally (step 2) rather than recomputed every round, and the
//     selection is a hashed grid per level rather than geodesic farthest-point sampling: one
//     sort per round, deterministic and independent of the thread count.
//   - The refinement follows spatially coherent differences between regions, not single
//     noisy cones: a noise test on top of Tolerance, refining only above the finest levels,
//     or skipping isolated outliers saved few casts and lost accuracy (a noise test also
//     suppresses the refinement that a block's edges need, where a cone's rays spread for
//     geometric reasons).
//   - Single rays (rtcIntersect1), Embree's default BVH quality and the full cone of
//     NumberOfRays at every cast origin: packets, Low quality and early-stopped cones were
//     slower or left the Exact values.
//
// Determinism, progress, abort: the selection and the search are serial and in index order;
// the refinement test runs in parallel but only sets flags (their union does not depend on
// the order); the casts run through CastShapeDiameterCones (per-origin results)
// and the sweeps are Jacobi steps (each origin reads the previous sweep), so any ParallelFor
// gives bit-identical results. Progress is reported per chunk of each round's casts, mapped
// to a monotone fraction; an abort stops at the next chunk and sets Aborted.
#pragma once

#include "SDF/ShapeDiameter.h"

namespace shapediameter
{

/// ComputeShapeDiameter (SDF.h) with options.Mode == Adaptive lands here. Throws
/// Error on bad options or sizes, as the Exact mode does (CheckShapeDiameterOptions,
/// CheckRayOrigins), and when the origins have no (or an inconsistent) neighbour graph.
ShapeDiameterResult ComputeAdaptiveShapeDiameter(const RayCaster& caster,
  const RayOrigins& origins, const ShapeDiameterOptions& options, const ParallelFor& parallelFor,
  const ProgressCallback& progress = ProgressCallback());

} // namespace shapediameter
