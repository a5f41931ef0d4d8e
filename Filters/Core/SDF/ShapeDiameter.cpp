// SPDX-License-Identifier: BSD-3-Clause
#include "SDF/ShapeDiameter.h"

#include "RayCasting/ConeSampling.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>
#include <string>

namespace shapediameter
{

namespace
{

/// Steps 3-4 of the header on raw arrays; scratch holds count doubles.
double RobustWeightedMeanOf(
  const double* lengths, const double* weights, int count, double* scratch, int& keptCount)
{
  int finiteCount = 0;
  double sum = 0;
  for (int i = 0; i < count; ++i)
  {
    if (std::isfinite(lengths[i]))
    {
      scratch[finiteCount++] = lengths[i];
      sum += lengths[i];
    }
  }
  keptCount = 0;
  if (finiteCount == 0)
  {
    return 0;
  }
  const double mean = sum / finiteCount;
  double squares = 0;
  for (int i = 0; i < finiteCount; ++i)
  {
    squares += (scratch[i] - mean) * (scratch[i] - mean);
  }
  const double sigma = std::sqrt(squares / finiteCount);

  // Insertion sort for the usual few dozen rays, where it beats the library sorts (measured;
  // a branch-free ranking by counting was slower still).
  if (finiteCount > 64)
  {
    std::sort(scratch, scratch + finiteCount);
  }
  for (int i = 1; i < finiteCount && finiteCount <= 64; ++i)
  {
    const double value = scratch[i];
    int j = i;
    for (; j > 0 && scratch[j - 1] > value; --j)
    {
      scratch[j] = scratch[j - 1];
    }
    scratch[j] = value;
  }
  const int middle = finiteCount / 2;
  const double upper = scratch[middle];
  double median = upper;
  double halfGap = 0;
  if (finiteCount % 2 == 0)
  {
    const double lower = scratch[middle - 1];
    median = 0.5 * (lower + upper);
    halfGap = std::max(median - lower, upper - median);
  }
  const double threshold = std::max(sigma, halfGap);

  double weightedSum = 0;
  double weightSum = 0;
  for (int i = 0; i < count; ++i)
  {
    if (std::isfinite(lengths[i]) && std::abs(lengths[i] - median) <= threshold)
    {
      weightedSum += weights[i] * lengths[i];
      weightSum += weights[i];
      ++keptCount;
    }
  }
  const double value = weightedSum / weightSum;
  if (!std::isfinite(value))
  {
    keptCount = 0;
    return 0;
  }
  return value;
}

/// Unit normal of the origin, or false when it has none.
bool UnitNormal(const RayOrigins& origins, Eigen::Index i, double normal[3])
{
  const double x = origins.Normals(i, 0), y = origins.Normals(i, 1), z = origins.Normals(i, 2);
  const double length = std::sqrt(x * x + y * y + z * z);
  if (!(length > 0) || !std::isfinite(length))
  {
    return false;
  }
  normal[0] = x / length;
  normal[1] = y / length;
  normal[2] = z / length;
  return true;
}

double Median(std::vector<double> samples)
{
  if (samples.empty())
  {
    return 0;
  }
  const std::size_t middle = samples.size() / 2;
  std::nth_element(samples.begin(), samples.begin() + static_cast<std::ptrdiff_t>(middle),
    samples.end());
  const double upper = samples[middle];
  if (samples.size() % 2 == 1)
  {
    return upper;
  }
  const double lower = *std::max_element(
    samples.begin(), samples.begin() + static_cast<std::ptrdiff_t>(middle));
  return 0.5 * (lower + upper);
}

} // namespace

void CheckShapeDiameterOptions(const ShapeDiameterOptions& options)
{
  CheckRange(options.ConeAngle, ConeAngleRange, "shape diameter: ConeAngle");
  CheckRange(options.VertexOriginOffset, VertexOriginOffsetRange, "shape diameter: VertexOriginOffset");
  if (options.OriginsPerChunk < 1)
  {
    throw Error("shape diameter: OriginsPerChunk must be >= 1");
  }
  if (options.Mode != ShapeDiameterMode::Exact && options.Mode != ShapeDiameterMode::Adaptive)
  {
    throw Error("shape diameter: unknown Mode");
  }
  CheckRange(options.Tolerance, ToleranceRange, "shape diameter: Tolerance");
  CheckRange(options.SpacingFraction, SpacingFractionRange, "shape diameter: SpacingFraction");
}

void CheckRayOrigins(const RayOrigins& origins)
{
  const auto n = origins.Points.rows();
  if (origins.Normals.rows() != n)
  {
    throw Error("shape diameter: " + std::to_string(n) + " origins but " +
      std::to_string(origins.Normals.rows()) + " normals");
  }
  if (origins.FirstAxes.rows() != 0 && origins.FirstAxes.rows() != n)
  {
    throw Error("shape diameter: FirstAxes must have 0 or one row per origin");
  }
  if (!origins.SourceTriangles.empty() &&
    origins.SourceTriangles.size() != static_cast<std::size_t>(n))
  {
    throw Error("shape diameter: SourceTriangles must be empty or one per origin");
  }
  if (!origins.Skip.empty() && origins.Skip.size() != static_cast<std::size_t>(n))
  {
    throw Error("shape diameter: Skip must be empty or one per origin");
  }
}

double RobustWeightedMean(
  const std::vector<double>& lengths, const std::vector<double>& weights, int& keptCount)
{
  if (lengths.size() != weights.size())
  {
    throw Error("shape diameter: as many weights as lengths are needed");
  }
  std::vector<double> scratch(lengths.size());
  return RobustWeightedMeanOf(
    lengths.data(), weights.data(), static_cast<int>(lengths.size()), scratch.data(), keptCount);
}

RayOrigins MakeFaceOrigins(const PointsView& points, const TrianglesView& triangles)
{
  const Eigen::Index n = triangles.rows();
  RayOrigins origins;
  origins.Points.resize(n, 3);
  origins.Normals.resize(n, 3);
  origins.FirstAxes.resize(n, 3);
  origins.SourceTriangles.resize(static_cast<std::size_t>(n));
  origins.Skip.assign(static_cast<std::size_t>(n), 0);
  const auto pointCount = static_cast<std::int64_t>(points.rows());
  for (Eigen::Index t = 0; t < n; ++t)
  {
    for (int c = 0; c < 3; ++c)
    {
      if (triangles(t, c) < 0 || triangles(t, c) >= pointCount)
      {
        throw Error("shape diameter: triangle " + std::to_string(t) +
          " has a vertex index out of range: " + std::to_string(triangles(t, c)));
      }
    }
    const Eigen::RowVector3d p0 = points.row(triangles(t, 0));
    const Eigen::RowVector3d p1 = points.row(triangles(t, 1));
    const Eigen::RowVector3d p2 = points.row(triangles(t, 2));
    const Eigen::RowVector3d edge = p1 - p0;
    const Eigen::RowVector3d normal = edge.cross(p2 - p0);
    const double length = normal.norm();
    origins.Points.row(t) = (p0 + p1 + p2) / 3.0;
    origins.FirstAxes.row(t) = edge;
    origins.SourceTriangles[static_cast<std::size_t>(t)] = t;
    if (length > 0 && std::isfinite(length) && origins.Points.row(t).allFinite())
    {
      origins.Normals.row(t) = normal / length;
    }
    else
    {
      origins.Normals.row(t).setZero();
      origins.Skip[static_cast<std::size_t>(t)] = 1;
    }
  }
  return origins;
}

RayOrigins MakeVertexOrigins(const PointsView& points, const PointsView& normals)
{
  if (points.rows() != normals.rows())
  {
    throw Error("shape diameter: " + std::to_string(points.rows()) + " points but " +
      std::to_string(normals.rows()) + " normals");
  }
  RayOrigins origins;
  origins.Points = points;
  origins.Normals = normals;
  origins.Skip.assign(static_cast<std::size_t>(points.rows()), 0);
  for (Eigen::Index i = 0; i < points.rows(); ++i)
  {
    double unit[3];
    if (!UnitNormal(origins, i, unit) || !points.row(i).allFinite())
    {
      origins.Skip[static_cast<std::size_t>(i)] = 1;
    }
  }
  return origins;
}

bool IsBuried(const RayCaster& caster, const RayOrigin& origin)
{
  // From just outside the surface along the outward normal, the first surface met is left
  // (not entered) only when that point is inside the volume: the origin lies inside another
  // part of a self-intersecting mesh.
  RayOrigin outside = origin;
  outside.Rule = HitRule::FirstHitLeaving;
  return std::isfinite(caster.ClosestValidHit(outside, origin.Normal));
}

bool CastShapeDiameterCones(const RayCaster& caster, const RayOrigins& origins,
  const ShapeDiameterOptions& options, const std::vector<std::size_t>* subset,
  ShapeDiameterResult& result, const ParallelFor& parallelFor, const ProgressCallback& progress)
{
  const ConePattern pattern = MakeConePattern(options.NumberOfRays, options.ConeAngle);

  const std::size_t originCount = subset ? subset->size() : static_cast<std::size_t>(origins.Points.rows());
  if (originCount == 0)
  {
    return true;
  }

  const std::size_t chunkSize = options.OriginsPerChunk;
  const std::size_t chunkCount = originCount / chunkSize + (originCount % chunkSize != 0);
  const double vertexMinDistance = options.VertexOriginOffset * caster.GetBoundingBoxDiagonal();
  const bool haveFirstAxes = origins.FirstAxes.rows() != 0;
  const int rayCount = pattern.GetNumberOfRays();

  std::atomic<bool> aborted{ false };
  std::atomic<std::size_t> castCount{ 0 };
  std::atomic<std::size_t> buriedCount{ 0 };
  std::mutex progressMutex;
  std::size_t chunksDone = 0;

  parallelFor(chunkCount, [&](std::size_t chunkBegin, std::size_t chunkEnd) {
    // Per-range scratch: nothing is allocated per origin or per ray.
    std::vector<double> directions(3 * static_cast<std::size_t>(rayCount));
    std::vector<double> distances(static_cast<std::size_t>(rayCount));
    std::vector<double> scratch(static_cast<std::size_t>(rayCount));
    std::size_t rangeCasts = 0;
    std::size_t rangeBuried = 0;
    for (std::size_t chunk = chunkBegin; chunk < chunkEnd; ++chunk)
    {
      if (aborted.load(std::memory_order_relaxed))
      {
        break;
      }
      const std::size_t begin = chunk * chunkSize;
      const std::size_t end = begin + std::min(chunkSize, originCount - begin);
      for (std::size_t k = begin; k < end; ++k)
      {
        const std::size_t o = subset ? (*subset)[k] : k;
        const auto row = static_cast<Eigen::Index>(o);
        RayOrigin origin;
        if ((!origins.Skip.empty() && origins.Skip[o]) ||
          !UnitNormal(origins, row, origin.Normal))
        {
          continue;
        }
        for (int c = 0; c < 3; ++c)
        {
          origin.Point[c] = origins.Points(row, c);
        }
        if (!raycasterdetail::IsFinite3(origin.Point))
        {
          continue;
        }
        origin.SourceTriangle = origins.SourceTriangles.empty() ? -1 : origins.SourceTriangles[o];
        origin.MinDistance = origin.SourceTriangle >= 0 ? 0.0 : vertexMinDistance;
        origin.Rule = options.Rule;

        ++rangeCasts;
        if (options.IgnoreBuriedFaces && IsBuried(caster, origin))
        {
          result.Values[o] = 0.0; // no cone: its rays would measure the enclosing part
          result.ValidRays[o] = 0;
          ++rangeBuried;
          continue;
        }
        const double axis[3] = { -origin.Normal[0], -origin.Normal[1], -origin.Normal[2] };
        double firstAxis[3], secondAxis[3];
        const double* preferred = haveFirstAxes ? origins.FirstAxes.row(row).data() : nullptr;
        MakeConeFrame(axis, preferred, firstAxis, secondAxis);
        OrientConePattern(pattern, axis, firstAxis, secondAxis, directions.data());
        caster.CastCone(origin, directions.data(), static_cast<std::size_t>(rayCount),
          distances.data());
        int kept = 0;
        const double value = RobustWeightedMeanOf(
          distances.data(), pattern.Weights.data(), rayCount, scratch.data(), kept);
        result.Values[o] = value;
        result.ValidRays[o] = kept;
      }
      if (progress)
      {
        std::lock_guard<std::mutex> lock(progressMutex);
        ++chunksDone;
        if (!aborted.load(std::memory_order_relaxed) &&
          !progress(static_cast<double>(chunksDone) / static_cast<double>(chunkCount)))
        {
          aborted.store(true, std::memory_order_relaxed);
        }
      }
    }
    castCount.fetch_add(rangeCasts, std::memory_order_relaxed);
    buriedCount.fetch_add(rangeBuried, std::memory_order_relaxed);
  });
  result.CastCount += castCount.load();
  result.BuriedCount += buriedCount.load();
  return !aborted.load();
}

ShapeDiameterResult ComputeExactShapeDiameter(const RayCaster& caster, const RayOrigins& origins,
  const ShapeDiameterOptions& options, const ParallelFor& parallelFor,
  const ProgressCallback& progress)
{
  CheckShapeDiameterOptions(options);
  CheckRayOrigins(origins);
  // Pattern errors before any work, also for an empty input.
  MakeConePattern(options.NumberOfRays, options.ConeAngle);

  const auto originCount = static_cast<std::size_t>(origins.Points.rows());
  ShapeDiameterResult result;
  result.Values.assign(originCount, 0.0);
  result.ValidRays.assign(originCount, 0);
  result.Aborted = !CastShapeDiameterCones(caster, origins, options, nullptr, result, parallelFor, progress);
  return result;
}

FillFromNeighborsSummary FillFromNeighbors(std::vector<double>& values,
  const std::vector<int>& validRays, const std::vector<std::int64_t>& adjacencyOffsets,
  const std::vector<std::int64_t>& adjacencyIndices)
{
  const std::size_t n = values.size();
  if (validRays.size() != n)
  {
    throw Error("fill from neighbours: values and validRays differ in size");
  }
  if (adjacencyOffsets.size() != n + 1 && !(n == 0 && adjacencyOffsets.empty()))
  {
    throw Error("fill from neighbours: adjacencyOffsets must have " +
      std::to_string(n + 1) + " entries, got " + std::to_string(adjacencyOffsets.size()));
  }
  if (n > 0)
  {
    if (adjacencyOffsets.front() != 0 ||
      adjacencyOffsets.back() != static_cast<std::int64_t>(adjacencyIndices.size()) ||
      !std::is_sorted(adjacencyOffsets.begin(), adjacencyOffsets.end()))
    {
      throw Error("fill from neighbours: adjacencyOffsets is not a valid CSR "
                               "offset array (0, non-decreasing, ends at the index count)");
    }
    for (const std::int64_t neighbour : adjacencyIndices)
    {
      if (neighbour < 0 || neighbour >= static_cast<std::int64_t>(n))
      {
        throw Error("fill from neighbours: neighbour index out of range: " +
          std::to_string(neighbour));
      }
    }
  }

  FillFromNeighborsSummary summary;
  std::vector<std::uint8_t> known(n, 0);
  std::vector<double> validValues;
  for (std::size_t i = 0; i < n; ++i)
  {
    if (validRays[i] > 0 && std::isfinite(values[i]))
    {
      known[i] = 1;
      validValues.push_back(values[i]);
    }
  }
  summary.FallbackValue = Median(std::move(validValues));

  auto neighboursOf = [&](std::size_t i) {
    return std::make_pair(adjacencyIndices.begin() + adjacencyOffsets[i],
      adjacencyIndices.begin() + adjacencyOffsets[i + 1]);
  };
  // First layer: invalid entries next to a valid one, in index order.
  std::vector<std::size_t> layer;
  std::vector<std::uint8_t> queued(n, 0);
  for (std::size_t i = 0; i < n; ++i)
  {
    if (known[i])
    {
      continue;
    }
    const auto [first, last] = neighboursOf(i);
    if (std::any_of(first, last, [&](std::int64_t j) { return known[static_cast<std::size_t>(j)]; }))
    {
      layer.push_back(i);
      queued[i] = 1;
    }
  }
  std::vector<double> layerValues;
  std::vector<std::size_t> nextLayer;
  while (!layer.empty())
  {
    // Jacobi step: all values of a layer come from entries known before the layer.
    layerValues.resize(layer.size());
    for (std::size_t k = 0; k < layer.size(); ++k)
    {
      const auto [first, last] = neighboursOf(layer[k]);
      double sum = 0;
      int count = 0;
      for (auto it = first; it != last; ++it)
      {
        const auto j = static_cast<std::size_t>(*it);
        if (known[j])
        {
          sum += values[j];
          ++count;
        }
      }
      layerValues[k] = sum / count; // count >= 1 by construction of the layer
    }
    nextLayer.clear();
    for (std::size_t k = 0; k < layer.size(); ++k)
    {
      values[layer[k]] = layerValues[k];
      known[layer[k]] = 1;
    }
    summary.FilledFromNeighbors += layer.size();
    for (const std::size_t i : layer)
    {
      const auto [first, last] = neighboursOf(i);
      for (auto it = first; it != last; ++it)
      {
        const auto j = static_cast<std::size_t>(*it);
        if (!known[j] && !queued[j])
        {
          queued[j] = 1;
          nextLayer.push_back(j);
        }
      }
    }
    std::sort(nextLayer.begin(), nextLayer.end());
    layer.swap(nextLayer);
  }
  for (std::size_t i = 0; i < n; ++i)
  {
    if (!known[i])
    {
      values[i] = summary.FallbackValue;
      ++summary.FilledWithFallback;
    }
  }
  return summary;
}

} // namespace shapediameter
