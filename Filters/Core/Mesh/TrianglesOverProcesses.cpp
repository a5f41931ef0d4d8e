// SPDX-License-Identifier: BSD-3-Clause
#include "Mesh/TrianglesOverProcesses.h"

#include "GatheredOrder.h"
#include "Release.h"

#include <algorithm>
#include <functional>
#include <string>

namespace shapediameter
{

namespace
{

constexpr std::size_t CellWidth = 2;  // global id, triangle count
constexpr std::size_t PointWidth = 4; // global id, x, y, z

/// What a process sends (the header's first paragraph), as doubles.
struct ShareRows
{
  std::vector<double> Cells;
  /// Per triangle: three corner global point ids, then the columns.
  std::vector<double> Triangles;
  std::vector<double> Points;
};

ShareRows RowsOfShare(const TriangleShare& share)
{
  const auto triangles = static_cast<std::size_t>(share.Triangles.rows());
  if (share.TriangleCell.size() != triangles ||
    std::any_of(share.Columns.begin(), share.Columns.end(),
      [&](const std::vector<double>* column) { return column->size() != triangles; }))
  {
    throw Error("triangles over processes: the share's per-triangle arrays do not match its triangles");
  }
  if (share.PointGlobalIds.size() != static_cast<std::size_t>(share.Points.rows()))
  {
    throw Error("triangles over processes: the share's global point ids do not match its points");
  }
  if (!std::all_of(share.CellGlobalIds.begin(), share.CellGlobalIds.end(), IsGatherableId) ||
    !std::all_of(share.PointGlobalIds.begin(), share.PointGlobalIds.end(), IsGatherableId))
  {
    throw Error("triangles over processes: a global id outside [0, 2^53)");
  }
  ShareRows rows;
  std::vector<double> counts(share.CellGlobalIds.size(), 0.0);
  for (std::size_t t = 0; t < triangles; ++t)
  {
    const std::int64_t cell = share.TriangleCell[t];
    if (cell < 0 || static_cast<std::size_t>(cell) >= counts.size() || (t > 0 && cell < share.TriangleCell[t - 1]))
    {
      throw Error("triangles over processes: the share's triangle cells are out of range or out of order");
    }
    counts[static_cast<std::size_t>(cell)] += 1.0;
  }
  rows.Cells.reserve(CellWidth * counts.size());
  for (std::size_t c = 0; c < counts.size(); ++c)
  {
    rows.Cells.push_back(static_cast<double>(share.CellGlobalIds[c]));
    rows.Cells.push_back(counts[c]);
  }
  rows.Triangles.reserve((3 + share.Columns.size()) * triangles);
  for (std::size_t t = 0; t < triangles; ++t)
  {
    for (int corner = 0; corner < 3; ++corner)
    {
      const std::int64_t point = share.Triangles(static_cast<Eigen::Index>(t), corner);
      if (point < 0 || point >= share.Points.rows())
      {
        throw Error("triangles over processes: triangle vertex index out of range");
      }
      rows.Triangles.push_back(static_cast<double>(share.PointGlobalIds[static_cast<std::size_t>(point)]));
    }
    for (const std::vector<double>* column : share.Columns)
    {
      rows.Triangles.push_back((*column)[t]);
    }
  }
  rows.Points.reserve(PointWidth * share.PointGlobalIds.size());
  for (std::size_t p = 0; p < share.PointGlobalIds.size(); ++p)
  {
    rows.Points.push_back(static_cast<double>(share.PointGlobalIds[p]));
    for (int axis = 0; axis < 3; ++axis)
    {
      rows.Points.push_back(share.Points(static_cast<Eigen::Index>(p), axis));
    }
  }
  return rows;
}

/// The whole mesh's points in global-id order; returns the order, of which the triangles read
/// only the id lookup.
GatheredOrder AssemblePoints(const std::vector<std::vector<double>>& points, WholeTriangles& whole)
{
  GatheredOrder pointOrder = OrderGatheredIds(points, PointWidth);
  whole.Points.resize(static_cast<Eigen::Index>(pointOrder.Ids.size()), 3);
  for (std::size_t p = 0; p < points.size(); ++p)
  {
    for (std::size_t r = 0; r < pointOrder.Index[p].size(); ++r)
    {
      if (pointOrder.Used[p][r])
      {
        for (int axis = 0; axis < 3; ++axis)
        {
          whole.Points(pointOrder.Index[p][r], axis) = points[p][PointWidth * r + 1 + static_cast<std::size_t>(axis)];
        }
      }
    }
  }
  Release(pointOrder.Index);
  Release(pointOrder.Used);
  return pointOrder;
}

/// The cells in global-id order and where each one's triangles start in the whole mesh
/// (FirstTriangle: one entry per cell plus one). Throws Error when two processes triangulate
/// a cell differently.
struct CellLayout
{
  GatheredOrder Order;
  std::vector<std::int64_t> FirstTriangle;
};

CellLayout LayOutCells(const std::vector<std::vector<double>>& cells)
{
  CellLayout layout{ OrderGatheredIds(cells, CellWidth), {} };
  Release(layout.Order.IndexOfId);
  const std::size_t cellCount = layout.Order.Ids.size();
  std::vector<std::int64_t>& first = layout.FirstTriangle;
  first.assign(cellCount + 1, 0);
  for (std::size_t p = 0; p < cells.size(); ++p)
  {
    for (std::size_t r = 0; r < layout.Order.Index[p].size(); ++r)
    {
      if (layout.Order.Used[p][r])
      {
        first[static_cast<std::size_t>(layout.Order.Index[p][r]) + 1] = static_cast<std::int64_t>(cells[p][CellWidth * r + 1]);
      }
    }
  }
  for (std::size_t p = 0; p < cells.size(); ++p)
  {
    for (std::size_t r = 0; r < layout.Order.Index[p].size(); ++r)
    {
      const auto cell = static_cast<std::size_t>(layout.Order.Index[p][r]);
      if (static_cast<std::int64_t>(cells[p][CellWidth * r + 1]) != first[cell + 1])
      {
        throw Error("triangles over processes: two processes triangulate cell " + std::to_string(layout.Order.Ids[cell]) +
          " differently");
      }
    }
  }
  for (std::size_t c = 0; c < cellCount; ++c)
  {
    first[c + 1] += first[c];
  }
  return layout;
}

/// The whole mesh's triangle arrays, sized for the cells' triangles.
void SizeTriangles(const CellLayout& cells, std::size_t processes, std::size_t columns, WholeTriangles& whole)
{
  const auto total = static_cast<std::size_t>(cells.FirstTriangle.back());
  whole.Triangles.resize(static_cast<Eigen::Index>(total), 3);
  whole.Columns.assign(columns, std::vector<double>(total, 0.0));
  whole.TriangleCellId.resize(total);
  whole.ProcessTriangles.resize(processes);
}

/// Process p's triangles, their columns and cells, into the whole mesh, cell by cell in the
/// cells' order.
void AssembleTrianglesOf(std::size_t p, const std::vector<double>& triangles, const GatheredOrder& pointOrder,
  const CellLayout& cells, std::size_t columns, WholeTriangles& whole)
{
  const std::size_t triangleWidth = 3 + columns;
  whole.ProcessTriangles[p].reserve(triangles.size() / triangleWidth);
  std::size_t t = 0; // the process's triangle
  for (std::size_t r = 0; r < cells.Order.Index[p].size(); ++r)
  {
    const auto cell = static_cast<std::size_t>(cells.Order.Index[p][r]);
    const auto firstOfCell = static_cast<std::size_t>(cells.FirstTriangle[cell]);
    const auto count = static_cast<std::size_t>(cells.FirstTriangle[cell + 1]) - firstOfCell;
    if (triangleWidth * (t + count) > triangles.size())
    {
      throw Error("triangles over processes: a process's triangles do not match its cells");
    }
    for (std::size_t k = 0; k < count; ++k, ++t)
    {
      const std::size_t w = firstOfCell + k;
      whole.ProcessTriangles[p].push_back(static_cast<std::int64_t>(w));
      if (!cells.Order.Used[p][r])
      {
        continue;
      }
      const double* row = triangles.data() + triangleWidth * t;
      for (int corner = 0; corner < 3; ++corner)
      {
        const std::int64_t index = pointOrder.IndexOf(static_cast<std::int64_t>(row[corner]));
        if (index < 0)
        {
          throw Error("triangles over processes: a triangle's corner is no process's point");
        }
        whole.Triangles(static_cast<Eigen::Index>(w), corner) = index;
      }
      for (std::size_t c = 0; c < columns; ++c)
      {
        whole.Columns[c][w] = row[3 + c];
      }
      whole.TriangleCellId[w] = cells.Order.Ids[cell];
    }
  }
  if (triangleWidth * t != triangles.size())
  {
    throw Error("triangles over processes: a process's triangles do not match its cells");
  }
}

} // namespace

WholeTriangles GatherTrianglesOnFirst(const TriangleShare& share, const ProcessGroup& group)
{
  // Field by field, each gathered field freed once laid out: the first process never holds
  // the three at once (at 832k triangles 27 MB less at its peak). An error found on the way is
  // thrown after the last collective, which every process has to join.
  ShareRows rows = RowsOfShare(share);
  const bool first = group.Rank() == 0;
  WholeTriangles whole;
  GatheredOrder pointOrder;
  CellLayout cells;
  std::string problem;
  const auto laidOut = [&](const std::function<void()>& layOut) {
    if (first && problem.empty())
    {
      try
      {
        layOut();
      }
      catch (const Error& error)
      {
        problem = error.what();
      }
    }
  };
  {
    const std::vector<std::vector<double>> points = group.GatherOnFirst(rows.Points);
    Release(rows.Points);
    laidOut([&] { pointOrder = AssemblePoints(points, whole); });
  }
  {
    const std::vector<std::vector<double>> cellRows = group.GatherOnFirst(rows.Cells);
    Release(rows.Cells);
    laidOut([&] { cells = LayOutCells(cellRows); });
  }
  // The triangles (the largest field) one process at a time, each laid out before the next
  // arrives: the first process holds one process's rows at a time, not every process's.
  const std::size_t processes = group.AllGather({ 0.0 }).size();
  laidOut([&] { SizeTriangles(cells, processes, share.Columns.size(), whole); });
  for (std::size_t p = 0; p < processes; ++p)
  {
    const bool sending = static_cast<std::size_t>(group.Rank()) == p;
    const std::vector<std::vector<double>> triangles = group.GatherOnFirst(sending ? rows.Triangles : std::vector<double>());
    if (sending)
    {
      Release(rows.Triangles);
    }
    laidOut([&] { AssembleTrianglesOf(p, triangles[p], pointOrder, cells, share.Columns.size(), whole); });
  }
  if (!problem.empty())
  {
    throw Error(problem);
  }
  return first ? std::move(whole) : WholeTriangles();
}

std::vector<std::vector<double>> GatherTriangleColumnsOnFirst(const std::vector<const std::vector<double>*>& columns,
  const std::vector<std::vector<std::int64_t>>& processTriangles, std::size_t wholeTriangles,
  const ProcessGroup& group)
{
  const std::size_t own = columns.empty() ? 0 : columns.front()->size();
  if (std::any_of(columns.begin(), columns.end(), [&](const std::vector<double>* column) { return column->size() != own; }))
  {
    throw Error("triangles over processes: the share's columns differ in length");
  }
  const bool first = group.Rank() == 0;
  const std::vector<std::int64_t> none;
  std::vector<std::vector<double>> whole(first ? columns.size() : 0, std::vector<double>(first ? wholeTriangles : 0));
  std::vector<std::uint8_t> written(first ? wholeTriangles : 0, 0);
  std::string problem;
  const auto rowsOfOwnTriangles = [&]() {
    // Triangle by triangle, its columns side by side.
    std::vector<double> rows;
    rows.reserve(own * columns.size());
    for (std::size_t t = 0; t < own; ++t)
    {
      for (const std::vector<double>* column : columns)
      {
        rows.push_back((*column)[t]);
      }
    }
    return rows;
  };
  GatherOnFirstInTurn(rowsOfOwnTriangles, [&](std::size_t p, std::vector<double>&& values) {
    const std::vector<std::int64_t>& triangles = p < processTriangles.size() ? processTriangles[p] : none;
    if (!problem.empty())
    {
      return;
    }
    if (values.size() != triangles.size() * columns.size())
    {
      problem = "triangles over processes: process " + std::to_string(p) + " sent " + std::to_string(values.size()) +
        " column values for " + std::to_string(triangles.size()) + " triangles";
      return;
    }
    for (std::size_t t = 0; t < triangles.size(); ++t)
    {
      const auto w = static_cast<std::size_t>(triangles[t]);
      if (w >= wholeTriangles)
      {
        problem = "triangles over processes: a process's triangle is outside the whole mesh";
        return;
      }
      if (written[w])
      {
        continue; // a lower process's triangle
      }
      written[w] = 1;
      for (std::size_t c = 0; c < columns.size(); ++c)
      {
        whole[c][w] = values[columns.size() * t + c];
      }
    }
  }, group);
  if (!problem.empty())
  {
    throw Error(problem);
  }
  return whole;
}

} // namespace shapediameter
