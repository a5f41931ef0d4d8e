// SPDX-License-Identifier: BSD-3-Clause
// SDF-guided skeleton, step 3 of 4: ordered poly-segments from the thinned cloud T.
//
// What it computes
//   The most confident point of T that is not yet clustered seeds a poly-segment, which grows
//   from it in both directions of its regression line. One growth step from the current end
//   e with direction d looks at the unclustered points q of T within
//   StepFactor * radius(e) of e that lie
//     - inside the cone of half-angle AngularToleranceDegrees around d, and
//     - whose own regression line is within the same angle of d (no sharp turn: two branches
//       meeting at a junction become two segments, joined later by step 4), and
//     - (when a volume is given, as ComputeSkeleton does) whose straight step from e meets no
//       surface (SegmentCrossesSurface, RayCaster.h): a segment does not jump between two
//       parts that touch or interpenetrate (a trunk resting on a foot). Deviation: the paper
//       has no such test; without it, segments and connecting paths through touching parts
//       merged a foot with the trunk in some elephant poses (docs/skeleton.md). For a volume
//       where every call is an exchange between processes (RayCaster::PrefersFewLargeBatches),
//       the steps are tested before the growth starts, in one batch: the direction at e is
//       always plus or minus e's regression line, so every step the growth may test is known
//       (q near e, in the cone either way, its line within the angle of e's). Ours, not the
//       paper's; the segments are the same either way (serially, testing them all costs more
//       rays than the growth casts).
//   The nearest such q becomes the new end; the other cone points that q has passed (their
//   projection on d is not beyond q's) are clustered into the segment without becoming nodes.
//   The direction becomes q's regression line, oriented along d. A side stops when the cone is
//   empty; then the next best unclustered point seeds a new segment, until T is used up
//   (paper, Fig. 12c).
//
// Reference
//   Shapira, Shamir, Cohen-Or 2008, section 5, fifth paragraph.
//
// Parameters (SkeletonSegmentOptions), lengths relative to the local radius(p)
//   StepFactor               reach of one step, * radius(e). Default 1 (the MLS neighbourhood
//                            radius): more than the largest gap 2 * epsilon that the
//                            epsilon-thinning leaves along a curve (epsilon = 0.25 radius), less
//                            than the gap low confidence leaves around a junction. (0, 10].
//   AngularToleranceDegrees  cone half-angle and largest turn per step. Default 30; (0, 90).
//   MinimumNodes             shorter segments are dropped (isolated confident specks in thick
//                            regions); their points stay clustered. If every segment of a
//                            surface component is shorter, its longest one is kept so that no
//                            component loses its skeleton. Default 3; [1, 1000].
//
// Degenerate cases
//   Empty T -> no segments. Segments never mix points of different surface components (the
//   component of a point is that of its source face). A closed curve (torus) gives one open
//   segment: the skeleton is a tree, its loop stays open by less than one step.
#pragma once

#include "Errors.h"
#include "RayCasting/RayCaster.h"
#include "Skeleton/SkeletonSampling.h"
#include "Skeleton/SkeletonThinning.h"

#include <cstdint>
#include <vector>

namespace shapediameter
{

struct SkeletonSegmentOptions
{
  /// Reach of a growth step, * radius of the current end. StepFactorRange (0, 10].
  double StepFactor = 1.0;
  /// Cone half-angle and largest turn per step, degrees. (0, 90), open at both ends: Range has
  /// no exclusive upper bound, so ValidateSegmentOptions checks this one by hand.
  double AngularToleranceDegrees = 30.0;
  /// Segments with fewer nodes are dropped (see header). MinimumNodesRange [1, 1000].
  int MinimumNodes = 3;
};

// The ranges, checked by ValidateSegmentOptions (none is a filter property).
inline constexpr Range<double> StepFactorRange{ 0.0, 10.0, true };
inline constexpr Range<int> MinimumNodesRange{ 1, 1000 };

/// One poly-segment: indices into the cloud of its nodes (points of T, at their MLS
/// positions), ordered along the curve.
using PolySegment = std::vector<std::int64_t>;

/// Throws Error if an option is outside its documented range.
void ValidateSegmentOptions(const SkeletonSegmentOptions& options);

/// Step 3: grows poly-segments through T, most confident seeds first.
/// pointComponent: surface component of each cloud point, or empty for a single component.
/// volume: the mesh's ray caster for the inside test of a growth step, or null for none; when it
/// PrefersFewLargeBatches, every step the growth may take is tested before it starts, with
/// parallelFor.
std::vector<PolySegment> GrowPolySegments(const ProjectedCloud& cloud,
  const ThinnedCloud& thinned, const std::vector<std::int64_t>& pointComponent,
  const SkeletonSegmentOptions& options, const RayCaster* volume = nullptr,
  const ParallelFor& parallelFor = SerialFor);

} // namespace shapediameter
