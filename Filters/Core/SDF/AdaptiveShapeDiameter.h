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
//   sweeps, crease angle 60 degrees, extremes 1 %.
//
// What was tried (against the Exact mode through the whole chain; the measurements are in
// README, "Adaptive SDF", "What was tried")
//   - Tolerance: a smaller one casts more faces and is more accurate. 0.15 is the default:
//     0.2 misses the p99 bar at 832k faces; 0.15 meets it there, at the cost of the dino's
//     cluster agreement and of speed at 208k.
//   - SpacingFraction 1 instead of 0.5 saves little: refinement, not the first spacing,
//     decides the count.
//   - A floor on refinement (no spacing below 1/8 or 1/4 of the SDF, to stop refining where
//     neighbouring cones differ by noise rather than by shape): far fewer casts, but the
//     maximum of the SDF was missed and the normalisation shifted every value; hence step 4b,
//     and no floor (with step 4b, a floor at 1/16 still raised p99 past the bar at 208k).
//   - Step 4b casting the extreme regions completely instead of two levels finer: several
//     times the casts, same accuracy.
//   - A partition-of-unity blend of neighbouring regions' values (weights (1 - d^2/R^2)^2,
//     R twice the cell size) before the sweeps, so that the blend spans a region whatever its
//     size in hops: no measurable gain; not kept. The remaining error is where the exact
//     field has structure finer than the spacing.
//   - Piecewise-constant fill (owner value only, 0 sweeps) against 8 or 32 sweeps: 8 sweeps
//     give nearly all of 32's gain.
//   - Recomputing the regions from all casts every round instead of the incremental update
//     above: a search over all faces per round, a large share of the run at 208k.
//   - Selection by a hashed grid per level (this file) rather than geodesic farthest-point
//     sampling: one sort per round, deterministic and independent of the thread count.
//   - A noise test on top of Tolerance (refine only where two cast values also differ by z
//     standard errors of their difference, each from the spread of its kept rays): z = 2 cast
//     12 % fewer at 208k, z = 3 38 % fewer, but z = 2 already failed the thin plate on a
//     block: near the block's edges a cone's rays spread for geometric reasons, not random
//     ones, and the test suppressed the refinement there. Not kept.
//   - One cast per cell and side of the cell's first normal instead of per dominant axis and
//     sign: no fewer casts. Refinement stopped one or two levels above the finest: 3-16 %
//     fewer casts; the casts are not spent at the finest level.
//   - No refinement for isolated outliers at the finest levels (a disagreeing pair refined only
//     if each region also agrees with some other neighbouring region): about 1 % fewer casts
//     and a worse p99; the refinement follows spatially coherent differences, not single noisy
//     cones. Embree's Low BVH quality: the build is faster but the casts slower, a net loss.
//   - Embree packets of 8 rays (rtcIntersect8) for a cone: slower than single rays (1.23 vs
//     1.13 x raw Embree in the exact filter; 2.16 with the coherent flag).
//   - Fewer rays per cone where the first rays agree (measured, not built): the 30-ray value
//     is itself a noisy estimate. Of the 208k armadillo's cast cones, two disjoint 10-ray
//     subsets (every third ray of the pattern) agree within 2 % for 13 % of the cones (5 %:
//     31 %, 10 %: 55 %), and among those the 20-ray value still differs from the 30-ray one by
//     more than 2 % in 45 % of the cones; the spread of one subset cannot serve as the test
//     (the rays' lengths differ by the cone's geometry: a coefficient of variation under 10 %
//     in fewer than 0.05 % of them). Stopping early would move cast values off the Exact
//     mode's by more than the accuracy bar allows, on the cones that are not on a jump (those
//     are the ones that agree), while the casts at the finest levels follow jumps, where rays
//     disagree.
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

/// ComputeShapeDiameter with options.Mode == Adaptive lands here. Throws ShapeDiameterError
/// when the origins have no (or an inconsistent) neighbour graph.
ShapeDiameterResult ComputeAdaptiveShapeDiameter(const RayCaster& caster,
  const RayOrigins& origins, const ShapeDiameterOptions& options, const ParallelFor& parallelFor,
  const ProgressCallback& progress = ProgressCallback());

} // namespace shapediameter
