// SPDX-License-Identifier: BSD-3-Clause
// Small per-vertex and per-cell geometry of a triangle mesh that the SDF's per-point mode and
// its cell output need: vertex normals, vertex adjacency, and the reduction of per-triangle
// values to the cells the triangles came from.
//
// What it computes
//   AreaWeightedVertexNormals  the sum of the area vectors (p1 - p0) x (p2 - p0) of the
//                              triangles around each vertex: twice the area-weighted normal,
//                              NOT normalised (MakeVertexOrigins normalises it, and skips a
//                              zero one). On a closed, outward-oriented surface it points out.
//   BuildPointAdjacency        the vertices joined to each vertex by a triangle edge, CSR,
//                              sorted and without duplicates (the graph of the per-point SDF's
//                              neighbour fill and its adaptive interpolation).
//   AreaWeightedCellMeans      one value per cell from one value per triangle, for cells that
//   CellSums                   are runs of consecutive triangles (a polygon split into a fan,
//                              a strip): the area-weighted mean of the cell's triangles (the
//                              SDF of a polygon), the sum (its valid rays).
//
// Input
//   points (n x 3), triangles (m x 3, indices into points; counter-clockwise seen from outside
//   for outward normals). cellFirstTriangle: size cells + 1, starting at 0, non-decreasing,
//   ending at m; the triangles of cell c are [cellFirstTriangle[c], cellFirstTriangle[c + 1]).
//
// Degenerate cases, all defined
//   - A vertex no triangle uses: normal (0, 0, 0), no neighbour.
//   - Degenerate triangles add a zero (or tiny) area vector. A triangle with a repeated corner
//     (a, a, b) makes a its own neighbour (FillFromNeighbors accepts self-loops).
//   - A cell without triangles (a VTK vertex or line): mean 0, sum 0. A cell of one triangle
//     takes its value exactly. A cell of several triangles whose areas sum to 0: the plain
//     mean.
// Bad input (throws Error): a triangle index outside [0, n), a malformed
// cellFirstTriangle, per-triangle values of another size than m.
//
// Cost: O(m) each (the adjacency sorts each vertex's list). Serial: a small fraction of the SDF.
#pragma once

#include "Errors.h"
#include "Mesh/MeshTypes.h"

#include <cstdint>
#include <stdexcept>
#include <vector>

namespace shapediameter
{

/// Sum of the adjacent triangles' area vectors per vertex (n x 3; see the header comment).
PointMatrix AreaWeightedVertexNormals(PointsView points, TrianglesView triangles);

/// Vertices joined by triangle edges, CSR: the neighbours of vertex v are
/// Neighbors[Offsets[v] .. Offsets[v + 1]), sorted, unique.
struct PointAdjacency
{
  std::vector<std::int64_t> Offsets;
  std::vector<std::int64_t> Neighbors;
};

/// The edge adjacency of `pointCount` vertices under `triangles`.
PointAdjacency BuildPointAdjacency(Eigen::Index pointCount, TrianglesView triangles);

/// Area-weighted mean of the per-triangle values over each cell (see the header comment).
std::vector<double> AreaWeightedCellMeans(PointsView points, TrianglesView triangles,
  const std::vector<std::int64_t>& cellFirstTriangle, const std::vector<double>& triangleValues);

/// Sum of the per-triangle values over each cell.
std::vector<int> CellSums(
  const std::vector<std::int64_t>& cellFirstTriangle, const std::vector<int>& triangleValues);

} // namespace shapediameter
