// SPDX-License-Identifier: BSD-3-Clause
// FaceGraph: adjacency, per-face geometry, dihedral angles, geodesic search.
#include "Mesh/FaceGraph.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

namespace
{

using namespace shapediameter;

constexpr double Pi = 3.14159265358979323846;

struct Polygons
{
  PointMatrix Points;
  std::vector<std::int64_t> Offsets;
  std::vector<std::int64_t> Connectivity;

  void Add(std::initializer_list<std::int64_t> face)
  {
    if (Offsets.empty())
    {
      Offsets.push_back(0);
    }
    Connectivity.insert(Connectivity.end(), face.begin(), face.end());
    Offsets.push_back(static_cast<std::int64_t>(Connectivity.size()));
  }
  FaceGraph Build(const ParallelFor& parallelFor = SerialFor) const
  {
    return BuildFaceGraph(Points, Offsets, Connectivity, parallelFor);
  }
};

PointMatrix UnitCubePoints()
{
  PointMatrix points(8, 3);
  for (int i = 0; i < 8; ++i)
  {
    points.row(i) << (i & 1), (i >> 1) & 1, (i >> 2) & 1;
  }
  return points;
}

// Six outward quads of the unit cube (corner i = (i&1, i>>1&1, i>>2&1)).
Polygons UnitCubeQuads()
{
  Polygons cube;
  cube.Points = UnitCubePoints();
  cube.Add({ 0, 2, 3, 1 }); // z = 0
  cube.Add({ 4, 5, 7, 6 }); // z = 1
  cube.Add({ 0, 1, 5, 4 }); // y = 0
  cube.Add({ 2, 6, 7, 3 }); // y = 1
  cube.Add({ 0, 4, 6, 2 }); // x = 0
  cube.Add({ 1, 3, 7, 5 }); // x = 1
  return cube;
}

// The cube with every quad split into two triangles.
Polygons UnitCubeTriangles()
{
  const Polygons quads = UnitCubeQuads();
  Polygons triangles;
  triangles.Points = quads.Points;
  for (std::size_t f = 0; f + 1 < quads.Offsets.size(); ++f)
  {
    const std::int64_t* q = &quads.Connectivity[static_cast<std::size_t>(quads.Offsets[f])];
    triangles.Add({ q[0], q[1], q[2] });
    triangles.Add({ q[0], q[2], q[3] });
  }
  return triangles;
}

Polygons RegularTetrahedron(double shift = 0.0)
{
  Polygons tetra;
  tetra.Points.resize(4, 3);
  tetra.Points << 1, 1, 1, 1, -1, -1, -1, 1, -1, -1, -1, 1;
  tetra.Points.col(0).array() += shift;
  tetra.Add({ 0, 1, 2 });
  tetra.Add({ 0, 3, 1 });
  tetra.Add({ 0, 2, 3 });
  tetra.Add({ 1, 3, 2 });
  return tetra;
}

// A flat n x n grid of unit squares in z = 0, two triangles each, normals +z.
Polygons FlatGrid(int n)
{
  Polygons grid;
  grid.Points.resize((n + 1) * (n + 1), 3);
  for (int j = 0; j <= n; ++j)
  {
    for (int i = 0; i <= n; ++i)
    {
      grid.Points.row(j * (n + 1) + i) << i, j, 0.0;
    }
  }
  for (int j = 0; j < n; ++j)
  {
    for (int i = 0; i < n; ++i)
    {
      const std::int64_t a = j * (n + 1) + i;
      grid.Add({ a, a + 1, a + n + 2 });
      grid.Add({ a, a + n + 2, a + n + 1 });
    }
  }
  return grid;
}

std::vector<std::int64_t> NeighborsOf(const FaceGraph& graph, std::int64_t face)
{
  return std::vector<std::int64_t>(graph.Neighbors.begin() + graph.NeighborBegin(face),
    graph.Neighbors.begin() + graph.NeighborEnd(face));
}

void ExpectAllFinite(const FaceGraph& graph)
{
  EXPECT_TRUE(graph.Centers.allFinite());
  EXPECT_TRUE(graph.Normals.allFinite());
  for (double value : graph.Areas)
  {
    EXPECT_TRUE(std::isfinite(value));
  }
  for (std::size_t e = 0; e < graph.Neighbors.size(); ++e)
  {
    EXPECT_TRUE(std::isfinite(graph.SharedEdgeLengths[e]));
    EXPECT_TRUE(std::isfinite(graph.CenterDistances[e]));
    EXPECT_TRUE(std::isfinite(graph.NormalAngles[e]));
  }
  EXPECT_TRUE(std::isfinite(graph.MeanEdgeLength));
  EXPECT_TRUE(std::isfinite(graph.BoundingBoxDiagonal));
}

} // namespace

TEST(FaceGraph, CubeQuadsHaveFourNeighborsAtRightAnglesAllConvex)
{
  const FaceGraph graph = UnitCubeQuads().Build();
  ASSERT_EQ(graph.FaceCount(), 6u);
  EXPECT_EQ(graph.EdgeCount, 12u);
  EXPECT_EQ(graph.BoundaryEdgeCount, 0u);
  EXPECT_EQ(graph.NonManifoldEdgeCount, 0u);
  EXPECT_EQ(graph.DegenerateFaceCount, 0u);
  EXPECT_DOUBLE_EQ(graph.MeanEdgeLength, 1.0);
  EXPECT_DOUBLE_EQ(graph.BoundingBoxDiagonal, std::sqrt(3.0));
  for (std::int64_t f = 0; f < 6; ++f)
  {
    EXPECT_EQ(graph.NeighborEnd(f) - graph.NeighborBegin(f), 4);
    EXPECT_NEAR(graph.Areas[static_cast<std::size_t>(f)], 1.0, 1e-14);
    // Outward: the normal points from the cube centre to the face centre.
    const Eigen::Vector3d outward = graph.Centers.row(f).transpose() - Eigen::Vector3d::Constant(0.5);
    EXPECT_NEAR(graph.Normals.row(f).dot(outward.normalized()), 1.0, 1e-14);
  }
  // z = 0 face: neighbours are the four side faces, sorted.
  EXPECT_EQ(NeighborsOf(graph, 0), (std::vector<std::int64_t>{ 2, 3, 4, 5 }));
  for (std::size_t e = 0; e < graph.Neighbors.size(); ++e)
  {
    EXPECT_NEAR(graph.NormalAngles[e], Pi / 2, 1e-14);
    EXPECT_EQ(graph.Concave[e], 0);
    EXPECT_NEAR(graph.DihedralAngle(static_cast<std::int64_t>(e)), Pi / 2, 1e-14);
    EXPECT_DOUBLE_EQ(graph.SharedEdgeLengths[e], 1.0);
    EXPECT_NEAR(graph.CenterDistances[e], std::sqrt(0.5), 1e-14);
  }
}

TEST(FaceGraph, TriangulatedCubeHasFlatDiagonalsAndConvexEdges)
{
  const FaceGraph graph = UnitCubeTriangles().Build();
  ASSERT_EQ(graph.FaceCount(), 12u);
  EXPECT_EQ(graph.EdgeCount, 18u);
  int flat = 0;
  int rightAngle = 0;
  for (std::int64_t f = 0; f < 12; ++f)
  {
    EXPECT_EQ(graph.NeighborEnd(f) - graph.NeighborBegin(f), 3);
    EXPECT_NEAR(graph.Areas[static_cast<std::size_t>(f)], 0.5, 1e-14);
  }
  for (std::size_t e = 0; e < graph.Neighbors.size(); ++e)
  {
    EXPECT_EQ(graph.Concave[e], 0);
    if (std::abs(graph.NormalAngles[e]) < 1e-14)
    {
      ++flat;
      EXPECT_NEAR(graph.SharedEdgeLengths[e], std::sqrt(2.0), 1e-14);
    }
    else if (std::abs(graph.NormalAngles[e] - Pi / 2) < 1e-14)
    {
      ++rightAngle;
    }
  }
  EXPECT_EQ(flat, 12);       // 6 diagonals, both directions
  EXPECT_EQ(rightAngle, 24); // 12 cube edges, both directions
}

TEST(FaceGraph, RegularTetrahedronAngles)
{
  const FaceGraph graph = RegularTetrahedron().Build();
  ASSERT_EQ(graph.FaceCount(), 4u);
  const double dihedral = std::acos(1.0 / 3.0);
  for (std::int64_t f = 0; f < 4; ++f)
  {
    EXPECT_EQ(NeighborsOf(graph, f).size(), 3u);
    EXPECT_NEAR(graph.Areas[static_cast<std::size_t>(f)], std::sqrt(3.0) / 4.0 * 8.0, 1e-13);
    EXPECT_GT(graph.Normals.row(f).dot(graph.Centers.row(f)), 0.0);
  }
  for (std::size_t e = 0; e < graph.Neighbors.size(); ++e)
  {
    EXPECT_NEAR(graph.NormalAngles[e], Pi - dihedral, 1e-13);
    EXPECT_NEAR(graph.DihedralAngle(static_cast<std::int64_t>(e)), dihedral, 1e-13);
    EXPECT_EQ(graph.Concave[e], 0);
    EXPECT_NEAR(graph.SharedEdgeLengths[e], std::sqrt(8.0), 1e-13);
  }
}

TEST(FaceGraph, ValleyIsConcaveRidgeIsConvex)
{
  // z = |x| (valley, normals up) and z = -|x| (ridge, normals up): two triangles each.
  for (double sign : { 1.0, -1.0 })
  {
    Polygons fold;
    fold.Points.resize(6, 3);
    fold.Points << -1, 0, sign, 0, 0, 0, 1, 0, sign, -1, 1, sign, 0, 1, 0, 1, 1, sign;
    fold.Add({ 0, 1, 4, 3 });
    fold.Add({ 1, 2, 5, 4 });
    const FaceGraph graph = fold.Build();
    ASSERT_EQ(graph.Neighbors.size(), 2u);
    EXPECT_GT(graph.Normals(0, 2), 0.0);
    EXPECT_GT(graph.Normals(1, 2), 0.0);
    EXPECT_NEAR(graph.NormalAngles[0], Pi / 2, 1e-14);
    EXPECT_EQ(graph.Concave[0], sign > 0 ? 1 : 0);
    EXPECT_EQ(graph.Concave[1], graph.Concave[0]); // both directions agree
    EXPECT_NEAR(graph.DihedralAngle(0), sign > 0 ? 1.5 * Pi : 0.5 * Pi, 1e-14);
    EXPECT_EQ(graph.BoundaryEdgeCount, 6u);
  }
}

TEST(FaceGraph, NewellNormalAndAreaOfPolygons)
{
  Polygons polygons;
  const int sides = 7;
  polygons.Points.resize(sides + 4, 3);
  for (int i = 0; i < sides; ++i)
  {
    const double angle = 2 * Pi * i / sides;
    // Regular heptagon of circumradius 2 in the plane x = 3, counter-clockwise about +x.
    polygons.Points.row(i) << 3.0, 2 * std::cos(angle), 2 * std::sin(angle);
  }
  // A warped quad: least-squares normal is +z by symmetry.
  polygons.Points.row(sides + 0) << 0, 0, 0.1;
  polygons.Points.row(sides + 1) << 1, 0, -0.1;
  polygons.Points.row(sides + 2) << 1, 1, 0.1;
  polygons.Points.row(sides + 3) << 0, 1, -0.1;
  polygons.Add({ 0, 1, 2, 3, 4, 5, 6 });
  polygons.Add({ sides, sides + 1, sides + 2, sides + 3 });
  const FaceGraph graph = polygons.Build();
  EXPECT_NEAR(graph.Areas[0], 0.5 * sides * 4 * std::sin(2 * Pi / sides), 1e-13);
  EXPECT_NEAR(graph.Normals(0, 0), 1.0, 1e-14);
  EXPECT_NEAR(graph.Centers(0, 0), 3.0, 1e-14);
  EXPECT_NEAR(graph.Normals(1, 2), 1.0, 1e-14);
  EXPECT_NEAR(graph.Centers(1, 2), 0.0, 1e-14);
  EXPECT_EQ(graph.DegenerateFaceCount, 0u);
}

TEST(FaceGraph, NonManifoldEdgeConnectsAllPairs)
{
  // Three triangles around the edge (0, 1), a fin.
  Polygons fin;
  fin.Points.resize(5, 3);
  fin.Points << 0, 0, 0, 0, 0, 1, 1, 0, 0, -1, 1, 0, -1, -1, 0;
  fin.Add({ 0, 1, 2 });
  fin.Add({ 1, 0, 3 });
  fin.Add({ 0, 1, 4 });
  const FaceGraph graph = fin.Build();
  EXPECT_EQ(graph.NonManifoldEdgeCount, 1u);
  EXPECT_EQ(graph.BoundaryEdgeCount, 6u);
  EXPECT_EQ(graph.EdgeCount, 7u);
  EXPECT_EQ(NeighborsOf(graph, 0), (std::vector<std::int64_t>{ 1, 2 }));
  EXPECT_EQ(NeighborsOf(graph, 1), (std::vector<std::int64_t>{ 0, 2 }));
  EXPECT_EQ(NeighborsOf(graph, 2), (std::vector<std::int64_t>{ 0, 1 }));
  ExpectAllFinite(graph);
  EXPECT_EQ(ComputeFaceComponents(graph).Count, 1u);
}

TEST(FaceGraph, FacesSharingSeveralEdgesAreOneAdjacency)
{
  // A double-sided triangle: the same three points in both orientations.
  Polygons sheet;
  sheet.Points.resize(3, 3);
  sheet.Points << 0, 0, 0, 3, 0, 0, 0, 4, 0;
  sheet.Add({ 0, 1, 2 });
  sheet.Add({ 0, 2, 1 });
  const FaceGraph graph = sheet.Build();
  EXPECT_EQ(NeighborsOf(graph, 0), (std::vector<std::int64_t>{ 1 }));
  EXPECT_EQ(NeighborsOf(graph, 1), (std::vector<std::int64_t>{ 0 }));
  EXPECT_DOUBLE_EQ(graph.SharedEdgeLengths[0], 12.0);
  EXPECT_NEAR(graph.NormalAngles[0], Pi, 1e-14);
  EXPECT_EQ(graph.Concave[0], graph.Concave[1]);
}

TEST(FaceGraph, OpenBoundaryIsolatedAndDegenerateFacesAreDefined)
{
  Polygons mixed;
  mixed.Points.resize(9, 3);
  mixed.Points << 0, 0, 0, 1, 0, 0, 0, 1, 0, // lone triangle
    5, 5, 5, 6, 6, 6, 7, 7, 7,              // collinear (zero area) triangle
    9, 9, 9, 10, 9, 9, 0.5, 0.5, 0;         // a segment, and the tip of a sliver
  mixed.Add({ 0, 1, 2 });
  mixed.Add({ 3, 4, 5 });
  mixed.Add({ 6, 7 });
  mixed.Add({ 1, 2, 8 }); // degenerate: point 8 lies on the edge (1, 2)
  mixed.Add({ 3, 3, 4 }); // repeated vertex
  const FaceGraph graph = mixed.Build();
  ASSERT_EQ(graph.FaceCount(), 5u);
  EXPECT_EQ(graph.Degenerate, (std::vector<std::uint8_t>{ 0, 1, 1, 1, 1 }));
  EXPECT_EQ(graph.DegenerateFaceCount, 4u);
  EXPECT_EQ(graph.Normals.row(1).norm(), 0.0);
  EXPECT_EQ(graph.Areas[1], 0.0);
  EXPECT_EQ(NeighborsOf(graph, 0), (std::vector<std::int64_t>{ 3 }));
  EXPECT_EQ(NeighborsOf(graph, 2), (std::vector<std::int64_t>{}));
  // The degenerate face 1 and face 4 (repeated vertex) share the edge (3, 4).
  EXPECT_EQ(NeighborsOf(graph, 1), (std::vector<std::int64_t>{ 4 }));
  // Angles involving a degenerate face are 0, never concave.
  for (std::size_t e = 0; e < graph.Neighbors.size(); ++e)
  {
    EXPECT_EQ(graph.NormalAngles[e], 0.0);
    EXPECT_EQ(graph.Concave[e], 0);
  }
  EXPECT_NEAR(graph.Centers(2, 0), 9.5, 1e-15);
  ExpectAllFinite(graph);
  const FaceComponents components = ComputeFaceComponents(graph);
  EXPECT_EQ(components.Count, 3u);
  EXPECT_EQ(components.Labels, (std::vector<std::int64_t>{ 0, 1, 2, 0, 1 }));
}

TEST(FaceGraph, EmptyAndSingleFace)
{
  const PointMatrix noPoints(0, 3);
  const FaceGraph empty = BuildFaceGraph(noPoints, std::vector<std::int64_t>{}, std::vector<std::int64_t>{});
  EXPECT_EQ(empty.FaceCount(), 0u);
  EXPECT_EQ(empty.MeanEdgeLength, 0.0);
  EXPECT_EQ(ComputeFaceComponents(empty).Count, 0u);
  const TriangleMatrix noTriangles(0, 3);
  EXPECT_EQ(BuildFaceGraph(noPoints, noTriangles).FaceCount(), 0u);

  PointMatrix points(3, 3);
  points << 0, 0, 0, 2, 0, 0, 0, 2, 0;
  TriangleMatrix one(1, 3);
  one << 0, 1, 2;
  const FaceGraph single = BuildFaceGraph(points, one);
  ASSERT_EQ(single.FaceCount(), 1u);
  EXPECT_EQ(single.Neighbors.size(), 0u);
  EXPECT_EQ(single.BoundaryEdgeCount, 3u);
  EXPECT_DOUBLE_EQ(single.Areas[0], 2.0);
  EXPECT_NEAR(single.MeanEdgeLength, (4.0 + std::sqrt(8.0)) / 3.0, 1e-15);
}

TEST(FaceGraph, BadInputThrows)
{
  const PointMatrix points = UnitCubePoints();
  EXPECT_THROW(BuildFaceGraph(points, std::vector<std::int64_t>{ 0, 3 }, std::vector<std::int64_t>{ 0, 1, 8 }),
    Error);
  EXPECT_THROW(BuildFaceGraph(points, std::vector<std::int64_t>{ 0, 3 }, std::vector<std::int64_t>{ 0, -1, 2 }),
    Error);
  EXPECT_THROW(BuildFaceGraph(points, std::vector<std::int64_t>{ 1, 3 }, std::vector<std::int64_t>{ 0, 1, 2 }),
    Error);
  EXPECT_THROW(BuildFaceGraph(points, std::vector<std::int64_t>{ 0, 2, 1 }, std::vector<std::int64_t>{ 0, 1 }),
    Error);
  EXPECT_THROW(BuildFaceGraph(points, std::vector<std::int64_t>{ 0, 2 }, std::vector<std::int64_t>{ 0, 1, 2 }),
    Error);
  EXPECT_THROW(BuildFaceGraph(points, std::vector<std::int64_t>{}, std::vector<std::int64_t>{ 0 }), Error);
  PointMatrix withNaN = points;
  withNaN(2, 1) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(BuildFaceGraph(withNaN, std::vector<std::int64_t>{ 0, 3 }, std::vector<std::int64_t>{ 0, 1, 2 }),
    Error);
  // A NaN point no face uses is harmless.
  EXPECT_NO_THROW(BuildFaceGraph(withNaN, std::vector<std::int64_t>{ 0, 3 }, std::vector<std::int64_t>{ 0, 1, 3 }));
}

TEST(FaceGraph, FlatGridInteriorFacesHaveThreeNeighborsAndComponentsSeparate)
{
  Polygons grid = FlatGrid(10);
  // A second, disjoint copy of the tetrahedron appended as another component.
  const Polygons tetra = RegularTetrahedron(100.0);
  const auto base = grid.Points.rows();
  grid.Points.conservativeResize(base + 4, 3);
  grid.Points.bottomRows(4) = tetra.Points;
  for (std::size_t f = 0; f + 1 < tetra.Offsets.size(); ++f)
  {
    const std::int64_t* t = &tetra.Connectivity[static_cast<std::size_t>(tetra.Offsets[f])];
    grid.Add({ base + t[0], base + t[1], base + t[2] });
  }
  const FaceGraph graph = grid.Build();
  ASSERT_EQ(graph.FaceCount(), 204u);
  EXPECT_EQ(graph.BoundaryEdgeCount, 40u);
  std::size_t three = 0;
  for (std::int64_t f = 0; f < 200; ++f)
  {
    const auto count = graph.NeighborEnd(f) - graph.NeighborBegin(f);
    EXPECT_GE(count, 1);
    EXPECT_LE(count, 3);
    three += count == 3;
  }
  EXPECT_EQ(three, 200u - 38u); // 40 boundary edges over 38 faces: two corner faces hold two each
  const FaceComponents components = ComputeFaceComponents(graph);
  EXPECT_EQ(components.Count, 2u);
  EXPECT_EQ(components.Labels[0], 0);
  EXPECT_EQ(components.Labels[203], 1);
}

TEST(FaceGraph, BitIdenticalForAnyThreadSplit)
{
  const Polygons grid = FlatGrid(40);
  PointMatrix bumpy = grid.Points;
  for (Eigen::Index v = 0; v < bumpy.rows(); ++v)
  {
    bumpy(v, 2) = 0.3 * std::sin(0.7 * bumpy(v, 0)) * std::cos(0.45 * bumpy(v, 1));
  }
  const FaceGraph serial = BuildFaceGraph(bumpy, grid.Offsets, grid.Connectivity, SerialFor);
  for (unsigned threads : { 2u, 3u })
  {
    const FaceGraph threaded = BuildFaceGraph(bumpy, grid.Offsets, grid.Connectivity, ThreadedFor(threads));
    EXPECT_EQ(serial.Offsets, threaded.Offsets);
    EXPECT_EQ(serial.Neighbors, threaded.Neighbors);
    EXPECT_EQ(serial.SharedEdgeLengths, threaded.SharedEdgeLengths);
    EXPECT_EQ(serial.CenterDistances, threaded.CenterDistances);
    EXPECT_EQ(serial.NormalAngles, threaded.NormalAngles);
    EXPECT_EQ(serial.Concave, threaded.Concave);
    EXPECT_EQ(serial.Areas, threaded.Areas);
    EXPECT_TRUE(serial.Normals == threaded.Normals);
    EXPECT_TRUE(serial.Centers == threaded.Centers);
    EXPECT_EQ(serial.MeanEdgeLength, threaded.MeanEdgeLength);
  }
  // The adjacency is symmetric with symmetric attributes.
  for (std::int64_t f = 0; f < static_cast<std::int64_t>(serial.FaceCount()); ++f)
  {
    for (std::int64_t e = serial.NeighborBegin(f); e < serial.NeighborEnd(f); ++e)
    {
      const std::int64_t g = serial.Neighbors[static_cast<std::size_t>(e)];
      bool found = false;
      for (std::int64_t r = serial.NeighborBegin(g); r < serial.NeighborEnd(g); ++r)
      {
        if (serial.Neighbors[static_cast<std::size_t>(r)] == f)
        {
          found = true;
          EXPECT_EQ(serial.Concave[static_cast<std::size_t>(r)], serial.Concave[static_cast<std::size_t>(e)]);
          EXPECT_NEAR(serial.NormalAngles[static_cast<std::size_t>(r)], serial.NormalAngles[static_cast<std::size_t>(e)], 1e-15);
        }
      }
      EXPECT_TRUE(found);
    }
  }
}

TEST(DualGeodesicSearch, DistancesOrderRadiusAndCap)
{
  const Polygons grid = FlatGrid(20);
  const FaceGraph graph = grid.Build();
  DualGeodesicSearch search(graph);
  std::vector<GeodesicNeighbor> neighbors;
  // A face in the middle; its three neighbours are at the dual distance of adjacent centres.
  const std::int64_t source = 2 * (10 * 20 + 10);
  search.Run(source, 100.0, 3, neighbors);
  ASSERT_EQ(neighbors.size(), 3u);
  const auto direct = NeighborsOf(graph, source);
  for (const GeodesicNeighbor& neighbor : neighbors)
  {
    EXPECT_NE(neighbor.Face, source);
    EXPECT_NE(std::find(direct.begin(), direct.end(), neighbor.Face), direct.end());
    const double euclidean = (graph.Centers.row(neighbor.Face) - graph.Centers.row(source)).norm();
    EXPECT_DOUBLE_EQ(neighbor.Distance, euclidean);
  }
  // Radius bound, sorted order, and the dual path never shorter than the straight line.
  search.Run(source, 3.0, 1000, neighbors);
  EXPECT_GT(neighbors.size(), 20u);
  EXPECT_LT(neighbors.size(), 120u);
  for (std::size_t k = 0; k < neighbors.size(); ++k)
  {
    EXPECT_LE(neighbors[k].Distance, 3.0);
    if (k > 0)
    {
      EXPECT_LE(neighbors[k - 1].Distance, neighbors[k].Distance);
    }
    const double euclidean = (graph.Centers.row(neighbors[k].Face) - graph.Centers.row(source)).norm();
    EXPECT_GE(neighbors[k].Distance, euclidean - 1e-12);
    EXPECT_LE(neighbors[k].Distance, 2.1 * euclidean); // zig-zag across the grid diagonals
  }
  // Zero radius / zero cap: nothing.
  search.Run(source, 0.0, 10, neighbors);
  EXPECT_TRUE(neighbors.empty());
  search.Run(source, 10.0, 0, neighbors);
  EXPECT_TRUE(neighbors.empty());
  search.Run(-1, 10.0, 10, neighbors);
  EXPECT_TRUE(neighbors.empty());
  search.Run(static_cast<std::int64_t>(graph.FaceCount()), 10.0, 10, neighbors);
  EXPECT_TRUE(neighbors.empty());
  // A large search (table growth) reaches the whole grid.
  search.Run(0, 1e9, 100000, neighbors);
  EXPECT_EQ(neighbors.size(), graph.FaceCount() - 1);
}

TEST(FaceGraph, SharedGraphIsReusedForIdenticalInputWhileItIsHeld)
{
  const Polygons grid = FlatGrid(6);
  std::shared_ptr<const FaceGraph> first = SharedFaceGraph(grid.Points, grid.Offsets, grid.Connectivity);
  ASSERT_TRUE(first);
  // Equal to a plain build, and the same object for a copy of the input.
  const FaceGraph built = grid.Build();
  EXPECT_EQ(first->Neighbors, built.Neighbors);
  EXPECT_EQ(first->NormalAngles, built.NormalAngles);
  const Polygons copy = grid;
  EXPECT_EQ(SharedFaceGraph(copy.Points, copy.Offsets, copy.Connectivity).get(), first.get());

  // Any change of a coordinate, an index or the faces gives another graph.
  Polygons moved = grid;
  moved.Points(8, 2) = 0.25; // a vertex inside the grid lifted: the normals change
  const auto movedGraph = SharedFaceGraph(moved.Points, moved.Offsets, moved.Connectivity);
  EXPECT_NE(movedGraph.get(), first.get());
  EXPECT_GT(*std::max_element(movedGraph->NormalAngles.begin(), movedGraph->NormalAngles.end()), 0.1);
  Polygons flipped = grid;
  std::swap(flipped.Connectivity[1], flipped.Connectivity[2]); // face 0 turned over
  const auto flippedGraph = SharedFaceGraph(flipped.Points, flipped.Offsets, flipped.Connectivity);
  EXPECT_NE(flippedGraph.get(), first.get());
  EXPECT_NEAR(flippedGraph->NormalAngles[0], Pi, 1e-12);
  Polygons fewer = grid;
  fewer.Offsets.pop_back();
  fewer.Connectivity.resize(fewer.Connectivity.size() - 3);
  const auto fewerGraph = SharedFaceGraph(fewer.Points, fewer.Offsets, fewer.Connectivity);
  EXPECT_EQ(fewerGraph->FaceCount(), grid.Offsets.size() - 2);

  // The registry never keeps a graph alive: once released, identical input builds anew.
  const std::weak_ptr<const FaceGraph> released = first;
  first.reset();
  EXPECT_TRUE(released.expired());
  const auto rebuilt = SharedFaceGraph(grid.Points, grid.Offsets, grid.Connectivity);
  EXPECT_EQ(rebuilt->Neighbors, built.Neighbors);

  // Bad input throws what BuildFaceGraph throws and registers nothing.
  Polygons broken = grid;
  broken.Points(0, 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(SharedFaceGraph(broken.Points, broken.Offsets, broken.Connectivity), Error);
}
