// SPDX-License-Identifier: BSD-3-Clause
// Step 3 of the skeleton (SkeletonSegments.h) through ComputeSkeleton: shapes whose medial
// curve is one curve (capsule with exact, noisy and ray-cast SDF, prolate spheroid, torus)
// give one fitted poly-segment along it.
#include "Skeleton/Skeleton.h"
#include "Skeleton/SkeletonTestSupport.h"
#include "TestShapes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <tuple>

namespace
{

using namespace shapediameter;
using namespace shapediameter::testshapes;
using namespace shapediameter::skeletontests;

TEST(Skeleton, CapsuleIsItsAxis)
{
  // Cylinder radius r = 1, cap centres at z = -4 and z = +4: the medial curve is that segment,
  // and step 7b (TipReach 1) carries both ends on to the caps' tips at z = -5 and +5.
  const TestMesh capsule = MakeCapsule(1.0, 4.0);
  const SkeletonResult result = RunSkeleton(capsule);
  ExpectWellFormed(result, capsule.Faces());
  ExpectStraightSkeleton(result, { 0, 0, -5 }, { 0, 0, 5 }, 0.05, 0.02);
  // Each cylinder face is linked to a node at its own height.
  for (Eigen::Index f = 0; f < capsule.Faces(); ++f)
  {
    double z = 0.0;
    for (int c = 0; c < 3; ++c)
    {
      z += capsule.Points(capsule.Triangles(f, c), 2) / 3.0;
    }
    if (std::abs(z) < 3.5)
    {
      EXPECT_NEAR(result.NodePositions(result.FaceNodeId[f], 2), z, 0.5);
    }
  }
}

TEST(Skeleton, CapsuleEndsFollowTipReach)
{
  // TipReach 0: the medial axis alone, carried on by step 4b to the cap centres (z = +-4);
  // TipReach 0.5: half way from them to the tips (z = +-4.5).
  const TestMesh capsule = MakeCapsule(1.0, 4.0);
  for (const auto& [reach, end, lengthTolerance] :
    { std::tuple{ 0.0, 4.0, 0.10 }, std::tuple{ 0.5, 4.5, 0.03 } })
  {
    SkeletonOptions options;
    options.LeafExtension.TipReach = reach;
    const SkeletonResult result = RunSkeleton(capsule, options);
    ExpectWellFormed(result, capsule.Faces());
    ExpectStraightSkeleton(result, { 0, 0, -end }, { 0, 0, end }, 0.05, lengthTolerance);
  }
}

TEST(Skeleton, ScaledCapsuleScalesItsTips)
{
  // The same capsule scaled by 10 (SDF too): the tips at z = -50 and +50.
  TestMesh capsule = MakeCapsule(1.0, 4.0);
  capsule.Points *= 10.0;
  for (double& sdf : capsule.Sdf)
  {
    sdf *= 10.0;
  }
  const SkeletonResult result = RunSkeleton(capsule);
  ExpectWellFormed(result, capsule.Faces());
  ExpectStraightSkeleton(result, { 0, 0, -50 }, { 0, 0, 50 }, 0.5, 0.02);
}

TEST(Skeleton, CapsuleWithNoisySdf)
{
  // +-15 % noise on every face's SDF scatters P by up to 0.15 r across the axis.
  TestMesh capsule = MakeCapsule(1.0, 4.0);
  AddSdfNoise(capsule, 0.15);
  const SkeletonResult result = RunSkeleton(capsule);
  ExpectWellFormed(result, capsule.Faces());
  ExpectStraightSkeleton(result, { 0, 0, -5 }, { 0, 0, 5 }, 0.05, 0.10);
}

TEST(Skeleton, CapsuleWithRayCastSdf)
{
  // A coarse capsule with a brute-force cone SDF: shorter diameters near the caps, noise from
  // the facets. The skeleton stays on the axis and reaches the tips (step 7b).
  TestMesh capsule = MakeCapsule(1.0, 4.0, 24, 6, 16);
  capsule.Sdf = RayCastSdf(capsule);
  const SkeletonResult result = RunSkeleton(capsule);
  ExpectWellFormed(result, capsule.Faces());
  ExpectStraightSkeleton(result, { 0, 0, -5 }, { 0, 0, 5 }, 0.05, 0.10);
}

TEST(Skeleton, ProlateSpheroidIsItsMedialSegment)
{
  // a = 5, b = 1: medial segment |z| <= a - b^2/a = 4.8 (length 9.6). Near the tips the SDF
  // vanishes, so the skeleton may stop short: 10 % of the length is allowed.
  const TestMesh spheroid = MakeProlateSpheroid(5.0, 1.0);
  const SkeletonResult result = RunSkeleton(spheroid);
  ExpectWellFormed(result, spheroid.Faces());
  ExpectStraightSkeleton(result, { 0, 0, -4.8 }, { 0, 0, 4.8 }, 0.05, 0.10);
}

TEST(Skeleton, TorusFollowsItsCoreCircle)
{
  const double R = 6.0;
  const double r = 1.0;
  const TestMesh torus = MakeTorus(R, r);
  const SkeletonResult result = RunSkeleton(torus);
  ExpectWellFormed(result, torus.Faces());
  double worst = 0.0;
  for (Eigen::Index n = 0; n < result.NodePositions.rows(); ++n)
  {
    const Eigen::Vector3d p = result.NodePositions.row(n).transpose();
    const double planar = std::hypot(p.x(), p.y());
    worst = std::max(worst, std::hypot(planar - R, p.z()));
  }
  EXPECT_LE(worst, 0.05 * r);
  const GraphSummary graph = Summarise(result);
  EXPECT_EQ(graph.Components, 1u);
  // A tree: the loop stays open, by less than two radii.
  EXPECT_GT(graph.Length, 2.0 * Pi * R - 2.0 * r);
  EXPECT_LT(graph.Length, 2.0 * Pi * R * 1.02);
  EXPECT_EQ(result.BoneLength.size(), 1u) << "an open loop is one branch";
}

} // namespace
