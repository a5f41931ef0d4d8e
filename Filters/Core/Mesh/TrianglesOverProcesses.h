// SPDX-License-Identifier: BSD-3-Clause
// The whole triangle mesh of a surface split over processes, assembled on the first process
// from every process's own triangles: what the distributed skeleton computes on, without the
// VTK surface.
//
// What it computes
//   Each process sends, per cell of its share, the cell's global id and triangle count, per
//   triangle its corners' global point ids and its payload columns, and per point its global
//   id and coordinates (8 bytes per value: about 40 bytes per triangle plus 8 per column).
//   The receiver orders the cells and the points by global id (GatheredOrder.h: a cell or
//   point several processes hold is taken once, from the lowest) and lays out the triangles
//   cell by cell in that order. The triangles of a cell are what each process made of it, so
//   when they depend on the cell alone (the adapter's Triangulate), the whole mesh is the
//   serial one: the same triangles, corners and order; the points are ordered by global id.
//
// Contract
//   Collective over the group. Bad shares (arrays of the wrong size, ids outside [0, 2^53),
//   triangle cells out of order) throw Error before the first collective; a corner that no
//   process sent, or a cell two processes triangulate differently, throws Error on the first
//   process, after the last collective (the others have returned their empty result).
#pragma once

#include "Mesh/MeshTypes.h"
#include "ProcessGroup.h"

#include <cstdint>
#include <vector>

namespace shapediameter
{

/// One process's own triangles: its share of the whole surface's cells, in global-id order.
struct TriangleShare
{
  PointsView Points;
  /// Triangles (point indices of Points), cell by cell.
  TrianglesView Triangles;
  /// Per triangle: its cell (index into CellGlobalIds), non-decreasing.
  const std::vector<std::int64_t>& TriangleCell;
  /// Per cell: its id in the whole surface, distinct within the share, in [0, 2^53).
  const std::vector<std::int64_t>& CellGlobalIds;
  /// Per point: its id in the whole surface, in [0, 2^53).
  const std::vector<std::int64_t>& PointGlobalIds;
  /// Per-triangle values carried to the whole mesh: each column one value per triangle (the
  /// same number of columns on every process).
  std::vector<const std::vector<double>*> Columns;
};

struct WholeTriangles
{
  PointMatrix Points;
  TriangleMatrix Triangles;
  /// The payload columns in the whole mesh's triangle order.
  std::vector<std::vector<double>> Columns;
  /// Per triangle of the whole mesh: its cell's global id.
  std::vector<std::int64_t> TriangleCellId;
  /// Per process, per triangle of its share: its triangle in the whole mesh.
  std::vector<std::vector<std::int64_t>> ProcessTriangles;
};

/// The whole mesh on the first process (empty elsewhere).
WholeTriangles GatherTrianglesOnFirst(const TriangleShare& share, const ProcessGroup& group);

/// More per-triangle columns after GatherTrianglesOnFirst (the first process can then work on
/// the geometry before the columns take their memory): every process passes its own columns
/// (one value per triangle of its share, the same number of columns everywhere); the first
/// process also passes the gathered mesh's ProcessTriangles and triangle count, and gets the
/// columns in the whole mesh's triangle order, a triangle several processes hold taken from
/// the lowest (as GatherTrianglesOnFirst takes it). One process's values at a time. Empty
/// elsewhere. Collective; a process whose columns do not match its triangles throws Error on
/// the first process, after the last collective.
std::vector<std::vector<double>> GatherTriangleColumnsOnFirst(const std::vector<const std::vector<double>*>& columns,
  const std::vector<std::vector<std::int64_t>>& processTriangles, std::size_t wholeTriangles,
  const ProcessGroup& group);

} // namespace shapediameter
