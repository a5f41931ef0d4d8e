// SPDX-License-Identifier: BSD-3-Clause
#include "Skeleton/SkeletonSegments.h"

#include "Skeleton/SkeletonPointTree.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <map>

namespace shapediameter
{

void ValidateSegmentOptions(const SkeletonSegmentOptions& options)
{
  CheckRange(options.StepFactor, StepFactorRange, "skeleton: StepFactor");
  // Open at both ends, which Range cannot state (SkeletonSegments.h).
  if (!(options.AngularToleranceDegrees > 0.0 && options.AngularToleranceDegrees < 90.0))
  {
    throw Error("skeleton: AngularToleranceDegrees must be in (0, 90)");
  }
  CheckRange(options.MinimumNodes, MinimumNodesRange, "skeleton: MinimumNodes");
}

namespace
{

class SegmentGrower
{
public:
  SegmentGrower(const ProjectedCloud& cloud, const ThinnedCloud& thinned,
    const std::vector<std::int64_t>& pointComponent, const SkeletonSegmentOptions& options,
    const RayCaster* volume, const ParallelFor& parallelFor)
    : Cloud(cloud)
    , Thinned(thinned)
    , PointComponent(pointComponent)
    , Options(options)
    , Volume(volume)
    , CosTolerance(std::cos(options.AngularToleranceDegrees * 3.14159265358979323846 / 180.0))
    , Positions(static_cast<Eigen::Index>(thinned.Thinned.size()), 3)
    , Clustered(thinned.Thinned.size(), 0)
  {
    for (std::size_t t = 0; t < thinned.Thinned.size(); ++t)
    {
      Positions.row(static_cast<Eigen::Index>(t)) = thinned.Positions.row(thinned.Thinned[t]);
    }
    Tree = std::make_unique<SkeletonPointTree>(Positions);
    if (volume && volume->PrefersFewLargeBatches())
    {
      TestPossibleSteps(*volume, parallelFor);
    }
  }

  /// Segments as indices into T, in seed order, before the MinimumNodes filter.
  std::vector<std::vector<std::int64_t>> GrowAll()
  {
    std::vector<std::vector<std::int64_t>> segments;
    for (std::size_t seed = 0; seed < Clustered.size(); ++seed)
    {
      if (Clustered[seed])
      {
        continue;
      }
      Clustered[seed] = 1;
      const auto seedIndex = static_cast<std::int64_t>(seed);
      const Eigen::Vector3d axis = AxisOf(seedIndex);
      std::vector<std::int64_t> backward = GrowSide(seedIndex, -axis);
      const std::vector<std::int64_t> forward = GrowSide(seedIndex, axis);
      std::reverse(backward.begin(), backward.end());
      backward.push_back(seedIndex);
      backward.insert(backward.end(), forward.begin(), forward.end());
      segments.push_back(std::move(backward));
    }
    return segments;
  }

  std::int64_t ComponentOf(std::int64_t t) const
  {
    return PointComponent.empty() ? 0 : PointComponent[Thinned.Thinned[t]];
  }

private:
  /// For a volume over processes (one exchange per call): the inside test of every step the
  /// growth may take, in one batch: from each point t of T to every point q near it (within t's
  /// step, same component) in the cone about t's axis, either way, whose own axis lies within
  /// the tolerance of t's. The growth's direction at t is always plus or minus t's axis, so
  /// these are all the steps it can test; which it does depends on what is clustered by then.
  void TestPossibleSteps(const RayCaster& volume, const ParallelFor& parallelFor)
  {
    const std::size_t count = Clustered.size();
    PossibleSteps.assign(count, {});
    std::vector<Segment> steps;
    std::vector<std::int64_t> nearby;
    for (std::size_t t = 0; t < count; ++t)
    {
      const auto from = static_cast<std::int64_t>(t);
      const Eigen::Vector3d origin = PositionOf(from);
      const Eigen::Vector3d axis = AxisOf(from);
      Tree->RadiusSearch(origin, Options.StepFactor * Cloud.Radius[Thinned.Thinned[from]], nearby);
      for (const std::int64_t q : nearby)
      {
        const Eigen::Vector3d offset = PositionOf(q) - origin;
        const double distance = offset.norm();
        // |along| as GrowSide's along for either sign of the direction (a negation is exact).
        if (ComponentOf(q) != ComponentOf(from) || !(distance > 0.0) ||
          std::abs(offset.dot(axis)) < CosTolerance * distance || std::abs(AxisOf(q).dot(axis)) < CosTolerance)
        {
          continue;
        }
        PossibleSteps[t].push_back(q);
        steps.push_back(Segment{ origin, PositionOf(q) });
      }
    }
    const std::vector<char> crossing = SegmentsCrossSurface(volume, steps, parallelFor);
    StepCrossing.assign(count, {});
    std::size_t at = 0;
    for (std::size_t t = 0; t < count; ++t)
    {
      StepCrossing[t].assign(crossing.begin() + static_cast<std::ptrdiff_t>(at),
        crossing.begin() + static_cast<std::ptrdiff_t>(at + PossibleSteps[t].size()));
      at += PossibleSteps[t].size();
    }
  }

  /// Whether the step from `from` to `to` (one GrowSide takes) meets the surface: tested now,
  /// or looked up among the possible steps tested up front.
  bool StepCrossesSurface(std::int64_t from, std::int64_t to) const
  {
    if (!Volume)
    {
      return false;
    }
    if (PossibleSteps.empty())
    {
      return SegmentCrossesSurface(*Volume, PositionOf(from), PositionOf(to));
    }
    const std::vector<std::int64_t>& possible = PossibleSteps[static_cast<std::size_t>(from)];
    const auto found = std::lower_bound(possible.begin(), possible.end(), to); // nearby lists ascend
    if (found == possible.end() || *found != to)
    {
      throw Error("skeleton: a growth step that was not tested through the volume");
    }
    return StepCrossing[static_cast<std::size_t>(from)][static_cast<std::size_t>(found - possible.begin())] != 0;
  }

  Eigen::Vector3d PositionOf(std::int64_t t) const { return Positions.row(t).transpose(); }
  Eigen::Vector3d AxisOf(std::int64_t t) const
  {
    return Thinned.Axis.row(Thinned.Thinned[t]).transpose();
  }

  std::vector<std::int64_t> GrowSide(std::int64_t seed, Eigen::Vector3d direction)
  {
    std::vector<std::int64_t> chain;
    std::vector<std::int64_t> nearby;
    std::vector<std::pair<std::int64_t, double>> cone;
    const std::int64_t component = ComponentOf(seed);
    std::int64_t end = seed;
    while (true)
    {
      const Eigen::Vector3d origin = PositionOf(end);
      Tree->RadiusSearch(
        origin, Options.StepFactor * Cloud.Radius[Thinned.Thinned[end]], nearby);
      cone.clear();
      std::int64_t next = -1;
      double nextDistance = std::numeric_limits<double>::infinity();
      for (const std::int64_t q : nearby)
      {
        if (Clustered[q] || ComponentOf(q) != component)
        {
          continue;
        }
        const Eigen::Vector3d offset = PositionOf(q) - origin;
        const double distance = offset.norm();
        const double along = offset.dot(direction);
        if (!(distance > 0.0) || along < CosTolerance * distance ||
          std::abs(AxisOf(q).dot(direction)) < CosTolerance)
        {
          continue;
        }
        if (StepCrossesSurface(end, q))
        {
          continue; // close in space, but another part
        }
        cone.emplace_back(q, along);
        // nearby is in ascending index order, so strict '<' breaks ties by lower index.
        if (distance < nextDistance)
        {
          next = q;
          nextDistance = distance;
        }
      }
      if (next < 0)
      {
        return chain;
      }
      const double nextAlong = (PositionOf(next) - origin).dot(direction);
      for (const auto& [q, along] : cone)
      {
        if (along <= nextAlong)
        {
          Clustered[q] = 1;
        }
      }
      chain.push_back(next);
      Eigen::Vector3d axis = AxisOf(next);
      direction = axis.dot(direction) >= 0.0 ? axis : Eigen::Vector3d(-axis);
      end = next;
    }
  }

  const ProjectedCloud& Cloud;
  const ThinnedCloud& Thinned;
  const std::vector<std::int64_t>& PointComponent;
  const SkeletonSegmentOptions& Options;
  const RayCaster* Volume;
  const double CosTolerance;
  PointMatrix Positions;
  std::vector<char> Clustered;
  std::unique_ptr<SkeletonPointTree> Tree;
  std::vector<std::vector<std::int64_t>> PossibleSteps; // per point of T, ascending
  std::vector<std::vector<char>> StepCrossing;          // per possible step
};

} // namespace

std::vector<PolySegment> GrowPolySegments(const ProjectedCloud& cloud,
  const ThinnedCloud& thinned, const std::vector<std::int64_t>& pointComponent,
  const SkeletonSegmentOptions& options, const RayCaster* volume, const ParallelFor& parallelFor)
{
  ValidateSegmentOptions(options);
  std::vector<PolySegment> result;
  if (thinned.Thinned.empty())
  {
    return result;
  }
  SegmentGrower grower(cloud, thinned, pointComponent, options, volume, parallelFor);
  const std::vector<std::vector<std::int64_t>> segments = grower.GrowAll();

  // Keep segments with enough nodes; a component whose segments are all short keeps its
  // longest (first in seed order among equals).
  std::map<std::int64_t, std::size_t> longestOfComponent;
  std::map<std::int64_t, bool> componentHasKept;
  for (std::size_t s = 0; s < segments.size(); ++s)
  {
    const std::int64_t component = grower.ComponentOf(segments[s].front());
    const auto found = longestOfComponent.find(component);
    if (found == longestOfComponent.end() || segments[found->second].size() < segments[s].size())
    {
      longestOfComponent[component] = s;
    }
    if (segments[s].size() >= static_cast<std::size_t>(options.MinimumNodes))
    {
      componentHasKept[component] = true;
    }
  }
  for (std::size_t s = 0; s < segments.size(); ++s)
  {
    const std::int64_t component = grower.ComponentOf(segments[s].front());
    const bool longEnough = segments[s].size() >= static_cast<std::size_t>(options.MinimumNodes);
    if (longEnough || (!componentHasKept[component] && longestOfComponent[component] == s))
    {
      PolySegment segment;
      segment.reserve(segments[s].size());
      for (const std::int64_t t : segments[s])
      {
        segment.push_back(thinned.Thinned[t]);
      }
      result.push_back(std::move(segment));
    }
  }
  return result;
}

} // namespace shapediameter
