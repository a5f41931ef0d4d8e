// SPDX-License-Identifier: BSD-3-Clause
// Tests of skeleton steps 4b and 7b (SkeletonLeafExtension.h): a leaf whose branch points
// head-on at its part's end is carried on to where a ball of its radius touches that end
// (4b), or TipReach of the way to the surface (7b); one that points at a side wall is not. On
// a capsule, whose medial curve ends at the cap centres and whose tips lie a radius beyond.
#include "RayCasting/EmbreeRayCaster.h"
#include "Skeleton/SkeletonLeafExtension.h"
#include "TestShapes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

namespace
{

using namespace shapediameter;
using namespace shapediameter::testshapes;

/// One polyline through the given nodes, all of the given radius, one component.
SkeletonGraph PathGraph(const std::vector<Eigen::Vector3d>& nodes, double radius)
{
  SkeletonGraph graph;
  graph.NodePositions.resize(static_cast<Eigen::Index>(nodes.size()), 3);
  std::vector<std::int64_t> polyline;
  for (std::size_t i = 0; i < nodes.size(); ++i)
  {
    graph.NodePositions.row(static_cast<Eigen::Index>(i)) = nodes[i].transpose();
    graph.NodeRadius.push_back(radius);
    graph.NodeConfidence.push_back(1.0);
    graph.NodeCloudIndex.push_back(static_cast<std::int64_t>(i));
    graph.NodeComponent.push_back(0);
    polyline.push_back(static_cast<std::int64_t>(i));
  }
  graph.Polylines.push_back(polyline);
  graph.IsConnection.push_back(0);
  return graph;
}

/// Nodes every `step` along the segment from a to b (both included).
std::vector<Eigen::Vector3d> Line(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double step)
{
  const int count = static_cast<int>(std::round((b - a).norm() / step));
  std::vector<Eigen::Vector3d> nodes;
  for (int i = 0; i <= count; ++i)
  {
    nodes.push_back(a + (b - a) * (static_cast<double>(i) / count));
  }
  return nodes;
}

TEST(SkeletonLeafExtension, ABranchStoppedShortReachesTheCapCentres)
{
  // Capsule of radius 0.5, cap centres at z = +-2; the branch stops at z = +-1.
  const TestMesh capsule = MakeCapsule(0.5, 2.0);
  const EmbreeRayCaster volume(capsule.Points, capsule.Triangles);
  SkeletonGraph graph = PathGraph(Line({ 0, 0, -1 }, { 0, 0, 1 }, 0.1), 0.5);
  const Eigen::Index before = graph.NodePositions.rows();
  EXPECT_EQ(ExtendLeavesToPartEnds(graph, volume, {}), 2u);
  ASSERT_EQ(graph.NodePositions.rows(), before + 2);
  ASSERT_EQ(graph.Polylines.size(), 3u);
  for (const Eigen::Index node : { before, before + 1 })
  {
    const Eigen::Vector3d position = graph.NodePositions.row(node).transpose();
    // The cap is tessellated: the exit lies within 0.5 (1 - cos 7.5 deg) of the sphere.
    EXPECT_NEAR(std::abs(position.z()), 2.0, 0.01);
    EXPECT_NEAR(position.head<2>().norm(), 0.0, 1e-9);
    EXPECT_EQ(graph.NodeRadius[static_cast<std::size_t>(node)], 0.5);
    EXPECT_EQ(graph.NodeConfidence[static_cast<std::size_t>(node)], 0.0);
  }
  // Each extension is a two-node polyline from its leaf.
  EXPECT_EQ(graph.Polylines[1].front(), 0);
  EXPECT_EQ(graph.Polylines[2].front(), before - 1);
}

TEST(SkeletonLeafExtension, ALeafAtTheCapCentreStays)
{
  const TestMesh capsule = MakeCapsule(0.5, 2.0);
  const EmbreeRayCaster volume(capsule.Points, capsule.Triangles);
  SkeletonGraph graph = PathGraph(Line({ 0, 0, -2 }, { 0, 0, 2 }, 0.1), 0.5);
  EXPECT_EQ(ExtendLeavesToPartEnds(graph, volume, {}), 0u);
  EXPECT_EQ(graph.Polylines.size(), 1u);
}

TEST(SkeletonLeafExtension, ABranchPointingAtASideWallStays)
{
  // A long capsule (cap centres at z = +-4); the branch runs 20 degrees off the axis, so its
  // line leaves through the cylinder at 70 degrees from the wall's normal.
  const TestMesh capsule = MakeCapsule(0.5, 4.0);
  const EmbreeRayCaster volume(capsule.Points, capsule.Triangles);
  const Eigen::Vector3d direction(std::sin(20.0 * Pi / 180.0), 0.0, std::cos(20.0 * Pi / 180.0));
  const SkeletonGraph start = PathGraph(Line(-0.5 * direction, 0.5 * direction, 0.05), 0.2);
  SkeletonGraph graph = start;
  EXPECT_EQ(ExtendLeavesToPartEnds(graph, volume, {}), 0u);
  EXPECT_EQ(graph.NodePositions.rows(), start.NodePositions.rows());
  // Not for lack of room: with any exit angle accepted, both ends run on to the wall.
  SkeletonLeafExtensionOptions anyAngle;
  anyAngle.MaximumExitAngle = 90.0;
  graph = start;
  EXPECT_EQ(ExtendLeavesToPartEnds(graph, volume, anyAngle), 2u);
}

TEST(SkeletonLeafExtension, ZeroAngleIsOffAndOptionsAreChecked)
{
  const TestMesh capsule = MakeCapsule(0.5, 2.0);
  const EmbreeRayCaster volume(capsule.Points, capsule.Triangles);
  SkeletonGraph graph = PathGraph(Line({ 0, 0, -1 }, { 0, 0, 1 }, 0.1), 0.5);
  SkeletonLeafExtensionOptions off;
  off.MaximumExitAngle = 0.0;
  EXPECT_EQ(ExtendLeavesToPartEnds(graph, volume, off), 0u);
  EXPECT_EQ(graph.Polylines.size(), 1u);
  for (const double bad : { -1.0, 90.5, std::nan("") })
  {
    SkeletonLeafExtensionOptions options;
    options.MaximumExitAngle = bad;
    EXPECT_THROW(ExtendLeavesToPartEnds(graph, volume, options), Error) << bad;
  }
}

/// PathGraph as one bone (bone 0, its length), as step 7b receives it.
SkeletonGraph PathBone(const std::vector<Eigen::Vector3d>& nodes, double radius)
{
  SkeletonGraph graph = PathGraph(nodes, radius);
  graph.NodeBone.assign(nodes.size(), 0);
  graph.PolylineBone.push_back(0);
  graph.BoneLength.push_back((nodes.back() - nodes.front()).norm());
  return graph;
}

TEST(SkeletonLeafExtension, TipsReachTheSurfaceInTheLeavesBone)
{
  // Capsule of radius 0.5, cap centres at z = +-2, tips at z = +-2.5; the bone stops at +-1.
  const TestMesh capsule = MakeCapsule(0.5, 2.0);
  const EmbreeRayCaster volume(capsule.Points, capsule.Triangles);
  SkeletonGraph graph = PathBone(Line({ 0, 0, -1 }, { 0, 0, 1 }, 0.1), 0.5);
  const Eigen::Index before = graph.NodePositions.rows();
  EXPECT_EQ(ExtendLeavesToSurface(graph, volume, {}), 2u);
  ASSERT_EQ(graph.NodePositions.rows(), before + 2);
  for (const Eigen::Index tip : { before, before + 1 })
  {
    EXPECT_NEAR(std::abs(graph.NodePositions(tip, 2)), 2.5, 1e-6);
    EXPECT_NEAR(graph.NodePositions(tip, 0), 0.0, 1e-9);
    EXPECT_EQ(graph.NodeRadius[static_cast<std::size_t>(tip)], 0.5) << "the leaf's radius";
    EXPECT_EQ(graph.NodeBone[static_cast<std::size_t>(tip)], 0);
  }
  ASSERT_EQ(graph.PolylineBone.size(), graph.Polylines.size());
  EXPECT_EQ(graph.PolylineBone.back(), 0);
  EXPECT_NEAR(graph.BoneLength[0], 5.0, 1e-6) << "tip to tip";
  // Again: the tips lie on the surface, less than r/4 from it, so nothing is added.
  EXPECT_EQ(ExtendLeavesToSurface(graph, volume, {}), 0u);
}

TEST(SkeletonLeafExtension, TipReachIsAShareOfTheWay)
{
  const TestMesh capsule = MakeCapsule(0.5, 2.0);
  const EmbreeRayCaster volume(capsule.Points, capsule.Triangles);
  SkeletonGraph graph = PathBone(Line({ 0, 0, -1 }, { 0, 0, 1 }, 0.1), 0.5);
  SkeletonLeafExtensionOptions half;
  half.TipReach = 0.5;
  EXPECT_EQ(ExtendLeavesToSurface(graph, volume, half), 2u);
  EXPECT_NEAR(std::abs(graph.NodePositions(graph.NodePositions.rows() - 1, 2)), 1.75, 1e-6);
  SkeletonLeafExtensionOptions off;
  off.TipReach = 0.0;
  graph = PathBone(Line({ 0, 0, -1 }, { 0, 0, 1 }, 0.1), 0.5);
  EXPECT_EQ(ExtendLeavesToSurface(graph, volume, off), 0u);
  off.TipReach = 1.0;
  off.MaximumExitAngle = 0.0;
  EXPECT_EQ(ExtendLeavesToSurface(graph, volume, off), 0u) << "MaximumExitAngle 0 turns both off";
  for (const double bad : { -0.1, 1.5, std::nan("") })
  {
    SkeletonLeafExtensionOptions options;
    options.TipReach = bad;
    EXPECT_THROW(ExtendLeavesToSurface(graph, volume, options), Error) << bad;
  }
}

TEST(SkeletonLeafExtension, ATipIsNotAddedTowardsASideWall)
{
  // The oblique branch of ABranchPointingAtASideWallStays: its leaves meet the wall at 70°.
  const TestMesh capsule = MakeCapsule(0.5, 4.0);
  const EmbreeRayCaster volume(capsule.Points, capsule.Triangles);
  const Eigen::Vector3d direction(std::sin(20.0 * Pi / 180.0), 0.0, std::cos(20.0 * Pi / 180.0));
  SkeletonGraph graph = PathBone(Line(-0.5 * direction, 0.5 * direction, 0.05), 0.2);
  EXPECT_EQ(ExtendLeavesToSurface(graph, volume, {}), 0u);
}

} // namespace
