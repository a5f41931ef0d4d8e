// SPDX-License-Identifier: BSD-3-Clause
// The multilevel graph cut against the plain alpha-expansion on a noisy synthetic partition
// problem large enough to be coarsened twice.
#include "Partition/MultilevelCut.h"

#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <cstdint>
#include <mutex>
#include <random>
#include <vector>

namespace
{

using shapediameter::AlphaExpansionResult;
using shapediameter::MinimizeByAlphaExpansion;
using shapediameter::MinimizeMultilevel;
using shapediameter::MultilevelOptions;
using shapediameter::PartitionEnergy;
using shapediameter::Error;

/// side x side grid, 4-neighbour pairs; three vertical bands with wavy borders as the truth,
/// posteriors 0.6 for the true label with 30 % of the faces flipped to a random label, and a
/// cut weight that makes the bands win (the regime of the SDF partition: strong smoothing).
/// `bands` (if given) receives the truth before the noise: the labelling a good cut recovers.
PartitionEnergy NoisyBands(int side, double weight, std::vector<int>* bands = nullptr)
{
  std::mt19937_64 generator(2008);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  PartitionEnergy energy;
  energy.FaceCount = static_cast<std::size_t>(side) * static_cast<std::size_t>(side);
  energy.LabelCount = 3;
  energy.DataCosts.resize(energy.FaceCount * 3);
  for (int y = 0; y < side; ++y)
  {
    for (int x = 0; x < side; ++x)
    {
      const double wave = 0.05 * side * std::sin(0.1 * y);
      int truth = x + wave < side / 3.0 ? 0 : (x + wave < 2.0 * side / 3.0 ? 1 : 2);
      if (bands)
      {
        bands->push_back(truth);
      }
      if (uniform(generator) < 0.3)
      {
        truth = static_cast<int>(uniform(generator) * 3.0) % 3;
      }
      const std::size_t f = static_cast<std::size_t>(y) * static_cast<std::size_t>(side) + static_cast<std::size_t>(x);
      for (int l = 0; l < 3; ++l)
      {
        energy.DataCosts[f * 3 + static_cast<std::size_t>(l)] = -std::log(l == truth ? 0.6 : 0.2);
      }
      if (x + 1 < side)
      {
        energy.PairFirst.push_back(static_cast<std::int64_t>(f));
        energy.PairSecond.push_back(static_cast<std::int64_t>(f + 1));
        energy.PairWeight.push_back(weight);
      }
      if (y + 1 < side)
      {
        energy.PairFirst.push_back(static_cast<std::int64_t>(f));
        energy.PairSecond.push_back(static_cast<std::int64_t>(f) + side);
        energy.PairWeight.push_back(weight);
      }
    }
  }
  return energy;
}

TEST(MultilevelCut, CloseToThePlainAlphaExpansion)
{
  std::vector<int> bands;
  const PartitionEnergy energy = NoisyBands(120, 2.0, &bands);
  ASSERT_EQ(bands.size(), energy.FaceCount);
  const AlphaExpansionResult plain = MinimizeByAlphaExpansion(energy);
  MultilevelOptions coarsen;
  coarsen.DirectBelowFaces = 500; // 14400 faces -> about 1800 clusters -> about 225: two levels
  const AlphaExpansionResult multilevel = MinimizeMultilevel(energy, coarsen);
  ASSERT_EQ(multilevel.Labels.size(), energy.FaceCount);
  EXPECT_FALSE(multilevel.Aborted);
  EXPECT_NEAR(multilevel.Energy, energy.Evaluate(multilevel.Labels), 1e-9 * multilevel.Energy);
  EXPECT_LT(multilevel.Energy, 0.7 * multilevel.InitialEnergy) << "the smoothing did its work";
  EXPECT_LE(multilevel.Energy, 1.03 * plain.Energy);
  std::size_t different = 0;
  for (std::size_t f = 0; f < energy.FaceCount; ++f)
  {
    different += multilevel.Labels[f] != plain.Labels[f] ? 1 : 0;
  }
  std::printf("multilevel E %.1f vs plain %.1f (argmax %.1f); %.2f %% of the faces differ\n", multilevel.Energy,
    plain.Energy, plain.InitialEnergy, 100.0 * static_cast<double>(different) / static_cast<double>(energy.FaceCount));
  EXPECT_LT(different, energy.FaceCount / 20);
  // Against the ground truth: the bands before the noise (20 % of the faces carry a wrong
  // most probable label). Bound set from the first measurement (plain 0.45 %, multilevel
  // 0.35 %) with a 3x margin: the rest sits along the wavy borders, which the cut straightens.
  const auto wrongShare = [&](const std::vector<int>& labels) {
    std::size_t wrong = 0;
    for (std::size_t f = 0; f < energy.FaceCount; ++f)
    {
      wrong += labels[f] != bands[f] ? 1 : 0;
    }
    return static_cast<double>(wrong) / static_cast<double>(energy.FaceCount);
  };
  const double wrongInitially = wrongShare(shapediameter::MostProbableLabels(energy));
  const double wrongPlain = wrongShare(plain.Labels);
  const double wrongMultilevel = wrongShare(multilevel.Labels);
  std::printf("faces off the true bands: argmax %.2f %%, plain %.2f %%, multilevel %.2f %%\n", 100.0 * wrongInitially,
    100.0 * wrongPlain, 100.0 * wrongMultilevel);
  EXPECT_LT(wrongPlain, 0.015);
  EXPECT_LT(wrongMultilevel, 0.015);
  EXPECT_GT(different, 0u) << "deterministic: a few faces differ when the coarse levels really ran";
}

TEST(MultilevelCut, SmallProblemsAreThePlainAlphaExpansion)
{
  const PartitionEnergy energy = NoisyBands(40, 2.0);
  EXPECT_EQ(MinimizeMultilevel(energy).Labels, MinimizeByAlphaExpansion(energy).Labels);
  // No pairs at all (isolated faces): nothing to coarsen, the plain cut (per-face argmax).
  PartitionEnergy isolated = energy;
  isolated.PairFirst.clear();
  isolated.PairSecond.clear();
  isolated.PairWeight.clear();
  MultilevelOptions coarsen;
  coarsen.DirectBelowFaces = 100;
  EXPECT_EQ(MinimizeMultilevel(isolated, coarsen).Labels, MinimizeByAlphaExpansion(isolated).Labels);
  MultilevelOptions bad;
  bad.ClusterSize = 1;
  EXPECT_THROW(MinimizeMultilevel(energy, bad), Error);
  bad = MultilevelOptions();
  bad.BandRings = 0;
  EXPECT_THROW(MinimizeMultilevel(energy, bad), Error);
  bad = MultilevelOptions();
  bad.LostRegionFaces = 0;
  EXPECT_THROW(MinimizeMultilevel(energy, bad), Error);
}

TEST(MultilevelCut, BandComponentsGiveTheSameCutOnAnyNumberOfThreads)
{
  // Three bands: the fine pass re-solves (at least) two separate boundary bands, which run
  // concurrently with threads; labels, energy and move counts must not depend on it.
  const PartitionEnergy energy = NoisyBands(120, 2.0);
  MultilevelOptions coarsen;
  coarsen.DirectBelowFaces = 500;
  const AlphaExpansionResult serial = MinimizeMultilevel(energy, coarsen);
  for (const unsigned threads : { 2u, 3u, 8u })
  {
    std::mutex mutex;
    std::vector<double> reported;
    const AlphaExpansionResult threaded = MinimizeMultilevel(energy, coarsen, {},
      [&](double fraction) {
        const std::lock_guard<std::mutex> lock(mutex);
        reported.push_back(fraction);
        return true;
      },
      shapediameter::ThreadedFor(threads));
    EXPECT_EQ(threaded.Labels, serial.Labels) << threads << " threads";
    EXPECT_EQ(threaded.Energy, serial.Energy) << threads << " threads";
    EXPECT_EQ(threaded.Moves, serial.Moves) << threads << " threads";
    EXPECT_TRUE(threaded.Converged);
    ASSERT_FALSE(reported.empty());
    EXPECT_TRUE(std::is_sorted(reported.begin(), reported.end())) << "progress never goes backwards";
    EXPECT_EQ(reported.back(), 1.0);
  }
  // An abort requested while the bands are being solved stops every band.
  const AlphaExpansionResult aborted = MinimizeMultilevel(
    energy, coarsen, {}, [](double fraction) { return fraction < 0.55; }, shapediameter::ThreadedFor(2));
  EXPECT_TRUE(aborted.Aborted);
  EXPECT_EQ(aborted.Labels.size(), energy.FaceCount);
}

TEST(MultilevelCut, AbortIsReported)
{
  const PartitionEnergy energy = NoisyBands(60, 2.0);
  MultilevelOptions coarsen;
  coarsen.DirectBelowFaces = 100;
  const AlphaExpansionResult result =
    MinimizeMultilevel(energy, coarsen, {}, [](double fraction) { return fraction < 0.25; });
  EXPECT_TRUE(result.Aborted);
  EXPECT_EQ(result.Labels.size(), energy.FaceCount);
}

} // namespace
