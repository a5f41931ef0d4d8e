// SPDX-License-Identifier: BSD-3-Clause
#include "Smoothing/SmoothAndNormalize.h"

#include "Mesh/FaceGraph.h"

#include <chrono>
#include <cmath>
#include <optional>
#include <string>
#include <tuple>
#include <utility>

namespace shapediameter
{
namespace
{
using Clock = std::chrono::steady_clock;

double MillisecondsSince(Clock::time_point start)
{
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

SmoothAndNormalizeResult AbortedResult()
{
  SmoothAndNormalizeResult result;
  result.Aborted = true;
  return result;
}

/// The values of the faces flagged in `own` among [first, last).
std::vector<double> OwnValues(const std::vector<double>& values, const std::vector<std::uint8_t>& own,
  std::size_t first, std::size_t last)
{
  std::vector<double> kept;
  for (std::size_t f = first; f < last; ++f)
  {
    if (own[f] != 0)
    {
      kept.push_back(values[f]);
    }
  }
  return kept;
}

/// The whole surface's measures the smoothing scales by, from each process's own faces.
/// Collective; throws bad input before its first collective only, and HaloTooNarrowError on
/// every process at once.
SmoothingShare WholeSurfaceMeasures(
  const SmoothAndNormalizeInput& input, const FaceShare& share, const BilateralSmoothingOptions& options)
{
  const std::vector<std::uint8_t>& counted = share.Counted ? *share.Counted : share.Own;
  if (counted.size() != share.Own.size())
  {
    throw Error("smooth and normalize: " + std::to_string(counted.size()) + " counted-face flags for " +
      std::to_string(share.Own.size()) + " faces");
  }
  const std::vector<double> ownValues = OwnValues(input.FaceValues, counted, 0, counted.size());
  for (const double value : ownValues)
  {
    if (!std::isfinite(value))
    {
      throw Error("non-finite value on a face of this process");
    }
  }
  // Collectives from here on, in the same order on every process.
  const double meanEdgeLength =
    MeanEdgeLengthOverProcesses(input.Points, input.FaceOffsets, input.FaceConnectivity, counted, share.Group);
  const double radius = NeighborhoodRadiusOf(options, meanEdgeLength); // the same on every process
  if (share.HaloWidth > 0.0 && radius > share.HaloWidth)
  {
    throw HaloTooNarrowError("smooth and normalize: the neighbourhood radius " + std::to_string(radius) +
      " exceeds the halo's width " + std::to_string(share.HaloWidth));
  }
  const auto [minimum, maximum] = RangeOverProcesses(ownValues, share.Group);
  const double spread = RobustSpreadOverProcesses(ownValues, share.Group);
  return SmoothingShare{ share.Own, meanEdgeLength, spread, std::isfinite(minimum) ? minimum : 0.0,
    std::isfinite(maximum) ? maximum : 0.0 };
}

/// Whether any process aborted. Collective.
bool AnyProcessAborted(bool aborted, const ProcessGroup& group)
{
  std::vector<std::int64_t> count{ aborted ? 1 : 0 };
  group.SumInPlace(count);
  return count[0] > 0;
}
} // namespace

SmoothAndNormalizeResult SmoothAndNormalize(const SmoothAndNormalizeInput& input,
  const SmoothAndNormalizeOptions& options, const ParallelFor& parallelFor, const ProgressCallback& progress)
{
  const std::size_t faceCount = input.FaceOffsets.empty() ? 0 : input.FaceOffsets.size() - 1;
  if (input.NormalizedFirst > input.NormalizedLast || input.NormalizedLast > faceCount)
  {
    throw Error("smooth and normalize: normalized faces [" +
      std::to_string(input.NormalizedFirst) + ", " + std::to_string(input.NormalizedLast) + ") of " +
      std::to_string(faceCount) + " faces");
  }
  // The user-facing alpha range, narrower than NormalizeLogarithmic's own (Normalization.h);
  // checked before any work. The smoothing options are checked by SmoothBilateral.
  CheckRange(options.Normalization.Alpha, AlphaRange, "smooth and normalize: Alpha");
  const FaceShare* share = input.Share;
  if (share && share->Own.size() != faceCount)
  {
    throw Error("smooth and normalize: " + std::to_string(share->Own.size()) + " face flags for " +
      std::to_string(faceCount) + " faces");
  }
  if (options.Normalization.UseGivenRange)
  {
    NormalizationRange({}, options.Normalization); // throws on a bad given range, before any work
  }
  SmoothAndNormalizeResult result;

  // 1. The dual graph (and, on a share, the whole surface's measures).
  Clock::time_point start = Clock::now();
  result.Graph = SharedFaceGraph(input.Points, input.FaceOffsets, input.FaceConnectivity, parallelFor);
  const FaceGraph& graph = *result.Graph;
  std::optional<SmoothingShare> smoothingShare;
  if (share)
  {
    smoothingShare.emplace(WholeSurfaceMeasures(input, *share, options.Smoothing));
  }
  result.Timings.FaceGraphMs = MillisecondsSince(start);
  // A process of a distributed run does not leave before the others know (they would wait).
  const bool stopAfterGraph = progress && !progress(0.1);
  if (stopAfterGraph && !share)
  {
    return AbortedResult();
  }

  // 2. The bilateral filter.
  start = Clock::now();
  BilateralSmoothingResult smoothed;
  if (!stopAfterGraph)
  {
    smoothed = SmoothBilateral(graph, input.FaceValues, options.Smoothing, parallelFor,
      SubProgress(progress, 0.1, 0.95), smoothingShare ? &*smoothingShare : nullptr);
  }
  result.Timings.SmoothingMs = MillisecondsSince(start);
  const bool aborted = stopAfterGraph || smoothed.Aborted;
  if (share ? AnyProcessAborted(aborted, share->Group) : aborted)
  {
    return AbortedResult();
  }
  result.Smoothed = std::move(smoothed.Values);

  // 3. The log normalisation of the given faces.
  start = Clock::now();
  const auto begin = result.Smoothed.begin();
  const std::vector<double> normalizedValues(begin + static_cast<std::ptrdiff_t>(input.NormalizedFirst),
    begin + static_cast<std::ptrdiff_t>(input.NormalizedLast));
  NormalizationOptions normalization = options.Normalization;
  bool constant = false; // over the whole surface: every face maps to 0, as in a serial run
  if (share && !normalization.UseGivenRange)
  {
    // The whole surface's range, given to each process's normalisation.
    const auto [minimum, maximum] = RangeOverProcesses(
      OwnValues(result.Smoothed, share->Own, input.NormalizedFirst, input.NormalizedLast), share->Group);
    constant = !(maximum > minimum);
    normalization.UseGivenRange = !constant;
    normalization.RangeMinimum = std::isfinite(minimum) ? minimum : 0.0; // no face anywhere: 0
    normalization.RangeMaximum = constant ? normalization.RangeMinimum : maximum;
  }
  if (constant)
  {
    result.Normalized.assign(normalizedValues.size(), 0.0);
    result.RangeMinimum = result.RangeMaximum = normalization.RangeMinimum;
  }
  else
  {
    result.Normalized = NormalizeLogarithmic(normalizedValues, normalization);
    std::tie(result.RangeMinimum, result.RangeMaximum) = NormalizationRange(normalizedValues, normalization);
  }
  result.Timings.NormalizationMs = MillisecondsSince(start);
  if (progress)
  {
    progress(1.0); // the result is complete: an abort requested now has nothing left to stop
  }
  return result;
}

SmoothAndNormalizeResult SmoothAndNormalize(PointsView points, TrianglesView triangles,
  const std::vector<double>& faceValues, const SmoothAndNormalizeOptions& options,
  const ParallelFor& parallelFor, const ProgressCallback& progress)
{
  std::vector<std::int64_t> offsets, connectivity;
  TriangleFaces(triangles, offsets, connectivity);
  const auto faceCount = static_cast<std::size_t>(triangles.rows());
  return SmoothAndNormalize(
    SmoothAndNormalizeInput{ points, offsets, connectivity, faceValues, 0, faceCount }, options, parallelFor, progress);
}

} // namespace shapediameter
