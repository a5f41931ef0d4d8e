// SPDX-License-Identifier: BSD-3-Clause
#include "SkeletonCoverage.h"

#include "SkeletonPointTree.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>
#include <utility>

namespace shapediameter
{

void ValidateCoverageOptions(const SkeletonCoverageOptions& options)
{
  if (!(options.UncoveredFactor >= 0.0 && options.UncoveredFactor <= 1e6))
  {
    throw SkeletonError("skeleton: UncoveredFactor must be in [0, 1e6]");
  }
  if (!(options.MinimumShare >= 0.0 && options.MinimumShare <= 1.0))
  {
    throw SkeletonError("skeleton: coverage MinimumShare must be in [0, 1]");
  }
  if (options.NumberOfNeighbors < 1 || options.NumberOfNeighbors > 100)
  {
    throw SkeletonError("skeleton: coverage NumberOfNeighbors must be in [1, 100]");
  }
}

namespace
{

using Adjacency = std::vector<std::vector<std::pair<std::int64_t, double>>>;

/// Neighbour graph of P restricted to edges with an uncovered end, within one component and
/// through the volume. Each pair is tested once, from its lower index, so the graph does not
/// depend on the thread count.
Adjacency UncoveredNeighborGraph(const ProjectedCloud& cloud, const std::vector<char>& uncovered,
  const std::function<std::int64_t(std::size_t)>& componentOf, int neighbors,
  const ParallelFor& parallelFor, const RayCaster* volume)
{
  const std::size_t n = cloud.Size();
  const SkeletonPointTree tree(cloud.Positions);
  std::vector<std::vector<std::pair<std::int64_t, double>>> edgesOf(n);
  parallelFor(n, [&](std::size_t begin, std::size_t end) {
    std::vector<std::int64_t> nearest;
    std::vector<double> squaredDistances;
    for (std::size_t i = begin; i < end; ++i)
    {
      tree.NearestNeighbors(cloud.Positions.row(static_cast<Eigen::Index>(i)).transpose(),
        static_cast<std::size_t>(neighbors) + 1, nearest, squaredDistances);
      for (std::size_t j = 0; j < nearest.size(); ++j)
      {
        const auto q = static_cast<std::size_t>(nearest[j]);
        if (q == i || componentOf(q) != componentOf(i) || !(uncovered[i] || uncovered[q]))
        {
          continue;
        }
        const std::size_t low = std::min(i, q);
        const std::size_t high = std::max(i, q);
        if (volume && SegmentCrossesSurface(*volume,
          cloud.Positions.row(static_cast<Eigen::Index>(low)).transpose(),
          cloud.Positions.row(static_cast<Eigen::Index>(high)).transpose()))
        {
          continue;
        }
        edgesOf[i].push_back({ static_cast<std::int64_t>(q), std::sqrt(squaredDistances[j]) });
      }
    }
  });
  Adjacency adjacency(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    for (const auto& [q, length] : edgesOf[i])
    {
      const auto other = static_cast<std::size_t>(q);
      const auto known = std::find_if(adjacency[i].begin(), adjacency[i].end(),
        [q = q](const auto& edge) { return edge.first == q; });
      if (known == adjacency[i].end())
      {
        adjacency[i].push_back({ q, length });
        adjacency[other].push_back({ static_cast<std::int64_t>(i), length });
      }
    }
  }
  return adjacency;
}

/// Shortest path through the graph from `tip` to the nearest covered point (ties: lowest
/// index), listed from that point to the tip; empty if no covered point is reachable.
std::vector<std::int64_t> PathToCovered(
  const Adjacency& adjacency, const std::vector<char>& uncovered, std::int64_t tip)
{
  std::vector<double> distance(adjacency.size(), std::numeric_limits<double>::infinity());
  std::vector<std::int64_t> previous(adjacency.size(), -1);
  using Entry = std::pair<double, std::int64_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  distance[static_cast<std::size_t>(tip)] = 0.0;
  queue.push({ 0.0, tip });
  while (!queue.empty())
  {
    const auto [reached, point] = queue.top();
    queue.pop();
    const auto p = static_cast<std::size_t>(point);
    if (reached > distance[p])
    {
      continue;
    }
    if (!uncovered[p])
    {
      std::vector<std::int64_t> path;
      for (std::int64_t v = point; v >= 0; v = previous[static_cast<std::size_t>(v)])
      {
        path.push_back(v);
      }
      return path;
    }
    for (const auto& [next, length] : adjacency[p])
    {
      const auto q = static_cast<std::size_t>(next);
      if (reached + length < distance[q])
      {
        distance[q] = reached + length;
        previous[q] = point;
        queue.push({ distance[q], next });
      }
    }
  }
  return {};
}

} // namespace

std::size_t ReachUncoveredParts(SkeletonGraph& graph, const ProjectedCloud& cloud,
  const ThinnedCloud& thinned, const std::vector<std::int64_t>& pointComponent,
  const SkeletonCoverageOptions& options, const ParallelFor& parallelFor, const RayCaster* volume)
{
  const std::size_t n = cloud.Size();
  if (!(options.UncoveredFactor > 0.0) || n == 0 || graph.NodePositions.rows() == 0)
  {
    return 0;
  }
  const auto componentOf = [&](std::size_t point) {
    return pointComponent.empty() ? std::int64_t{ 0 } : pointComponent[point];
  };
  const auto nodeComponent = [&](std::int64_t node) {
    return pointComponent.empty() ? std::int64_t{ 0 } : graph.NodeComponent[static_cast<std::size_t>(node)];
  };

  // 1. Distance of every point to the skeleton of its component.
  const SkeletonPointTree nodes(graph.NodePositions);
  std::vector<double> gap(n, 0.0);
  std::vector<std::int64_t> nearestNode(n, -1);
  std::vector<char> uncovered(n, 0);
  parallelFor(n, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
    {
      const Eigen::Vector3d point = cloud.Positions.row(static_cast<Eigen::Index>(i)).transpose();
      const std::int64_t node = nodes.NearestAccepted(
        point, [&](std::int64_t candidate) { return nodeComponent(candidate) == componentOf(i); });
      nearestNode[i] = node;
      if (node >= 0)
      {
        gap[i] = (point - graph.NodePositions.row(node).transpose()).norm();
        // A point without thickness (SDF 0) has no scale to be far at.
        uncovered[i] = cloud.Radius[i] > 0.0 && gap[i] > options.UncoveredFactor * cloud.Radius[i];
      }
    }
  });

  if (std::none_of(uncovered.begin(), uncovered.end(), [](char u) { return u != 0; }))
  {
    return 0; // the common case: no neighbour graph to build
  }

  // 2. Groups of uncovered points.
  const Adjacency adjacency =
    UncoveredNeighborGraph(cloud, uncovered, componentOf, options.NumberOfNeighbors, parallelFor, volume);
  std::vector<std::int64_t> group(n, -1);
  std::vector<std::size_t> groupSize;
  std::vector<std::int64_t> groupTip;
  for (std::size_t seed = 0; seed < n; ++seed)
  {
    if (!uncovered[seed] || group[seed] >= 0)
    {
      continue;
    }
    const auto label = static_cast<std::int64_t>(groupSize.size());
    groupSize.push_back(0);
    groupTip.push_back(static_cast<std::int64_t>(seed));
    std::vector<std::size_t> stack{ seed };
    group[seed] = label;
    while (!stack.empty())
    {
      const std::size_t point = stack.back();
      stack.pop_back();
      ++groupSize.back();
      const auto tip = static_cast<std::size_t>(groupTip.back());
      if (gap[point] > gap[tip] || (gap[point] == gap[tip] && point < tip))
      {
        groupTip.back() = static_cast<std::int64_t>(point);
      }
      for (const auto& [next, length] : adjacency[point])
      {
        const auto q = static_cast<std::size_t>(next);
        if (uncovered[q] && group[q] < 0)
        {
          group[q] = label;
          stack.push_back(q);
        }
      }
    }
  }

  // 3. One branch per large group.
  std::size_t added = 0;
  for (std::size_t g = 0; g < groupSize.size(); ++g)
  {
    if (static_cast<double>(groupSize[g]) < options.MinimumShare * static_cast<double>(n))
    {
      continue;
    }
    const std::vector<std::int64_t> path = PathToCovered(adjacency, uncovered, groupTip[g]);
    if (path.empty())
    {
      continue;
    }
    std::vector<std::int64_t> polyline{ nearestNode[static_cast<std::size_t>(path.front())] };
    Eigen::Vector3d last = graph.NodePositions.row(polyline.front()).transpose();
    for (std::size_t j = 1; j < path.size(); ++j)
    {
      const auto point = static_cast<std::size_t>(path[j]);
      const Eigen::Vector3d position = thinned.Positions.row(static_cast<Eigen::Index>(point)).transpose();
      if (j + 1 < path.size() && (position - last).norm() < 0.5 * cloud.Radius[point])
      {
        continue;
      }
      const Eigen::Index row = graph.NodePositions.rows();
      graph.NodePositions.conservativeResize(row + 1, 3);
      graph.NodePositions.row(row) = position.transpose();
      graph.NodeRadius.push_back(cloud.Radius[point]);
      graph.NodeConfidence.push_back(thinned.Confidence[point]);
      graph.NodeCloudIndex.push_back(static_cast<std::int64_t>(point));
      graph.NodeComponent.push_back(componentOf(point));
      polyline.push_back(static_cast<std::int64_t>(row));
      last = position;
    }
    if (polyline.size() < 2)
    {
      continue;
    }
    graph.Polylines.push_back(std::move(polyline));
    graph.IsConnection.push_back(1);
    ++added;
  }
  if (added > 0)
  {
    AssignBranchBones(graph);
  }
  return added;
}

} // namespace shapediameter
