// SPDX-License-Identifier: BSD-3-Clause
#include "Mesh/Orientation.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>
#include <vector>

using namespace shapediameter;

namespace
{
// A closed, outward-wound octahedron.
void Octahedron(PointMatrix& points, TriangleMatrix& triangles, double shift = 0.0)
{
  points.resize(6, 3);
  points << 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1, 0, 0, 0, 1, 0, 0, -1;
  points.col(0).array() += shift;
  triangles.resize(8, 3);
  triangles << 0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5;
}

double Volume(const PointMatrix& p, const TriangleMatrix& t)
{
  double volume = 0;
  for (Eigen::Index i = 0; i < t.rows(); ++i)
  {
    volume += p.row(t(i, 0)).dot(p.row(t(i, 1)).cross(p.row(t(i, 2)))) / 6.0;
  }
  return volume;
}
} // namespace

TEST(Orientation, OutwardMeshIsUntouched)
{
  PointMatrix points;
  TriangleMatrix triangles;
  Octahedron(points, triangles);
  ASSERT_GT(Volume(points, triangles), 0);
  const OrientationResult result = OrientOutward(points, triangles);
  EXPECT_EQ(result.FlippedTriangles, 0u);
  EXPECT_EQ(result.ComponentCount, 1u);
}

TEST(Orientation, InvertedMeshIsFlippedWhole)
{
  PointMatrix points;
  TriangleMatrix triangles;
  Octahedron(points, triangles);
  triangles.col(1).swap(triangles.col(2));
  OrientationResult result = OrientOutward(points, triangles);
  EXPECT_EQ(result.FlippedTriangles, 8u);
  EXPECT_EQ(result.InwardComponents, 1u);
  EXPECT_EQ(result.InconsistentComponents, 0u);
  ApplyFlips(triangles, result.Flip);
  EXPECT_NEAR(Volume(points, triangles), 4.0 / 3.0, 1e-12);
}

TEST(Orientation, MixedWindingIsRepairedPerComponent)
{
  PointMatrix a, b;
  TriangleMatrix ta, tb;
  Octahedron(a, ta);
  Octahedron(b, tb, 5.0);
  PointMatrix points(12, 3);
  points << a, b;
  TriangleMatrix triangles(16, 3);
  triangles << ta, (tb.array() + 6).matrix();
  // Component 1: two triangles wrong; component 2: all inverted but one.
  for (int t : { 1, 6, 8, 9, 10, 11, 12, 13, 14 })
  {
    std::swap(triangles(t, 1), triangles(t, 2));
  }
  OrientationResult result = OrientOutward(points, triangles);
  EXPECT_EQ(result.ComponentCount, 2u);
  EXPECT_EQ(result.InconsistentComponents, 2u);
  EXPECT_EQ(result.FlippedTriangles, 9u);
  ApplyFlips(triangles, result.Flip);
  TriangleMatrix first = triangles.topRows(8);
  TriangleMatrix second = (triangles.bottomRows(8).array() - 6).matrix();
  EXPECT_NEAR(Volume(a, first), 4.0 / 3.0, 1e-12);
  EXPECT_NEAR(Volume(b, second) , 4.0 / 3.0, 1e-9);
}

TEST(Orientation, EmptyAndOutOfRange)
{
  PointMatrix points(0, 3);
  TriangleMatrix triangles(0, 3);
  EXPECT_EQ(OrientOutward(points, triangles).ComponentCount, 0u);
  points.setZero(3, 3);
  triangles.resize(1, 3);
  triangles << 0, 1, 3;
  EXPECT_THROW(OrientOutward(points, triangles), std::out_of_range);
}

TEST(Orientation, FlatComponentsKeepTheirWinding)
{
  // A triangle soup: every triangle its own component, all wound as given.
  PointMatrix points(6, 3);
  points << 0, 0, 0, 1, 0, 0, 0, 1, 0, 5, 5, 5, 6, 5.1, 5, 5, 6, 5.3;
  TriangleMatrix triangles(2, 3);
  triangles << 0, 1, 2, 3, 5, 4;
  const OrientationResult result = OrientOutward(points, triangles);
  EXPECT_EQ(result.ComponentCount, 2u);
  EXPECT_EQ(result.FlippedTriangles, 0u);
}

TEST(Orientation, TriangleAdjacencyLinksManifoldEdgesInOrder)
{
  PointMatrix points;
  TriangleMatrix triangles;
  Octahedron(points, triangles);
  // Triangle 0 (0 2 4) meets 1 (2 1 4) on 2-4, 3 (3 0 4) on 0-4 and 4 (2 0 5) on 0-2.
  TriangleAdjacency adjacency = BuildTriangleAdjacency(triangles);
  ASSERT_EQ(adjacency.Offsets.size(), 9u);
  for (std::size_t t = 0; t < 8; ++t)
  {
    EXPECT_EQ(adjacency.Offsets[t + 1] - adjacency.Offsets[t], 3) << "triangle " << t;
  }
  EXPECT_EQ(std::vector<std::int64_t>(adjacency.Neighbors.begin(), adjacency.Neighbors.begin() + 3),
    (std::vector<std::int64_t>{ 1, 3, 4 }));
  // Consistent winding: every shared edge is run in opposite directions.
  for (const std::uint8_t same : adjacency.SameDirection)
  {
    EXPECT_EQ(same, 0);
  }

  // Reversing triangle 0: its three links (and their mirrors) run the edge the same way.
  std::swap(triangles(0, 1), triangles(0, 2));
  adjacency = BuildTriangleAdjacency(triangles);
  EXPECT_EQ(std::count(adjacency.SameDirection.begin(), adjacency.SameDirection.end(), 1), 6);

  // A third triangle on edge 0-2 makes it non-manifold: no link across it, the others stay.
  TriangleMatrix fin(9, 3);
  Octahedron(points, triangles);
  fin << triangles, 0, 2, 1;
  adjacency = BuildTriangleAdjacency(fin);
  EXPECT_EQ(std::vector<std::int64_t>(adjacency.Neighbors.begin() + adjacency.Offsets[0],
              adjacency.Neighbors.begin() + adjacency.Offsets[1]),
    (std::vector<std::int64_t>{ 1, 3 }));
  EXPECT_EQ(adjacency.Offsets[9] - adjacency.Offsets[8], 0);

  // A degenerate triangle (4 4 0) runs edge 0-4 twice: four half-edges there, no link across
  // it (two fewer of the 24), none for the degenerate triangle.
  TriangleMatrix withDegenerate(9, 3);
  withDegenerate << triangles, 4, 4, 0;
  adjacency = BuildTriangleAdjacency(withDegenerate);
  EXPECT_EQ(adjacency.Offsets[8], 22);
  EXPECT_EQ(adjacency.Offsets[9], 22);

  TriangleMatrix negative(1, 3);
  negative << 0, -1, 2;
  EXPECT_THROW(BuildTriangleAdjacency(negative), std::out_of_range);
}
