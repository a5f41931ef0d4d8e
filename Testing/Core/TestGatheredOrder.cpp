// SPDX-License-Identifier: BSD-3-Clause
// The whole order of rows gathered from processes by global id (GatheredOrder.h): the table
// of dense ids and the sort of sparse ones agree, and a repeated id is taken once.
#include "GatheredOrder.h"

#include <gtest/gtest.h>

#include <vector>

namespace
{

using namespace shapediameter;

/// Rows of two values (id, payload) for three processes; ids 7 and 2 are sent twice.
std::vector<std::vector<double>> RowsWithRepeats(double scale)
{
  return { { 7 * scale, 0, 3 * scale, 1 }, {}, { 2 * scale, 2, 7 * scale, 3, 2 * scale, 4, 0, 5 } };
}

TEST(GatheredOrder, DenseAndSparseIdsGiveTheSameOrderAndTakeARepeatedIdOnce)
{
  for (const double scale : { 1.0, 1e6 }) // a table, then a sort
  {
    const GatheredOrder order = OrderGatheredIds(RowsWithRepeats(scale), 2);
    EXPECT_EQ(order.IndexOfId.empty(), scale > 1.0);
    const auto id = [&](double value) { return static_cast<std::int64_t>(value * scale); };
    EXPECT_EQ(order.Ids, (std::vector<std::int64_t>{ 0, id(2), id(3), id(7) }));
    EXPECT_EQ(order.Index, (std::vector<std::vector<std::int64_t>>{ { 3, 2 }, {}, { 1, 3, 1, 0 } }));
    // Id 7: process 0's row; id 2: process 2's first row.
    EXPECT_EQ(order.Used, (std::vector<std::vector<std::uint8_t>>{ { 1, 1 }, {}, { 1, 0, 0, 1 } }));
    EXPECT_EQ(order.IndexOf(id(3)), 2);
    EXPECT_EQ(order.IndexOf(id(5)), -1);
    EXPECT_EQ(order.IndexOf(-1), -1);
    EXPECT_EQ(order.IndexOf(id(9)), -1);
  }
}

TEST(GatheredOrder, NoRowsGiveAnEmptyOrder)
{
  const GatheredOrder order = OrderGatheredIds({ {}, {} });
  EXPECT_TRUE(order.Ids.empty());
  EXPECT_EQ(order.Index.size(), 2u);
  EXPECT_EQ(order.IndexOf(0), -1);
}

} // namespace
