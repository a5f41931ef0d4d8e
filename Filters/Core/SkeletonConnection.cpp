// SPDX-License-Identifier: BSD-3-Clause
#include "SkeletonConnection.h"

#include "SkeletonPointTree.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <queue>
#include <tuple>

namespace shapediameter
{

void ValidateConnectionOptions(const SkeletonConnectionOptions& options)
{
  if (options.NumberOfNeighbors < 1 || options.NumberOfNeighbors > 64)
  {
    throw SkeletonError("skeleton: NumberOfNeighbors must be in [1, 64]");
  }
  if (!(options.SeedRadiusFactor >= 0.0 && options.SeedRadiusFactor <= 10.0))
  {
    throw SkeletonError("skeleton: SeedRadiusFactor must be in [0, 10]");
  }
  if (!(options.SpacingFactor >= 0.0 && options.SpacingFactor <= 10.0))
  {
    throw SkeletonError("skeleton: connection SpacingFactor must be in [0, 10]");
  }
  if (!(options.MinimumBranchFactor >= 0.0 && options.MinimumBranchFactor <= 10.0))
  {
    throw SkeletonError("skeleton: MinimumBranchFactor must be in [0, 10]");
  }
}

namespace
{

class UnionFind
{
public:
  explicit UnionFind(std::size_t size)
    : Parent(size)
  {
    std::iota(Parent.begin(), Parent.end(), std::int64_t{ 0 });
  }
  std::int64_t Find(std::int64_t i)
  {
    while (Parent[i] != i)
    {
      Parent[i] = Parent[Parent[i]];
      i = Parent[i];
    }
    return i;
  }
  /// Returns false if a and b were already in one set. The lower root survives.
  bool Unite(std::int64_t a, std::int64_t b)
  {
    a = Find(a);
    b = Find(b);
    if (a == b)
    {
      return false;
    }
    Parent[std::max(a, b)] = std::min(a, b);
    return true;
  }

private:
  std::vector<std::int64_t> Parent;
};

using Edge = std::pair<std::int64_t, std::int64_t>;

/// Adjacency in compressed rows; edges are undirected and stored both ways.
struct NeighborGraph
{
  std::vector<std::size_t> Offsets;
  std::vector<std::int64_t> Targets;
  std::vector<double> Weights;
};

NeighborGraph MakeGraph(const PointMatrix& positions, std::vector<Edge> edges)
{
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  NeighborGraph graph;
  const auto count = static_cast<std::size_t>(positions.rows());
  std::vector<std::size_t> degree(count, 0);
  for (const auto& [a, b] : edges)
  {
    ++degree[a];
    ++degree[b];
  }
  graph.Offsets.assign(count + 1, 0);
  for (std::size_t i = 0; i < count; ++i)
  {
    graph.Offsets[i + 1] = graph.Offsets[i] + degree[i];
  }
  graph.Targets.resize(graph.Offsets[count]);
  graph.Weights.resize(graph.Offsets[count]);
  std::vector<std::size_t> fill(graph.Offsets.begin(), graph.Offsets.end() - 1);
  for (const auto& [a, b] : edges)
  {
    const double weight = (positions.row(a) - positions.row(b)).norm();
    graph.Targets[fill[a]] = b;
    graph.Weights[fill[a]++] = weight;
    graph.Targets[fill[b]] = a;
    graph.Weights[fill[b]++] = weight;
  }
  return graph;
}

/// Links the pieces of the neighbour graph that belong to one surface component by their
/// shortest gaps: every piece but the largest of its component adds its shortest edge to
/// another piece of the same component, until each component is one piece.
void BridgeGraphPieces(const SkeletonPointTree& tree, const PointMatrix& positions,
  const std::vector<std::int64_t>& component, std::vector<Edge>& edges)
{
  const auto count = static_cast<std::size_t>(positions.rows());
  UnionFind pieces(count);
  for (const auto& [a, b] : edges)
  {
    pieces.Unite(a, b);
  }
  while (true)
  {
    std::vector<std::int64_t> piece(count);
    std::map<std::int64_t, std::vector<std::int64_t>> membersOfPiece;
    for (std::size_t i = 0; i < count; ++i)
    {
      piece[i] = pieces.Find(static_cast<std::int64_t>(i));
      membersOfPiece[piece[i]].push_back(static_cast<std::int64_t>(i));
    }
    // Largest piece of every component (ties: lowest root) does not search.
    std::map<std::int64_t, std::int64_t> largestPiece;
    std::map<std::int64_t, std::size_t> piecesOfComponent;
    for (const auto& [root, members] : membersOfPiece)
    {
      const std::int64_t c = component[root];
      ++piecesOfComponent[c];
      const auto found = largestPiece.find(c);
      if (found == largestPiece.end() || membersOfPiece[found->second].size() < members.size())
      {
        largestPiece[c] = root;
      }
    }
    if (std::all_of(piecesOfComponent.begin(), piecesOfComponent.end(),
          [](const auto& entry) { return entry.second < 2; }))
    {
      return;
    }
    const std::vector<std::int64_t> nodeLabels = tree.NodeLabels(piece);
    std::vector<Edge> added;
    for (const auto& [root, members] : membersOfPiece)
    {
      const std::int64_t c = component[root];
      if (piecesOfComponent[c] < 2 || largestPiece[c] == root)
      {
        continue;
      }
      std::tuple<double, std::int64_t, std::int64_t> best(
        std::numeric_limits<double>::infinity(), -1, -1);
      for (const std::int64_t i : members)
      {
        // Subtrees of the own piece are pruned whole, so a query costs O(log n) plus the
        // boundary of the piece, not its size.
        const std::int64_t q = tree.NearestAccepted(positions.row(i).transpose(),
          [&](std::int64_t j) { return component[j] == c && piece[j] != root; }, &nodeLabels,
          root);
        if (q >= 0)
        {
          const double squaredDistance = (positions.row(i) - positions.row(q)).squaredNorm();
          best = std::min(best, std::make_tuple(squaredDistance, std::min(i, q), std::max(i, q)));
        }
      }
      if (std::get<1>(best) >= 0)
      {
        added.emplace_back(std::get<1>(best), std::get<2>(best));
      }
    }
    if (added.empty())
    {
      return;
    }
    for (const auto& [a, b] : added)
    {
      pieces.Unite(a, b);
      edges.emplace_back(a, b);
    }
  }
}

} // namespace

SkeletonGraph ConnectPolySegments(const ProjectedCloud& cloud, const ThinnedCloud& thinned,
  const std::vector<PolySegment>& segments, const std::vector<std::int64_t>& pointComponent,
  const SkeletonConnectionOptions& options, const ParallelFor& parallelFor,
  const ProgressCallback& progress, bool& aborted, const RayCaster* volume)
{
  ValidateConnectionOptions(options);
  aborted = false;
  SkeletonGraph graph;
  const std::size_t count = cloud.Size();
  if (count == 0)
  {
    return graph;
  }
  const std::vector<std::int64_t> component =
    pointComponent.empty() ? std::vector<std::int64_t>(count, 0) : pointComponent;
  const PointMatrix& positions = cloud.Positions;
  const SkeletonPointTree tree(positions);
  const auto report = [&](double fraction) {
    if (progress && !progress(fraction))
    {
      aborted = true;
    }
    return !aborted;
  };

  // 1. k-nearest-neighbour graph on P, restricted to surface components.
  const auto k = static_cast<std::size_t>(options.NumberOfNeighbors);
  std::vector<std::int64_t> nearest(count * k, -1);
  parallelFor(count, [&](std::size_t begin, std::size_t end) {
    std::vector<std::int64_t> indices;
    std::vector<double> squaredDistances;
    for (std::size_t i = begin; i < end; ++i)
    {
      tree.NearestNeighbors(positions.row(static_cast<Eigen::Index>(i)).transpose(), k + 1,
        indices, squaredDistances);
      std::size_t slot = 0;
      for (const std::int64_t j : indices)
      {
        if (slot < k && j != static_cast<std::int64_t>(i) && component[j] == component[i])
        {
          nearest[i * k + slot++] = j;
        }
      }
    }
  });
  std::vector<Edge> edges;
  edges.reserve(count * k);
  for (std::size_t i = 0; i < count; ++i)
  {
    for (std::size_t slot = 0; slot < k; ++slot)
    {
      const std::int64_t j = nearest[i * k + slot];
      if (j >= 0)
      {
        edges.emplace_back(std::min<std::int64_t>(static_cast<std::int64_t>(i), j),
          std::max<std::int64_t>(static_cast<std::int64_t>(i), j));
      }
    }
  }
  if (volume)
  {
    // Each edge once (most are in both end points' lists), tested in parallel.
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    std::vector<char> crossing(edges.size(), 0);
    parallelFor(edges.size(), [&](std::size_t begin, std::size_t end) {
      for (std::size_t e = begin; e < end; ++e)
      {
        crossing[e] = SegmentCrossesSurface(*volume, positions.row(edges[e].first).transpose(),
          positions.row(edges[e].second).transpose());
      }
    });
    std::size_t kept = 0;
    for (std::size_t e = 0; e < edges.size(); ++e)
    {
      if (!crossing[e])
      {
        edges[kept++] = edges[e];
      }
    }
    edges.resize(kept);
  }
  if (!report(0.3))
  {
    return {};
  }
  BridgeGraphPieces(tree, positions, component, edges);
  const NeighborGraph neighbours = MakeGraph(positions, std::move(edges));
  if (!report(0.5))
  {
    return {};
  }

  // 2. Seeds: every segment node claims nearby points of P with their distance to it.
  std::vector<std::size_t> segmentOffset(segments.size() + 1, 0);
  for (std::size_t s = 0; s < segments.size(); ++s)
  {
    segmentOffset[s + 1] = segmentOffset[s] + segments[s].size();
  }
  const std::size_t segmentNodes = segmentOffset.back();
  std::vector<std::int64_t> nodeSegment(segmentNodes);
  const double infinity = std::numeric_limits<double>::infinity();
  std::vector<double> distance(count, infinity);
  std::vector<std::int64_t> owner(count, -1);
  std::vector<std::int64_t> parent(count, -1);
  std::vector<std::int64_t> rootNode(count, -1);
  std::vector<std::int64_t> nearby;
  for (std::size_t s = 0; s < segments.size(); ++s)
  {
    for (std::size_t m = 0; m < segments[s].size(); ++m)
    {
      const std::int64_t cloudIndex = segments[s][m];
      const auto node = static_cast<std::int64_t>(segmentOffset[s] + m);
      nodeSegment[node] = static_cast<std::int64_t>(s);
      const std::int64_t c = component[cloudIndex];
      const Eigen::Vector3d x = thinned.Positions.row(cloudIndex).transpose();
      tree.RadiusSearch(x, options.SeedRadiusFactor * cloud.Radius[cloudIndex], nearby);
      nearby.push_back(tree.NearestAccepted(x, [&](std::int64_t j) { return component[j] == c; }));
      for (const std::int64_t j : nearby)
      {
        if (j < 0 || component[j] != c)
        {
          continue;
        }
        const double d = (positions.row(j).transpose() - x).norm();
        if (std::make_tuple(d, node) < std::make_tuple(distance[j], rootNode[j]) ||
          rootNode[j] < 0)
        {
          distance[j] = d;
          owner[j] = static_cast<std::int64_t>(s);
          rootNode[j] = node;
        }
      }
    }
  }

  // Dijkstra from all seeds at once; the queue orders by (distance, index).
  using QueueEntry = std::pair<double, std::int64_t>;
  std::priority_queue<QueueEntry, std::vector<QueueEntry>, std::greater<QueueEntry>> queue;
  for (std::size_t j = 0; j < count; ++j)
  {
    if (owner[j] >= 0)
    {
      queue.emplace(distance[j], static_cast<std::int64_t>(j));
    }
  }
  std::vector<char> settled(count, 0);
  while (!queue.empty())
  {
    const auto [d, j] = queue.top();
    queue.pop();
    if (settled[j] || d > distance[j])
    {
      continue;
    }
    settled[j] = 1;
    for (std::size_t e = neighbours.Offsets[j]; e < neighbours.Offsets[j + 1]; ++e)
    {
      const std::int64_t target = neighbours.Targets[e];
      const double candidate = d + neighbours.Weights[e];
      if (!settled[target] && candidate < distance[target])
      {
        distance[target] = candidate;
        owner[target] = owner[j];
        parent[target] = j;
        rootNode[target] = rootNode[j];
        queue.emplace(candidate, target);
      }
    }
  }
  if (!report(0.8))
  {
    return {};
  }

  // 3. Joins where two growths meet, cheapest first, no cycles.
  std::vector<std::tuple<double, std::int64_t, std::int64_t>> joins;
  for (std::size_t a = 0; a < count; ++a)
  {
    for (std::size_t e = neighbours.Offsets[a]; e < neighbours.Offsets[a + 1]; ++e)
    {
      const std::int64_t b = neighbours.Targets[e];
      if (static_cast<std::int64_t>(a) < b && owner[a] >= 0 && owner[b] >= 0 &&
        owner[a] != owner[b])
      {
        joins.emplace_back(distance[a] + neighbours.Weights[e] + distance[b],
          static_cast<std::int64_t>(a), b);
      }
    }
  }
  std::sort(joins.begin(), joins.end());
  UnionFind linked(segments.size());

  // 4. Merged connecting paths. Vertex ids: segment nodes [0, segmentNodes), point j of P is
  // segmentNodes + j.
  const auto pathVertex = [segmentNodes](std::int64_t j) {
    return static_cast<std::int64_t>(segmentNodes) + j;
  };
  std::vector<Edge> pathEdges;
  const auto addEdge = [&pathEdges](std::int64_t a, std::int64_t b) {
    pathEdges.emplace_back(std::min(a, b), std::max(a, b));
  };
  const auto addPathToRoot = [&](std::int64_t j) {
    while (parent[j] >= 0)
    {
      addEdge(pathVertex(j), pathVertex(parent[j]));
      j = parent[j];
    }
    addEdge(pathVertex(j), rootNode[j]);
  };
  for (const auto& [cost, a, b] : joins)
  {
    if (linked.Unite(owner[a], owner[b]))
    {
      addPathToRoot(a);
      addPathToRoot(b);
      addEdge(pathVertex(a), pathVertex(b));
    }
  }
  std::sort(pathEdges.begin(), pathEdges.end());
  pathEdges.erase(std::unique(pathEdges.begin(), pathEdges.end()), pathEdges.end());

  // Adjacency of the merged paths.
  std::map<std::int64_t, std::vector<std::int64_t>> pathAdjacency;
  for (const auto& [a, b] : pathEdges)
  {
    pathAdjacency[a].push_back(b);
    pathAdjacency[b].push_back(a);
  }
  for (auto& entry : pathAdjacency)
  {
    std::sort(entry.second.begin(), entry.second.end());
  }
  const auto isSegmentVertex = [segmentNodes](std::int64_t v) {
    return v < static_cast<std::int64_t>(segmentNodes);
  };
  const auto isBreak = [&](std::int64_t v) {
    return isSegmentVertex(v) || pathAdjacency[v].size() != 2;
  };
  const auto cloudIndexOf = [&](std::int64_t v) {
    return isSegmentVertex(v) ? segments[nodeSegment[v]][v - segmentOffset[nodeSegment[v]]]
                              : v - static_cast<std::int64_t>(segmentNodes);
  };
  const auto vertexPosition = [&](std::int64_t v) -> Eigen::Vector3d {
    return isSegmentVertex(v) ? Eigen::Vector3d(thinned.Positions.row(cloudIndexOf(v)).transpose())
                              : Eigen::Vector3d(positions.row(cloudIndexOf(v)).transpose());
  };

  // Chains between break vertices, thinned to the node spacing.
  std::vector<std::vector<std::int64_t>> chains;
  std::map<Edge, bool> walked;
  for (const auto& [start, adjacent] : pathAdjacency)
  {
    if (!isBreak(start))
    {
      continue;
    }
    for (const std::int64_t first : adjacent)
    {
      if (walked[{ std::min(start, first), std::max(start, first) }])
      {
        continue;
      }
      std::vector<std::int64_t> chain{ start };
      std::int64_t previous = start;
      std::int64_t current = first;
      walked[{ std::min(start, first), std::max(start, first) }] = true;
      while (!isBreak(current))
      {
        const std::vector<std::int64_t>& around = pathAdjacency[current];
        const std::int64_t next = around[0] == previous ? around[1] : around[0];
        walked[{ std::min(current, next), std::max(current, next) }] = true;
        chain.push_back(current);
        previous = current;
        current = next;
      }
      chain.push_back(current);
      // Keep the ends; keep an interior point once it is epsilon from the last kept one and
      // not crowding the far end.
      std::vector<std::int64_t> kept{ chain.front() };
      const Eigen::Vector3d last = vertexPosition(chain.back());
      for (std::size_t i = 1; i + 1 < chain.size(); ++i)
      {
        const Eigen::Vector3d x = vertexPosition(chain[i]);
        const double epsilon = options.SpacingFactor * cloud.Radius[cloudIndexOf(chain[i])];
        if ((x - vertexPosition(kept.back())).norm() >= epsilon &&
          (x - last).norm() >= 0.5 * epsilon)
        {
          kept.push_back(chain[i]);
        }
      }
      kept.push_back(chain.back());
      chains.push_back(std::move(kept));
    }
  }

  // Assemble nodes and polylines.
  std::map<std::int64_t, std::int64_t> nodeOfVertex;
  const auto nodeOf = [&](std::int64_t v) {
    const auto found = nodeOfVertex.find(v);
    if (found != nodeOfVertex.end())
    {
      return found->second;
    }
    const auto node = static_cast<std::int64_t>(graph.NodeRadius.size());
    const std::int64_t cloudIndex = cloudIndexOf(v);
    nodeOfVertex[v] = node;
    graph.NodeCloudIndex.push_back(cloudIndex);
    graph.NodeRadius.push_back(cloud.Radius[cloudIndex]);
    graph.NodeConfidence.push_back(thinned.Confidence[cloudIndex]);
    graph.NodeComponent.push_back(component[cloudIndex]);
    return node;
  };
  std::vector<Eigen::Vector3d> nodePositions;
  const auto appendPolyline = [&](const std::vector<std::int64_t>& vertices, int isConnection) {
    std::vector<std::int64_t> polyline;
    for (const std::int64_t v : vertices)
    {
      const std::size_t before = graph.NodeRadius.size();
      polyline.push_back(nodeOf(v));
      if (graph.NodeRadius.size() > before)
      {
        nodePositions.push_back(vertexPosition(v));
      }
    }
    graph.Polylines.push_back(std::move(polyline));
    graph.IsConnection.push_back(isConnection);
  };
  std::vector<std::vector<std::int64_t>> polylines;
  std::vector<int> isConnection;
  for (std::size_t s = 0; s < segments.size(); ++s)
  {
    std::vector<std::int64_t> vertices(segments[s].size());
    std::iota(vertices.begin(), vertices.end(), static_cast<std::int64_t>(segmentOffset[s]));
    polylines.push_back(std::move(vertices));
    isConnection.push_back(0);
  }
  for (auto& chain : chains)
  {
    polylines.push_back(std::move(chain));
    isConnection.push_back(1);
  }
  CleanJunctions(polylines, isConnection, vertexPosition,
    [&](std::int64_t v) { return cloud.Radius[cloudIndexOf(v)]; },
    [&](std::int64_t v) { return component[cloudIndexOf(v)]; }, options.MinimumBranchFactor);
  for (std::size_t p = 0; p < polylines.size(); ++p)
  {
    appendPolyline(polylines[p], isConnection[p]);
  }

  // Components of P without any segment: one node at the point nearest to their mean.
  std::map<std::int64_t, std::pair<Eigen::Vector3d, double>> sums;
  for (std::size_t j = 0; j < count; ++j)
  {
    auto& entry = sums.try_emplace(component[j], Eigen::Vector3d::Zero(), 0.0).first->second;
    entry.first += positions.row(static_cast<Eigen::Index>(j)).transpose();
    entry.second += 1.0;
  }
  std::map<std::int64_t, bool> hasSegment;
  for (const auto& segment : segments)
  {
    hasSegment[component[segment.front()]] = true;
  }
  for (const auto& [c, entry] : sums)
  {
    if (hasSegment[c])
    {
      continue;
    }
    const Eigen::Vector3d mean = entry.first / entry.second;
    const std::int64_t medoid =
      tree.NearestAccepted(mean, [&, c = c](std::int64_t j) { return component[j] == c; });
    appendPolyline({ pathVertex(medoid) }, 0);
  }

  graph.NodePositions.resize(static_cast<Eigen::Index>(nodePositions.size()), 3);
  for (std::size_t i = 0; i < nodePositions.size(); ++i)
  {
    graph.NodePositions.row(static_cast<Eigen::Index>(i)) = nodePositions[i].transpose();
  }
  AssignBranchBones(graph);
  if (!report(1.0))
  {
    return {};
  }
  return graph;
}

} // namespace shapediameter
