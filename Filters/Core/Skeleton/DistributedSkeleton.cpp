// SPDX-License-Identifier: BSD-3-Clause
#include "Skeleton/DistributedSkeleton.h"

#include "GatheredOrder.h"
#include "Mesh/Orientation.h"

#include <algorithm>
#include <string>
#include <utility>

namespace shapediameter
{

namespace
{

/// Global ids travel as doubles: exact below 2^53.
constexpr double IdLimit = 9007199254740992.0;

/// What a process sends the first process (step 1 of the header), as doubles.
struct ShareRows
{
  /// Per cell: global id, triangle count.
  std::vector<double> Cells;
  /// Per triangle: three corner global point ids, SDF, part, cloud label.
  std::vector<double> Triangles;
  /// Per point: global id, x, y, z.
  std::vector<double> Points;
};

constexpr std::size_t CellWidth = 2;
constexpr std::size_t TriangleWidth = 6;
constexpr std::size_t PointWidth = 4;

ShareRows RowsOfShare(const SkeletonShareInput& input, const SkeletonShare& share)
{
  const auto triangles = static_cast<std::size_t>(input.Triangles.rows());
  if (input.TriangleCell.size() != triangles || input.TriangleSdf.size() != triangles ||
    (!input.TriangleParts.empty() && input.TriangleParts.size() != triangles) ||
    (!input.TriangleCloudLabels.empty() && input.TriangleCloudLabels.size() != triangles))
  {
    throw Error("skeleton: the share's per-triangle arrays do not match its triangles");
  }
  if (share.PointGlobalIds.size() != static_cast<std::size_t>(input.Points.rows()))
  {
    throw Error("skeleton: the share's global point ids do not match its points");
  }
  const auto validId = [](std::int64_t id) { return id >= 0 && static_cast<double>(id) < IdLimit; };
  if (!std::all_of(share.CellGlobalIds.begin(), share.CellGlobalIds.end(), validId) ||
    !std::all_of(share.PointGlobalIds.begin(), share.PointGlobalIds.end(), validId))
  {
    throw Error("skeleton: a global id outside [0, 2^53)");
  }
  ShareRows rows;
  std::vector<double> counts(share.CellGlobalIds.size(), 0.0);
  for (std::size_t t = 0; t < triangles; ++t)
  {
    const std::int64_t cell = input.TriangleCell[t];
    if (cell < 0 || static_cast<std::size_t>(cell) >= counts.size() || (t > 0 && cell < input.TriangleCell[t - 1]))
    {
      throw Error("skeleton: the share's triangle cells are out of range or out of order");
    }
    counts[static_cast<std::size_t>(cell)] += 1.0;
  }
  rows.Cells.reserve(CellWidth * counts.size());
  for (std::size_t c = 0; c < counts.size(); ++c)
  {
    rows.Cells.push_back(static_cast<double>(share.CellGlobalIds[c]));
    rows.Cells.push_back(counts[c]);
  }
  rows.Triangles.reserve(TriangleWidth * triangles);
  for (std::size_t t = 0; t < triangles; ++t)
  {
    for (int corner = 0; corner < 3; ++corner)
    {
      const std::int64_t point = input.Triangles(static_cast<Eigen::Index>(t), corner);
      if (point < 0 || point >= input.Points.rows())
      {
        throw Error("skeleton: triangle vertex index out of range");
      }
      rows.Triangles.push_back(static_cast<double>(share.PointGlobalIds[static_cast<std::size_t>(point)]));
    }
    rows.Triangles.push_back(input.TriangleSdf[t]);
    rows.Triangles.push_back(input.TriangleParts.empty() ? 0.0 : static_cast<double>(input.TriangleParts[t]));
    rows.Triangles.push_back(input.TriangleCloudLabels.empty() ? 0.0 : input.TriangleCloudLabels[t]);
  }
  rows.Points.reserve(PointWidth * share.PointGlobalIds.size());
  for (std::size_t p = 0; p < share.PointGlobalIds.size(); ++p)
  {
    rows.Points.push_back(static_cast<double>(share.PointGlobalIds[p]));
    for (int axis = 0; axis < 3; ++axis)
    {
      rows.Points.push_back(input.Points(static_cast<Eigen::Index>(p), axis));
    }
  }
  return rows;
}

/// The whole mesh on the first process (step 2 of the header).
struct WholeMesh
{
  PointMatrix Points;
  TriangleMatrix Triangles;
  std::vector<double> Sdf;
  std::vector<std::int64_t> Parts;
  std::vector<double> CloudLabels;
  std::vector<std::int64_t> TriangleCellId;
  /// Per process, per triangle of its share: its triangle in the whole mesh.
  std::vector<std::vector<std::int64_t>> ProcessTriangles;
};

WholeMesh AssembleWholeMesh(const std::vector<std::vector<double>>& cells,
  const std::vector<std::vector<double>>& triangles, const std::vector<std::vector<double>>& points,
  bool withParts, bool withCloudLabels)
{
  WholeMesh whole;
  {
    const GatheredOrder pointOrder = OrderGatheredIds(points, PointWidth);
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
    const GatheredOrder cellOrder = OrderGatheredIds(cells, CellWidth);
    const std::size_t cellCount = cellOrder.Ids.size();
    std::vector<std::int64_t> cellTriangles(cellCount, 0);
    for (std::size_t p = 0; p < cells.size(); ++p)
    {
      for (std::size_t r = 0; r < cellOrder.Index[p].size(); ++r)
      {
        if (cellOrder.Used[p][r])
        {
          cellTriangles[static_cast<std::size_t>(cellOrder.Index[p][r])] =
            static_cast<std::int64_t>(cells[p][CellWidth * r + 1]);
        }
      }
    }
    std::vector<std::int64_t> firstTriangle(cellCount + 1, 0);
    for (std::size_t c = 0; c < cellCount; ++c)
    {
      firstTriangle[c + 1] = firstTriangle[c] + cellTriangles[c];
    }
    const auto total = static_cast<std::size_t>(firstTriangle[cellCount]);
    whole.Triangles.resize(static_cast<Eigen::Index>(total), 3);
    whole.Sdf.resize(total);
    whole.Parts.assign(withParts ? total : 0, 0);
    whole.CloudLabels.assign(withCloudLabels ? total : 0, 0.0);
    whole.TriangleCellId.resize(total);
    whole.ProcessTriangles.resize(cells.size());
    const auto pointIndex = [&](double id) {
      const std::int64_t index = pointOrder.IndexOf(static_cast<std::int64_t>(id));
      if (index < 0)
      {
        throw Error("skeleton: a triangle's corner is no process's point");
      }
      return index;
    };
    for (std::size_t p = 0; p < cells.size(); ++p)
    {
      std::size_t t = 0; // the process's triangle
      for (std::size_t r = 0; r < cellOrder.Index[p].size(); ++r)
      {
        const auto cell = static_cast<std::size_t>(cellOrder.Index[p][r]);
        const auto count = static_cast<std::size_t>(cells[p][CellWidth * r + 1]);
        if (static_cast<std::int64_t>(count) != cellTriangles[cell])
        {
          throw Error("skeleton: two processes triangulate cell " + std::to_string(cellOrder.Ids[cell]) + " differently");
        }
        for (std::size_t k = 0; k < count; ++k, ++t)
        {
          const auto w = static_cast<std::size_t>(firstTriangle[cell]) + k;
          whole.ProcessTriangles[p].push_back(static_cast<std::int64_t>(w));
          if (!cellOrder.Used[p][r])
          {
            continue;
          }
          const double* row = triangles[p].data() + TriangleWidth * t;
          for (int corner = 0; corner < 3; ++corner)
          {
            whole.Triangles(static_cast<Eigen::Index>(w), corner) = pointIndex(row[corner]);
          }
          whole.Sdf[w] = row[3];
          if (withParts)
          {
            whole.Parts[w] = static_cast<std::int64_t>(row[4]);
          }
          if (withCloudLabels)
          {
            whole.CloudLabels[w] = row[5];
          }
          whole.TriangleCellId[w] = cellOrder.Ids[cell];
        }
      }
      if (TriangleWidth * t != triangles[p].size())
      {
        throw Error("skeleton: a process's triangles do not match its cells");
      }
    }
  }
  return whole;
}

enum SkeletonStatus : int
{
  Computed = 0,
  Aborted = 1
};

} // namespace

DistributedSkeletonResult ComputeSkeletonOverProcesses(const SkeletonShareInput& input,
  const SkeletonShare& share, const SkeletonOptions& options, const ParallelFor& parallelFor,
  const ProgressCallback& progress)
{
  ValidateSkeletonOptions(options);
  const ProcessGroup& group = share.Group;
  const bool first = group.Rank() == 0;
  WholeMesh whole;
  {
    ShareRows rows = RowsOfShare(input, share);
    // Parts and cloud labels are used when every process has them: a serial run links by
    // parts only when every face has a usable label.
    std::vector<std::int64_t> having{ input.TriangleParts.empty() ? 0 : 1, input.TriangleCloudLabels.empty() ? 0 : 1 };
    group.SumInPlace(having);
    const std::int64_t processes = static_cast<std::int64_t>(group.AllGather({ 0.0 }).size());
    const bool withParts = having[0] == processes;
    const bool withCloudLabels = having[1] == processes;
    std::vector<std::vector<double>> cells = group.GatherOnFirst(rows.Cells);
    rows.Cells = {};
    std::vector<std::vector<double>> points = group.GatherOnFirst(rows.Points);
    rows.Points = {};
    std::vector<std::vector<double>> triangles = group.GatherOnFirst(rows.Triangles);
    rows.Triangles = {};
    if (first)
    {
      whole = AssembleWholeMesh(cells, triangles, points, withParts, withCloudLabels);
      if (whole.Triangles.rows() == 0)
      {
        throw Error("the input has no polygon with three points"); // the adapter's serial wording
      }
    }
  }

  DistributedSkeletonResult result;
  if (first)
  {
    ApplyFlips(whole.Triangles, OrientOutward(whole.Points, whole.Triangles).Flip);
    SkeletonResult skeleton = ComputeSkeleton(whole.Points, whole.Triangles, whole.Sdf, PointMatrix(0, 3), {}, options,
      parallelFor, progress, whole.Parts);
    whole.Points = PointMatrix();
    whole.Triangles = TriangleMatrix();
    whole.Sdf = {};
    whole.Parts = {};
    result.Aborted = skeleton.Aborted;
    result.Whole = std::move(skeleton);
    if (!whole.CloudLabels.empty())
    {
      for (const std::int64_t source : result.Whole.CloudSourceFace)
      {
        result.CloudLabels.push_back(whole.CloudLabels[static_cast<std::size_t>(source)]);
      }
    }
  }
  // 4. Every process's triangles' links: status, then node and bone per triangle.
  const std::vector<double> part = group.ScatterFromFirst([&](int process) {
    std::vector<double> values{ static_cast<double>(result.Aborted ? Aborted : Computed) };
    if (!result.Aborted)
    {
      for (const std::int64_t w : whole.ProcessTriangles[static_cast<std::size_t>(process)])
      {
        values.push_back(static_cast<double>(result.Whole.FaceNodeId[static_cast<std::size_t>(w)]));
        values.push_back(static_cast<double>(result.Whole.FaceBoneId[static_cast<std::size_t>(w)]));
      }
    }
    return values;
  });
  if (part.empty() || part[0] != Computed)
  {
    result = DistributedSkeletonResult();
    result.Aborted = true;
    return result;
  }
  const auto triangles = static_cast<std::size_t>(input.Triangles.rows());
  if (part.size() != 1 + 2 * triangles)
  {
    throw Error("skeleton: the first process returned " + std::to_string(part.size()) + " values for " +
      std::to_string(triangles) + " triangles");
  }
  result.FaceNodeId.resize(triangles);
  result.FaceBoneId.resize(triangles);
  for (std::size_t t = 0; t < triangles; ++t)
  {
    result.FaceNodeId[t] = static_cast<std::int64_t>(part[1 + 2 * t]);
    result.FaceBoneId[t] = static_cast<std::int64_t>(part[2 + 2 * t]);
  }
  if (first)
  {
    result.Whole.FaceNodeId = {};
    result.Whole.FaceBoneId = {};
    result.WholeTriangleCellId = std::move(whole.TriangleCellId);
  }
  return result;
}

} // namespace shapediameter
