// SPDX-License-Identifier: BSD-3-Clause
// Skeleton step 7 (ours, not the paper's): every bone made a smooth curve through the volume.
//
// What it does
//   The nodes of a bone are thinned points of T (fitted poly-segments) and points of P
//   (connecting paths), each scattered about the medial axis by the SDF's noise; as output
//   they zig-zag (the camel's legs: turning angles of 33° at the 90th percentile). After the
//   topology and the surface link are final, for every bone (a maximal path between leaves
//   and junctions):
//     1. s = arc length along the bone's nodes as they are.
//     2. Every node i of the bone is given a local polynomial fit of the bone's nodes in s
//        (moving least squares: weights exp(-(s_j - s_i)^2 / 2 sigma_i^2) within 3 sigma_i,
//        sigma_i = Bandwidth x the node's radius), position and radius alike: quadratic where
//        the window holds at least two nodes on either side, else linear (near the ends, where
//        a one-sided quadratic would extrapolate). An interior node (degree 2) moves to its
//        fit, a leaf to its bone's one-sided fit (along the bone's line: a straight bone keeps
//        its end), a junction to the mean of the fits of the bones it ends, so the tree stays
//        connected. Why quadratic: a linear fit (a weighted mean, in effect, inside a bone)
//        pulls a curved bone towards its centre of curvature by about sigma^2 / 2R (the test
//        torus, R = 6 radii: 0.11 radii off its core circle against 0.03), and cuts the
//        corners where a limb bends into the body (cheburashka rig recall 88.3 -> 84.4 %; with
//        the quadratic fit 88.3 %, as without the step).
//     3. Through the volume: an edge of the smoothed skeleton whose straight segment meets the
//        surface (SegmentCrossesSurface, as the connection's paths) moves its two nodes half
//        way back to where they were, up to four times, then all the way; edges that already
//        met the surface before smoothing are not held against it.
//   The radius of a moved node is fitted with its position (the radii along a bone vary
//   smoothly; a node moved towards the axis keeps a radius of its neighbourhood rather than
//   its own sample's).
//
// Why: rigs, measurements and animation read a bone as a curve. Resampled at half a radius
//   (Testing/Evaluation/measure_skeleton_smoothness.py), the 90th percentile of the turning
//   angle was 24° / 30° / 27° on the camel / man / armadillo, and is 8° / 11° / 14° with the
//   step (a linear fit: 7° / 10° / 14°, but the bias above; Bandwidth 1.5: 9° / 12° / 15°).
//   Rig recall is that of the skeleton without the step (docs/skeleton.md).
//
// Deviation: the paper's skeleton ends with the connected poly-segments; this step is ours.
//   It moves nodes only: node ids, branches and polylines are those before it. The caller
//   (ComputeSkeleton) then numbers the bones again by their smoothed lengths (BoneLength stays
//   the length of the bone as output, longest first), renames the faces' SkeletonBoneId with
//   them (every face keeps its branch) and links each face again to the nearest node of its
//   bone.
//
// Parameters (SkeletonSmoothingOptions)
//   Bandwidth   1.0 [0, 100]   sigma of the fit in node radii; 0 = step off.
//
// Determinism: serial, in bone order; the volume tests do not depend on threads.
#pragma once

#include "Errors.h"
#include "RayCasting/RayCaster.h"
#include "Skeleton/SkeletonBones.h"

#include <cstddef>

namespace shapediameter
{

struct SkeletonSmoothingOptions
{
  /// Standard deviation of the fit's weights along a bone, in units of the node's radius;
  /// 0 = off. BoneSmoothingRange [0, 100].
  double Bandwidth = 1.0;
};

/// Bandwidth, checked by ValidateSmoothingOptions; vtkSDFSkeleton's vtkSetClampMacro repeats it
/// (Testing/Filters/TestParameterRanges.cxx).
inline constexpr Range<double> BoneSmoothingRange{ 0.0, 100.0 };

/// Throws Error if an option is outside its documented range.
void ValidateSmoothingOptions(const SkeletonSmoothingOptions& options);

struct BoneSmoothingResult
{
  std::size_t MovedNodes = 0; ///< nodes that moved (all the way or part of it)
  std::size_t HeldNodes = 0;  ///< nodes held back by the volume, part or all of the way
};

/// Step 7 (see the header comment): moves the nodes of every bone of `graph` and updates their
/// radii; topology untouched. volume: the mesh's ray caster (nullptr: no
/// volume test).
BoneSmoothingResult SmoothBones(
  SkeletonGraph& graph, const RayCaster* volume, const SkeletonSmoothingOptions& options);

} // namespace shapediameter
