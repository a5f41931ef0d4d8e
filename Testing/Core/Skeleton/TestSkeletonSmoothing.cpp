// SPDX-License-Identifier: BSD-3-Clause
// Tests of skeleton step 7 (SkeletonSmoothing.h) on hand-made bones whose answer is known: a
// straight bone stays as it is, a zig-zag becomes a nearly straight line, a smoothed bone does
// not leave the volume it ran through, and the option is checked.
#include "Skeleton/SkeletonSmoothing.h"

#include "RayCasting/EmbreeRayCaster.h"
#include "TestShapes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace
{

using namespace shapediameter;
using namespace shapediameter::testshapes;

/// One bone through `positions` (one polyline, leaves at both ends), radius `radius(i)`.
template <typename RadiusOf>
SkeletonGraph MakeBone(const std::vector<Eigen::Vector3d>& positions, RadiusOf radius)
{
  SkeletonGraph graph;
  const auto n = static_cast<Eigen::Index>(positions.size());
  graph.NodePositions.resize(n, 3);
  std::vector<std::int64_t> polyline;
  for (Eigen::Index i = 0; i < n; ++i)
  {
    graph.NodePositions.row(i) = positions[static_cast<std::size_t>(i)].transpose();
    graph.NodeRadius.push_back(radius(static_cast<std::size_t>(i)));
    graph.NodeConfidence.push_back(0.9);
    graph.NodeCloudIndex.push_back(i);
    graph.NodeComponent.push_back(0);
    graph.NodeBone.push_back(0);
    polyline.push_back(i);
  }
  graph.Polylines.push_back(polyline);
  graph.IsConnection.push_back(0);
  graph.PolylineBone.push_back(0);
  graph.BoneLength.push_back(0.0);
  return graph;
}

/// Largest turning angle (degrees) at the interior nodes of the graph's single polyline.
double LargestTurningAngle(const SkeletonGraph& graph)
{
  double largest = 0.0;
  const Eigen::Index n = graph.NodePositions.rows();
  for (Eigen::Index i = 1; i + 1 < n; ++i)
  {
    const Eigen::Vector3d in = graph.NodePositions.row(i) - graph.NodePositions.row(i - 1);
    const Eigen::Vector3d out = graph.NodePositions.row(i + 1) - graph.NodePositions.row(i);
    const double cosine = std::clamp(in.normalized().dot(out.normalized()), -1.0, 1.0);
    largest = std::max(largest, std::acos(cosine) * 180.0 / Pi);
  }
  return largest;
}

TEST(SkeletonSmoothing, StraightBoneWithLinearRadiusStaysAsItIs)
{
  // A local linear fit reproduces a straight line and a linear radius exactly, ends included.
  std::vector<Eigen::Vector3d> positions;
  for (int i = 0; i <= 40; ++i)
  {
    positions.emplace_back(0.1 * i, 0.05 * i, -0.02 * i);
  }
  SkeletonGraph graph = MakeBone(positions, [](std::size_t i) { return 0.2 + 0.01 * i; });
  const SkeletonGraph before = graph;
  SmoothBones(graph, nullptr, {});
  EXPECT_LT((graph.NodePositions - before.NodePositions).cwiseAbs().maxCoeff(), 1e-9);
  for (std::size_t i = 0; i < graph.NodeRadius.size(); ++i)
  {
    EXPECT_NEAR(graph.NodeRadius[i], before.NodeRadius[i], 1e-9) << i;
  }
  EXPECT_EQ(graph.Polylines, before.Polylines);
}

TEST(SkeletonSmoothing, ZigZagBecomesNearlyStraight)
{
  // Nodes every 0.1 along x, alternately 0.03 above and below the axis, radius 0.3: turning
  // angles of about 60 degrees before; after, the nodes are within a tenth of the zig-zag's
  // amplitude of the axis away from the ends and turn by less than 3 degrees.
  std::vector<Eigen::Vector3d> positions;
  for (int i = 0; i <= 60; ++i)
  {
    positions.emplace_back(0.1 * i, (i % 2 == 0 ? 0.03 : -0.03), 0.0);
  }
  SkeletonGraph graph = MakeBone(positions, [](std::size_t) { return 0.3; });
  ASSERT_GT(LargestTurningAngle(graph), 50.0);
  const BoneSmoothingResult result = SmoothBones(graph, nullptr, {});
  EXPECT_EQ(result.MovedNodes, positions.size());
  EXPECT_EQ(result.HeldNodes, 0u);
  EXPECT_LT(LargestTurningAngle(graph), 3.0);
  for (Eigen::Index i = 10; i <= 50; ++i)
  {
    EXPECT_LT(std::abs(graph.NodePositions(i, 1)), 0.003) << i;
    EXPECT_NEAR(graph.NodeRadius[static_cast<std::size_t>(i)], 0.3, 1e-9);
  }
  // The ends stay where the bone ends (along its line), not pulled inwards.
  EXPECT_NEAR(graph.NodePositions(0, 0), 0.0, 0.01);
  EXPECT_NEAR(graph.NodePositions(60, 0), 6.0, 0.01);
}

TEST(SkeletonSmoothing, SmoothedBoneStaysInsideTheVolumeItRanThrough)
{
  // Three quarters of the core circle of a thin torus (R = 1, r = 0.1), with node radii of
  // 1 (far larger than the tube): without the volume the fit pulls the arc into the hole and
  // some edges cross the tube's surface; with it no edge does, and nodes are held.
  const TestMesh torus = MakeTorus(1.0, 0.1, 144, 24);
  const EmbreeRayCaster volume(torus.Points, torus.Triangles);
  std::vector<Eigen::Vector3d> positions;
  for (int i = 0; i <= 90; ++i)
  {
    const double angle = 1.5 * Pi * i / 90.0;
    const double wobble = i % 2 == 0 ? 0.02 : -0.02;
    positions.emplace_back((1.0 + wobble) * std::cos(angle), (1.0 + wobble) * std::sin(angle), 0.0);
  }
  const auto edgesCrossing = [&](const SkeletonGraph& graph) {
    int crossing = 0;
    for (Eigen::Index i = 1; i < graph.NodePositions.rows(); ++i)
    {
      crossing += SegmentCrossesSurface(volume, graph.NodePositions.row(i - 1).transpose(),
                    graph.NodePositions.row(i).transpose())
        ? 1
        : 0;
    }
    return crossing;
  };
  SkeletonGraph free = MakeBone(positions, [](std::size_t) { return 1.0; });
  ASSERT_EQ(edgesCrossing(free), 0);
  SkeletonGraph held = free;
  SmoothBones(free, nullptr, {});
  EXPECT_GT(edgesCrossing(free), 0);
  const BoneSmoothingResult result = SmoothBones(held, &volume, {});
  EXPECT_EQ(edgesCrossing(held), 0);
  EXPECT_GT(result.HeldNodes, 0u);
}

TEST(SkeletonSmoothing, BandwidthZeroLeavesTheBonesAlone)
{
  std::vector<Eigen::Vector3d> positions;
  for (int i = 0; i <= 20; ++i)
  {
    positions.emplace_back(0.1 * i, (i % 2 == 0 ? 0.03 : -0.03), 0.0);
  }
  SkeletonGraph graph = MakeBone(positions, [](std::size_t) { return 0.3; });
  const SkeletonGraph before = graph;
  SkeletonSmoothingOptions off;
  off.Bandwidth = 0.0;
  const BoneSmoothingResult result = SmoothBones(graph, nullptr, off);
  EXPECT_EQ(result.MovedNodes, 0u);
  EXPECT_TRUE(graph.NodePositions == before.NodePositions);
  EXPECT_EQ(graph.NodeRadius, before.NodeRadius);
}

TEST(SkeletonSmoothing, BandwidthOutsideItsRangeIsAnError)
{
  SkeletonGraph graph = MakeBone({ { 0, 0, 0 }, { 1, 0, 0 } }, [](std::size_t) { return 0.3; });
  for (const double bandwidth : { -0.5, 100.5, std::numeric_limits<double>::quiet_NaN() })
  {
    SkeletonSmoothingOptions options;
    options.Bandwidth = bandwidth;
    EXPECT_THROW(SmoothBones(graph, nullptr, options), Error) << bandwidth;
  }
}

} // namespace
