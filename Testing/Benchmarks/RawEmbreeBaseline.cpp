// SPDX-License-Identifier: BSD-3-Clause
#include "RawEmbreeBaseline.h"

#include "RayCasting/ConeSampling.h"
#include "SDF/ShapeDiameter.h"

#include <limits>
#include <stdexcept>

namespace shapediameter::bench
{

namespace
{

struct RawContext
{
#if RTC_VERSION_MAJOR >= 4
  RTCRayQueryContext Context; // first member: Embree hands this pointer to the filter
#else
  RTCIntersectContext Context; // first member: Embree hands this pointer to the filter
#endif
  float Normal[3];
  unsigned int Source;
};

void RawFilter(const RTCFilterFunctionNArguments* args)
{
  const auto* context = reinterpret_cast<const RawContext*>(args->context);
  for (unsigned int i = 0; i < args->N; ++i)
  {
    if (args->valid[i] == 0)
    {
      continue;
    }
    const float dot = RTCHitN_Ng_x(args->hit, args->N, i) * context->Normal[0] +
      RTCHitN_Ng_y(args->hit, args->N, i) * context->Normal[1] +
      RTCHitN_Ng_z(args->hit, args->N, i) * context->Normal[2];
    if (RTCHitN_primID(args->hit, args->N, i) == context->Source || dot >= 0)
    {
      args->valid[i] = 0;
    }
  }
}

} // namespace

RawScene::RawScene(const PointsView& points, const TrianglesView& triangles)
{
  this->Vertices.resize(3 * static_cast<std::size_t>(points.rows()) + 1);
  for (Eigen::Index i = 0; i < points.rows(); ++i)
  {
    for (int c = 0; c < 3; ++c)
    {
      this->Vertices[static_cast<std::size_t>(3 * i + c)] = static_cast<float>(points(i, c));
    }
  }
  this->Indices.resize(3 * static_cast<std::size_t>(triangles.rows()));
  for (Eigen::Index t = 0; t < triangles.rows(); ++t)
  {
    for (int c = 0; c < 3; ++c)
    {
      this->Indices[static_cast<std::size_t>(3 * t + c)] = static_cast<unsigned int>(triangles(t, c));
    }
  }
  this->Device = rtcNewDevice(nullptr);
  if (!this->Device)
  {
    throw std::runtime_error("raw Embree baseline: rtcNewDevice failed");
  }
  this->Scene = rtcNewScene(this->Device);
  rtcSetSceneBuildQuality(this->Scene, RTC_BUILD_QUALITY_MEDIUM);
  RTCGeometry geometry = rtcNewGeometry(this->Device, RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
    this->Vertices.data(), 0, 3 * sizeof(float), static_cast<std::size_t>(points.rows()));
  rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
    this->Indices.data(), 0, 3 * sizeof(unsigned int), static_cast<std::size_t>(triangles.rows()));
  rtcSetGeometryIntersectFilterFunction(geometry, &RawFilter);
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(this->Scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(this->Scene);
  if (rtcGetDeviceError(this->Device) != RTC_ERROR_NONE)
  {
    rtcReleaseScene(this->Scene);
    rtcReleaseDevice(this->Device);
    throw std::runtime_error("raw Embree baseline: building the BVH failed");
  }
}

RawScene::~RawScene()
{
  rtcReleaseScene(this->Scene);
  rtcReleaseDevice(this->Device);
}

RawRays MakeRawRays(
  const PointsView& points, const TrianglesView& triangles, int raysPerFace, double coneAngleDegrees)
{
  const RayOrigins origins = MakeFaceOrigins(points, triangles);
  const ConePattern pattern = MakeConePattern(raysPerFace, coneAngleDegrees);
  RawRays rays;
  rays.RaysPerFace = pattern.GetNumberOfRays();
  const auto faces = static_cast<std::size_t>(origins.Points.rows());
  const auto perFace = static_cast<std::size_t>(3 * rays.RaysPerFace);
  rays.Origins.resize(3 * faces);
  rays.Normals.resize(3 * faces);
  rays.Directions.resize(perFace * faces);
  rays.Skip.assign(faces, 0);
  std::vector<double> directions(perFace);
  for (std::size_t f = 0; f < faces; ++f)
  {
    const auto row = static_cast<Eigen::Index>(f);
    rays.Skip[f] = origins.Skip.empty() ? 0 : origins.Skip[f];
    const double axis[3] = { -origins.Normals(row, 0), -origins.Normals(row, 1),
      -origins.Normals(row, 2) };
    double x[3], y[3];
    MakeConeFrame(axis, origins.FirstAxes.row(row).data(), x, y);
    OrientConePattern(pattern, axis, x, y, directions.data());
    for (int c = 0; c < 3; ++c)
    {
      rays.Origins[3 * f + c] = static_cast<float>(origins.Points(row, c));
      rays.Normals[3 * f + c] = static_cast<float>(origins.Normals(row, c));
    }
    for (std::size_t k = 0; k < perFace; ++k)
    {
      rays.Directions[perFace * f + k] = static_cast<float>(directions[k]);
    }
  }
  return rays;
}

double CastRaw(const RawScene& scene, const RawRays& rays, const ParallelFor& parallelFor)
{
  const std::size_t faces = rays.NumberOfFaces();
  const auto perFace = static_cast<std::size_t>(3 * rays.RaysPerFace);
  std::vector<double> partialSums(faces, 0.0);
  parallelFor(faces, [&](std::size_t begin, std::size_t end) {
    RawContext context;
    RTCRayHit rayHit;
#if RTC_VERSION_MAJOR >= 4
    RTCIntersectArguments arguments;
    rtcInitIntersectArguments(&arguments);
    arguments.context = &context.Context;
#endif
    for (std::size_t f = begin; f < end; ++f)
    {
      if (rays.Skip[f])
      {
        continue;
      }
#if RTC_VERSION_MAJOR >= 4
      rtcInitRayQueryContext(&context.Context);
#else
      rtcInitIntersectContext(&context.Context);
#endif
      context.Normal[0] = rays.Normals[3 * f];
      context.Normal[1] = rays.Normals[3 * f + 1];
      context.Normal[2] = rays.Normals[3 * f + 2];
      context.Source = static_cast<unsigned int>(f);
      double sum = 0;
      for (int i = 0; i < rays.RaysPerFace; ++i)
      {
        const float* d = rays.Directions.data() + perFace * f + 3 * static_cast<std::size_t>(i);
        rayHit.ray.org_x = rays.Origins[3 * f];
        rayHit.ray.org_y = rays.Origins[3 * f + 1];
        rayHit.ray.org_z = rays.Origins[3 * f + 2];
        rayHit.ray.dir_x = d[0];
        rayHit.ray.dir_y = d[1];
        rayHit.ray.dir_z = d[2];
        rayHit.ray.tnear = 0.0f;
        rayHit.ray.tfar = std::numeric_limits<float>::infinity();
        rayHit.ray.time = 0.0f;
        rayHit.ray.mask = 0xFFFFFFFFu;
        rayHit.ray.id = 0;
        rayHit.ray.flags = 0;
        rayHit.hit.geomID = RTC_INVALID_GEOMETRY_ID;
        rayHit.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
#if RTC_VERSION_MAJOR >= 4
        rtcIntersect1(scene.Get(), &rayHit, &arguments);
#else
        rtcIntersect1(scene.Get(), &context.Context, &rayHit);
#endif
        if (rayHit.hit.geomID != RTC_INVALID_GEOMETRY_ID)
        {
          sum += rayHit.ray.tfar;
        }
      }
      partialSums[f] = sum;
    }
  });
  double total = 0;
  for (const double s : partialSums)
  {
    total += s;
  }
  return total;
}

} // namespace shapediameter::bench
