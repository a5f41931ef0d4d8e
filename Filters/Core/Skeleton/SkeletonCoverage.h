// SPDX-License-Identifier: BSD-3-Clause
// Skeleton steps 5 and 6 (ours, not the paper's): a branch into every part the skeleton misses,
// and into a partition segment left without a bone of its own.
//
// What it does
//   The paper's skeleton only grows from confident, curve-like points of T, and its connection
//   step only joins the poly-segments found: a part whose projected points never form a
//   confident segment (a limb that bends or is short and thick, a sheet such as an ear) gets
//   no branch, and whether it does changes from pose to pose. After the connection step:
//     1. A point p of P is uncovered when its distance to the nearest skeleton node of its
//        own component exceeds UncoveredFactor * radius(p) (never when radius(p) = 0). A point of a part the skeleton
//        runs through lies within about its radius of it; one of a missed part lies far away.
//        With a volume (as ComputeSkeleton passes), p is uncovered too when the straight
//        segment to that node meets the surface: a node behind the surface covers nothing. A
//        tail hanging against a hind leg otherwise covers the leg's upper points, the leg's
//        branch joins the tail's tip, and the tail gets no leaf (the segmentation benchmark's
//        four-legged animals: limbs reached 91.4 -> 93.2 %; docs/skeleton.md).
//     2. Uncovered points are grouped through the connection step's neighbour graph of P
//        (CloudNeighborGraph, SkeletonConnection.h: each point's NumberOfNeighbors nearest
//        points of its component, edges whose straight segment meets the surface dropped,
//        pieces of a component bridged): a group is a connected set of uncovered points
//        linked by edges between uncovered points. The graph is the connection's, not one
//        of its own, so that the work is done once and the paths obey the same edges. Its
//        bridges (IsBridge: shortest gaps whose segment meets the surface) are not used, so
//        that a branch runs through the volume only and a piece the inside test cuts off
//        gets none (with them, spurious leaves appeared: docs/skeleton.md). A bridge inside
//        the volume is an ordinary edge (a thin ear whose points' nearest neighbours are all
//        its own is linked to the head by one; the segmentation benchmark's sheep 391 had no
//        leaf in its right ear).
//     3. Every group holding at least MinimumShare of all points, and every thin or small
//        limb (below), gets one branch: the shortest path through the neighbour graph from
//        the centre of the group's far end to the first covered point, joined to that point's
//        nearest node. The far end's centre: the group's tip is its point farthest from the
//        skeleton; of the points within one tip radius of the tip's distance, the centroid,
//        moved out along the direction from the tip's nearest node to the tip's depth; the
//        point nearest to it (ties: lowest index). On a tube it is the tip; on a stub as thick
//        as it is long the farthest point is a corner of its end, and a branch to it ran
//        sideways (the libigl hand's wrist: its rig leaf 0.054 of the diagonal from the
//        skeleton, 0.017 now).
//        Its nodes are the MLS-projected positions (ThinnedCloud::Positions) of the path's
//        points, kept when at least half their radius from the previous node (the end is
//        always kept). It is a connecting path (IsConnection 1).
//     4. (side limbs) A large group can be several limbs: a head with its snout and two ears
//        is one group when all of it lies far from the tree, and step 3 gives it one branch,
//        to the snout (the armadillo meshes of the segmentation benchmark: ears missed in 5 of
//        15). So every far end of a large group gets a branch of its own, along the shortest
//        path from it to the first covered point, when it is a limb and not a lobe of one:
//        the depth of a point is its distance through the group from where the group meets
//        covered points; taking the points deepest first, each local maximum of the depth
//        starts a region, and where two regions meet, the one with the shallower far end ends
//        (ties: the lower index). Such a far end is a side limb when its region meets the rest
//        within SideLimbJoinDepth (1/3) of its own depth (ears and snout meet where they leave
//        the head: at 0-0.12 of their depth), reaches at least UncoveredFactor of its radii
//        beyond the meeting point, and holds at least MinimumShare of all points. The flaps of
//        one sheet meet deep inside it (an elephant's ear: at 0.47-0.78 of their depth), and
//        they get no branch of their own.
//   Then the bones are assigned again (AssignBranchBones). A branch joins the nearest node,
//   which can lie a node or two from a junction: ComputeSkeleton then contracts the inner
//   branches shorter than MinimumBranchFactor radii (CleanGraphJunctions with
//   LeafPruning::Keep: a branch to an ear can be shorter than the torso's radius at its
//   junction, and pruning leaves here removed real leaves; docs/skeleton.md).
//
// Thin limbs: a tail, a finger or a horn of radius r and length L holds about r L of the
// area, so area-weighted sampling gives it few points (the camel's tail: 0.8 % of the area, 53
// uncovered points, under the 1 % a group needs), too few for a confident segment and for
// MinimumShare. A group below MinimumShare still gets a branch when it is a limb by its shape:
// its points lie along a line (ThinLimbLinearity: largest eigenvalue / sum of their covariance
// >= 0.95, a group about 4.4 times as long as it is wide; a flat toe pad or an ear's sheet
// scores 0.75-0.89, the camel's tail 0.99), its tip lies at least ThinLimbFactor (6) of its
// radii from the skeleton (twice what uncovers a point), and it holds at least
// ThinLimbMinimumShare (0.2 %) of the points, enough for its covariance. Length and shape in
// radii do not change with the pose; the point count near the share does (docs/skeleton.md).
//
// Small limbs: a flat hand, a fish's fin or an airplane's tail fin is no line (linearity
// 0.76-0.85) and holds 0.7-0.9 % of the points, under MinimumShare; of two symmetric fins one
// held 1.07 % and got a branch, the other 0.80 % and got none. A group below MinimumShare also
// gets a branch when it holds at least SmallLimbMinimumShare (0.5 %) of the points and its tip
// lies at least ThinLimbFactor of its radii from the skeleton, whatever its shape. The camel's
// ears and toe pads (26-32 points) stay below it. Segmentation benchmark: limbs reached 91.0 ->
// 91.7 % (Human 89.5 -> 91.1 %, Fish 82.3 -> 86.5 %), no category lower; 0.4-0.65 % give
// 91.6-91.7 % (docs/skeleton.md).
//
// Why: on posed characters the missed parts are not missed in every pose (an ear's sheet of
// points happens to form a confident segment in some poses only), so the paper's skeleton
// changes its leaves from pose to pose; with this step every pose gets them. It also reaches
// limbs whose branch stopped at the hip. Measurements: docs/skeleton.md.
//
// Step 6 (ReachPartsWithoutBones, with part labels) builds the same kind of branch into one
// part of the surface (the partition's segment) that the part link left without a bone of its
// own: the part's points take the place of the uncovered ones, and the branch is added only when
// the part's tip lies more than PartUncoveredFactor radii from the skeleton. Skeleton.h picks the
// parts and says why; the measurements are in docs/skeleton.md.
//
// Parameters (SkeletonCoverageOptions)
//   SideLimbJoinDepth    1/3    [0, 1]    step 4: a side limb's region meets the rest of its
//                                         group within this share of its far end's depth; 0 =
//                                         no side limbs. Why 1/3: between the ears' 0.12 and
//                                         the elephant ear flaps' 0.47 (docs/skeleton.md).
//   UncoveredFactor      3      [0, 1e6]  in units of the point's radius; 0 = step off. It was
//                                         4 until the libigl hand's wrist (a stub as thick as it
//                                         is long, its points 2–3.5 radii from the tree) showed
//                                         that 4 misses short, thick limbs: rig recall 78.3 ->
//                                         89.5 %, the bundled meshes' bones unchanged
//                                         (docs/skeleton.md).
//   MinimumShare         0.01   [0, 1]    of all projected points, per group.
//   ThinLimbFactor       6      [0, 1e6]  a thin or small limb's tip, in its radii; 0 = both off.
//   ThinLimbLinearity    0.95   [0, 1]    a thin limb's points' linearity.
//   ThinLimbMinimumShare 0.002  [0, 1]    of all projected points, per thin limb.
//   SmallLimbMinimumShare 0.005 [0, 1]    of all projected points, per small limb of any
//                                         shape (tip ThinLimbFactor radii away); 0 = off.
//   PartMinimumShare     0.03   [0, 1]    step 6: of all projected points, per part. It was
//                                         0.05 until the segmentation benchmark's teddies
//                                         showed stubby arms of 4-5 % of the area without a
//                                         leaf (docs/skeleton.md); 0.02 costs bearings.
//   PartUncoveredFactor  2      [0, 1e6]  step 6: the part's tip, in its radii; 0 = step off.
//   (The graph's neighbour count is the connection's, SkeletonConnectionOptions.)
//
// Determinism: the neighbour graph does not depend on the thread count (SkeletonConnection.h);
// groups, tips (ties: lowest index) and shortest paths (ties: lowest index) do not either.
#pragma once

#include "Errors.h"
#include "Mesh/MeshTypes.h"
#include "Parallel.h"
#include "RayCasting/RayCaster.h"
#include "Skeleton/SkeletonBones.h"
#include "Skeleton/SkeletonConnection.h"
#include "Skeleton/SkeletonSampling.h"
#include "Skeleton/SkeletonThinning.h"

#include <cstddef>
#include <cstdint>
#include <vector>

namespace shapediameter
{

struct SkeletonCoverageOptions
{
  /// A projected point farther than this many radii from every node is uncovered; 0 = off.
  /// UncoveredFactorRange [0, 1e6].
  double UncoveredFactor = 3.0;
  /// A group of uncovered points gets a branch when it holds this share of all points.
  /// CoverageMinimumShareRange [0, 1].
  double MinimumShare = 0.01;
  /// Another far end of a large group gets a branch of its own when its region meets the rest
  /// of the group within this share of its depth (the header comment, step 4); 0 = none.
  /// SideLimbJoinDepthRange [0, 1].
  double SideLimbJoinDepth = 1.0 / 3.0;
  /// Step 6 (with part labels): a part without a bone of its own gets a branch when it holds
  /// this share of all points of P, PartMinimumShareRange [0, 1]; 1 = step 6 off in practice.
  double PartMinimumShare = 0.03;
  /// Step 6: ... and when its point farthest from the skeleton lies more than this many of
  /// its radii away, PartUncoveredFactorRange [0, 1e6]; 0 = step 6 off.
  double PartUncoveredFactor = 2.0;
  /// A group below MinimumShare still gets a branch when it is a thin or small limb: its tip
  /// lies at least this many of its radii from the skeleton, ... ThinLimbFactorRange [0, 1e6];
  /// 0 = off (both).
  double ThinLimbFactor = 6.0;
  /// ... its points lie along a line (largest eigenvalue / sum of their covariance at least
  /// this), ThinLimbLinearityRange [0, 1] ...
  double ThinLimbLinearity = 0.95;
  /// ... and it holds at least this share of all points, ThinLimbMinimumShareRange [0, 1].
  double ThinLimbMinimumShare = 0.002;
  /// A group below MinimumShare that holds at least this share of all points and whose tip lies
  /// ThinLimbFactor of its radii away gets a branch whatever its shape (a small limb: a hand, a
  /// fin); SmallLimbMinimumShareRange [0, 1]; 0 = off.
  double SmallLimbMinimumShare = 0.005;
};

// The ranges, checked by ValidateCoverageOptions; vtkSDFSkeleton's vtkSetClampMacro repeats those
// of its properties (UncoveredFactor, PartUncoveredFactor; Testing/Filters/TestParameterRanges.cxx).
inline constexpr Range<double> UncoveredFactorRange{ 0.0, 1e6 };
/// Not a filter property.
inline constexpr Range<double> CoverageMinimumShareRange{ 0.0, 1.0 };
/// Not a filter property.
inline constexpr Range<double> SideLimbJoinDepthRange{ 0.0, 1.0 };
/// Not a filter property.
inline constexpr Range<double> PartMinimumShareRange{ 0.0, 1.0 };
inline constexpr Range<double> PartUncoveredFactorRange{ 0.0, 1e6 };
inline constexpr Range<double> ThinLimbFactorRange{ 0.0, 1e6 };
/// Not a filter property.
inline constexpr Range<double> ThinLimbLinearityRange{ 0.0, 1.0 };
/// Not a filter property.
inline constexpr Range<double> ThinLimbMinimumShareRange{ 0.0, 1.0 };
/// Not a filter property.
inline constexpr Range<double> SmallLimbMinimumShareRange{ 0.0, 1.0 };

/// Throws Error if an option is outside its documented range.
void ValidateCoverageOptions(const SkeletonCoverageOptions& options);

/// Step 5: adds a branch into every large group of uncovered points, into its side limbs and
/// into every thin limb (see the header comment) and assigns the bones again when it added
/// any. pointComponent: surface component of each point of P, or empty for one component.
/// neighbours: the neighbour graph of P that the connection step used (ConnectPolySegments'
/// neighboursOut, or BuildCloudNeighborGraph); throws Error if it does not have one row per
/// point of P. volume: the mesh's ray caster (nullptr: a node covers through the surface).
/// Returns the number of branches added.
std::size_t ReachUncoveredParts(SkeletonGraph& graph, const ProjectedCloud& cloud,
  const ThinnedCloud& thinned, const std::vector<std::int64_t>& pointComponent,
  const CloudNeighborGraph& neighbours, const SkeletonCoverageOptions& options,
  const ParallelFor& parallelFor, const RayCaster* volume = nullptr);

/// Step 6 (ours, with part labels): one branch into a part that has no bone of its own (see
/// Skeleton.h, which picks the parts). inPart flags the points of P of that part; they are
/// grouped through the neighbour graph as in step 5 (bridges not used), and the largest group
/// gets a branch from the centre of its far end (as in step 5) along the shortest path to the
/// first point outside the part, joined to that point's nearest node, when its tip (its point
/// farthest from the skeleton) lies more than PartUncoveredFactor of its radii from the
/// skeleton. Assigns the bones again when
/// it added the branch. Returns the number of branches added (0 or 1).
std::size_t ReachPartsWithoutBones(SkeletonGraph& graph, const ProjectedCloud& cloud,
  const ThinnedCloud& thinned, const std::vector<std::int64_t>& pointComponent,
  const CloudNeighborGraph& neighbours, const std::vector<char>& inPart,
  const SkeletonCoverageOptions& options, const ParallelFor& parallelFor);

} // namespace shapediameter
