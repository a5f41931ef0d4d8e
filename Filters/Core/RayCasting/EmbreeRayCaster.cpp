// SPDX-License-Identifier: BSD-3-Clause
#include "RayCasting/EmbreeRayCaster.h"

// Embree 3 (Debian 12) and Embree 4 (Debian 13) from the same source: CMake sets
// SHAPEDIAMETER_EMBREE_MAJOR on the embree target to the major version it found; the API
// differences are the RTC_VERSION_MAJOR branches below (header path, RTCIntersectContext vs
// RTCRayQueryContext + RTCIntersectArguments in rtcIntersect1).
#if SHAPEDIAMETER_EMBREE_MAJOR >= 4
#include <embree4/rtcore.h>
#else
#include <embree3/rtcore.h>
#endif
#if RTC_VERSION_MAJOR != SHAPEDIAMETER_EMBREE_MAJOR
#error "Embree header and the Embree package CMake found differ in major version"
#endif

#include <algorithm>
#include <string>

namespace shapediameter
{

namespace
{
using raycasterdetail::TrianglePlane;

#if RTC_VERSION_MAJOR >= 4
using RayContext = RTCRayQueryContext;
#else
using RayContext = RTCIntersectContext;
#endif

/// Embree passes our context back to the filter: the Embree context (RTCIntersectContext in
/// Embree 3, RTCRayQueryContext in Embree 4) must stay the first member so that the pointer
/// Embree gives us is the address of this struct.
struct FilterContext
{
  RayContext Context;
  const TrianglePlane* Planes;
  double OriginNormal[3]; // unit
  unsigned int SourceTriangle;
  bool SkipSameFacing;
};

/// |cos| between Ng and the origin normal above which Embree's single-precision Ng decides
/// alone. Ng's direction error is ~6e-8 x (coordinate magnitude / edge length), far below this
/// for any mesh whose edges exceed 1e-5 of its bounding box.
constexpr double kSinglePrecisionBand = 1e-2;

/// The validity rules of RayCaster.h. A clear case is decided on Embree's own geometric
/// normal Ng (in registers); only a hit within kSinglePrecisionBand of perpendicular reads the
/// double-precision plane table, so the decisions are those of the double-precision rule
/// (as BruteForceRayCaster's) while avoiding a cache miss per candidate hit (which cost ~20%
/// of the SDF run time).
void RejectInvalidHits(const RTCFilterFunctionNArguments* args)
{
  const auto* filter = reinterpret_cast<const FilterContext*>(args->context);
  constexpr double band2 = kSinglePrecisionBand * kSinglePrecisionBand;
  for (unsigned int i = 0; i < args->N; ++i)
  {
    if (args->valid[i] == 0)
    {
      continue;
    }
    const unsigned int triangle = RTCHitN_primID(args->hit, args->N, i);
    if (triangle == filter->SourceTriangle)
    {
      args->valid[i] = 0;
      continue;
    }
    if (!filter->SkipSameFacing)
    {
      continue; // HitRule::FirstHitLeaving: the closest hit is judged after the traversal
    }
    const double nx = RTCHitN_Ng_x(args->hit, args->N, i);
    const double ny = RTCHitN_Ng_y(args->hit, args->N, i);
    const double nz = RTCHitN_Ng_z(args->hit, args->N, i);
    const double dot =
      nx * filter->OriginNormal[0] + ny * filter->OriginNormal[1] + nz * filter->OriginNormal[2];
    const bool valid = dot * dot > band2 * (nx * nx + ny * ny + nz * nz)
      ? dot < 0
      : raycasterdetail::FacesAway(filter->Planes[triangle], filter->OriginNormal);
    if (!valid)
    {
      args->valid[i] = 0;
    }
  }
}

std::string DeviceErrorText(RTCDevice device)
{
  switch (rtcGetDeviceError(device))
  {
    case RTC_ERROR_NONE:
      return "no error";
    case RTC_ERROR_INVALID_ARGUMENT:
      return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION:
      return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY:
      return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU:
      return "unsupported CPU";
    case RTC_ERROR_CANCELLED:
      return "cancelled";
    default:
      return "unknown error";
  }
}
} // namespace

struct EmbreeRayCaster::Internals
{
  RTCDevice Device = nullptr;
  RTCScene Scene = nullptr;
  std::vector<float> Vertices;       // relative to Centre, padded by one float for SSE loads
  std::vector<unsigned int> Indices; // 3 per triangle
  std::vector<TrianglePlane> Planes; // Offset relative to Centre
  double Centre[3] = { 0, 0, 0 };
  double BoundingBoxDiagonal = 0;

  ~Internals()
  {
    if (this->Scene)
    {
      rtcReleaseScene(this->Scene);
    }
    if (this->Device)
    {
      rtcReleaseDevice(this->Device);
    }
  }
};

EmbreeRayCaster::EmbreeRayCaster(
  const PointsView& points, const TrianglesView& triangles, const EmbreeRayCasterOptions& options)
  : Impl(std::make_unique<Internals>())
{
  this->CopyMesh(points, triangles, options);
  this->BuildBvh(options);
}

EmbreeRayCaster::EmbreeRayCaster(PointMatrix&& points, TriangleMatrix&& triangles, const EmbreeRayCasterOptions& options)
  : Impl(std::make_unique<Internals>())
{
  this->CopyMesh(points, triangles, options);
  points = PointMatrix();
  triangles = TriangleMatrix();
  this->BuildBvh(options);
}

void EmbreeRayCaster::CopyMesh(const PointsView& points, const TrianglesView& triangles, const EmbreeRayCasterOptions& options)
{
  Internals& impl = *this->Impl;
  impl.Planes =
    raycasterdetail::CheckMeshAndComputePlanes(points, triangles, impl.BoundingBoxDiagonal);
  if (points.rows() >= static_cast<Eigen::Index>(RTC_INVALID_GEOMETRY_ID) ||
    triangles.rows() >= static_cast<Eigen::Index>(RTC_INVALID_GEOMETRY_ID))
  {
    throw Error("Embree ray caster: more than 2^32 - 1 points or triangles");
  }
  if (triangles.rows() == 0)
  {
    return; // Nothing to hit: every cast returns +inf without Embree.
  }

  const Eigen::RowVector3d centre = options.Centre
    ? Eigen::RowVector3d((*options.Centre)[0], (*options.Centre)[1], (*options.Centre)[2])
    : Eigen::RowVector3d(0.5 * (points.colwise().maxCoeff() + points.colwise().minCoeff()));
  if (!centre.allFinite())
  {
    throw Error("Embree ray caster: the centre is not finite");
  }
  for (int c = 0; c < 3; ++c)
  {
    impl.Centre[c] = centre(c);
  }
  impl.Vertices.resize(3 * static_cast<std::size_t>(points.rows()) + 1, 0.0f);
  for (Eigen::Index p = 0; p < points.rows(); ++p)
  {
    for (int c = 0; c < 3; ++c)
    {
      impl.Vertices[static_cast<std::size_t>(3 * p + c)] =
        static_cast<float>(points(p, c) - centre(c));
    }
  }
  impl.Indices.resize(3 * static_cast<std::size_t>(triangles.rows()));
  for (Eigen::Index t = 0; t < triangles.rows(); ++t)
  {
    for (int c = 0; c < 3; ++c)
    {
      impl.Indices[static_cast<std::size_t>(3 * t + c)] =
        static_cast<unsigned int>(triangles(t, c));
    }
    // Offsets relative to the centre avoid cancellation in the distance refinement.
    TrianglePlane& plane = impl.Planes[static_cast<std::size_t>(t)];
    const auto p0 = points.row(triangles(t, 0));
    plane.Offset = plane.Normal[0] * (p0(0) - centre(0)) + plane.Normal[1] * (p0(1) - centre(1)) +
      plane.Normal[2] * (p0(2) - centre(2));
    if (!std::isfinite(plane.Offset))
    {
      plane = TrianglePlane{ { 0, 0, 0 }, 0 };
    }
  }
}

void EmbreeRayCaster::BuildBvh(const EmbreeRayCasterOptions& options)
{
  Internals& impl = *this->Impl;
  if (impl.Planes.empty())
  {
    return; // Nothing to hit: every cast returns +inf without Embree.
  }
  impl.Device = rtcNewDevice(nullptr);
  if (!impl.Device)
  {
    throw Error("Embree ray caster: rtcNewDevice failed: " + DeviceErrorText(nullptr));
  }
  if (!rtcGetDeviceProperty(impl.Device, RTC_DEVICE_PROPERTY_FILTER_FUNCTION_SUPPORTED))
  {
    throw Error("Embree ray caster: this Embree was built without filter functions");
  }
  impl.Scene = rtcNewScene(impl.Device);
  rtcSetSceneFlags(impl.Scene, static_cast<RTCSceneFlags>((options.Robust ? RTC_SCENE_FLAG_ROBUST : RTC_SCENE_FLAG_NONE) |
                                 (options.Compact ? RTC_SCENE_FLAG_COMPACT : RTC_SCENE_FLAG_NONE)));
  const RTCBuildQuality quality = options.BuildQuality == EmbreeBuildQuality::Low
    ? RTC_BUILD_QUALITY_LOW
    : options.BuildQuality == EmbreeBuildQuality::High ? RTC_BUILD_QUALITY_HIGH
                                                       : RTC_BUILD_QUALITY_MEDIUM;
  rtcSetSceneBuildQuality(impl.Scene, quality);

  RTCGeometry geometry = rtcNewGeometry(impl.Device, RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetGeometryBuildQuality(geometry, quality);
  rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
    impl.Vertices.data(), 0, 3 * sizeof(float), (impl.Vertices.size() - 1) / 3);
  rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
    impl.Indices.data(), 0, 3 * sizeof(unsigned int), impl.Planes.size());
  rtcSetGeometryIntersectFilterFunction(geometry, &RejectInvalidHits);
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(impl.Scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(impl.Scene);
  if (rtcGetDeviceError(impl.Device) != RTC_ERROR_NONE)
  {
    throw Error("Embree ray caster: building the BVH failed: " +
      DeviceErrorText(impl.Device));
  }
}

EmbreeRayCaster::~EmbreeRayCaster() = default;

std::size_t EmbreeRayCaster::GetNumberOfTriangles() const
{
  return this->Impl->Planes.size();
}

double EmbreeRayCaster::GetBoundingBoxDiagonal() const
{
  return this->Impl->BoundingBoxDiagonal;
}

double EmbreeRayCaster::ClosestValidHit(const RayOrigin& origin, const double direction[3]) const
{
  double distance;
  this->CastCone(origin, direction, 1, &distance);
  return distance;
}

void EmbreeRayCaster::CastCone(const RayOrigin& origin, const double* directions,
  std::size_t count, double* outDistances) const
{
  this->Cast(origin, directions, count, outDistances, nullptr);
}

void EmbreeRayCaster::CastRaysWithOrder(const std::vector<Ray>& rays, std::vector<double>& outDistances,
  std::vector<float>& outOrder, const ParallelFor& parallelFor) const
{
  outDistances.resize(rays.size());
  outOrder.resize(rays.size());
  parallelFor(rays.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i)
    {
      this->Cast(rays[i].Origin, rays[i].Direction, 1, outDistances.data() + i, outOrder.data() + i);
    }
  });
}

void EmbreeRayCaster::Cast(const RayOrigin& origin, const double* directions, std::size_t count,
  double* outDistances, float* outOrder) const
{
  const double infinity = std::numeric_limits<double>::infinity();
  const Internals& impl = *this->Impl;
  if (outOrder)
  {
    std::fill(outOrder, outOrder + count, std::numeric_limits<float>::infinity());
  }
  if (!impl.Scene || !raycasterdetail::IsFinite3(origin.Point) ||
    !raycasterdetail::IsFinite3(origin.Normal) || !std::isfinite(origin.MinDistance) || std::isnan(origin.MaxDistance))
  {
    std::fill(outDistances, outDistances + count, infinity);
    return;
  }

  FilterContext filter;
  if (!raycasterdetail::UnitVector(origin.Normal, filter.OriginNormal))
  {
    std::fill(outDistances, outDistances + count, infinity);
    return;
  }
#if RTC_VERSION_MAJOR >= 4
  rtcInitRayQueryContext(&filter.Context);
  RTCIntersectArguments arguments;
  rtcInitIntersectArguments(&arguments);
  arguments.context = &filter.Context; // the geometry's filter (RejectInvalidHits) receives it
#else
  rtcInitIntersectContext(&filter.Context);
#endif
  filter.SkipSameFacing = origin.Rule == HitRule::SkipSameFacing;
  filter.Planes = impl.Planes.data();
  filter.SourceTriangle =
    origin.SourceTriangle >= 0 && origin.SourceTriangle < static_cast<std::int64_t>(impl.Planes.size())
    ? static_cast<unsigned int>(origin.SourceTriangle)
    : RTC_INVALID_GEOMETRY_ID;

  // Origin relative to the BVH's centre, in double for the refinement.
  const double o[3] = { origin.Point[0] - impl.Centre[0], origin.Point[1] - impl.Centre[1],
    origin.Point[2] - impl.Centre[2] };
  const float minDistance = static_cast<float>(std::max(0.0, origin.MinDistance));
  const float maxDistance = static_cast<float>(origin.MaxDistance);

  // Rays are cast in blocks; the refinement runs after each block, by which time the
  // prefetched triangle planes have arrived (a cache miss per ray otherwise cost ~5%).
  constexpr std::size_t blockSize = 64;
  unsigned int hitTriangles[blockSize];
  RTCRayHit rayHit;
  for (std::size_t blockBegin = 0; blockBegin < count; blockBegin += blockSize)
  {
    const std::size_t blockEnd = std::min(count, blockBegin + blockSize);
    for (std::size_t i = blockBegin; i < blockEnd; ++i)
    {
      const double* d = directions + 3 * i;
      hitTriangles[i - blockBegin] = RTC_INVALID_GEOMETRY_ID;
      outDistances[i] = infinity;
      if (!raycasterdetail::IsFinite3(d) || (d[0] == 0 && d[1] == 0 && d[2] == 0))
      {
        continue;
      }
      rayHit.ray.org_x = static_cast<float>(o[0]);
      rayHit.ray.org_y = static_cast<float>(o[1]);
      rayHit.ray.org_z = static_cast<float>(o[2]);
      rayHit.ray.tnear = minDistance;
      rayHit.ray.dir_x = static_cast<float>(d[0]);
      rayHit.ray.dir_y = static_cast<float>(d[1]);
      rayHit.ray.dir_z = static_cast<float>(d[2]);
      rayHit.ray.time = 0.0f;
      rayHit.ray.tfar = maxDistance;
      rayHit.ray.mask = 0xFFFFFFFFu;
      rayHit.ray.id = 0;
      rayHit.ray.flags = 0;
      rayHit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rayHit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
#if RTC_VERSION_MAJOR >= 4
      rtcIntersect1(impl.Scene, &rayHit, &arguments);
#else
      rtcIntersect1(impl.Scene, &filter.Context, &rayHit);
#endif
      if (rayHit.hit.geomID != RTC_INVALID_GEOMETRY_ID)
      {
        hitTriangles[i - blockBegin] = rayHit.hit.primID;
        outDistances[i] = rayHit.ray.tfar;
        if (outOrder)
        {
          outOrder[i] = rayHit.ray.tfar;
        }
        // The plane is needed only after the block: fetch it while the next rays traverse.
        __builtin_prefetch(impl.Planes.data() + rayHit.hit.primID);
      }
    }
    for (std::size_t i = blockBegin; i < blockEnd; ++i)
    {
      const unsigned int triangle = hitTriangles[i - blockBegin];
      if (triangle == RTC_INVALID_GEOMETRY_ID)
      {
        continue;
      }
      // Double-precision distance to the hit triangle's plane. Skipped when the ray is
      // nearly parallel to the plane (|cos| < 1e-9), where it is ill-conditioned.
      const double* d = directions + 3 * i;
      const TrianglePlane& plane = impl.Planes[triangle];
      const double* n = plane.Normal;
      if (!filter.SkipSameFacing && !raycasterdetail::RayLeavesThrough(plane, d))
      {
        outDistances[i] = infinity; // HitRule::FirstHitLeaving: the ray enters the volume here
        continue;
      }
      const double nd = n[0] * d[0] + n[1] * d[1] + n[2] * d[2];
      if (nd * nd >= 1e-18 * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]))
      {
        const double refined = (plane.Offset - (n[0] * o[0] + n[1] * o[1] + n[2] * o[2])) / nd;
        if (std::isfinite(refined) && refined >= 0)
        {
          outDistances[i] = refined;
        }
      }
    }
  }
}

} // namespace shapediameter
