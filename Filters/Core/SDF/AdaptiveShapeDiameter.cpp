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
    throw Error("adaptive shape diameter: the origins need a neighbour graph "
                             "(NeighborOffsets with " + std::to_string(n + 1) + " entries, got " +
      std::to_string(offsets.size()) + ")");
  }
  if (offsets.front() != 0 || offsets.back() != static_cast<std::int64_t>(indices.size()) ||
    !std::is_sorted(offsets.begin(), offsets.end()))
  {
    throw Error("adaptive shape diameter: NeighborOffsets is not a valid CSR "
                             "offset array (0, non-decreasing, ends at the neighbour count)");
  }
  for (const std::int64_t j : indices)
  {
    if (j < 0 || j >= static_cast<std::int64_t>(n))
    {
      throw Error(
        "adaptive shape diameter: neighbour index out of range: " + std::to_string(j));
    }
  }
}

/// The origins that may be cast (the others keep 0 / 0, as in the Exact mode), their unit
/// normals and the bounding box of their points.
struct CastableOrigins
{
  std::vector<std::uint8_t> Eligible;
  std::vector<double> Normals; ///< 3 per origin, 0 for the origins that are not eligible
  double MinCorner[3];
  double MaxCorner[3];
};

CastableOrigins FindCastableOrigins(const RayOrigins& origins, std::size_t n)
{
  CastableOrigins castable;
  castable.Eligible.assign(n, 0);
  castable.Normals.assign(3 * n, 0.0);
  for (int c = 0; c < 3; ++c)
  {
    castable.MinCorner[c] = std::numeric_limits<double>::infinity();
    castable.MaxCorner[c] = -castable.MinCorner[c];
  }
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
    castable.Eligible[i] = 1;
    for (int c = 0; c < 3; ++c)
    {
      castable.Normals[3 * i + c] = origins.Normals(row, c) / length;
      castable.MinCorner[c] = std::min(castable.MinCorner[c], origins.Points(row, c));
      castable.MaxCorner[c] = std::max(castable.MaxCorner[c], origins.Points(row, c));
    }
  }
  return castable;
}

/// The cell sizes h_k = E 2^k of the levels k = 0..K.
struct LevelScale
{
  double CellUnit = 0; ///< E
  int CoarseLevel = 0; ///< K; 0 = the origins are no denser than the coarsest cells
};

/// E: mean distance between neighbouring origins; K: the coarse level, h_K ~ diagonal / 32.
LevelScale MeasureLevelScale(
  const RayOrigins& origins, const Graph& graph, const CastableOrigins& castable, std::size_t n)
{
  const std::vector<std::uint8_t>& eligible = castable.Eligible;
  const double* minCorner = castable.MinCorner;
  const double* maxCorner = castable.MaxCorner;
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
  LevelScale scale;
  scale.CellUnit = cellUnit;
  scale.CoarseLevel = coarseLevel;
  return scale;
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

/// Steps 1-5 over the state they share: the level each origin is selected at, which origins
/// are cast (and with a valid value: the sources), the regions (owner and depth in hops) and
/// the progress reported so far. The results go to `result`, sized by the caller.
class AdaptiveCasting
{
public:
  AdaptiveCasting(const RayCaster& caster, const RayOrigins& origins,
    const ShapeDiameterOptions& options, const ParallelFor& parallelFor,
    const ProgressCallback& progress, const Graph& graph, const CastableOrigins& castable,
    const LevelScale& scale, ShapeDiameterResult& result);

  /// The coarse pass, the spacing from its estimate and the refinement rounds (steps 1-4).
  /// False when aborted.
  bool CastCoarseAndRefine();
  /// Step 4b: the extremes. False when aborted.
  bool CastExtremes();
  /// Step 5: the interpolation.
  void Interpolate();

private:
  int LevelFor(double sdf) const;
  std::vector<std::size_t> SelectUncast(const std::vector<std::size_t>& among) const;
  bool CastAndUpdateRegions(const std::vector<std::size_t>& chosen, double span);
  std::vector<std::size_t> SpacingFromEstimate();
  std::vector<std::size_t> RefinementCandidates();
  std::vector<std::size_t> ExtremeRegionOrigins() const;
  void TakeOwnerValues(std::vector<std::uint8_t>& known, std::vector<std::uint8_t>& free);
  void SmoothAcrossNeighbors(
    const std::vector<std::uint8_t>& known, const std::vector<std::uint8_t>& free);

  const RayCaster& Caster;
  const RayOrigins& Origins;
  const ShapeDiameterOptions& Options;
  const ParallelFor& Parallel;
  const ProgressCallback& Progress;
  const Graph& Adjacency; ///< the origins' neighbour graph
  const CastableOrigins& Castable;
  const LevelScale Scale;
  ShapeDiameterResult& Result;
  const std::size_t N;

  std::vector<int> Level;
  std::vector<std::uint8_t> Cast, Source;
  std::vector<std::atomic<std::uint8_t>> Refine;
  std::vector<std::int64_t> Owner; ///< empty until the first cast
  std::vector<int> Depth;
  double ProgressDone = 0;
};

AdaptiveCasting::AdaptiveCasting(const RayCaster& caster, const RayOrigins& origins,
  const ShapeDiameterOptions& options, const ParallelFor& parallelFor,
  const ProgressCallback& progress, const Graph& graph, const CastableOrigins& castable,
  const LevelScale& scale, ShapeDiameterResult& result)
  : Caster(caster)
  , Origins(origins)
  , Options(options)
  , Parallel(parallelFor)
  , Progress(progress)
  , Adjacency(graph)
  , Castable(castable)
  , Scale(scale)
  , Result(result)
  , N(static_cast<std::size_t>(origins.Points.rows()))
  , Level(N, scale.CoarseLevel)
  , Cast(N, 0)
  , Source(N, 0)
  , Refine(N)
{
}

int AdaptiveCasting::LevelFor(double sdf) const
{
  const double spacing = Options.SpacingFraction * sdf;
  if (!(spacing >= 2 * Scale.CellUnit))
  {
    return 0;
  }
  return std::min(
    Scale.CoarseLevel, static_cast<int>(std::floor(std::log2(spacing / Scale.CellUnit))));
}

std::vector<std::size_t> AdaptiveCasting::SelectUncast(const std::vector<std::size_t>& among) const
{
  std::vector<std::size_t> selected =
    Select(among, Level, Origins.Points, Castable.Normals, Castable.MinCorner, Scale.CellUnit);
  selected.erase(
    std::remove_if(selected.begin(), selected.end(), [&](std::size_t i) { return Cast[i] != 0; }),
    selected.end());
  return selected;
}

/// Casts the chosen origins, reporting progress over the next `span` of the whole, and grows
/// the regions of the new sources. False when aborted.
bool AdaptiveCasting::CastAndUpdateRegions(const std::vector<std::size_t>& chosen, double span)
{
  ProgressCallback roundProgress;
  if (Progress)
  {
    roundProgress = [this, base = ProgressDone, span](double fraction) {
      return Progress(base + span * fraction);
    };
  }
  const bool completed =
    CastShapeDiameterCones(Caster, Origins, Options, &chosen, Result, Parallel, roundProgress);
  ProgressDone += span;
  if (!completed)
  {
    return false;
  }
  for (const std::size_t i : chosen)
  {
    Cast[i] = 1;
    Source[i] = Result.ValidRays[i] > 0 ? 1 : 0;
  }
  if (Owner.empty())
  {
    Owner.assign(N, -1);
    Depth.assign(N, -1);
  }
  UpdateRegions(Adjacency, chosen, Source, Owner, Depth);
  return true;
}

bool AdaptiveCasting::CastCoarseAndRefine()
{
  std::vector<std::size_t> candidates;
  for (std::size_t i = 0; i < N; ++i)
  {
    if (Castable.Eligible[i])
    {
      candidates.push_back(i);
    }
  }
  bool checked = true; // the current regions went through RefinementCandidates
  for (int round = 0; round <= Scale.CoarseLevel + kExtraRounds; ++round)
  {
    std::vector<std::size_t> chosen = SelectUncast(candidates);
    if (chosen.empty() && !checked)
    {
      candidates = RefinementCandidates();
      checked = true;
      chosen = SelectUncast(candidates);
    }
    if (chosen.empty())
    {
      break;
    }
    const double span = round == 0 ? 0.1 : 0.5 * (0.95 - ProgressDone);
    if (!CastAndUpdateRegions(chosen, span))
    {
      return false;
    }
    if (round == 0)
    {
      candidates = SpacingFromEstimate();
      checked = false;
    }
    else
    {
      candidates = RefinementCandidates();
      checked = true;
    }
  }
  return true;
}

/// Step 3: the spacing from the coarse estimate. Returns the origins whose level dropped, and
/// those no region reached (one level finer), to be selected again.
std::vector<std::size_t> AdaptiveCasting::SpacingFromEstimate()
{
  std::vector<std::size_t> candidates;
  for (std::size_t i = 0; i < N; ++i)
  {
    if (!Castable.Eligible[i] || Cast[i])
    {
      continue;
    }
    const int wanted = Owner[i] < 0 ? std::max(0, Level[i] - 1)
                                    : LevelFor(Result.Values[static_cast<std::size_t>(Owner[i])]);
    if (wanted < Level[i] || Owner[i] < 0)
    {
      Level[i] = std::min(Level[i], wanted);
      candidates.push_back(i);
    }
  }
  return candidates;
}

/// Step 4's test on the current regions: the origins to select again, one level finer.
std::vector<std::size_t> AdaptiveCasting::RefinementCandidates()
{
  // In parallel: the flags are only ever set, so their final state does not depend on the
  // order (relaxed atomic stores; the scan reads nothing else that changes).
  for (auto& flag : Refine)
  {
    flag.store(0, std::memory_order_relaxed);
  }
  const double tolerance = Options.Tolerance;
  Parallel((N + kSweepChunk - 1) / kSweepChunk, [&](std::size_t chunkBegin, std::size_t chunkEnd) {
    for (std::size_t i = chunkBegin * kSweepChunk; i < std::min(N, chunkEnd * kSweepChunk); ++i)
    {
      const std::int64_t a = Owner[i];
      if (a < 0)
      {
        continue;
      }
      const double va = Result.Values[static_cast<std::size_t>(a)];
      for (std::size_t k = Adjacency.Begin(i); k < Adjacency.End(i); ++k)
      {
        const std::int64_t b = Owner[Adjacency.At(k)];
        if (b > a) // each pair of regions once per edge direction is enough
        {
          const double vb = Result.Values[static_cast<std::size_t>(b)];
          if (std::abs(va - vb) > tolerance * std::max(va, vb))
          {
            Refine[static_cast<std::size_t>(a)].store(1, std::memory_order_relaxed);
            Refine[static_cast<std::size_t>(b)].store(1, std::memory_order_relaxed);
          }
        }
      }
      if (Depth[i] > 2 * (1 << std::min(Level[i], 20)) + 2)
      {
        Refine[static_cast<std::size_t>(a)].store(1, std::memory_order_relaxed);
      }
    }
  });
  std::vector<std::size_t> selected;
  for (std::size_t i = 0; i < N; ++i)
  {
    if (!Castable.Eligible[i] || Cast[i])
    {
      continue;
    }
    if (Owner[i] < 0)
    {
      Level[i] = std::max(0, Level[i] - 1);
      selected.push_back(i);
    }
    else if (Refine[static_cast<std::size_t>(Owner[i])].load(std::memory_order_relaxed))
    {
      Level[i] = std::max(0, Level[i] - 1);
      selected.push_back(i);
    }
  }
  return selected;
}

/// The uncast origins of the regions whose value is in the lowest or highest
/// kExtremeFraction of the cast values.
std::vector<std::size_t> AdaptiveCasting::ExtremeRegionOrigins() const
{
  std::vector<double> castValues;
  for (std::size_t i = 0; i < N; ++i)
  {
    if (Source[i])
    {
      castValues.push_back(Result.Values[i]);
    }
  }
  std::vector<std::size_t> chosen;
  if (castValues.empty())
  {
    return chosen;
  }
  std::sort(castValues.begin(), castValues.end());
  const auto last = castValues.size() - 1;
  const double low = castValues[static_cast<std::size_t>(kExtremeFraction * static_cast<double>(last))];
  const double high = castValues[last - static_cast<std::size_t>(kExtremeFraction * static_cast<double>(last))];
  for (std::size_t i = 0; i < N; ++i)
  {
    if (Castable.Eligible[i] && !Cast[i] && Owner[i] >= 0)
    {
      const double v = Result.Values[static_cast<std::size_t>(Owner[i])];
      if (v <= low || v >= high)
      {
        chosen.push_back(i);
      }
    }
  }
  return chosen;
}

/// The normalisation maps the smoothed SDF's minimum and maximum to 0 and 1, so a missed
/// extreme shifts every normalised value: the extreme regions (ExtremeRegionOrigins) are
/// selected again kExtremeLevels levels finer.
bool AdaptiveCasting::CastExtremes()
{
  if (Owner.empty() || !(kExtremeFraction > 0))
  {
    return true;
  }
  std::vector<std::size_t> chosen = ExtremeRegionOrigins();
  for (const std::size_t i : chosen)
  {
    Level[i] = std::max(0, Level[i] - kExtremeLevels);
  }
  chosen = SelectUncast(chosen);
  if (chosen.empty())
  {
    return true;
  }
  return CastAndUpdateRegions(chosen, 0.5 * (0.95 - ProgressDone));
}

void AdaptiveCasting::Interpolate()
{
  std::vector<std::uint8_t> known(N, 0), free(N, 0);
  TakeOwnerValues(known, free);
  SmoothAcrossNeighbors(known, free);
}

/// Every origin a region reached is known; those not cast with a valid value (free) take
/// their owner's value and ValidRays.
void AdaptiveCasting::TakeOwnerValues(
  std::vector<std::uint8_t>& known, std::vector<std::uint8_t>& free)
{
  for (std::size_t i = 0; i < N; ++i)
  {
    if (!Castable.Eligible[i] || Owner.empty() || Owner[i] < 0)
    {
      continue;
    }
    known[i] = 1;
    if (!Source[i])
    {
      free[i] = 1;
      const auto a = static_cast<std::size_t>(Owner[i]);
      Result.Values[i] = Result.Values[a];
      Result.ValidRays[i] = Result.ValidRays[a];
    }
  }
}

/// Jacobi sweeps: each free origin becomes the mean of itself and its known neighbours of the
/// previous sweep, not across concave creases.
void AdaptiveCasting::SmoothAcrossNeighbors(
  const std::vector<std::uint8_t>& known, const std::vector<std::uint8_t>& free)
{
  const std::size_t chunks = (N + kSweepChunk - 1) / kSweepChunk;
  const double creaseCos = std::cos(kCreaseAngleDegrees * 3.14159265358979323846 / 180.0);
  std::vector<double> next(Result.Values);
  const int sweeps = kSmoothingIterations;
  for (int sweep = 0; sweep < sweeps && !Owner.empty(); ++sweep)
  {
    Parallel(chunks, [&](std::size_t chunkBegin, std::size_t chunkEnd) {
      for (std::size_t i = chunkBegin * kSweepChunk; i < std::min(N, chunkEnd * kSweepChunk); ++i)
      {
        if (!free[i])
        {
          next[i] = Result.Values[i];
          continue;
        }
        double sum = Result.Values[i];
        int count = 1;
        const double* ni = Castable.Normals.data() + 3 * i;
        for (std::size_t k = Adjacency.Begin(i); k < Adjacency.End(i); ++k)
        {
          const std::size_t j = Adjacency.At(k);
          if (!known[j] || j == i)
          {
            continue;
          }
          const double* nj = Castable.Normals.data() + 3 * j;
          const double cosine = ni[0] * nj[0] + ni[1] * nj[1] + ni[2] * nj[2];
          if (cosine < creaseCos)
          {
            double above = 0;
            for (int c = 0; c < 3; ++c)
            {
              above += (Origins.Points(static_cast<Eigen::Index>(j), c) -
                         Origins.Points(static_cast<Eigen::Index>(i), c)) * ni[c];
            }
            if (above > 0)
            {
              continue; // concave crease
            }
          }
          sum += Result.Values[j];
          ++count;
        }
        next[i] = sum / count;
      }
    });
    Result.Values.swap(next);
  }
}
} // namespace

ShapeDiameterResult ComputeAdaptiveShapeDiameter(const RayCaster& caster,
  const RayOrigins& origins, const ShapeDiameterOptions& options, const ParallelFor& parallelFor,
  const ProgressCallback& progress)
{
  CheckShapeDiameterOptions(options);
  CheckRayOrigins(origins);
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
  const CastableOrigins castable = FindCastableOrigins(origins, n);
  const LevelScale scale = MeasureLevelScale(origins, graph, castable, n);
  if (scale.CoarseLevel == 0)
  {
    // The coarsest cell is no larger than the spacing of the origins: every origin would be
    // cast, so the Exact mode runs (same values, none of the bookkeeping).
    result.Aborted = !CastShapeDiameterCones(caster, origins, options, nullptr, result, parallelFor, progress);
    return result;
  }

  AdaptiveCasting casting(
    caster, origins, options, parallelFor, progress, graph, castable, scale, result);
  if (!casting.CastCoarseAndRefine() || !casting.CastExtremes())
  {
    result.Aborted = true;
    return result;
  }
  casting.Interpolate();
  if (progress && !progress(1.0))
  {
    result.Aborted = true;
  }
  return result;
}

} // namespace shapediameter
