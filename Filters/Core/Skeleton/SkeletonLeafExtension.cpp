// SPDX-License-Identifier: BSD-3-Clause
#include "Skeleton/SkeletonLeafExtension.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace shapediameter
{

void ValidateLeafExtensionOptions(const SkeletonLeafExtensionOptions& options)
{
  CheckRange(options.MaximumExitAngle, MaximumExitAngleRange, "skeleton: MaximumExitAngle");
}

namespace
{

/// Distance along `direction` (unit) at which a ray from `from` leaves the volume; +inf if it
/// does not (it enters first or meets nothing).
double ExitDistance(const RayCaster& volume, const Eigen::Vector3d& from, const Eigen::Vector3d& direction)
{
  RayOrigin origin;
  for (int c = 0; c < 3; ++c)
  {
    origin.Point[c] = from(c);
    origin.Normal[c] = direction(c);
  }
  origin.Rule = HitRule::FirstHitLeaving;
  return volume.ClosestValidHit(origin, direction.data());
}

/// Neighbours of every node in the union of the polylines' edges.
std::vector<std::vector<std::int64_t>> NodeAdjacency(const SkeletonGraph& graph)
{
  std::vector<std::vector<std::int64_t>> adjacency(graph.NodeRadius.size());
  for (const auto& polyline : graph.Polylines)
  {
    for (std::size_t i = 1; i < polyline.size(); ++i)
    {
      const std::int64_t a = polyline[i - 1];
      const std::int64_t b = polyline[i];
      if (a != b && std::find(adjacency[a].begin(), adjacency[a].end(), b) == adjacency[a].end())
      {
        adjacency[a].push_back(b);
        adjacency[b].push_back(a);
      }
    }
  }
  return adjacency;
}

} // namespace

std::size_t ExtendLeavesToPartEnds(SkeletonGraph& graph, const RayCaster& volume,
  const SkeletonLeafExtensionOptions& options)
{
  ValidateLeafExtensionOptions(options);
  if (!(options.MaximumExitAngle > 0.0))
  {
    return 0;
  }
  const double minimumCosine = std::cos(options.MaximumExitAngle * 3.14159265358979323846 / 180.0);
  const std::vector<std::vector<std::int64_t>> adjacency = NodeAdjacency(graph);
  const std::size_t nodes = adjacency.size();
  const auto position = [&graph](std::int64_t node) -> Eigen::Vector3d {
    return graph.NodePositions.row(node).transpose();
  };
  std::size_t extended = 0;
  for (std::size_t v = 0; v < nodes; ++v)
  {
    const auto leaf = static_cast<std::int64_t>(v);
    const double radius = graph.NodeRadius[v];
    if (adjacency[v].size() != 1 || !(radius > 0.0))
    {
      continue;
    }
    // 1. Direction: from the farthest node within 2 r back along the branch.
    const Eigen::Vector3d tip = position(leaf);
    std::int64_t previous = leaf;
    std::int64_t current = adjacency[v][0];
    std::int64_t back = current;
    while (adjacency[current].size() == 2)
    {
      const auto& around = adjacency[current];
      const std::int64_t next = around[0] == previous ? around[1] : around[0];
      previous = current;
      current = next;
      if ((position(current) - tip).norm() >= 2.0 * radius)
      {
        break;
      }
      back = current;
    }
    Eigen::Vector3d direction = tip - position(back);
    if (!(direction.norm() > 0.0))
    {
      continue;
    }
    direction.normalize();

    // 2. Where the branch's line leaves the volume, and the exit surface's normal there.
    const double exit = ExitDistance(volume, tip, direction);
    const double extension = exit - radius;
    if (!std::isfinite(exit) || !(extension > 0.25 * radius))
    {
      continue;
    }
    const Eigen::Vector3d side = direction.unitOrthogonal();
    const Eigen::Vector3d other = direction.cross(side);
    const double exitSide = ExitDistance(volume, tip + 0.25 * radius * side, direction);
    const double exitOther = ExitDistance(volume, tip + 0.25 * radius * other, direction);
    if (!std::isfinite(exitSide) || !std::isfinite(exitOther))
    {
      continue;
    }
    const Eigen::Vector3d exitPoint = tip + exit * direction;
    const Eigen::Vector3d normal = (tip + 0.25 * radius * side + exitSide * direction - exitPoint)
                                     .cross(tip + 0.25 * radius * other + exitOther * direction - exitPoint);
    if (!(normal.norm() > 0.0) || std::abs(normal.normalized().dot(direction)) < minimumCosine)
    {
      continue;
    }

    // 3. One node where a ball of the leaf's radius touches the surface ahead.
    const Eigen::Index row = graph.NodePositions.rows();
    graph.NodePositions.conservativeResize(row + 1, 3);
    graph.NodePositions.row(row) = (tip + extension * direction).transpose();
    graph.NodeRadius.push_back(radius);
    graph.NodeConfidence.push_back(0.0);
    graph.NodeCloudIndex.push_back(graph.NodeCloudIndex[v]);
    graph.NodeComponent.push_back(graph.NodeComponent[v]);
    graph.Polylines.push_back({ leaf, static_cast<std::int64_t>(row) });
    graph.IsConnection.push_back(0);
    ++extended;
  }
  return extended;
}

} // namespace shapediameter
