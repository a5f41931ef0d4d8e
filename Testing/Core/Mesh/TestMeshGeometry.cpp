// SPDX-License-Identifier: BSD-3-Clause
// MeshGeometry: area-weighted vertex normals, vertex adjacency, per-cell reduction of
// per-triangle values.
#include "Mesh/MeshGeometry.h"
#include "TestShapes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace
{

using namespace shapediameter;
using namespace shapediameter::testshapes;

/// Unit tetrahedron (0, e_x, e_y, e_z), outward oriented, plus an unused fifth point.
TestMesh Tetrahedron()
{
  return Assemble({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 0, 0, 1 }, { 5, 5, 5 } },
    { { 0, 2, 1 }, { 0, 1, 3 }, { 0, 3, 2 }, { 1, 2, 3 } });
}

TEST(MeshGeometry, VertexNormalsOfACapsulePointOutward)
{
  const double radius = 1.0, halfLength = 2.0;
  const TestMesh capsule = MakeCapsule(radius, halfLength, 32, 8, 12);
  const PointMatrix normals = AreaWeightedVertexNormals(capsule.Points, capsule.Triangles);
  ASSERT_EQ(normals.rows(), capsule.Points.rows());
  Eigen::RowVector3d sum = Eigen::RowVector3d::Zero();
  for (Eigen::Index v = 0; v < capsule.Points.rows(); ++v)
  {
    // The exact outward normal: from the nearest point of the axis segment to the vertex.
    const Eigen::RowVector3d p = capsule.Points.row(v);
    const Eigen::RowVector3d axisPoint(0.0, 0.0, std::clamp(p.z(), -halfLength, halfLength));
    const Eigen::RowVector3d exact = (p - axisPoint).normalized();
    const Eigen::RowVector3d unit = normals.row(v).normalized();
    EXPECT_NEAR(unit.norm(), 1.0, 1e-12) << "vertex " << v;
    // By symmetry only the latitude step (90 / 8 degrees on the caps) tilts a vertex normal,
    // by less than half a step: cos(5.6 degrees) = 0.995.
    EXPECT_GT(unit.dot(exact), 0.99) << "vertex " << v;
    sum += normals.row(v);
  }
  // Every triangle adds its area vector to its three corners; on a closed surface the area
  // vectors sum to zero.
  EXPECT_LT(sum.norm(), 1e-12 * capsule.Faces());
}

TEST(MeshGeometry, VertexNormalsOfAFlatFanAreTwiceTheAdjacentArea)
{
  // A unit square split into four triangles around its centre (4), in the xy plane.
  const TestMesh fan = Assemble({ { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 }, { 0.5, 0.5, 0 } },
    { { 0, 1, 4 }, { 1, 2, 4 }, { 2, 3, 4 }, { 3, 0, 4 } });
  const PointMatrix normals = AreaWeightedVertexNormals(fan.Points, fan.Triangles);
  // Each triangle has area 1/4, area vector (0, 0, 1/2).
  EXPECT_EQ(normals.row(4), Eigen::RowVector3d(0, 0, 2.0));
  for (Eigen::Index corner = 0; corner < 4; ++corner)
  {
    EXPECT_EQ(normals.row(corner), Eigen::RowVector3d(0, 0, 1.0)) << "corner " << corner;
  }
  // Reversed winding: inward.
  const TestMesh flipped = Flipped(fan);
  EXPECT_EQ(AreaWeightedVertexNormals(flipped.Points, flipped.Triangles).row(4), Eigen::RowVector3d(0, 0, -2.0));
}

TEST(MeshGeometry, AnUnusedVertexHasAZeroNormalAndNoNeighbour)
{
  const TestMesh tetrahedron = Tetrahedron();
  EXPECT_EQ(AreaWeightedVertexNormals(tetrahedron.Points, tetrahedron.Triangles).row(4), Eigen::RowVector3d::Zero());
  const PointAdjacency adjacency = BuildPointAdjacency(tetrahedron.Points.rows(), tetrahedron.Triangles);
  EXPECT_EQ(adjacency.Offsets[4], adjacency.Offsets[5]);
}

TEST(MeshGeometry, AdjacencyOfATetrahedronJoinsEveryPair)
{
  const TestMesh tetrahedron = Tetrahedron();
  const PointAdjacency adjacency = BuildPointAdjacency(tetrahedron.Points.rows(), tetrahedron.Triangles);
  EXPECT_EQ(adjacency.Offsets, (std::vector<std::int64_t>{ 0, 3, 6, 9, 12, 12 }));
  // Each edge is in two triangles and four directions: listed once, sorted.
  EXPECT_EQ(adjacency.Neighbors, (std::vector<std::int64_t>{ 1, 2, 3, 0, 2, 3, 0, 1, 3, 0, 1, 2 }));
}

TEST(MeshGeometry, AdjacencyOfACapsuleIsSymmetricAndMatchesEuler)
{
  const TestMesh capsule = MakeCapsule(1.0, 2.0, 16, 4, 6);
  const PointAdjacency adjacency = BuildPointAdjacency(capsule.Points.rows(), capsule.Triangles);
  ASSERT_EQ(adjacency.Offsets.size(), static_cast<std::size_t>(capsule.Points.rows()) + 1);
  // A closed triangle mesh has 3F/2 edges, each listed from both ends.
  EXPECT_EQ(adjacency.Neighbors.size(), static_cast<std::size_t>(3 * capsule.Faces()));
  for (std::size_t v = 0; v + 1 < adjacency.Offsets.size(); ++v)
  {
    for (auto e = adjacency.Offsets[v]; e < adjacency.Offsets[v + 1]; ++e)
    {
      const auto w = static_cast<std::size_t>(adjacency.Neighbors[static_cast<std::size_t>(e)]);
      EXPECT_NE(w, v);
      const auto begin = adjacency.Neighbors.begin() + adjacency.Offsets[w];
      const auto end = adjacency.Neighbors.begin() + adjacency.Offsets[w + 1];
      EXPECT_TRUE(std::binary_search(begin, end, static_cast<std::int64_t>(v))) << v << " - " << w;
    }
  }
}

TEST(MeshGeometry, CellMeansAreAreaWeighted)
{
  // Cell 0: a vertex (no triangle); cell 1: one triangle; cell 2: two triangles of areas 1/2
  // and 1; cell 3: two zero-area triangles.
  const TestMesh mesh = Assemble({ { 0, 0, 0 }, { 1, 0, 0 }, { 0, 1, 0 }, { 2, 0, 0 }, { 0, 2, 0 } },
    { { 0, 1, 2 }, { 0, 1, 2 }, { 1, 3, 4 }, { 0, 0, 1 }, { 1, 3, 3 } });
  const std::vector<std::int64_t> cellFirstTriangle{ 0, 0, 1, 3, 5 };
  const std::vector<double> values{ 0.3, 1.0, 4.0, 2.0, 6.0 };
  const std::vector<double> means = AreaWeightedCellMeans(mesh.Points, mesh.Triangles, cellFirstTriangle, values);
  ASSERT_EQ(means.size(), 4u);
  EXPECT_EQ(means[0], 0.0);
  EXPECT_EQ(means[1], 0.3);
  EXPECT_DOUBLE_EQ(means[2], (0.5 * 1.0 + 1.0 * 4.0) / 1.5);
  EXPECT_DOUBLE_EQ(means[3], 4.0);
  EXPECT_EQ(CellSums(cellFirstTriangle, { 3, 1, 2, 0, 7 }), (std::vector<int>{ 0, 3, 3, 7 }));
}

TEST(MeshGeometry, BadInputThrows)
{
  const TestMesh tetrahedron = Tetrahedron();
  EXPECT_THROW(AreaWeightedVertexNormals(tetrahedron.Points.topRows(3), tetrahedron.Triangles), Error);
  EXPECT_THROW(BuildPointAdjacency(3, tetrahedron.Triangles), Error);
  const std::vector<double> values(4, 1.0);
  EXPECT_THROW(AreaWeightedCellMeans(tetrahedron.Points, tetrahedron.Triangles, { 0, 2, 3 }, values), Error);
  EXPECT_THROW(AreaWeightedCellMeans(tetrahedron.Points, tetrahedron.Triangles, { 0, 3, 2, 4 }, values), Error);
  EXPECT_THROW(AreaWeightedCellMeans(tetrahedron.Points, tetrahedron.Triangles, { 0, 4 }, { 1.0 }), Error);
  EXPECT_THROW(CellSums({ 1, 2 }, { 1, 1 }), Error);
  EXPECT_THROW(CellSums({}, {}), Error);
}

} // namespace
