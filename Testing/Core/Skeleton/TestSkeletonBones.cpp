// SPDX-License-Identifier: BSD-3-Clause
// The skeleton's tree topology (SkeletonBones.h) on hand-made graphs: bones are the
// branches of the forest (polylines cut at junctions, numbered by length), and the junction
// cleaning (leaf stubs removed, short inner branches contracted).
#include "Skeleton/SkeletonBones.h"
#include "Skeleton/SkeletonTestSupport.h"

#include <gtest/gtest.h>

#include <map>

namespace
{

using namespace shapediameter;
using namespace shapediameter::testshapes;
using namespace shapediameter::skeletontests;

SkeletonGraph MakeGraph(const std::vector<Eigen::Vector3d>& positions,
  std::vector<std::vector<std::int64_t>> polylines, std::vector<int> isConnection)
{
  SkeletonGraph graph;
  graph.NodePositions.resize(static_cast<Eigen::Index>(positions.size()), 3);
  for (std::size_t i = 0; i < positions.size(); ++i)
  {
    graph.NodePositions.row(static_cast<Eigen::Index>(i)) = positions[i].transpose();
  }
  graph.Polylines = std::move(polylines);
  graph.IsConnection = std::move(isConnection);
  return graph;
}

TEST(SkeletonBones, PolylineThroughAJunctionIsCut)
{
  // A fitted segment 0-1-2-3-4 along x (2 units left of node 2, 3 units right of it), a
  // connecting path 2-5-6 leaving node 2 along y (1 unit), a blob node 7 and a node 8 that no
  // polyline holds. Branches: 2..4 (3), 0..2 (2), 2..6 (1), {7}, {8}.
  SkeletonGraph graph = MakeGraph({ { -2, 0, 0 }, { -1, 0, 0 }, { 0, 0, 0 }, { 1.5, 0, 0 },
                                    { 3, 0, 0 }, { 0, 0.5, 0 }, { 0, 1, 0 }, { 9, 9, 9 }, { 8, 8, 8 } },
    { { 0, 1, 2, 3, 4 }, { 2, 5, 6 }, { 7 } }, { 0, 1, 0 });
  AssignBranchBones(graph);
  const std::vector<std::vector<std::int64_t>> polylines{ { 0, 1, 2 }, { 2, 3, 4 }, { 2, 5, 6 },
    { 7 }, { 8 } };
  EXPECT_EQ(graph.Polylines, polylines);
  EXPECT_EQ(graph.IsConnection, (std::vector<int>{ 0, 0, 1, 0, 0 }));
  EXPECT_EQ(graph.PolylineBone, (std::vector<std::int64_t>{ 1, 0, 2, 3, 4 }));
  EXPECT_EQ(graph.BoneLength, (std::vector<double>{ 3.0, 2.0, 1.0, 0.0, 0.0 }));
  // The junction takes the lowest (longest) bone meeting there.
  EXPECT_EQ(graph.NodeBone, (std::vector<std::int64_t>{ 1, 1, 0, 0, 0, 2, 2, 3, 4 }));
  ExpectBonesAreBranches(graph.NodePositions, graph.Polylines, graph.PolylineBone,
    graph.NodeBone, graph.BoneLength);

  // Idempotent.
  const SkeletonGraph again = [&graph] {
    SkeletonGraph copy = graph;
    AssignBranchBones(copy);
    return copy;
  }();
  EXPECT_EQ(again.Polylines, graph.Polylines);
  EXPECT_EQ(again.PolylineBone, graph.PolylineBone);
  EXPECT_EQ(again.NodeBone, graph.NodeBone);
  EXPECT_EQ(again.BoneLength, graph.BoneLength);
}

TEST(SkeletonBones, PiecesOfOneBranchShareItsBone)
{
  // A path cut into three polylines (segment, connection, segment) is one bone; the same path
  // with a side branch at node 3 is three.
  std::vector<Eigen::Vector3d> positions;
  for (int i = 0; i < 7; ++i)
  {
    positions.emplace_back(i, 0, 0);
  }
  SkeletonGraph path = MakeGraph(positions, { { 0, 1, 2 }, { 2, 3, 4 }, { 4, 5, 6 } }, { 0, 1, 0 });
  AssignBranchBones(path);
  EXPECT_EQ(path.PolylineBone, (std::vector<std::int64_t>{ 0, 0, 0 }));
  EXPECT_EQ(path.Polylines.size(), 3u);
  EXPECT_EQ(path.BoneLength, std::vector<double>{ 6.0 });

  positions.emplace_back(3, 2, 0);
  SkeletonGraph branched =
    MakeGraph(positions, { { 0, 1, 2 }, { 2, 3, 4 }, { 4, 5, 6 }, { 3, 7 } }, { 0, 1, 0, 1 });
  AssignBranchBones(branched);
  // Branches 0..3 and 3..6 both have length 3: the one with the lower node (0) comes first.
  EXPECT_EQ(branched.Polylines, (std::vector<std::vector<std::int64_t>>{
                                  { 0, 1, 2 }, { 2, 3 }, { 3, 4 }, { 4, 5, 6 }, { 3, 7 } }));
  EXPECT_EQ(branched.IsConnection, (std::vector<int>{ 0, 1, 1, 0, 1 }));
  EXPECT_EQ(branched.PolylineBone, (std::vector<std::int64_t>{ 0, 0, 1, 1, 2 }));
  EXPECT_EQ(branched.BoneLength, (std::vector<double>{ 3.0, 3.0, 2.0 }));
  EXPECT_EQ(branched.NodeBone[3], 0);
  ExpectBonesAreBranches(branched.NodePositions, branched.Polylines, branched.PolylineBone,
    branched.NodeBone, branched.BoneLength);
}

TEST(SkeletonBones, LoopsRepeatsAndBadIndices)
{
  // A closed square (not produced by the steps, but accepted) is one bone cut at node 0; a
  // repeated node and an edge held by two polylines do not create bones.
  SkeletonGraph loop = MakeGraph({ { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 } },
    { { 1, 2, 2, 3 }, { 3, 0, 1 }, { 0, 1 } }, { 0, 1, 1 });
  AssignBranchBones(loop);
  EXPECT_EQ(loop.BoneLength, std::vector<double>{ 4.0 });
  EXPECT_EQ(loop.PolylineBone, (std::vector<std::int64_t>{ 0, 0, 0 }));
  EXPECT_EQ(loop.NodeBone, (std::vector<std::int64_t>{ 0, 0, 0, 0 }));
  EXPECT_EQ(loop.Polylines[0], (std::vector<std::int64_t>{ 1, 2, 2, 3 }));

  SkeletonGraph empty = MakeGraph({}, {}, {});
  AssignBranchBones(empty);
  EXPECT_TRUE(empty.BoneLength.empty() && empty.Polylines.empty() && empty.NodeBone.empty());

  SkeletonGraph bad = MakeGraph({ { 0, 0, 0 } }, { { 0, 1 } }, { 0 });
  EXPECT_THROW(AssignBranchBones(bad), Error);
  bad = MakeGraph({ { 0, 0, 0 } }, { { 0 } }, {});
  EXPECT_THROW(AssignBranchBones(bad), Error);
}

TEST(SkeletonBones, JunctionCleaning)
{
  // A torso 0..9 along y (radius 2), an arm joining it at vertex 3 by a connecting path
  // 3-10-11-12 whose fitted segment 19-18-12-...-17 overshoots back towards the torso (stub
  // 12-18-19, longer than the arm's radius at 12 but ending inside the torso's ball), a second
  // arm joining at vertex 4 (one unit from 3: an inner branch shorter than the radius), a long
  // arm from 6 whose hand rests inside the torso's ball near vertex 2 (kept: longer than two
  // radii), and a big ball of another component (ignored).
  std::map<std::int64_t, Eigen::Vector3d> position;
  std::map<std::int64_t, double> radius;
  std::map<std::int64_t, std::int64_t> component;
  const auto add = [&](std::int64_t v, double x, double y, double r, std::int64_t c = 0) {
    position[v] = Eigen::Vector3d(x, y, 0);
    radius[v] = r;
    component[v] = c;
  };
  for (int i = 0; i <= 9; ++i)
  {
    add(i, 0, i, 2.0);
  }
  for (int i = 10; i <= 17; ++i)
  {
    add(i, i - 9, 3, 0.5);
  }
  add(18, 2.2, 3.3, 0.5);
  add(19, 1.5, 3.4, 0.5);
  for (int i = 50; i <= 55; ++i)
  {
    add(i, -(i - 49), 4, 0.5);
  }
  add(40, -1, 6, 0.5);
  add(41, -2, 6, 0.5);
  add(42, -3, 5, 0.5);
  add(43, -3, 4, 0.5);
  add(44, -3, 3, 0.5);
  add(45, -1.5, 1.8, 0.5);
  add(99, 8.5, 3, 5.0, 1);
  const std::vector<std::vector<std::int64_t>> input{ { 0, 1, 2, 3, 4, 5, 6, 7, 8, 9 },
    { 3, 10, 11, 12 }, { 19, 18, 12, 13, 14, 15, 16, 17 }, { 4, 50 }, { 50, 51, 52, 53, 54, 55 },
    { 6, 40, 41, 42, 43, 44, 45 }, { 99 } };
  const std::vector<int> inputIsConnection{ 0, 1, 0, 1, 0, 1, 0 };
  const auto positionOf = [&](std::int64_t v) { return position.at(v); };
  const auto radiusOf = [&](std::int64_t v) { return radius.at(v); };
  const auto componentOf = [&](std::int64_t v) { return component.at(v); };

  std::vector<std::vector<std::int64_t>> polylines = input;
  std::vector<int> isConnection = inputIsConnection;
  CleanJunctions(polylines, isConnection, positionOf, radiusOf, componentOf, 1.0);
  const std::vector<std::vector<std::int64_t>> expected{ { 0, 1, 2, 3, 5, 6, 7, 8, 9 },
    { 3, 10, 11, 12 }, { 12, 13, 14, 15, 16, 17 }, { 3, 50 }, { 50, 51, 52, 53, 54, 55 },
    { 6, 40, 41, 42, 43, 44, 45 }, { 99 } };
  EXPECT_EQ(polylines, expected);
  EXPECT_EQ(isConnection, inputIsConnection);

  // Without leaf pruning the stub 12-18-19 stays (so 12 stays a junction), and the inner
  // branch 3-4 is still contracted.
  polylines = input;
  isConnection = inputIsConnection;
  CleanJunctions(polylines, isConnection, positionOf, radiusOf, componentOf, 1.0, LeafPruning::Keep);
  const std::vector<std::vector<std::int64_t>> contractedOnly{ { 0, 1, 2, 3, 5, 6, 7, 8, 9 },
    { 3, 10, 11, 12 }, { 19, 18, 12, 13, 14, 15, 16, 17 }, { 3, 50 }, { 50, 51, 52, 53, 54, 55 },
    { 6, 40, 41, 42, 43, 44, 45 }, { 99 } };
  EXPECT_EQ(polylines, contractedOnly);
  EXPECT_EQ(isConnection, inputIsConnection);

  // Factor 0 keeps everything; a single path is never cut.
  polylines = input;
  isConnection = inputIsConnection;
  CleanJunctions(polylines, isConnection, positionOf, radiusOf, componentOf, 0.0);
  EXPECT_EQ(polylines, input);
  polylines = { { 0, 1 } };
  isConnection = { 0 };
  CleanJunctions(polylines, isConnection, positionOf, radiusOf, componentOf, 10.0);
  EXPECT_EQ(polylines, (std::vector<std::vector<std::int64_t>>{ { 0, 1 } }));
}

} // namespace
