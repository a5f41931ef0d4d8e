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
  int Rank() const override { return 0; }
  std::vector<std::vector<double>> GatherOnFirst(const std::vector<double>& values) const override
  {
    return { values };
  }
  std::vector<double> ScatterFromFirst(const std::function<std::vector<double>(int)>& part) const override
  {
    return part(0);
  }
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

void GatherOnFirstInTurn(const std::function<std::vector<double>()>& mine,
  const std::function<void(std::size_t process, std::vector<double>&& values)>& take, const ProcessGroup& group)
{
  const std::size_t processes = group.AllGather({ 0.0 }).size();
  for (std::size_t p = 0; p < processes; ++p)
  {
    std::vector<std::vector<double>> gathered =
      group.GatherOnFirst(static_cast<std::size_t>(group.Rank()) == p ? mine() : std::vector<double>());
    if (group.Rank() == 0)
    {
      take(p, std::move(gathered.at(p)));
    }
  }
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
  // For each rank r: the smallest key K with at least r + 1 keys <= K, inside [low, high]. Each
  // round splits every open interval into Buckets and counts, over the processes, the keys up
  // to each bucket's end: 8 rounds narrow 2^64 keys to one.
  constexpr std::uint64_t Buckets = 256;
  const std::size_t count = ranks.size();
  std::vector<std::uint64_t> low(count, 0), high(count, std::numeric_limits<std::uint64_t>::max());
  const auto bucketEnd = [&](std::size_t i, std::uint64_t bucket) {
    const std::uint64_t width = (high[i] - low[i]) / Buckets + 1;
    const unsigned __int128 end = static_cast<unsigned __int128>(low[i]) +
      static_cast<unsigned __int128>(bucket + 1) * width - 1;
    return end >= high[i] ? high[i] : static_cast<std::uint64_t>(end);
  };
  for (;;)
  {
    // Every process takes the same decisions (the sums are the same everywhere), so all of
    // them leave the loop in the same round.
    std::vector<std::int64_t> atMost(count * Buckets + 1, 0);
    bool open = false;
    for (std::size_t i = 0; i < count; ++i)
    {
      open = open || low[i] < high[i];
      for (std::uint64_t b = 0; b < Buckets && low[i] < high[i]; ++b)
      {
        atMost[i * Buckets + b] = std::upper_bound(keys.begin(), keys.end(), bucketEnd(i, b)) - keys.begin();
      }
    }
    atMost.back() = open ? 1 : 0;
    group.SumInPlace(atMost);
    if (atMost.back() == 0)
    {
      break;
    }
    for (std::size_t i = 0; i < count; ++i)
    {
      if (low[i] == high[i])
      {
        continue;
      }
      std::uint64_t b = 0;
      while (b + 1 < Buckets && atMost[i * Buckets + b] < ranks[i] + 1)
      {
        ++b;
      }
      const std::uint64_t end = bucketEnd(i, b);
      low[i] = b == 0 ? low[i] : bucketEnd(i, b - 1) + 1;
      high[i] = end;
    }
  }
  std::vector<double> result(count);
  std::transform(low.begin(), low.end(), result.begin(), FromKey);
  return result;
}

} // namespace shapediameter
