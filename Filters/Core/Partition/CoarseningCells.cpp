// SPDX-License-Identifier: BSD-3-Clause
#include "Partition/CoarseningCells.h"

#include "ExactSum.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace shapediameter
{
namespace
{
constexpr int AxisBits = 21;
constexpr std::uint64_t AxisMask = (std::uint64_t{ 1 } << AxisBits) - 1;
} // namespace

CellGridTerms CollectCellGridTerms(const DualGraphView& graph, const std::uint8_t* own)
{
  CellGridTerms terms;
  const double* centre = graph.FaceCenter;
  terms.Low.fill(std::numeric_limits<double>::infinity());
  terms.High.fill(-std::numeric_limits<double>::infinity());
  for (std::size_t i = 0; i < 3 * graph.FaceCount; ++i)
  {
    terms.Finite = terms.Finite && std::isfinite(centre[i]);
  }
  if (!terms.Finite)
  {
    return terms; // no grid: the sums would not be exact
  }
  for (std::size_t f = 0; f < graph.FaceCount; ++f)
  {
    if (own && !own[f])
    {
      continue;
    }
    for (std::size_t axis = 0; axis < 3; ++axis)
    {
      terms.Low[axis] = std::min(terms.Low[axis], centre[3 * f + axis]);
      terms.High[axis] = std::max(terms.High[axis], centre[3 * f + axis]);
    }
    for (std::int64_t e = graph.Offsets[f]; e < graph.Offsets[f + 1]; ++e)
    {
      const auto g = static_cast<std::size_t>(graph.Neighbors[e]);
      if (g > f)
      {
        terms.Spacing.Add(std::hypot(centre[3 * f] - centre[3 * g], centre[3 * f + 1] - centre[3 * g + 1],
          centre[3 * f + 2] - centre[3 * g + 2]));
        ++terms.Pairs;
      }
    }
  }
  return terms;
}

std::vector<std::uint64_t> CoarseningCells(const DualGraphView& graph, int clusterSize)
{
  const std::size_t n = graph.FaceCount;
  const double* centre = graph.FaceCenter;
  if (!centre || n == 0 || clusterSize < 1)
  {
    return {};
  }
  const CellGridTerms terms = CollectCellGridTerms(graph);
  if (!terms.Finite || terms.Pairs == 0)
  {
    return {};
  }
  const CellGrid grid =
    MakeCellGrid(terms.Low, terms.High, terms.Spacing.Rounded() / static_cast<double>(terms.Pairs), clusterSize);
  if (grid.Side == 0.0)
  {
    return {};
  }
  std::vector<std::uint64_t> cells(n);
  for (std::size_t f = 0; f < n; ++f)
  {
    cells[f] = CellOf(grid, centre + 3 * f);
  }
  return cells;
}

CellGrid MakeCellGrid(const std::array<double, 3>& low, const std::array<double, 3>& high, double meanSpacing,
  int clusterSize)
{
  CellGrid grid;
  double side = std::sqrt(static_cast<double>(clusterSize)) * meanSpacing;
  const double extent = std::max({ high[0] - low[0], high[1] - low[1], high[2] - low[2] });
  side = std::max(side, extent / static_cast<double>(AxisMask));
  if (side > 0.0 && std::isfinite(side) && clusterSize >= 1)
  {
    grid.Origin = low;
    grid.Side = side;
  }
  return grid;
}

std::uint64_t CellOf(const CellGrid& grid, const double* point)
{
  std::uint64_t cell = 0;
  for (std::size_t axis = 0; axis < 3; ++axis)
  {
    const double index = std::floor((point[axis] - grid.Origin[axis]) / grid.Side);
    cell |= std::min(AxisMask, static_cast<std::uint64_t>(std::max(0.0, index))) << (AxisBits * axis);
  }
  return cell;
}

std::uint64_t ParentCell(std::uint64_t cell)
{
  std::uint64_t parent = 0;
  for (int axis = 0; axis < 3; ++axis)
  {
    parent |= (((cell >> (AxisBits * axis)) & AxisMask) >> 1) << (AxisBits * axis);
  }
  return parent;
}

} // namespace shapediameter
