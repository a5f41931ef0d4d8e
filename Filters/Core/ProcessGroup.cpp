// SPDX-License-Identifier: BSD-3-Clause
#include "ProcessGroup.h"

#include <algorithm>
#include <cstring>
#include <limits>

namespace shapediameter
{
namespace
{
class Single final : public ProcessGroup
{
public:
  std::vector<double> AllGather(const std::vector<double>& values) const override { return values; }
  void SumInPlace(std::vector<std::int64_t>&) const override {}
  void MaxInPlace(std::vector<double>&) const override {}
};

/// The doubles' order as unsigned integers: a < b (finite, -0 before +0) iff Key(a) < Key(b).
std::uint64_t Key(double value)
{
  std::uint64_t bits = 0;
  std::memcpy(&bits, &value, sizeof bits);
  constexpr std::uint64_t sign = std::uint64_t{ 1 } << 63;
  return (bits & sign) ? ~bits : (bits | sign);
}

double FromKey(std::uint64_t key)
{
  constexpr std::uint64_t sign = std::uint64_t{ 1 } << 63;
  const std::uint64_t bits = (key & sign) ? (key & ~sign) : ~key;
  double value = 0.0;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}
} // namespace

const ProcessGroup& SingleProcess()
{
  static const Single single;
  return single;
}

double SumOverProcesses(const ExactSum& local, const ProcessGroup& group)
{
  ExactSum all;
  all.Add(group.AllGather(local.Partials()));
  return all.Rounded();
}

std::pair<double, double> RangeOverProcesses(const std::vector<double>& values, const ProcessGroup& group)
{
  std::vector<double> negatedMinimumAndMaximum{ -std::numeric_limits<double>::infinity(),
    -std::numeric_limits<double>::infinity() };
  for (const double value : values)
  {
    negatedMinimumAndMaximum[0] = std::max(negatedMinimumAndMaximum[0], -value);
    negatedMinimumAndMaximum[1] = std::max(negatedMinimumAndMaximum[1], value);
  }
  group.MaxInPlace(negatedMinimumAndMaximum);
  return { -negatedMinimumAndMaximum[0], negatedMinimumAndMaximum[1] };
}

std::vector<double> OrderStatisticsOverProcesses(
  std::vector<double> values, const std::vector<std::int64_t>& ranks, const ProcessGroup& group)
{
  std::vector<std::uint64_t> keys(values.size());
  std::transform(values.begin(), values.end(), keys.begin(), Key);
  std::sort(keys.begin(), keys.end());
  // For each rank r: the smallest key K with at least r + 1 keys <= K, by bisection on [low, high].
  const std::size_t count = ranks.size();
  std::vector<std::uint64_t> low(count, 0), high(count, std::numeric_limits<std::uint64_t>::max());
  std::vector<std::int64_t> atMost(count);
  for (int round = 0; round < 64; ++round)
  {
    bool open = false;
    for (std::size_t i = 0; i < count; ++i)
    {
      const std::uint64_t middle = low[i] + (high[i] - low[i]) / 2;
      atMost[i] = std::upper_bound(keys.begin(), keys.end(), middle) - keys.begin();
      open = open || low[i] < high[i];
    }
    // Every process takes the same decisions (the sums are the same everywhere), so all of
    // them leave the loop in the same round.
    std::vector<std::int64_t> sums(atMost);
    sums.push_back(open ? 1 : 0);
    group.SumInPlace(sums);
    if (sums.back() == 0)
    {
      break;
    }
    for (std::size_t i = 0; i < count; ++i)
    {
      const std::uint64_t middle = low[i] + (high[i] - low[i]) / 2;
      if (sums[i] >= ranks[i] + 1)
      {
        high[i] = middle;
      }
      else
      {
        low[i] = middle + 1;
      }
    }
  }
  std::vector<double> result(count);
  std::transform(low.begin(), low.end(), result.begin(), FromKey);
  return result;
}

} // namespace shapediameter
