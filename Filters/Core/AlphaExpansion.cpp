// SPDX-License-Identifier: BSD-3-Clause
#include "AlphaExpansion.h"

#include <boost/graph/boykov_kolmogorov_max_flow.hpp>
#include <boost/graph/compressed_sparse_row_graph.hpp>
#include <boost/property_map/property_map.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

namespace shapediameter
{
namespace
{

using FlowGraph = boost::compressed_sparse_row_graph<boost::directedS, boost::no_property,
  boost::no_property, boost::no_property, std::uint32_t, std::uint32_t>;
using FlowEdge = boost::graph_traits<FlowGraph>::edge_descriptor;
using FlowVertex = boost::graph_traits<FlowGraph>::vertex_descriptor;

/// Checks without ordered comparisons on NaN (they raise FE_INVALID when traps are on).
bool InRange(double value, double low, double high)
{
  return std::isfinite(value) && value >= low && value <= high;
}

void ValidateLabels(const PartitionEnergy& energy, const std::vector<int>& labels)
{
  if (labels.size() != energy.faceCount)
  {
    throw PartitionEnergyError("alpha expansion: " + std::to_string(labels.size()) +
      " labels for " + std::to_string(energy.faceCount) + " faces");
  }
  for (std::size_t f = 0; f < labels.size(); ++f)
  {
    if (labels[f] < 0 || labels[f] >= energy.labelCount)
    {
      throw PartitionEnergyError("alpha expansion: label out of range at face " + std::to_string(f));
    }
  }
}

void ValidateEnergy(const PartitionEnergy& energy)
{
  if (energy.labelCount < 1 ||
    energy.dataCost.size() != energy.faceCount * static_cast<std::size_t>(energy.labelCount) ||
    energy.pairFirst.size() != energy.pairWeight.size() ||
    energy.pairSecond.size() != energy.pairWeight.size())
  {
    throw PartitionEnergyError("alpha expansion: the energy has inconsistent sizes");
  }
  for (double cost : energy.dataCost)
  {
    if (!std::isfinite(cost))
    {
      throw PartitionEnergyError("alpha expansion: a data cost is NaN or infinite");
    }
  }
  const auto n = static_cast<std::int64_t>(energy.faceCount);
  for (std::size_t p = 0; p < energy.pairWeight.size(); ++p)
  {
    const std::int64_t a = energy.pairFirst[p], b = energy.pairSecond[p];
    if (a < 0 || b < 0 || a >= n || b >= n || a == b)
    {
      throw PartitionEnergyError("alpha expansion: pair " + std::to_string(p) + " has invalid faces");
    }
    if (!InRange(energy.pairWeight[p], 0.0, std::numeric_limits<double>::max()))
    {
      throw PartitionEnergyError("alpha expansion: pair weight " + std::to_string(p) + " is negative, NaN or infinite");
    }
  }
}

/// E without validation (labels known valid): sum of data costs plus cut pair weights.
double EnergyOf(const PartitionEnergy& energy, const std::vector<int>& labels)
{
  double data = 0.0;
  for (std::size_t f = 0; f < energy.faceCount; ++f)
  {
    data += energy.DataCost(f, labels[f]);
  }
  double smoothness = 0.0;
  for (std::size_t p = 0; p < energy.pairWeight.size(); ++p)
  {
    if (labels[static_cast<std::size_t>(energy.pairFirst[p])] !=
      labels[static_cast<std::size_t>(energy.pairSecond[p])])
    {
      smoothness += energy.pairWeight[p];
    }
  }
  return data + smoothness;
}

/// The s-t graph of an expansion move. Its topology does not depend on the labels or on
/// alpha, so it is built once; each move refills the capacities.
///   y_f = 0: f keeps its label (f on the source side), y_f = 1: f takes alpha (sink side).
///   Edge s->f is cut when y_f = 1, f->t when y_f = 0, f->g when y_f = 0 and y_g = 1.
class ExpansionGraph
{
public:
  explicit ExpansionGraph(const PartitionEnergy& energy)
    : Energy(energy)
    , FaceCount(energy.faceCount)
  {
    const std::size_t n = FaceCount;
    const std::size_t pairs = energy.pairWeight.size();
    const std::size_t edgeCount = 4 * n + 2 * pairs;
    if (n + 2 > std::numeric_limits<std::uint32_t>::max() ||
      edgeCount > std::numeric_limits<std::uint32_t>::max())
    {
      throw PartitionEnergyError("alpha expansion: graph too large for 32-bit indices");
    }
    Source = static_cast<std::uint32_t>(n);
    Sink = static_cast<std::uint32_t>(n + 1);

    // Out-edges of face f, in this order: f->s, f->t, then f->neighbour for each pair.
    std::vector<std::uint32_t> rowStart(n + 1, 0);
    std::vector<std::uint32_t> degree(n, 2);
    for (std::size_t p = 0; p < pairs; ++p)
    {
      ++degree[static_cast<std::size_t>(energy.pairFirst[p])];
      ++degree[static_cast<std::size_t>(energy.pairSecond[p])];
    }
    for (std::size_t f = 0; f < n; ++f)
    {
      rowStart[f + 1] = rowStart[f] + degree[f];
    }
    const std::uint32_t sourceStart = rowStart[n];
    const std::uint32_t sinkStart = sourceStart + static_cast<std::uint32_t>(n);

    std::vector<std::pair<std::uint32_t, std::uint32_t>> edges(edgeCount);
    std::vector<std::uint32_t> reverse(edgeCount);
    std::vector<std::uint32_t> fill(rowStart.begin(), rowStart.end() - 1);
    for (std::size_t f = 0; f < n; ++f)
    {
      const auto face = static_cast<std::uint32_t>(f);
      const std::uint32_t toSource = fill[f]++, toSink = fill[f]++;
      const std::uint32_t fromSource = sourceStart + face, fromSink = sinkStart + face;
      edges[toSource] = { face, Source };
      edges[toSink] = { face, Sink };
      edges[fromSource] = { Source, face };
      edges[fromSink] = { Sink, face };
      reverse[toSource] = fromSource;
      reverse[fromSource] = toSource;
      reverse[toSink] = fromSink;
      reverse[fromSink] = toSink;
    }
    SourceEdge.resize(n);
    SinkEdge.resize(n);
    for (std::size_t f = 0; f < n; ++f)
    {
      SourceEdge[f] = sourceStart + static_cast<std::uint32_t>(f);
      SinkEdge[f] = rowStart[f] + 1;
    }
    ForwardEdge.resize(pairs);
    for (std::size_t p = 0; p < pairs; ++p)
    {
      const auto a = static_cast<std::uint32_t>(energy.pairFirst[p]);
      const auto b = static_cast<std::uint32_t>(energy.pairSecond[p]);
      const std::uint32_t forward = fill[a]++, backward = fill[b]++;
      edges[forward] = { a, b };
      edges[backward] = { b, a };
      reverse[forward] = backward;
      reverse[backward] = forward;
      ForwardEdge[p] = forward;
    }

    Graph = FlowGraph(boost::edges_are_sorted, edges.begin(), edges.end(), n + 2);
    Reverse.resize(edgeCount);
    for (std::size_t e = 0; e < edgeCount; ++e)
    {
      Reverse[e] = FlowEdge(edges[reverse[e]].first, reverse[e]);
    }
    Capacity.assign(edgeCount, 0.0);
    Residual.assign(edgeCount, 0.0);
    Predecessor.resize(n + 2);
    Color.resize(n + 2);
    Distance.resize(n + 2);
    KeepCost.resize(n);
    AlphaCost.resize(n);
  }

  /// Writes into `result` the optimal move from `labels` towards alpha.
  void Move(const std::vector<int>& labels, int alpha, std::vector<int>& result)
  {
    const std::size_t n = FaceCount;
    for (std::size_t f = 0; f < n; ++f)
    {
      KeepCost[f] = Energy.DataCost(f, labels[f]);
      AlphaCost[f] = Energy.DataCost(f, alpha);
    }
    // Pair table (y_a, y_b): E00 = w[x_a != x_b], E01 = w[x_a != alpha], E10 = w[x_b != alpha],
    // E11 = 0, written as E00 + (E10 - E00) y_a + (E11 - E10) y_b + (E01 + E10 - E00 - E11)
    // (1 - y_a) y_b; the constant E00 is dropped (E is evaluated directly afterwards).
    for (std::size_t p = 0; p < Energy.pairWeight.size(); ++p)
    {
      const auto a = static_cast<std::size_t>(Energy.pairFirst[p]);
      const auto b = static_cast<std::size_t>(Energy.pairSecond[p]);
      const double w = Energy.pairWeight[p];
      const double e00 = labels[a] != labels[b] ? w : 0.0;
      const double e01 = labels[a] != alpha ? w : 0.0;
      const double e10 = labels[b] != alpha ? w : 0.0;
      AlphaCost[a] += e10 - e00;
      AlphaCost[b] -= e10;
      Capacity[ForwardEdge[p]] = e01 + e10 - e00;
    }
    for (std::size_t f = 0; f < n; ++f)
    {
      const double common = std::min(KeepCost[f], AlphaCost[f]);
      Capacity[SourceEdge[f]] = AlphaCost[f] - common;
      Capacity[SinkEdge[f]] = KeepCost[f] - common;
    }
    const auto edgeIndex = boost::get(boost::edge_index, Graph);
    const auto vertexIndex = boost::get(boost::vertex_index, Graph);
    boost::boykov_kolmogorov_max_flow(Graph,
      boost::make_iterator_property_map(Capacity.begin(), edgeIndex),
      boost::make_iterator_property_map(Residual.begin(), edgeIndex),
      boost::make_iterator_property_map(Reverse.begin(), edgeIndex),
      boost::make_iterator_property_map(Predecessor.begin(), vertexIndex),
      boost::make_iterator_property_map(Color.begin(), vertexIndex),
      boost::make_iterator_property_map(Distance.begin(), vertexIndex), vertexIndex, Source, Sink);
    result.resize(n);
    for (std::size_t f = 0; f < n; ++f)
    {
      // Black = the source search tree = the faces reachable from s: they keep their label.
      result[f] = Color[f] == boost::black_color ? labels[f] : alpha;
    }
  }

private:
  const PartitionEnergy& Energy;
  std::size_t FaceCount;
  std::uint32_t Source = 0;
  std::uint32_t Sink = 0;
  FlowGraph Graph;
  std::vector<std::uint32_t> SourceEdge; // s->f
  std::vector<std::uint32_t> SinkEdge;   // f->t
  std::vector<std::uint32_t> ForwardEdge; // first->second of each pair
  std::vector<double> Capacity;
  std::vector<double> Residual;
  std::vector<FlowEdge> Reverse;
  std::vector<FlowEdge> Predecessor;
  std::vector<boost::default_color_type> Color;
  std::vector<long> Distance;
  std::vector<double> KeepCost;
  std::vector<double> AlphaCost;
};

} // namespace

AlphaExpansionResult MinimizeByAlphaExpansion(
  const PartitionEnergy& energy, const AlphaExpansionOptions& options, const ProgressCallback& progress)
{
  ValidateEnergy(energy);
  return MinimizeByAlphaExpansion(energy, MostProbableLabels(energy), options, progress);
}

AlphaExpansionResult MinimizeByAlphaExpansion(const PartitionEnergy& energy,
  const std::vector<int>& initialLabels, const AlphaExpansionOptions& options,
  const ProgressCallback& progress)
{
  if (options.maxCycles < 1 || options.maxCycles > 1000000)
  {
    throw PartitionEnergyError("alpha expansion: maxCycles must be in [1, 1e6]");
  }
  if (!InRange(options.relativeTolerance, 0.0, 1.0))
  {
    throw PartitionEnergyError("alpha expansion: relativeTolerance must be in [0, 1]");
  }
  ValidateEnergy(energy);
  ValidateLabels(energy, initialLabels);

  AlphaExpansionResult result;
  result.labels = initialLabels;
  result.initialEnergy = EnergyOf(energy, result.labels);
  result.energy = result.initialEnergy;
  const int k = energy.labelCount;
  if (energy.faceCount == 0 || k == 1)
  {
    result.converged = true;
    if (progress)
    {
      progress(1.0);
    }
    return result;
  }

  ExpansionGraph graph(energy);
  std::vector<int> candidate;
  const long totalMoves = static_cast<long>(options.maxCycles) * k;
  int movesWithoutDecrease = 0;
  for (long move = 0; move < totalMoves; ++move)
  {
    const int alpha = static_cast<int>(move % k);
    graph.Move(result.labels, alpha, candidate);
    const double candidateEnergy = EnergyOf(energy, candidate);
    const double margin = options.relativeTolerance * std::max(1.0, std::abs(result.energy));
    if (candidateEnergy < result.energy - margin)
    {
      result.labels.swap(candidate);
      result.energy = candidateEnergy;
      ++result.appliedMoves;
      movesWithoutDecrease = 0;
    }
    else
    {
      ++movesWithoutDecrease;
    }
    ++result.moves;
    result.energyTrace.push_back(result.energy);
    if (movesWithoutDecrease >= k)
    {
      result.converged = true;
      break;
    }
    if (progress && !progress(static_cast<double>(move + 1) / static_cast<double>(totalMoves)))
    {
      result.aborted = true;
      return result;
    }
  }
  if (progress)
  {
    progress(1.0);
  }
  return result;
}

std::vector<int> OptimalExpansionMove(const PartitionEnergy& energy, const std::vector<int>& labels, int alpha)
{
  ValidateEnergy(energy);
  ValidateLabels(energy, labels);
  if (alpha < 0 || alpha >= energy.labelCount)
  {
    throw PartitionEnergyError("alpha expansion: alpha out of range");
  }
  if (energy.faceCount == 0)
  {
    return {};
  }
  ExpansionGraph graph(energy);
  std::vector<int> result;
  graph.Move(labels, alpha, result);
  return result;
}

} // namespace shapediameter
