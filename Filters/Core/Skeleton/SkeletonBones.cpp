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

/// The forest of CleanJunctions as an adjacency map, and what the cleaning removed and merged.
class JunctionCleaner
{
public:
  JunctionCleaner(const std::vector<std::vector<std::int64_t>>& polylines,
    const std::function<Eigen::Vector3d(std::int64_t)>& positionOf,
    const std::function<double(std::int64_t)>& radiusOf,
    const std::function<std::int64_t(std::int64_t)>& componentOf, double factor,
    LeafPruning leaves)
    : PositionOf(positionOf)
    , RadiusOf(radiusOf)
    , ComponentOf(componentOf)
    , Factor(factor)
    , Leaves(leaves)
  {
    for (const auto& polyline : polylines)
    {
      Adjacency.try_emplace(polyline.front());
      for (std::size_t i = 1; i < polyline.size(); ++i)
      {
        if (polyline[i] != polyline[i - 1])
        {
          Adjacency[polyline[i - 1]].insert(polyline[i]);
          Adjacency[polyline[i]].insert(polyline[i - 1]);
        }
      }
    }
  }

  /// Removes every leaf branch that is too short (unless leaves are kept); true if any was.
  bool PruneShortLeafBranches()
  {
    bool changed = false;
    std::vector<std::int64_t> leafVertices;
    for (const auto& [vertex, neighbours] : Adjacency)
    {
      if (Leaves == LeafPruning::Prune && neighbours.size() == 1)
      {
        leafVertices.push_back(vertex);
      }
    }
    for (const std::int64_t leaf : leafVertices)
    {
      if (Adjacency[leaf].size() != 1)
      {
        continue;
      }
      double length = 0.0;
      const std::int64_t junction = Walk(leaf, *Adjacency[leaf].begin(), length);
      if (Adjacency[junction].size() < 3)
      {
        continue; // reached another leaf: the whole tree is a path, nothing to prune
      }
      if (!IsShortLeafBranch(leaf, junction, length))
      {
        continue;
      }
      RemoveLeafBranch(leaf, junction);
      changed = true;
    }
    return changed;
  }

  /// Contracts the first inner branch (in junction order) that is too short into its junction
  /// of larger radius; true if there was one.
  bool ContractShortInnerBranch()
  {
    for (auto& [junction, neighbours] : Adjacency)
    {
      if (neighbours.size() < 3)
      {
        continue;
      }
      for (const std::int64_t first : neighbours)
      {
        double length = 0.0;
        const std::int64_t other = Walk(junction, first, length);
        if (other == junction || Adjacency[other].size() < 3 ||
          length >= Factor * std::max(RadiusOf(junction), RadiusOf(other)))
        {
          continue;
        }
        Contract(junction, other);
        return true;
      }
    }
    return false;
  }

  const std::set<std::int64_t>& Removed() const { return RemovedVertices; }
  const std::map<std::int64_t, std::int64_t>& MergedInto() const { return Merged; }

private:
  /// Walks from `start` through `first` along degree-2 vertices; leaves the vertices passed
  /// (start and the stop vertex excluded) in Inner, the length in `length`; returns the stop
  /// vertex.
  std::int64_t Walk(std::int64_t start, std::int64_t first, double& length)
  {
    Inner.clear();
    length = (PositionOf(first) - PositionOf(start)).norm();
    std::int64_t previous = start;
    std::int64_t current = first;
    while (Adjacency[current].size() == 2 && current != start)
    {
      const std::set<std::int64_t>& around = Adjacency[current];
      const std::int64_t next = *around.begin() == previous ? *around.rbegin() : *around.begin();
      Inner.push_back(current);
      length += (PositionOf(next) - PositionOf(current)).norm();
      previous = current;
      current = next;
    }
    return current;
  }

  /// The leaf branch just walked (Inner) is shorter than factor * radius at its junction, or a
  /// stub inside another vertex's medial ball.
  bool IsShortLeafBranch(std::int64_t leaf, std::int64_t junction, double length)
  {
    if (length < Factor * RadiusOf(junction))
    {
      return true;
    }
    const Eigen::Vector3d tip = PositionOf(leaf);
    const std::int64_t component = ComponentOf(leaf);
    const std::set<std::int64_t> branch(Inner.begin(), Inner.end());
    for (const auto& [vertex, neighbours] : Adjacency)
    {
      const double radius = RadiusOf(vertex);
      if (vertex != leaf && !branch.count(vertex) && length < 2.0 * Factor * radius &&
        (PositionOf(vertex) - tip).norm() < Factor * radius && ComponentOf(vertex) == component)
      {
        return true;
      }
    }
    return false;
  }

  /// Removes the leaf branch just walked (Inner), leaf included.
  void RemoveLeafBranch(std::int64_t leaf, std::int64_t junction)
  {
    Adjacency[junction].erase(Inner.empty() ? leaf : Inner.back());
    Inner.push_back(leaf);
    for (const std::int64_t vertex : Inner)
    {
      Adjacency.erase(vertex);
      RemovedVertices.insert(vertex);
    }
  }

  /// Contracts the inner branch just walked (Inner) from `junction` to `other` into the one of
  /// larger radius (ties: lower id). By value: the contraction may erase the map entry whose
  /// key the caller passes.
  void Contract(std::int64_t junction, std::int64_t other)
  {
    const bool keepJunction = RadiusOf(junction) > RadiusOf(other) ||
      (RadiusOf(junction) == RadiusOf(other) && junction < other);
    const std::int64_t survivor = keepJunction ? junction : other;
    const std::int64_t merged = keepJunction ? other : junction;
    for (const std::int64_t vertex : Inner)
    {
      Adjacency.erase(vertex);
      RemovedVertices.insert(vertex);
    }
    const std::set<std::int64_t> mergedNeighbors = Adjacency[merged];
    Adjacency.erase(merged);
    Merged[merged] = survivor;
    for (const std::int64_t neighbour : mergedNeighbors)
    {
      const auto found = Adjacency.find(neighbour);
      if (found == Adjacency.end())
      {
        continue; // an inner vertex, removed above
      }
      found->second.erase(merged);
      if (neighbour != survivor)
      {
        found->second.insert(survivor);
        Adjacency[survivor].insert(neighbour);
      }
    }
    if (!Inner.empty())
    {
      Adjacency[survivor].erase(keepJunction ? Inner.front() : Inner.back());
    }
  }

  const std::function<Eigen::Vector3d(std::int64_t)>& PositionOf;
  const std::function<double(std::int64_t)>& RadiusOf;
  const std::function<std::int64_t(std::int64_t)>& ComponentOf;
  const double Factor;
  const LeafPruning Leaves;
  std::map<std::int64_t, std::set<std::int64_t>> Adjacency;
  std::set<std::int64_t> RemovedVertices;
  std::map<std::int64_t, std::int64_t> Merged;
  /// The vertices passed by the last Walk.
  std::vector<std::int64_t> Inner;
};

/// Drops the removed vertices from the polylines and maps the merged ones to their survivors;
/// drops the polylines left with fewer than two vertices (single-vertex input polylines stay).
void RewritePolylines(std::vector<std::vector<std::int64_t>>& polylines,
  std::vector<int>& isConnection, const std::set<std::int64_t>& removed,
  const std::map<std::int64_t, std::int64_t>& mergedInto)
{
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

/// The skeleton graph as AssignBranchBones walks it: the union of the polylines' edges,
/// sorted and unique, and each node's neighbours in ascending order.
struct EdgeGraph
{
  std::vector<Edge> Edges;
  std::vector<std::vector<std::int64_t>> Adjacency;
  /// Nodes in some polyline.
  std::vector<char> InPolyline;

  std::size_t EdgeIndex(std::int64_t a, std::int64_t b) const
  {
    return static_cast<std::size_t>(
      std::lower_bound(Edges.begin(), Edges.end(), Edge(std::min(a, b), std::max(a, b))) -
      Edges.begin());
  }
  /// An end or a junction: where a branch stops.
  bool IsBreak(std::int64_t v) const { return Adjacency[v].size() != 2; }
};

/// Throws Error on a polyline node index out of range.
EdgeGraph CollectEdges(const SkeletonGraph& graph)
{
  const auto nodeCount = static_cast<std::size_t>(graph.NodePositions.rows());
  EdgeGraph edgeGraph;
  std::vector<Edge>& edges = edgeGraph.Edges;
  edgeGraph.InPolyline.assign(nodeCount, 0);
  for (const auto& polyline : graph.Polylines)
  {
    for (std::size_t i = 0; i < polyline.size(); ++i)
    {
      if (polyline[i] < 0 || static_cast<std::size_t>(polyline[i]) >= nodeCount)
      {
        throw Error("skeleton: polyline node index out of range");
      }
      edgeGraph.InPolyline[polyline[i]] = 1;
      if (i > 0 && polyline[i - 1] != polyline[i])
      {
        edges.emplace_back(std::min(polyline[i - 1], polyline[i]), std::max(polyline[i - 1], polyline[i]));
      }
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  edgeGraph.Adjacency.resize(nodeCount);
  for (const auto& [a, b] : edges)
  {
    edgeGraph.Adjacency[a].push_back(b);
    edgeGraph.Adjacency[b].push_back(a);
  }
  for (auto& neighbours : edgeGraph.Adjacency)
  {
    std::sort(neighbours.begin(), neighbours.end());
  }
  return edgeGraph;
}

struct Branch
{
  std::vector<std::int64_t> Nodes;
  double Length = 0.0;
};

/// The branches, and the branch of every edge.
struct Branches
{
  std::vector<Branch> List;
  std::vector<std::int64_t> OfEdge;
};

/// Walks the branches: from every end or junction (ascending) along each unwalked edge until
/// the next end or junction, a node of degree 0 being a branch by itself; then loops of
/// degree-2 nodes from their lowest node.
Branches WalkBranches(const EdgeGraph& edgeGraph, const PointMatrix& positions)
{
  const auto nodeCount = edgeGraph.Adjacency.size();
  Branches branches;
  branches.OfEdge.assign(edgeGraph.Edges.size(), -1);
  const auto walk = [&](std::int64_t start, std::int64_t first) {
    Branch branch;
    branch.Nodes.push_back(start);
    std::int64_t previous = start;
    std::int64_t current = first;
    const auto branchIndex = static_cast<std::int64_t>(branches.List.size());
    while (true)
    {
      branches.OfEdge[edgeGraph.EdgeIndex(previous, current)] = branchIndex;
      branch.Length += (positions.row(current) - positions.row(previous)).norm();
      branch.Nodes.push_back(current);
      if (current == start || edgeGraph.IsBreak(current))
      {
        break;
      }
      const std::vector<std::int64_t>& around = edgeGraph.Adjacency[current];
      const std::int64_t next = around[0] == previous ? around[1] : around[0];
      previous = current;
      current = next;
    }
    branches.List.push_back(std::move(branch));
  };
  for (std::size_t v = 0; v < nodeCount; ++v)
  {
    const auto node = static_cast<std::int64_t>(v);
    if (edgeGraph.Adjacency[v].empty())
    {
      Branch single;
      single.Nodes.push_back(node);
      branches.List.push_back(std::move(single));
      continue;
    }
    if (!edgeGraph.IsBreak(node))
    {
      continue;
    }
    for (const std::int64_t neighbour : edgeGraph.Adjacency[v])
    {
      if (branches.OfEdge[edgeGraph.EdgeIndex(node, neighbour)] < 0)
      {
        walk(node, neighbour);
      }
    }
  }
  for (std::size_t v = 0; v < nodeCount; ++v)
  {
    const auto node = static_cast<std::int64_t>(v);
    const std::vector<std::int64_t>& around = edgeGraph.Adjacency[v];
    if (!around.empty() && branches.OfEdge[edgeGraph.EdgeIndex(node, around[0])] < 0)
    {
      walk(node, around[0]); // a loop: every node has degree 2
    }
  }
  return branches;
}

/// A node of degree 0 in no polyline gets a single-node polyline.
void AddIsolatedNodePolylines(SkeletonGraph& graph, const EdgeGraph& edgeGraph)
{
  for (std::size_t v = 0; v < edgeGraph.Adjacency.size(); ++v)
  {
    if (edgeGraph.Adjacency[v].empty() && !edgeGraph.InPolyline[v])
    {
      graph.Polylines.push_back({ static_cast<std::int64_t>(v) });
      graph.IsConnection.push_back(0);
    }
  }
}

/// Numbers the branches by decreasing length, then lowest node, then node sequence from the
/// lower end (each branch is oriented so); returns the bone of each branch and fills
/// boneLength.
std::vector<std::int64_t> NumberBones(std::vector<Branch>& branches, std::vector<double>& boneLength)
{
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
  boneLength.assign(branches.size(), 0.0);
  for (std::size_t rank = 0; rank < order.size(); ++rank)
  {
    boneOfBranch[order[rank]] = static_cast<std::int64_t>(rank);
    boneLength[rank] = branches[order[rank]].Length;
  }
  return boneOfBranch;
}

/// The bone of every node: the lowest bone among its edges, or its single-node branch's.
std::vector<std::int64_t> NodeBones(const EdgeGraph& edgeGraph,
  const std::vector<std::int64_t>& edgeBone, const std::vector<Branch>& branches,
  const std::vector<std::int64_t>& boneOfBranch)
{
  std::vector<std::int64_t> nodeBone(
    edgeGraph.Adjacency.size(), std::numeric_limits<std::int64_t>::max());
  for (std::size_t e = 0; e < edgeGraph.Edges.size(); ++e)
  {
    for (const std::int64_t v : { edgeGraph.Edges[e].first, edgeGraph.Edges[e].second })
    {
      nodeBone[v] = std::min(nodeBone[v], edgeBone[e]);
    }
  }
  for (std::size_t b = 0; b < branches.size(); ++b)
  {
    if (branches[b].Nodes.size() == 1)
    {
      nodeBone[branches[b].Nodes.front()] = boneOfBranch[b];
    }
  }
  return nodeBone;
}

/// Cuts the polylines where they pass from one bone to the next; empty ones are dropped.
void CutPolylinesAtBones(
  SkeletonGraph& graph, const EdgeGraph& edgeGraph, const std::vector<std::int64_t>& edgeBone)
{
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
        const std::int64_t edgeOwner = edgeBone[edgeGraph.EdgeIndex(polyline[i - 1], polyline[i])];
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
  JunctionCleaner cleaner(polylines, positionOf, radiusOf, componentOf, factor, leaves);
  // Leaves first, until none is left to prune; then one inner branch at a time, since a
  // contraction changes the branches around it.
  while (cleaner.PruneShortLeafBranches() || cleaner.ContractShortInnerBranch())
  {
  }
  RewritePolylines(polylines, isConnection, cleaner.Removed(), cleaner.MergedInto());
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
  if (graph.IsConnection.size() != graph.Polylines.size())
  {
    throw Error("skeleton: IsConnection must have one entry per polyline");
  }
  const EdgeGraph edgeGraph = CollectEdges(graph);
  Branches branches = WalkBranches(edgeGraph, graph.NodePositions);
  AddIsolatedNodePolylines(graph, edgeGraph);
  const std::vector<std::int64_t> boneOfBranch = NumberBones(branches.List, graph.BoneLength);
  std::vector<std::int64_t> edgeBone(edgeGraph.Edges.size());
  for (std::size_t e = 0; e < edgeGraph.Edges.size(); ++e)
  {
    edgeBone[e] = boneOfBranch[branches.OfEdge[e]];
  }
  graph.NodeBone = NodeBones(edgeGraph, edgeBone, branches.List, boneOfBranch);
  CutPolylinesAtBones(graph, edgeGraph, edgeBone);
}

} // namespace shapediameter
