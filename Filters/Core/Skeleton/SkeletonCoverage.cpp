// SPDX-License-Identifier: BSD-3-Clause
#include "Skeleton/SkeletonCoverage.h"

#include "Skeleton/SkeletonPointTree.h"

#include <Eigen/Eigenvalues>

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
  CheckRange(options.UncoveredFactor, UncoveredFactorRange, "skeleton: UncoveredFactor");
  CheckRange(options.MinimumShare, CoverageMinimumShareRange, "skeleton: coverage MinimumShare");
  CheckRange(options.SideLimbJoinDepth, SideLimbJoinDepthRange, "skeleton: coverage SideLimbJoinDepth");
  CheckRange(options.PartMinimumShare, PartMinimumShareRange, "skeleton: coverage PartMinimumShare");
  CheckRange(options.PartUncoveredFactor, PartUncoveredFactorRange, "skeleton: coverage PartUncoveredFactor");
  CheckRange(options.ThinLimbFactor, ThinLimbFactorRange, "skeleton: ThinLimbFactor");
  CheckRange(options.ThinLimbLinearity, ThinLimbLinearityRange, "skeleton: coverage ThinLimbLinearity");
  CheckRange(options.ThinLimbMinimumShare, ThinLimbMinimumShareRange, "skeleton: coverage ThinLimbMinimumShare");
  CheckRange(options.SmallLimbMinimumShare, SmallLimbMinimumShareRange, "skeleton: coverage SmallLimbMinimumShare");
}

namespace
{

/// Dijkstra through the graph's edges that are not bridges (through the volume only, see the
/// header comment) from `sources` (at distance 0), entering only the points mayEnter accepts;
/// stops at the first point settled that isGoal accepts (ties: lowest index) and returns it,
/// -1 when none is. distance (one per point, +inf) receives the distances reached, previous
/// (if given, one per point, -1) each point's predecessor.
template <typename MayEnter, typename IsGoal>
std::int64_t WalkThroughVolume(const CloudNeighborGraph& neighbours, const std::vector<std::int64_t>& sources,
  MayEnter mayEnter, IsGoal isGoal, std::vector<double>& distance, std::vector<std::int64_t>* previous)
{
  using Entry = std::pair<double, std::int64_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> queue;
  for (const std::int64_t source : sources)
  {
    distance[static_cast<std::size_t>(source)] = 0.0;
    queue.push({ 0.0, source });
  }
  while (!queue.empty())
  {
    const auto [reached, point] = queue.top();
    queue.pop();
    const auto p = static_cast<std::size_t>(point);
    if (reached > distance[p])
    {
      continue;
    }
    if (isGoal(p))
    {
      return point;
    }
    for (std::size_t e = neighbours.Offsets[p]; e < neighbours.Offsets[p + 1]; ++e)
    {
      const std::int64_t next = neighbours.Targets[e];
      const auto q = static_cast<std::size_t>(next);
      if (!neighbours.IsBridge[e] && mayEnter(q) && reached + neighbours.Weights[e] < distance[q])
      {
        distance[q] = reached + neighbours.Weights[e];
        if (previous)
        {
          (*previous)[q] = point;
        }
        queue.push({ distance[q], next });
      }
    }
  }
  return -1;
}

/// Shortest path through the graph from `tip` to the nearest covered point (ties: lowest
/// index), listed from that point to the tip; empty if no covered point is reachable. Only
/// uncovered points are expanded: the path ends at the first covered point.
std::vector<std::int64_t> PathToCovered(
  const CloudNeighborGraph& neighbours, const std::vector<char>& uncovered, std::int64_t tip)
{
  std::vector<double> distance(uncovered.size(), std::numeric_limits<double>::infinity());
  std::vector<std::int64_t> previous(uncovered.size(), -1);
  const std::int64_t covered = WalkThroughVolume(
    neighbours, { tip }, [](std::size_t) { return true; }, [&](std::size_t p) { return !uncovered[p]; },
    distance, &previous);
  std::vector<std::int64_t> path;
  for (std::int64_t v = covered; v >= 0; v = previous[static_cast<std::size_t>(v)])
  {
    path.push_back(v);
  }
  return path;
}

/// Adds the branch along `path` (from its first point, outside the region, to the tip): it
/// starts at the node nearest to the first point and runs through the MLS positions of the
/// others, each kept when at least half its radius from the previous node (the tip always).
/// Returns false (nothing added) for an empty path or one that adds no node.
bool AddBranch(SkeletonGraph& graph, const ProjectedCloud& cloud, const ThinnedCloud& thinned,
  const std::vector<std::int64_t>& path, const std::vector<std::int64_t>& nearestNode,
  const std::vector<std::int64_t>& pointComponent)
{
  if (path.empty())
  {
    return false;
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
    graph.NodeComponent.push_back(pointComponent.empty() ? std::int64_t{ 0 } : pointComponent[point]);
    polyline.push_back(static_cast<std::int64_t>(row));
    last = position;
  }
  if (polyline.size() < 2)
  {
    return false;
  }
  graph.Polylines.push_back(std::move(polyline));
  graph.IsConnection.push_back(1);
  return true;
}

/// Nearest node of its own component for every point of P, and the distance to it.
void NearestNodes(const SkeletonGraph& graph, const ProjectedCloud& cloud,
  const std::vector<std::int64_t>& pointComponent, const ParallelFor& parallelFor,
  std::vector<std::int64_t>& nearestNode, std::vector<double>& gap)
{
  const std::size_t n = cloud.Size();
  const SkeletonPointTree nodes(graph.NodePositions);
  nearestNode.assign(n, -1);
  gap.assign(n, 0.0);
  parallelFor(n, [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
    {
      const Eigen::Vector3d point = cloud.Positions.row(static_cast<Eigen::Index>(i)).transpose();
      const std::int64_t component = pointComponent.empty() ? 0 : pointComponent[i];
      const std::int64_t node = nodes.NearestAccepted(point, [&](std::int64_t candidate) {
        return pointComponent.empty() || graph.NodeComponent[static_cast<std::size_t>(candidate)] == component;
      });
      nearestNode[i] = node;
      if (node >= 0)
      {
        gap[i] = (point - graph.NodePositions.row(node).transpose()).norm();
      }
    }
  });
}

/// Throws Error unless the neighbour graph has one row per point of P.
void CheckNeighbourGraph(const CloudNeighborGraph& neighbours, std::size_t n)
{
  if (neighbours.Offsets.size() != n + 1 || neighbours.Targets.size() != neighbours.Offsets[n]
    || neighbours.Weights.size() != neighbours.Offsets[n]
    || neighbours.IsBridge.size() != neighbours.Offsets[n])
  {
    throw Error("skeleton: the neighbour graph does not match the projected cloud");
  }
}

/// The connected sets of flagged points through the neighbour graph (bridges not used), in
/// order of their lowest point.
struct PointGroups
{
  std::vector<std::size_t> Size;
  /// The point farthest from the skeleton (gap; ties: the lowest index): how far the part
  /// reaches.
  std::vector<std::int64_t> Tip;
  /// Where its branch ends: of the points within one radius (the tip's) of the tip's gap (the
  /// part's far end), the one nearest to their centroid moved out along the tip's direction
  /// from its nearest node to the tip's depth (ties: the lowest index): centred across the
  /// end, as far out as the tip. Why not the tip itself: the farthest point of a stub as thick
  /// as it is long is a corner of its end (the libigl hand's wrist: its branch ran sideways to
  /// the wrist's edge). On a line of points the end is the tip.
  std::vector<std::int64_t> End;
  /// Largest eigenvalue / sum of the covariance of the group's points (1 = on a line); 0 for a
  /// group of fewer than 3 points.
  std::vector<double> Linearity;
  /// Per point of the cloud: its group, -1 for a point not flagged.
  std::vector<std::int64_t> GroupOf;
};

/// Linearity (PointGroups::Linearity) of the points `members` of `positions`, centred first so
/// that far-off coordinates do not cancel.
double Linearity(const PointMatrix& positions, const std::vector<std::size_t>& members)
{
  if (members.size() < 3)
  {
    return 0.0;
  }
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const std::size_t point : members)
  {
    mean += positions.row(static_cast<Eigen::Index>(point)).transpose();
  }
  mean /= static_cast<double>(members.size());
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const std::size_t point : members)
  {
    const Eigen::Vector3d d = positions.row(static_cast<Eigen::Index>(point)).transpose() - mean;
    covariance += d * d.transpose();
  }
  const Eigen::Vector3d eigenvalues = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(covariance).eigenvalues();
  const double total = eigenvalues.sum();
  return total > 0.0 ? eigenvalues(2) / total : 0.0;
}

/// PointGroups::End of the group `members` whose farthest point is `tip`, `outward` the unit
/// direction from the tip's nearest node to the tip (zero: none).
std::size_t FarEndCentre(const ProjectedCloud& cloud, const std::vector<double>& gap,
  const std::vector<std::size_t>& members, std::size_t tip, const Eigen::Vector3d& outward)
{
  const double farEnd = gap[tip] - cloud.Radius[tip];
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  std::size_t count = 0;
  for (const std::size_t point : members)
  {
    if (gap[point] >= farEnd)
    {
      centre += cloud.Positions.row(static_cast<Eigen::Index>(point)).transpose();
      ++count;
    }
  }
  centre /= static_cast<double>(count); // the tip itself is counted
  const Eigen::Vector3d tipPosition = cloud.Positions.row(static_cast<Eigen::Index>(tip)).transpose();
  centre += (tipPosition - centre).dot(outward) * outward;
  std::size_t end = tip;
  double nearest = std::numeric_limits<double>::infinity();
  for (const std::size_t point : members)
  {
    const double distance = (cloud.Positions.row(static_cast<Eigen::Index>(point)).transpose() - centre).norm();
    if (gap[point] >= farEnd && (distance < nearest || (distance == nearest && point < end)))
    {
      nearest = distance;
      end = point;
    }
  }
  return end;
}

PointGroups GroupFlaggedPoints(const CloudNeighborGraph& neighbours, const ProjectedCloud& cloud,
  const std::vector<char>& flagged, const std::vector<double>& gap, const SkeletonGraph& graph,
  const std::vector<std::int64_t>& nearestNode)
{
  PointGroups groups;
  groups.GroupOf.assign(flagged.size(), -1);
  std::vector<char> visited(flagged.size(), 0);
  for (std::size_t seed = 0; seed < flagged.size(); ++seed)
  {
    if (!flagged[seed] || visited[seed])
    {
      continue;
    }
    std::size_t tip = seed;
    std::vector<std::size_t> members;
    std::vector<std::size_t> stack{ seed };
    visited[seed] = 1;
    while (!stack.empty())
    {
      const std::size_t point = stack.back();
      stack.pop_back();
      members.push_back(point);
      groups.GroupOf[point] = static_cast<std::int64_t>(groups.Size.size());
      if (gap[point] > gap[tip] || (gap[point] == gap[tip] && point < tip))
      {
        tip = point;
      }
      for (std::size_t e = neighbours.Offsets[point]; e < neighbours.Offsets[point + 1]; ++e)
      {
        const auto q = static_cast<std::size_t>(neighbours.Targets[e]);
        if (!neighbours.IsBridge[e] && flagged[q] && !visited[q])
        {
          visited[q] = 1;
          stack.push_back(q);
        }
      }
    }
    groups.Size.push_back(members.size());
    groups.Tip.push_back(static_cast<std::int64_t>(tip));
    Eigen::Vector3d outward = Eigen::Vector3d::Zero();
    if (nearestNode[tip] >= 0 && gap[tip] > 0.0)
    {
      outward = (cloud.Positions.row(static_cast<Eigen::Index>(tip)) -
                  graph.NodePositions.row(nearestNode[tip])).transpose() / gap[tip];
    }
    groups.End.push_back(static_cast<std::int64_t>(FarEndCentre(cloud, gap, members, tip, outward)));
    groups.Linearity.push_back(Linearity(cloud.Positions, members));
  }
  return groups;
}

/// Depth of every point of group `group`: its shortest distance through the group's edges
/// (bridges not used) from a point of the group with a neighbour outside it (a covered point);
/// +inf for the points of other groups and for those the group's edges do not reach.
std::vector<double> DepthsInGroup(
  const CloudNeighborGraph& neighbours, const PointGroups& groups, std::int64_t group)
{
  const std::size_t n = groups.GroupOf.size();
  std::vector<std::int64_t> border;
  for (std::size_t p = 0; p < n; ++p)
  {
    if (groups.GroupOf[p] != group)
    {
      continue;
    }
    for (std::size_t e = neighbours.Offsets[p]; e < neighbours.Offsets[p + 1]; ++e)
    {
      if (!neighbours.IsBridge[e] && groups.GroupOf[static_cast<std::size_t>(neighbours.Targets[e])] < 0)
      {
        border.push_back(static_cast<std::int64_t>(p));
        break;
      }
    }
  }
  std::vector<double> depth(n, std::numeric_limits<double>::infinity());
  WalkThroughVolume(
    neighbours, border, [&](std::size_t q) { return groups.GroupOf[q] == group; },
    [](std::size_t) { return false; }, depth, nullptr);
  return depth;
}

/// The side limbs of group `group` (the header comment, step 4), in index order: the points
/// deepest first (ties: the lower index) each start a region or join their neighbours'; where
/// two regions meet, the one with the shallower far end ends there, and it is a limb of its
/// own when the meeting point lies within joinDepth of its far end's depth and at least
/// lengthFactor of the far end's radii below it, and the region holds minimumPoints points.
/// The region that is left at the end is a limb too. The limb whose region holds `reached`
/// (the end of the group's first branch) has its branch; the far ends of the others are
/// returned.
std::vector<std::int64_t> SideLimbEnds(const CloudNeighborGraph& neighbours, const ProjectedCloud& cloud,
  const PointGroups& groups, std::int64_t group, std::int64_t reached, double joinDepth, double lengthFactor,
  double minimumPoints)
{
  const std::vector<double> depth = DepthsInGroup(neighbours, groups, group);
  std::vector<std::size_t> order;
  for (std::size_t p = 0; p < depth.size(); ++p)
  {
    if (std::isfinite(depth[p]))
    {
      order.push_back(p);
    }
  }
  const auto deeper = [&](std::size_t a, std::size_t b) {
    return depth[a] > depth[b] || (depth[a] == depth[b] && a < b);
  };
  std::sort(order.begin(), order.end(), deeper);
  // Union-find over the regions; a root holds its region's far end, its size, and whether
  // `reached` is in it and not in a limb that ended inside it.
  std::vector<std::size_t> parent(depth.size()), farEnd(depth.size()), size(depth.size(), 0);
  std::vector<char> holdsReached(depth.size(), 0);
  const auto find = [&](std::size_t x) {
    while (parent[x] != x)
    {
      parent[x] = parent[parent[x]];
      x = parent[x];
    }
    return x;
  };
  std::vector<std::int64_t> ends;
  for (const std::size_t p : order)
  {
    parent[p] = p;
    farEnd[p] = p;
    size[p] = 1;
    holdsReached[p] = static_cast<std::int64_t>(p) == reached;
    for (std::size_t e = neighbours.Offsets[p]; e < neighbours.Offsets[p + 1]; ++e)
    {
      const auto q = static_cast<std::size_t>(neighbours.Targets[e]);
      if (neighbours.IsBridge[e] || size[q] == 0 || groups.GroupOf[q] != group)
      {
        continue; // not yet taken, or outside the group
      }
      const std::size_t a = find(p), b = find(q);
      if (a == b)
      {
        continue;
      }
      const bool aKeeps = deeper(farEnd[a], farEnd[b]);
      const std::size_t kept = aKeeps ? a : b, ended = aKeeps ? b : a;
      const std::size_t end = farEnd[ended];
      const bool limb = depth[p] <= joinDepth * depth[end] &&
        depth[end] - depth[p] >= lengthFactor * cloud.Radius[end] &&
        static_cast<double>(size[ended]) >= minimumPoints;
      if (limb && !holdsReached[ended])
      {
        ends.push_back(static_cast<std::int64_t>(end));
      }
      parent[ended] = kept;
      size[kept] += size[ended];
      holdsReached[kept] = holdsReached[kept] || (holdsReached[ended] && !limb);
    }
  }
  // The region left at the end (its far end the deepest point, which never ends) is a limb.
  if (!order.empty() && !holdsReached[find(order.front())])
  {
    ends.push_back(static_cast<std::int64_t>(farEnd[find(order.front())]));
  }
  std::sort(ends.begin(), ends.end());
  return ends;
}

} // namespace

std::size_t ReachUncoveredParts(SkeletonGraph& graph, const ProjectedCloud& cloud,
  const ThinnedCloud& thinned, const std::vector<std::int64_t>& pointComponent,
  const CloudNeighborGraph& neighbours, const SkeletonCoverageOptions& options,
  const ParallelFor& parallelFor, const RayCaster* volume)
{
  ValidateCoverageOptions(options);
  const std::size_t n = cloud.Size();
  if (!(options.UncoveredFactor > 0.0) || n == 0 || graph.NodePositions.rows() == 0)
  {
    return 0;
  }
  CheckNeighbourGraph(neighbours, n);

  // 1. Distance of every point to the skeleton of its component.
  std::vector<std::int64_t> nearestNode;
  std::vector<double> gap;
  NearestNodes(graph, cloud, pointComponent, parallelFor, nearestNode, gap);
  std::vector<char> uncovered(n, 0);
  for (std::size_t i = 0; i < n; ++i)
  {
    // A point without thickness (SDF 0) has no scale to be far at.
    uncovered[i] = nearestNode[i] >= 0 && cloud.Radius[i] > 0.0 && gap[i] > options.UncoveredFactor * cloud.Radius[i];
  }
  // Through the volume: a node behind the surface does not cover a point (a hind leg's points
  // near the nodes of a tail hanging against it).
  if (volume)
  {
    std::vector<std::size_t> tested;
    std::vector<Segment> toNodes;
    tested.reserve(n);
    toNodes.reserve(n);
    for (std::size_t i = 0; i < n; ++i)
    {
      if (!uncovered[i] && nearestNode[i] >= 0 && cloud.Radius[i] > 0.0)
      {
        tested.push_back(i);
        toNodes.push_back(Segment{ cloud.Positions.row(static_cast<Eigen::Index>(i)).transpose(),
          graph.NodePositions.row(nearestNode[i]).transpose() });
      }
    }
    const std::vector<char> crossing = SegmentsCrossSurface(*volume, toNodes, parallelFor);
    for (std::size_t t = 0; t < tested.size(); ++t)
    {
      uncovered[tested[t]] = crossing[t];
    }
  }

  if (std::none_of(uncovered.begin(), uncovered.end(), [](char u) { return u != 0; }))
  {
    return 0; // the common case
  }

  // 2. Groups of uncovered points: connected through neighbour edges between uncovered
  // points (the graph's edges stay within a surface component; bridges are not used).
  const PointGroups groups = GroupFlaggedPoints(neighbours, cloud, uncovered, gap, graph, nearestNode);

  // 3. One branch per large group, and per thin or small limb.
  std::size_t added = 0;
  for (std::size_t g = 0; g < groups.Size.size(); ++g)
  {
    const auto size = static_cast<double>(groups.Size[g]);
    const auto tip = static_cast<std::size_t>(groups.Tip[g]);
    const bool large = size >= options.MinimumShare * static_cast<double>(n);
    const bool farTip = options.ThinLimbFactor > 0.0 && gap[tip] >= options.ThinLimbFactor * cloud.Radius[tip];
    const bool thinLimb = farTip && size >= options.ThinLimbMinimumShare * static_cast<double>(n) &&
      groups.Linearity[g] >= options.ThinLimbLinearity;
    const bool smallLimb = farTip && options.SmallLimbMinimumShare > 0.0 &&
      size >= options.SmallLimbMinimumShare * static_cast<double>(n);
    if (!(large || thinLimb || smallLimb) ||
      !AddBranch(
        graph, cloud, thinned, PathToCovered(neighbours, uncovered, groups.End[g]), nearestNode, pointComponent))
    {
      continue;
    }
    ++added;
    if (large && options.SideLimbJoinDepth > 0.0)
    {
      const double minimumPoints = std::max(2.0, options.MinimumShare * static_cast<double>(n));
      for (const std::int64_t end : SideLimbEnds(neighbours, cloud, groups, static_cast<std::int64_t>(g),
             groups.End[g], options.SideLimbJoinDepth, options.UncoveredFactor, minimumPoints))
      {
        const std::vector<std::int64_t> path = PathToCovered(neighbours, uncovered, end);
        added += AddBranch(graph, cloud, thinned, path, nearestNode, pointComponent) ? 1 : 0;
      }
    }
  }
  if (added > 0)
  {
    AssignBranchBones(graph);
  }
  return added;
}

std::size_t ReachPartsWithoutBones(SkeletonGraph& graph, const ProjectedCloud& cloud,
  const ThinnedCloud& thinned, const std::vector<std::int64_t>& pointComponent,
  const CloudNeighborGraph& neighbours, const std::vector<char>& inPart,
  const SkeletonCoverageOptions& options, const ParallelFor& parallelFor)
{
  ValidateCoverageOptions(options);
  const std::size_t n = cloud.Size();
  if (!(options.PartUncoveredFactor > 0.0) || n == 0 || graph.NodePositions.rows() == 0)
  {
    return 0;
  }
  if (inPart.size() != n)
  {
    throw Error("skeleton: the part flags do not match the projected cloud");
  }
  CheckNeighbourGraph(neighbours, n);
  std::vector<std::int64_t> nearestNode;
  std::vector<double> gap;
  NearestNodes(graph, cloud, pointComponent, parallelFor, nearestNode, gap);
  // The part's points, grouped as step 5 groups uncovered points: the largest group's tip and
  // far end.
  const PointGroups groups = GroupFlaggedPoints(neighbours, cloud, inPart, gap, graph, nearestNode);
  if (groups.Size.empty())
  {
    return 0;
  }
  std::size_t best = 0; // the largest group, the first of equal ones
  for (std::size_t g = 1; g < groups.Size.size(); ++g)
  {
    if (groups.Size[g] > groups.Size[best])
    {
      best = g;
    }
  }
  // A part the skeleton runs through (its points within a radius or two of a bone it shares)
  // is not given a second, parallel branch.
  const auto tip = static_cast<std::size_t>(groups.Tip[best]);
  if (!(cloud.Radius[tip] > 0.0) || !(gap[tip] > options.PartUncoveredFactor * cloud.Radius[tip]) ||
    !AddBranch(graph, cloud, thinned, PathToCovered(neighbours, inPart, groups.End[best]), nearestNode, pointComponent))
  {
    return 0;
  }
  AssignBranchBones(graph);
  return 1;
}

} // namespace shapediameter
