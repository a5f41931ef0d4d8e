// SPDX-License-Identifier: BSD-3-Clause
// The raw Embree baseline of the SDF benchmarks (BenchShapeDiameter, BenchPipeline).
//
// It casts exactly the rays of the shape diameter function -- the same origins (face
// centroids from MakeFaceOrigins), the same cone pattern and frames (MakeConePattern,
// MakeConeFrame, OrientConePattern: 30 rays in a 120-degree cone by default) -- with plain
// rtcIntersect1 and the same intersection filter (reject the source triangle and hits whose
// geometric normal Ng has a non-negative dot product with the origin normal), keeping the
// first valid hit only: no statistics, no double-precision refinement, no virtual calls, rays
// precomputed in float. It includes Embree directly on purpose: it is the independent
// baseline, not product code, and the lower bound any SDF implementation has to pay.
// (The product's filter differs only within 1e-6 of perpendicular, see RayCaster.h.)
#pragma once

#include "Mesh/MeshTypes.h"
#include "Parallel.h"

// Embree 3 or 4: CMake sets SHAPEDIAMETER_EMBREE_MAJOR on the embree target (see EmbreeRayCaster.cpp).
#if SHAPEDIAMETER_EMBREE_MAJOR >= 4
#include <embree4/rtcore.h>
#else
#include <embree3/rtcore.h>
#endif

#include <cstdint>
#include <vector>

namespace shapediameter::bench
{

/// An Embree device and scene (medium build quality, like EmbreeRayCaster) over a triangle
/// mesh with the SDF's validity filter. Constructing it builds the BVH.
class RawScene
{
public:
  RawScene(const PointsView& points, const TrianglesView& triangles);
  ~RawScene();
  RawScene(const RawScene&) = delete;
  RawScene& operator=(const RawScene&) = delete;

  RTCScene Get() const { return this->Scene; }

private:
  RTCDevice Device = nullptr;
  RTCScene Scene = nullptr;
  std::vector<float> Vertices; // padded by one float for Embree's SSE loads
  std::vector<unsigned int> Indices;
};

/// The SDF's rays in float: per face an origin, its unit outward normal and RaysPerFace
/// directions (3 floats each, face-major).
struct RawRays
{
  std::vector<float> Origins, Normals, Directions;
  /// Nonzero = not cast (MakeFaceOrigins' Skip: zero-area faces), as in the product.
  std::vector<std::uint8_t> Skip;
  int RaysPerFace = 0;

  std::size_t NumberOfFaces() const { return this->Origins.size() / 3; }
  std::size_t NumberOfRays() const { return this->Directions.size() / 3; }
};

/// The rays ComputeShapeDiameter casts from MakeFaceOrigins(points, triangles) with the
/// given pattern (defaults: ShapeDiameterOptions'). Throws what MakeFaceOrigins and
/// MakeConePattern throw.
RawRays MakeRawRays(const PointsView& points, const TrianglesView& triangles,
  int raysPerFace = 30, double coneAngleDegrees = 120.0);

/// Casts every ray through parallelFor (over faces) and returns the sum of the hit distances
/// (so the work cannot be optimised away).
double CastRaw(const RawScene& scene, const RawRays& rays, const ParallelFor& parallelFor);

} // namespace shapediameter::bench
