// SPDX-License-Identifier: BSD-3-Clause
// Minimum s-t cut of a graph whose topology is fixed and whose capacities change between
// solves: the max-flow behind every alpha-expansion move (AlphaExpansion.h).
//
// What it computes
//   The maximum flow from the source s to the sink t and the minimum cut it proves, for a
//   graph of n nodes with, per node, a capacity from s and a capacity to t, and, per
//   undirected pair {a, b}, a capacity a->b and a capacity b->a (all finite, >= 0).
//   Algorithm: Boykov & Kolmogorov, "An experimental comparison of min-cut/max-flow
//   algorithms for energy minimization in vision", PAMI 26(9), 2004 -- two search trees
//   grown from s and t, augmentation along the path where they meet, adoption of the
//   orphans the saturated arcs leave behind -- with the terminal residuals of a node kept
//   as one signed number and the timestamp/distance heuristic for the choice of parents.
//   Written for this project (arrays of indices, no per-solve allocation after the first);
//   the tests check it against Boost.Graph's implementation of the same algorithm on
//   random graphs.
//
// Why not Boost.Graph's boykov_kolmogorov_max_flow: on the same graphs -- the recorded
//   expansion moves of one alpha-expansion run, replayed to both in one process
//   (Testing/Benchmarks/BenchMaxFlow.cpp; topology built once for both, timed: filling the
//   capacities and solving) -- ours was faster in every run, by more on the larger graph,
//   with the same flow value on every move (measurements: docs/performance.md).
//
// Result
//   InSourceSet(i): i is reachable from s in the final residual graph. This is the unique
//   minimal source set of a minimum cut, so the cut does not depend on the order of the
//   augmentations (up to floating-point ties).
//
// Cost: no polynomial bound better than O(n^2 m |C|) is known, but on the planar-like
// graphs of mesh partitioning it is close to linear per solve (measured in BenchPartition).
#pragma once

#include <cstdint>
#include <vector>

namespace shapediameter
{

class MaxFlowGraph
{
public:
  /// Topology: nodeCount nodes and the undirected pairs (first[p], second[p]), p < pairCount.
  /// Throws std::invalid_argument on an index out of range, a self pair, or more than
  /// 2^31 - 2 nodes or arcs.
  MaxFlowGraph(std::size_t nodeCount, const std::vector<std::int64_t>& first,
    const std::vector<std::int64_t>& second);

  std::size_t NodeCount() const { return this->TerminalCapacity.size(); }

  /// Capacities of the next Solve(). Terminal: s->node and node->t. Pair p: first->second
  /// and second->first. Values must be finite and >= 0 (not checked: the caller builds them).
  void SetTerminalCapacities(std::size_t node, double fromSource, double toSink);
  void SetPairCapacities(std::size_t pair, double forward, double backward);

  /// Arc-level access, for callers that fill capacities node by node (sequential memory):
  /// the arcs leaving `node` are [FirstArc(node), FirstArc(node + 1)); each belongs to one pair.
  std::int32_t FirstArc(std::size_t node) const { return this->ArcStart[node]; }
  std::int32_t ArcHead(std::int32_t arc) const { return this->Arcs[static_cast<std::size_t>(arc)].head; }
  std::int32_t ArcPair(std::int32_t arc) const { return this->ArcPairIndex[static_cast<std::size_t>(arc)]; }
  void SetArcCapacity(std::int32_t arc, double capacity)
  {
    this->Arcs[static_cast<std::size_t>(arc)].residual = capacity;
  }

  /// Maximum flow value for the capacities set since the last Solve() (the capacities are
  /// consumed: set them all again before the next Solve()).
  double Solve();

  /// Residual capacities: before Solve() the capacities set, after it what the flow left.
  /// For tests (the source set against reachability in the residual graph) and benchmarks
  /// (recording the graphs of a run). Terminal: > 0 the residual s->node, < 0 minus the
  /// residual node->t (the part common to both links is not stored: it flows s->node->t).
  std::size_t ArcCount() const { return this->Arcs.size(); }
  double ArcResidual(std::int32_t arc) const { return this->Arcs[static_cast<std::size_t>(arc)].residual; }
  double TerminalResidual(std::size_t node) const { return this->TerminalCapacity[node]; }

  /// After Solve(): true when the node is on the source side of the minimum cut.
  bool InSourceSet(std::size_t node) const
  {
    return this->Nodes[node].parent != NoParent && !this->Nodes[node].inSinkTree;
  }

private:
  static constexpr std::int32_t NoParent = -1;
  static constexpr std::int32_t TerminalParent = -2;
  static constexpr std::int32_t OrphanParent = -3;

  void MakeActive(std::int32_t node);
  std::int32_t NextActive();
  bool Grow(std::int32_t node, std::int32_t& meetingArc);
  void Augment(std::int32_t meetingArc);
  void Adopt(std::int32_t node);
  /// The arc to the node's parent saturated: it becomes an orphan, adopted before growing on.
  void CutOff(std::size_t node);
  /// Distance from `node` to its terminal through valid parents, or -1 when the chain ends in
  /// an orphan; marks the chain with the current time.
  std::int64_t OriginDistance(std::int32_t node);

  // Arcs and nodes as records: a search step touches every field of one arc or node, so
  // keeping them together saves cache misses (measurement: docs/performance.md).
  struct Arc
  {
    std::int32_t head = 0;
    std::int32_t sister = 0;
    double residual = 0.0;
  };
  struct Node
  {
    std::int32_t parent = NoParent; ///< arc from the node to its parent, or a constant above
    std::int32_t distance = 0;
    std::int32_t timestamp = 0; ///< augmentations per solve stay far below 2^31
    std::uint8_t inSinkTree = 0;
    std::uint8_t active = 0;
  };

  // Topology (CSR by tail node): arcs of node i are [ArcStart[i], ArcStart[i + 1]).
  std::vector<std::int32_t> ArcStart;
  std::vector<Arc> Arcs;
  std::vector<std::int32_t> PairArc; ///< per pair, the arc first->second
  std::vector<std::int32_t> ArcPairIndex; ///< per arc, its pair
  std::vector<double> TerminalCapacity; ///< > 0: residual s->i, < 0: residual i->t
  double FlowFromTerminals = 0.0;
  double FlowValue = 0.0;
  std::vector<Node> Nodes;
  std::vector<std::int32_t> ActiveQueue;
  std::size_t ActiveHead = 0;
  // Orphans: those cut off by an augmentation are adopted first, the last cut first (a stack);
  // the children of a freed orphan after them, in order (a queue).
  std::vector<std::int32_t> NewOrphans;
  std::vector<std::int32_t> OrphanQueue;
  std::size_t OrphanHead = 0;
  std::int32_t Time = 0;
};

} // namespace shapediameter
