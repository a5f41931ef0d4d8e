// SPDX-License-Identifier: BSD-3-Clause
#include "Partition/DensityModes.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace shapediameter
{

namespace
{

void CheckInput(ValuesView values, ValuesView weights, const DensityModesOptions& options)
{
  if (values.size() == 0)
  {
    throw Error("no values");
  }
  if (weights.size() != values.size())
  {
    throw Error("values and weights differ in length");
  }
  for (Eigen::Index i = 0; i < values.size(); ++i)
  {
    if (!std::isfinite(values[i]))
    {
      throw Error("non-finite value at index " + std::to_string(i));
    }
    if (!std::isfinite(weights[i]) || weights[i] < 0)
    {
      throw Error("negative or non-finite weight at index " + std::to_string(i));
    }
  }
  // Wider than the user-facing ModeBandwidthRange etc. (checked by ValidatePartitionOptions):
  // the fine level widens the bandwidth of a part up to 1 (PartRefinement.cpp).
  if (!(options.Bandwidth > 0 && options.Bandwidth <= 1) || !(options.MinimumProminence >= 0) ||
    !(options.MinimumValleyDepth >= 0 && options.MinimumValleyDepth <= 1) ||
    options.MaximumModes < 1 || options.BinCount < 2 || options.GridSize < 3 || !(options.MinSigmaRelative > 0))
  {
    throw Error("invalid density-mode options");
  }
}

struct PeakSeparation
{
  double Prominence; ///< height above the key saddle, relative to the highest point
  double ValleyDepth; ///< height above the key saddle, relative to the peak's own height
};

/// How far each local maximum rises above its key saddle (see the header comment, step 2).
std::vector<PeakSeparation> Separations(const std::vector<double>& density, const std::vector<int>& peaks)
{
  const double highest = *std::max_element(density.begin(), density.end());
  const int last = static_cast<int>(density.size()) - 1;
  std::vector<PeakSeparation> separations;
  for (const int peak : peaks)
  {
    // Towards each side: the lowest point before a higher one; a side that reaches the end of
    // the range without a higher point does not bound the peak (saddle 0 there).
    const double height = density[static_cast<std::size_t>(peak)];
    double saddle = 0.0;
    for (const int step : { -1, 1 })
    {
      double lowest = height;
      int i = peak;
      while (i + step >= 0 && i + step <= last && density[static_cast<std::size_t>(i + step)] <= height)
      {
        i += step;
        lowest = std::min(lowest, density[static_cast<std::size_t>(i)]);
      }
      const bool bounded = i + step >= 0 && i + step <= last;
      saddle = std::max(saddle, bounded ? lowest : 0.0);
    }
    separations.push_back({ (height - saddle) / highest, (height - saddle) / height });
  }
  return separations;
}

/// The values' weights as used by every step: the given ones, or 1 each when they sum to 0.
struct SampleWeights
{
  ValuesView Weights;
  bool Unweighted;
  double Total;

  double operator()(Eigen::Index i) const { return Unweighted ? 1.0 : Weights[i]; }
};

/// The density on its evaluation grid.
struct GridDensity
{
  std::vector<double> Grid;
  std::vector<double> Density;
};

/// Weighted histogram of the values, then the Gaussian kernel density on the grid (kernel cut
/// at 6 sigma; header step 1).
GridDensity KernelDensity(ValuesView values, const SampleWeights& weightOf, double low, double span,
  const DensityModesOptions& options)
{
  const auto bins = static_cast<std::size_t>(options.BinCount);
  std::vector<double> histogram(bins, 0.0);
  const double binWidth = span / static_cast<double>(bins);
  for (Eigen::Index i = 0; i < values.size(); ++i)
  {
    const auto bin = std::min(bins - 1, static_cast<std::size_t>((values[i] - low) / binWidth));
    histogram[bin] += weightOf(i) / weightOf.Total;
  }
  const double bandwidth = options.Bandwidth * span;
  const auto points = static_cast<std::size_t>(options.GridSize);
  const double gridLow = low - 3 * bandwidth;
  const double gridStep = (span + 6 * bandwidth) / static_cast<double>(points - 1);
  GridDensity result{ std::vector<double>(points), std::vector<double>(points, 0.0) };
  for (std::size_t g = 0; g < points; ++g)
  {
    result.Grid[g] = gridLow + gridStep * static_cast<double>(g);
  }
  for (std::size_t b = 0; b < bins; ++b)
  {
    if (histogram[b] == 0)
    {
      continue;
    }
    const double centre = low + (static_cast<double>(b) + 0.5) * binWidth;
    const auto first = static_cast<std::size_t>(std::max(0.0, std::floor((centre - 6 * bandwidth - gridLow) / gridStep)));
    const auto end = std::min(points, static_cast<std::size_t>(std::ceil((centre + 6 * bandwidth - gridLow) / gridStep)) + 1);
    for (std::size_t g = first; g < end; ++g)
    {
      const double z = (result.Grid[g] - centre) / bandwidth;
      result.Density[g] += histogram[b] * std::exp(-0.5 * z * z);
    }
  }
  return result;
}

/// The density's peaks, the ones kept as modes (most prominent first, up to MaximumModes) and
/// the valleys between neighbouring kept modes, into result (header steps 2-3).
void SelectModes(const GridDensity& density, const DensityModesOptions& options, DensityModesResult& result)
{
  const std::vector<double>& grid = density.Grid;
  const std::vector<double>& values = density.Density;
  std::vector<int> peaks;
  for (std::size_t g = 1; g + 1 < values.size(); ++g)
  {
    if (values[g] >= values[g - 1] && values[g] > values[g + 1])
    {
      peaks.push_back(static_cast<int>(g));
    }
  }
  const std::vector<PeakSeparation> separation = Separations(values, peaks);
  std::vector<std::size_t> order(peaks.size());
  std::iota(order.begin(), order.end(), std::size_t{ 0 });
  std::stable_sort(order.begin(), order.end(),
    [&](std::size_t a, std::size_t b) { return separation[a].Prominence > separation[b].Prominence; });
  std::vector<std::size_t> kept;
  for (const std::size_t p : order)
  {
    if (separation[p].Prominence >= options.MinimumProminence &&
      separation[p].ValleyDepth >= options.MinimumValleyDepth && static_cast<int>(kept.size()) < options.MaximumModes)
    {
      kept.push_back(p);
    }
  }
  if (kept.empty())
  {
    kept.push_back(order.front()); // the highest peak always has prominence and depth 1
  }
  std::sort(kept.begin(), kept.end());
  for (std::size_t m = 0; m < kept.size(); ++m)
  {
    result.Modes.push_back(grid[static_cast<std::size_t>(peaks[kept[m]])]);
    result.Prominences.push_back(separation[kept[m]].Prominence);
    result.ValleyDepths.push_back(separation[kept[m]].ValleyDepth);
    if (m > 0)
    {
      const auto from = values.begin() + peaks[kept[m - 1]];
      const auto to = values.begin() + peaks[kept[m]] + 1;
      result.Valleys.push_back(grid[static_cast<std::size_t>(std::min_element(from, to) - values.begin())]);
    }
  }
}

/// One Gaussian per basin between the valleys, from the weighted moments of its values, largest
/// mean first (header step 4). A basin whose values all weigh 0 gives no cluster.
void FitBasinGaussians(ValuesView values, const SampleWeights& weightOf, double span,
  const DensityModesOptions& options, DensityModesResult& result)
{
  const std::size_t basins = result.Modes.size();
  std::vector<double> sum(basins, 0.0), sumWeights(basins, 0.0), sumSquares(basins, 0.0);
  std::vector<std::size_t> basinOf(static_cast<std::size_t>(values.size()));
  for (Eigen::Index i = 0; i < values.size(); ++i)
  {
    const auto basin = static_cast<std::size_t>(
      std::upper_bound(result.Valleys.begin(), result.Valleys.end(), values[i]) - result.Valleys.begin());
    basinOf[static_cast<std::size_t>(i)] = basin;
    sum[basin] += weightOf(i) * values[i];
    sumWeights[basin] += weightOf(i);
  }
  std::vector<double> means(basins);
  for (std::size_t c = 0; c < basins; ++c)
  {
    means[c] = sumWeights[c] > 0 ? sum[c] / sumWeights[c] : result.Modes[c];
  }
  for (Eigen::Index i = 0; i < values.size(); ++i)
  {
    const std::size_t basin = basinOf[static_cast<std::size_t>(i)];
    sumSquares[basin] += weightOf(i) * (values[i] - means[basin]) * (values[i] - means[basin]);
  }
  const double sigmaFloor = options.MinSigmaRelative * span;
  GaussianMixtureModel& model = result.Model;
  // Largest mean first: the basins are in increasing order and their means increase with them.
  for (std::size_t c = basins; c-- > 0;)
  {
    if (!(sumWeights[c] > 0))
    {
      continue;
    }
    model.Means.push_back(means[c]);
    model.Sigmas.push_back(std::max(sigmaFloor, std::sqrt(sumSquares[c] / sumWeights[c])));
    model.Weights.push_back(sumWeights[c] / weightOf.Total);
  }
}

/// The unweighted log-likelihood of the values under the mixture (each term floored at 1e-300).
double LogLikelihood(ValuesView values, const GaussianMixtureModel& model)
{
  double logLikelihood = 0.0;
  for (Eigen::Index i = 0; i < values.size(); ++i)
  {
    double likelihood = 0.0;
    for (std::size_t c = 0; c < model.Means.size(); ++c)
    {
      const double z = (values[i] - model.Means[c]) / model.Sigmas[c];
      likelihood += model.Weights[c] * std::exp(-0.5 * z * z) / (model.Sigmas[c] * std::sqrt(2 * M_PI));
    }
    logLikelihood += std::log(std::max(likelihood, 1e-300));
  }
  return logLikelihood;
}

} // namespace

DensityModesResult FitDensityModes(ValuesView values, ValuesView weights, const DensityModesOptions& options)
{
  CheckInput(values, weights, options);
  const double weightSum = weights.sum();
  const bool unweighted = !(weightSum > 0);
  const SampleWeights weightOf{ weights, unweighted, unweighted ? static_cast<double>(values.size()) : weightSum };
  const double low = values.minCoeff();
  const double high = values.maxCoeff();
  const double span = high - low;

  DensityModesResult result;
  GaussianMixtureModel& model = result.Model;
  model.SampleCount = static_cast<std::size_t>(values.size());
  if (!(span > 0))
  {
    model.Means = { low };
    model.Sigmas = { options.MinSigmaRelative * std::max(std::abs(low), 1.0) };
    model.Weights = { 1.0 };
    result.Modes = { low };
    result.Prominences = { 1.0 };
    return result;
  }
  SelectModes(KernelDensity(values, weightOf, low, span, options), options, result);
  FitBasinGaussians(values, weightOf, span, options, result);
  model.LogLikelihood = LogLikelihood(values, model);
  model.Converged = true;
  return result;
}

} // namespace shapediameter
