// SPDX-License-Identifier: BSD-3-Clause
// Log normalisation (paper sec. 4).
#include "Smoothing/Normalization.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <utility>
#include <vector>

using namespace shapediameter;

TEST(Normalization, MinToZeroMaxToOneMonotone)
{
  const std::vector<double> sdf{ 0.7, 0.2, 1.2, 0.2, 0.45, 0.95 };
  const std::vector<double> nsdf = NormalizeLogarithmic(sdf);
  ASSERT_EQ(nsdf.size(), sdf.size());
  EXPECT_EQ(nsdf[1], 0.0);
  EXPECT_EQ(nsdf[3], 0.0);
  EXPECT_EQ(nsdf[2], 1.0);
  for (std::size_t i = 0; i < sdf.size(); ++i)
  {
    for (std::size_t j = 0; j < sdf.size(); ++j)
    {
      if (sdf[i] < sdf[j])
      {
        EXPECT_LT(nsdf[i], nsdf[j]);
      }
    }
  }
}

TEST(Normalization, MatchesThePaperFormulaAndAlpha)
{
  // sdf in [2, 6]; the midpoint 4 has fraction 1/2: nsdf = log(alpha / 2 + 1) / log(alpha + 1).
  const std::vector<double> sdf{ 2.0, 4.0, 6.0, 3.0 };
  const std::vector<double> defaults = NormalizeLogarithmic(sdf);
  EXPECT_NEAR(defaults[1], std::log(3.0) / std::log(5.0), 1e-15); // alpha = 4
  EXPECT_NEAR(defaults[3], std::log(2.0) / std::log(5.0), 1e-15);
  // Concave: the midpoint maps above 1/2, more so for a larger alpha.
  EXPECT_GT(defaults[1], 0.5);
  NormalizationOptions options;
  options.Alpha = 20.0;
  const std::vector<double> stretched = NormalizeLogarithmic(sdf, options);
  EXPECT_NEAR(stretched[1], std::log(11.0) / std::log(21.0), 1e-15);
  EXPECT_GT(stretched[1], defaults[1]);
  // alpha -> 0 tends to the linear map. 1e-9 is below AlphaRange (the filter's [0.001, 1000]):
  // NormalizeLogarithmic alone keeps the wider NormalizeLogarithmicAlphaRange (Normalization.h).
  options.Alpha = 1e-9;
  EXPECT_NEAR(NormalizeLogarithmic(sdf, options)[1], 0.5, 1e-9);
}

TEST(Normalization, ConstantEmptyAndExtremeInputs)
{
  EXPECT_EQ(NormalizeLogarithmic({ 0.3, 0.3, 0.3 }), (std::vector<double>{ 0.0, 0.0, 0.0 }));
  EXPECT_EQ(NormalizeLogarithmic({ 5.0 }), (std::vector<double>{ 0.0 }));
  EXPECT_TRUE(NormalizeLogarithmic({}).empty());
  // max - min overflows a double: still finite, ends at 0 and 1, midpoint right.
  const std::vector<double> extreme = NormalizeLogarithmic({ -1e308, 0.0, 1e308 });
  EXPECT_EQ(extreme[0], 0.0);
  EXPECT_EQ(extreme[2], 1.0);
  EXPECT_NEAR(extreme[1], std::log(3.0) / std::log(5.0), 1e-15);
  // Tiny spreads are fine too.
  const std::vector<double> tiny = NormalizeLogarithmic({ 1.0, 1.0 + 1e-15 });
  EXPECT_EQ(tiny[0], 0.0);
  EXPECT_EQ(tiny[1], 1.0);
}

TEST(Normalization, AGivenFamilyRangeReplacesTheOwnMinimumAndMaximum)
{
  // Two members of a family: [2, 6] and [3, 5]. Alone, each maps its own extremes to 0 and 1;
  // with the family range [2, 6] the value 4 means the same on both, and 3 and 5 are not
  // stretched to the ends.
  const std::vector<double> narrow{ 3.0, 4.0, 5.0 };
  EXPECT_EQ(NormalizeLogarithmic(narrow)[2], 1.0);
  NormalizationOptions family;
  family.UseGivenRange = true;
  family.RangeMinimum = 2.0;
  family.RangeMaximum = 6.0;
  const std::vector<double> shared = NormalizeLogarithmic(narrow, family);
  const std::vector<double> wide = NormalizeLogarithmic({ 2.0, 4.0, 6.0, 3.0, 5.0 });
  EXPECT_EQ(shared[1], wide[1]);
  EXPECT_EQ(shared[0], wide[3]);
  EXPECT_EQ(shared[2], wide[4]);
  EXPECT_NEAR(shared[1], std::log(3.0) / std::log(5.0), 1e-15);
  EXPECT_EQ(NormalizationRange(narrow, family), std::make_pair(2.0, 6.0));
  EXPECT_EQ(NormalizationRange(narrow), std::make_pair(3.0, 5.0));
  // Values outside the given range end at 0 and 1.
  family.RangeMinimum = 3.5;
  family.RangeMaximum = 4.5;
  const std::vector<double> clamped = NormalizeLogarithmic(narrow, family);
  EXPECT_EQ(clamped[0], 0.0);
  EXPECT_NEAR(clamped[1], std::log(3.0) / std::log(5.0), 1e-15);
  EXPECT_EQ(clamped[2], 1.0);
  // An empty or reversed given range is an error, not a silent fallback.
  for (const auto& [low, high] : { std::make_pair(1.0, 1.0), std::make_pair(2.0, 1.0),
         std::make_pair(0.0, std::numeric_limits<double>::infinity()),
         std::make_pair(std::numeric_limits<double>::quiet_NaN(), 1.0) })
  {
    family.RangeMinimum = low;
    family.RangeMaximum = high;
    EXPECT_THROW(NormalizeLogarithmic(narrow, family), Error);
  }
}

TEST(Normalization, BadInputThrows)
{
  EXPECT_THROW(NormalizeLogarithmic({ 1.0, std::numeric_limits<double>::quiet_NaN() }), Error);
  EXPECT_THROW(NormalizeLogarithmic({ std::numeric_limits<double>::infinity(), 1.0 }), Error);
  NormalizationOptions options;
  for (double alpha : { 0.0, -1.0, std::numeric_limits<double>::infinity(), std::numeric_limits<double>::quiet_NaN() })
  {
    options.Alpha = alpha;
    EXPECT_THROW(NormalizeLogarithmic({ 1.0, 2.0 }, options), Error);
  }
}
