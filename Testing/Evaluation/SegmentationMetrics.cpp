// SPDX-License-Identifier: BSD-3-Clause
#include "SegmentationMetrics.h"
#include "IO/TextFiles.h"

#include <Eigen/Geometry>
#include <nanoflann.hpp>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <queue>
#include <unordered_map>
#include <utility>

namespace shapediameter
{

namespace
{

// ---------------------------------------------------------------------------------------------
// Surface: triangles (fan-triangulated polygons) with the polygon each comes from.

struct Surface
{
  std::vector<std::array<std::int64_t, 3>> triangles;
  std::vector<std::size_t> triangleFace;
  std::vector<double> faceAreas;
  std::vector<double> triangleAreas;
};

double TriangleArea(const PointsView& points, std::int64_t i, std::int64_t j, std::int64_t k)
{
  const Eigen::Vector3d a = points.row(i).transpose();
  const Eigen::Vector3d b = points.row(j).transpose();
  const Eigen::Vector3d c = points.row(k).transpose();
  return 0.5 * (b - a).cross(c - a).norm();
}

void CheckVertex(const PointsView& points, std::int64_t index, std::size_t face, std::vector<char>& checked)
{
  if (index < 0 || index >= points.rows())
  {
    throw SegmentationMetricsError("face " + std::to_string(face) + ": point index " +
      std::to_string(index) + " out of range [0, " + std::to_string(points.rows()) + ")");
  }
  char& seen = checked[static_cast<std::size_t>(index)];
  if (!seen)
  {
    if (!points.row(index).allFinite())
    {
      throw SegmentationMetricsError("point " + std::to_string(index) + " has a NaN or infinite coordinate");
    }
    seen = 1;
  }
}

Surface SurfaceFromTriangles(const PointsView& points, const TrianglesView& triangles)
{
  Surface surface;
  const auto count = static_cast<std::size_t>(triangles.rows());
  std::vector<char> checked(static_cast<std::size_t>(points.rows()), 0);
  surface.triangles.resize(count);
  surface.triangleFace.resize(count);
  surface.faceAreas.resize(count);
  for (std::size_t t = 0; t < count; ++t)
  {
    for (int k = 0; k < 3; ++k)
    {
      const std::int64_t v = triangles(static_cast<Eigen::Index>(t), k);
      CheckVertex(points, v, t, checked);
      surface.triangles[t][static_cast<std::size_t>(k)] = v;
    }
    surface.triangleFace[t] = t;
    const auto& triangle = surface.triangles[t];
    surface.faceAreas[t] = TriangleArea(points, triangle[0], triangle[1], triangle[2]);
  }
  surface.triangleAreas = surface.faceAreas;
  return surface;
}

Surface SurfaceFromPolygons(const PointsView& points, const std::vector<std::int64_t>& faceOffsets,
  const std::vector<std::int64_t>& faceConnectivity)
{
  Surface surface;
  if (faceOffsets.empty())
  {
    if (!faceConnectivity.empty())
    {
      throw SegmentationMetricsError("face offsets are empty but the connectivity is not");
    }
    return surface;
  }
  if (faceOffsets.front() != 0 ||
    faceOffsets.back() != static_cast<std::int64_t>(faceConnectivity.size()))
  {
    throw SegmentationMetricsError("face offsets must start at 0 and end at the connectivity size");
  }
  const std::size_t faceCount = faceOffsets.size() - 1;
  std::vector<char> checked(static_cast<std::size_t>(points.rows()), 0);
  surface.faceAreas.assign(faceCount, 0.0);
  for (std::size_t f = 0; f < faceCount; ++f)
  {
    const std::int64_t begin = faceOffsets[f];
    const std::int64_t end = faceOffsets[f + 1];
    if (end < begin)
    {
      throw SegmentationMetricsError("face offsets decrease at face " + std::to_string(f));
    }
    for (std::int64_t i = begin; i < end; ++i)
    {
      CheckVertex(points, faceConnectivity[static_cast<std::size_t>(i)], f, checked);
    }
    for (std::int64_t i = begin + 1; i + 1 < end; ++i)
    {
      const std::int64_t first = faceConnectivity[static_cast<std::size_t>(begin)];
      const std::array<std::int64_t, 3> triangle = { first, faceConnectivity[static_cast<std::size_t>(i)],
        faceConnectivity[static_cast<std::size_t>(i + 1)] };
      const double area = TriangleArea(points, triangle[0], triangle[1], triangle[2]);
      surface.triangles.push_back(triangle);
      surface.triangleFace.push_back(f);
      surface.triangleAreas.push_back(area);
      surface.faceAreas[f] += area;
    }
  }
  return surface;
}

void CheckLabelSizes(std::size_t faceCount, const std::vector<int>& labelsA, const std::vector<int>& labelsB)
{
  if (labelsA.size() != labelsB.size())
  {
    throw SegmentationMetricsError("the two segmentations have different sizes (" +
      std::to_string(labelsA.size()) + " and " + std::to_string(labelsB.size()) + " labels)");
  }
  if (labelsA.size() != faceCount)
  {
    throw SegmentationMetricsError("the segmentations have " + std::to_string(labelsA.size()) +
      " labels but the mesh has " + std::to_string(faceCount) + " faces");
  }
}

// ---------------------------------------------------------------------------------------------
// Contingency table.

/// Segment index of each face, numbered in order of first appearance (so a relabelling, which
/// keeps the partition, keeps every index and every summation order).
std::vector<std::uint32_t> CompactLabels(const std::vector<int>& labels, std::size_t& segmentCount)
{
  std::unordered_map<int, std::uint32_t> ids;
  std::vector<std::uint32_t> compact(labels.size());
  for (std::size_t f = 0; f < labels.size(); ++f)
  {
    const auto inserted = ids.emplace(labels[f], static_cast<std::uint32_t>(ids.size()));
    compact[f] = inserted.first->second;
  }
  segmentCount = ids.size();
  return compact;
}

/// Stable counting sort of `order` by keys[order[i]].
std::vector<std::size_t> SortByKey(
  const std::vector<std::size_t>& order, const std::vector<std::uint32_t>& keys, std::size_t keyCount)
{
  std::vector<std::size_t> start(keyCount + 1, 0);
  for (std::size_t index : order)
  {
    ++start[keys[index] + 1];
  }
  for (std::size_t k = 0; k < keyCount; ++k)
  {
    start[k + 1] += start[k];
  }
  std::vector<std::size_t> sorted(order.size());
  for (std::size_t index : order)
  {
    sorted[start[keys[index]]++] = index;
  }
  return sorted;
}

struct Cell
{
  std::uint32_t a;
  std::uint32_t b;
  double weight;
  double pairCount; ///< uniform mode: C(count, 2); unused otherwise
};

double Clamp01(double value)
{
  if (!(value > 0.0)) // also catches NaN, which cannot happen but must never leave
  {
    return 0.0;
  }
  return std::min(value, 1.0);
}

double ChooseTwo(double count)
{
  return 0.5 * count * (count - 1.0);
}

} // namespace

// ---------------------------------------------------------------------------------------------

SegFileError::SegFileError(std::int64_t line, const std::string& reason, const std::string& source)
  : std::runtime_error(LineMessage(line, reason, source))
  , LineNumber(line)
{
}

PartitionComparison ComparePartitions(
  const std::vector<int>& labelsA, const std::vector<int>& labelsB, const std::vector<double>& faceWeights)
{
  if (labelsA.size() != labelsB.size())
  {
    throw SegmentationMetricsError("the two segmentations have different sizes (" +
      std::to_string(labelsA.size()) + " and " + std::to_string(labelsB.size()) + " labels)");
  }
  const std::size_t faceCount = labelsA.size();
  if (!faceWeights.empty() && faceWeights.size() != faceCount)
  {
    throw SegmentationMetricsError("there are " + std::to_string(faceWeights.size()) +
      " face weights for " + std::to_string(faceCount) + " faces");
  }
  for (double w : faceWeights)
  {
    if (!std::isfinite(w) || w < 0.0)
    {
      throw SegmentationMetricsError("a face weight is negative, NaN or infinite");
    }
  }

  PartitionComparison result;
  std::vector<std::uint32_t> segmentA = CompactLabels(labelsA, result.SegmentCountA);
  std::vector<std::uint32_t> segmentB = CompactLabels(labelsB, result.SegmentCountB);
  if (faceCount == 0)
  {
    result.UsedUniformWeights = faceWeights.empty();
    return result;
  }

  bool uniform = faceWeights.empty();
  if (!uniform)
  {
    double total = 0.0;
    for (double w : faceWeights)
    {
      total += w;
    }
    uniform = !(total > 0.0);
  }
  result.UsedUniformWeights = uniform;
  const auto weightOf = [&](std::size_t f) { return uniform ? 1.0 : faceWeights[f]; };

  // Cells of the sparse contingency table, sorted by (a, b): two stable counting sorts.
  std::vector<std::size_t> order(faceCount);
  for (std::size_t f = 0; f < faceCount; ++f)
  {
    order[f] = f;
  }
  order = SortByKey(order, segmentB, result.SegmentCountB);
  order = SortByKey(order, segmentA, result.SegmentCountA);
  std::vector<Cell> cells;
  for (std::size_t i = 0; i < faceCount;)
  {
    const std::uint32_t a = segmentA[order[i]];
    const std::uint32_t b = segmentB[order[i]];
    double weight = 0.0;
    std::size_t count = 0;
    for (; i < faceCount && segmentA[order[i]] == a && segmentB[order[i]] == b; ++i)
    {
      weight += weightOf(order[i]);
      ++count;
    }
    cells.push_back({ a, b, weight, ChooseTwo(static_cast<double>(count)) });
  }

  const std::size_t kA = result.SegmentCountA;
  const std::size_t kB = result.SegmentCountB;
  std::vector<double> sizeA(kA, 0.0), sizeB(kB, 0.0), bestA(kA, 0.0), bestB(kB, 0.0);
  for (const Cell& cell : cells)
  {
    sizeA[cell.a] += cell.weight;
    sizeB[cell.b] += cell.weight;
    bestA[cell.a] = std::max(bestA[cell.a], cell.weight);
    bestB[cell.b] = std::max(bestB[cell.b], cell.weight);
  }
  double total = 0.0;
  for (double s : sizeA)
  {
    total += s;
  }

  // Hamming: each term is >= 0 (a rounded sum of non-negative terms is >= each of them).
  double missing = 0.0, falseAlarm = 0.0;
  for (std::size_t j = 0; j < kB; ++j)
  {
    missing += sizeB[j] - bestB[j];
  }
  for (std::size_t i = 0; i < kA; ++i)
  {
    falseAlarm += sizeA[i] - bestA[i];
  }
  result.MissingRate = Clamp01(missing / total);
  result.FalseAlarmRate = Clamp01(falseAlarm / total);
  result.HammingDistance = 0.5 * (result.MissingRate + result.FalseAlarmRate);

  // Rand index: pairs grouped together by A only plus pairs grouped together by B only.
  if (uniform)
  {
    double sameA = 0.0, sameB = 0.0, sameBoth = 0.0;
    for (double s : sizeA)
    {
      sameA += ChooseTwo(s);
    }
    for (double s : sizeB)
    {
      sameB += ChooseTwo(s);
    }
    for (const Cell& cell : cells)
    {
      sameBoth += cell.pairCount;
    }
    const double pairs = ChooseTwo(static_cast<double>(faceCount));
    result.RandIndexError = pairs > 0.0 ? Clamp01(((sameA - sameBoth) + (sameB - sameBoth)) / pairs) : 0.0;
  }
  else
  {
    double squaresA = 0.0, squaresB = 0.0, squaresBoth = 0.0;
    for (double s : sizeA)
    {
      squaresA += s * s;
    }
    for (double s : sizeB)
    {
      squaresB += s * s;
    }
    for (const Cell& cell : cells)
    {
      squaresBoth += cell.weight * cell.weight;
    }
    result.RandIndexError = Clamp01(((squaresA - squaresBoth) + (squaresB - squaresBoth)) / (total * total));
  }

  // Consistency errors: E(A,B,f) depends only on the cell of f.
  double refinementAB = 0.0, refinementBA = 0.0, local = 0.0;
  for (const Cell& cell : cells)
  {
    const double errorAB = sizeA[cell.a] > 0.0 ? (sizeA[cell.a] - cell.weight) / sizeA[cell.a] : 0.0;
    const double errorBA = sizeB[cell.b] > 0.0 ? (sizeB[cell.b] - cell.weight) / sizeB[cell.b] : 0.0;
    refinementAB += cell.weight * errorAB;
    refinementBA += cell.weight * errorBA;
    local += cell.weight * std::min(errorAB, errorBA);
  }
  result.GlobalConsistencyError = Clamp01(std::min(refinementAB, refinementBA) / total);
  result.LocalConsistencyError = Clamp01(local / total);
  return result;
}

// ---------------------------------------------------------------------------------------------
// Cut discrepancy.

namespace
{

struct EdgeGraph
{
  std::vector<std::int64_t> first, second; ///< unique undirected edges, first < second
  std::vector<double> length;
  std::vector<std::int64_t> offsets;       ///< vertex CSR over the edges
  std::vector<std::int64_t> neighbor;
  std::vector<double> neighborLength;
};

struct Cuts
{
  EdgeGraph graph;
  std::vector<std::size_t> edgesA, edgesB;
};

Cuts FindCuts(const PointsView& points, const Surface& surface, const std::vector<int>& labelsA,
  const std::vector<int>& labelsB)
{
  struct Side
  {
    std::int64_t low, high;
    std::size_t triangle;
  };
  std::vector<Side> sides;
  sides.reserve(3 * surface.triangles.size());
  for (std::size_t t = 0; t < surface.triangles.size(); ++t)
  {
    for (std::size_t k = 0; k < 3; ++k)
    {
      const std::int64_t u = surface.triangles[t][k];
      const std::int64_t v = surface.triangles[t][(k + 1) % 3];
      if (u != v)
      {
        sides.push_back({ std::min(u, v), std::max(u, v), t });
      }
    }
  }
  std::sort(sides.begin(), sides.end(), [](const Side& x, const Side& y) {
    return x.low != y.low ? x.low < y.low : (x.high != y.high ? x.high < y.high : x.triangle < y.triangle);
  });

  Cuts cuts;
  EdgeGraph& graph = cuts.graph;
  for (std::size_t i = 0; i < sides.size();)
  {
    std::size_t end = i + 1;
    while (end < sides.size() && sides[end].low == sides[i].low && sides[end].high == sides[i].high)
    {
      ++end;
    }
    const std::size_t edge = graph.first.size();
    graph.first.push_back(sides[i].low);
    graph.second.push_back(sides[i].high);
    graph.length.push_back((points.row(sides[i].low) - points.row(sides[i].high)).norm());
    const std::size_t firstFace = surface.triangleFace[sides[i].triangle];
    bool cutA = false, cutB = false;
    for (std::size_t s = i + 1; s < end; ++s)
    {
      const std::size_t face = surface.triangleFace[sides[s].triangle];
      cutA = cutA || labelsA[face] != labelsA[firstFace];
      cutB = cutB || labelsB[face] != labelsB[firstFace];
    }
    if (cutA)
    {
      cuts.edgesA.push_back(edge);
    }
    if (cutB)
    {
      cuts.edgesB.push_back(edge);
    }
    i = end;
  }

  const auto vertexCount = static_cast<std::size_t>(points.rows());
  graph.offsets.assign(vertexCount + 1, 0);
  for (std::size_t e = 0; e < graph.first.size(); ++e)
  {
    ++graph.offsets[static_cast<std::size_t>(graph.first[e]) + 1];
    ++graph.offsets[static_cast<std::size_t>(graph.second[e]) + 1];
  }
  for (std::size_t v = 0; v < vertexCount; ++v)
  {
    graph.offsets[v + 1] += graph.offsets[v];
  }
  std::vector<std::int64_t> fill(graph.offsets.begin(), graph.offsets.end() - 1);
  graph.neighbor.resize(2 * graph.first.size());
  graph.neighborLength.resize(2 * graph.first.size());
  for (std::size_t e = 0; e < graph.first.size(); ++e)
  {
    const auto u = static_cast<std::size_t>(graph.first[e]);
    const auto v = static_cast<std::size_t>(graph.second[e]);
    graph.neighbor[static_cast<std::size_t>(fill[u])] = graph.second[e];
    graph.neighborLength[static_cast<std::size_t>(fill[u]++)] = graph.length[e];
    graph.neighbor[static_cast<std::size_t>(fill[v])] = graph.first[e];
    graph.neighborLength[static_cast<std::size_t>(fill[v]++)] = graph.length[e];
  }
  return cuts;
}

/// Sorted distinct vertices of the given edges.
std::vector<std::int64_t> CutVertices(const EdgeGraph& graph, const std::vector<std::size_t>& edges)
{
  std::vector<std::int64_t> vertices;
  vertices.reserve(2 * edges.size());
  for (std::size_t e : edges)
  {
    vertices.push_back(graph.first[e]);
    vertices.push_back(graph.second[e]);
  }
  std::sort(vertices.begin(), vertices.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  return vertices;
}

/// Edge-graph distance of every vertex from the nearest source (infinity when unreachable).
std::vector<double> DistancesFrom(const EdgeGraph& graph, const std::vector<std::int64_t>& sources)
{
  const double infinity = std::numeric_limits<double>::infinity();
  std::vector<double> distance(graph.offsets.size() - 1, infinity);
  using Entry = std::pair<double, std::int64_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  for (std::int64_t s : sources)
  {
    distance[static_cast<std::size_t>(s)] = 0.0;
    queue.push({ 0.0, s });
  }
  while (!queue.empty())
  {
    const auto [d, u] = queue.top();
    queue.pop();
    if (d > distance[static_cast<std::size_t>(u)])
    {
      continue;
    }
    const auto vertex = static_cast<std::size_t>(u);
    for (std::int64_t i = graph.offsets[vertex]; i < graph.offsets[vertex + 1]; ++i)
    {
      const std::int64_t v = graph.neighbor[static_cast<std::size_t>(i)];
      const double candidate = d + graph.neighborLength[static_cast<std::size_t>(i)];
      if (candidate < distance[static_cast<std::size_t>(v)])
      {
        distance[static_cast<std::size_t>(v)] = candidate;
        queue.push({ candidate, v });
      }
    }
  }
  return distance;
}

struct CutPointCloud
{
  const PointsView& points;
  const std::vector<std::int64_t>& vertices;

  std::size_t kdtree_get_point_count() const { return this->vertices.size(); }
  double kdtree_get_pt(std::size_t index, std::size_t dim) const
  {
    return this->points(this->vertices[index], static_cast<Eigen::Index>(dim));
  }
  template <class BoundingBox>
  bool kdtree_get_bbox(BoundingBox&) const
  {
    return false;
  }
};

using CutPointTree = nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, CutPointCloud>,
  CutPointCloud, 3, std::size_t>;

/// Replaces infinite distances at `queryVertices` by the Euclidean distance to the nearest of
/// `targetVertices` (non-empty). Returns how many were replaced.
std::size_t FillUnreachable(const PointsView& points, const std::vector<std::int64_t>& queryVertices,
  const std::vector<std::int64_t>& targetVertices, std::vector<double>& distance)
{
  std::size_t replaced = 0;
  std::unique_ptr<CutPointCloud> cloud;
  std::unique_ptr<CutPointTree> tree;
  for (std::int64_t v : queryVertices)
  {
    double& d = distance[static_cast<std::size_t>(v)];
    if (std::isfinite(d))
    {
      continue;
    }
    if (!tree)
    {
      cloud = std::make_unique<CutPointCloud>(CutPointCloud{ points, targetVertices });
      tree = std::make_unique<CutPointTree>(3, *cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
    }
    const std::array<double, 3> query = { points(v, 0), points(v, 1), points(v, 2) };
    std::size_t nearest = 0;
    double squared = 0.0;
    tree->knnSearch(query.data(), 1, &nearest, &squared);
    d = std::sqrt(squared);
    ++replaced;
  }
  return replaced;
}

/// Mean Euclidean distance of the surface from its area centroid (7-point degree-5 rule per
/// triangle); the vertex version when the area is zero.
double AverageRadius(const PointsView& points, const Surface& surface)
{
  double area = 0.0;
  Eigen::Vector3d weightedCenter = Eigen::Vector3d::Zero();
  for (std::size_t t = 0; t < surface.triangles.size(); ++t)
  {
    const double a = surface.triangleAreas[t];
    const auto& tri = surface.triangles[t];
    weightedCenter += a / 3.0 * (points.row(tri[0]) + points.row(tri[1]) + points.row(tri[2])).transpose();
    area += a;
  }
  if (area > 0.0)
  {
    const Eigen::Vector3d center = weightedCenter / area;
    const double root15 = std::sqrt(15.0);
    const double a1 = (9.0 - 2.0 * root15) / 21.0, b1 = (6.0 + root15) / 21.0, w1 = (155.0 + root15) / 1200.0;
    const double a2 = (9.0 + 2.0 * root15) / 21.0, b2 = (6.0 - root15) / 21.0, w2 = (155.0 - root15) / 1200.0;
    const std::array<std::array<double, 3>, 7> nodes = { { { 1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0 }, { a1, b1, b1 },
      { b1, a1, b1 }, { b1, b1, a1 }, { a2, b2, b2 }, { b2, a2, b2 }, { b2, b2, a2 } } };
    const std::array<double, 7> weights = { 0.225, w1, w1, w1, w2, w2, w2 };
    double integral = 0.0;
    for (std::size_t t = 0; t < surface.triangles.size(); ++t)
    {
      const auto& tri = surface.triangles[t];
      const Eigen::Vector3d p0 = points.row(tri[0]).transpose() - center;
      const Eigen::Vector3d p1 = points.row(tri[1]).transpose() - center;
      const Eigen::Vector3d p2 = points.row(tri[2]).transpose() - center;
      double mean = 0.0;
      for (std::size_t q = 0; q < nodes.size(); ++q)
      {
        mean += weights[q] * (nodes[q][0] * p0 + nodes[q][1] * p1 + nodes[q][2] * p2).norm();
      }
      integral += surface.triangleAreas[t] * mean;
    }
    return integral / area;
  }
  // No area: the vertices used by triangles, each once.
  std::vector<std::int64_t> used;
  for (const auto& tri : surface.triangles)
  {
    used.insert(used.end(), tri.begin(), tri.end());
  }
  std::sort(used.begin(), used.end());
  used.erase(std::unique(used.begin(), used.end()), used.end());
  if (used.empty())
  {
    return 0.0;
  }
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  for (std::int64_t v : used)
  {
    center += points.row(v).transpose();
  }
  center /= static_cast<double>(used.size());
  double sum = 0.0;
  for (std::int64_t v : used)
  {
    sum += (points.row(v).transpose() - center).norm();
  }
  return sum / static_cast<double>(used.size());
}

/// Integral of `distance` over the cut (length-weighted trapezoid) or its sum over the cut
/// vertices, and the matching measure (length or vertex count).
std::pair<double, double> IntegrateOverCut(const EdgeGraph& graph, const std::vector<std::size_t>& edges,
  const std::vector<std::int64_t>& vertices, const std::vector<double>& distance, bool byLength)
{
  double integral = 0.0, measure = 0.0;
  if (byLength)
  {
    for (std::size_t e : edges)
    {
      const double mean = 0.5 *
        (distance[static_cast<std::size_t>(graph.first[e])] + distance[static_cast<std::size_t>(graph.second[e])]);
      integral += graph.length[e] * mean;
      measure += graph.length[e];
    }
  }
  else
  {
    for (std::int64_t v : vertices)
    {
      integral += distance[static_cast<std::size_t>(v)];
    }
    measure = static_cast<double>(vertices.size());
  }
  return { integral, measure };
}

CutDiscrepancyResult CutDiscrepancy(const PointsView& points, const Surface& surface, const std::vector<int>& labelsA,
  const std::vector<int>& labelsB, const SegmentationMetricsOptions& options)
{
  CutDiscrepancyResult result;
  const Cuts cuts = FindCuts(points, surface, labelsA, labelsB);
  const EdgeGraph& graph = cuts.graph;
  result.CutEdgeCountA = cuts.edgesA.size();
  result.CutEdgeCountB = cuts.edgesB.size();
  for (std::size_t e : cuts.edgesA)
  {
    result.CutLengthA += graph.length[e];
  }
  for (std::size_t e : cuts.edgesB)
  {
    result.CutLengthB += graph.length[e];
  }
  result.AverageRadius = AverageRadius(points, surface);
  if (cuts.edgesA.empty() || cuts.edgesB.empty())
  {
    result.CutDiscrepancyDefined = cuts.edgesA.empty() && cuts.edgesB.empty();
    return result;
  }

  const std::vector<std::int64_t> verticesA = CutVertices(graph, cuts.edgesA);
  const std::vector<std::int64_t> verticesB = CutVertices(graph, cuts.edgesB);
  std::vector<double> distanceToB = DistancesFrom(graph, verticesB);
  std::vector<double> distanceToA = DistancesFrom(graph, verticesA);
  result.CutPointsWithEuclideanDistance = FillUnreachable(points, verticesA, verticesB, distanceToB) +
    FillUnreachable(points, verticesB, verticesA, distanceToA);

  // Cut edges of zero total length (coincident points) cannot weigh by length: count vertices.
  const bool byLength = options.Weighting == SegmentationWeighting::FaceArea && result.CutLengthA > 0.0 &&
    result.CutLengthB > 0.0;
  const auto [integralA, measureA] = IntegrateOverCut(graph, cuts.edgesA, verticesA, distanceToB, byLength);
  const auto [integralB, measureB] = IntegrateOverCut(graph, cuts.edgesB, verticesB, distanceToA, byLength);
  const double radius = result.AverageRadius;
  if (!(radius > 0.0) || !std::isfinite(radius))
  {
    return result; // every point coincides: every distance is 0
  }
  const auto finite = [](double value) { return std::isfinite(value) && value > 0.0 ? value : 0.0; };
  result.DirectionalCutDiscrepancyAB = finite(integralA / measureA / radius);
  result.DirectionalCutDiscrepancyBA = finite(integralB / measureB / radius);
  result.CutDiscrepancy = finite((integralA + integralB) / (measureA + measureB) / radius);
  return result;
}

} // namespace

CutDiscrepancyResult ComputeCutDiscrepancy(const PointsView& points, const TrianglesView& triangles,
  const std::vector<int>& labelsA, const std::vector<int>& labelsB, const SegmentationMetricsOptions& options)
{
  const Surface surface = SurfaceFromTriangles(points, triangles);
  CheckLabelSizes(surface.faceAreas.size(), labelsA, labelsB);
  return CutDiscrepancy(points, surface, labelsA, labelsB, options);
}

namespace
{

SegmentationComparison CompareOnSurface(const PointsView& points, const Surface& surface,
  const std::vector<int>& labelsA, const std::vector<int>& labelsB, const SegmentationMetricsOptions& options)
{
  CheckLabelSizes(surface.faceAreas.size(), labelsA, labelsB);
  SegmentationComparison result;
  result.Cut = CutDiscrepancy(points, surface, labelsA, labelsB, options);
  static const std::vector<double> noWeights;
  result.Partition = ComparePartitions(labelsA, labelsB,
    options.Weighting == SegmentationWeighting::FaceArea ? surface.faceAreas : noWeights);
  return result;
}

} // namespace

SegmentationComparison CompareSegmentations(const PointsView& points, const TrianglesView& triangles,
  const std::vector<int>& labelsA, const std::vector<int>& labelsB, const SegmentationMetricsOptions& options)
{
  return CompareOnSurface(points, SurfaceFromTriangles(points, triangles), labelsA, labelsB, options);
}

SegmentationComparison CompareSegmentations(const PointsView& points, const std::vector<std::int64_t>& faceOffsets,
  const std::vector<std::int64_t>& faceConnectivity, const std::vector<int>& labelsA, const std::vector<int>& labelsB,
  const SegmentationMetricsOptions& options)
{
  return CompareOnSurface(
    points, SurfaceFromPolygons(points, faceOffsets, faceConnectivity), labelsA, labelsB, options);
}

std::vector<double> ComputeFaceAreas(const PointsView& points, const std::vector<std::int64_t>& faceOffsets,
  const std::vector<std::int64_t>& faceConnectivity)
{
  return SurfaceFromPolygons(points, faceOffsets, faceConnectivity).faceAreas;
}

std::size_t CountSegmentsCovering(
  const std::vector<int>& labels, const std::vector<double>& faceWeights, double minimumShare)
{
  if (!faceWeights.empty() && faceWeights.size() != labels.size())
  {
    throw SegmentationMetricsError("the segmentation has " + std::to_string(labels.size()) + " labels but " +
      std::to_string(faceWeights.size()) + " face weights");
  }
  double total = 0.0;
  for (double w : faceWeights)
  {
    if (!(w >= 0.0) || !std::isfinite(w))
    {
      throw SegmentationMetricsError("a face weight is negative or not finite");
    }
    total += w;
  }
  const bool counted = !(total > 0.0);
  std::size_t segmentCount = 0;
  const std::vector<std::uint32_t> segment = CompactLabels(labels, segmentCount);
  std::vector<double> weight(segmentCount, 0.0);
  for (std::size_t f = 0; f < labels.size(); ++f)
  {
    weight[segment[f]] += counted ? 1.0 : faceWeights[f];
  }
  const double threshold = minimumShare * (counted ? static_cast<double>(labels.size()) : total);
  return static_cast<std::size_t>(
    std::count_if(weight.begin(), weight.end(), [threshold](double w) { return w >= threshold; }));
}

// ---------------------------------------------------------------------------------------------
// .seg files

namespace
{

inline bool IsBlank(char c)
{
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

} // namespace

std::vector<int> ParseSeg(const char* data, std::size_t size, const std::string& source)
{
  std::vector<int> labels;
  if (size == 0)
  {
    return labels;
  }
  const char* cursor = data;
  const char* const stop = data + size;
  if (size >= 3 && std::memcmp(data, "\xEF\xBB\xBF", 3) == 0)
  {
    cursor += 3;
  }
  std::int64_t line = 0;
  std::int64_t firstBlankLine = 0; // a blank line is fine only if no label follows it
  while (cursor < stop)
  {
    ++line;
    const auto remaining = static_cast<std::size_t>(stop - cursor);
    const char* lineEnd = static_cast<const char*>(std::memchr(cursor, '\n', remaining));
    if (!lineEnd)
    {
      lineEnd = stop;
    }
    const char* begin = cursor;
    const char* end = lineEnd;
    cursor = lineEnd < stop ? lineEnd + 1 : stop;
    while (begin < end && IsBlank(*begin))
    {
      ++begin;
    }
    while (end > begin && IsBlank(end[-1]))
    {
      --end;
    }
    if (begin == end)
    {
      if (firstBlankLine == 0)
      {
        firstBlankLine = line;
      }
      continue;
    }
    if (firstBlankLine != 0)
    {
      throw SegFileError(line, "a label after the blank line " + std::to_string(firstBlankLine) +
          " (each line must hold one label; blank lines are allowed only at the end)", source);
    }
    const char* number = begin;
    if (*number == '+' && number + 1 < end && number[1] != '-' && number[1] != '+')
    {
      ++number;
    }
    int value = 0;
    const std::from_chars_result parsed = std::from_chars(number, end, value);
    if (parsed.ec == std::errc::result_out_of_range)
    {
      throw SegFileError(line, "label '" + PrintableText(begin, end) + "' is outside the int range", source);
    }
    if (parsed.ec != std::errc() || parsed.ptr != end)
    {
      throw SegFileError(line, "expected one integer label, found '" + PrintableText(begin, end) + "'", source);
    }
    labels.push_back(value);
  }
  return labels;
}

std::vector<int> ReadSegFile(const std::string& path)
{
  std::string content;
  switch (ReadWholeFile(path, content))
  {
    case FileReadFailure::Open:
      throw SegFileError(0, std::string("cannot open: ") + std::strerror(errno), path);
    case FileReadFailure::Read:
      throw SegFileError(0, "read error", path);
    case FileReadFailure::None:
      break;
  }
  return ParseSeg(content.data(), content.size(), path);
}

void WriteSegFile(const std::string& path, const std::vector<int>& labels)
{
  std::FILE* file = std::fopen(path.c_str(), "wb");
  if (!file)
  {
    throw SegFileError(0, std::string("cannot open for writing: ") + std::strerror(errno), path);
  }
  bool failed = false;
  for (int label : labels)
  {
    if (std::fprintf(file, "%d\n", label) < 0)
    {
      failed = true;
      break;
    }
  }
  failed = std::fclose(file) != 0 || failed;
  if (failed)
  {
    throw SegFileError(0, "write error", path);
  }
}

} // namespace shapediameter
