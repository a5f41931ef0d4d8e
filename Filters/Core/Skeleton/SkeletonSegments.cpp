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
    const RayCaster* volume)
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
    std::vector<std::int64_t> ahead;
    std::vector<Segment> steps;
    const std::int64_t component = ComponentOf(seed);
    std::int64_t end = seed;
    while (true)
    {
      const Eigen::Vector3d origin = PositionOf(end);
      Tree->RadiusSearch(
        origin, Options.StepFactor * Cloud.Radius[Thinned.Thinned[end]], nearby);
      ahead.clear();
      steps.clear();
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
        ahead.push_back(q);
        steps.push_back(Segment{ origin, PositionOf(q) });
      }
      // The inside tests of one step in one batch (a volume over processes answers it in one
      // exchange).
      const std::vector<char> crossing =
        Volume ? SegmentsCrossSurface(*Volume, steps, SerialFor) : std::vector<char>(ahead.size(), 0);
      cone.clear();
      std::int64_t next = -1;
      double nextDistance = std::numeric_limits<double>::infinity();
      for (std::size_t a = 0; a < ahead.size(); ++a)
      {
        if (crossing[a])
        {
          continue; // close in space, but another part
        }
        const std::int64_t q = ahead[a];
        const Eigen::Vector3d offset = PositionOf(q) - origin;
        cone.emplace_back(q, offset.dot(direction));
        // ahead is in ascending index order, so strict '<' breaks ties by lower index.
        const double distance = offset.norm();
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
};

} // namespace

std::vector<PolySegment> GrowPolySegments(const ProjectedCloud& cloud,
  const ThinnedCloud& thinned, const std::vector<std::int64_t>& pointComponent,
  const SkeletonSegmentOptions& options, const RayCaster* volume)
{
  ValidateSegmentOptions(options);
  std::vector<PolySegment> result;
  if (thinned.Thinned.empty())
  {
    return result;
  }
  SegmentGrower grower(cloud, thinned, pointComponent, options, volume);
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
