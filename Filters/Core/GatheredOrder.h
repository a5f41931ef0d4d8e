// SPDX-License-Identifier: BSD-3-Clause
// The whole surface's order of entries (faces, points) that every process sent the first
// process with their global ids: what the distributed partition and skeleton assemble by.
//
// What it computes
//   From one list per process (in process order) of rows whose first value is a global id:
//   the distinct ids in increasing order, each row's place among them, and which row is used
//   for its id (a face or point several processes hold is taken once: the lowest process's
//   first row). Dense ids (the reader's 0 .. n - 1, largest id below 2 n + 1024) go through a
//   table, in linear time; others are sorted.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace shapediameter
{

/// Whether a global id can travel as a double in the collectives: exactly, in [0, 2^53).
inline bool IsGatherableId(std::int64_t id)
{
  return id >= 0 && id < (std::int64_t{ 1 } << 53);
}

struct GatheredOrder
{
  /// The distinct ids, increasing: entry w of the whole has id Ids[w].
  std::vector<std::int64_t> Ids;
  /// Per process, per row: the index of its id in Ids.
  std::vector<std::vector<std::int64_t>> Index;
  /// Per process, per row: 1 for the row used for its id.
  std::vector<std::vector<std::uint8_t>> Used;
  /// Per id in [0, largest id], its index (-1: none), when the ids are dense; else empty.
  std::vector<std::int64_t> IndexOfId;

  /// The index of `id` in Ids, -1 when no process sent it.
  std::int64_t IndexOf(std::int64_t id) const;
};

/// Rows of `width` values (ids exact as doubles: below 2^53, non-negative), one list per
/// process; see the header comment.
GatheredOrder OrderGatheredIds(const std::vector<std::vector<double>>& processRows, std::size_t width = 1);

} // namespace shapediameter
