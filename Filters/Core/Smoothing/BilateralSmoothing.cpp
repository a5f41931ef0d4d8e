// SPDX-License-Identifier: BSD-3-Clause
#include "Smoothing/BilateralSmoothing.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace shapediameter
{

namespace
{

constexpr double LowerSpreadQuantile = 0.02;
constexpr double UpperSpreadQuantile = 0.98;
constexpr std::size_t ProgressBlocks = 20;

void ValidateOptions(const BilateralSmoothingOptions& options)
{
  CheckRange(options.NumberOfIterations, SmoothingIterationsRange, "smoothing: NumberOfIterations");
  CheckRange(options.SpatialSigma, SpatialSigmaRange, "smoothing: SpatialSigma");
  CheckRange(options.NeighborhoodRadius, NeighborhoodRadiusRange, "smoothing: NeighborhoodRadius");
  CheckRange(options.RangeThreshold, RangeThresholdRange, "smoothing: RangeThreshold");
}

// Nearest-rank quantile: the value at index floor(q (n - 1)) of the n sorted values.
std::size_t QuantileRank(double q, std::size_t n)
{
  return static_cast<std::size_t>(std::floor(q * static_cast<double>(n - 1)));
}

double Quantile(std::vector<double>& scratch, double q)
{
  const std::size_t rank = QuantileRank(q, scratch.size());
  std::nth_element(scratch.begin(), scratch.begin() + static_cast<std::ptrdiff_t>(rank), scratch.end());
  return scratch[rank];
}

} // namespace

double RobustSpread(const std::vector<double>& values)
{
  if (values.empty())
  {
    return 0.0;
  }
  std::vector<double> scratch(values);
  const double lower = Quantile(scratch, LowerSpreadQuantile);
  const double upper = Quantile(scratch, UpperSpreadQuantile);
  double spread = upper - lower;
  if (spread == 0.0)
  {
    const auto [minimum, maximum] = std::minmax_element(values.begin(), values.end());
    spread = *maximum - *minimum;
  }
  return spread;
}

double RobustSpreadOverProcesses(const std::vector<double>& values, const ProcessGroup& group)
{
  std::vector<std::int64_t> count{ static_cast<std::int64_t>(values.size()) };
  group.SumInPlace(count);
  if (count[0] == 0)
  {
    return 0.0;
  }
  const auto n = static_cast<std::size_t>(count[0]);
  const std::vector<double> quantiles = OrderStatisticsOverProcesses(values,
    { static_cast<std::int64_t>(QuantileRank(LowerSpreadQuantile, n)),
      static_cast<std::int64_t>(QuantileRank(UpperSpreadQuantile, n)) },
    group);
  const double spread = quantiles[1] - quantiles[0];
  if (spread != 0.0)
  {
    return spread;
  }
  const auto [minimum, maximum] = RangeOverProcesses(values, group);
  return maximum - minimum;
}

BilateralSmoothingResult SmoothBilateral(const FaceGraph& graph, const std::vector<double>& values,
  const BilateralSmoothingOptions& options, const ParallelFor& parallelFor, const ProgressCallback& progress,
  const SmoothingShare* share)
{
  ValidateOptions(options);
  const std::size_t faceCount = graph.FaceCount();
  if (values.size() != faceCount)
  {
    throw Error("got " + std::to_string(values.size()) + " values for " +
      std::to_string(faceCount) + " faces");
  }
  double minimum = faceCount > 0 ? values[0] : 0.0;
  double maximum = minimum;
  for (std::size_t f = 0; f < faceCount; ++f)
  {
    if (!std::isfinite(values[f]))
    {
      throw Error("non-finite value at face " + std::to_string(f));
    }
    minimum = std::min(minimum, values[f]);
    maximum = std::max(maximum, values[f]);
  }
  // Every difference f^i(x) - f(y) then stays finite (f^i(x) stays within [min, max]).
  if (share && share->Own.size() != faceCount)
  {
    throw Error("got " + std::to_string(share->Own.size()) + " face flags for " + std::to_string(faceCount) + " faces");
  }
  if (share)
  {
    minimum = share->Minimum;
    maximum = share->Maximum;
  }
  if (!std::isfinite(maximum - minimum))
  {
    throw Error("the value range overflows");
  }

  BilateralSmoothingResult result;
  result.Values = values;
  const double spread = share ? share->Spread : RobustSpread(values);
  // No difference exceeds max - min, so a larger t is the same t (and stays finite).
  result.RangeThreshold = std::min(options.RangeThreshold * spread, maximum - minimum);
  const double meanEdgeLength = share ? share->MeanEdgeLength : graph.MeanEdgeLength;
  result.SpatialSigma = options.SpatialSigma * meanEdgeLength;
  result.NeighborhoodRadius = NeighborhoodRadiusOf(options, meanEdgeLength);
  if (faceCount == 0 || spread == 0.0 || options.NumberOfIterations == 0 || options.MaxNeighbors == 0 ||
    !(result.SpatialSigma > 0.0))
  {
    if (progress)
    {
      progress(1.0);
    }
    return result;
  }

  const double threshold = result.RangeThreshold;
  const double radius = result.NeighborhoodRadius;
  const double inverseTwoSigmaSquared = 1.0 / (2.0 * result.SpatialSigma * result.SpatialSigma);
  const int iterations = options.NumberOfIterations;
  std::vector<double>& smoothed = result.Values;

  auto smoothRange = [&](std::size_t begin, std::size_t end) {
    DualGeodesicSearch search(graph);
    std::vector<GeodesicNeighbor> neighbors;
    std::vector<double> weights;      // w_x(y)
    std::vector<double> originals;    // f(y)
    std::vector<double> clampedWeights; // c(|f^i(x) - f(y)|) w_x(y)
    for (std::size_t face = begin; face < end; ++face)
    {
      if (share && share->Own[face] == 0)
      {
        continue;
      }
      search.Run(static_cast<std::int64_t>(face), radius, options.MaxNeighbors, neighbors);
      const std::size_t count = neighbors.size();
      if (count == 0)
      {
        continue;
      }
      weights.resize(count);
      originals.resize(count);
      clampedWeights.resize(count);
      for (std::size_t k = 0; k < count; ++k)
      {
        weights[k] = std::exp(-neighbors[k].Distance * neighbors[k].Distance * inverseTwoSigmaSquared);
        originals[k] = values[static_cast<std::size_t>(neighbors[k].Face)];
      }
      double value = values[face];
      for (int iteration = 0; iteration < iterations; ++iteration)
      {
        double denominator = 1.0;
        for (std::size_t k = 0; k < count; ++k)
        {
          clampedWeights[k] = std::abs(value - originals[k]) <= threshold ? weights[k] : 0.0;
          denominator += clampedWeights[k];
        }
        double step = 0.0;
        for (std::size_t k = 0; k < count; ++k)
        {
          step += (clampedWeights[k] / denominator) * (originals[k] - value);
        }
        value += step;
      }
      smoothed[face] = value;
    }
  };

  if (!progress)
  {
    parallelFor(faceCount, smoothRange);
    return result;
  }
  const std::size_t blockSize = (faceCount + ProgressBlocks - 1) / ProgressBlocks;
  for (std::size_t blockBegin = 0; blockBegin < faceCount; blockBegin += blockSize)
  {
    const std::size_t blockEnd = std::min(faceCount, blockBegin + blockSize);
    parallelFor(blockEnd - blockBegin,
      [&](std::size_t begin, std::size_t end) { smoothRange(blockBegin + begin, blockBegin + end); });
    if (!progress(static_cast<double>(blockEnd) / static_cast<double>(faceCount)))
    {
      result.Aborted = blockEnd < faceCount;
      break;
    }
  }
  return result;
}

} // namespace shapediameter
