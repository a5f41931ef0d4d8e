// SPDX-License-Identifier: BSD-3-Clause
// The project's max-flow against Boost.Graph's Boykov-Kolmogorov on random graphs: the same
// flow value, and a source set that is a minimum cut (its capacity equals the flow) and is
// exactly the set of nodes reachable from s in the final residual graph, with no residual
// path left to t.
#include "Partition/MaxFlow.h"

#include <boost/graph/boykov_kolmogorov_max_flow.hpp>
#include <boost/graph/compressed_sparse_row_graph.hpp>
#include <boost/property_map/property_map.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

namespace
{

using shapediameter::MaxFlowGraph;

struct Problem
{
  std::size_t nodes = 0;
  std::vector<std::int64_t> first, second;
  std::vector<double> forward, backward, fromSource, toSink;
};

/// A grid-like graph (every node linked to its right and lower neighbour) plus random chords;
/// capacities with many zeros and repeated values (ties), like expansion moves.
Problem RandomProblem(std::mt19937_64& generator, int side)
{
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  auto capacity = [&]() {
    const double u = uniform(generator);
    return u < 0.3 ? 0.0 : (u < 0.5 ? 1.0 : 10.0 * uniform(generator));
  };
  Problem problem;
  problem.nodes = static_cast<std::size_t>(side) * static_cast<std::size_t>(side);
  auto add = [&](std::int64_t a, std::int64_t b) {
    problem.first.push_back(a);
    problem.second.push_back(b);
    problem.forward.push_back(capacity());
    problem.backward.push_back(uniform(generator) < 0.5 ? 0.0 : capacity());
  };
  for (int y = 0; y < side; ++y)
  {
    for (int x = 0; x < side; ++x)
    {
      const std::int64_t i = y * side + x;
      if (x + 1 < side)
      {
        add(i, i + 1);
      }
      if (y + 1 < side)
      {
        add(i, i + side);
      }
    }
  }
  std::uniform_int_distribution<std::int64_t> node(0, static_cast<std::int64_t>(problem.nodes) - 1);
  for (int c = 0; c < side; ++c)
  {
    const std::int64_t a = node(generator), b = node(generator);
    if (a != b)
    {
      add(a, b);
    }
  }
  for (std::size_t i = 0; i < problem.nodes; ++i)
  {
    problem.fromSource.push_back(capacity());
    problem.toSink.push_back(capacity());
  }
  return problem;
}

double BoostMaxFlow(const Problem& problem)
{
  using Graph = boost::compressed_sparse_row_graph<boost::directedS>;
  using Edge = boost::graph_traits<Graph>::edge_descriptor;
  const std::size_t n = problem.nodes;
  const std::size_t source = n, sink = n + 1;
  std::vector<std::pair<std::size_t, std::size_t>> edges;
  std::vector<double> capacities;
  auto add = [&](std::size_t a, std::size_t b, double forward, double backward) {
    edges.emplace_back(a, b);
    capacities.push_back(forward);
    edges.emplace_back(b, a);
    capacities.push_back(backward);
  };
  for (std::size_t p = 0; p < problem.first.size(); ++p)
  {
    add(static_cast<std::size_t>(problem.first[p]), static_cast<std::size_t>(problem.second[p]),
      problem.forward[p], problem.backward[p]);
  }
  for (std::size_t i = 0; i < n; ++i)
  {
    add(source, i, problem.fromSource[i], 0.0);
    add(i, sink, problem.toSink[i], 0.0);
  }
  // The CSR graph sorts the edges: keep each one's capacity and partner through the sort.
  std::vector<std::size_t> order(edges.size());
  for (std::size_t e = 0; e < order.size(); ++e)
  {
    order[e] = e;
  }
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return edges[a].first < edges[b].first; });
  std::vector<std::size_t> position(edges.size());
  std::vector<std::pair<std::size_t, std::size_t>> sorted(edges.size());
  std::vector<double> capacity(edges.size()), residual(edges.size());
  for (std::size_t k = 0; k < order.size(); ++k)
  {
    position[order[k]] = k;
    sorted[k] = edges[order[k]];
    capacity[k] = capacities[order[k]];
  }
  const Graph graph(boost::edges_are_sorted, sorted.begin(), sorted.end(), n + 2);
  std::vector<Edge> reverse(edges.size());
  for (std::size_t e = 0; e < edges.size(); ++e)
  {
    const std::size_t partner = e ^ 1u; // edges were added in (forward, backward) pairs
    reverse[position[e]] = Edge(edges[partner].first, position[partner]);
  }
  std::vector<Edge> predecessor(n + 2);
  std::vector<boost::default_color_type> color(n + 2);
  std::vector<long> distance(n + 2);
  const auto edgeIndex = boost::get(boost::edge_index, graph);
  const auto vertexIndex = boost::get(boost::vertex_index, graph);
  return boost::boykov_kolmogorov_max_flow(graph, boost::make_iterator_property_map(capacity.begin(), edgeIndex),
    boost::make_iterator_property_map(residual.begin(), edgeIndex),
    boost::make_iterator_property_map(reverse.begin(), edgeIndex),
    boost::make_iterator_property_map(predecessor.begin(), vertexIndex),
    boost::make_iterator_property_map(color.begin(), vertexIndex),
    boost::make_iterator_property_map(distance.begin(), vertexIndex), vertexIndex, source, sink);
}

/// Capacity of the cut (source set S = InSourceSet, sink set its complement).
double CutCapacity(const Problem& problem, const MaxFlowGraph& graph)
{
  double cut = 0.0;
  for (std::size_t i = 0; i < problem.nodes; ++i)
  {
    cut += graph.InSourceSet(i) ? problem.toSink[i] : problem.fromSource[i];
  }
  for (std::size_t p = 0; p < problem.first.size(); ++p)
  {
    const bool a = graph.InSourceSet(static_cast<std::size_t>(problem.first[p]));
    const bool b = graph.InSourceSet(static_cast<std::size_t>(problem.second[p]));
    cut += (a && !b) ? problem.forward[p] : 0.0;
    cut += (b && !a) ? problem.backward[p] : 0.0;
  }
  return cut;
}

/// Nodes reachable from s in the residual graph after Solve() (breadth first over the arcs
/// with residual capacity left). Also counts the reachable nodes that still have residual
/// capacity to t: each would be an augmenting path, so a maximum flow has none.
std::vector<bool> ReachableFromSource(const MaxFlowGraph& graph, std::size_t& reachingSink)
{
  std::vector<bool> reached(graph.NodeCount(), false);
  std::vector<std::size_t> queue;
  for (std::size_t i = 0; i < graph.NodeCount(); ++i)
  {
    if (graph.TerminalResidual(i) > 0.0)
    {
      reached[i] = true;
      queue.push_back(i);
    }
  }
  for (std::size_t head = 0; head < queue.size(); ++head)
  {
    const std::size_t i = queue[head];
    for (std::int32_t arc = graph.FirstArc(i); arc < graph.FirstArc(i + 1); ++arc)
    {
      const auto j = static_cast<std::size_t>(graph.ArcHead(arc));
      if (graph.ArcResidual(arc) > 0.0 && !reached[j])
      {
        reached[j] = true;
        queue.push_back(j);
      }
    }
  }
  reachingSink = 0;
  for (std::size_t i = 0; i < graph.NodeCount(); ++i)
  {
    reachingSink += reached[i] && graph.TerminalResidual(i) < 0.0 ? 1 : 0;
  }
  return reached;
}

/// Nodes whose InSourceSet() differs from residual reachability from s.
std::size_t SourceSetMismatches(const MaxFlowGraph& graph, const std::vector<bool>& reachable)
{
  std::size_t mismatches = 0;
  for (std::size_t i = 0; i < graph.NodeCount(); ++i)
  {
    mismatches += graph.InSourceSet(i) != reachable[i] ? 1 : 0;
  }
  return mismatches;
}

void Load(const Problem& problem, MaxFlowGraph& graph)
{
  for (std::size_t i = 0; i < problem.nodes; ++i)
  {
    graph.SetTerminalCapacities(i, problem.fromSource[i], problem.toSink[i]);
  }
  for (std::size_t p = 0; p < problem.first.size(); ++p)
  {
    graph.SetPairCapacities(p, problem.forward[p], problem.backward[p]);
  }
}

TEST(MaxFlow, SameFlowAsBoostAndAMinimumCut)
{
  std::mt19937_64 generator(20081124);
  for (int trial = 0; trial < 300; ++trial)
  {
    const Problem problem = RandomProblem(generator, 2 + trial % 23);
    MaxFlowGraph graph(problem.nodes, problem.first, problem.second);
    Load(problem, graph);
    const double flow = graph.Solve();
    const double reference = BoostMaxFlow(problem);
    const double tolerance = 1e-9 * std::max(1.0, reference);
    ASSERT_NEAR(flow, reference, tolerance) << "trial " << trial;
    ASSERT_NEAR(CutCapacity(problem, graph), flow, tolerance) << "trial " << trial << ": not a minimum cut";
    std::size_t reachingSink = 0;
    const std::vector<bool> reachable = ReachableFromSource(graph, reachingSink);
    ASSERT_EQ(reachingSink, 0u) << "trial " << trial << ": an augmenting path is left";
    ASSERT_EQ(SourceSetMismatches(graph, reachable), 0u)
      << "trial " << trial << ": the source set is not the set reachable from s in the residual graph";
  }
}

TEST(MaxFlow, ReusedTopologyGivesFreshResults)
{
  std::mt19937_64 generator(7);
  const Problem one = RandomProblem(generator, 12);
  Problem two = one;
  std::uniform_real_distribution<double> uniform(0.0, 3.0);
  for (double& c : two.fromSource)
  {
    c = uniform(generator);
  }
  MaxFlowGraph graph(one.nodes, one.first, one.second);
  Load(one, graph);
  const double first = graph.Solve();
  Load(two, graph);
  const double second = graph.Solve();
  // Nothing of the first solve's trees may survive into the second's cut.
  std::size_t reachingSink = 0;
  const std::vector<bool> reachable = ReachableFromSource(graph, reachingSink);
  EXPECT_EQ(reachingSink, 0u);
  EXPECT_EQ(SourceSetMismatches(graph, reachable), 0u);
  Load(one, graph);
  EXPECT_DOUBLE_EQ(graph.Solve(), first);
  EXPECT_NEAR(second, BoostMaxFlow(two), 1e-9 * std::max(1.0, second));
}

TEST(MaxFlow, SmallCasesByHand)
{
  // s -> 0 (3), 0 -> 1 (2), 1 -> t (5): the flow is 2, the cut is the pair arc.
  MaxFlowGraph chain(2, { 0 }, { 1 });
  chain.SetTerminalCapacities(0, 3.0, 0.0);
  chain.SetTerminalCapacities(1, 0.0, 5.0);
  chain.SetPairCapacities(0, 2.0, 0.0);
  EXPECT_DOUBLE_EQ(chain.Solve(), 2.0);
  EXPECT_TRUE(chain.InSourceSet(0));
  EXPECT_FALSE(chain.InSourceSet(1));
  // Both terminals on one node: the common part flows directly.
  MaxFlowGraph single(1, {}, {});
  single.SetTerminalCapacities(0, 4.0, 1.5);
  EXPECT_DOUBLE_EQ(single.Solve(), 1.5);
  EXPECT_TRUE(single.InSourceSet(0));
  // An isolated node with no capacity is not reachable from s.
  MaxFlowGraph empty(1, {}, {});
  EXPECT_DOUBLE_EQ(empty.Solve(), 0.0);
  EXPECT_FALSE(empty.InSourceSet(0));
  EXPECT_THROW(MaxFlowGraph(2, { 0 }, { 0 }), std::invalid_argument);
  EXPECT_THROW(MaxFlowGraph(2, { 0 }, { 2 }), std::invalid_argument);
  EXPECT_THROW(MaxFlowGraph(2, { 0 }, {}), std::invalid_argument);
}

} // namespace
