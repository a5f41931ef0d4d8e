// SPDX-License-Identifier: BSD-3-Clause
// Tests of skeleton step 5 (SkeletonCoverage.h): a branch into every large group of projected
// points far from the tree and into every thin limb (a small group along a line), on a hand-made cloud whose answer is known: an L of points where the
// skeleton covers one arm only. The points are grouped and joined through the connection
// step's neighbour graph (SkeletonConnection.h).
#include "Skeleton/SkeletonCoverage.h"

#include "RayCasting/BruteForceRayCaster.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace
{

using namespace shapediameter;

struct LCloud
{
  ProjectedCloud Cloud;
  ThinnedCloud Thinned;
  SkeletonGraph Graph;
};

/// One polyline of `nodes` nodes every 0.2 along x from the origin, radius 0.1, node i from
/// cloud point 10 i, bones assigned.
SkeletonGraph LineSkeleton(int nodes)
{
  SkeletonGraph graph;
  graph.NodePositions.resize(nodes, 3);
  std::vector<std::int64_t> polyline;
  for (int i = 0; i < nodes; ++i)
  {
    graph.NodePositions.row(i) << 0.2 * i, 0.0, 0.0;
    graph.NodeRadius.push_back(0.1);
    graph.NodeConfidence.push_back(0.9);
    graph.NodeCloudIndex.push_back(10 * i);
    graph.NodeComponent.push_back(0);
    polyline.push_back(i);
  }
  graph.Polylines.push_back(polyline);
  graph.IsConnection.push_back(0);
  AssignBranchBones(graph);
  return graph;
}

/// Points of radius 0.1 on a line from (0,0,0) to (4,0,0) (the skeleton: nodes every 0.2 on
/// it) and, unless `armPoints` is 0, on a line from (4,0,0) up to (4,armLength,0) that no node
/// covers; plus a few points around (0,0,0).
LCloud MakeL(int armPoints, double armLength = 2.0)
{
  std::vector<Eigen::Vector3d> positions;
  for (int i = 0; i <= 200; ++i)
  {
    positions.emplace_back(4.0 * i / 200.0, 0.0, 0.0);
  }
  for (int i = 1; i <= armPoints; ++i)
  {
    positions.emplace_back(4.0, armLength * i / armPoints, 0.0);
  }
  LCloud l;
  const auto n = static_cast<Eigen::Index>(positions.size());
  l.Cloud.Positions.resize(n, 3);
  for (Eigen::Index i = 0; i < n; ++i)
  {
    l.Cloud.Positions.row(i) = positions[static_cast<std::size_t>(i)].transpose();
  }
  l.Cloud.Radius.assign(positions.size(), 0.1);
  l.Cloud.SourceFace.assign(positions.size(), 0);
  l.Thinned.Positions = l.Cloud.Positions;
  l.Thinned.Confidence.assign(positions.size(), 0.9);
  l.Graph = LineSkeleton(21);
  return l;
}

/// A long covered line (2001 points of radius 0.1 from (0,0,0) to (40,0,0), nodes every 0.2)
/// and `extra` points of radius `extraRadius` beside it, under 1 % of the cloud.
LCloud MakeLineWith(const std::vector<Eigen::Vector3d>& extra, double extraRadius)
{
  LCloud l;
  const Eigen::Index base = 2001;
  const auto n = base + static_cast<Eigen::Index>(extra.size());
  l.Cloud.Positions.resize(n, 3);
  for (Eigen::Index i = 0; i < base; ++i)
  {
    l.Cloud.Positions.row(i) << 40.0 * static_cast<double>(i) / (base - 1), 0.0, 0.0;
    l.Cloud.Radius.push_back(0.1);
  }
  for (std::size_t i = 0; i < extra.size(); ++i)
  {
    l.Cloud.Positions.row(base + static_cast<Eigen::Index>(i)) = extra[i].transpose();
    l.Cloud.Radius.push_back(extraRadius);
  }
  l.Cloud.SourceFace.assign(static_cast<std::size_t>(n), 0);
  l.Thinned.Positions = l.Cloud.Positions;
  l.Thinned.Confidence.assign(static_cast<std::size_t>(n), 0.9);
  l.Graph = LineSkeleton(201);
  return l;
}

/// `count` points every `step` from (20, step, 0) up along y: a thin limb off the line.
std::vector<Eigen::Vector3d> ThinArm(int count, double step)
{
  std::vector<Eigen::Vector3d> arm;
  for (int i = 1; i <= count; ++i)
  {
    arm.emplace_back(20.0, step * i, 0.0);
  }
  return arm;
}

/// Step 5 on the connection's neighbour graph of the L (default neighbour count, no volume).
std::size_t Reach(LCloud& l, const std::vector<std::int64_t>& component = {},
  const SkeletonCoverageOptions& options = {}, const ParallelFor& parallelFor = SerialFor)
{
  const CloudNeighborGraph neighbours = BuildCloudNeighborGraph(
    l.Cloud, component, SkeletonConnectionOptions().NumberOfNeighbors, parallelFor);
  return ReachUncoveredParts(l.Graph, l.Cloud, l.Thinned, component, neighbours, options, parallelFor);
}

} // namespace

TEST(SkeletonCoverage, AnUncoveredArmGetsABranchToItsTip)
{
  LCloud l = MakeL(100);
  const std::size_t added = Reach(l);
  ASSERT_EQ(added, 1u);
  ASSERT_EQ(l.Graph.Polylines.size(), 2u) << "the old line and the new branch";
  EXPECT_EQ(l.Graph.IsConnection.back(), 1);
  const std::vector<std::int64_t>& branch = l.Graph.Polylines.back();
  // It starts at the corner node (4,0,0) and ends at the tip of the arm (4,2,0).
  EXPECT_NEAR((l.Graph.NodePositions.row(branch.front()) - Eigen::RowVector3d(4, 0, 0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((l.Graph.NodePositions.row(branch.back()) - Eigen::RowVector3d(4, 2, 0)).norm(), 0.0, 1e-12);
  // Nodes follow the arm at a spacing of at least half the radius (the tip is always kept).
  for (std::size_t i = 1; i + 1 < branch.size(); ++i)
  {
    const Eigen::RowVector3d node = l.Graph.NodePositions.row(branch[i]);
    EXPECT_NEAR(node.x(), 4.0, 1e-12);
    EXPECT_GE((node - l.Graph.NodePositions.row(branch[i - 1])).norm(), 0.05 - 1e-12);
  }
  // Every point of the cloud now lies within 3 radii (the default factor) of a node.
  for (Eigen::Index p = 0; p < l.Cloud.Positions.rows(); ++p)
  {
    double nearest = 1e300;
    for (Eigen::Index v = 0; v < l.Graph.NodePositions.rows(); ++v)
    {
      nearest = std::min(nearest, (l.Cloud.Positions.row(p) - l.Graph.NodePositions.row(v)).norm());
    }
    EXPECT_LE(nearest, 0.3) << "point " << p;
  }
  // The bones were assigned again: the line turns into the arm at (4,0,0), a node of degree
  // 2, so the tree is one branch of length 4 + 2.
  EXPECT_EQ(l.Graph.BoneLength.size(), 1u);
  EXPECT_NEAR(l.Graph.BoneLength[0], 6.0, 1e-9);
}

TEST(SkeletonCoverage, AThinLimbBelowTheShareGetsABranch)
{
  // 12 points of radius 0.02 along y up to 1.2 (60 radii): 0.6 % of the cloud, under the 1 %
  // a group needs, but on a line and long: a tail.
  LCloud tail = MakeLineWith(ThinArm(12, 0.1), 0.02);
  ASSERT_EQ(Reach(tail), 1u);
  EXPECT_NEAR((tail.Graph.NodePositions.row(tail.Graph.Polylines.back().back()) -
                Eigen::RowVector3d(20.0, 1.2, 0.0)).norm(), 0.0, 1e-12) << "to the limb's tip";
  // Off, or with the tip closer than ThinLimbFactor radii (6 uncovered points up to 0.098:
  // 4.9 radii), or below ThinLimbMinimumShare (3 points, 0.15 %): no branch.
  SkeletonCoverageOptions off;
  off.ThinLimbFactor = 0.0;
  LCloud same = MakeLineWith(ThinArm(12, 0.1), 0.02);
  EXPECT_EQ(Reach(same, {}, off), 0u);
  LCloud stub = MakeLineWith(ThinArm(14, 0.007), 0.02);
  EXPECT_EQ(Reach(stub), 0u);
  LCloud few = MakeLineWith(ThinArm(3, 0.4), 0.02);
  EXPECT_EQ(Reach(few), 0u);
}

namespace
{

/// side x side points of radius 0.02, 0.1 apart, in a square centred on x = 20 rising from the
/// line (y = 0.1 ... 0.1 side): a flat group, not along a line (linearity 0.5).
std::vector<Eigen::Vector3d> FlatPad(int side)
{
  std::vector<Eigen::Vector3d> pad;
  for (int i = 0; i < side; ++i)
  {
    for (int j = 0; j < side; ++j)
    {
      pad.emplace_back(20.0 + 0.1 * (i - 0.5 * (side - 1)), 0.1 + 0.1 * j, 0.0);
    }
  }
  return pad;
}

} // namespace

TEST(SkeletonCoverage, ASmallFlatLimbGetsABranchASmallerPadNone)
{
  // 16 points up to 0.4 (tip 20 radii away): 0.79 % of the cloud, under the 1 % a group needs,
  // not along a line, but above SmallLimbMinimumShare (0.5 %): a hand, a fin.
  LCloud hand = MakeLineWith(FlatPad(4), 0.02);
  ASSERT_EQ(Reach(hand), 1u);
  EXPECT_NEAR(hand.Graph.NodePositions(hand.Graph.Polylines.back().back(), 1), 0.4, 0.05)
    << "to the far end";
  // 9 points (0.45 %, a toe pad): none; nor with small limbs off, nor with the tip closer than
  // ThinLimbFactor radii.
  LCloud pad = MakeLineWith(FlatPad(3), 0.02);
  EXPECT_EQ(Reach(pad), 0u);
  SkeletonCoverageOptions off;
  off.SmallLimbMinimumShare = 0.0;
  LCloud same = MakeLineWith(FlatPad(4), 0.02);
  EXPECT_EQ(Reach(same, {}, off), 0u);
  SkeletonCoverageOptions farther;
  farther.ThinLimbFactor = 25.0;
  LCloud near = MakeLineWith(FlatPad(4), 0.02);
  EXPECT_EQ(Reach(near, {}, farther), 0u);
  // The small pad counts as a large group when the share allows it.
  SkeletonCoverageOptions anySize;
  anySize.MinimumShare = 0.001;
  LCloud large = MakeLineWith(FlatPad(3), 0.02);
  EXPECT_EQ(Reach(large, {}, anySize), 1u);
}

TEST(SkeletonCoverage, SmallGroupsFactorZeroAndThreadsDoNotChangeTheResult)
{
  // An arm of 0.35: only its last two points are farther than 3 radii from the line, 2 of 211
  // points, below the default share of 1 % (2.11 points).
  LCloud small = MakeL(10, 0.35);
  EXPECT_EQ(Reach(small), 0u);
  EXPECT_EQ(small.Graph.Polylines.size(), 1u);

  SkeletonCoverageOptions off;
  off.UncoveredFactor = 0.0;
  LCloud unchanged = MakeL(100);
  EXPECT_EQ(Reach(unchanged, {}, off), 0u);
  EXPECT_EQ(unchanged.Graph.NodePositions.rows(), 21);

  LCloud serial = MakeL(100);
  LCloud threaded = MakeL(100);
  Reach(serial);
  Reach(threaded, {}, {}, ThreadedFor(3));
  EXPECT_TRUE(serial.Graph.NodePositions == threaded.Graph.NodePositions);
  EXPECT_EQ(serial.Graph.Polylines, threaded.Graph.Polylines);
}

namespace
{

/// Points every 0.02 from `from` to `to`, `from` left out.
std::vector<Eigen::Vector3d> Segment(const Eigen::Vector3d& from, const Eigen::Vector3d& to)
{
  std::vector<Eigen::Vector3d> points;
  const auto count = static_cast<int>(std::lround((to - from).norm() / 0.02));
  for (int i = 1; i <= count; ++i)
  {
    points.push_back(from + (to - from) * i / count);
  }
  return points;
}

/// Off the covered line at (20,0,0): a stem up to (20,`forkAt`,0), an arm on up to
/// (20,2.5,0), and a side arm from the fork along x for `sideLength`; radius 0.1 throughout.
/// The stem above 0.3 (three radii), both arms and the side arm are one uncovered group.
LCloud MakeFork(double forkAt, double sideLength)
{
  std::vector<Eigen::Vector3d> extra = Segment({ 20, 0, 0 }, { 20, 2.5, 0 });
  const std::vector<Eigen::Vector3d> side = Segment({ 20, forkAt, 0 }, { 20 + sideLength, forkAt, 0 });
  extra.insert(extra.end(), side.begin(), side.end());
  return MakeLineWith(extra, 0.1);
}

} // namespace

TEST(SkeletonCoverage, TwoLimbsOfOneGroupMeetingNearTheTreeGetABranchEach)
{
  // The side arm (1.5 long) leaves the stem 0.2 above where the group meets the covered
  // points, at 0.12 of its far end's depth (1.7): a limb of its own, as an ear beside a snout.
  LCloud fork = MakeFork(0.5, 1.5);
  ASSERT_EQ(Reach(fork), 2u) << "the farthest arm, then the side arm";
  const Eigen::RowVector3d sideEnd(21.5, 0.5, 0.0);
  const Eigen::RowVector3d armEnd(20.0, 2.5, 0.0);
  const auto endOf = [&](std::size_t polyline) {
    return Eigen::RowVector3d(fork.Graph.NodePositions.row(fork.Graph.Polylines[polyline].back()));
  };
  const std::size_t count = fork.Graph.Polylines.size();
  EXPECT_NEAR((endOf(count - 1) - sideEnd).norm(), 0.0, 1e-12);
  EXPECT_LT((endOf(count - 2) - armEnd).norm(), 0.05) << "the first branch ends at the arm's far end";
  // Without side limbs, or with a side arm under three radii (0.25), one branch.
  SkeletonCoverageOptions off;
  off.SideLimbJoinDepth = 0.0;
  LCloud single = MakeFork(0.5, 1.5);
  EXPECT_EQ(Reach(single, {}, off), 1u);
  LCloud stub = MakeFork(0.5, 0.24);
  EXPECT_EQ(Reach(stub), 1u);
  // Threads do not change it.
  LCloud threaded = MakeFork(0.5, 1.5);
  ASSERT_EQ(Reach(threaded, {}, {}, ThreadedFor(3)), 2u);
  EXPECT_TRUE(threaded.Graph.NodePositions == fork.Graph.NodePositions);
  EXPECT_EQ(threaded.Graph.Polylines, fork.Graph.Polylines);
}

TEST(SkeletonCoverage, AFlapThatMeetsItsGroupDeepInsideGetsNoBranchOfItsOwn)
{
  // The side arm leaves at 2.0, 1.7 deep, and reaches 2.7: its region and the arm's meet at
  // 0.77 of the arm's depth (2.2), beyond SideLimbJoinDepth (1/3): the lobes of one limb, as
  // an elephant ear's flaps. One branch, to the farthest point (the arm's end).
  LCloud flap = MakeFork(2.0, 1.0);
  ASSERT_EQ(Reach(flap), 1u);
  EXPECT_LT((flap.Graph.NodePositions.row(flap.Graph.Polylines.back().back()) - Eigen::RowVector3d(20, 2.5, 0)).norm(), 0.05);
  // Allowed to meet anywhere, the region without the branch gets one.
  SkeletonCoverageOptions anywhere;
  anywhere.SideLimbJoinDepth = 1.0;
  LCloud both = MakeFork(2.0, 1.0);
  EXPECT_EQ(Reach(both, {}, anywhere), 2u);
}

TEST(SkeletonCoverage, APointWhoseNearestNodeIsBehindTheSurfaceIsUncovered)
{
  // A wall across the arm at y = 0.15 (two triangles, x 3.5-4.5, z -1-1): the arm's points
  // between 0.15 and 0.3 lie within three radii of the corner node (4,0,0) but behind the
  // wall from it, as a hind leg's points lie near a tail's nodes. Without the volume they are
  // covered and the branch's first step goes above 0.3; with it, it starts below the wall.
  PointMatrix wallPoints(4, 3);
  wallPoints << 3.5, 0.15, -1.0, 4.5, 0.15, -1.0, 4.5, 0.15, 1.0, 3.5, 0.15, 1.0;
  TriangleMatrix wallTriangles(2, 3);
  wallTriangles << 0, 1, 2, 0, 2, 3;
  const BruteForceRayCaster wall(wallPoints, wallTriangles);
  const auto secondNodeHeight = [](const LCloud& l) {
    return l.Graph.NodePositions(l.Graph.Polylines.back()[1], 1);
  };
  LCloud open = MakeL(100);
  ASSERT_EQ(Reach(open), 1u);
  EXPECT_GT(secondNodeHeight(open), 0.3);
  LCloud walled = MakeL(100);
  const CloudNeighborGraph neighbours = BuildCloudNeighborGraph(walled.Cloud, {}, 8, SerialFor);
  ASSERT_EQ(ReachUncoveredParts(walled.Graph, walled.Cloud, walled.Thinned, {}, neighbours, {}, SerialFor, &wall), 1u);
  EXPECT_LT(secondNodeHeight(walled), 0.3);
  EXPECT_LT(secondNodeHeight(walled), secondNodeHeight(open) - 0.1);
}

TEST(SkeletonCoverage, PointsOfAnotherComponentAreNotJoined)
{
  // The arm is another surface component with no node of its own: nothing to join it to.
  LCloud l = MakeL(100);
  std::vector<std::int64_t> component(static_cast<std::size_t>(l.Cloud.Positions.rows()), 0);
  for (std::size_t p = 201; p < component.size(); ++p)
  {
    component[p] = 1;
  }
  EXPECT_EQ(Reach(l, component), 0u);
}

TEST(SkeletonCoverage, APieceReachedOnlyByABridgeGetsNoBranch)
{
  // The arm moved 1 up, away from the line: the neighbour graph has two pieces, linked by a
  // bridge that was not tested against any surface; the branch would cross the gap.
  LCloud l = MakeL(100);
  for (Eigen::Index p = 201; p < l.Cloud.Positions.rows(); ++p)
  {
    l.Cloud.Positions(p, 1) += 1.0;
  }
  l.Thinned.Positions = l.Cloud.Positions;
  const CloudNeighborGraph neighbours = BuildCloudNeighborGraph(l.Cloud, {}, 8, SerialFor);
  EXPECT_EQ(std::count(neighbours.IsBridge.begin(), neighbours.IsBridge.end(), 1), 2)
    << "one bridge, stored both ways";
  EXPECT_EQ(ReachUncoveredParts(l.Graph, l.Cloud, l.Thinned, {}, neighbours, {}, SerialFor), 0u);
  EXPECT_EQ(l.Graph.Polylines.size(), 1u);
}

TEST(SkeletonCoverage, APieceLinkedByABridgeInsideTheVolumeGetsABranch)
{
  // The arm 1 up as above, built with a volume: a wall (two triangles, y = 0.5, z -1-1) across
  // the gap between the line's end and the arm keeps the link a bridge (no branch); the same
  // wall beside the gap (x 10-11) leaves the link inside the volume, an edge the k nearest
  // missed (a thin ear whose points' neighbours are all its own), and the arm gets its branch.
  const auto shiftedArm = [] {
    LCloud l = MakeL(100);
    for (Eigen::Index p = 201; p < l.Cloud.Positions.rows(); ++p)
    {
      l.Cloud.Positions(p, 1) += 1.0;
    }
    l.Thinned.Positions = l.Cloud.Positions;
    return l;
  };
  TriangleMatrix wallTriangles(2, 3);
  wallTriangles << 0, 1, 2, 0, 2, 3;
  PointMatrix across(4, 3), beside(4, 3);
  across << 3.5, 0.5, -1.0, 4.5, 0.5, -1.0, 4.5, 0.5, 1.0, 3.5, 0.5, 1.0;
  beside << 10.0, 0.5, -1.0, 11.0, 0.5, -1.0, 11.0, 0.5, 1.0, 10.0, 0.5, 1.0;
  const BruteForceRayCaster wallAcross(across, wallTriangles);
  const BruteForceRayCaster wallBeside(beside, wallTriangles);
  for (const auto& [wall, branches] :
    { std::make_pair(&wallAcross, std::size_t{ 0 }), std::make_pair(&wallBeside, std::size_t{ 1 }) })
  {
    LCloud l = shiftedArm();
    const CloudNeighborGraph neighbours = BuildCloudNeighborGraph(l.Cloud, {}, 8, SerialFor, wall);
    EXPECT_EQ(std::count(neighbours.IsBridge.begin(), neighbours.IsBridge.end(), 1), 2 * (1 - static_cast<int>(branches)));
    EXPECT_EQ(ReachUncoveredParts(l.Graph, l.Cloud, l.Thinned, {}, neighbours, {}, SerialFor, wall), branches);
  }
}

TEST(SkeletonCoverage, APartWithoutABoneGetsABranchWhenItsTipIsFarFromTheSkeleton)
{
  // Step 6: an arm of 0.3 (three radii): within step 5's four radii, so step 5 leaves it, but
  // as a part of its own with no bone it gets a branch (tip 3 radii > PartUncoveredFactor 2).
  LCloud l = MakeL(30, 0.3);
  EXPECT_EQ(Reach(l), 0u);
  const CloudNeighborGraph neighbours = BuildCloudNeighborGraph(l.Cloud, {}, 8, SerialFor);
  const auto n = static_cast<std::size_t>(l.Cloud.Positions.rows());
  std::vector<char> arm(n, 0);
  std::fill(arm.begin() + 201, arm.end(), 1);
  LCloud threaded = l;
  ASSERT_EQ(ReachPartsWithoutBones(l.Graph, l.Cloud, l.Thinned, {}, neighbours, arm, {}, SerialFor), 1u);
  const std::vector<std::int64_t>& branch = l.Graph.Polylines.back();
  EXPECT_EQ(l.Graph.IsConnection.back(), 1);
  EXPECT_NEAR((l.Graph.NodePositions.row(branch.front()) - Eigen::RowVector3d(4, 0, 0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((l.Graph.NodePositions.row(branch.back()) - Eigen::RowVector3d(4, 0.3, 0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(l.Graph.BoneLength[0], 4.3, 1e-9) << "bones assigned again: the line turns into the arm";
  ASSERT_EQ(ReachPartsWithoutBones(threaded.Graph, threaded.Cloud, threaded.Thinned, {}, neighbours, arm, {},
              ThreadedFor(3)), 1u);
  EXPECT_TRUE(threaded.Graph.NodePositions == l.Graph.NodePositions);
  EXPECT_EQ(threaded.Graph.Polylines, l.Graph.Polylines);

  // Its tip within PartUncoveredFactor radii: the skeleton runs close enough, no branch.
  SkeletonCoverageOptions strict;
  strict.PartUncoveredFactor = 4.0;
  LCloud near = MakeL(30, 0.3);
  EXPECT_EQ(ReachPartsWithoutBones(near.Graph, near.Cloud, near.Thinned, {}, neighbours, arm, strict, SerialFor), 0u);
  EXPECT_EQ(near.Graph.Polylines.size(), 1u);
  // A part along the line the skeleton already follows gets none either.
  std::vector<char> onLine(n, 0);
  std::fill(onLine.begin() + 50, onLine.begin() + 100, 1);
  EXPECT_EQ(ReachPartsWithoutBones(near.Graph, near.Cloud, near.Thinned, {}, neighbours, onLine, {}, SerialFor), 0u);
  // Flags of another cloud are refused.
  EXPECT_THROW(ReachPartsWithoutBones(near.Graph, near.Cloud, near.Thinned, {}, neighbours,
                 std::vector<char>(n - 1, 0), {}, SerialFor),
    Error);
}

TEST(SkeletonCoverage, OptionsOutsideTheirRangeThrow)
{
  SkeletonCoverageOptions options;
  options.UncoveredFactor = -1.0;
  EXPECT_THROW(ValidateCoverageOptions(options), Error);
  options = {};
  options.MinimumShare = 1.5;
  EXPECT_THROW(ValidateCoverageOptions(options), Error);
  options = {};
  options.PartMinimumShare = -0.1;
  EXPECT_THROW(ValidateCoverageOptions(options), Error);
  options = {};
  options.PartUncoveredFactor = -1.0;
  EXPECT_THROW(ValidateCoverageOptions(options), Error);
  options = {};
  options.ThinLimbFactor = -1.0;
  EXPECT_THROW(ValidateCoverageOptions(options), Error);
  options = {};
  options.ThinLimbLinearity = 1.5;
  EXPECT_THROW(ValidateCoverageOptions(options), Error);
  options = {};
  options.ThinLimbMinimumShare = std::nan("");
  EXPECT_THROW(ValidateCoverageOptions(options), Error);
  options = {};
  options.SideLimbJoinDepth = 1.5;
  EXPECT_THROW(ValidateCoverageOptions(options), Error);
  options = {};
  options.SmallLimbMinimumShare = 2.0;
  EXPECT_THROW(ValidateCoverageOptions(options), Error);
  EXPECT_NO_THROW(ValidateCoverageOptions({}));
}

TEST(SkeletonCoverage, UsesTheConnectionsNeighbourGraph)
{
  // The graph ConnectPolySegments hands out is the one BuildCloudNeighborGraph builds alone
  // (here without segments: the L is one blob for the connection).
  LCloud l = MakeL(100);
  bool aborted = false;
  CloudNeighborGraph fromConnection;
  ConnectPolySegments(l.Cloud, l.Thinned, {}, {}, {}, SerialFor, {}, aborted, nullptr, &fromConnection);
  ASSERT_FALSE(aborted);
  const CloudNeighborGraph alone = BuildCloudNeighborGraph(
    l.Cloud, {}, SkeletonConnectionOptions().NumberOfNeighbors, ThreadedFor(3));
  EXPECT_EQ(fromConnection.Offsets, alone.Offsets);
  EXPECT_EQ(fromConnection.Targets, alone.Targets);
  EXPECT_EQ(fromConnection.Weights, alone.Weights);
  EXPECT_EQ(fromConnection.IsBridge, alone.IsBridge);
  EXPECT_EQ(fromConnection.Offsets.size(), static_cast<std::size_t>(l.Cloud.Positions.rows()) + 1);

  // A graph of another cloud is refused.
  LCloud other = MakeL(10);
  EXPECT_THROW(ReachUncoveredParts(l.Graph, l.Cloud, l.Thinned, {},
                 BuildCloudNeighborGraph(other.Cloud, {}, 8, SerialFor), {}, SerialFor),
    Error);
}
