// SPDX-License-Identifier: BSD-3-Clause
// GaussianMixture: EM recovers sampled mixtures, posteriors, BIC, degenerate inputs.
#include "Partition/GaussianMixture.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace
{
using namespace shapediameter;

double Uniform(std::mt19937_64& generator)
{
  return static_cast<double>(generator() >> 11) * (1.0 / 9007199254740992.0);
}

/// Box-Muller on our own uniform mapping: reproducible on every platform.
double Normal(std::mt19937_64& generator)
{
  const double u1 = 1.0 - Uniform(generator); // (0, 1]
  const double u2 = Uniform(generator);
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * 3.14159265358979323846 * u2);
}

struct Component
{
  double mean, sigma, weight;
};

Eigen::VectorXd SampleMixture(const std::vector<Component>& components, int count, std::uint64_t seed)
{
  std::mt19937_64 generator(seed);
  Eigen::VectorXd values(count);
  for (int i = 0; i < count; ++i)
  {
    double u = Uniform(generator);
    std::size_t m = 0;
    while (m + 1 < components.size() && u >= components[m].weight)
    {
      u -= components[m].weight;
      ++m;
    }
    values[i] = components[m].mean + components[m].sigma * Normal(generator);
  }
  return values;
}

const std::vector<Component> kThreeModes = { { 0.2, 0.04, 0.3 }, { 0.5, 0.05, 0.45 }, { 0.8, 0.03, 0.25 } };

TEST(GaussianMixture, RecoversThreeComponentsSortedByMeanDescending)
{
  const Eigen::VectorXd values = SampleMixture(kThreeModes, 30000, 7);
  const GaussianMixtureModel model = FitGaussianMixture(values, 3);
  ASSERT_EQ(model.ComponentCount(), 3);
  EXPECT_TRUE(model.Converged);
  const int truthOrder[3] = { 2, 1, 0 }; // descending means
  for (int m = 0; m < 3; ++m)
  {
    const Component& truth = kThreeModes[truthOrder[m]];
    EXPECT_NEAR(model.Means[m], truth.mean, 0.02 * truth.mean) << m;
    EXPECT_NEAR(model.Sigmas[m], truth.sigma, 0.06 * truth.sigma) << m;
    EXPECT_NEAR(model.Weights[m], truth.weight, 0.015) << m;
  }
  EXPECT_GT(model.Means[0], model.Means[1]);
  EXPECT_GT(model.Means[1], model.Means[2]);
  EXPECT_NEAR(model.Weights[0] + model.Weights[1] + model.Weights[2], 1.0, 1e-12);
  EXPECT_EQ(model.SampleCount, 30000u);
  EXPECT_TRUE(std::isfinite(model.LogLikelihood));
}

TEST(GaussianMixture, BinnedFitIsCloseToExactFit)
{
  const Eigen::VectorXd values = SampleMixture(kThreeModes, 30000, 11);
  GaussianMixtureOptions exact;
  exact.BinCount = 0;
  const GaussianMixtureModel binned = FitGaussianMixture(values, 3);
  const GaussianMixtureModel reference = FitGaussianMixture(values, 3, exact);
  const double range = values.maxCoeff() - values.minCoeff();
  for (int m = 0; m < 3; ++m)
  {
    EXPECT_NEAR(binned.Means[m], reference.Means[m], 1e-3 * range);
    EXPECT_NEAR(binned.Sigmas[m], reference.Sigmas[m], 1e-3 * range);
    EXPECT_NEAR(binned.Weights[m], reference.Weights[m], 1e-3);
  }
  // Binned log-likelihood is a lower bound, and tight.
  EXPECT_LE(binned.LogLikelihood, reference.LogLikelihood + 1e-6 * std::abs(reference.LogLikelihood));
  EXPECT_NEAR(binned.LogLikelihood, reference.LogLikelihood, 1e-4 * std::abs(reference.LogLikelihood));
}

TEST(GaussianMixture, IsDeterministicAndRestartsDoNotHurt)
{
  const Eigen::VectorXd values = SampleMixture(kThreeModes, 5000, 3);
  const GaussianMixtureModel a = FitGaussianMixture(values, 4);
  const GaussianMixtureModel b = FitGaussianMixture(values, 4);
  EXPECT_EQ(a.Means, b.Means);
  EXPECT_EQ(a.Sigmas, b.Sigmas);
  EXPECT_EQ(a.Weights, b.Weights);
  // Without screening every seeding runs to the end; seeding 0 is the same in both runs.
  GaussianMixtureOptions full;
  full.ScreeningIterations = full.MaximumIterations;
  GaussianMixtureOptions single = full;
  single.Restarts = 1;
  EXPECT_GE(FitGaussianMixture(values, 4, full).LogLikelihood,
    FitGaussianMixture(values, 4, single).LogLikelihood);
}

TEST(GaussianMixture, PosteriorRowsSumToOneAndThreadingIsBitIdentical)
{
  const Eigen::VectorXd values = SampleMixture(kThreeModes, 20000, 5);
  const GaussianMixtureModel model = FitGaussianMixture(values, 3);
  const PosteriorMatrix serial = ComputePosteriors(model, values);
  ASSERT_EQ(serial.rows(), values.size());
  ASSERT_EQ(serial.cols(), 3);
  for (Eigen::Index i = 0; i < serial.rows(); ++i)
  {
    EXPECT_NEAR(serial.row(i).sum(), 1.0, 1e-12);
    for (Eigen::Index m = 0; m < 3; ++m)
    {
      ASSERT_TRUE(std::isfinite(serial(i, m)));
      ASSERT_GE(serial(i, m), 0.0);
      ASSERT_LE(serial(i, m), 1.0);
    }
  }
  EXPECT_EQ(serial, ComputePosteriors(model, values, ThreadedFor(2)));
  EXPECT_EQ(serial, ComputePosteriors(model, values, ThreadedFor(3)));

  // Cluster 0 is the largest mean: a value near 0.8 belongs to it, near 0.2 to cluster 2.
  Eigen::VectorXd probes(4);
  probes << 0.8, 0.5, 0.2, 1e6; // the last is far from everything: still finite, one-hot
  const PosteriorMatrix probe = ComputePosteriors(model, probes);
  EXPECT_GT(probe(0, 0), 0.99);
  EXPECT_GT(probe(1, 1), 0.99);
  EXPECT_GT(probe(2, 2), 0.99);
  EXPECT_NEAR(probe.row(3).sum(), 1.0, 1e-12);
  EXPECT_TRUE(probe.allFinite());
}

TEST(GaussianMixture, ConstantDataGivesOneComponent)
{
  const Eigen::VectorXd values = Eigen::VectorXd::Constant(100, 0.37);
  const GaussianMixtureModel model = FitGaussianMixture(values, 4);
  ASSERT_EQ(model.ComponentCount(), 1);
  EXPECT_EQ(model.Means[0], 0.37);
  EXPECT_GT(model.Sigmas[0], 0.0);
  EXPECT_EQ(model.Weights[0], 1.0);
  EXPECT_TRUE(std::isfinite(model.LogLikelihood));
  const PosteriorMatrix posteriors = ComputePosteriors(model, values);
  EXPECT_TRUE((posteriors.array() == 1.0).all());

  const Eigen::VectorXd single = Eigen::VectorXd::Constant(1, -2.0);
  EXPECT_EQ(FitGaussianMixture(single, 3).ComponentCount(), 1);
}

TEST(GaussianMixture, MoreComponentsThanDistinctValuesAreReduced)
{
  Eigen::VectorXd values(30);
  for (int i = 0; i < 30; ++i)
  {
    values[i] = i < 10 ? 0.1 : 0.9;
  }
  for (int binCount : { 1024, 0 })
  {
    GaussianMixtureOptions options;
    options.BinCount = binCount;
    const GaussianMixtureModel model = FitGaussianMixture(values, 5, options);
    ASSERT_EQ(model.ComponentCount(), 2) << binCount;
    EXPECT_NEAR(model.Means[0], 0.9, 1e-12);
    EXPECT_NEAR(model.Means[1], 0.1, 1e-12);
    EXPECT_NEAR(model.Weights[0], 2.0 / 3.0, 1e-9);
    // Each component sits on one value: its sigma is the floor, 1e-3 of the range.
    EXPECT_NEAR(model.Sigmas[0], 1e-3 * 0.8, 1e-12);
    const PosteriorMatrix posteriors = ComputePosteriors(model, values);
    EXPECT_TRUE(posteriors.allFinite());
    EXPECT_NEAR(posteriors(0, 1), 1.0, 1e-12);
  }
}

TEST(GaussianMixture, SigmaNeverCollapsesBelowTheFloor)
{
  Eigen::VectorXd values = SampleMixture({ { 0.5, 0.2, 1.0 } }, 2000, 9);
  values.head(1000).setConstant(0.25); // a spike that attracts a component
  const GaussianMixtureModel model = FitGaussianMixture(values, 3);
  const double floor = 1e-3 * (values.maxCoeff() - values.minCoeff());
  for (double sigma : model.Sigmas)
  {
    EXPECT_GE(sigma, floor * (1.0 - 1e-12));
  }
  EXPECT_TRUE(std::isfinite(model.LogLikelihood));
  EXPECT_TRUE(ComputePosteriors(model, values).allFinite());
}

TEST(GaussianMixture, BadInputThrows)
{
  const Eigen::VectorXd empty(0);
  EXPECT_THROW(FitGaussianMixture(empty, 2), Error);
  Eigen::VectorXd withNaN(3);
  withNaN << 0.1, std::numeric_limits<double>::quiet_NaN(), 0.3;
  EXPECT_THROW(FitGaussianMixture(withNaN, 2), Error);
  Eigen::VectorXd withInf(2);
  withInf << 0.1, std::numeric_limits<double>::infinity();
  EXPECT_THROW(FitGaussianMixture(withInf, 2), Error);
  Eigen::VectorXd huge(2);
  huge << -1e308, 1e308; // the range overflows
  EXPECT_THROW(FitGaussianMixture(huge, 2), Error);
  const Eigen::VectorXd fine = Eigen::VectorXd::LinSpaced(10, 0.0, 1.0);
  EXPECT_THROW(FitGaussianMixture(fine, 0), Error);
  GaussianMixtureOptions badOptions;
  badOptions.Restarts = 0;
  EXPECT_THROW(FitGaussianMixture(fine, 2, badOptions), Error);
  EXPECT_THROW(FitGaussianMixtureBic(fine, 3, 2), Error);
  EXPECT_THROW(ComputePosteriors(GaussianMixtureModel{}, fine), Error);
  const GaussianMixtureModel model = FitGaussianMixture(fine, 2);
  EXPECT_THROW(ComputePosteriors(model, withNaN), Error);
  EXPECT_EQ(ComputePosteriors(model, empty).rows(), 0);
}

TEST(GaussianMixture, BicPicksTheNumberOfModes)
{
  const Eigen::VectorXd three = SampleMixture(kThreeModes, 30000, 21);
  const GaussianMixtureBicResult threeFit = FitGaussianMixtureBic(three, 1, 8);
  EXPECT_EQ(threeFit.Model.ComponentCount(), 3);
  EXPECT_EQ(threeFit.ComponentCounts.size(), 8u);
  EXPECT_EQ(threeFit.Bics.size(), 8u);

  const Eigen::VectorXd two = SampleMixture({ { 0.25, 0.05, 0.5 }, { 0.75, 0.05, 0.5 } }, 20000, 22);
  EXPECT_EQ(FitGaussianMixtureBic(two).Model.ComponentCount(), 2);

  const Eigen::VectorXd one = SampleMixture({ { 0.5, 0.1, 1.0 } }, 20000, 23);
  EXPECT_EQ(FitGaussianMixtureBic(one, 1, 8).Model.ComponentCount(), 1);

  // Two distinct values: larger k reduce to 2 and are not tried twice.
  Eigen::VectorXd twoValues(40);
  for (int i = 0; i < 40; ++i)
  {
    twoValues[i] = (i % 2) ? 0.2 : 0.6;
  }
  const GaussianMixtureBicResult reduced = FitGaussianMixtureBic(twoValues, 2, 8);
  EXPECT_EQ(reduced.ComponentCounts, std::vector<int>({ 2 }));
  EXPECT_EQ(reduced.Model.ComponentCount(), 2);
}

} // namespace
