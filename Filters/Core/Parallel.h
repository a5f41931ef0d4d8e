// SPDX-License-Identifier: BSD-3-Clause
// The one threading primitive of the core.
//
// Core algorithms take a ParallelFor and never create threads themselves: the VTK
// adapters pass one backed by vtkSMPTools, tests pass SerialFor or ThreadedFor.
// Every core algorithm must give bit-identical results whatever the split of
// [0, count) into ranges: each index writes only its own outputs and reductions
// are done serially afterwards in index order.
#pragma once

#include <algorithm>
#include <cstddef>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace shapediameter
{

/// body(begin, end) processes the indices [begin, end).
using RangeBody = std::function<void(std::size_t begin, std::size_t end)>;
/// Calls body over disjoint ranges covering [0, count), possibly concurrently.
using ParallelFor = std::function<void(std::size_t count, const RangeBody& body)>;

/// Reports the fraction of work done in [0, 1]; returns false to request an abort.
using ProgressCallback = std::function<bool(double fraction)>;

/// Maps a step's progress [0, 1] to [begin, end] of the whole computation (empty without a
/// callback). Refers to `progress`, which must outlive the returned callback.
inline ProgressCallback SubProgress(const ProgressCallback& progress, double begin, double end)
{
  if (!progress)
  {
    return {};
  }
  return [&progress, begin, end](double fraction) { return progress(begin + (end - begin) * fraction); };
}

/// Progress of parts solved concurrently, each weighted by its size; the callback is called
/// under a lock and never goes backwards. Any part's abort request is seen by all.
class SharedProgress
{
public:
  SharedProgress(ProgressCallback progress, std::size_t total)
    : Progress(std::move(progress))
    , Total(static_cast<double>(std::max<std::size_t>(1, total)))
  {
  }

  ProgressCallback ForPart(std::size_t size)
  {
    if (!Progress)
    {
      return nullptr;
    }
    return [this, size = static_cast<double>(size), reported = 0.0](double fraction) mutable {
      const std::lock_guard<std::mutex> lock(Mutex);
      Done += (fraction - reported) * size;
      reported = fraction;
      Highest = std::max(Highest, std::min(1.0, Done / Total));
      Continue = Continue && Progress(Highest);
      return Continue;
    };
  }

private:
  ProgressCallback Progress;
  double Total;
  std::mutex Mutex;
  double Done = 0.0;
  double Highest = 0.0;
  bool Continue = true;
};

inline void SerialFor(std::size_t count, const RangeBody& body)
{
  if (count > 0)
  {
    body(0, count);
  }
}

/// A std::thread implementation for tests and VTK-free users.
inline ParallelFor ThreadedFor(unsigned threadCount)
{
  return [threadCount](std::size_t count, const RangeBody& body) {
    const std::size_t threads = std::max<std::size_t>(1, std::min<std::size_t>(threadCount, count));
    if (threads <= 1)
    {
      SerialFor(count, body);
      return;
    }
    std::vector<std::thread> workers;
    const std::size_t chunk = (count + threads - 1) / threads;
    for (std::size_t begin = 0; begin < count; begin += chunk)
    {
      workers.emplace_back([&body, begin, end = std::min(count, begin + chunk)] { body(begin, end); });
    }
    for (auto& worker : workers)
    {
      worker.join();
    }
  };
}

} // namespace shapediameter
