// SPDX-License-Identifier: BSD-3-Clause
// Tests of the RayCaster contract (RayCaster.h) for EmbreeRayCaster and BruteForceRayCaster,
// and of their agreement ray by ray.
#include "RayCasting/BruteForceRayCaster.h"
#include "RayCasting/ConeSampling.h"
#include "RayCasting/EmbreeRayCaster.h"
#include "TestShapes.h"
#include "SDF/ShapeDiameter.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <limits>
#include <memory>
#include <vector>

namespace
{
using namespace shapediameter;
using testshapes::TestMesh;

const double kInfinity = std::numeric_limits<double>::infinity();
constexpr double kPi = 3.14159265358979323846;

enum class CasterKind
{
  Embree,
  BruteForce
};

std::unique_ptr<RayCaster> MakeCaster(CasterKind kind, const TestMesh& mesh)
{
  if (kind == CasterKind::Embree)
  {
    return std::make_unique<EmbreeRayCaster>(mesh.Points, mesh.Triangles);
  }
  return std::make_unique<BruteForceRayCaster>(mesh.Points, mesh.Triangles);
}

/// An origin under the rule the paper's sentence reads literally (skip same-facing hits), which
/// most contract tests below pin; FirstHitLeaving has its own tests.
RayOrigin Origin(double x, double y, double z, double nx, double ny, double nz,
  std::int64_t source = -1, double minDistance = 0, HitRule rule = HitRule::SkipSameFacing)
{
  RayOrigin origin;
  origin.Rule = rule;
  origin.Point[0] = x, origin.Point[1] = y, origin.Point[2] = z;
  origin.Normal[0] = nx, origin.Normal[1] = ny, origin.Normal[2] = nz;
  origin.SourceTriangle = source;
  origin.MinDistance = minDistance;
  return origin;
}

/// Three large triangles stacked along z at z = 1 (normal +z), z = 2 (normal -z) and
/// z = 3 (normal -z), each covering the point (0, 0).
TestMesh StackedTriangles()
{
  TestMesh mesh;
  mesh.Points.resize(9, 3);
  mesh.Triangles.resize(3, 3);
  for (int layer = 0; layer < 3; ++layer)
  {
    const double z = layer + 1;
    mesh.Points.row(3 * layer + 0) << -1, -1, z;
    mesh.Points.row(3 * layer + 1) << 2, -1, z;
    mesh.Points.row(3 * layer + 2) << -1, 2, z;
    if (layer == 0)
    {
      mesh.Triangles.row(layer) << 0, 1, 2; // counter-clockwise from +z: normal +z
    }
    else
    {
      mesh.Triangles.row(layer) << 3 * layer, 3 * layer + 2, 3 * layer + 1; // normal -z
    }
  }
  return mesh;
}

class RayCasterContract : public ::testing::TestWithParam<CasterKind>
{
};

TEST_P(RayCasterContract, SkipsTrianglesFacingTheOriginNormal)
{
  const TestMesh mesh = StackedTriangles();
  const auto caster = MakeCaster(GetParam(), mesh);
  const double up[3] = { 0, 0, 1 };
  // Origin normal -z (like the bottom of a body): the z = 1 triangle faces +z, opposite to
  // the origin normal -> valid.
  EXPECT_DOUBLE_EQ(caster->ClosestValidHit(Origin(0, 0, 0, 0, 0, -1), up), 1.0);
  // Origin normal +z: the z = 1 triangle faces the same way and is transparent; the z = 2
  // triangle faces -z -> valid at distance 2.
  EXPECT_DOUBLE_EQ(caster->ClosestValidHit(Origin(0, 0, 0, 0, 0, 1), up), 2.0);
  // A tilted origin normal: only the sign of the dot product matters.
  EXPECT_DOUBLE_EQ(caster->ClosestValidHit(Origin(0, 0, 0, 5, 0, 0.01), up), 2.0);
  // Exactly perpendicular (90 degrees) counts as "same direction": rejected everywhere.
  EXPECT_EQ(caster->ClosestValidHit(Origin(0, 0, 0, 1, 0, 0), up), kInfinity);
  // ... and so does anything within kPerpendicularTolerance of 90 degrees (rounding noise).
  EXPECT_EQ(caster->ClosestValidHit(Origin(0, 0, 0, 1, 0, -1e-8), up), kInfinity);
  EXPECT_DOUBLE_EQ(caster->ClosestValidHit(Origin(0, 0, 0, 1, 0, -1e-4), up), 1.0);
  // Going away from everything.
  const double down[3] = { 0, 0, -1 };
  EXPECT_EQ(caster->ClosestValidHit(Origin(0, 0, 0, 0, 0, 1), down), kInfinity);
  // Distances are ray parameters: a direction of length 2 halves them.
  const double up2[3] = { 0, 0, 2 };
  EXPECT_DOUBLE_EQ(caster->ClosestValidHit(Origin(0, 0, 0, 0, 0, 1), up2), 1.0);
}

TEST_P(RayCasterContract, SkipsTheSourceTriangleAndHitsBeforeMinDistance)
{
  const TestMesh mesh = StackedTriangles();
  const auto caster = MakeCaster(GetParam(), mesh);
  const double up[3] = { 0, 0, 1 };
  // Source triangle 1 (z = 2) is ignored: next is z = 3.
  EXPECT_DOUBLE_EQ(caster->ClosestValidHit(Origin(0, 0, 0, 0, 0, 1, 1), up), 3.0);
  // An origin lying on triangle 1 without a source index but with MinDistance.
  EXPECT_DOUBLE_EQ(caster->ClosestValidHit(Origin(0, 0, 2, 0, 0, 1, -1, 1e-6), up), 1.0);
}

TEST_P(RayCasterContract, ZeroAreaTrianglesAreNeverHit)
{
  TestMesh mesh = StackedTriangles();
  // Replace the z = 2 triangle by a collinear one lying on the ray and a point triangle.
  mesh.Points.conservativeResize(12, 3);
  mesh.Points.row(9) << 0, 0, 1.5;
  mesh.Points.row(10) << 0, 0, 2.5;
  mesh.Points.row(11) << 0, 0, 2.0;
  mesh.Triangles.row(1) << 9, 10, 11;
  mesh.Triangles.conservativeResize(4, 3);
  mesh.Triangles.row(3) << 11, 11, 11;
  // The same two kinds just above the z = 3 triangle, for FirstHitLeaving, which judges only the
  // closest hit: a zero-area hit there would drop the ray instead of letting it reach z = 3.
  mesh.Points.conservativeResize(15, 3);
  mesh.Points.row(12) << 0, 0, 3.1;
  mesh.Points.row(13) << 0, 0, 3.4;
  mesh.Points.row(14) << 0, 0, 3.2;
  mesh.Triangles.conservativeResize(6, 3);
  mesh.Triangles.row(4) << 12, 13, 14;
  mesh.Triangles.row(5) << 14, 14, 14;
  const auto caster = MakeCaster(GetParam(), mesh);
  const double up[3] = { 0, 0, 1 };
  EXPECT_DOUBLE_EQ(caster->ClosestValidHit(Origin(0, 0, 0, 0, 0, 1), up), 3.0);
  const double down[3] = { 0, 0, -1 };
  EXPECT_DOUBLE_EQ(
    caster->ClosestValidHit(Origin(0, 0, 3.5, 0, 0, 1, -1, 0, HitRule::FirstHitLeaving), down), 0.5);
}

TEST_P(RayCasterContract, FirstHitLeavingJudgesOnlyTheClosestHit)
{
  TestMesh mesh = StackedTriangles();
  const auto caster = MakeCaster(GetParam(), mesh);
  const double up[3] = { 0, 0, 1 };
  const double down[3] = { 0, 0, -1 };
  const auto first = [](double z, double nz, std::int64_t source = -1)
  { return Origin(0, 0, z, 0, 0, nz, source, 0, HitRule::FirstHitLeaving); };
  // The z = 1 triangle faces +z: going up, the ray leaves through it, whatever the origin normal.
  EXPECT_DOUBLE_EQ(caster->ClosestValidHit(first(0, 1), up), 1.0);
  EXPECT_DOUBLE_EQ(caster->ClosestValidHit(first(0, -1), up), 1.0);
  // With z = 1 the source, the closest hit is z = 2 (facing -z): the ray enters there, so it has
  // no valid hit; it does not go on to z = 3.
  EXPECT_EQ(caster->ClosestValidHit(first(0, 1, 0), up), kInfinity);
  // Going down from z = 2.5 the first hit is z = 2 (normal -z, along the ray): valid at 0.5.
  EXPECT_DOUBLE_EQ(caster->ClosestValidHit(first(2.5, 1), down), 0.5);
  // From z = 3.5 down, the first hit z = 3 faces -z: leaving, valid at 0.5; with z = 3 the
  // source, z = 2 is next (leaving as well): 1.5.
  EXPECT_DOUBLE_EQ(caster->ClosestValidHit(first(3.5, 1), down), 0.5);
  EXPECT_DOUBLE_EQ(caster->ClosestValidHit(first(3.5, 1, 2), down), 1.5);
}

TEST_P(RayCasterContract, NonFiniteRaysMissAndEmptyMeshesNeverHit)
{
  const TestMesh mesh = StackedTriangles();
  const auto caster = MakeCaster(GetParam(), mesh);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double up[3] = { 0, 0, 1 };
  const double bad[3] = { 0, nan, 1 };
  const double zero[3] = { 0, 0, 0 };
  EXPECT_EQ(caster->ClosestValidHit(Origin(0, nan, 0, 0, 0, 1), up), kInfinity);
  EXPECT_EQ(caster->ClosestValidHit(Origin(0, 0, 0, 0, nan, 1), up), kInfinity);
  EXPECT_EQ(caster->ClosestValidHit(Origin(0, 0, 0, 0, 0, 1), bad), kInfinity);
  EXPECT_EQ(caster->ClosestValidHit(Origin(0, 0, 0, 0, 0, 1), zero), kInfinity);

  TestMesh empty;
  empty.Points.resize(0, 3);
  empty.Triangles.resize(0, 3);
  const auto emptyCaster = MakeCaster(GetParam(), empty);
  EXPECT_EQ(emptyCaster->GetNumberOfTriangles(), 0u);
  EXPECT_EQ(emptyCaster->GetBoundingBoxDiagonal(), 0.0);
  EXPECT_EQ(emptyCaster->ClosestValidHit(Origin(0, 0, 0, 0, 0, 1), up), kInfinity);
}

TEST_P(RayCasterContract, RejectsBadMeshes)
{
  TestMesh mesh = StackedTriangles();
  mesh.Triangles(2, 1) = 9;
  EXPECT_THROW(MakeCaster(GetParam(), mesh), Error);
  mesh.Triangles(2, 1) = -1;
  EXPECT_THROW(MakeCaster(GetParam(), mesh), Error);
  mesh = StackedTriangles();
  mesh.Points(4, 2) = std::numeric_limits<double>::infinity();
  EXPECT_THROW(MakeCaster(GetParam(), mesh), Error);
}

TEST_P(RayCasterContract, CastConeMatchesSingleRays)
{
  const TestMesh mesh = testshapes::MakeIcosphere(8, 1.5);
  const auto caster = MakeCaster(GetParam(), mesh);
  const RayOrigins origins = MakeFaceOrigins(mesh.Points, mesh.Triangles);
  const ConePattern pattern = MakeConePattern(30, 120);
  std::vector<double> directions(90), batch(30);
  for (const HitRule rule : { HitRule::SkipSameFacing, HitRule::FirstHitLeaving })
  {
    for (Eigen::Index f = 0; f < origins.Points.rows(); f += 17)
    {
      const RayOrigin origin = Origin(origins.Points(f, 0), origins.Points(f, 1), origins.Points(f, 2),
        origins.Normals(f, 0), origins.Normals(f, 1), origins.Normals(f, 2), f, 0, rule);
      const double axis[3] = { -origin.Normal[0], -origin.Normal[1], -origin.Normal[2] };
      double x[3], y[3];
      MakeConeFrame(axis, origins.FirstAxes.row(f).data(), x, y);
      OrientConePattern(pattern, axis, x, y, directions.data());
      caster->CastCone(origin, directions.data(), 30, batch.data());
      for (int i = 0; i < 30; ++i)
      {
        EXPECT_EQ(batch[i], caster->ClosestValidHit(origin, directions.data() + 3 * i));
        // On a sphere a ray at angle theta from the inward normal lands where the normal makes
        // 180 - 2 theta degrees with the origin normal: SkipSameFacing keeps it only below 45
        // degrees; inside a convex body every first hit is where the ray leaves, so
        // FirstHitLeaving keeps every ray.
        const double degrees = pattern.AnglesToAxis[static_cast<std::size_t>(i)] * 180 / kPi;
        if (degrees < 38 || rule == HitRule::FirstHitLeaving)
        {
          EXPECT_TRUE(std::isfinite(batch[i])) << degrees;
        }
        else if (degrees > 52)
        {
          EXPECT_EQ(batch[i], kInfinity) << degrees;
        }
      }
    }
  }
}

TEST_P(RayCasterContract, SegmentCrossesSurfaceSeesEverySurfaceBetweenTheEnds)
{
  // Stacked triangles: z = 1 faces +z, z = 2 and z = 3 face -z.
  const auto stacked = MakeCaster(GetParam(), StackedTriangles());
  const auto crosses = [](const RayCaster& caster, double z0, double z1) {
    return SegmentCrossesSurface(caster, Eigen::Vector3d(0, 0, z0), Eigen::Vector3d(0, 0, z1));
  };
  EXPECT_TRUE(crosses(*stacked, 0.5, 1.5));  // left through z = 1
  EXPECT_TRUE(crosses(*stacked, 1.5, 2.5));  // entered through z = 2 (the closest hit enters)
  EXPECT_TRUE(crosses(*stacked, 2.5, 1.5));  // the same segment from the other end
  EXPECT_TRUE(crosses(*stacked, 0.5, 3.5));  // three surfaces
  EXPECT_FALSE(crosses(*stacked, 1.2, 1.8)); // between two surfaces
  EXPECT_FALSE(crosses(*stacked, 3.5, 4.5)); // beyond all of them
  EXPECT_FALSE(crosses(*stacked, 1.5, 1.5)); // zero length

  // Two unit spheres whose volumes overlap (centres 1.5 apart), as posed characters'
  // parts interpenetrate: the union of the volumes does not join them.
  const TestMesh first = testshapes::MakeIcosphere(8, 1.0);
  const TestMesh second = testshapes::Transformed(
    testshapes::MakeIcosphere(8, 1.0), Eigen::Matrix3d::Identity(), Eigen::Vector3d(1.5, 0, 0));
  const auto spheres = MakeCaster(GetParam(), testshapes::Concatenate(first, second));
  EXPECT_FALSE(SegmentCrossesSurface(*spheres, Eigen::Vector3d(-0.5, 0, 0), Eigen::Vector3d(0.3, 0.2, 0)));
  // From the first centre into the overlap: the second sphere's surface lies in between.
  EXPECT_TRUE(SegmentCrossesSurface(*spheres, Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.75, 0, 0)));
  EXPECT_TRUE(SegmentCrossesSurface(*spheres, Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1.5, 0, 0)));
  // Both ends outside, the segment through the first sphere.
  EXPECT_TRUE(SegmentCrossesSurface(*spheres, Eigen::Vector3d(0, -2, 0), Eigen::Vector3d(0, 2, 0)));
  EXPECT_FALSE(SegmentCrossesSurface(*spheres, Eigen::Vector3d(0, -2, 0), Eigen::Vector3d(0, -3, 0)));
}

TEST_P(RayCasterContract, SegmentBatchesAnswerEachSegment)
{
  // The cases above in one batch, in an order that mixes segments needing one ray, two rays
  // (the closest hit enters) and none (zero length): each answer lands on its own segment.
  const auto stacked = MakeCaster(GetParam(), StackedTriangles());
  const auto along = [](double z0, double z1) { return Segment{ Eigen::Vector3d(0, 0, z0), Eigen::Vector3d(0, 0, z1) }; };
  const std::vector<Segment> segments{ along(1.2, 1.8), along(1.5, 2.5), along(1.5, 1.5), along(0.5, 1.5),
    along(3.5, 4.5), along(2.5, 1.5), along(0.5, 3.5), along(1.8, 1.2) };
  const std::vector<char> expected{ 0, 1, 0, 1, 0, 1, 1, 0 };
  EXPECT_EQ(SegmentsCrossSurface(*stacked, segments, ThreadedFor(3)), expected);
  EXPECT_TRUE(SegmentsCrossSurface(*stacked, {}, SerialFor).empty());
}

TEST_P(RayCasterContract, CastRaysMatchesSingleRaysWhateverTheThreads)
{
  const TestMesh mesh = testshapes::Concatenate(testshapes::MakeIcosphere(6, 1.0),
    testshapes::Transformed(testshapes::MakeIcosphere(6, 1.0), Eigen::Matrix3d::Identity(), Eigen::Vector3d(1.5, 0, 0)));
  const auto caster = MakeCaster(GetParam(), mesh);
  std::vector<Ray> rays;
  for (int i = 0; i < 700; ++i) // more than the 512 rays CastRays casts serially
  {
    const double angle = 0.1 * i;
    const Eigen::Vector3d from(0.004 * (i % 600) - 0.5, 0.3 * std::sin(angle), 0.2 * std::cos(3 * angle));
    const Eigen::Vector3d direction = Eigen::Vector3d(std::cos(angle), std::sin(angle), 0.3 * std::cos(2 * angle)).normalized();
    rays.push_back(ExitRay(from, direction, i % 3 == 0 ? 0.8 : kInfinity));
    rays.back().Origin.Rule = i % 2 == 0 ? HitRule::FirstHitLeaving : HitRule::SkipSameFacing;
  }
  std::vector<double> serial, threaded;
  caster->CastRays(rays, serial, SerialFor);
  caster->CastRays(rays, threaded, ThreadedFor(3));
  ASSERT_EQ(serial.size(), rays.size());
  int hits = 0;
  for (std::size_t i = 0; i < rays.size(); ++i)
  {
    EXPECT_EQ(serial[i], caster->ClosestValidHit(rays[i].Origin, rays[i].Direction)) << i;
    EXPECT_EQ(threaded[i], serial[i]) << i;
    hits += std::isfinite(serial[i]) ? 1 : 0;
  }
  EXPECT_GT(hits, 250);
  EXPECT_LT(hits, 650); // some rays stop short (MaxDistance) or enter first
  RecordProperty("Hits", hits);
}

TEST_P(RayCasterContract, RaysRejectedByABoxNeverHitItsTriangles)
{
  // One piece of a larger mesh (a box, whose faces fill its bounding box's, far from the
  // origin, as a process's own triangles are): rays from around it in every direction, some
  // along an axis, some stopping short; every ray RayMayMeetBox rejects has no hit, and the
  // test rejects most of the rays that cannot reach the piece.
  const TestMesh piece = testshapes::Transformed(
    testshapes::MakeBox(Eigen::Vector3d(2, 1.5, 1), 4), Eigen::Matrix3d::Identity(), Eigen::Vector3d(300, -200, 50));
  const auto caster = MakeCaster(GetParam(), piece);
  AxisBox box;
  EXPECT_TRUE(box.Empty());
  for (Eigen::Index p = 0; p < piece.Points.rows(); ++p)
  {
    box.Extend(piece.Points.row(p).transpose());
  }
  ASSERT_FALSE(box.Empty());
  const Eigen::Vector3d centre(301, -199.25, 50.5);
  std::vector<Ray> rays;
  for (int i = 0; i < 2000; ++i)
  {
    const double angle = 0.37 * i;
    const Eigen::Vector3d from = centre + Eigen::Vector3d(3 * std::cos(angle), 2.5 * std::sin(1.3 * angle), 2 * std::cos(0.7 * angle));
    Eigen::Vector3d direction = Eigen::Vector3d(std::cos(2.1 * angle), std::sin(0.9 * angle), std::cos(1.7 * angle)).normalized();
    if (i % 7 == 0)
    {
      direction = Eigen::Vector3d::Unit(i % 3) * (i % 2 == 0 ? 1 : -1);
    }
    rays.push_back(ExitRay(from, direction, i % 4 == 0 ? 1.0 + 0.001 * (i % 1000) : kInfinity));
    rays.back().Origin.Rule = HitRule::FirstHitLeaving;
  }
  // Every crossing of the surface counts: the closest leaving hit (FirstHitLeaving) or the
  // closest entering one (SkipSameFacing with the direction as the normal).
  std::vector<Ray> entering = rays;
  for (Ray& ray : entering)
  {
    ray.Origin.Rule = HitRule::SkipSameFacing;
  }
  std::vector<double> leavingDistances, enteringDistances;
  caster->CastRays(rays, leavingDistances, SerialFor);
  caster->CastRays(entering, enteringDistances, SerialFor);
  int rejected = 0, misses = 0;
  const double margin = 1e-5 * (2 + 400);
  for (std::size_t i = 0; i < rays.size(); ++i)
  {
    const bool hit = std::isfinite(leavingDistances[i]) || std::isfinite(enteringDistances[i]);
    const bool mayMeet = RayMayMeetBox(rays[i], box, margin);
    misses += hit ? 0 : 1;
    rejected += mayMeet ? 0 : 1;
    if (!mayMeet)
    {
      EXPECT_FALSE(hit) << i;
    }
  }
  EXPECT_GT(rejected, 500);
  EXPECT_GT(rejected, misses / 2);
  RecordProperty("Rejected", rejected);

  // Edges: a ray stopping just before the box is rejected, one reaching it is not; an empty box
  // meets nothing; a non-finite ray is left to the caster.
  const Ray towards = ExitRay(Eigen::Vector3d(290, -199.25, 50.5), Eigen::Vector3d(1, 0, 0), 9.99);
  EXPECT_FALSE(RayMayMeetBox(towards, box, 1e-3));
  EXPECT_TRUE(RayMayMeetBox(ExitRay(Eigen::Vector3d(290, -199.25, 50.5), Eigen::Vector3d(1, 0, 0), 10.01), box, 1e-3));
  EXPECT_FALSE(RayMayMeetBox(ExitRay(Eigen::Vector3d(290, -199.25, 50.5), Eigen::Vector3d(-1, 0, 0), kInfinity), box, 1e-3));
  EXPECT_FALSE(RayMayMeetBox(ExitRay(Eigen::Vector3d(290, -199.25, 51.1), Eigen::Vector3d(1, 0, 0), kInfinity), box, 1e-3));
  EXPECT_TRUE(RayMayMeetBox(ExitRay(Eigen::Vector3d(290, -199.25, 50.9), Eigen::Vector3d(1, 0, 0), kInfinity), box, 1e-3));
  EXPECT_FALSE(RayMayMeetBox(towards, AxisBox{}, 1e-3));
  EXPECT_TRUE(RayMayMeetBox(ExitRay(Eigen::Vector3d(kInfinity, 0, 0), Eigen::Vector3d(1, 0, 0), kInfinity), box, 1e-3));
}

INSTANTIATE_TEST_SUITE_P(BothCasters, RayCasterContract,
  ::testing::Values(CasterKind::Embree, CasterKind::BruteForce),
  [](const ::testing::TestParamInfo<CasterKind>& info) {
    return info.param == CasterKind::Embree ? std::string("Embree") : std::string("BruteForce");
  });

/// Casts the SDF cones of every face of `mesh` (plus the outward cones, which exercise the
/// filter on a closed mesh) with both casters and returns the worst relative difference;
/// counts rays where exactly one caster found a hit.
double WorstRelativeDifference(const TestMesh& mesh, int& hitMismatches, int& hits)
{
  const EmbreeRayCaster embree(mesh.Points, mesh.Triangles);
  const BruteForceRayCaster bruteForce(mesh.Points, mesh.Triangles);
  const RayOrigins origins = MakeFaceOrigins(mesh.Points, mesh.Triangles);
  const ConePattern pattern = MakeConePattern(30, 120);
  std::vector<double> directions(90), fromEmbree(30), fromBruteForce(30);
  double worst = 0;
  hitMismatches = 0;
  hits = 0;
  for (Eigen::Index f = 0; f < origins.Points.rows(); ++f)
  {
    for (const double sign : { 1.0, -1.0 })
    {
      const RayOrigin origin =
        Origin(origins.Points(f, 0), origins.Points(f, 1), origins.Points(f, 2),
          sign * origins.Normals(f, 0), sign * origins.Normals(f, 1), sign * origins.Normals(f, 2), f);
      const double axis[3] = { -origin.Normal[0], -origin.Normal[1], -origin.Normal[2] };
      double x[3], y[3];
      MakeConeFrame(axis, origins.FirstAxes.row(f).data(), x, y);
      OrientConePattern(pattern, axis, x, y, directions.data());
      embree.CastCone(origin, directions.data(), 30, fromEmbree.data());
      bruteForce.CastCone(origin, directions.data(), 30, fromBruteForce.data());
      for (int i = 0; i < 30; ++i)
      {
        const bool embreeHit = std::isfinite(fromEmbree[i]);
        if (embreeHit != std::isfinite(fromBruteForce[i]))
        {
          ++hitMismatches;
        }
        else if (embreeHit)
        {
          ++hits;
          worst = std::max(worst,
            std::abs(fromEmbree[i] - fromBruteForce[i]) / std::abs(fromBruteForce[i]));
        }
      }
    }
  }
  return worst;
}

TEST(RayCasters, EmbreeMatchesBruteForceOnACapsule)
{
  // 2 * 16 * (2 * 6 + 4 - 1) = 480 faces; rays through vertices and edges included.
  const TestMesh mesh = testshapes::MakeCapsule(0.5, 1.0, 16, 6, 4);
  ASSERT_EQ(mesh.Triangles.rows(), 480);
  int mismatches = 0, hits = 0;
  const double worst = WorstRelativeDifference(mesh, mismatches, hits);
  EXPECT_EQ(mismatches, 0);
  // Only rays below ~45 degrees find a valid hit on a round body (see above).
  EXPECT_GT(hits, 480 * 30 / 2);
  EXPECT_LT(worst, 1e-9);
  RecordProperty("WorstRelativeDifference", std::to_string(worst));
}

TEST(RayCasters, EmbreeKeepsDoublePrecisionFarFromTheOrigin)
{
  // A capsule 1e6 away from the origin: float coordinates alone would give ~0.06 errors.
  const TestMesh mesh = testshapes::Transformed(testshapes::MakeCapsule(0.5, 1.0, 12, 4, 3),
    Eigen::Matrix3d::Identity(), Eigen::Vector3d(1e6, -2e6, 3e6));
  int mismatches = 0, hits = 0;
  const double worst = WorstRelativeDifference(mesh, mismatches, hits);
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(hits, 0);
  EXPECT_LT(worst, 1e-6);
}

TEST(RayCasters, EmbreeBuildQualitiesAgree)
{
  const TestMesh mesh = testshapes::MakeIcosphere(6);
  const RayOrigins origins = MakeFaceOrigins(mesh.Points, mesh.Triangles);
  const EmbreeRayCaster medium(mesh.Points, mesh.Triangles);
  EmbreeRayCasterOptions options;
  options.BuildQuality = EmbreeBuildQuality::High;
  options.Robust = true;
  const EmbreeRayCaster high(mesh.Points, mesh.Triangles, options);
  const double direction[3] = { 0.3, -0.2, 0.9 };
  for (Eigen::Index f = 0; f < origins.Points.rows(); ++f)
  {
    const RayOrigin origin = Origin(origins.Points(f, 0), origins.Points(f, 1),
      origins.Points(f, 2), origins.Normals(f, 0), origins.Normals(f, 1), origins.Normals(f, 2), f);
    const double a = medium.ClosestValidHit(origin, direction);
    const double b = high.ClosestValidHit(origin, direction);
    ASSERT_EQ(std::isfinite(a), std::isfinite(b));
    if (std::isfinite(a))
    {
      EXPECT_NEAR(a, b, 1e-9 * a);
    }
  }
}

TEST(RayCasters, EmbreeCompactBvhGivesTheSameHits)
{
  // The skeleton's volume: low quality, compact leaves. Same hit distances, to the bit.
  const TestMesh mesh = testshapes::MakeCapsule(0.5, 1.0, 24, 8, 6);
  const RayOrigins origins = MakeFaceOrigins(mesh.Points, mesh.Triangles);
  EmbreeRayCasterOptions lowOptions;
  lowOptions.BuildQuality = EmbreeBuildQuality::Low;
  const EmbreeRayCaster low(mesh.Points, mesh.Triangles, lowOptions);
  EmbreeRayCasterOptions compactOptions = lowOptions;
  compactOptions.Compact = true;
  const EmbreeRayCaster compact(mesh.Points, mesh.Triangles, compactOptions);
  int hits = 0;
  for (Eigen::Index f = 0; f < origins.Points.rows(); ++f)
  {
    // Inward, tilted off the normal: every face's ray crosses the capsule.
    const double direction[3] = { -origins.Normals(f, 0) + 0.2, -origins.Normals(f, 1), -origins.Normals(f, 2) - 0.1 };
    const RayOrigin origin = Origin(origins.Points(f, 0), origins.Points(f, 1),
      origins.Points(f, 2), origins.Normals(f, 0), origins.Normals(f, 1), origins.Normals(f, 2), f);
    const double a = low.ClosestValidHit(origin, direction);
    const double b = compact.ClosestValidHit(origin, direction);
    ASSERT_EQ(std::isfinite(a), std::isfinite(b)) << "face " << f;
    if (std::isfinite(a))
    {
      ++hits;
      EXPECT_EQ(a, b) << "face " << f;
    }
  }
  EXPECT_GT(hits, 9 * origins.Points.rows() / 10);
}

/// The triangles of `mesh` whose index passes `keep`, with only the points they use.
TestMesh TrianglesWhere(const TestMesh& mesh, const std::function<bool(Eigen::Index)>& keep)
{
  std::vector<Eigen::Index> newIndex(static_cast<std::size_t>(mesh.Points.rows()), -1);
  std::vector<Eigen::Index> kept, usedPoints;
  for (Eigen::Index t = 0; t < mesh.Triangles.rows(); ++t)
  {
    if (!keep(t))
    {
      continue;
    }
    kept.push_back(t);
    for (int c = 0; c < 3; ++c)
    {
      auto& index = newIndex[static_cast<std::size_t>(mesh.Triangles(t, c))];
      if (index < 0)
      {
        index = static_cast<Eigen::Index>(usedPoints.size());
        usedPoints.push_back(mesh.Triangles(t, c));
      }
    }
  }
  TestMesh piece;
  piece.Points.resize(static_cast<Eigen::Index>(usedPoints.size()), 3);
  for (std::size_t p = 0; p < usedPoints.size(); ++p)
  {
    piece.Points.row(static_cast<Eigen::Index>(p)) = mesh.Points.row(usedPoints[p]);
  }
  piece.Triangles.resize(static_cast<Eigen::Index>(kept.size()), 3);
  for (std::size_t k = 0; k < kept.size(); ++k)
  {
    for (int c = 0; c < 3; ++c)
    {
      piece.Triangles(static_cast<Eigen::Index>(k), c) = newIndex[static_cast<std::size_t>(mesh.Triangles(kept[k], c))];
    }
  }
  return piece;
}

TEST(RayCasters, EmbreePiecesMergedByOrderAnswerAsTheWholeMesh)
{
  // The skeleton's volume over processes: each process casts against its own triangles (with
  // the whole mesh's centre), and the answer of the lowest order is the whole mesh's. Pieces
  // are slabs across x (as the reader's spatial pieces); some triangles in two pieces.
  // Far from the origin, where a piece's own centre would round its vertices differently.
  const TestMesh mesh = testshapes::Transformed(testshapes::Concatenate(testshapes::MakeIcosphere(10, 1.0),
                                                  testshapes::MakeCapsule(0.3, 2.0, 20, 6, 8)),
    Eigen::Matrix3d::Identity(), Eigen::Vector3d(1e4, 3e3, -2e4));
  EmbreeRayCasterOptions options;
  options.BuildQuality = EmbreeBuildQuality::Low;
  options.Compact = true;
  const EmbreeRayCaster whole(mesh.Points, mesh.Triangles, options);
  const Eigen::RowVector3d wholeCentre = 0.5 * (mesh.Points.colwise().maxCoeff() + mesh.Points.colwise().minCoeff());
  options.Centre = { wholeCentre(0), wholeCentre(1), wholeCentre(2) };
  std::vector<std::unique_ptr<EmbreeRayCaster>> pieces;
  const double left = mesh.Points.col(0).minCoeff(), width = mesh.Points.col(0).maxCoeff() - left;
  for (Eigen::Index piece = 0; piece < 3; ++piece)
  {
    const TestMesh own = TrianglesWhere(mesh, [&](Eigen::Index t) {
      const double x = mesh.Points(mesh.Triangles(t, 0), 0);
      return static_cast<Eigen::Index>(std::min(2.0, 3 * (x - left) / width)) == piece || t % 7 == piece;
    });
    pieces.push_back(std::make_unique<EmbreeRayCaster>(own.Points, own.Triangles, options));
  }
  std::vector<Ray> rays;
  const Eigen::Vector3d centre(1e4, 3e3, -2e4);
  for (int i = 0; i < 2000; ++i)
  {
    const double angle = 0.37 * i;
    const Eigen::Vector3d from = centre + Eigen::Vector3d(0.002 * (i % 700) - 0.7, 0.4 * std::sin(1.3 * angle), 0.4 * std::cos(angle));
    const Eigen::Vector3d direction =
      Eigen::Vector3d(std::cos(angle), std::sin(angle) * std::cos(0.5 * angle), std::sin(0.7 * angle)).normalized();
    rays.push_back(ExitRay(from, direction, i % 5 == 0 ? 0.5 : kInfinity));
    rays.back().Origin.Rule = i % 2 == 0 ? HitRule::FirstHitLeaving : HitRule::SkipSameFacing;
  }
  std::vector<double> expected, distances;
  whole.CastRays(rays, expected, ThreadedFor(2));
  std::vector<double> merged(rays.size(), kInfinity);
  std::vector<float> lowest(rays.size(), std::numeric_limits<float>::infinity()), order;
  for (const auto& piece : pieces)
  {
    piece->CastRaysWithOrder(rays, distances, order, ThreadedFor(2));
    for (std::size_t i = 0; i < rays.size(); ++i)
    {
      if (order[i] < lowest[i])
      {
        lowest[i] = order[i];
        merged[i] = distances[i];
      }
    }
  }
  int hits = 0, entering = 0;
  for (std::size_t i = 0; i < rays.size(); ++i)
  {
    EXPECT_EQ(merged[i], expected[i]) << "ray " << i;
    hits += std::isfinite(expected[i]) ? 1 : 0;
    entering += std::isfinite(lowest[i]) && !std::isfinite(expected[i]) ? 1 : 0;
  }
  EXPECT_GT(hits, 800);
  EXPECT_GT(entering, 50); // first hits that enter (FirstHitLeaving) or only skipped ones
}

TEST(RayCasters, MaxDistanceStopsTheSearchForBothCasters)
{
  // From the centre of a unit sphere every ray leaves about 1 away: found within 1.5, not
  // within 0.9; NaN finds nothing. Embree and the brute-force caster agree.
  const TestMesh sphere = testshapes::MakeSphere(1.0, 48, 24);
  const EmbreeRayCaster embree(sphere.Points, sphere.Triangles);
  const BruteForceRayCaster brute(sphere.Points, sphere.Triangles);
  const double direction[3] = { 0.3, -0.5, 0.8 };
  for (const RayCaster* caster : { static_cast<const RayCaster*>(&embree), static_cast<const RayCaster*>(&brute) })
  {
    RayOrigin origin = Origin(0, 0, 0, -0.3, 0.5, -0.8, -1);
    const double unlimited = caster->ClosestValidHit(origin, direction);
    ASSERT_NEAR(unlimited, 1.0, 0.01);
    origin.MaxDistance = 1.5;
    EXPECT_EQ(caster->ClosestValidHit(origin, direction), unlimited);
    origin.MaxDistance = 0.9;
    EXPECT_EQ(caster->ClosestValidHit(origin, direction), std::numeric_limits<double>::infinity());
    origin.MaxDistance = std::numeric_limits<double>::quiet_NaN();
    EXPECT_EQ(caster->ClosestValidHit(origin, direction), std::numeric_limits<double>::infinity());
  }
}

} // namespace
