// SPDX-License-Identifier: BSD-3-Clause
// The cells of space by which the multilevel cut (MultilevelCut.h) groups faces: a face's
// cluster decided from where it lies, not from the order of the faces.
//
// Why
//   The multilevel cut used to grow its clusters breadth-first in face order: a face's cluster
//   depended on every face before it. Clusters formed only from a face's position, its label
//   and its neighbours inside one cell are the same sets of faces for any face order and for any
//   split of the surface over processes, given each process the faces of the cells it touches
//   (docs/distributed.md: the cut on every process's faces needs exactly that).
//
// What it computes
//   A grid of cubes over the face centres: origin the per-axis minimum of the centres, side
//   sqrt(clusterSize) times the mean distance between the centres of adjacent faces (a mean over
//   the pairs with an order-independent sum, ExactSum.h), so that a cube holds about clusterSize
//   faces on a surface. Each face gets the packed integer coordinates of its cube, 21 bits per
//   axis (ParentCell: the cube of twice the side that contains it, the next level's). When the
//   surface's extent needs more than 2^21 cubes along an axis the side grows to fit (a few
//   far-away faces then coarsen the rest more).
//
// Degenerate cases: no pairs, a zero or non-finite spacing or a non-finite centre give no cells
//   (empty): the cut then grows its clusters breadth-first, as before.
#pragma once

#include "ExactSum.h"
#include "Partition/PartitionEnergy.h"

#include <array>
#include <cstdint>
#include <vector>

namespace shapediameter
{

/// The grid: origin and side (0 = no grid).
struct CellGrid
{
  std::array<double, 3> Origin{};
  double Side = 0.0;
};

/// What the grid is made of, over the faces of `graph` (FaceCenter set) that `own` marks (null:
/// all): the centres' per-axis extremes, the exact sum of the distances between adjacent
/// centres over the pairs (f, g > f) counted at f, and the pair count; whether every centre of
/// the graph is finite. A process computes these over its own faces (its share's graph), and
/// the whole surface's are their extremes and sums.
struct CellGridTerms
{
  std::array<double, 3> Low{}, High{};
  ExactSum Spacing;
  std::size_t Pairs = 0;
  bool Finite = true;
};
CellGridTerms CollectCellGridTerms(const DualGraphView& graph, const std::uint8_t* own = nullptr);

/// The grid of the header from the centres' per-axis minimum and maximum and the mean distance
/// between adjacent centres (the mean of an exact sum, for processes to agree on it).
CellGrid MakeCellGrid(const std::array<double, 3>& low, const std::array<double, 3>& high, double meanSpacing,
  int clusterSize);

/// The packed cell of a point (x, y, z) in a grid with Side > 0.
std::uint64_t CellOf(const CellGrid& grid, const double* point);

/// Per face of `graph` (FaceCenter must be set), the packed cell of its centre; see the header.
std::vector<std::uint64_t> CoarseningCells(const DualGraphView& graph, int clusterSize);

/// The cell of twice the side that contains `cell` (the grids share their origin).
std::uint64_t ParentCell(std::uint64_t cell);

} // namespace shapediameter
