// SPDX-License-Identifier: BSD-3-Clause
#include "Skeleton/SkeletonBones.h"

#include <algorithm>
#include <limits>
#include <map>
#include <numeric>
#include <set>
#include <utility>

namespace shapediameter
{

namespace
{

using Edge = std::pair<std::int64_t, std::int64_t>;

} // namespace

void CleanJunctions(std::vector<std::vector<std::int64_t>>& polylines,
  std::vector<int>& isConnection,
  const std::function<Eigen::Vector3d(std::int64_t)>& positionOf,
  const std::function<double(std::int64_t)>& radiusOf,
  const std::function<std::int64_t(std::int64_t)>& componentOf, double factor,
  LeafPruning leaves)
{
  if (!(factor > 0.0))
  {
    return;
  }
  std::map<std::int64_t, std::set<std::int64_t>> adjacency;
  for (const auto& polyline : polylines)
  {
    adjacency.try_emplace(polyline.front());
    for (std::size_t i = 1; i < polyline.size(); ++i)
    {
      if (polyline[i] != polyline[i - 1])
      {
        adjacency[polyline[i - 1]].insert(polyline[i]);
        adjacency[polyline[i]].insert(polyline[i - 1]);
      }
    }
  }
  std::set<std::int64_t> removed;
  std::map<std::int64_t, std::int64_t> mergedInto;
  /// Walks from `start` through `first` along degree-2 vertices; returns the vertices passed
  /// (start and the stop vertex excluded), the stop vertex and the length.
  const auto walk = [&](std::int64_t start, std::int64_t first, std::vector<std::int64_t>& inner,
                      double& length) {
    inner.clear();
    length = (positionOf(first) - positionOf(start)).norm();
    std::int64_t previous = start;
    std::int64_t current = first;
    while (adjacency[current].size() == 2 && current != start)
    {
      const std::set<std::int64_t>& around = adjacency[current];
      const std::int64_t next = *around.begin() == previous ? *around.rbegin() : *around.begin();
      inner.push_back(current);
      length += (positionOf(next) - positionOf(current)).norm();
      previous = current;
      current = next;
    }
    return current;
  };
  std::vector<std::int64_t> inner;
  bool changed = true;
  while (changed)
  {
    changed = false;
    std::vector<std::int64_t> leafVertices;
    for (const auto& [vertex, neighbours] : adjacency)
    {
      if (leaves == LeafPruning::Prune && neighbours.size() == 1)
      {
        leafVertices.push_back(vertex);
      }
    }
    for (const std::int64_t leaf : leafVertices)
    {
      if (adjacency[leaf].size() != 1)
      {
        continue;
      }
      double length = 0.0;
      const std::int64_t junction = walk(leaf, *adjacency[leaf].begin(), inner, length);
      if (adjacency[junction].size() < 3)
      {
        continue; // reached another leaf: the whole tree is a path, nothing to prune
      }
      bool prune = length < factor * radiusOf(junction);
      if (!prune)
      {
        const Eigen::Vector3d tip = positionOf(leaf);
        const std::int64_t component = componentOf(leaf);
        const std::set<std::int64_t> branch(inner.begin(), inner.end());
        for (const auto& [vertex, neighbours] : adjacency)
        {
          const double radius = radiusOf(vertex);
          if (vertex != leaf && !branch.count(vertex) && length < 2.0 * factor * radius &&
            (positionOf(vertex) - tip).norm() < factor * radius && componentOf(vertex) == component)
          {
            prune = true;
            break;
          }
        }
      }
      if (!prune)
      {
        continue;
      }
      adjacency[junction].erase(inner.empty() ? leaf : inner.back());
      inner.push_back(leaf);
      for (const std::int64_t vertex : inner)
      {
        adjacency.erase(vertex);
        removed.insert(vertex);
      }
      changed = true;
    }
    if (changed)
    {
      continue;
    }
    for (auto& [junction, neighbours] : adjacency)
    {
      if (neighbours.size() < 3)
      {
        continue;
      }
      for (const std::int64_t first : neighbours)
      {
        double length = 0.0;
        const std::int64_t other = walk(junction, first, inner, length);
        if (other == junction || adjacency[other].size() < 3 ||
          length >= factor * std::max(radiusOf(junction), radiusOf(other)))
        {
          continue;
        }
        const bool keepJunction = radiusOf(junction) > radiusOf(other) ||
          (radiusOf(junction) == radiusOf(other) && junction < other);
        const std::int64_t survivor = keepJunction ? junction : other;
        const std::int64_t merged = keepJunction ? other : junction;
        for (const std::int64_t vertex : inner)
        {
          adjacency.erase(vertex);
          removed.insert(vertex);
        }
        const std::set<std::int64_t> mergedNeighbors = adjacency[merged];
        adjacency.erase(merged);
        mergedInto[merged] = survivor;
        for (const std::int64_t neighbour : mergedNeighbors)
        {
          const auto found = adjacency.find(neighbour);
          if (found == adjacency.end())
          {
            continue; // an inner vertex, removed above
          }
          found->second.erase(merged);
          if (neighbour != survivor)
          {
            found->second.insert(survivor);
            adjacency[survivor].insert(neighbour);
          }
        }
        if (!inner.empty())
        {
          adjacency[survivor].erase(keepJunction ? inner.front() : inner.back());
        }
        changed = true;
        break;
      }
      if (changed)
      {
        break;
      }
    }
  }
  if (removed.empty() && mergedInto.empty())
  {
    return;
  }
  const auto representative = [&mergedInto](std::int64_t vertex) {
    for (auto found = mergedInto.find(vertex); found != mergedInto.end();
         found = mergedInto.find(vertex))
    {
      vertex = found->second;
    }
    return vertex;
  };
  // Removed vertices form a prefix or a suffix of each polyline, or all of it.
  std::vector<std::vector<std::int64_t>> kept;
  std::vector<int> keptIsConnection;
  for (std::size_t p = 0; p < polylines.size(); ++p)
  {
    std::vector<std::int64_t> remaining;
    for (const std::int64_t vertex : polylines[p])
    {
      if (removed.count(vertex))
      {
        continue;
      }
      const std::int64_t mapped = representative(vertex);
      if (remaining.empty() || remaining.back() != mapped)
      {
        remaining.push_back(mapped);
      }
    }
    if (remaining.size() >= 2 || (polylines[p].size() == 1 && remaining.size() == 1))
    {
      kept.push_back(std::move(remaining));
      keptIsConnection.push_back(isConnection[p]);
    }
  }
  polylines.swap(kept);
  isConnection.swap(keptIsConnection);
}

void CleanGraphJunctions(SkeletonGraph& graph, double factor, LeafPruning leaves)
{
  CleanJunctions(graph.Polylines, graph.IsConnection,
    [&graph](std::int64_t v) -> Eigen::Vector3d { return graph.NodePositions.row(v).transpose(); },
    [&graph](std::int64_t v) { return graph.NodeRadius[v]; },
    [&graph](std::int64_t v) { return graph.NodeComponent[v]; }, factor, leaves);
  const auto nodeCount = static_cast<std::size_t>(graph.NodePositions.rows());
  std::vector<char> used(nodeCount, 0);
  for (const auto& polyline : graph.Polylines)
  {
    for (const std::int64_t v : polyline)
    {
      used[v] = 1;
    }
  }
  std::vector<std::int64_t> newIndex(nodeCount, -1);
  SkeletonGraph kept;
  kept.NodePositions.resize(std::count(used.begin(), used.end(), char{ 1 }), 3);
  for (std::size_t v = 0; v < nodeCount; ++v)
  {
    if (!used[v])
    {
      continue;
    }
    const auto row = static_cast<std::int64_t>(kept.NodeRadius.size());
    newIndex[v] = row;
    kept.NodePositions.row(row) = graph.NodePositions.row(static_cast<Eigen::Index>(v));
    kept.NodeRadius.push_back(graph.NodeRadius[v]);
    kept.NodeConfidence.push_back(graph.NodeConfidence[v]);
    kept.NodeCloudIndex.push_back(graph.NodeCloudIndex[v]);
    kept.NodeComponent.push_back(graph.NodeComponent[v]);
  }
  for (auto& polyline : graph.Polylines)
  {
    for (std::int64_t& v : polyline)
    {
      v = newIndex[v];
    }
  }
  kept.Polylines = std::move(graph.Polylines);
  kept.IsConnection = std::move(graph.IsConnection);
  graph = std::move(kept);
  AssignBranchBones(graph);
}

void AssignBranchBones(SkeletonGraph& graph)
{
  const auto nodeCount = static_cast<std::size_t>(graph.NodePositions.rows());
  if (graph.IsConnection.size() != graph.Polylines.size())
  {
    throw SkeletonError("skeleton: IsConnection must have one entry per polyline");
  }
  std::vector<Edge> edges;
  std::vector<char> inPolyline(nodeCount, 0);
  for (const auto& polyline : graph.Polylines)
  {
    for (std::size_t i = 0; i < polyline.size(); ++i)
    {
      if (polyline[i] < 0 || static_cast<std::size_t>(polyline[i]) >= nodeCount)
      {
        throw SkeletonError("skeleton: polyline node index out of range");
      }
      inPolyline[polyline[i]] = 1;
      if (i > 0 && polyline[i - 1] != polyline[i])
      {
        edges.emplace_back(std::min(polyline[i - 1], polyline[i]), std::max(polyline[i - 1], polyline[i]));
      }
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  const auto edgeIndex = [&edges](std::int64_t a, std::int64_t b) {
    return static_cast<std::size_t>(
      std::lower_bound(edges.begin(), edges.end(), Edge(std::min(a, b), std::max(a, b))) -
      edges.begin());
  };
  std::vector<std::vector<std::int64_t>> adjacency(nodeCount);
  for (const auto& [a, b] : edges)
  {
    adjacency[a].push_back(b);
    adjacency[b].push_back(a);
  }
  for (auto& neighbours : adjacency)
  {
    std::sort(neighbours.begin(), neighbours.end());
  }

  // Walk the branches: from every end or junction (ascending) along each unwalked edge until
  // the next end or junction; then loops of degree-2 nodes from their lowest node.
  struct Branch
  {
    std::vector<std::int64_t> Nodes;
    double Length = 0.0;
  };
  std::vector<Branch> branches;
  std::vector<std::int64_t> edgeBranch(edges.size(), -1);
  const auto isBreak = [&adjacency](std::int64_t v) { return adjacency[v].size() != 2; };
  const auto walk = [&](std::int64_t start, std::int64_t first) {
    Branch branch;
    branch.Nodes.push_back(start);
    std::int64_t previous = start;
    std::int64_t current = first;
    const auto branchIndex = static_cast<std::int64_t>(branches.size());
    while (true)
    {
      edgeBranch[edgeIndex(previous, current)] = branchIndex;
      branch.Length += (graph.NodePositions.row(current) - graph.NodePositions.row(previous)).norm();
      branch.Nodes.push_back(current);
      if (current == start || isBreak(current))
      {
        break;
      }
      const std::vector<std::int64_t>& around = adjacency[current];
      const std::int64_t next = around[0] == previous ? around[1] : around[0];
      previous = current;
      current = next;
    }
    branches.push_back(std::move(branch));
  };
  for (std::size_t v = 0; v < nodeCount; ++v)
  {
    const auto node = static_cast<std::int64_t>(v);
    if (adjacency[v].empty())
    {
      Branch single;
      single.Nodes.push_back(node);
      branches.push_back(std::move(single));
      if (!inPolyline[v])
      {
        graph.Polylines.push_back({ node });
        graph.IsConnection.push_back(0);
      }
      continue;
    }
    if (!isBreak(node))
    {
      continue;
    }
    for (const std::int64_t neighbour : adjacency[v])
    {
      if (edgeBranch[edgeIndex(node, neighbour)] < 0)
      {
        walk(node, neighbour);
      }
    }
  }
  for (std::size_t v = 0; v < nodeCount; ++v)
  {
    const auto node = static_cast<std::int64_t>(v);
    if (!adjacency[v].empty() && edgeBranch[edgeIndex(node, adjacency[v][0])] < 0)
    {
      walk(node, adjacency[v][0]); // a loop: every node has degree 2
    }
  }

  // Number by decreasing length, then lowest node, then node sequence from the lower end.
  for (Branch& branch : branches)
  {
    if (branch.Nodes.back() < branch.Nodes.front())
    {
      std::reverse(branch.Nodes.begin(), branch.Nodes.end());
    }
  }
  std::vector<std::int64_t> lowestNode(branches.size());
  for (std::size_t b = 0; b < branches.size(); ++b)
  {
    lowestNode[b] = *std::min_element(branches[b].Nodes.begin(), branches[b].Nodes.end());
  }
  std::vector<std::size_t> order(branches.size());
  std::iota(order.begin(), order.end(), std::size_t{ 0 });
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (branches[a].Length != branches[b].Length)
    {
      return branches[a].Length > branches[b].Length;
    }
    if (lowestNode[a] != lowestNode[b])
    {
      return lowestNode[a] < lowestNode[b];
    }
    return branches[a].Nodes < branches[b].Nodes;
  });
  std::vector<std::int64_t> boneOfBranch(branches.size());
  graph.BoneLength.assign(branches.size(), 0.0);
  for (std::size_t rank = 0; rank < order.size(); ++rank)
  {
    boneOfBranch[order[rank]] = static_cast<std::int64_t>(rank);
    graph.BoneLength[rank] = branches[order[rank]].Length;
  }
  std::vector<std::int64_t> edgeBone(edges.size());
  for (std::size_t e = 0; e < edges.size(); ++e)
  {
    edgeBone[e] = boneOfBranch[edgeBranch[e]];
  }
  graph.NodeBone.assign(nodeCount, std::numeric_limits<std::int64_t>::max());
  for (std::size_t e = 0; e < edges.size(); ++e)
  {
    for (const std::int64_t v : { edges[e].first, edges[e].second })
    {
      graph.NodeBone[v] = std::min(graph.NodeBone[v], edgeBone[e]);
    }
  }
  for (std::size_t b = 0; b < branches.size(); ++b)
  {
    if (branches[b].Nodes.size() == 1)
    {
      graph.NodeBone[branches[b].Nodes.front()] = boneOfBranch[b];
    }
  }

  // Cut the polylines where they pass from one bone to the next.
  std::vector<std::vector<std::int64_t>> pieces;
  std::vector<int> pieceIsConnection;
  std::vector<std::int64_t> pieceBone;
  for (std::size_t p = 0; p < graph.Polylines.size(); ++p)
  {
    const std::vector<std::int64_t>& polyline = graph.Polylines[p];
    if (polyline.empty())
    {
      continue;
    }
    std::vector<std::int64_t> piece{ polyline.front() };
    std::int64_t bone = -1;
    for (std::size_t i = 1; i < polyline.size(); ++i)
    {
      if (polyline[i] != polyline[i - 1])
      {
        const std::int64_t edgeOwner = edgeBone[edgeIndex(polyline[i - 1], polyline[i])];
        if (bone >= 0 && edgeOwner != bone)
        {
          pieces.push_back(std::move(piece));
          pieceIsConnection.push_back(graph.IsConnection[p]);
          pieceBone.push_back(bone);
          piece = { polyline[i - 1] };
        }
        bone = edgeOwner;
      }
      piece.push_back(polyline[i]);
    }
    pieces.push_back(std::move(piece));
    pieceIsConnection.push_back(graph.IsConnection[p]);
    pieceBone.push_back(bone >= 0 ? bone : graph.NodeBone[polyline.front()]);
  }
  graph.Polylines = std::move(pieces);
  graph.IsConnection = std::move(pieceIsConnection);
  graph.PolylineBone = std::move(pieceBone);
}

} // namespace shapediameter
