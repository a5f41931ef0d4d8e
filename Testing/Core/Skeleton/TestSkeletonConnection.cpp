// SPDX-License-Identifier: BSD-3-Clause
// Step 4 of the skeleton (SkeletonConnection.h) through ComputeSkeleton: segments joined into
// one tree per component (tripod, star of eight, cross: one junction), separate components
// give separate trees, a blob one node; step 2's sheet factors on a plate and a tube.
#include "RayCasting/EmbreeRayCaster.h"
#include "Skeleton/Skeleton.h"
#include "Skeleton/SkeletonConnection.h"
#include "Skeleton/SkeletonTestSupport.h"
#include "TestShapes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>

namespace
{

using namespace shapediameter;
using namespace shapediameter::testshapes;
using namespace shapediameter::skeletontests;

/// Three branches from the caps' tips (one radius beyond the cap centres: step 7b) meeting in
/// one junction near the origin. Branch ends must lie within endTolerance of the tips.
void ExpectTripodSkeleton(const TestMesh& tripod, double length, double r, double endTolerance)
{
  const SkeletonResult result = RunSkeleton(tripod);
  ExpectWellFormed(result, tripod.Faces());
  const GraphSummary graph = Summarise(result);
  EXPECT_EQ(graph.Components, 1u);
  EXPECT_EQ(graph.CountDegree(1), 3u) << "three branch ends";
  std::size_t junctions = 0;
  for (Eigen::Index n = 0; n < result.NodePositions.rows(); ++n)
  {
    if (graph.Degree[n] >= 3)
    {
      ++junctions;
      EXPECT_LE(result.NodePositions.row(n).norm(), r) << "junction away from the centre";
    }
  }
  EXPECT_EQ(junctions, 1u);
  // Every node near one of the three axes, every branch end near a tip.
  const std::vector<Arm> arms = TripodArms(length, r);
  std::set<std::size_t> armsReached;
  for (Eigen::Index n = 0; n < result.NodePositions.rows(); ++n)
  {
    const Eigen::Vector3d p = result.NodePositions.row(n).transpose();
    double nearest = std::numeric_limits<double>::infinity();
    for (const Arm& arm : arms)
    {
      nearest = std::min(nearest, SegmentDistance(p, Eigen::Vector3d::Zero(), (arm.Length + r) * arm.Direction));
    }
    EXPECT_LE(nearest, 0.25 * r);
    if (graph.Degree[n] == 1)
    {
      for (std::size_t a = 0; a < arms.size(); ++a)
      {
        if ((p - (arms[a].Length + r) * arms[a].Direction).norm() < endTolerance)
        {
          armsReached.insert(a);
        }
      }
    }
  }
  EXPECT_EQ(armsReached.size(), 3u);
  // Three bones, one per arm, each holding the faces of its arm (beyond 2 r from the centre).
  EXPECT_EQ(result.BoneLength.size(), 3u);
  std::vector<std::map<std::int64_t, std::size_t>> armBones(arms.size());
  for (Eigen::Index f = 0; f < tripod.Faces(); ++f)
  {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int c = 0; c < 3; ++c)
    {
      centroid += tripod.Points.row(tripod.Triangles(f, c)).transpose() / 3.0;
    }
    for (std::size_t a = 0; a < arms.size(); ++a)
    {
      if (centroid.dot(arms[a].Direction) > 2.0 * r &&
        SegmentDistance(centroid, Eigen::Vector3d::Zero(), arms[a].Length * arms[a].Direction) < 1.5 * r)
      {
        ++armBones[a][result.FaceBoneId[f]];
      }
    }
  }
  std::set<std::int64_t> distinct;
  for (const auto& bones : armBones)
  {
    ASSERT_EQ(bones.size(), 1u) << "the faces of one arm link to one bone";
    distinct.insert(bones.begin()->first);
  }
  EXPECT_EQ(distinct.size(), 3u);
}

TEST(Skeleton, TripodHasThreeBranchesAndOneJunction)
{
  ExpectTripodSkeleton(MakeTripod(5.0, 1.0), 5.0, 1.0, 0.5);
}

TEST(Skeleton, TripodWithRayCastSdf)
{
  // Coarse tripod (7.5 degree facets), brute-force cone SDF: larger diameters and scattered
  // points at the junction, shorter diameters on the caps (the medial branches stop short of
  // the cap centres by about half a radius; steps 4b and 7b carry them on to the tips).
  TestMesh tripod = MakeTripod(5.0, 1.0, 48, 24);
  tripod.Sdf = RayCastSdf(tripod);
  ExpectTripodSkeleton(tripod, 5.0, 1.0, 1.0);
}

TEST(Skeleton, StarOfEightWithNoisySdf)
{
  // Eight capsules of different radii and lengths from one centre, +-20 % independent noise
  // on every face's SDF: eight branches, no stubs (short-branch pruning), one tree.
  std::vector<Arm> arms;
  for (int k = 0; k < 8; ++k)
  {
    const double angle = 2.0 * Pi * k / 8.0;
    arms.push_back({ Eigen::Vector3d(std::cos(angle), std::sin(angle), 0.2 * (k % 2)).normalized(),
      4.0 + 0.3 * k, 0.4 + 0.1 * k });
  }
  TestMesh star = MakeCapsuleStar(arms, 256, 128, Eigen::Vector3d::UnitZ());
  AddSdfNoise(star, 0.2);
  const SkeletonResult result = RunSkeleton(star);
  ExpectWellFormed(result, star.Faces());
  const GraphSummary graph = Summarise(result);
  EXPECT_EQ(graph.Components, 1u);
  EXPECT_EQ(graph.CountDegree(1), 8u);
  std::set<std::size_t> armsReached;
  for (Eigen::Index n = 0; n < result.NodePositions.rows(); ++n)
  {
    const Eigen::Vector3d p = result.NodePositions.row(n).transpose();
    for (std::size_t a = 0; a < arms.size(); ++a)
    {
      if (graph.Degree[n] == 1 && (p - arms[a].Length * arms[a].Direction).norm() < arms[a].Radius)
      {
        armsReached.insert(a);
      }
    }
  }
  EXPECT_EQ(armsReached.size(), 8u);
  // One bone per arm; the arms meet at several junctions around the centre, joined by inner
  // branches longer than the radius there, which are bones too.
  EXPECT_GE(result.BoneLength.size(), 8u);
  const std::size_t junctions = static_cast<std::size_t>(std::count_if(graph.Degree.begin(),
    graph.Degree.end(), [](std::size_t degree) { return degree >= 3; }));
  EXPECT_EQ(result.BoneLength.size(), 8u + junctions - 1u) << "a tree: ends + junctions - 1";
}

TEST(Skeleton, TwoCapsulesGiveTwoTrees)
{
  TestMesh first = MakeCapsule(1.0, 3.0, 32, 8, 24);
  TestMesh second = MakeCapsule(0.5, 2.0, 32, 8, 24);
  Place(second, { 1, 0, 0 }, { 0, 3.0, 0 }); // 1.5 apart from the first, lying along x
  const TestMesh both = Concatenate(first, second);
  const SkeletonResult result = RunSkeleton(both);
  ExpectWellFormed(result, both.Faces());
  const GraphSummary graph = Summarise(result);
  EXPECT_EQ(graph.Components, 2u);
  ASSERT_EQ(result.BoneLength.size(), 2u);
  // The longer capsule's axis (length 6) with its tips (r = 1 each side) is bone 0, the
  // shorter one's (length 4, r = 0.5) bone 1.
  EXPECT_NEAR(result.BoneLength[0], 8.0, 0.6);
  EXPECT_NEAR(result.BoneLength[1], 5.0, 0.4);
  // Faces link to nodes of their own capsule.
  for (Eigen::Index f = 0; f < both.Faces(); ++f)
  {
    const Eigen::Vector3d node = result.NodePositions.row(result.FaceNodeId[f]).transpose();
    const bool onFirst = std::hypot(node.x(), node.y()) < 0.1;
    ASSERT_EQ(onFirst, f < first.Faces());
    ASSERT_EQ(result.FaceBoneId[f], onFirst ? 0 : 1);
  }
  // Told that both are one component, the skeleton bridges the gap into one tree.
  const std::vector<std::int64_t> oneLabel(static_cast<std::size_t>(both.Faces()), 42);
  const SkeletonResult joined =
    ComputeSkeleton(both.Points, both.Triangles, both.Sdf, PointMatrix(), oneLabel, {}, SerialFor);
  ExpectWellFormed(joined, both.Faces());
  EXPECT_EQ(Summarise(joined).Components, 1u);
}

TEST(Skeleton, SphereIsOneNode)
{
  // Exact SDF sends every sample to the centre: no curve, one node there.
  const TestMesh sphere = MakeSphere(2.0);
  const SkeletonResult result = RunSkeleton(sphere);
  ExpectWellFormed(result, sphere.Faces());
  ASSERT_EQ(result.NodePositions.rows(), 1);
  EXPECT_LT(result.NodePositions.row(0).norm(), 0.05);
  ASSERT_EQ(result.Polylines.size(), 1u);
  EXPECT_EQ(result.IsConnection[0], 0);
  EXPECT_EQ(result.BoneId, std::vector<std::int64_t>{ 0 });
  EXPECT_EQ(result.BoneLength, std::vector<double>{ 0.0 });
}

TEST(Skeleton, CrossHasOneJunctionAndFourBones)
{
  // Four arms in a plane: the two collinear arms give one fitted segment straight through
  // the centre, the other two join it by connecting paths that may land a little apart. The
  // junction cleaning contracts the short piece between them: one junction of degree 4 and
  // four bones, one per arm, whatever the noise.
  const std::vector<Arm> arms{ { Eigen::Vector3d(1, 0, 0), 5.0, 1.0 },
    { Eigen::Vector3d(-1, 0, 0), 5.0, 1.0 }, { Eigen::Vector3d(0, 1, 0), 4.0, 0.6 },
    { Eigen::Vector3d(0, -1, 0), 4.5, 0.7 } };
  for (const std::uint64_t noiseSeed : { 1u, 2u, 3u })
  {
    TestMesh cross = MakeCapsuleStar(arms, 192, 96, Eigen::Vector3d::UnitZ());
    AddSdfNoise(cross, 0.1, noiseSeed);
    const SkeletonResult result = RunSkeleton(cross);
    ExpectWellFormed(result, cross.Faces());
    const GraphSummary graph = Summarise(result);
    EXPECT_EQ(graph.CountDegree(1), 4u) << noiseSeed;
    EXPECT_EQ(graph.MaxDegree(), 4u) << noiseSeed;
    EXPECT_EQ(graph.CountDegree(3), 0u) << noiseSeed;
    EXPECT_EQ(result.BoneLength.size(), 4u) << noiseSeed;
  }
}

} // namespace

namespace
{

/// Points of P on a grid in the plane z = zMid, over [x0, x1] x [y0, y1], with one radius.
ProjectedCloud GridCloud(double x0, double x1, double y0, double y1, double zMid, double step, double radius)
{
  std::vector<Eigen::Vector3d> points;
  for (double x = x0; x <= x1 + 1e-9; x += step)
  {
    for (double y = y0; y <= y1 + 1e-9; y += step)
    {
      points.emplace_back(x, y, zMid);
    }
  }
  ProjectedCloud cloud;
  cloud.Positions.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    cloud.Positions.row(static_cast<Eigen::Index>(i)) = points[i].transpose();
    cloud.Radius.push_back(radius);
    cloud.SourceFace.push_back(0);
  }
  return cloud;
}

std::size_t NearestRow(const ProjectedCloud& cloud, const Eigen::Vector3d& p)
{
  Eigen::Index row = 0;
  (cloud.Positions.rowwise() - p.transpose()).rowwise().squaredNorm().minCoeff(&row);
  return static_cast<std::size_t>(row);
}

} // namespace

TEST(SheetFactors, AreSmallInTheMiddleOfASheetAndOneAtItsRimAndInATube)
{
  // A plate 4 x 4 x 0.4: its projected points lie in the middle plane, radius 0.2. In-plane
  // clearance from the centre is 2 (the rays stop at 4 radii: factor 1/4), 0.4 from a point
  // 0.4 inside a side (0.2 / 0.4), 0.1 at the rim (1).
  const TestMesh plate = MakeBox(Eigen::Vector3d(4.0, 4.0, 0.4), 20);
  const EmbreeRayCaster plateVolume(plate.Points, plate.Triangles);
  const ProjectedCloud sheet = GridCloud(0.1, 3.9, 0.1, 3.9, 0.2, 0.1, 0.2);
  const ThinnedCloud sheetThinned = ThinProjectedCloud(sheet, SkeletonThinningOptions(), SerialFor);
  const auto factors = [&](double exponent, const ParallelFor& parallelFor) {
    return SheetFactors(sheet, sheetThinned, plateVolume, exponent, parallelFor);
  };
  const std::vector<double> onSheet = factors(1.0, SerialFor);
  EXPECT_DOUBLE_EQ(onSheet[NearestRow(sheet, { 2.0, 2.0, 0.2 })], 0.25);
  EXPECT_NEAR(onSheet[NearestRow(sheet, { 2.0, 0.4, 0.2 })], 0.5, 1e-6);
  EXPECT_DOUBLE_EQ(onSheet[NearestRow(sheet, { 2.0, 0.1, 0.2 })], 1.0);
  // The exponent: (0.2 / 0.4)^2.
  EXPECT_NEAR(factors(2.0, SerialFor)[NearestRow(sheet, { 2.0, 0.4, 0.2 })], 0.25, 1e-6);
  // Exponent 0: Euclidean lengths everywhere; out of range: an error.
  const std::vector<double> off = factors(0.0, SerialFor);
  EXPECT_TRUE(std::all_of(off.begin(), off.end(), [](double f) { return f == 1.0; }));
  EXPECT_THROW(factors(4.5, SerialFor), Error);
  // The same on two threads.
  EXPECT_EQ(factors(1.0, ThreadedFor(2)), onSheet);

  // Along a capsule's axis (radius 0.5) the cloud is a line: Euclidean lengths.
  const TestMesh capsule = MakeCapsule(0.5, 3.0);
  const EmbreeRayCaster capsuleVolume(capsule.Points, capsule.Triangles);
  ProjectedCloud axis;
  axis.Positions.resize(61, 3);
  axis.Radius.assign(61, 0.5);
  axis.SourceFace.assign(61, 0);
  for (Eigen::Index i = 0; i < 61; ++i)
  {
    // Scattered by 0.02 across the axis, as the SDF's noise scatters P.
    axis.Positions.row(i) << 0.02 * std::sin(1.7 * static_cast<double>(i)), 0.02 * std::cos(2.3 * static_cast<double>(i)),
      -3.0 + 0.1 * static_cast<double>(i);
  }
  const ThinnedCloud axisThinned = ThinProjectedCloud(axis, SkeletonThinningOptions(), SerialFor);
  const std::vector<double> onAxis = SheetFactors(axis, axisThinned, capsuleVolume, 1.0, SerialFor);
  EXPECT_TRUE(std::all_of(onAxis.begin(), onAxis.end(), [](double f) { return f == 1.0; }));
  // A local spread of another size is an error; none at all (a thinned cloud made by hand)
  // gives Euclidean lengths.
  EXPECT_THROW(SheetFactors(axis, sheetThinned, capsuleVolume, 1.0, SerialFor), Error);
  ThinnedCloud withoutSpread = sheetThinned;
  withoutSpread.LocalSpread = PointMatrix();
  withoutSpread.LocalNormal = PointMatrix();
  const std::vector<double> unknown = SheetFactors(sheet, withoutSpread, plateVolume, 1.0, SerialFor);
  EXPECT_TRUE(std::all_of(unknown.begin(), unknown.end(), [](double f) { return f == 1.0; }));
}
