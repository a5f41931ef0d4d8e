// SPDX-License-Identifier: BSD-3-Clause
// Skeleton steps 4b and 7b (ours, not the paper's): every leaf carried on to the end of its
// part, and, once the bones are smooth, on to the surface.
//
// What it does
//   The paper's skeleton is built from confident, curve-like points of T; near the end of a
//   part (a hand, a foot, a head on a neck) the projected points thin out and lose confidence,
//   so a branch stops short of the part's end by an amount that changes with the pose and the
//   sampling. For every leaf node v (degree 1) of radius r, after the connection step and
//   before its junction cleaning:
//     1. d = the branch's direction at the leaf: from its node about 2 r back (the farthest
//        within 2 r along the branch, else the leaf's neighbour) to v.
//     2. A ray from v along d leaves the volume at distance h (FirstHitLeaving; none: no
//        extension). Two more rays, parallel and r/4 to the side in two directions, give the
//        exit surface's normal n at the exit point (the plane through the three exits).
//     3. If the exit is met head-on, angle(n, d) <= MaximumExitAngle, the branch gets one more
//        node at v + (h - r) d (where a ball of radius r ahead touches the surface), when that
//        is more than r/4 ahead of v. Its radius is r, its confidence 0, its cloud point v's.
//   A branch that points at a side wall (a ring's skeleton cut open, a branch inside a bent
//   part) meets it obliquely and is left alone: the straight extension would leave the
//   medial axis. Junction cleaning (SkeletonBones.h) then runs on the extended tree, so a
//   stub is measured to its part's end: the articulated test figure's head, a ball on a short
//   neck, keeps its branch in both poses.
//   For a capsule limb whose branch stops short, h - r is exactly the distance to the cap's
//   centre, the end of the medial axis.
//
// Why: rigs and users expect a limb's branch to reach the limb's end (without this step the
// cheburashka rig's head-top joint is the one leaf not reached); measurements: docs/skeleton.md.
//
// Step 7b, ExtendLeavesToSurface, after the bones are smoothed (SkeletonSmoothing.h): the
// medial axis of a limb ends one radius inside its tip, where a rig puts the end joint of a
// finger, a foot or a head at the tip itself, and a limb's length read off the skeleton is
// short by that radius. Every leaf whose smoothed bone meets the surface ahead head-on (the
// test of step 2, on the smoothed nodes) gets one more node TipReach of the way to the exit
// point, in its own bone (the topology, the bones and the faces' bones are unchanged; the
// caller numbers the bones again by length and links the faces again to the nearest node of
// their bone). Its radius is the leaf's: the SDF/2 of the part's end, not an inscribed ball's
// (which shrinks to 0 at the surface). Done after the smoothing so that its direction is the
// smoothed bone's, not the noisy last nodes', and the fit cannot pull it off the tip. The
// libigl elephant rig: recall 88.7 -> 92.9 % (its feet's and head's end bones); the other
// rigs unchanged (docs/skeleton.md).
//
// Deviation: the paper's branches end where the confident points end; this step is ours.
//
// Parameters (SkeletonLeafExtensionOptions)
//   MaximumExitAngle   40 degrees   [0, 90]; 0 = both steps off. Chosen between the angle at
//                      which a head-on part end is met and the one of an oblique stub inside
//                      a bent part (docs/skeleton.md).
//   TipReach           1            [0, 1]; step 7b: share of the way from the leaf to the
//                      surface ahead; 1 = at the surface, 0 = step 7b off.
//
// Determinism: serial over the leaves in node order; the rays do not depend on threads.
#pragma once

#include "Errors.h"
#include "RayCasting/RayCaster.h"
#include "Skeleton/SkeletonBones.h"

#include <cstddef>

namespace shapediameter
{

struct SkeletonLeafExtensionOptions
{
  /// Largest angle (degrees) between the branch's direction and the normal of the surface it
  /// leaves through for the leaf to be extended; 0 = off. MaximumExitAngleRange [0, 90].
  double MaximumExitAngle = 40.0;
  /// Step 7b: share of the way from a head-on leaf to the surface ahead that its branch is
  /// carried on; 0 = off. TipReachRange [0, 1].
  double TipReach = 1.0;
};

/// MaximumExitAngle, degrees, checked by ValidateLeafExtensionOptions; vtkSDFSkeleton's
/// vtkSetClampMacro repeats it (Testing/Filters/TestParameterRanges.cxx).
inline constexpr Range<double> MaximumExitAngleRange{ 0.0, 90.0 };

/// TipReach, checked by ValidateLeafExtensionOptions.
inline constexpr Range<double> TipReachRange{ 0.0, 1.0 };

/// Throws Error if an option is outside its documented range.
void ValidateLeafExtensionOptions(const SkeletonLeafExtensionOptions& options);

/// Step 4b: appends to `graph` one node and one two-node polyline (IsConnection 0) per
/// extended leaf (see the header comment); bones are not reassigned (the caller cleans the
/// junctions and assigns them next). volume: the mesh's ray caster. Returns the number of
/// leaves extended.
std::size_t ExtendLeavesToPartEnds(SkeletonGraph& graph, const RayCaster& volume,
  const SkeletonLeafExtensionOptions& options);

/// Step 7b: appends one node per head-on leaf at TipReach of the way to the surface ahead, in
/// the leaf's bone (NodeBone, PolylineBone and BoneLength updated; the bones are not numbered
/// again). Returns the number of leaves extended.
std::size_t ExtendLeavesToSurface(SkeletonGraph& graph, const RayCaster& volume,
  const SkeletonLeafExtensionOptions& options);

} // namespace shapediameter
