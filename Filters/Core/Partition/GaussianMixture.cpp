// SPDX-License-Identifier: BSD-3-Clause
#include "Partition/GaussianMixture.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>

namespace shapediameter
{
namespace
{

constexpr double kHalfLogTwoPi = 0.91893853320467274178; // 0.5 ln(2 pi)
constexpr double kWeightFloor = 1e-12;

/// Values reduced to weighted points: EM sees only these. Positions are shifted by `origin`
/// (the data minimum) so that second moments do not cancel for data far from zero.
struct WeightedPoints
{
  std::vector<double> position;     ///< mean of the values of the point, minus origin
  std::vector<double> count;        ///< number of values
  std::vector<double> meanSquareDev; ///< mean squared deviation of the values from position
  double origin = 0.0;
  double total = 0.0;
  std::size_t Size() const { return position.size(); }
};

struct Parameters
{
  std::vector<double> mean; // shifted by origin
  std::vector<double> sigma;
  std::vector<double> weight;
};

/// Checks without ordered comparisons on NaN (they raise FE_INVALID when traps are on).
bool InRange(double value, double low, double high)
{
  return std::isfinite(value) && value >= low && value <= high;
}

/// (r >> 11) * 2^-53: uniform in [0, 1) with 53 random bits, identical on every platform.
double UniformUnit(std::mt19937_64& generator)
{
  return static_cast<double>(generator() >> 11) * (1.0 / 9007199254740992.0);
}

void ValidateOptions(const GaussianMixtureOptions& options)
{
  CheckRange(options.Restarts, RestartsRange, "GMM: Restarts");
  CheckRange(options.MaximumIterations, MaximumIterationsRange, "GMM: MaximumIterations");
  if (!InRange(options.Tolerance, 0.0, 1.0))
  {
    throw Error("GMM: Tolerance must be in [0, 1]");
  }
  if (options.ScreeningIterations < 1 || options.ScreeningIterations > 1000000)
  {
    throw Error("GMM: ScreeningIterations must be in [1, 1e6]");
  }
  if (options.BinCount < 0 || options.BinCount > 10000000)
  {
    throw Error("GMM: BinCount must be in [0, 1e7]");
  }
  if (!InRange(options.MinSigmaRelative, 1e-12, 1.0))
  {
    throw Error("GMM: MinSigmaRelative must be in [1e-12, 1]");
  }
}

void MinMaxChecked(ValuesView values, double& minValue, double& maxValue)
{
  if (values.size() == 0)
  {
    throw Error("GMM: no values to fit");
  }
  minValue = std::numeric_limits<double>::infinity();
  maxValue = -std::numeric_limits<double>::infinity();
  for (Eigen::Index i = 0; i < values.size(); ++i)
  {
    const double v = values[i];
    if (!std::isfinite(v))
    {
      throw Error("GMM: value " + std::to_string(i) + " is NaN or infinite");
    }
    minValue = std::min(minValue, v);
    maxValue = std::max(maxValue, v);
  }
}

WeightedPoints BinValues(ValuesView values, double minValue, double maxValue, int binCount)
{
  WeightedPoints points;
  points.origin = minValue;
  points.total = static_cast<double>(values.size());
  const double range = maxValue - minValue;
  const auto bins = static_cast<std::size_t>(binCount);
  const double binWidth = range / static_cast<double>(binCount);
  // Deviations from the bin centre are small, so one pass accumulating them is accurate.
  std::vector<double> count(bins, 0.0), sumDev(bins, 0.0), sumSquareDev(bins, 0.0);
  const double scale = static_cast<double>(binCount) / range;
  for (Eigen::Index i = 0; i < values.size(); ++i)
  {
    const double shifted = values[i] - minValue;
    auto bin = static_cast<std::size_t>(shifted * scale);
    bin = std::min(bin, bins - 1);
    const double deviation = shifted - (static_cast<double>(bin) + 0.5) * binWidth;
    count[bin] += 1.0;
    sumDev[bin] += deviation;
    sumSquareDev[bin] += deviation * deviation;
  }
  for (std::size_t bin = 0; bin < bins; ++bin)
  {
    if (count[bin] == 0.0)
    {
      continue;
    }
    const double meanDev = sumDev[bin] / count[bin];
    points.position.push_back((static_cast<double>(bin) + 0.5) * binWidth + meanDev);
    points.count.push_back(count[bin]);
    points.meanSquareDev.push_back(std::max(0.0, sumSquareDev[bin] / count[bin] - meanDev * meanDev));
  }
  return points;
}

WeightedPoints DistinctValues(ValuesView values, double minValue)
{
  std::vector<double> sorted(values.data(), values.data() + values.size()); // Ref: contiguous
  std::sort(sorted.begin(), sorted.end());
  WeightedPoints points;
  points.origin = minValue;
  points.total = static_cast<double>(values.size());
  for (std::size_t i = 0; i < sorted.size();)
  {
    std::size_t j = i;
    while (j < sorted.size() && sorted[j] == sorted[i])
    {
      ++j;
    }
    points.position.push_back(sorted[i] - minValue);
    points.count.push_back(static_cast<double>(j - i));
    points.meanSquareDev.push_back(0.0);
    i = j;
  }
  return points;
}

using ConstArrayMap = Eigen::Map<const Eigen::ArrayXd>;

/// E-step: responsibilities (points x k) and the log-likelihood of the parameters.
/// Every value of a point shares the point's responsibilities; its expected log density is
/// exact from the point's mean and mean squared deviation. Vectorised over the points.
double ExpectationStep(const WeightedPoints& points, const Parameters& parameters,
  Eigen::ArrayXXd& responsibility)
{
  const auto size = static_cast<Eigen::Index>(points.Size());
  const ConstArrayMap position(points.position.data(), size);
  const ConstArrayMap spread(points.meanSquareDev.data(), size);
  const ConstArrayMap count(points.count.data(), size);
  const auto k = static_cast<Eigen::Index>(parameters.mean.size());
  for (Eigen::Index m = 0; m < k; ++m)
  {
    const auto c = static_cast<std::size_t>(m);
    const double logPrefix = std::log(parameters.weight[c]) - std::log(parameters.sigma[c]);
    const double halfInverseVariance = 0.5 / (parameters.sigma[c] * parameters.sigma[c]);
    responsibility.col(m) =
      logPrefix - halfInverseVariance * ((position - parameters.mean[c]).square() + spread);
  }
  const Eigen::ArrayXd largest = responsibility.rowwise().maxCoeff();
  responsibility.colwise() -= largest;
  responsibility = responsibility.exp();
  const Eigen::ArrayXd sum = responsibility.rowwise().sum();
  responsibility.colwise() /= sum;
  return (count * (largest + sum.log())).sum() - points.total * kHalfLogTwoPi;
}

void MaximizationStep(const WeightedPoints& points, const Eigen::ArrayXXd& responsibility,
  double sigmaFloor, Parameters& parameters)
{
  const auto size = static_cast<Eigen::Index>(points.Size());
  const ConstArrayMap position(points.position.data(), size);
  const ConstArrayMap spread(points.meanSquareDev.data(), size);
  const ConstArrayMap count(points.count.data(), size);
  const std::size_t k = parameters.mean.size();
  for (std::size_t m = 0; m < k; ++m)
  {
    const Eigen::ArrayXd mass = count * responsibility.col(static_cast<Eigen::Index>(m));
    const double totalMass = mass.sum();
    if (!(totalMass > kWeightFloor * points.total))
    {
      // A component nobody belongs to keeps its place; its tiny weight avoids log(0).
      parameters.weight[m] = kWeightFloor;
      continue;
    }
    const double mean = (mass * position).sum() / totalMass;
    const double second = (mass * ((position - mean).square() + spread)).sum();
    parameters.mean[m] = mean;
    parameters.sigma[m] = std::max(sigmaFloor, std::sqrt(second / totalMass));
    parameters.weight[m] = std::max(kWeightFloor, totalMass / points.total);
  }
  const double weightSum = std::accumulate(parameters.weight.begin(), parameters.weight.end(), 0.0);
  for (double& w : parameters.weight)
  {
    w /= weightSum;
  }
}

std::size_t SampleIndex(const std::vector<double>& mass, double total, std::mt19937_64& generator)
{
  const double target = UniformUnit(generator) * total;
  double running = 0.0;
  std::size_t last = 0;
  for (std::size_t j = 0; j < mass.size(); ++j)
  {
    if (mass[j] > 0.0)
    {
      running += mass[j];
      last = j;
      if (running > target)
      {
        return j;
      }
    }
  }
  return last; // rounding pushed the target past the sum: the last point with mass
}

/// k-means++ centres, then weights and sigmas from the nearest-centre assignment.
Parameters Seed(const WeightedPoints& points, std::size_t k, double sigmaFloor,
  std::mt19937_64& generator)
{
  const std::size_t n = points.Size();
  std::vector<double> centres;
  std::vector<double> nearestSquared(n, std::numeric_limits<double>::infinity());
  std::vector<double> mass(points.count);
  double total = points.total;
  while (centres.size() < k)
  {
    const std::size_t chosen = SampleIndex(mass, total, generator);
    centres.push_back(points.position[chosen]);
    total = 0.0;
    for (std::size_t j = 0; j < n; ++j)
    {
      const double d = points.position[j] - centres.back();
      nearestSquared[j] = std::min(nearestSquared[j], d * d);
      mass[j] = points.count[j] * nearestSquared[j];
      total += mass[j];
    }
    if (!(total > 0.0) && centres.size() < k)
    {
      // Cannot happen with k <= distinct points, but never loop forever.
      mass = points.count;
      total = points.total;
    }
  }
  Parameters parameters;
  parameters.mean.assign(k, 0.0);
  parameters.sigma.assign(k, sigmaFloor);
  parameters.weight.assign(k, 0.0);
  std::vector<double> first(k, 0.0), second(k, 0.0);
  std::vector<std::size_t> owner(n, 0);
  for (std::size_t j = 0; j < n; ++j)
  {
    std::size_t best = 0;
    for (std::size_t m = 1; m < k; ++m)
    {
      if (std::abs(points.position[j] - centres[m]) < std::abs(points.position[j] - centres[best]))
      {
        best = m;
      }
    }
    owner[j] = best;
    parameters.weight[best] += points.count[j];
    first[best] += points.count[j] * points.position[j];
  }
  for (std::size_t m = 0; m < k; ++m)
  {
    parameters.mean[m] = parameters.weight[m] > 0.0 ? first[m] / parameters.weight[m] : centres[m];
  }
  for (std::size_t j = 0; j < n; ++j)
  {
    const double d = points.position[j] - parameters.mean[owner[j]];
    second[owner[j]] += points.count[j] * (d * d + points.meanSquareDev[j]);
  }
  double weightSum = 0.0;
  for (std::size_t m = 0; m < k; ++m)
  {
    if (parameters.weight[m] > 0.0)
    {
      parameters.sigma[m] = std::max(sigmaFloor, std::sqrt(second[m] / parameters.weight[m]));
    }
    parameters.weight[m] = std::max(kWeightFloor, parameters.weight[m] / points.total);
    weightSum += parameters.weight[m];
  }
  for (double& w : parameters.weight)
  {
    w /= weightSum;
  }
  return parameters;
}

GaussianMixtureModel ToSortedModel(const Parameters& parameters, double origin)
{
  const std::size_t k = parameters.mean.size();
  std::vector<std::size_t> order(k);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    if (parameters.mean[a] != parameters.mean[b])
    {
      return parameters.mean[a] > parameters.mean[b];
    }
    if (parameters.weight[a] != parameters.weight[b])
    {
      return parameters.weight[a] > parameters.weight[b];
    }
    return a < b;
  });
  GaussianMixtureModel model;
  for (std::size_t m : order)
  {
    model.Means.push_back(parameters.mean[m] + origin);
    model.Sigmas.push_back(parameters.sigma[m]);
    model.Weights.push_back(parameters.weight[m]);
  }
  return model;
}

} // namespace

double GaussianMixtureModel::Bic() const
{
  const double parameterCount = 3.0 * static_cast<double>(ComponentCount()) - 1.0;
  return -2.0 * LogLikelihood +
    parameterCount * std::log(static_cast<double>(std::max<std::size_t>(SampleCount, 1)));
}

GaussianMixtureModel FitGaussianMixture(
  ValuesView values, int componentCount, const GaussianMixtureOptions& options)
{
  ValidateOptions(options);
  if (componentCount < 1)
  {
    throw Error("GMM: the number of components must be at least 1");
  }
  double minValue = 0.0, maxValue = 0.0;
  MinMaxChecked(values, minValue, maxValue);
  const double range = maxValue - minValue;
  if (!std::isfinite(range))
  {
    throw Error("GMM: the values span more than the double range");
  }
  if (range <= 0.0)
  {
    GaussianMixtureModel model;
    model.Means = { minValue };
    model.Sigmas = { options.MinSigmaRelative * std::max(std::abs(minValue), 1.0) };
    model.Weights = { 1.0 };
    model.SampleCount = static_cast<std::size_t>(values.size());
    const double n = static_cast<double>(values.size());
    model.LogLikelihood = -n * (kHalfLogTwoPi + std::log(model.Sigmas[0]));
    model.Converged = true;
    return model;
  }
  const WeightedPoints points = options.BinCount > 0
    ? BinValues(values, minValue, maxValue, options.BinCount)
    : DistinctValues(values, minValue);
  const std::size_t k = std::min<std::size_t>(static_cast<std::size_t>(componentCount), points.Size());
  const double sigmaFloor = options.MinSigmaRelative * range;

  // Screen every seeding with a few iterations, then run only the most likely to convergence:
  // the seedings differ in which basin they fall into, which a few iterations reveal.
  std::mt19937_64 generator(options.Seed);
  Eigen::ArrayXXd responsibility(static_cast<Eigen::Index>(points.Size()), static_cast<Eigen::Index>(k));
  const auto runEm = [&](Parameters& parameters, double& logLikelihood, int& iterations, int limit) {
    while (iterations < limit)
    {
      MaximizationStep(points, responsibility, sigmaFloor, parameters);
      const double next = ExpectationStep(points, parameters, responsibility);
      ++iterations;
      const double gain = next - logLikelihood;
      logLikelihood = next;
      if (gain < options.Tolerance * points.total)
      {
        return true;
      }
    }
    return false;
  };
  Parameters best;
  double bestLogLikelihood = -std::numeric_limits<double>::infinity();
  int bestIterations = 0;
  bool bestConverged = false;
  const int screening = std::min(options.ScreeningIterations, options.MaximumIterations);
  for (int restart = 0; restart < options.Restarts; ++restart)
  {
    Parameters parameters = Seed(points, k, sigmaFloor, generator);
    double logLikelihood = ExpectationStep(points, parameters, responsibility);
    int iterations = 0;
    const bool converged = runEm(parameters, logLikelihood, iterations, screening);
    if (logLikelihood > bestLogLikelihood || restart == 0)
    {
      best = parameters;
      bestLogLikelihood = logLikelihood;
      bestIterations = iterations;
      bestConverged = converged;
    }
  }
  if (!bestConverged)
  {
    ExpectationStep(points, best, responsibility);
    bestConverged = runEm(best, bestLogLikelihood, bestIterations, options.MaximumIterations);
  }
  GaussianMixtureModel model = ToSortedModel(best, points.origin);
  model.LogLikelihood = bestLogLikelihood;
  model.SampleCount = static_cast<std::size_t>(values.size());
  model.Iterations = bestIterations;
  model.Converged = bestConverged;
  return model;
}

GaussianMixtureBicResult FitGaussianMixtureBic(
  ValuesView values, int minComponents, int maxComponents, const GaussianMixtureOptions& options)
{
  if (minComponents < 1 || minComponents > maxComponents || maxComponents > 64)
  {
    throw Error("GMM: the BIC range must satisfy 1 <= min <= max <= 64");
  }
  GaussianMixtureBicResult result;
  for (int k = minComponents; k <= maxComponents; ++k)
  {
    GaussianMixtureModel model = FitGaussianMixture(values, k, options);
    const int used = model.ComponentCount();
    if (std::find(result.ComponentCounts.begin(), result.ComponentCounts.end(), used) !=
      result.ComponentCounts.end())
    {
      break; // reduced: every larger k reduces to the same count
    }
    const double bic = model.Bic();
    if (result.Bics.empty() || bic < *std::min_element(result.Bics.begin(), result.Bics.end()))
    {
      result.Model = model;
    }
    result.ComponentCounts.push_back(used);
    result.Bics.push_back(bic);
  }
  return result;
}

PosteriorMatrix ComputePosteriors(
  const GaussianMixtureModel& model, ValuesView values, const ParallelFor& parallelFor)
{
  const std::size_t k = model.Means.size();
  if (k == 0 || model.Sigmas.size() != k || model.Weights.size() != k)
  {
    throw Error("GMM: the model has no components or inconsistent sizes");
  }
  std::vector<double> logPrefix(k), inverseSigma(k);
  for (std::size_t m = 0; m < k; ++m)
  {
    if (!std::isfinite(model.Means[m]) || !std::isfinite(model.Sigmas[m]) || model.Sigmas[m] <= 0.0 ||
      !std::isfinite(model.Weights[m]) || model.Weights[m] <= 0.0)
    {
      throw Error("GMM: component " + std::to_string(m) +
        " needs a finite mean, a positive finite sigma and a positive finite weight");
    }
    logPrefix[m] = std::log(model.Weights[m]) - std::log(model.Sigmas[m]);
    inverseSigma[m] = 1.0 / model.Sigmas[m];
  }
  for (Eigen::Index i = 0; i < values.size(); ++i)
  {
    if (!std::isfinite(values[i]))
    {
      throw Error("GMM: value " + std::to_string(i) + " is NaN or infinite");
    }
  }
  const auto n = static_cast<std::size_t>(values.size());
  PosteriorMatrix posteriors(values.size(), static_cast<Eigen::Index>(k));
  parallelFor(n, [&](std::size_t begin, std::size_t end) {
    std::vector<double> logDensity(k);
    for (std::size_t i = begin; i < end; ++i)
    {
      const double x = values[static_cast<Eigen::Index>(i)];
      double largest = -std::numeric_limits<double>::infinity();
      for (std::size_t m = 0; m < k; ++m)
      {
        const double z = (x - model.Means[m]) * inverseSigma[m];
        logDensity[m] = logPrefix[m] - 0.5 * z * z;
        largest = std::max(largest, logDensity[m]);
      }
      auto row = posteriors.row(static_cast<Eigen::Index>(i));
      if (!std::isfinite(largest))
      {
        // Overflowing distances (values ~1e154 from every mean): the nearest in sigmas wins.
        std::size_t nearest = 0;
        for (std::size_t m = 1; m < k; ++m)
        {
          if (std::abs(x - model.Means[m]) * inverseSigma[m] <
            std::abs(x - model.Means[nearest]) * inverseSigma[nearest])
          {
            nearest = m;
          }
        }
        row.setZero();
        row[static_cast<Eigen::Index>(nearest)] = 1.0;
        continue;
      }
      double sum = 0.0;
      for (std::size_t m = 0; m < k; ++m)
      {
        logDensity[m] = std::exp(logDensity[m] - largest);
        sum += logDensity[m];
      }
      for (std::size_t m = 0; m < k; ++m)
      {
        row[static_cast<Eigen::Index>(m)] = logDensity[m] / sum;
      }
    }
  });
  return posteriors;
}

} // namespace shapediameter
