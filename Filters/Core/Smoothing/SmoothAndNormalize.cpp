// SPDX-License-Identifier: BSD-3-Clause
#include "Smoothing/SmoothAndNormalize.h"

#include "Mesh/FaceGraph.h"

#include <chrono>
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
  SmoothAndNormalizeResult result;

  // 1. The dual graph.
  Clock::time_point start = Clock::now();
  result.Graph = SharedFaceGraph(input.Points, input.FaceOffsets, input.FaceConnectivity, parallelFor);
  const FaceGraph& graph = *result.Graph;
  result.Timings.FaceGraphMs = MillisecondsSince(start);
  if (progress && !progress(0.1))
  {
    return AbortedResult();
  }

  // 2. The bilateral filter.
  start = Clock::now();
  BilateralSmoothingResult smoothed =
    SmoothBilateral(graph, input.FaceValues, options.Smoothing, parallelFor, SubProgress(progress, 0.1, 0.95));
  result.Timings.SmoothingMs = MillisecondsSince(start);
  if (smoothed.Aborted)
  {
    return AbortedResult();
  }
  result.Smoothed = std::move(smoothed.Values);

  // 3. The log normalisation of the given faces.
  start = Clock::now();
  const auto begin = result.Smoothed.begin();
  const std::vector<double> normalizedValues(begin + static_cast<std::ptrdiff_t>(input.NormalizedFirst),
    begin + static_cast<std::ptrdiff_t>(input.NormalizedLast));
  result.Normalized = NormalizeLogarithmic(normalizedValues, options.Normalization);
  std::tie(result.RangeMinimum, result.RangeMaximum) = NormalizationRange(normalizedValues, options.Normalization);
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
