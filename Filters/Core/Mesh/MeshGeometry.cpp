// SPDX-License-Identifier: BSD-3-Clause
#include "Mesh/MeshGeometry.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <string>

namespace shapediameter
{
namespace
{

void CheckTriangleIndices(Eigen::Index pointCount, const TrianglesView& triangles)
{
  for (Eigen::Index t = 0; t < triangles.rows(); ++t)
  {
    for (int corner = 0; corner < 3; ++corner)
    {
      if (triangles(t, corner) < 0 || triangles(t, corner) >= pointCount)
      {
        throw Error("mesh geometry: triangle " + std::to_string(t) + " uses point " +
          std::to_string(triangles(t, corner)) + " of " + std::to_string(pointCount));
      }
    }
  }
}

void CheckCells(const std::vector<std::int64_t>& cellFirstTriangle, Eigen::Index triangleCount,
  std::size_t valueCount)
{
  if (cellFirstTriangle.empty() || cellFirstTriangle.front() != 0 || cellFirstTriangle.back() != triangleCount ||
    !std::is_sorted(cellFirstTriangle.begin(), cellFirstTriangle.end()))
  {
    throw Error("mesh geometry: the cells' first triangles must run from 0 to " +
      std::to_string(triangleCount) + ", non-decreasing");
  }
  if (valueCount != static_cast<std::size_t>(triangleCount))
  {
    throw Error("mesh geometry: " + std::to_string(valueCount) + " values for " +
      std::to_string(triangleCount) + " triangles");
  }
}

/// (p1 - p0) x (p2 - p0) of triangle t: twice its area times its unit normal.
Eigen::RowVector3d AreaVector(const PointsView& points, const TrianglesView& triangles, Eigen::Index t)
{
  const Eigen::RowVector3d a = points.row(triangles(t, 0));
  return (points.row(triangles(t, 1)) - a).cross(points.row(triangles(t, 2)) - a);
}

} // namespace

PointMatrix AreaWeightedVertexNormals(PointsView points, TrianglesView triangles)
{
  CheckTriangleIndices(points.rows(), triangles);
  PointMatrix normals = PointMatrix::Zero(points.rows(), 3);
  for (Eigen::Index t = 0; t < triangles.rows(); ++t)
  {
    const Eigen::RowVector3d areaVector = AreaVector(points, triangles, t);
    for (int corner = 0; corner < 3; ++corner)
    {
      normals.row(triangles(t, corner)) += areaVector;
    }
  }
  return normals;
}

PointAdjacency BuildPointAdjacency(Eigen::Index pointCount, TrianglesView triangles)
{
  CheckTriangleIndices(pointCount, triangles);
  std::vector<std::vector<std::int64_t>> lists(static_cast<std::size_t>(pointCount));
  for (Eigen::Index t = 0; t < triangles.rows(); ++t)
  {
    for (int corner = 0; corner < 3; ++corner)
    {
      const auto a = triangles(t, corner);
      const auto b = triangles(t, (corner + 1) % 3);
      lists[static_cast<std::size_t>(a)].push_back(b);
      lists[static_cast<std::size_t>(b)].push_back(a);
    }
  }
  PointAdjacency adjacency;
  adjacency.Offsets.assign(1, 0);
  for (auto& list : lists)
  {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    adjacency.Neighbors.insert(adjacency.Neighbors.end(), list.begin(), list.end());
    adjacency.Offsets.push_back(static_cast<std::int64_t>(adjacency.Neighbors.size()));
  }
  return adjacency;
}

std::vector<double> AreaWeightedCellMeans(PointsView points, TrianglesView triangles,
  const std::vector<std::int64_t>& cellFirstTriangle, const std::vector<double>& triangleValues)
{
  CheckCells(cellFirstTriangle, triangles.rows(), triangleValues.size());
  CheckTriangleIndices(points.rows(), triangles);
  std::vector<double> means(cellFirstTriangle.size() - 1);
  for (std::size_t cell = 0; cell < means.size(); ++cell)
  {
    const auto begin = cellFirstTriangle[cell];
    const auto end = cellFirstTriangle[cell + 1];
    double weighted = 0.0, area = 0.0, plain = 0.0;
    for (auto t = begin; t < end; ++t)
    {
      // A cell of one triangle (the common case) needs no area.
      const double weight = end - begin > 1 ? 0.5 * AreaVector(points, triangles, t).norm() : 1.0;
      const double value = triangleValues[static_cast<std::size_t>(t)];
      weighted += weight * value;
      area += weight;
      plain += value;
    }
    means[cell] = end == begin ? 0.0 : area > 0.0 ? weighted / area : plain / double(end - begin);
  }
  return means;
}

std::vector<int> CellSums(const std::vector<std::int64_t>& cellFirstTriangle, const std::vector<int>& triangleValues)
{
  CheckCells(cellFirstTriangle, static_cast<Eigen::Index>(triangleValues.size()), triangleValues.size());
  std::vector<int> sums(cellFirstTriangle.size() - 1, 0);
  for (std::size_t cell = 0; cell < sums.size(); ++cell)
  {
    for (auto t = cellFirstTriangle[cell]; t < cellFirstTriangle[cell + 1]; ++t)
    {
      sums[cell] += triangleValues[static_cast<std::size_t>(t)];
    }
  }
  return sums;
}

} // namespace shapediameter
