// SPDX-License-Identifier: BSD-3-Clause
#include "Skeleton/SkeletonConnection.h"

#include "UnionFind.h"

#include "Skeleton/SkeletonPointTree.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <queue>
#include <tuple>

#include <Eigen/Eigenvalues>

namespace shapediameter
{

void ValidateConnectionOptions(const SkeletonConnectionOptions& options)
{
  CheckRange(options.NumberOfNeighbors, NumberOfNeighborsRange, "skeleton: NumberOfNeighbors");
  CheckRange(options.SeedRadiusFactor, SeedRadiusFactorRange, "skeleton: SeedRadiusFactor");
  CheckRange(options.SpacingFactor, ConnectionSpacingFactorRange, "skeleton: connection SpacingFactor");
  CheckRange(options.MinimumBranchFactor, MinimumBranchFactorRange, "skeleton: MinimumBranchFactor");
  CheckRange(options.SheetClearanceExponent, SheetClearanceExponentRange, "skeleton: SheetClearanceExponent");
}

namespace
{

using Edge = std::pair<std::int64_t, std::int64_t>;

/// bridges: the edges of `edges` that BridgeGraphPieces added, sorted.
CloudNeighborGraph MakeGraph(
  const PointMatrix& positions, std::vector<Edge> edges, const std::vector<Edge>& bridges)
{
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  CloudNeighborGraph graph;
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
  graph.IsBridge.assign(graph.Offsets[count], 0);
  std::vector<std::size_t> fill(graph.Offsets.begin(), graph.Offsets.end() - 1);
  for (const auto& edge : edges)
  {
    const auto [a, b] = edge;
    const double weight = (positions.row(a) - positions.row(b)).norm();
    const char bridge = std::binary_search(bridges.begin(), bridges.end(), edge) ? 1 : 0;
    graph.IsBridge[fill[a]] = bridge;
    graph.Targets[fill[a]] = b;
    graph.Weights[fill[a]++] = weight;
    graph.IsBridge[fill[b]] = bridge;
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

/// Stage 1, first part: each point of P linked to its k nearest points of the same surface
/// component, as (lower, higher) index pairs; an edge in both end points' lists is there twice.
std::vector<Edge> NearestNeighborEdges(const SkeletonPointTree& tree, const ProjectedCloud& cloud,
  const std::vector<std::int64_t>& component, std::size_t k, const ParallelFor& parallelFor)
{
  const std::size_t count = cloud.Size();
  const PointMatrix& positions = cloud.Positions;
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
  return edges;
}

/// The straight segments of the edges between positions' rows.
std::vector<Segment> EdgeSegments(const PointMatrix& positions, const std::vector<Edge>& edges)
{
  std::vector<Segment> segments;
  segments.reserve(edges.size());
  for (const Edge& edge : edges)
  {
    segments.push_back(Segment{ positions.row(edge.first).transpose(), positions.row(edge.second).transpose() });
  }
  return segments;
}

/// Stage 1, the inside test: leaves out every edge whose straight segment meets the surface.
void DropSurfaceCrossings(const RayCaster& volume, const PointMatrix& positions,
  const ParallelFor& parallelFor, std::vector<Edge>& edges)
{
  // Each edge once (most are in both end points' lists), tested in parallel.
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  const std::vector<char> crossing = SegmentsCrossSurface(volume, EdgeSegments(positions, edges), parallelFor);
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

/// Stage 1 on a tree of P's positions: nearest-neighbour edges, surface crossings dropped,
/// pieces bridged. between (may be empty) runs before the bridging; returning false stops
/// there with an empty graph (the connection's progress report and abort).
CloudNeighborGraph NeighborGraphOnCloud(const SkeletonPointTree& tree, const ProjectedCloud& cloud,
  const std::vector<std::int64_t>& component, std::size_t k, const ParallelFor& parallelFor,
  const RayCaster* volume, const std::function<bool()>& between)
{
  std::vector<Edge> edges = NearestNeighborEdges(tree, cloud, component, k, parallelFor);
  if (volume)
  {
    DropSurfaceCrossings(*volume, cloud.Positions, parallelFor, edges);
  }
  if (between && !between())
  {
    return {};
  }
  const std::size_t unbridged = edges.size();
  BridgeGraphPieces(tree, cloud.Positions, component, edges);
  std::vector<Edge> bridges(edges.begin() + static_cast<std::ptrdiff_t>(unbridged), edges.end());
  // A bridge that stays inside the volume is an edge the k nearest missed (a thin ear whose
  // points' neighbours are all its own), not a gap: steps 5 and 6 may walk it.
  if (volume)
  {
    const std::vector<char> crossing = SegmentsCrossSurface(*volume, EdgeSegments(cloud.Positions, bridges), parallelFor);
    std::size_t kept = 0;
    for (std::size_t b = 0; b < bridges.size(); ++b)
    {
      if (crossing[b])
      {
        bridges[kept++] = bridges[b];
      }
    }
    bridges.resize(kept);
  }
  std::sort(bridges.begin(), bridges.end());
  return MakeGraph(cloud.Positions, std::move(edges), bridges);
}

/// The vertices of the connecting paths: segment nodes [0, SegmentNodes()) in segment order
/// (at their MLS positions), then point j of P as vertex SegmentNodes() + j (at its P position).
class PathVertices
{
public:
  PathVertices(const std::vector<PolySegment>& segments, const PointMatrix& segmentPositions,
    const PointMatrix& cloudPositions)
    : Segments(segments)
    , SegmentPositions(segmentPositions)
    , CloudPositions(cloudPositions)
    , SegmentOffset(segments.size() + 1, 0)
  {
    for (std::size_t s = 0; s < segments.size(); ++s)
    {
      SegmentOffset[s + 1] = SegmentOffset[s] + segments[s].size();
    }
    NodeSegment.resize(SegmentOffset.back());
    for (std::size_t s = 0; s < segments.size(); ++s)
    {
      for (std::size_t m = 0; m < segments[s].size(); ++m)
      {
        NodeSegment[SegmentOffset[s] + m] = static_cast<std::int64_t>(s);
      }
    }
  }

  std::size_t SegmentNodes() const { return SegmentOffset.back(); }
  /// The vertex of node m of segment s.
  std::int64_t SegmentNode(std::size_t s, std::size_t m) const
  {
    return static_cast<std::int64_t>(SegmentOffset[s] + m);
  }
  /// The vertex of point j of P.
  std::int64_t CloudPoint(std::int64_t j) const
  {
    return static_cast<std::int64_t>(SegmentNodes()) + j;
  }
  bool IsSegmentNode(std::int64_t v) const
  {
    return v < static_cast<std::int64_t>(SegmentNodes());
  }
  /// The point of P a vertex stands for.
  std::int64_t CloudIndex(std::int64_t v) const
  {
    return IsSegmentNode(v) ? Segments[NodeSegment[v]][v - SegmentOffset[NodeSegment[v]]]
                            : v - static_cast<std::int64_t>(SegmentNodes());
  }
  Eigen::Vector3d Position(std::int64_t v) const
  {
    return IsSegmentNode(v) ? Eigen::Vector3d(SegmentPositions.row(CloudIndex(v)).transpose())
                            : Eigen::Vector3d(CloudPositions.row(CloudIndex(v)).transpose());
  }

private:
  const std::vector<PolySegment>& Segments;
  const PointMatrix& SegmentPositions;
  const PointMatrix& CloudPositions;
  std::vector<std::size_t> SegmentOffset;
  std::vector<std::int64_t> NodeSegment;
};

/// The k-terminal growth over P, per point: the distance along the neighbour graph to the
/// segment that reached it first (Owner), the segment node that path starts from (RootNode)
/// and the point before it on the path (Parent); -1 where not reached (Parent: a seed).
struct Growth
{
  std::vector<double> Distance;
  std::vector<std::int64_t> Owner;
  std::vector<std::int64_t> Parent;
  std::vector<std::int64_t> RootNode;
};

/// A unit vector perpendicular to n (unit), from the coordinate axis least aligned with it.
Eigen::Vector3d Perpendicular(const Eigen::Vector3d& n)
{
  Eigen::Index least = 0;
  n.cwiseAbs().minCoeff(&least);
  return n.cross(Eigen::Vector3d::Unit(least)).normalized();
}

/// The neighbour graph with every edge's weight times the mean of its ends' factors.
CloudNeighborGraph ScaledByFactors(CloudNeighborGraph graph, const std::vector<double>& factor)
{
  for (std::size_t a = 0; a + 1 < graph.Offsets.size(); ++a)
  {
    for (std::size_t e = graph.Offsets[a]; e < graph.Offsets[a + 1]; ++e)
    {
      graph.Weights[e] *= 0.5 * (factor[a] + factor[static_cast<std::size_t>(graph.Targets[e])]);
    }
  }
  return graph;
}

/// Stage 2, the seeds: every segment node claims the points of P of its component within
/// seedRadiusFactor * radius, and the nearest one, with their distance to it (ties: lower node).
Growth SeedGrowth(const SkeletonPointTree& tree, const ProjectedCloud& cloud,
  const ThinnedCloud& thinned, const std::vector<PolySegment>& segments,
  const std::vector<std::int64_t>& component, double seedRadiusFactor,
  const PathVertices& vertices)
{
  const std::size_t count = cloud.Size();
  const PointMatrix& positions = cloud.Positions;
  Growth growth;
  growth.Distance.assign(count, std::numeric_limits<double>::infinity());
  growth.Owner.assign(count, -1);
  growth.Parent.assign(count, -1);
  growth.RootNode.assign(count, -1);
  std::vector<double>& distance = growth.Distance;
  std::vector<std::int64_t>& rootNode = growth.RootNode;
  std::vector<std::int64_t> nearby;
  for (std::size_t s = 0; s < segments.size(); ++s)
  {
    for (std::size_t m = 0; m < segments[s].size(); ++m)
    {
      const std::int64_t cloudIndex = segments[s][m];
      const std::int64_t node = vertices.SegmentNode(s, m);
      const std::int64_t c = component[cloudIndex];
      const Eigen::Vector3d x = thinned.Positions.row(cloudIndex).transpose();
      tree.RadiusSearch(x, seedRadiusFactor * cloud.Radius[cloudIndex], nearby);
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
          growth.Owner[j] = static_cast<std::int64_t>(s);
          rootNode[j] = node;
        }
      }
    }
  }
  return growth;
}

/// Stage 2, the growth: Dijkstra from all seeds at once; the queue orders by (distance, index).
void GrowFromSeeds(const CloudNeighborGraph& neighbours, Growth& growth)
{
  const std::size_t count = growth.Owner.size();
  using QueueEntry = std::pair<double, std::int64_t>;
  std::priority_queue<QueueEntry, std::vector<QueueEntry>, std::greater<QueueEntry>> queue;
  for (std::size_t j = 0; j < count; ++j)
  {
    if (growth.Owner[j] >= 0)
    {
      queue.emplace(growth.Distance[j], static_cast<std::int64_t>(j));
    }
  }
  std::vector<char> settled(count, 0);
  while (!queue.empty())
  {
    const auto [d, j] = queue.top();
    queue.pop();
    if (settled[j] || d > growth.Distance[j])
    {
      continue;
    }
    settled[j] = 1;
    for (std::size_t e = neighbours.Offsets[j]; e < neighbours.Offsets[j + 1]; ++e)
    {
      const std::int64_t target = neighbours.Targets[e];
      const double candidate = d + neighbours.Weights[e];
      if (!settled[target] && candidate < growth.Distance[target])
      {
        growth.Distance[target] = candidate;
        growth.Owner[target] = growth.Owner[j];
        growth.Parent[target] = j;
        growth.RootNode[target] = growth.RootNode[j];
        queue.emplace(candidate, target);
      }
    }
  }
}

/// A possible join of two segments: (cost, a, b) for the graph edge ab where their growths meet.
using Join = std::tuple<double, std::int64_t, std::int64_t>;

/// Stage 3: every graph edge between points of different segments, cheapest first.
std::vector<Join> JoinsWhereGrowthsMeet(const CloudNeighborGraph& neighbours, const Growth& growth)
{
  const std::vector<std::int64_t>& owner = growth.Owner;
  std::vector<Join> joins;
  for (std::size_t a = 0; a < owner.size(); ++a)
  {
    for (std::size_t e = neighbours.Offsets[a]; e < neighbours.Offsets[a + 1]; ++e)
    {
      const std::int64_t b = neighbours.Targets[e];
      if (static_cast<std::int64_t>(a) < b && owner[a] >= 0 && owner[b] >= 0 &&
        owner[a] != owner[b])
      {
        joins.emplace_back(growth.Distance[a] + neighbours.Weights[e] + growth.Distance[b],
          static_cast<std::int64_t>(a), b);
      }
    }
  }
  std::sort(joins.begin(), joins.end());
  return joins;
}

/// Adjacency of the merged connecting paths over path vertices, each list ascending.
using PathAdjacency = std::map<std::int64_t, std::vector<std::int64_t>>;

/// Stage 4, the paths: each join that links two not yet linked segments (union-find, cheapest
/// first) becomes node -> points of P -> ... -> node; paths sharing points merge.
PathAdjacency MergedJoinPaths(const std::vector<Join>& joins, const Growth& growth,
  std::size_t segmentCount, const PathVertices& vertices)
{
  UnionFind linked(segmentCount);
  std::vector<Edge> pathEdges;
  const auto addEdge = [&pathEdges](std::int64_t a, std::int64_t b) {
    pathEdges.emplace_back(std::min(a, b), std::max(a, b));
  };
  const auto addPathToRoot = [&](std::int64_t j) {
    while (growth.Parent[j] >= 0)
    {
      addEdge(vertices.CloudPoint(j), vertices.CloudPoint(growth.Parent[j]));
      j = growth.Parent[j];
    }
    addEdge(vertices.CloudPoint(j), growth.RootNode[j]);
  };
  for (const auto& [cost, a, b] : joins)
  {
    if (linked.Unite(growth.Owner[a], growth.Owner[b]))
    {
      addPathToRoot(a);
      addPathToRoot(b);
      addEdge(vertices.CloudPoint(a), vertices.CloudPoint(b));
    }
  }
  std::sort(pathEdges.begin(), pathEdges.end());
  pathEdges.erase(std::unique(pathEdges.begin(), pathEdges.end()), pathEdges.end());

  PathAdjacency pathAdjacency;
  for (const auto& [a, b] : pathEdges)
  {
    pathAdjacency[a].push_back(b);
    pathAdjacency[b].push_back(a);
  }
  for (auto& entry : pathAdjacency)
  {
    std::sort(entry.second.begin(), entry.second.end());
  }
  return pathAdjacency;
}

/// Stage 4, the polylines: the merged paths cut at segment nodes and branching points into
/// chains, each thinned to a node spacing of spacingFactor * radius.
std::vector<std::vector<std::int64_t>> ThinnedChains(PathAdjacency& pathAdjacency,
  const PathVertices& vertices, const std::vector<double>& radius, double spacingFactor)
{
  const auto isBreak = [&](std::int64_t v) {
    return vertices.IsSegmentNode(v) || pathAdjacency[v].size() != 2;
  };
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
      const Eigen::Vector3d last = vertices.Position(chain.back());
      for (std::size_t i = 1; i + 1 < chain.size(); ++i)
      {
        const Eigen::Vector3d x = vertices.Position(chain[i]);
        const double epsilon = spacingFactor * radius[vertices.CloudIndex(chain[i])];
        if ((x - vertices.Position(kept.back())).norm() >= epsilon &&
          (x - last).norm() >= 0.5 * epsilon)
        {
          kept.push_back(chain[i]);
        }
      }
      kept.push_back(chain.back());
      chains.push_back(std::move(kept));
    }
  }
  return chains;
}

/// Polylines over path vertices with their IsConnection flags.
struct PathPolylines
{
  std::vector<std::vector<std::int64_t>> Vertices;
  std::vector<int> IsConnection;
};

/// Stage 5: the segments (IsConnection 0) then the chains (1), junctions cleaned.
PathPolylines CleanedPolylines(const std::vector<PolySegment>& segments,
  std::vector<std::vector<std::int64_t>> chains, const PathVertices& vertices,
  const std::vector<double>& radius, const std::vector<std::int64_t>& component,
  double minimumBranchFactor)
{
  PathPolylines polylines;
  for (std::size_t s = 0; s < segments.size(); ++s)
  {
    std::vector<std::int64_t> segmentVertices(segments[s].size());
    std::iota(segmentVertices.begin(), segmentVertices.end(), vertices.SegmentNode(s, 0));
    polylines.Vertices.push_back(std::move(segmentVertices));
    polylines.IsConnection.push_back(0);
  }
  for (auto& chain : chains)
  {
    polylines.Vertices.push_back(std::move(chain));
    polylines.IsConnection.push_back(1);
  }
  CleanJunctions(polylines.Vertices, polylines.IsConnection,
    [&vertices](std::int64_t v) { return vertices.Position(v); },
    [&](std::int64_t v) { return radius[vertices.CloudIndex(v)]; },
    [&](std::int64_t v) { return component[vertices.CloudIndex(v)]; }, minimumBranchFactor);
  return polylines;
}

/// Surface components of P without any segment (blobs): the point of P nearest to the mean
/// of each one's points, in component order.
std::vector<std::int64_t> BlobMedoids(const SkeletonPointTree& tree, const ProjectedCloud& cloud,
  const std::vector<std::int64_t>& component, const std::vector<PolySegment>& segments)
{
  std::map<std::int64_t, std::pair<Eigen::Vector3d, double>> sums;
  for (std::size_t j = 0; j < cloud.Size(); ++j)
  {
    auto& entry = sums.try_emplace(component[j], Eigen::Vector3d::Zero(), 0.0).first->second;
    entry.first += cloud.Positions.row(static_cast<Eigen::Index>(j)).transpose();
    entry.second += 1.0;
  }
  std::map<std::int64_t, bool> hasSegment;
  for (const auto& segment : segments)
  {
    hasSegment[component[segment.front()]] = true;
  }
  std::vector<std::int64_t> medoids;
  for (const auto& [c, entry] : sums)
  {
    if (hasSegment[c])
    {
      continue;
    }
    const Eigen::Vector3d mean = entry.first / entry.second;
    medoids.push_back(
      tree.NearestAccepted(mean, [&, c = c](std::int64_t j) { return component[j] == c; }));
  }
  return medoids;
}

/// Builds the SkeletonGraph from polylines over path vertices: each vertex becomes a node on
/// first use, with the radius, confidence and component of its point of P.
class GraphAssembler
{
public:
  GraphAssembler(const ProjectedCloud& cloud, const ThinnedCloud& thinned,
    const std::vector<std::int64_t>& component, const PathVertices& vertices)
    : Cloud(cloud)
    , Thinned(thinned)
    , Component(component)
    , Vertices(vertices)
  {
  }

  void AppendPolyline(const std::vector<std::int64_t>& vertices, int isConnection)
  {
    std::vector<std::int64_t> polyline;
    for (const std::int64_t v : vertices)
    {
      const std::size_t before = Graph.NodeRadius.size();
      polyline.push_back(NodeOf(v));
      if (Graph.NodeRadius.size() > before)
      {
        NodePositions.push_back(Vertices.Position(v));
      }
    }
    Graph.Polylines.push_back(std::move(polyline));
    Graph.IsConnection.push_back(isConnection);
  }

  /// The graph with its node positions; bones are not assigned yet.
  SkeletonGraph Finish()
  {
    Graph.NodePositions.resize(static_cast<Eigen::Index>(NodePositions.size()), 3);
    for (std::size_t i = 0; i < NodePositions.size(); ++i)
    {
      Graph.NodePositions.row(static_cast<Eigen::Index>(i)) = NodePositions[i].transpose();
    }
    return std::move(Graph);
  }

private:
  std::int64_t NodeOf(std::int64_t v)
  {
    const auto found = NodeOfVertex.find(v);
    if (found != NodeOfVertex.end())
    {
      return found->second;
    }
    const auto node = static_cast<std::int64_t>(Graph.NodeRadius.size());
    const std::int64_t cloudIndex = Vertices.CloudIndex(v);
    NodeOfVertex[v] = node;
    Graph.NodeCloudIndex.push_back(cloudIndex);
    Graph.NodeRadius.push_back(Cloud.Radius[cloudIndex]);
    Graph.NodeConfidence.push_back(Thinned.Confidence[cloudIndex]);
    Graph.NodeComponent.push_back(Component[cloudIndex]);
    return node;
  }

  const ProjectedCloud& Cloud;
  const ThinnedCloud& Thinned;
  const std::vector<std::int64_t>& Component;
  const PathVertices& Vertices;
  SkeletonGraph Graph;
  std::map<std::int64_t, std::int64_t> NodeOfVertex;
  std::vector<Eigen::Vector3d> NodePositions;
};

} // namespace

std::vector<double> SheetFactors(const ProjectedCloud& cloud, const ThinnedCloud& thinned, const RayCaster& volume,
  double exponent, const ParallelFor& parallelFor)
{
  CheckRange(exponent, SheetClearanceExponentRange, "skeleton: SheetClearanceExponent");
  constexpr double lineSpread = 0.1;   // second variance below this share of the first: a line
  constexpr double flatSpread = 0.25;  // smallest above this share of the second: not flat
  constexpr double smallestFactor = 0.25; // a sheet's middle at most 4 times cheaper
  constexpr int rays = 8;
  const std::size_t count = cloud.Size();
  std::vector<double> factor(count, 1.0);
  if (exponent == 0.0 || (thinned.LocalSpread.rows() == 0 && thinned.LocalNormal.rows() == 0))
  {
    return factor; // off, or a thinned cloud made without its local spread
  }
  // Rays reach no farther than where the factor reaches its smallest value.
  const double reachRadii = std::pow(1.0 / smallestFactor, 1.0 / exponent);
  if (static_cast<std::size_t>(thinned.LocalSpread.rows()) != count ||
    static_cast<std::size_t>(thinned.LocalNormal.rows()) != count)
  {
    throw Error("skeleton: the thinned cloud's local spread does not match the cloud");
  }
  // The rays of every sheet point in one batch (a volume over processes answers it in one
  // exchange), each point's clearance the shortest of its own.
  std::vector<std::size_t> sheetPoints;
  std::vector<Ray> fan;
  fan.reserve(rays * count);
  for (std::size_t i = 0; i < count; ++i)
  {
    const auto row = static_cast<Eigen::Index>(i);
    const Eigen::Vector3d spread = thinned.LocalSpread.row(row).transpose();
    const double radius = cloud.Radius[i];
    if (!(radius > 0.0) || !(spread(2) > 0.0) || spread(1) < lineSpread * spread(2) ||
      spread(0) > flatSpread * spread(1))
    {
      continue; // undefined, a line (a tube's axis) or a blob: Euclidean lengths
    }
    const Eigen::Vector3d normal = thinned.LocalNormal.row(row).transpose();
    const Eigen::Vector3d first = Perpendicular(normal);
    const Eigen::Vector3d second = normal.cross(first);
    const Eigen::Vector3d position = cloud.Positions.row(row).transpose();
    sheetPoints.push_back(i);
    for (int k = 0; k < rays; ++k)
    {
      const double angle = 2.0 * 3.14159265358979323846 * k / rays;
      fan.push_back(ExitRay(position, std::cos(angle) * first + std::sin(angle) * second, radius * reachRadii));
    }
  }
  std::vector<double> exits;
  volume.CastRays(fan, exits, parallelFor);
  for (std::size_t s = 0; s < sheetPoints.size(); ++s)
  {
    const std::size_t i = sheetPoints[s];
    const double radius = cloud.Radius[i];
    double clearance = radius * reachRadii;
    for (int k = 0; k < rays; ++k)
    {
      clearance = std::min(clearance, exits[s * rays + static_cast<std::size_t>(k)]);
    }
    if (clearance > 0.0)
    {
      factor[i] = std::clamp(std::pow(radius / clearance, exponent), smallestFactor, 1.0);
    }
  }
  return factor;
}

SkeletonGraph ConnectPolySegments(const ProjectedCloud& cloud, const ThinnedCloud& thinned,
  const std::vector<PolySegment>& segments, const std::vector<std::int64_t>& pointComponent,
  const SkeletonConnectionOptions& options, const ParallelFor& parallelFor,
  const ProgressCallback& progress, bool& aborted, const RayCaster* volume,
  CloudNeighborGraph* neighboursOut)
{
  ValidateConnectionOptions(options);
  aborted = false;
  const std::size_t count = cloud.Size();
  if (count == 0)
  {
    return {};
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

  // 1. Neighbour graph on P, restricted to surface components (and the volume), one piece
  // per component.
  CloudNeighborGraph neighbours =
    NeighborGraphOnCloud(tree, cloud, component, static_cast<std::size_t>(options.NumberOfNeighbors),
      parallelFor, volume, [&] { return report(0.3); });
  if (!report(0.5))
  {
    return {};
  }

  // 2. k-terminal growth from the segment nodes.
  const PathVertices vertices(segments, thinned.Positions, positions);
  Growth growth =
    SeedGrowth(tree, cloud, thinned, segments, component, options.SeedRadiusFactor, vertices);
  // Costs that follow the middle of sheets (the header comment); step 5 reads the Euclidean
  // graph.
  const bool sheets = volume && options.SheetClearanceExponent > 0.0;
  const CloudNeighborGraph growthGraph = sheets
    ? ScaledByFactors(neighbours, SheetFactors(cloud, thinned, *volume, options.SheetClearanceExponent, parallelFor))
    : CloudNeighborGraph();
  const CloudNeighborGraph& costs = sheets ? growthGraph : neighbours;
  GrowFromSeeds(costs, growth);
  if (!report(0.8))
  {
    return {};
  }

  // 3. Joins where growths meet; 4. the accepted joins' merged paths as thinned chains.
  PathAdjacency paths = MergedJoinPaths(
    JoinsWhereGrowthsMeet(costs, growth), growth, segments.size(), vertices);
  std::vector<std::vector<std::int64_t>> chains =
    ThinnedChains(paths, vertices, cloud.Radius, options.SpacingFactor);

  // 5. Polylines with junctions cleaned, then a single node for every blob component.
  const PathPolylines polylines = CleanedPolylines(
    segments, std::move(chains), vertices, cloud.Radius, component, options.MinimumBranchFactor);
  GraphAssembler assembler(cloud, thinned, component, vertices);
  for (std::size_t p = 0; p < polylines.Vertices.size(); ++p)
  {
    assembler.AppendPolyline(polylines.Vertices[p], polylines.IsConnection[p]);
  }
  for (const std::int64_t medoid : BlobMedoids(tree, cloud, component, segments))
  {
    assembler.AppendPolyline({ vertices.CloudPoint(medoid) }, 0);
  }
  SkeletonGraph graph = assembler.Finish();

  // 6. Bones.
  AssignBranchBones(graph);
  if (!report(1.0))
  {
    return {};
  }
  if (neighboursOut)
  {
    *neighboursOut = std::move(neighbours);
  }
  return graph;
}

CloudNeighborGraph BuildCloudNeighborGraph(const ProjectedCloud& cloud,
  const std::vector<std::int64_t>& pointComponent, int numberOfNeighbors,
  const ParallelFor& parallelFor, const RayCaster* volume)
{
  SkeletonConnectionOptions options;
  options.NumberOfNeighbors = numberOfNeighbors;
  ValidateConnectionOptions(options);
  const std::size_t count = cloud.Size();
  if (count == 0)
  {
    CloudNeighborGraph empty;
    empty.Offsets.assign(1, 0);
    return empty;
  }
  const std::vector<std::int64_t> component =
    pointComponent.empty() ? std::vector<std::int64_t>(count, 0) : pointComponent;
  const SkeletonPointTree tree(cloud.Positions);
  return NeighborGraphOnCloud(tree, cloud, component, static_cast<std::size_t>(numberOfNeighbors),
    parallelFor, volume, {});
}

} // namespace shapediameter
