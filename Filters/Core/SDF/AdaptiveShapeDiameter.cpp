// SPDX-License-Identifier: BSD-3-Clause
#include "SDF/AdaptiveShapeDiameter.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <tuple>

namespace shapediameter
{

namespace
{
/// Cell size of the coarsest level, x the diagonal of the origins' bounding box.
constexpr double kCoarseCellFraction = 1.0 / 32.0;
/// Jacobi sweeps of the interpolation (step 5).
constexpr int kSmoothingIterations = 8;
/// Normals further apart than this across a concave edge: a crease not smoothed across.
constexpr double kCreaseAngleDegrees = 60.0;
/// Refinement rounds after the coarse level is reached, beyond K.
constexpr int kExtraRounds = 8;
/// Step 4b: the lowest and highest fraction of the cast values whose regions are refined.
constexpr double kExtremeFraction = 0.01;
/// Step 4b: the extreme regions are selected again this many levels finer.
constexpr int kExtremeLevels = 2;
/// Origins per task of the sweeps.
constexpr std::size_t kSweepChunk = 4096;

struct Graph
{
  const std::vector<std::int64_t>& Offsets;
  const std::vector<std::int64_t>& Indices;
  std::size_t Begin(std::size_t i) const { return static_cast<std::size_t>(this->Offsets[i]); }
  std::size_t End(std::size_t i) const { return static_cast<std::size_t>(this->Offsets[i + 1]); }
  std::size_t At(std::size_t k) const { return static_cast<std::size_t>(this->Indices[k]); }
};

void CheckNeighbors(const RayOrigins& origins, std::size_t n)
{
  const auto& offsets = origins.NeighborOffsets;
  const auto& indices = origins.Neighbors;
  if (n == 0 && offsets.empty())
  {
    return;
  }
  if (offsets.size() != n + 1)
  {
    throw ShapeDiameterError("adaptive shape diameter: the origins need a neighbour graph "
                             "(NeighborOffsets with " + std::to_string(n + 1) + " entries, got " +
      std::to_string(offsets.size()) + ")");
  }
  if (offsets.front() != 0 || offsets.back() != static_cast<std::int64_t>(indices.size()) ||
    !std::is_sorted(offsets.begin(), offsets.end()))
  {
    throw ShapeDiameterError("adaptive shape diameter: NeighborOffsets is not a valid CSR "
                             "offset array (0, non-decreasing, ends at the neighbour count)");
  }
  for (const std::int64_t j : indices)
  {
    if (j < 0 || j >= static_cast<std::int64_t>(n))
    {
      throw ShapeDiameterError(
        "adaptive shape diameter: neighbour index out of range: " + std::to_string(j));
    }
  }
}

/// Step 1: one origin per (level, cell, normal direction) among the candidates; every
/// candidate at level 0. Sorted, distinct.
std::vector<std::size_t> Select(const std::vector<std::size_t>& candidates,
  const std::vector<int>& level, const PointMatrix& points, const std::vector<double>& normals,
  const double minCorner[3], double cellUnit)
{
  // The bin packed into two words (level and direction, then the three cell indices in 32
  // bits each: a cell index is below diagonal / cellUnit, far below 2^32), so that the sort
  // compares two integers rather than five fields (most of Select's time at 832k faces).
  struct Binned
  {
    std::uint64_t High, Low;
    double Distance2;
    std::size_t Index;
  };
  std::vector<std::size_t> chosen;
  std::vector<Binned> binned;
  binned.reserve(candidates.size());
  for (const std::size_t i : candidates)
  {
    if (level[i] <= 0)
    {
      chosen.push_back(i);
      continue;
    }
    const double h = std::ldexp(cellUnit, level[i]);
    double distance2 = 0;
    std::uint64_t cell[3];
    for (int c = 0; c < 3; ++c)
    {
      const double x = (points(static_cast<Eigen::Index>(i), c) - minCorner[c]) / h;
      const double floor = std::floor(x);
      cell[c] = static_cast<std::uint32_t>(static_cast<std::int64_t>(floor));
      distance2 += (x - floor - 0.5) * (x - floor - 0.5);
    }
    const double* n = normals.data() + 3 * i;
    int axis = 0;
    for (int c = 1; c < 3; ++c)
    {
      if (std::abs(n[c]) > std::abs(n[axis]))
      {
        axis = c;
      }
    }
    const auto direction = static_cast<std::uint64_t>(2 * axis + (n[axis] < 0));
    binned.push_back({ (static_cast<std::uint64_t>(level[i]) << 40) | (direction << 32) | cell[0],
      (cell[1] << 32) | cell[2], distance2, i });
  }
  std::sort(binned.begin(), binned.end(), [](const Binned& a, const Binned& b) {
    return std::tie(a.High, a.Low, a.Distance2, a.Index) < std::tie(b.High, b.Low, b.Distance2, b.Index);
  });
  for (std::size_t k = 0; k < binned.size(); ++k)
  {
    if (k == 0 || binned[k].High != binned[k - 1].High || binned[k].Low != binned[k - 1].Low)
    {
      chosen.push_back(binned[k].Index);
    }
  }
  std::sort(chosen.begin(), chosen.end());
  chosen.erase(std::unique(chosen.begin(), chosen.end()), chosen.end());
  return chosen;
}

/// Step 2: breadth-first regions of the cast origins with a valid value. After new casts, the
/// regions of the sources added since the last call take over every origin they are strictly
/// closer to (in hops); the rest keep their owner. The same hop distances as a search from all
/// sources, at the cost of the origins that change. The first call starts from owner and depth
/// all -1 with every source in `added` (ascending, so ties go to the lower source index).
void UpdateRegions(const Graph& graph, const std::vector<std::size_t>& added,
  const std::vector<std::uint8_t>& source, std::vector<std::int64_t>& owner, std::vector<int>& depth)
{
  std::vector<std::size_t> layer, next;
  for (const std::size_t s : added)
  {
    if (source[s])
    {
      owner[s] = static_cast<std::int64_t>(s);
      depth[s] = 0;
      layer.push_back(s);
    }
  }
  while (!layer.empty())
  {
    next.clear();
    for (const std::size_t f : layer)
    {
      const int d = depth[f] + 1;
      for (std::size_t k = graph.Begin(f); k < graph.End(f); ++k)
      {
        const std::size_t g = graph.At(k);
        if (depth[g] < 0 || d < depth[g])
        {
          owner[g] = owner[f];
          depth[g] = d;
          next.push_back(g);
        }
      }
    }
    layer.swap(next);
  }
}
} // namespace

ShapeDiameterResult ComputeAdaptiveShapeDiameter(const RayCaster& caster,
  const RayOrigins& origins, const ShapeDiameterOptions& options, const ParallelFor& parallelFor,
  const ProgressCallback& progress)
{
  const auto n = static_cast<std::size_t>(origins.Points.rows());
  ShapeDiameterResult result;
  result.Values.assign(n, 0.0);
  result.ValidRays.assign(n, 0);
  CheckNeighbors(origins, n);
  if (n == 0)
  {
    // Bad ray options are reported for an empty input too.
    const std::vector<std::size_t> none;
    CastShapeDiameterCones(caster, origins, options, &none, result, parallelFor, ProgressCallback());
    return result;
  }
  const Graph graph{ origins.NeighborOffsets, origins.Neighbors };

  // Origins that may be cast (the others keep 0 / 0, as in the Exact mode), unit normals.
  std::vector<std::uint8_t> eligible(n, 0);
  std::vector<double> normals(3 * n, 0.0);
  double minCorner[3] = { std::numeric_limits<double>::infinity(),
    std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity() };
  double maxCorner[3] = { -minCorner[0], -minCorner[1], -minCorner[2] };
  for (std::size_t i = 0; i < n; ++i)
  {
    const auto row = static_cast<Eigen::Index>(i);
    if ((!origins.Skip.empty() && origins.Skip[i]) || !origins.Points.row(row).allFinite())
    {
      continue;
    }
    const double length = origins.Normals.row(row).norm();
    if (!(length > 0) || !std::isfinite(length))
    {
      continue;
    }
    eligible[i] = 1;
    for (int c = 0; c < 3; ++c)
    {
      normals[3 * i + c] = origins.Normals(row, c) / length;
      minCorner[c] = std::min(minCorner[c], origins.Points(row, c));
      maxCorner[c] = std::max(maxCorner[c], origins.Points(row, c));
    }
  }

  // E: mean distance between neighbouring origins; K: the coarse level.
  double edgeSum = 0;
  std::size_t edgeCount = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    for (std::size_t k = graph.Begin(i); k < graph.End(i); ++k)
    {
      const std::size_t j = graph.At(k);
      if (eligible[i] && eligible[j] && i != j)
      {
        edgeSum += (origins.Points.row(static_cast<Eigen::Index>(i)) -
          origins.Points.row(static_cast<Eigen::Index>(j)))
                     .norm();
        ++edgeCount;
      }
    }
  }
  double diagonal = 0;
  for (int c = 0; c < 3; ++c)
  {
    diagonal += maxCorner[c] > minCorner[c] ? (maxCorner[c] - minCorner[c]) * (maxCorner[c] - minCorner[c]) : 0.0;
  }
  diagonal = std::sqrt(diagonal);
  double cellUnit = edgeCount > 0 ? edgeSum / static_cast<double>(edgeCount) : 0.0;
  if (!(cellUnit > 0) || !std::isfinite(cellUnit))
  {
    cellUnit = diagonal > 0 ? diagonal / std::sqrt(static_cast<double>(n)) : 1.0;
  }
  int coarseLevel = 0;
  if (diagonal * kCoarseCellFraction > cellUnit)
  {
    coarseLevel = std::min(30, static_cast<int>(std::floor(std::log2(diagonal * kCoarseCellFraction / cellUnit))));
  }
  const double spacingFraction = options.SpacingFraction;
  const double tolerance = options.Tolerance;
  if (coarseLevel == 0)
  {
    // The coarsest cell is no larger than the spacing of the origins: every origin would be
    // cast, so the Exact mode runs (same values, none of the bookkeeping).
    result.Aborted = !CastShapeDiameterCones(caster, origins, options, nullptr, result, parallelFor, progress);
    return result;
  }
  const auto levelFor = [&](double sdf) {
    const double spacing = spacingFraction * sdf;
    if (!(spacing >= 2 * cellUnit))
    {
      return 0;
    }
    return std::min(coarseLevel, static_cast<int>(std::floor(std::log2(spacing / cellUnit))));
  };

  std::vector<int> level(n, coarseLevel);
  std::vector<std::uint8_t> cast(n, 0), source(n, 0);
  std::vector<std::atomic<std::uint8_t>> refine(n);
  std::vector<std::int64_t> owner;
  std::vector<int> depth;
  std::vector<std::size_t> candidates;
  for (std::size_t i = 0; i < n; ++i)
  {
    if (eligible[i])
    {
      candidates.push_back(i);
    }
  }

  // Step 4's test on the current regions: the origins to select again.
  const auto refinementCandidates = [&]() {
    // In parallel: the flags are only ever set, so their final state does not depend on the
    // order (relaxed atomic stores; the scan reads nothing else that changes).
    for (auto& flag : refine)
    {
      flag.store(0, std::memory_order_relaxed);
    }
    parallelFor((n + kSweepChunk - 1) / kSweepChunk, [&](std::size_t chunkBegin, std::size_t chunkEnd) {
      for (std::size_t i = chunkBegin * kSweepChunk; i < std::min(n, chunkEnd * kSweepChunk); ++i)
      {
        const std::int64_t a = owner[i];
        if (a < 0)
        {
          continue;
        }
        const double va = result.Values[static_cast<std::size_t>(a)];
        for (std::size_t k = graph.Begin(i); k < graph.End(i); ++k)
        {
          const std::int64_t b = owner[graph.At(k)];
          if (b > a) // each pair of regions once per edge direction is enough
          {
            const double vb = result.Values[static_cast<std::size_t>(b)];
            if (std::abs(va - vb) > tolerance * std::max(va, vb))
            {
              refine[static_cast<std::size_t>(a)].store(1, std::memory_order_relaxed);
              refine[static_cast<std::size_t>(b)].store(1, std::memory_order_relaxed);
            }
          }
        }
        if (depth[i] > 2 * (1 << std::min(level[i], 20)) + 2)
        {
          refine[static_cast<std::size_t>(a)].store(1, std::memory_order_relaxed);
        }
      }
    });
    std::vector<std::size_t> selected;
    for (std::size_t i = 0; i < n; ++i)
    {
      if (!eligible[i] || cast[i])
      {
        continue;
      }
      if (owner[i] < 0)
      {
        level[i] = std::max(0, level[i] - 1);
        selected.push_back(i);
      }
      else if (refine[static_cast<std::size_t>(owner[i])].load(std::memory_order_relaxed))
      {
        level[i] = std::max(0, level[i] - 1);
        selected.push_back(i);
      }
    }
    return selected;
  };

  double progressDone = 0;
  bool checked = true; // the current regions went through refinementCandidates
  for (int round = 0; round <= coarseLevel + kExtraRounds; ++round)
  {
    const auto selectUncast = [&]() {
      std::vector<std::size_t> selected = Select(candidates, level, origins.Points, normals, minCorner, cellUnit);
      selected.erase(
        std::remove_if(selected.begin(), selected.end(), [&](std::size_t i) { return cast[i] != 0; }),
        selected.end());
      return selected;
    };
    std::vector<std::size_t> chosen = selectUncast();
    if (chosen.empty() && !checked)
    {
      candidates = refinementCandidates();
      checked = true;
      chosen = selectUncast();
    }
    if (chosen.empty())
    {
      break;
    }

    const double span = round == 0 ? 0.1 : 0.5 * (0.95 - progressDone);
    ProgressCallback roundProgress;
    if (progress)
    {
      roundProgress = [&, base = progressDone, span](double fraction) { return progress(base + span * fraction); };
    }
    const bool completed =
      CastShapeDiameterCones(caster, origins, options, &chosen, result, parallelFor, roundProgress);
    progressDone += span;
    if (!completed)
    {
      result.Aborted = true;
      return result;
    }
    for (const std::size_t i : chosen)
    {
      cast[i] = 1;
      source[i] = result.ValidRays[i] > 0 ? 1 : 0;
    }
    if (round == 0)
    {
      owner.assign(n, -1);
      depth.assign(n, -1);
    }
    UpdateRegions(graph, chosen, source, owner, depth);

    if (round == 0)
    {
      // Step 3: the spacing from the coarse estimate.
      candidates.clear();
      for (std::size_t i = 0; i < n; ++i)
      {
        if (!eligible[i] || cast[i])
        {
          continue;
        }
        const int wanted = owner[i] < 0 ? std::max(0, level[i] - 1)
                                        : levelFor(result.Values[static_cast<std::size_t>(owner[i])]);
        if (wanted < level[i] || owner[i] < 0)
        {
          level[i] = std::min(level[i], wanted);
          candidates.push_back(i);
        }
      }
      checked = false;
    }
    else
    {
      candidates = refinementCandidates();
      checked = true;
    }
  }

  // Step 4b: the extremes. The normalisation maps the smoothed SDF's minimum and maximum to 0
  // and 1, so a missed extreme shifts every normalised value: the regions whose value is in
  // the lowest or highest kExtremeFraction of the cast values are selected again
  // kExtremeLevels levels finer.
  const double extremeFraction = kExtremeFraction;
  const int extremeDrop = kExtremeLevels;
  if (!owner.empty() && extremeFraction > 0)
  {
    std::vector<double> castValues;
    for (std::size_t i = 0; i < n; ++i)
    {
      if (source[i])
      {
        castValues.push_back(result.Values[i]);
      }
    }
    if (!castValues.empty())
    {
      std::sort(castValues.begin(), castValues.end());
      const auto last = castValues.size() - 1;
      const double low = castValues[static_cast<std::size_t>(extremeFraction * static_cast<double>(last))];
      const double high = castValues[last - static_cast<std::size_t>(extremeFraction * static_cast<double>(last))];
      std::vector<std::size_t> chosen;
      for (std::size_t i = 0; i < n; ++i)
      {
        if (eligible[i] && !cast[i] && owner[i] >= 0)
        {
          const double v = result.Values[static_cast<std::size_t>(owner[i])];
          if (v <= low || v >= high)
          {
            chosen.push_back(i);
          }
        }
      }
      for (const std::size_t i : chosen)
      {
        level[i] = std::max(0, level[i] - extremeDrop);
      }
      chosen = Select(chosen, level, origins.Points, normals, minCorner, cellUnit);
      chosen.erase(std::remove_if(chosen.begin(), chosen.end(), [&](std::size_t i) { return cast[i] != 0; }),
        chosen.end());
      if (!chosen.empty())
      {
        const double span = 0.5 * (0.95 - progressDone);
        ProgressCallback roundProgress;
        if (progress)
        {
          roundProgress = [&, base = progressDone, span](double fraction) { return progress(base + span * fraction); };
        }
        if (!CastShapeDiameterCones(caster, origins, options, &chosen, result, parallelFor, roundProgress))
        {
          result.Aborted = true;
          return result;
        }
        progressDone += span;
        for (const std::size_t i : chosen)
        {
          cast[i] = 1;
          source[i] = result.ValidRays[i] > 0 ? 1 : 0;
        }
        UpdateRegions(graph, chosen, source, owner, depth);
      }
    }
  }

  // Step 5: interpolation.
  std::vector<std::uint8_t> known(n, 0), free(n, 0);
  for (std::size_t i = 0; i < n; ++i)
  {
    if (!eligible[i] || owner.empty() || owner[i] < 0)
    {
      continue;
    }
    known[i] = 1;
    if (!source[i])
    {
      free[i] = 1;
      const auto a = static_cast<std::size_t>(owner[i]);
      result.Values[i] = result.Values[a];
      result.ValidRays[i] = result.ValidRays[a];
    }
  }
  const std::size_t chunks = (n + kSweepChunk - 1) / kSweepChunk;
  const double creaseCos = std::cos(kCreaseAngleDegrees * 3.14159265358979323846 / 180.0);
  std::vector<double> next(result.Values);
  const int sweeps = kSmoothingIterations;
  for (int sweep = 0; sweep < sweeps && !owner.empty(); ++sweep)
  {
    parallelFor(chunks, [&](std::size_t chunkBegin, std::size_t chunkEnd) {
      for (std::size_t i = chunkBegin * kSweepChunk; i < std::min(n, chunkEnd * kSweepChunk); ++i)
      {
        if (!free[i])
        {
          next[i] = result.Values[i];
          continue;
        }
        double sum = result.Values[i];
        int count = 1;
        const double* ni = normals.data() + 3 * i;
        for (std::size_t k = graph.Begin(i); k < graph.End(i); ++k)
        {
          const std::size_t j = graph.At(k);
          if (!known[j] || j == i)
          {
            continue;
          }
          const double* nj = normals.data() + 3 * j;
          const double cosine = ni[0] * nj[0] + ni[1] * nj[1] + ni[2] * nj[2];
          if (cosine < creaseCos)
          {
            double above = 0;
            for (int c = 0; c < 3; ++c)
            {
              above += (origins.Points(static_cast<Eigen::Index>(j), c) -
                         origins.Points(static_cast<Eigen::Index>(i), c)) * ni[c];
            }
            if (above > 0)
            {
              continue; // concave crease
            }
          }
          sum += result.Values[j];
          ++count;
        }
        next[i] = sum / count;
      }
    });
    result.Values.swap(next);
  }
  if (progress && !progress(1.0))
  {
    result.Aborted = true;
  }
  return result;
}

} // namespace shapediameter
