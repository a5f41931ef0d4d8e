// SPDX-License-Identifier: BSD-3-Clause
// Release (Release.h) frees what `container = {}` keeps: the distributed steps free their
// gathered rows with it where their processes' memory peaks.
#include "Release.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <unordered_map>
#include <vector>

namespace
{

using namespace shapediameter;

TEST(Release, FreesTheCapacityThatAnEmptyAssignmentKeeps)
{
  std::vector<double> emptied(100000, 1.0);
  emptied = {};
  EXPECT_TRUE(emptied.empty());
  EXPECT_GE(emptied.capacity(), 100000u) << "if this fails, '= {}' frees after all and Release is only tidier";
  std::vector<double> released(100000, 1.0);
  Release(released);
  EXPECT_TRUE(released.empty());
  EXPECT_EQ(released.capacity(), 0u);

  std::unordered_map<std::int64_t, std::int64_t> map;
  for (std::int64_t i = 0; i < 10000; ++i)
  {
    map[i] = i;
  }
  Release(map);
  EXPECT_TRUE(map.empty());
  EXPECT_LT(map.bucket_count(), 100u);
}

} // namespace
