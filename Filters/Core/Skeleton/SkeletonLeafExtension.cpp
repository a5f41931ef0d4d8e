// SPDX-License-Identifier: BSD-3-Clause
#include "Skeleton/SkeletonLeafExtension.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

namespace shapediameter
{

void ValidateLeafExtensionOptions(const SkeletonLeafExtensionOptions& options)
{
  CheckRange(options.MaximumExitAngle, MaximumExitAngleRange, "skeleton: MaximumExitAngle");
  CheckRange(options.TipReach, TipReachRange, "skeleton: TipReach");
}

namespace
{

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

/// Where a leaf's branch leaves the volume, when it meets that exit head-on.
struct LeafExit
{
  Eigen::Vector3d Tip;
  Eigen::Vector3d Direction; ///< unit, along the branch towards the leaf and beyond
  double Distance = 0.0;     ///< from Tip to the surface along Direction
};

/// A leaf's branch line and the two rays beside it whose exits give the exit surface's normal.
struct LeafLine
{
  std::int64_t Leaf = -1;
  Eigen::Vector3d Tip;
  Eigen::Vector3d Direction; ///< unit, along the branch towards the leaf and beyond
  Eigen::Vector3d Side;      ///< tip offset of the first ray beside the line
  Eigen::Vector3d Other;     ///< tip offset of the second
};

/// The branch's direction at leaf v (from its node about 2 r back); false when it has none.
bool FindLeafLine(const SkeletonGraph& graph, const std::vector<std::vector<std::int64_t>>& adjacency,
  std::int64_t leaf, LeafLine& line)
{
  const auto position = [&graph](std::int64_t node) -> Eigen::Vector3d {
    return graph.NodePositions.row(node).transpose();
  };
  const double radius = graph.NodeRadius[static_cast<std::size_t>(leaf)];
  const Eigen::Vector3d tip = position(leaf);
  std::int64_t previous = leaf;
  std::int64_t current = adjacency[static_cast<std::size_t>(leaf)][0];
  std::int64_t back = current;
  while (adjacency[static_cast<std::size_t>(current)].size() == 2)
  {
    const auto& around = adjacency[static_cast<std::size_t>(current)];
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
    return false;
  }
  direction.normalize();
  const Eigen::Vector3d side = direction.unitOrthogonal();
  line = LeafLine{ leaf, tip, direction, 0.25 * radius * side, 0.25 * radius * direction.cross(side) };
  return true;
}

/// Where the line leaves the volume (exit along it, exitSide and exitOther beside it), when it
/// meets that exit head-on: the exit surface within the angle whose cosine is minimumCosine.
bool IsHeadOnExit(const LeafLine& line, double exit, double exitSide, double exitOther, double minimumCosine)
{
  if (!std::isfinite(exit) || !std::isfinite(exitSide) || !std::isfinite(exitOther))
  {
    return false;
  }
  const Eigen::Vector3d& direction = line.Direction;
  const Eigen::Vector3d exitPoint = line.Tip + exit * direction;
  const Eigen::Vector3d normal = (line.Tip + line.Side + exitSide * direction - exitPoint)
                                   .cross(line.Tip + line.Other + exitOther * direction - exitPoint);
  if (!(normal.norm() > 0.0) || std::abs(normal.normalized().dot(direction)) < minimumCosine)
  {
    return false;
  }
  return true;
}

/// Appends a node after leaf v: position, v's radius, confidence 0, v's cloud point and
/// component, and the two-node polyline (IsConnection 0).
void AppendLeafNode(SkeletonGraph& graph, std::int64_t leaf, const Eigen::Vector3d& at)
{
  const auto v = static_cast<std::size_t>(leaf);
  const Eigen::Index row = graph.NodePositions.rows();
  graph.NodePositions.conservativeResize(row + 1, 3);
  graph.NodePositions.row(row) = at.transpose();
  graph.NodeRadius.push_back(graph.NodeRadius[v]);
  graph.NodeConfidence.push_back(0.0);
  graph.NodeCloudIndex.push_back(graph.NodeCloudIndex[v]);
  graph.NodeComponent.push_back(graph.NodeComponent[v]);
  graph.Polylines.push_back({ leaf, static_cast<std::int64_t>(row) });
  graph.IsConnection.push_back(0);
}

/// The leaves (degree 1, radius > 0) whose branch meets its exit head-on (within
/// maximumExitAngle degrees), with that exit, in node order; none when the angle is 0.
std::vector<std::pair<std::int64_t, LeafExit>> HeadOnLeafExits(
  const SkeletonGraph& graph, const RayCaster& volume, double maximumExitAngle)
{
  std::vector<std::pair<std::int64_t, LeafExit>> exits;
  if (!(maximumExitAngle > 0.0))
  {
    return exits;
  }
  const double minimumCosine = std::cos(maximumExitAngle * 3.14159265358979323846 / 180.0);
  const std::vector<std::vector<std::int64_t>> adjacency = NodeAdjacency(graph);
  // Every leaf's three rays in one batch (a volume over processes answers it in one exchange).
  std::vector<LeafLine> lines;
  std::vector<Ray> rays;
  for (std::size_t v = 0; v < adjacency.size(); ++v)
  {
    LeafLine line;
    if (adjacency[v].size() == 1 && graph.NodeRadius[v] > 0.0 &&
      FindLeafLine(graph, adjacency, static_cast<std::int64_t>(v), line))
    {
      lines.push_back(line);
      for (const Eigen::Vector3d& offset : { Eigen::Vector3d::Zero().eval(), line.Side, line.Other })
      {
        rays.push_back(ExitRay(line.Tip + offset, line.Direction));
      }
    }
  }
  std::vector<double> distances;
  volume.CastRays(rays, distances, SerialFor);
  for (std::size_t l = 0; l < lines.size(); ++l)
  {
    const double exit = distances[3 * l];
    if (IsHeadOnExit(lines[l], exit, distances[3 * l + 1], distances[3 * l + 2], minimumCosine))
    {
      exits.emplace_back(lines[l].Leaf, LeafExit{ lines[l].Tip, lines[l].Direction, exit });
    }
  }
  return exits;
}

} // namespace

std::size_t ExtendLeavesToPartEnds(SkeletonGraph& graph, const RayCaster& volume,
  const SkeletonLeafExtensionOptions& options)
{
  ValidateLeafExtensionOptions(options);
  std::size_t extended = 0;
  for (const auto& [leaf, exit] : HeadOnLeafExits(graph, volume, options.MaximumExitAngle))
  {
    // One node where a ball of the leaf's radius touches the surface ahead.
    const double radius = graph.NodeRadius[static_cast<std::size_t>(leaf)];
    const double extension = exit.Distance - radius;
    if (extension > 0.25 * radius)
    {
      AppendLeafNode(graph, leaf, exit.Tip + extension * exit.Direction);
      ++extended;
    }
  }
  return extended;
}

std::size_t ExtendLeavesToSurface(SkeletonGraph& graph, const RayCaster& volume,
  const SkeletonLeafExtensionOptions& options)
{
  ValidateLeafExtensionOptions(options);
  if (!(options.TipReach > 0.0))
  {
    return 0;
  }
  std::size_t extended = 0;
  for (const auto& [leaf, exit] : HeadOnLeafExits(graph, volume, options.MaximumExitAngle))
  {
    const auto v = static_cast<std::size_t>(leaf);
    const double extension = options.TipReach * exit.Distance;
    if (extension > 0.25 * graph.NodeRadius[v])
    {
      AppendLeafNode(graph, leaf, exit.Tip + extension * exit.Direction);
      graph.NodeBone.push_back(graph.NodeBone[v]);
      graph.PolylineBone.push_back(graph.NodeBone[v]);
      graph.BoneLength[static_cast<std::size_t>(graph.NodeBone[v])] += extension;
      ++extended;
    }
  }
  return extended;
}

} // namespace shapediameter
