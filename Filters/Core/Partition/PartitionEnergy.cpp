// SPDX-License-Identifier: BSD-3-Clause
#include "Partition/PartitionEnergy.h"

#include "ExactSum.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <numeric>
#include <string>

namespace shapediameter
{
namespace
{

constexpr double kPi = 3.14159265358979323846;

/// Checks without ordered comparisons on NaN (they raise FE_INVALID when traps are on).
bool InRange(double value, double low, double high)
{
  return std::isfinite(value) && value >= low && value <= high;
}

void ValidateOptions(const PartitionEnergyOptions& options)
{
  CheckRange(options.Lambda, LambdaRange, "partition energy: Lambda");
  CheckRange(options.Epsilon, EpsilonRange, "partition energy: Epsilon");
  CheckRange(options.ConvexityFactor, ConvexityFactorRange, "partition energy: ConvexityFactor");
  CheckRange(options.MinAngleRatio, MinAngleRatioRange, "partition energy: MinAngleRatio");
}

/// Number of CSR entries; an empty graph may come without any array.
std::size_t EntryCount(const DualGraphView& graph)
{
  return graph.Offsets == nullptr ? 0 : static_cast<std::size_t>(graph.Offsets[graph.FaceCount]);
}

/// Offsets, neighbour range, no self loops, symmetry.
void ValidateTopology(const DualGraphView& graph, const ParallelFor& parallelFor)
{
  if (graph.Offsets == nullptr && graph.FaceCount == 0)
  {
    return;
  }
  if (graph.Offsets == nullptr)
  {
    throw Error("dual graph: offsets are missing");
  }
  if (graph.Offsets[0] != 0)
  {
    throw Error("dual graph: offsets must start at 0");
  }
  const std::size_t n = graph.FaceCount;
  for (std::size_t f = 0; f < n; ++f)
  {
    if (graph.Offsets[f + 1] < graph.Offsets[f])
    {
      throw Error("dual graph: offsets decrease at face " + std::to_string(f));
    }
  }
  const std::size_t entryCount = EntryCount(graph);
  if (entryCount > 0 && graph.Neighbors == nullptr)
  {
    throw Error("dual graph: neighbour indices are missing");
  }
  // The neighbour lists, checked in parallel; the error is the lowest failing face's, so it
  // does not depend on the thread split (and nothing is thrown on a worker thread).
  const auto faceCount = static_cast<std::int64_t>(n);
  auto problemOf = [&](std::size_t f) -> std::string {
    for (std::int64_t e = graph.Offsets[f]; e < graph.Offsets[f + 1]; ++e)
    {
      const std::int64_t g = graph.Neighbors[e];
      if (g < 0 || g >= faceCount)
      {
        return "dual graph: neighbour index out of range at face " + std::to_string(f);
      }
      if (g == static_cast<std::int64_t>(f))
      {
        return "dual graph: face " + std::to_string(f) + " is its own neighbour";
      }
      const std::int64_t* begin = graph.Neighbors + graph.Offsets[g];
      const std::int64_t* end = graph.Neighbors + graph.Offsets[g + 1];
      if (std::find(begin, end, static_cast<std::int64_t>(f)) == end)
      {
        return "dual graph: not symmetric, face " + std::to_string(g) + " does not list its neighbour " +
          std::to_string(f);
      }
    }
    return {};
  };
  std::atomic<std::size_t> firstBad{ n };
  parallelFor(n, [&](std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end && f < firstBad.load(std::memory_order_relaxed); ++f)
    {
      if (!problemOf(f).empty())
      {
        std::size_t current = firstBad.load(std::memory_order_relaxed);
        while (f < current && !firstBad.compare_exchange_weak(current, f, std::memory_order_relaxed))
        {
        }
        return;
      }
    }
  });
  if (firstBad.load() < n)
  {
    throw Error(problemOf(firstBad.load()));
  }
}

/// The factors that make E a discretisation of an energy over the surface (see the header):
/// data cost times area / mean area, pair weight times edge length * FaceCount / sqrt(total
/// area). Fallbacks for a surface of zero total area: data factor 1, pair factor edge length /
/// mean edge length (1 when that is 0 too).
struct GeometricWeights
{
  std::vector<double> face; ///< empty = all 1
  double perUnitLength = 0.0; ///< 0 = all pair factors 1
};

GeometricWeights ComputeGeometricWeights(const DualGraphView& graph, const PartitionEnergyOptions& options)
{
  GeometricWeights weights;
  if (!options.GeometricWeights || graph.FaceCount == 0)
  {
    return weights;
  }
  const double totalArea = std::accumulate(graph.FaceArea, graph.FaceArea + graph.FaceCount, 0.0);
  if (totalArea > 0.0 && std::isfinite(totalArea))
  {
    const AreaScale scale = AreaScaleOf(totalArea, graph.FaceCount);
    weights.face.assign(graph.FaceArea, graph.FaceArea + graph.FaceCount);
    for (double& w : weights.face)
    {
      w /= scale.MeanArea;
    }
    weights.perUnitLength = scale.PerUnitLength;
    return weights;
  }
  double sum = 0.0;
  std::size_t count = 0;
  for (std::size_t f = 0; f < graph.FaceCount; ++f)
  {
    for (std::int64_t e = graph.Offsets[f]; e < graph.Offsets[f + 1]; ++e)
    {
      if (graph.Neighbors[e] > static_cast<std::int64_t>(f))
      {
        sum += graph.EdgeLength[e];
        ++count;
      }
    }
  }
  const double mean = count > 0 ? sum / static_cast<double>(count) : 0.0;
  weights.perUnitLength = mean > 0.0 && std::isfinite(mean) ? 1.0 / mean : 0.0;
  return weights;
}

} // namespace

DualGraphView MakeDualGraphView(const FaceGraph& graph)
{
  DualGraphView view;
  view.Offsets = graph.Offsets.data();
  view.Neighbors = graph.Neighbors.data();
  view.NormalAngle = graph.NormalAngles.data();
  view.Concave = graph.Concave.data();
  view.EdgeLength = graph.SharedEdgeLengths.data();
  view.FaceArea = graph.Areas.data();
  view.FaceCenter = graph.Centers.data();
  view.FaceCount = graph.FaceCount();
  return view;
}

namespace
{
void CheckLabels(const PartitionEnergy& energy, const std::vector<int>& labels)
{
  if (labels.size() != energy.FaceCount)
  {
    throw Error("partition energy: " + std::to_string(labels.size()) + " labels for " +
      std::to_string(energy.FaceCount) + " faces");
  }
  for (std::size_t f = 0; f < energy.FaceCount; ++f)
  {
    if (labels[f] < 0 || labels[f] >= energy.LabelCount)
    {
      throw Error("partition energy: label out of range at face " + std::to_string(f));
    }
  }
}
} // namespace

double PartitionEnergy::Evaluate(const std::vector<int>& labels) const
{
  CheckLabels(*this, labels);
  double data = 0.0;
  for (std::size_t f = 0; f < FaceCount; ++f)
  {
    data += DataCost(f, labels[f]);
  }
  double smoothness = 0.0;
  for (std::size_t p = 0; p < PairWeight.size(); ++p)
  {
    if (labels[static_cast<std::size_t>(PairFirst[p])] != labels[static_cast<std::size_t>(PairSecond[p])])
    {
      smoothness += PairWeight[p];
    }
  }
  return data + smoothness;
}

double PartitionEnergy::EvaluateExactly(const std::vector<int>& labels) const
{
  CheckLabels(*this, labels);
  ExactSum sum;
  for (std::size_t f = 0; f < FaceCount; ++f)
  {
    sum.Add(DataCost(f, labels[f]));
  }
  for (std::size_t p = 0; p < PairWeight.size(); ++p)
  {
    if (labels[static_cast<std::size_t>(PairFirst[p])] != labels[static_cast<std::size_t>(PairSecond[p])])
    {
      sum.Add(PairWeight[p]);
    }
  }
  return sum.Rounded();
}

double SmoothnessTerm(double normalAngle, bool concave, const PartitionEnergyOptions& options)
{
  const double angle = std::isfinite(normalAngle) ? std::clamp(normalAngle, 0.0, kPi) : 0.0;
  const double scaled = concave ? angle : options.ConvexityFactor * angle;
  return -std::log(std::max(scaled / kPi, options.MinAngleRatio));
}

void ValidateDualGraph(const DualGraphView& graph, bool requireGeometry, const ParallelFor& parallelFor)
{
  ValidateTopology(graph, parallelFor);
  if (requireGeometry && graph.FaceCount > 0)
  {
    if (graph.FaceArea == nullptr)
    {
      throw Error("dual graph: face areas are missing (needed for geometric weights)");
    }
    for (std::size_t f = 0; f < graph.FaceCount; ++f)
    {
      if (!InRange(graph.FaceArea[f], 0.0, std::numeric_limits<double>::max()))
      {
        throw Error("dual graph: area of face " + std::to_string(f) + " is negative, NaN or infinite");
      }
    }
  }
  const std::size_t entryCount = EntryCount(graph);
  if (entryCount == 0)
  {
    return;
  }
  if (graph.NormalAngle == nullptr || graph.Concave == nullptr)
  {
    throw Error("dual graph: normal angles or concave flags are missing");
  }
  if (requireGeometry && graph.EdgeLength == nullptr)
  {
    throw Error("dual graph: edge lengths are missing (needed for geometric weights)");
  }
  for (std::size_t e = 0; e < entryCount; ++e)
  {
    if (!std::isfinite(graph.NormalAngle[e]))
    {
      throw Error("dual graph: normal angle " + std::to_string(e) + " is NaN or infinite");
    }
    if (requireGeometry && !InRange(graph.EdgeLength[e], 0.0, std::numeric_limits<double>::max()))
    {
      throw Error("dual graph: edge length " + std::to_string(e) + " is negative, NaN or infinite");
    }
  }
}

namespace
{
/// BuildPartitionEnergy after the checks of the options and of the graph.
PartitionEnergy BuildCheckedPartitionEnergy(Eigen::Ref<const PosteriorMatrix> posteriors,
  const DualGraphView& graph, const PartitionEnergyOptions& options, const ParallelFor& parallelFor)
{
  const std::size_t n = graph.FaceCount;
  if (static_cast<std::size_t>(posteriors.rows()) != n || posteriors.cols() < 1)
  {
    throw Error("partition energy: posteriors must be FaceCount x k with k >= 1");
  }
  if (!posteriors.allFinite())
  {
    for (std::size_t f = 0; f < n; ++f)
    {
      if (!posteriors.row(static_cast<Eigen::Index>(f)).allFinite())
      {
        throw Error("partition energy: posterior of face " + std::to_string(f) + " is NaN or infinite");
      }
    }
  }
  PartitionEnergy energy;
  energy.FaceCount = n;
  energy.LabelCount = static_cast<int>(posteriors.cols());
  const auto k = static_cast<std::size_t>(energy.LabelCount);
  energy.DataCosts.resize(n * k);
  const GeometricWeights weights = ComputeGeometricWeights(graph, options);
  // Pairs in the order of their lower face: each face writes its own data costs and pairs
  // (slots from a prefix sum), so the result does not depend on the thread split.
  std::vector<std::size_t> pairStart(n + 1, 0);
  parallelFor(n, [&](std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f)
    {
      const double faceWeight = weights.face.empty() ? 1.0 : weights.face[f];
      for (std::size_t l = 0; l < k; ++l)
      {
        energy.DataCosts[f * k + l] =
          WeightedDataCost(faceWeight, posteriors(static_cast<Eigen::Index>(f), static_cast<Eigen::Index>(l)), options);
      }
      std::size_t higher = 0;
      for (std::int64_t e = graph.Offsets[f]; e < graph.Offsets[f + 1]; ++e)
      {
        higher += graph.Neighbors[e] > static_cast<std::int64_t>(f) ? 1 : 0;
      }
      pairStart[f + 1] = higher;
    }
  });
  std::partial_sum(pairStart.begin(), pairStart.end(), pairStart.begin());
  energy.PairFirst.resize(pairStart[n]);
  energy.PairSecond.resize(pairStart[n]);
  energy.PairWeight.resize(pairStart[n]);
  parallelFor(n, [&](std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f)
    {
      std::size_t pair = pairStart[f];
      for (std::int64_t e = graph.Offsets[f]; e < graph.Offsets[f + 1]; ++e)
      {
        const std::int64_t g = graph.Neighbors[e];
        if (g <= static_cast<std::int64_t>(f))
        {
          continue;
        }
        energy.PairFirst[pair] = static_cast<std::int64_t>(f);
        energy.PairSecond[pair] = g;
        energy.PairWeight[pair] = PairWeight(graph.NormalAngle[e], graph.Concave[e] != 0,
          weights.perUnitLength > 0.0 ? graph.EdgeLength[e] : 0.0, weights.perUnitLength, options);
        ++pair;
      }
    }
  });
  return energy;
}
} // namespace

PartitionEnergy BuildPartitionEnergy(Eigen::Ref<const PosteriorMatrix> posteriors,
  const DualGraphView& graph, const PartitionEnergyOptions& options, const ParallelFor& parallelFor)
{
  ValidateOptions(options);
  ValidateDualGraph(graph, options.GeometricWeights, parallelFor);
  return BuildCheckedPartitionEnergy(posteriors, graph, options, parallelFor);
}

PartitionEnergy BuildPartitionEnergyOnValidGraph(Eigen::Ref<const PosteriorMatrix> posteriors,
  const DualGraphView& graph, const PartitionEnergyOptions& options, const ParallelFor& parallelFor)
{
  ValidateOptions(options);
  return BuildCheckedPartitionEnergy(posteriors, graph, options, parallelFor);
}

std::vector<int> MostProbableLabels(const PartitionEnergy& energy)
{
  return MostProbableLabels(energy.DataCosts.data(), energy.FaceCount, energy.LabelCount);
}

std::vector<int> MostProbableLabels(const double* dataCosts, std::size_t faceCount, int labelCount)
{
  std::vector<int> labels(faceCount, 0);
  for (std::size_t f = 0; f < faceCount; ++f)
  {
    const double* costs = dataCosts + f * static_cast<std::size_t>(std::max(labelCount, 0));
    for (int l = 1; l < labelCount; ++l)
    {
      if (costs[l] < costs[labels[f]])
      {
        labels[f] = l;
      }
    }
  }
  return labels;
}

AreaScale AreaScaleOf(double totalArea, std::size_t faceCount)
{
  const auto faces = static_cast<double>(faceCount);
  return { totalArea / faces, faces / std::sqrt(totalArea) };
}

double WeightedDataCost(double faceWeight, double posterior, const PartitionEnergyOptions& options)
{
  return faceWeight * -std::log(std::clamp(posterior, 0.0, 1.0) + options.Epsilon);
}

double PairWeight(double normalAngle, bool concave, double edgeLength, double perUnitLength,
  const PartitionEnergyOptions& options)
{
  double weight = options.Lambda * SmoothnessTerm(normalAngle, concave, options);
  if (perUnitLength > 0.0)
  {
    weight *= edgeLength * perUnitLength;
  }
  return weight;
}

std::vector<int> HierarchyLevel(const std::vector<int>& clusters, int level)
{
  if (level < 1)
  {
    throw Error("hierarchy: level must be at least 1");
  }
  std::vector<int> result(clusters.size());
  for (std::size_t f = 0; f < clusters.size(); ++f)
  {
    if (clusters[f] < 0)
    {
      throw Error("hierarchy: negative cluster at face " + std::to_string(f));
    }
    result[f] = std::min(clusters[f], level);
  }
  return result;
}

ConnectedSegments FindConnectedSegments(const DualGraphView& graph, const std::vector<int>& labels,
  const std::vector<double>& faceAreas, const ParallelFor& parallelFor)
{
  ValidateTopology(graph, parallelFor);
  return FindConnectedSegmentsOnValidGraph(graph, labels, faceAreas);
}

ConnectedSegments FindConnectedSegmentsOnValidGraph(const DualGraphView& graph, const std::vector<int>& labels,
  const std::vector<double>& faceAreas)
{
  const std::size_t n = graph.FaceCount;
  if (labels.size() != n || faceAreas.size() != n)
  {
    throw Error("segments: labels and face areas need one value per face");
  }
  for (std::size_t f = 0; f < n; ++f)
  {
    if (!InRange(faceAreas[f], 0.0, std::numeric_limits<double>::max()))
    {
      throw Error("segments: area of face " + std::to_string(f) + " is negative, NaN or infinite");
    }
  }
  // Flood fill in face order: components are discovered in order of their lowest face.
  std::vector<int> component(n, -1);
  std::vector<double> area;
  std::vector<int> componentLabel;
  std::vector<std::size_t> stack;
  for (std::size_t seed = 0; seed < n; ++seed)
  {
    if (component[seed] >= 0)
    {
      continue;
    }
    const int id = static_cast<int>(area.size());
    area.push_back(0.0);
    componentLabel.push_back(labels[seed]);
    component[seed] = id;
    stack.push_back(seed);
    while (!stack.empty())
    {
      const std::size_t f = stack.back();
      stack.pop_back();
      area[static_cast<std::size_t>(id)] += faceAreas[f];
      for (std::int64_t e = graph.Offsets[f]; e < graph.Offsets[f + 1]; ++e)
      {
        const auto g = static_cast<std::size_t>(graph.Neighbors[e]);
        if (component[g] < 0 && labels[g] == labels[seed])
        {
          component[g] = id;
          stack.push_back(g);
        }
      }
    }
  }
  std::vector<int> order(area.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
    [&](int a, int b) { return area[static_cast<std::size_t>(a)] > area[static_cast<std::size_t>(b)]; });
  std::vector<int> rank(area.size());
  ConnectedSegments result;
  for (std::size_t r = 0; r < order.size(); ++r)
  {
    rank[static_cast<std::size_t>(order[r])] = static_cast<int>(r);
    result.Area.push_back(area[static_cast<std::size_t>(order[r])]);
    result.Label.push_back(componentLabel[static_cast<std::size_t>(order[r])]);
  }
  result.Segment.resize(n);
  for (std::size_t f = 0; f < n; ++f)
  {
    result.Segment[f] = rank[static_cast<std::size_t>(component[f])];
  }
  return result;
}

} // namespace shapediameter
