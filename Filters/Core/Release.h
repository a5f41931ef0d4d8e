// SPDX-License-Identifier: BSD-3-Clause
// Freeing a container's memory at a point of a step, where a step's peak depends on it.
#pragma once

namespace shapediameter
{

/// Frees `container`'s memory now. `container = {}` does not: for a std::vector (or an
/// unordered map) it is the initializer-list assignment, which empties the container but keeps
/// its capacity (and buckets) until it is destroyed.
template <typename Container>
void Release(Container& container)
{
  Container().swap(container);
}

} // namespace shapediameter
