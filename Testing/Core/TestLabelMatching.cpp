// SPDX-License-Identifier: BSD-3-Clause
// LabelMatching: the Table 2 measure and the assignment solver behind it.
#include "LabelMatching.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <vector>

namespace
{
using namespace shapediameter;

std::vector<int> Relabel(const std::vector<int>& labels, const std::vector<int>& permutation)
{
  std::vector<int> result(labels.size());
  for (std::size_t f = 0; f < labels.size(); ++f)
  {
    result[f] = permutation[static_cast<std::size_t>(labels[f])];
  }
  return result;
}

std::vector<int> RandomLabels(std::mt19937_64& generator, std::size_t count, int labels)
{
  std::vector<int> result(count);
  for (int& l : result)
  {
    l = static_cast<int>(generator() % static_cast<std::uint64_t>(labels));
  }
  return result;
}

TEST(LabelMatching, HandComputedCase)
{
  // Overlaps: (0,1) 2 faces, (0,0) 1, (1,0) 2, (2,2) 1. Best: 0<->1, 1<->0, 2<->2 = 5 faces.
  const std::vector<int> first = { 0, 0, 0, 1, 1, 2 };
  const std::vector<int> second = { 1, 1, 0, 0, 0, 2 };
  const LabelMatchingResult result = CompareLabelings(first, second);
  EXPECT_EQ(result.DifferentCount, 1u);
  EXPECT_NEAR(result.PercentDifferent, 100.0 / 6.0, 1e-12);
  const std::vector<std::pair<int, int>> expected = { { 0, 1 }, { 1, 0 }, { 2, 2 } };
  EXPECT_EQ(result.Matching, expected);

  // Greedy would take (0,1)=3 then lose (1,0)... here the one-to-one optimum is not greedy:
  // overlaps (a0,b0) 3, (a0,b1) 2, (a1,b0) 2, (a1,b1) 0 -> best 2 + 2 = 4, not 3 + 0.
  const std::vector<int> a = { 0, 0, 0, 0, 0, 1, 1 };
  const std::vector<int> b = { 0, 0, 0, 1, 1, 0, 0 };
  EXPECT_EQ(CompareLabelings(a, b).DifferentCount, 3u);
}

TEST(LabelMatching, IdenticalAndPermutedLabelingsAgreeCompletely)
{
  std::mt19937_64 generator(3);
  const std::vector<int> labels = RandomLabels(generator, 1000, 6);
  EXPECT_EQ(CompareLabelings(labels, labels).PercentDifferent, 0.0);
  std::vector<int> permutation = { 3, 5, 0, 1, 4, 2 };
  EXPECT_EQ(CompareLabelings(labels, Relabel(labels, permutation)).PercentDifferent, 0.0);
  // Arbitrary label values (not 0..k-1) are fine too.
  std::vector<int> shifted = labels;
  for (int& l : shifted)
  {
    l = 100 - 7 * l;
  }
  EXPECT_EQ(CompareLabelings(labels, shifted).DifferentCount, 0u);
}

TEST(LabelMatching, InvariantUnderPermutationsAndSymmetric)
{
  std::mt19937_64 generator(4);
  for (int trial = 0; trial < 20; ++trial)
  {
    const std::vector<int> a = RandomLabels(generator, 300, 5);
    std::vector<int> b = a;
    for (int& l : b)
    {
      if (generator() % 4 == 0)
      {
        l = static_cast<int>(generator() % 5);
      }
    }
    std::vector<int> p(5), q(5);
    std::iota(p.begin(), p.end(), 0);
    std::iota(q.begin(), q.end(), 0);
    std::shuffle(p.begin(), p.end(), generator);
    std::shuffle(q.begin(), q.end(), generator);
    const std::size_t reference = CompareLabelings(a, b).DifferentCount;
    EXPECT_EQ(CompareLabelings(Relabel(a, p), b).DifferentCount, reference);
    EXPECT_EQ(CompareLabelings(a, Relabel(b, q)).DifferentCount, reference);
    EXPECT_EQ(CompareLabelings(b, a).DifferentCount, reference);
    // Exhaustive check over all 5! matchings.
    std::vector<int> matching(5);
    std::iota(matching.begin(), matching.end(), 0);
    std::size_t best = 0;
    do
    {
      std::size_t agree = 0;
      for (std::size_t f = 0; f < a.size(); ++f)
      {
        agree += matching[static_cast<std::size_t>(a[f])] == b[f] ? 1 : 0;
      }
      best = std::max(best, agree);
    } while (std::next_permutation(matching.begin(), matching.end()));
    EXPECT_EQ(reference, a.size() - best);
  }
}

TEST(LabelMatching, DifferentLabelCounts)
{
  EXPECT_NEAR(CompareLabelings({ 0, 0, 1, 1 }, { 0, 0, 0, 0 }).PercentDifferent, 50.0, 1e-12);
  EXPECT_NEAR(CompareLabelings({ 0, 0, 0, 0 }, { 0, 1, 2, 3 }).PercentDifferent, 75.0, 1e-12);
}

TEST(LabelMatching, DegenerateInputs)
{
  EXPECT_EQ(CompareLabelings({}, {}).PercentDifferent, 0.0);
  EXPECT_EQ(CompareLabelings({ 7 }, { 2 }).PercentDifferent, 0.0);
  EXPECT_THROW(CompareLabelings({ 0, 1 }, { 0 }), LabelMatchingError);
  std::vector<int> many(3000);
  std::iota(many.begin(), many.end(), 0);
  EXPECT_THROW(CompareLabelings(many, many), LabelMatchingError);
}

TEST(LabelMatching, AssignmentMatchesExhaustiveSearch)
{
  std::mt19937_64 generator(6);
  for (int trial = 0; trial < 200; ++trial)
  {
    const std::size_t size = 1 + generator() % 7;
    std::vector<double> cost(size * size);
    for (double& c : cost)
    {
      c = static_cast<double>(generator() % 1000) / 10.0 - 30.0;
    }
    const std::vector<int> assignment = SolveAssignment(cost, size);
    std::vector<int> sorted = assignment;
    std::sort(sorted.begin(), sorted.end());
    std::vector<int> identity(size);
    std::iota(identity.begin(), identity.end(), 0);
    ASSERT_EQ(sorted, identity); // a permutation
    double total = 0.0;
    for (std::size_t r = 0; r < size; ++r)
    {
      total += cost[r * size + static_cast<std::size_t>(assignment[r])];
    }
    double best = std::numeric_limits<double>::infinity();
    do
    {
      double sum = 0.0;
      for (std::size_t r = 0; r < size; ++r)
      {
        sum += cost[r * size + static_cast<std::size_t>(identity[r])];
      }
      best = std::min(best, sum);
    } while (std::next_permutation(identity.begin(), identity.end()));
    ASSERT_NEAR(total, best, 1e-9) << "trial " << trial;
  }
  EXPECT_THROW(SolveAssignment({ 1.0, 2.0 }, 2), LabelMatchingError);
  EXPECT_THROW(SolveAssignment({ std::numeric_limits<double>::quiet_NaN() }, 1), LabelMatchingError);
  EXPECT_TRUE(SolveAssignment({}, 0).empty());
}

} // namespace
