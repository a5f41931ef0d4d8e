// SPDX-License-Identifier: BSD-3-Clause
// Disjoint sets with path halving, the lower root surviving a union (so a set's root is its
// lowest member): the skeleton's graph pieces and the distributed cut's clusters and bands.
#pragma once

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <vector>

namespace shapediameter
{

class UnionFind
{
public:
  explicit UnionFind(std::size_t size)
    : Parent(size)
  {
    std::iota(Parent.begin(), Parent.end(), std::int64_t{ 0 });
  }
  std::int64_t Find(std::int64_t i)
  {
    while (Parent[static_cast<std::size_t>(i)] != i)
    {
      Parent[static_cast<std::size_t>(i)] = Parent[static_cast<std::size_t>(Parent[static_cast<std::size_t>(i)])];
      i = Parent[static_cast<std::size_t>(i)];
    }
    return i;
  }
  /// Returns false if a and b were already in one set. The lower root survives.
  bool Unite(std::int64_t a, std::int64_t b)
  {
    a = Find(a);
    b = Find(b);
    if (a == b)
    {
      return false;
    }
    Parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
    return true;
  }

private:
  std::vector<std::int64_t> Parent;
};

} // namespace shapediameter
