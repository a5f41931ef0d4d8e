// SPDX-License-Identifier: BSD-3-Clause
// Clusters from the modes of a weighted density: known modes found, noise bumps ignored, the
// boundaries stable under a small shift of the values, bad input rejected.
#include "Partition/DensityModes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace
{

using shapediameter::Error;
using shapediameter::DensityModesOptions;
using shapediameter::FitDensityModes;

/// Samples of a mixture of normals (fixed seed), clamped to [0, 1] like SDFNormalized.
std::vector<double> Mixture(const std::vector<double>& means, const std::vector<double>& sigmas,
  const std::vector<int>& counts, std::uint32_t seed = 11)
{
  std::mt19937 random(seed);
  std::vector<double> values;
  for (std::size_t c = 0; c < means.size(); ++c)
  {
    std::normal_distribution<double> normal(means[c], sigmas[c]);
    for (int i = 0; i < counts[c]; ++i)
    {
      values.push_back(std::min(1.0, std::max(0.0, normal(random))));
    }
  }
  return values;
}

Eigen::Map<const Eigen::VectorXd> View(const std::vector<double>& values)
{
  return Eigen::Map<const Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size()));
}

TEST(DensityModes, FindsSeparatedModesWithTheirMomentsAndValleys)
{
  const std::vector<double> values = Mixture({ 0.15, 0.5, 0.85 }, { 0.04, 0.05, 0.03 }, { 3000, 5000, 2000 });
  const std::vector<double> weights(values.size(), 1.0);
  const auto result = FitDensityModes(View(values), View(weights));
  ASSERT_EQ(result.Model.ComponentCount(), 3);
  // Largest mean first, like the EM fit.
  EXPECT_NEAR(result.Model.Means[0], 0.85, 0.01);
  EXPECT_NEAR(result.Model.Means[1], 0.50, 0.01);
  EXPECT_NEAR(result.Model.Means[2], 0.15, 0.01);
  EXPECT_NEAR(result.Model.Weights[0], 0.2, 0.01);
  EXPECT_NEAR(result.Model.Weights[1], 0.5, 0.01);
  EXPECT_NEAR(result.Model.Sigmas[1], 0.05, 0.005);
  ASSERT_EQ(result.Valleys.size(), 2u);
  EXPECT_GT(result.Valleys[0], 0.25);
  EXPECT_LT(result.Valleys[0], 0.38);
  EXPECT_GT(result.Valleys[1], 0.62);
  EXPECT_LT(result.Valleys[1], 0.76);
  EXPECT_DOUBLE_EQ(result.Prominences[1], 1.0) << "the highest peak";
  EXPECT_TRUE(std::isfinite(result.Model.LogLikelihood));
}

TEST(DensityModes, WeightsDecideTheModesNotTheCounts)
{
  // Many light values at 0.2, few heavy ones at 0.7: by weight 0.7 dominates; a mode of 5 %
  // of the weight is still a mode.
  std::vector<double> values = Mixture({ 0.2, 0.7 }, { 0.03, 0.03 }, { 9000, 1000 });
  std::vector<double> weights(values.size(), 0.01);
  std::fill(weights.begin() + 9000, weights.end(), 1.0);
  const auto result = FitDensityModes(View(values), View(weights));
  ASSERT_EQ(result.Model.ComponentCount(), 2);
  EXPECT_NEAR(result.Model.Weights[0], 1000.0 / 1090.0, 1e-9);
  EXPECT_NEAR(result.Prominences[1], 1.0, 1e-12) << "the heavy mode is the highest";
}

TEST(DensityModes, NoiseBumpsAndCapsAreHonoured)
{
  // One broad mode: sampling noise must not create clusters.
  const std::vector<double> broad = Mixture({ 0.5 }, { 0.15 }, { 20000 });
  const std::vector<double> ones(broad.size(), 1.0);
  EXPECT_EQ(FitDensityModes(View(broad), View(ones)).Model.ComponentCount(), 1);
  // Four clear modes, at most two kept: the two most prominent (the two largest).
  const std::vector<double> four = Mixture({ 0.1, 0.35, 0.6, 0.85 }, { 0.03, 0.03, 0.03, 0.03 }, { 1000, 4000, 3000, 800 });
  const std::vector<double> fourWeights(four.size(), 1.0);
  DensityModesOptions capped;
  capped.MaximumModes = 2;
  const auto result = FitDensityModes(View(four), View(fourWeights), capped);
  ASSERT_EQ(result.Model.ComponentCount(), 2);
  EXPECT_NEAR(result.Modes[0], 0.35, 0.02);
  EXPECT_NEAR(result.Modes[1], 0.6, 0.02);
  // A prominence threshold above every secondary peak keeps only the highest.
  DensityModesOptions strict;
  strict.MinimumProminence = 0.99;
  EXPECT_EQ(FitDensityModes(View(four), View(fourWeights), strict).Model.ComponentCount(), 1);
}

TEST(DensityModes, AShoulderIsNotAModeButASmallSeparatedModeIs)
{
  // A thickness level overlapping a larger one (0.52 next to 0.4) makes a shoulder with a
  // shallow local maximum; a small level far from the others (0.85, 2.6 % of the values) makes
  // a low but separated peak. With a valley depth of 0.25 only the second is a cluster.
  const std::vector<double> values = Mixture({ 0.4, 0.52, 0.85 }, { 0.05, 0.03, 0.02 }, { 8000, 3000, 300 });
  const std::vector<double> ones(values.size(), 1.0);
  DensityModesOptions prominenceAlone;
  prominenceAlone.MinimumValleyDepth = 0.0;
  const auto all = FitDensityModes(View(values), View(ones), prominenceAlone);
  ASSERT_EQ(all.Modes.size(), 3u) << "the shoulder has a local maximum above the prominence floor";
  EXPECT_NEAR(all.Modes[1], 0.52, 0.03);
  EXPECT_GT(all.Prominences[1], 0.05) << "prominent enough for the former rule (prominence 0.05 alone)";
  EXPECT_LT(all.ValleyDepths[1], 0.25);
  EXPECT_GT(all.ValleyDepths[2], 0.9);
  DensityModesOptions quarterValley;
  quarterValley.MinimumValleyDepth = 0.25;
  const auto result = FitDensityModes(View(values), View(ones), quarterValley);
  ASSERT_EQ(result.Modes.size(), 2u);
  EXPECT_NEAR(result.Modes[0], 0.4, 0.03);
  EXPECT_NEAR(result.Modes[1], 0.85, 0.02);
  ASSERT_EQ(result.ValleyDepths.size(), 2u);
  EXPECT_DOUBLE_EQ(result.ValleyDepths[0], 1.0) << "the highest peak";
  EXPECT_LT(result.Prominences[1], 0.15);
  // The shoulder's values join the larger mode's basin.
  ASSERT_EQ(result.Valleys.size(), 1u);
  EXPECT_GT(result.Valleys[0], 0.62);
}

TEST(DensityModes, ValleysMoveWithTheValuesAndFewValuesChangeCluster)
{
  // The consistency property: shift every value by 1 % of the range plus noise of 0.5 %; the
  // valleys follow the shift and few values change basin.
  const std::vector<double> values = Mixture({ 0.2, 0.5, 0.8 }, { 0.05, 0.05, 0.05 }, { 4000, 4000, 4000 });
  std::vector<double> moved(values.size());
  std::mt19937 random(5);
  std::normal_distribution<double> noise(0.0, 0.005);
  for (std::size_t i = 0; i < values.size(); ++i)
  {
    moved[i] = values[i] + 0.01 + noise(random);
  }
  const std::vector<double> ones(values.size(), 1.0);
  const auto a = FitDensityModes(View(values), View(ones));
  const auto b = FitDensityModes(View(moved), View(ones));
  ASSERT_EQ(a.Valleys.size(), 2u);
  ASSERT_EQ(b.Valleys.size(), 2u);
  int changed = 0;
  for (std::size_t i = 0; i < values.size(); ++i)
  {
    const auto basin = [](const std::vector<double>& valleys, double v) {
      return std::upper_bound(valleys.begin(), valleys.end(), v) - valleys.begin();
    };
    changed += basin(a.Valleys, values[i]) != basin(b.Valleys, moved[i]) ? 1 : 0;
  }
  EXPECT_NEAR(b.Valleys[0] - a.Valleys[0], 0.01, 0.02);
  EXPECT_LT(changed, static_cast<int>(values.size()) / 50) << "under 2 % of the values change cluster";
}

TEST(DensityModes, DegenerateAndBadInput)
{
  const std::vector<double> constant(10, 0.3), ones(10, 1.0), zeros(10, 0.0);
  const auto single = FitDensityModes(View(constant), View(ones));
  ASSERT_EQ(single.Model.ComponentCount(), 1);
  EXPECT_EQ(single.Model.Means[0], 0.3);
  EXPECT_GT(single.Model.Sigmas[0], 0.0);
  // All weights zero: every value counts once.
  const std::vector<double> two = Mixture({ 0.2, 0.8 }, { 0.02, 0.02 }, { 500, 500 });
  const std::vector<double> twoZeros(two.size(), 0.0);
  EXPECT_EQ(FitDensityModes(View(two), View(twoZeros)).Model.ComponentCount(), 2);
  const std::vector<double> empty;
  EXPECT_THROW(FitDensityModes(View(empty), View(empty)), Error);
  EXPECT_THROW(FitDensityModes(View(constant), View(std::vector<double>(9, 1.0))), Error);
  std::vector<double> withNan = constant;
  withNan[3] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(FitDensityModes(View(withNan), View(ones)), Error);
  std::vector<double> negative = ones;
  negative[0] = -1.0;
  EXPECT_THROW(FitDensityModes(View(constant), View(negative)), Error);
  DensityModesOptions bad;
  bad.Bandwidth = 0.0;
  EXPECT_THROW(FitDensityModes(View(two), View(std::vector<double>(two.size(), 1.0)), bad), Error);
  for (const double depth : { -0.1, 1.5, std::numeric_limits<double>::quiet_NaN() })
  {
    DensityModesOptions badDepth;
    badDepth.MinimumValleyDepth = depth;
    EXPECT_THROW(FitDensityModes(View(two), View(std::vector<double>(two.size(), 1.0)), badDepth), Error)
      << depth;
  }
}

} // namespace
