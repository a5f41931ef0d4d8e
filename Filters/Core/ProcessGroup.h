// SPDX-License-Identifier: BSD-3-Clause
// The processes of a distributed run, as the core sees them: a few collectives, no MPI.
//
// A core step that runs on one process's share of a surface (its own faces plus a halo of
// neighbours, e.g. SmoothAndNormalize with a FaceShare) still needs measures of the whole
// surface: a mean edge length, quantiles and the range of a field. It computes them from its
// own faces and combines them over the processes with these collectives, which the VTK
// adapter implements over ParaView's controller (Filters/DistributedSupport.cxx). A serial
// run uses SingleProcess(), for which every collective is the identity.
//
// Contract: every process calls the same collectives in the same order, with vectors of the
// same length (AllGather excepted). An implementation may throw shapediameter::Error from a
// collective when another process stopped (bad input, an exception), so that every process
// reports it instead of waiting.
//
// The helpers below give results that are identical on every process and equal, bit for bit,
// to the same measure computed by one process over all the faces: exact sums (ExactSum),
// minima, maxima and order statistics do not depend on how the values are split.
#pragma once

#include "Errors.h"
#include "ExactSum.h"

#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

namespace shapediameter
{

class ProcessGroup
{
public:
  virtual ~ProcessGroup() = default;
  /// Every process's `values`, concatenated in process order, on every process.
  virtual std::vector<double> AllGather(const std::vector<double>& values) const = 0;
  /// Element-wise sums over the processes, in place.
  virtual void SumInPlace(std::vector<std::int64_t>& values) const = 0;
  /// Element-wise maxima over the processes, in place.
  virtual void MaxInPlace(std::vector<double>& values) const = 0;
  /// This process's index, in [0, number of processes); 0 is the first process.
  virtual int Rank() const = 0;
  /// On the first process, every process's `values` (one entry per process, in process
  /// order); an empty list on the others. For a step that must see the whole surface's data
  /// in one place (the partition's graph cut).
  virtual std::vector<std::vector<double>> GatherOnFirst(const std::vector<double>& values) const = 0;
  /**
   * Each process's part of a result the first process computed: the first process calls
   * `part(r)` for every process r, one at a time (so that it never holds all the parts at
   * once), and every process returns its own part. `part` is not called on the others.
   */
  virtual std::vector<double> ScatterFromFirst(const std::function<std::vector<double>(int process)>& part) const = 0;
};

/**
 * Thrown, on every process at the same point, by a step run on shares of a surface when the
 * shares' halo turns out narrower than the neighbourhood the step needs (the width is known
 * exactly only from whole-surface measures): the caller must run the step on the whole surface
 * instead. Not bad input: callers that report errors let it through.
 */
class HaloTooNarrowError : public Error
{
public:
  using Error::Error;
};

/// The group of one process: every collective returns its input.
const ProcessGroup& SingleProcess();

/// The exact sum over the processes of each one's `local` sum, correctly rounded.
double SumOverProcesses(const ExactSum& local, const ProcessGroup& group);

/**
 * Every process's values on the first process, one process at a time, so that the first never
 * holds more than one process's at once: in process order, the process whose turn it is calls
 * `mine` and sends what it returns; the first process passes each to `take(process, values)`
 * (not called on the others). One GatherOnFirst per process.
 */
void GatherOnFirstInTurn(const std::function<std::vector<double>()>& mine,
  const std::function<void(std::size_t process, std::vector<double>&& values)>& take, const ProcessGroup& group);

/// The minimum and maximum of every process's `values` (+inf and -inf when there are none).
std::pair<double, double> RangeOverProcesses(const std::vector<double>& values, const ProcessGroup& group);

/**
 * The values of the given ranks (0-based, each in [0, n) for n values in all) in the sorted
 * union of every process's finite `values`: what std::nth_element would find in one vector of
 * all of them. Found by narrowing an interval of the doubles' order, 256 buckets per round
 * (at most 8 rounds of one sum of 256 counts per rank asked), so that no process holds more
 * than its own values.
 */
std::vector<double> OrderStatisticsOverProcesses(
  std::vector<double> values, const std::vector<std::int64_t>& ranks, const ProcessGroup& group);

} // namespace shapediameter
