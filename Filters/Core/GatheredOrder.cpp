// SPDX-License-Identifier: BSD-3-Clause
#include "GatheredOrder.h"

#include <algorithm>

namespace shapediameter
{

std::int64_t GatheredOrder::IndexOf(std::int64_t id) const
{
  if (!this->IndexOfId.empty())
  {
    return id >= 0 && static_cast<std::size_t>(id) < this->IndexOfId.size() ? this->IndexOfId[static_cast<std::size_t>(id)]
                                                                             : -1;
  }
  const auto found = std::lower_bound(this->Ids.begin(), this->Ids.end(), id);
  return found != this->Ids.end() && *found == id ? found - this->Ids.begin() : -1;
}

GatheredOrder OrderGatheredIds(const std::vector<std::vector<double>>& processRows, std::size_t width)
{
  GatheredOrder order;
  const std::size_t processes = processRows.size();
  order.Index.resize(processes);
  order.Used.resize(processes);
  std::size_t total = 0;
  std::int64_t largest = -1;
  for (std::size_t p = 0; p < processes; ++p)
  {
    const std::size_t rows = processRows[p].size() / width;
    order.Index[p].resize(rows);
    order.Used[p].assign(rows, 0);
    total += rows;
    for (std::size_t r = 0; r < rows; ++r)
    {
      largest = std::max(largest, static_cast<std::int64_t>(processRows[p][width * r]));
    }
  }
  const auto id = [&](std::size_t p, std::size_t r) { return static_cast<std::int64_t>(processRows[p][width * r]); };
  if (static_cast<double>(largest) < 2.0 * static_cast<double>(total) + 1024.0)
  {
    order.IndexOfId.assign(static_cast<std::size_t>(largest + 1), -1);
    for (std::size_t p = 0; p < processes; ++p)
    {
      for (std::size_t r = 0; r < order.Index[p].size(); ++r)
      {
        order.IndexOfId[static_cast<std::size_t>(id(p, r))] = 0;
      }
    }
    for (std::size_t i = 0; i < order.IndexOfId.size(); ++i)
    {
      if (order.IndexOfId[i] == 0)
      {
        order.IndexOfId[i] = static_cast<std::int64_t>(order.Ids.size());
        order.Ids.push_back(static_cast<std::int64_t>(i));
      }
    }
    std::vector<std::uint8_t> taken(order.Ids.size(), 0);
    for (std::size_t p = 0; p < processes; ++p) // lowest process first: its rows are used
    {
      for (std::size_t r = 0; r < order.Index[p].size(); ++r)
      {
        const std::int64_t w = order.IndexOfId[static_cast<std::size_t>(id(p, r))];
        order.Index[p][r] = w;
        order.Used[p][r] = taken[static_cast<std::size_t>(w)] ? 0 : 1;
        taken[static_cast<std::size_t>(w)] = 1;
      }
    }
    return order;
  }
  struct Entry
  {
    std::int64_t Id;
    std::size_t Process, Row;
  };
  std::vector<Entry> entries;
  entries.reserve(total);
  for (std::size_t p = 0; p < processes; ++p)
  {
    for (std::size_t r = 0; r < order.Index[p].size(); ++r)
    {
      entries.push_back(Entry{ id(p, r), p, r });
    }
  }
  // Ties (one id from several rows): the lowest process's first row is used.
  std::sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) {
    return a.Id != b.Id ? a.Id < b.Id : a.Process != b.Process ? a.Process < b.Process : a.Row < b.Row;
  });
  for (const Entry& entry : entries)
  {
    const bool first = order.Ids.empty() || order.Ids.back() != entry.Id;
    if (first)
    {
      order.Ids.push_back(entry.Id);
    }
    order.Index[entry.Process][entry.Row] = static_cast<std::int64_t>(order.Ids.size()) - 1;
    order.Used[entry.Process][entry.Row] = first ? 1 : 0;
  }
  return order;
}

} // namespace shapediameter
