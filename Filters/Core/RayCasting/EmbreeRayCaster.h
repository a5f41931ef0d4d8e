// SPDX-License-Identifier: BSD-3-Clause
// EmbreeRayCaster: the product's RayCaster, an Embree BVH over the triangle mesh.
//
// This class (its .cpp) is the only place in the project that includes Embree. It builds
// against Embree 3 (Debian 12) or Embree 4 (Debian 13); the two differ only in the
// RTC_VERSION_MAJOR branches of the .cpp (header path, intersection context).
//
// How it meets the contract of RayCaster.h:
//   - One RTC_GEOMETRY_TYPE_TRIANGLE over float vertex and uint32 index buffers owned by this
//     object and shared with Embree (rtcSetSharedGeometryBuffer, no second copy). The vertices are translated by the bounding-box centre
//     before the conversion to float so that a mesh far from the origin keeps its precision.
//   - Rays are cast one at a time with rtcIntersect1; an intersection filter on the geometry
//     rejects the source triangle, so Embree goes on to the next surface. Under
//     HitRule::SkipSameFacing it also rejects triangles whose geometric normal does not face
//     away from the origin normal (with RayCaster.h's tolerance): clear cases (|cos| > 1e-2)
//     are decided on Embree's own Ng (single precision, right-hand rule of the vertex order
//     like VTK's polygon normal, no memory access); hits near 90 degrees use a
//     double-precision normal table, so the decisions are the same as BruteForceRayCaster's.
//     Under HitRule::FirstHitLeaving (the default) the closest hit is tested after the
//     traversal against the double-precision plane (the ray must leave through it).
//   - Embree's single-precision distance is replaced by the double-precision distance to the
//     plane of the hit triangle (original coordinates), so results agree with
//     BruteForceRayCaster to ~1e-12 relative and scale exactly with the mesh. When the ray is
//     nearly parallel to that plane (ill-conditioned) Embree's distance is kept.
//
// Threading: construction builds the BVH (Embree uses its own TBB threads for that); casting
// is const and thread-safe.
#pragma once

#include "RayCasting/RayCaster.h"

#include <array>
#include <memory>
#include <optional>

namespace shapediameter
{

/// Embree's BVH build quality. Medium is the default: High's longer build costs about what
/// its faster traversal saves for one SDF pass, a wash; Low builds fastest but traverses
/// slower (the skeleton's volume tests, dominated by the build, use it). Robust costs
/// traversal time. Measurements: docs/performance.md, "Design measurements".
enum class EmbreeBuildQuality
{
  Low,
  Medium,
  High
};

struct EmbreeRayCasterOptions
{
  EmbreeBuildQuality BuildQuality = EmbreeBuildQuality::Medium;
  /// RTC_SCENE_FLAG_ROBUST: Embree avoids optimisations that lose accuracy (slower).
  bool Robust = false;
  /// RTC_SCENE_FLAG_COMPACT: a smaller BVH (its leaves index the vertices instead of holding
  /// copies) that traverses slower. Hits are the same. For a volume that answers few rays: the
  /// skeleton's BVH at 832k faces 114 -> 78 MB.
  bool Compact = false;
  /// The point the vertices are translated by before their conversion to float; by default
  /// the centre of their bounding box. Casters of the pieces of one mesh given that mesh's
  /// centre hold its very single-precision triangles, so CastRaysWithOrder's answers merge to
  /// those of one caster of the whole mesh.
  std::optional<std::array<double, 3>> Centre;
};

class EmbreeRayCaster final : public RayCaster
{
public:
  /// Copies the mesh and builds the BVH. Throws Error on a non-finite coordinate, a
  /// vertex index out of range, more than 2^32 - 1 points, or an Embree failure.
  EmbreeRayCaster(const PointsView& points, const TrianglesView& triangles,
    const EmbreeRayCasterOptions& options = EmbreeRayCasterOptions());
  /// The same, releasing the caller's mesh once it is copied and before the BVH is built, the
  /// moment the caster's memory peaks (the skeleton's volume on the process that holds the
  /// whole surface of a distributed run).
  EmbreeRayCaster(PointMatrix&& points, TriangleMatrix&& triangles,
    const EmbreeRayCasterOptions& options = EmbreeRayCasterOptions());
  ~EmbreeRayCaster() override;

  double ClosestValidHit(const RayOrigin& origin, const double direction[3]) const override;
  void CastCone(const RayOrigin& origin, const double* directions, std::size_t count,
    double* outDistances) const override;
  /// CastRays, giving also per ray Embree's single-precision distance of the closest hit it
  /// kept before judging it (+inf: none), the order in which Embree ranks hits. Several casters
  /// of disjoint or overlapping pieces of one mesh (with its Centre) answer a ray as the whole
  /// mesh's caster does when the answer of the lowest order is taken (a tie, two triangles at
  /// the very same single-precision distance, is the one case where they may differ).
  void CastRaysWithOrder(const std::vector<Ray>& rays, std::vector<double>& outDistances,
    std::vector<float>& outOrder, const ParallelFor& parallelFor) const;
  std::size_t GetNumberOfTriangles() const override;
  double GetBoundingBoxDiagonal() const override;

private:
  void CopyMesh(const PointsView& points, const TrianglesView& triangles, const EmbreeRayCasterOptions& options);
  void BuildBvh(const EmbreeRayCasterOptions& options);
  void Cast(const RayOrigin& origin, const double* directions, std::size_t count, double* outDistances,
    float* outOrder) const;

  struct Internals;
  std::unique_ptr<Internals> Impl;
};

} // namespace shapediameter
