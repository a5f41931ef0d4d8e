// SPDX-License-Identifier: BSD-3-Clause
#include "Partition/AlphaExpansion.h"

#include "Partition/MaxFlow.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

namespace shapediameter
{
namespace
{

/// Checks without ordered comparisons on NaN (they raise FE_INVALID when traps are on).
bool InRange(double value, double low, double high)
{
  return std::isfinite(value) && value >= low && value <= high;
}

void ValidateLabels(const PartitionEnergy& energy, const std::vector<int>& labels)
{
  if (labels.size() != energy.FaceCount)
  {
    throw Error("alpha expansion: " + std::to_string(labels.size()) +
      " labels for " + std::to_string(energy.FaceCount) + " faces");
  }
  for (std::size_t f = 0; f < labels.size(); ++f)
  {
    if (labels[f] < 0 || labels[f] >= energy.LabelCount)
    {
      throw Error("alpha expansion: label out of range at face " + std::to_string(f));
    }
  }
}

} // namespace

void ValidateEnergyForCut(const PartitionEnergy& energy)
{
  if (energy.LabelCount < 1 ||
    energy.DataCosts.size() != energy.FaceCount * static_cast<std::size_t>(energy.LabelCount) ||
    energy.PairFirst.size() != energy.PairWeight.size() ||
    energy.PairSecond.size() != energy.PairWeight.size())
  {
    throw Error("alpha expansion: the energy has inconsistent sizes");
  }
  for (double cost : energy.DataCosts)
  {
    if (!std::isfinite(cost))
    {
      throw Error("alpha expansion: a data cost is NaN or infinite");
    }
  }
  const auto n = static_cast<std::int64_t>(energy.FaceCount);
  for (std::size_t p = 0; p < energy.PairWeight.size(); ++p)
  {
    const std::int64_t a = energy.PairFirst[p], b = energy.PairSecond[p];
    if (a < 0 || b < 0 || a >= n || b >= n || a == b)
    {
      throw Error("alpha expansion: pair " + std::to_string(p) + " has invalid faces");
    }
    if (!InRange(energy.PairWeight[p], 0.0, std::numeric_limits<double>::max()))
    {
      throw Error("alpha expansion: pair weight " + std::to_string(p) + " is negative, NaN or infinite");
    }
  }
}

namespace
{

/// E without validation (labels known valid): sum of data costs plus cut pair weights.
double EnergyOf(const PartitionEnergy& energy, const std::vector<int>& labels)
{
  double data = 0.0;
  for (std::size_t f = 0; f < energy.FaceCount; ++f)
  {
    data += energy.DataCost(f, labels[f]);
  }
  double smoothness = 0.0;
  for (std::size_t p = 0; p < energy.PairWeight.size(); ++p)
  {
    if (labels[static_cast<std::size_t>(energy.PairFirst[p])] !=
      labels[static_cast<std::size_t>(energy.PairSecond[p])])
    {
      smoothness += energy.PairWeight[p];
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
  ExpansionGraph(const PartitionEnergy& energy, const std::function<void(const MaxFlowGraph&)>& beforeEachCut)
    : Energy(energy)
    , BeforeEachCut(beforeEachCut)
    , Graph(energy.FaceCount, energy.PairFirst, energy.PairSecond)
  {
    const std::size_t arcCount = 2 * energy.PairWeight.size();
    ArcWeight.resize(arcCount);
    for (std::size_t arc = 0; arc < arcCount; ++arc)
    {
      ArcWeight[arc] = energy.PairWeight[static_cast<std::size_t>(Graph.ArcPair(static_cast<std::int32_t>(arc)))];
    }
  }

  /// Writes into `result` the optimal move from `labels` towards alpha.
  void Move(const std::vector<int>& labels, int alpha, std::vector<int>& result)
  {
    // Pair table of faces (a, b) over (y_a, y_b): A = E00 = w[x_a != x_b], B = E01 =
    // w[x_a != alpha], C = E10 = w[x_b != alpha], D = E11 = 0, written as
    //   A + u_a y_a + u_b y_b + c_ab (1 - y_a) y_b + c_ba y_a (1 - y_b),
    // u_a + u_b = D - A, c_ab = B - A - u_b >= 0, c_ba = C - A - u_a >= 0 (possible because
    // B + C >= A + D). The unaries are split evenly where the arcs allow (at most one of the
    // two clips applies, so the split does not depend on which face is called a): a pair of
    // equal labels then costs w in both arc directions and adds no terminal capacity, and the
    // max-flow only routes what the data term really asks for (the one-sided form
    // u_a = C - A, u_b = D - C put +-w on both faces of every edge and made the flow carry them
    // across the whole surface, several times slower). Each face fills its own arcs and
    // terminal capacities, in arc order. The constant A is dropped (E is evaluated directly
    // afterwards).
    const std::size_t n = Energy.FaceCount;
    for (std::size_t f = 0; f < n; ++f)
    {
      const int label = labels[f];
      const double keepCost = Energy.DataCost(f, label);
      double alphaCost = Energy.DataCost(f, alpha);
      const std::int32_t end = Graph.FirstArc(f + 1);
      for (std::int32_t arc = Graph.FirstArc(f); arc < end; ++arc)
      {
        const int other = labels[static_cast<std::size_t>(Graph.ArcHead(arc))];
        const double w = ArcWeight[static_cast<std::size_t>(arc)];
        const double cutNow = label != other ? w : 0.0;    // A
        const double cutIfOther = label != alpha ? w : 0.0; // B: f keeps, the other takes alpha
        const double cutIfThis = other != alpha ? w : 0.0;  // C: f takes alpha, the other keeps
        double unaryThis = -0.5 * cutNow;
        double unaryOther = -0.5 * cutNow;
        if (unaryThis > cutIfThis - cutNow)
        {
          unaryThis = cutIfThis - cutNow;
          unaryOther = -cutNow - unaryThis;
        }
        if (unaryOther > cutIfOther - cutNow)
        {
          unaryOther = cutIfOther - cutNow;
          unaryThis = -cutNow - unaryOther;
        }
        alphaCost += unaryThis;
        Graph.SetArcCapacity(arc, std::max(0.0, cutIfOther - cutNow - unaryOther));
      }
      // s->f is cut when f takes alpha, f->t when it keeps its label (MaxFlowGraph removes the
      // part both have in common).
      Graph.SetTerminalCapacities(f, alphaCost, keepCost);
    }
    if (BeforeEachCut)
    {
      BeforeEachCut(Graph);
    }
    Graph.Solve();
    result.resize(n);
    for (std::size_t f = 0; f < n; ++f)
    {
      // The source side (reachable from s in the residual graph) keeps its label.
      result[f] = Graph.InSourceSet(f) ? labels[f] : alpha;
    }
  }

private:
  const PartitionEnergy& Energy;
  const std::function<void(const MaxFlowGraph&)>& BeforeEachCut;
  MaxFlowGraph Graph;
  std::vector<double> ArcWeight; ///< the pair weight of every arc, in arc order
};

} // namespace

AlphaExpansionResult MinimizeByAlphaExpansion(
  const PartitionEnergy& energy, const AlphaExpansionOptions& options, const ProgressCallback& progress)
{
  ValidateEnergyForCut(energy);
  return MinimizeByAlphaExpansion(energy, MostProbableLabels(energy), options, progress);
}

AlphaExpansionResult MinimizeByAlphaExpansion(const PartitionEnergy& energy,
  const std::vector<int>& initialLabels, const AlphaExpansionOptions& options,
  const ProgressCallback& progress)
{
  if (options.MaxCycles < 1 || options.MaxCycles > 1000000)
  {
    throw Error("alpha expansion: MaxCycles must be in [1, 1e6]");
  }
  if (!InRange(options.RelativeTolerance, 0.0, 1.0))
  {
    throw Error("alpha expansion: RelativeTolerance must be in [0, 1]");
  }
  ValidateEnergyForCut(energy);
  ValidateLabels(energy, initialLabels);

  AlphaExpansionResult result;
  result.Labels = initialLabels;
  result.InitialEnergy = EnergyOf(energy, result.Labels);
  result.Energy = result.InitialEnergy;
  const int k = energy.LabelCount;
  if (energy.FaceCount == 0 || k == 1)
  {
    result.Converged = true;
    if (progress)
    {
      progress(1.0);
    }
    return result;
  }

  ExpansionGraph graph(energy, options.BeforeEachCut);
  std::vector<int> candidate;
  const long totalMoves = static_cast<long>(options.MaxCycles) * k;
  int movesWithoutDecrease = 0;
  // An alpha-move from labels that no other move has changed since the last alpha-move cannot
  // lower E (an expansion of an expansion of x is an expansion of x): it is counted as tried
  // without solving it.
  std::vector<long> lastTried(static_cast<std::size_t>(k), -1);
  long lastApplied = -1;
  for (long move = 0; move < totalMoves; ++move)
  {
    const int alpha = static_cast<int>(move % k);
    long& previous = lastTried[static_cast<std::size_t>(alpha)];
    const bool known = previous >= 0 && lastApplied <= previous;
    previous = move;
    bool applied = false;
    if (!known)
    {
      graph.Move(result.Labels, alpha, candidate);
      const double candidateEnergy = EnergyOf(energy, candidate);
      const double margin = options.RelativeTolerance * std::max(1.0, std::abs(result.Energy));
      if (candidateEnergy < result.Energy - margin)
      {
        result.Labels.swap(candidate);
        result.Energy = candidateEnergy;
        applied = true;
      }
    }
    if (applied)
    {
      ++result.AppliedMoves;
      lastApplied = move;
      movesWithoutDecrease = 0;
    }
    else
    {
      ++movesWithoutDecrease;
    }
    ++result.Moves;
    result.EnergyTrace.push_back(result.Energy);
    if (movesWithoutDecrease >= k)
    {
      result.Converged = true;
      break;
    }
    if (progress && !progress(static_cast<double>(move + 1) / static_cast<double>(totalMoves)))
    {
      result.Aborted = true;
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
  ValidateEnergyForCut(energy);
  ValidateLabels(energy, labels);
  if (alpha < 0 || alpha >= energy.LabelCount)
  {
    throw Error("alpha expansion: alpha out of range");
  }
  if (energy.FaceCount == 0)
  {
    return {};
  }
  const std::function<void(const MaxFlowGraph&)> noObserver;
  ExpansionGraph graph(energy, noObserver);
  std::vector<int> result;
  graph.Move(labels, alpha, result);
  return result;
}

} // namespace shapediameter
