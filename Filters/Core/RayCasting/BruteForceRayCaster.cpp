// SPDX-License-Identifier: BSD-3-Clause
#include "RayCasting/BruteForceRayCaster.h"

namespace shapediameter
{

BruteForceRayCaster::BruteForceRayCaster(const PointsView& points, const TrianglesView& triangles)
  : Points(points)
  , Triangles(triangles)
{
  this->Planes =
    raycasterdetail::CheckMeshAndComputePlanes(points, triangles, this->BoundingBoxDiagonal);
}

double BruteForceRayCaster::ClosestValidHit(const RayOrigin& origin, const double direction[3]) const
{
  const double infinity = std::numeric_limits<double>::infinity();
  if (!raycasterdetail::IsFinite3(origin.Point) || !raycasterdetail::IsFinite3(origin.Normal) ||
    !raycasterdetail::IsFinite3(direction))
  {
    return infinity;
  }
  double originNormal[3];
  if (!raycasterdetail::UnitVector(origin.Normal, originNormal))
  {
    return infinity;
  }
  const double* o = origin.Point;
  const double* d = direction;
  const bool skipSameFacing = origin.Rule == HitRule::SkipSameFacing;
  double closest = infinity;
  Eigen::Index closestTriangle = -1;
  for (Eigen::Index t = 0; t < this->Triangles.rows(); ++t)
  {
    const raycasterdetail::TrianglePlane& plane = this->Planes[static_cast<std::size_t>(t)];
    const bool degenerate = plane.Normal[0] == 0 && plane.Normal[1] == 0 && plane.Normal[2] == 0;
    if (t == origin.SourceTriangle || degenerate ||
      (skipSameFacing && !raycasterdetail::FacesAway(plane, originNormal)))
    {
      continue;
    }
    const auto p0 = this->Points.row(this->Triangles(t, 0));
    const auto p1 = this->Points.row(this->Triangles(t, 1));
    const auto p2 = this->Points.row(this->Triangles(t, 2));
    const double e1[3] = { p1(0) - p0(0), p1(1) - p0(1), p1(2) - p0(2) };
    const double e2[3] = { p2(0) - p0(0), p2(1) - p0(1), p2(2) - p0(2) };
    const double p[3] = { d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2],
      d[0] * e2[1] - d[1] * e2[0] };
    const double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
    if (det == 0 || !std::isfinite(det))
    {
      continue;
    }
    const double inverseDet = 1.0 / det;
    const double s[3] = { o[0] - p0(0), o[1] - p0(1), o[2] - p0(2) };
    const double u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) * inverseDet;
    if (!(u >= 0 && u <= 1))
    {
      continue;
    }
    const double q[3] = { s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2],
      s[0] * e1[1] - s[1] * e1[0] };
    const double v = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) * inverseDet;
    if (!(v >= 0 && u + v <= 1))
    {
      continue;
    }
    const double distance = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) * inverseDet;
    if (distance >= origin.MinDistance && distance >= 0 && distance <= origin.MaxDistance && distance < closest)
    {
      closest = distance;
      closestTriangle = t;
    }
  }
  if (!skipSameFacing && closestTriangle >= 0 &&
    !raycasterdetail::RayLeavesThrough(this->Planes[static_cast<std::size_t>(closestTriangle)], d))
  {
    return infinity;
  }
  return closest;
}

} // namespace shapediameter
