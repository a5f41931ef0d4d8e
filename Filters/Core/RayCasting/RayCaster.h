// SPDX-License-Identifier: BSD-3-Clause
// RayCaster: "closest valid hit along a ray" against a triangle mesh.
//
// The SDF (Shapira, Shamir & Cohen-Or 2008, Sect. 3) casts rays from a surface point into
// the object and ignores intersections "where the normal at the intersection points in the
// same direction as the point-of-origin (angle difference less than 90 degrees)", which
// removes false hits with the outside of the mesh. The sentence has two readings, the two
// values of HitRule (RayOrigin::Rule). Every implementation returns, for each ray, the
// distance t of the closest hit that is VALID under the origin's rule.
//
// Common to both rules:
//   - the origin's source triangle is never hit (a face-centre origin never hits its own
//     face), nor is a zero-area triangle; hits with t < the origin's MinDistance (Embree's
//     tnear) or t > its MaxDistance (tfar) are ignored;
//   - normals are compared with N_hit = (v1 - v0) x (v2 - v0), the hit triangle's geometric
//     normal by the right-hand rule of its vertex order (VTK's polygon normal), normalised, in
//     double precision, with a tolerance kPerpendicularTolerance (1e-6) on the cosine: without
//     it, a wall exactly perpendicular to the test direction (boxes, the facets of a cylinder
//     with a slice count divisible by 4) would be accepted or rejected by the last bit of the
//     coordinates, and such a mesh would change its SDF under a rigid motion;
//   - an origin with a zero or non-finite normal, or a non-finite point or direction, hits
//     nothing.
//
// HitRule::FirstHitLeaving (the default, CGAL's reading): only the source triangle and
//   zero-area triangles are transparent. The closest other hit is valid when the ray leaves
//   the volume through it, cos(N_hit, direction) > kPerpendicularTolerance; otherwise the ray
//   has no valid hit (+infinity): a first hit on a surface turned towards the ray is no
//   measurement.
// HitRule::SkipSameFacing ("ignore and continue"): a hit is valid when
//   cos(N_hit, originNormal) < -kPerpendicularTolerance (the normals more than 90 degrees
//   apart); rejected hits are transparent and traversal goes on to the next surface.
//
// The distance is the ray parameter t (hit = point + t * direction), i.e. a length when the
// direction is a unit vector, and +infinity when there is no valid hit.
//
// Implementations: EmbreeRayCaster (the product; BVH in single precision, the reported t is
// recomputed in double against the hit triangle's plane) and BruteForceRayCaster (every
// triangle, double-precision Moller-Trumbore; tests only). Both are immutable after
// construction and safe to call from several threads at once.
#pragma once

#include "Errors.h"
#include "Mesh/MeshTypes.h"
#include "Parallel.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace shapediameter
{

/// Which hit along a ray counts (see the header comment and ShapeDiameter.h).
enum class HitRule
{
  /// The closest hit other than the source triangle, valid when the ray leaves the volume
  /// through it (cos(N_hit, direction) > kPerpendicularTolerance); otherwise the ray has no
  /// valid hit and is dropped (CGAL's reading of the paper). The default (RayOrigin::Rule,
  /// ShapeDiameterOptions::Rule, vtkShapeDiameterFilter's HitRule 0).
  FirstHitLeaving,
  /// Hits on triangles facing the same way as the origin are transparent and the ray goes on
  /// to the next surface (the paper's sentence read as "ignore and continue"; the filter's
  /// HitRule 1).
  SkipSameFacing
};

/// Where a bundle of rays starts and what it must not hit.
struct RayOrigin
{
  double Point[3] = { 0, 0, 0 };
  /// Outward normal at the origin (any length). Under SkipSameFacing, hits on triangles facing
  /// the same way are transparent; under either rule a zero or non-finite normal hits nothing.
  double Normal[3] = { 0, 0, 0 };
  /// Triangle that is never reported (the origin's own face); -1 = none.
  std::int64_t SourceTriangle = -1;
  /// Hits with t < MinDistance are ignored (used for vertex origins, which lie on several
  /// triangles and have no single source triangle).
  double MinDistance = 0;
  /// Hits with t > MaxDistance are not looked for (Embree's tfar: a short query in a large
  /// mesh stops early); +inf = none. NaN: no hit at all.
  double MaxDistance = std::numeric_limits<double>::infinity();
  /// Which hit counts; default FirstHitLeaving.
  HitRule Rule = HitRule::FirstHitLeaving;
};

/// One ray of a batch (RayCaster::CastRays): where it starts, and its direction.
struct Ray
{
  RayOrigin Origin;
  double Direction[3] = { 0, 0, 0 };
};

class RayCaster
{
public:
  virtual ~RayCaster() = default;

  /// Distance to the closest valid hit along one ray; +inf when there is none.
  virtual double ClosestValidHit(const RayOrigin& origin, const double direction[3]) const = 0;

  /// Many rays, each from its own origin: outDistances[i] is ClosestValidHit of rays[i]. The
  /// skeleton's volume tests are written in this form so that a caster whose triangles are
  /// spread over processes answers a whole batch in one exchange (DistributedSkeleton.cpp). This
  /// default casts the rays with parallelFor, serially when there are fewer than 512.
  virtual void CastRays(const std::vector<Ray>& rays, std::vector<double>& outDistances, const ParallelFor& parallelFor) const
  {
    outDistances.resize(rays.size());
    const RangeBody cast = [&](std::size_t begin, std::size_t end) {
      for (std::size_t i = begin; i < end; ++i)
      {
        outDistances[i] = this->ClosestValidHit(rays[i].Origin, rays[i].Direction);
      }
    };
    // Below this many rays starting a parallel loop costs more than the rays (the VTK adapters'
    // loops start a thread each, to report progress; a ray costs a few microseconds).
    constexpr std::size_t fewRays = 512;
    if (rays.size() < fewRays)
    {
      SerialFor(rays.size(), cast);
    }
    else
    {
      parallelFor(rays.size(), cast);
    }
  }

  /// Batch form, the one the SDF loop uses (one virtual call per origin, not per ray):
  /// directions is count x 3 (row-major), outDistances receives count values.
  virtual void CastCone(const RayOrigin& origin, const double* directions, std::size_t count,
    double* outDistances) const
  {
    for (std::size_t i = 0; i < count; ++i)
    {
      outDistances[i] = this->ClosestValidHit(origin, directions + 3 * i);
    }
  }

  /// True when every call is an exchange between processes rather than a traversal (the
  /// skeleton's volume over processes): a caller then tests up front, in one batch, what it may
  /// need instead of one ray at a time as it goes.
  virtual bool PrefersFewLargeBatches() const { return false; }

  virtual std::size_t GetNumberOfTriangles() const = 0;
  /// Length of the diagonal of the mesh's axis-aligned bounding box (0 when empty); the
  /// scale for relative tolerances such as RayOrigin::MinDistance.
  virtual double GetBoundingBoxDiagonal() const = 0;

protected:
  RayCaster() = default;
  RayCaster(const RayCaster&) = delete;
  RayCaster& operator=(const RayCaster&) = delete;
};

/// The ray from `from`, a point inside the volume, along `direction` (unit) that ExitDistance
/// casts: HitRule::FirstHitLeaving, looked for no farther than maxDistance.
inline Ray ExitRay(const Eigen::Vector3d& from, const Eigen::Vector3d& direction,
  double maxDistance = std::numeric_limits<double>::infinity())
{
  Ray ray;
  for (int c = 0; c < 3; ++c)
  {
    ray.Origin.Point[c] = from(c);
    ray.Origin.Normal[c] = direction(c); // any non-zero normal: under FirstHitLeaving only its presence counts
    ray.Direction[c] = direction(c);
  }
  ray.Origin.MaxDistance = maxDistance;
  ray.Origin.Rule = HitRule::FirstHitLeaving;
  return ray;
}

/// Distance along `direction` (unit) at which a ray from `from`, a point inside the volume,
/// first leaves it (HitRule::FirstHitLeaving), looked for no farther than maxDistance; +inf
/// when it does not (it meets nothing, or enters first). The skeleton's clearance tests (the
/// thinning's medial ball, the connection's sheet factors) and its leaf extensions use it.
inline double ExitDistance(const RayCaster& caster, const Eigen::Vector3d& from, const Eigen::Vector3d& direction,
  double maxDistance = std::numeric_limits<double>::infinity())
{
  const Ray ray = ExitRay(from, direction, maxDistance);
  return caster.ClosestValidHit(ray.Origin, ray.Direction);
}

/// A straight segment from A to B, for SegmentsCrossSurface.
struct Segment
{
  Eigen::Vector3d A;
  Eigen::Vector3d B;
};

/// Per segment, true when it meets the surface of the mesh anywhere between its ends. Used by
/// the skeleton to keep its paths inside one part of the volume: two parts that touch (a trunk
/// resting on a foot) are close in space but not through the volume. Any surface counts,
/// entered or left: posed characters often interpenetrate (a trunk pushed into a foot), and the
/// union of their volumes must not join the two parts either.
/// One or two rays from A, in two batches (CastRays): FirstHitLeaving returns the closest hit
/// when it is a leaving one (the usual case from inside); otherwise the closest hit, if any, is
/// an entering one, which SkipSameFacing with the origin normal along the ray finds (it skips
/// the leaving hits). A segment of zero or non-finite length crosses nothing.
inline std::vector<char> SegmentsCrossSurface(
  const RayCaster& caster, const std::vector<Segment>& segments, const ParallelFor& parallelFor)
{
  std::vector<char> crossing(segments.size(), 0);
  std::vector<std::size_t> cast;
  std::vector<Ray> rays;
  cast.reserve(segments.size());
  rays.reserve(segments.size());
  for (std::size_t s = 0; s < segments.size(); ++s)
  {
    const double length = (segments[s].B - segments[s].A).norm();
    if (!(length > 0) || !std::isfinite(length))
    {
      continue;
    }
    // Hits beyond the segment cannot make it cross: the search stops at its end (Embree's tfar,
    // the ray's MaxDistance, which is the segment's length below).
    cast.push_back(s);
    rays.push_back(ExitRay(segments[s].A, (segments[s].B - segments[s].A) / length, length));
  }
  std::vector<double> distances;
  caster.CastRays(rays, distances, parallelFor);
  std::vector<std::size_t> entering;
  std::vector<Ray> second;
  for (std::size_t r = 0; r < cast.size(); ++r)
  {
    if (std::isfinite(distances[r]))
    {
      crossing[cast[r]] = distances[r] < rays[r].Origin.MaxDistance; // the closest hit is this one
    }
    else
    {
      entering.push_back(cast[r]);
      second.push_back(rays[r]);
      second.back().Origin.Rule = HitRule::SkipSameFacing;
    }
  }
  caster.CastRays(second, distances, parallelFor);
  for (std::size_t r = 0; r < entering.size(); ++r)
  {
    crossing[entering[r]] = distances[r] < second[r].Origin.MaxDistance;
  }
  return crossing;
}

/// An axis-aligned box; empty (Low above High) until a point extends it.
struct AxisBox
{
  Eigen::Vector3d Low = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d High = Eigen::Vector3d::Constant(-std::numeric_limits<double>::infinity());

  void Extend(const Eigen::Vector3d& point)
  {
    this->Low = this->Low.cwiseMin(point);
    this->High = this->High.cwiseMax(point);
  }
  bool Empty() const { return !(this->Low.array() <= this->High.array()).all(); }
};

/// False only when the ray cannot meet anything inside `box`: no point of it between its origin
/// and its MaxDistance (or beyond: 1e-5 of it, and `margin` farther) lies within `margin` of the
/// box. A ray with a non-finite origin or direction may meet it (the caster decides). A caster
/// of the box's triangles, whose single-precision hits lie within a small fraction of the mesh's
/// size of the exact ones, has no hit for a ray this rejects when `margin` exceeds that
/// fraction (VolumeOverProcesses sends each process only the rays that may meet its box).
inline bool RayMayMeetBox(const Ray& ray, const AxisBox& box, double margin)
{
  if (box.Empty())
  {
    return false;
  }
  const double* origin = ray.Origin.Point;
  const double* direction = ray.Direction;
  if (!std::isfinite(origin[0]) || !std::isfinite(origin[1]) || !std::isfinite(origin[2]) ||
    !std::isfinite(direction[0]) || !std::isfinite(direction[1]) || !std::isfinite(direction[2]))
  {
    return true;
  }
  const double length = std::sqrt(direction[0] * direction[0] + direction[1] * direction[1] + direction[2] * direction[2]);
  double low = 0.0;
  double high = std::numeric_limits<double>::infinity();
  if (std::isfinite(ray.Origin.MaxDistance) && length > 0)
  {
    high = std::max(0.0, ray.Origin.MaxDistance) * (1 + 1e-5) + margin / length;
  }
  for (int axis = 0; axis < 3; ++axis)
  {
    const double from = box.Low(axis) - margin;
    const double to = box.High(axis) + margin;
    if (direction[axis] == 0.0)
    {
      if (origin[axis] < from || origin[axis] > to)
      {
        return false;
      }
      continue;
    }
    double enter = (from - origin[axis]) / direction[axis];
    double leave = (to - origin[axis]) / direction[axis];
    if (enter > leave)
    {
      std::swap(enter, leave);
    }
    low = std::max(low, enter);
    high = std::min(high, leave);
    if (low > high)
    {
      return false;
    }
  }
  return true;
}

/// SegmentsCrossSurface of the one segment from a to b.
inline bool SegmentCrossesSurface(const RayCaster& caster, const Eigen::Vector3d& a, const Eigen::Vector3d& b)
{
  return SegmentsCrossSurface(caster, { Segment{ a, b } }, SerialFor)[0] != 0;
}

namespace raycasterdetail
{
inline bool IsFinite3(const double v[3])
{
  return std::isfinite(v[0]) && std::isfinite(v[1]) && std::isfinite(v[2]);
}

/// unit = v / |v|; false (unit = 0) when v is zero or not finite.
inline bool UnitVector(const double v[3], double unit[3])
{
  const double length = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  if (!(length > 0) || !std::isfinite(length))
  {
    unit[0] = unit[1] = unit[2] = 0;
    return false;
  }
  for (int c = 0; c < 3; ++c)
  {
    unit[c] = v[c] / length;
  }
  return true;
}

/// See the validity rules above.
constexpr double kPerpendicularTolerance = 1e-6;

/// Unit geometric normal (right-hand rule; zero for a zero-area triangle) and plane offset
/// dot(normal, v0).
struct TrianglePlane
{
  double Normal[3];
  double Offset;
};

/// Checks the mesh (finite coordinates, indices in range) and returns the triangle planes
/// and the bounding-box diagonal. Throws Error.
inline std::vector<TrianglePlane> CheckMeshAndComputePlanes(const PointsView& points,
  const TrianglesView& triangles, double& boundingBoxDiagonal)
{
  if (!points.allFinite())
  {
    throw Error("ray caster: the mesh has a non-finite point coordinate");
  }
  const auto pointCount = static_cast<std::int64_t>(points.rows());
  boundingBoxDiagonal = 0;
  if (points.rows() > 0)
  {
    boundingBoxDiagonal = (points.colwise().maxCoeff() - points.colwise().minCoeff()).norm();
  }
  std::vector<TrianglePlane> planes(static_cast<std::size_t>(triangles.rows()));
  for (Eigen::Index t = 0; t < triangles.rows(); ++t)
  {
    for (int c = 0; c < 3; ++c)
    {
      const std::int64_t index = triangles(t, c);
      if (index < 0 || index >= pointCount)
      {
        throw Error("ray caster: triangle " + std::to_string(t) +
          " has a vertex index out of range: " + std::to_string(index));
      }
    }
    const auto p0 = points.row(triangles(t, 0));
    const auto p1 = points.row(triangles(t, 1));
    const auto p2 = points.row(triangles(t, 2));
    const double e1[3] = { p1(0) - p0(0), p1(1) - p0(1), p1(2) - p0(2) };
    const double e2[3] = { p2(0) - p0(0), p2(1) - p0(1), p2(2) - p0(2) };
    const double normal[3] = { e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
      e1[0] * e2[1] - e1[1] * e2[0] };
    TrianglePlane& plane = planes[static_cast<std::size_t>(t)];
    if (UnitVector(normal, plane.Normal))
    {
      plane.Offset = plane.Normal[0] * p0(0) + plane.Normal[1] * p0(1) + plane.Normal[2] * p0(2);
    }
    if (!std::isfinite(plane.Offset))
    {
      // Zero area, or overflow for absurd coordinates: unhittable rather than NaN.
      plane = TrianglePlane{ { 0, 0, 0 }, 0 };
    }
  }
  return planes;
}

/// HitRule::FirstHitLeaving's test: the ray (any length) leaves the volume through the plane.
inline bool RayLeavesThrough(const TrianglePlane& plane, const double direction[3])
{
  const double length = std::sqrt(direction[0] * direction[0] + direction[1] * direction[1] +
    direction[2] * direction[2]);
  return plane.Normal[0] * direction[0] + plane.Normal[1] * direction[1] + plane.Normal[2] * direction[2] >
    kPerpendicularTolerance * length;
}

/// HitRule::SkipSameFacing's test: a hit on `plane` may count for an origin with outward UNIT
/// normal.
inline bool FacesAway(const TrianglePlane& plane, const double unitOriginNormal[3])
{
  return plane.Normal[0] * unitOriginNormal[0] + plane.Normal[1] * unitOriginNormal[1] +
    plane.Normal[2] * unitOriginNormal[2] <
    -kPerpendicularTolerance;
}
} // namespace raycasterdetail

} // namespace shapediameter
