// SPDX-License-Identifier: BSD-3-Clause
// BruteForceRayCaster: the reference RayCaster that tests every triangle of the mesh.
//
// For tests only (O(triangles) per ray). Implements exactly the validity rules documented in
// RayCaster.h with a double-precision Moller-Trumbore test whose barycentric bounds are
// inclusive (a ray through a shared edge hits both triangles, at the same distance), so the
// Embree caster can be checked against it ray by ray. Zero-area triangles are never hit.
#pragma once

#include "RayCasting/RayCaster.h"

namespace shapediameter
{

class BruteForceRayCaster final : public RayCaster
{
public:
  /// Copies the mesh. Throws Error on a non-finite coordinate or a vertex index out
  /// of range.
  BruteForceRayCaster(const PointsView& points, const TrianglesView& triangles);

  double ClosestValidHit(const RayOrigin& origin, const double direction[3]) const override;
  std::size_t GetNumberOfTriangles() const override { return this->Planes.size(); }
  double GetBoundingBoxDiagonal() const override { return this->BoundingBoxDiagonal; }

private:
  PointMatrix Points;
  TriangleMatrix Triangles;
  std::vector<raycasterdetail::TrianglePlane> Planes;
  double BoundingBoxDiagonal = 0;
};

} // namespace shapediameter
