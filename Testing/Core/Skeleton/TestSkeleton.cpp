// SPDX-License-Identifier: BSD-3-Clause
// The whole SDF-guided skeleton (ComputeSkeleton, Skeleton.h; paper section 5): the analytic
// test shapes themselves, determinism across seeds and threads, the shared articulated figure in
// two poses with the real (ray-cast, smoothed) SDF, and degenerate or invalid input, progress
// and abort. The steps have their own files: TestSkeletonSampling, -PointTree, -Thinning,
// -Segments, -Connection, -Bones.
#include "ArticulatedFigure.h"
#include "Smoothing/BilateralSmoothing.h"
#include "Mesh/FaceGraph.h"
#include "SDF/SDF.h"
#include "SDF/ShapeDiameter.h"
#include "Skeleton/Skeleton.h"
#include "Skeleton/SkeletonTestSupport.h"
#include "TestShapes.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <map>
#include <set>

namespace
{

using namespace shapediameter;
using namespace shapediameter::testshapes;
using namespace shapediameter::skeletontests;

TEST(TestShapes, ClosedAndOutward)
{
  const double pi = Pi;
  EXPECT_NEAR(SignedVolume(MakeCapsule(1.0, 3.0, 96, 24, 40)),
    pi * 6.0 + 4.0 / 3.0 * pi, 0.02 * (6.0 * pi + 4.0 / 3.0 * pi));
  EXPECT_NEAR(SignedVolume(MakeTorus(6.0, 1.0)), 2.0 * pi * pi * 6.0, 0.03 * 2.0 * pi * pi * 6.0);
  EXPECT_NEAR(SignedVolume(MakeProlateSpheroid(5.0, 1.0)), 4.0 / 3.0 * pi * 5.0, 0.02 * 4.0 / 3.0 * pi * 5.0);
  EXPECT_GT(SignedVolume(MakeTripod(5.0, 1.0, 120, 60)), 3.0 * pi * 4.0);
  EXPECT_GT(SignedVolume(MakeSphere(1.0)), 0.0);
}

TEST(Skeleton, DeterministicForSeedAndThreads)
{
  TestMesh tripod = MakeTripod(5.0, 1.0, 120, 60);
  AddSdfNoise(tripod, 0.1);
  SkeletonOptions options;
  options.Sampling.NumberOfSamples = 4000;
  const SkeletonResult serial = RunSkeleton(tripod, options, SerialFor);
  for (const unsigned threads : { 2u, 3u })
  {
    const SkeletonResult threaded = RunSkeleton(tripod, options, ThreadedFor(threads));
    EXPECT_TRUE(threaded.NodePositions == serial.NodePositions) << threads;
    EXPECT_EQ(threaded.NodeRadius, serial.NodeRadius);
    EXPECT_EQ(threaded.NodeConfidence, serial.NodeConfidence);
    EXPECT_EQ(threaded.Polylines, serial.Polylines);
    EXPECT_EQ(threaded.IsConnection, serial.IsConnection);
    EXPECT_EQ(threaded.BoneId, serial.BoneId);
    EXPECT_EQ(threaded.NodeBoneId, serial.NodeBoneId);
    EXPECT_EQ(threaded.BoneLength, serial.BoneLength);
    EXPECT_EQ(threaded.FaceNodeId, serial.FaceNodeId);
    EXPECT_EQ(threaded.FaceBoneId, serial.FaceBoneId);
    EXPECT_TRUE(threaded.CloudPositions == serial.CloudPositions);
    EXPECT_EQ(threaded.CloudConfidence, serial.CloudConfidence);
  }
  const SkeletonResult again = RunSkeleton(tripod, options, SerialFor);
  EXPECT_TRUE(again.NodePositions == serial.NodePositions);
  options.Sampling.Seed = 12345;
  const SkeletonResult reseeded = RunSkeleton(tripod, options, SerialFor);
  EXPECT_FALSE(reseeded.CloudPositions == serial.CloudPositions);
  EXPECT_EQ(Summarise(reseeded).CountDegree(1), 3u);
}

// ---------------------------------------------------------------------------------------------
// The articulated figure with the real SDF

struct FigureSkeleton
{
  shapediameter::testing::ArticulatedFigure Figure;
  SkeletonResult Skeleton;
};

FigureSkeleton SkeletonOfFigure(const shapediameter::testing::ArticulatedFigureTemplate& figure,
  const shapediameter::testing::FigurePose& pose)
{
  FigureSkeleton result{ figure.Pose(pose), {} };
  const PointMatrix& points = result.Figure.Points;
  const TriangleMatrix& triangles = result.Figure.Triangles;
  const ShapeDiameterResult sdf =
    ComputeFaceShapeDiameter(points, triangles, ShapeDiameterOptions{}, ThreadedFor(2));
  const std::vector<double> smoothed =
    SmoothBilateral(BuildFaceGraph(points, triangles), sdf.Values).Values;
  result.Skeleton = ComputeSkeleton(points, triangles, smoothed, {}, ThreadedFor(2));
  return result;
}

TEST(Skeleton, ArticulatedFigureKeepsItsBonesAcrossPoses)
{
  // The product requirement: the same figure in two poses has the same number of bones, and
  // each limb's faces stay linked to one bone of their own. Bones are the branches of the
  // tree, so this holds although the algorithm grows its pieces differently per pose (7
  // polylines in the T-pose, whose arms form one straight segment through the torso; 9 when
  // bent). The head is a ball on a short neck: the ball has no curve-like part, so the
  // skeleton's branch towards it stops in a stub above the torso (0.21-0.34 long, junction
  // radius 0.23-0.25) that the leaf pruning used to keep in the bent pose only. Step 4b
  // (SkeletonLeafExtension.h) carries the stub on to the top of the head before the pruning,
  // so both poses now have the head's branch: five ends, and the same bones (limbs 0.9-1.0,
  // torso 0.6-0.75, head 0.44-0.55; one more torso piece if arms and legs met the torso at
  // separate junctions).
  using namespace shapediameter::testing;
  const ArticulatedFigureTemplate figure;
  FigurePose bent;
  bent.LeftArm = 0.9;
  bent.RightArm = -0.6;
  bent.LeftLeg = 0.5;
  bent.RightLeg = -0.4;
  std::vector<std::size_t> boneCounts, endCounts;
  for (const FigurePose& pose : { FigurePose{}, bent })
  {
    const FigureSkeleton result = SkeletonOfFigure(figure, pose);
    const SkeletonResult& skeleton = result.Skeleton;
    ExpectWellFormed(skeleton, result.Figure.Triangles.rows());
    const GraphSummary graph = Summarise(skeleton);
    EXPECT_EQ(graph.Components, 1u);
    boneCounts.push_back(BoneCount(skeleton));
    EXPECT_EQ(boneCounts.back(), skeleton.BoneLength.size());
    EXPECT_GE(boneCounts.back(), 6u);
    EXPECT_LE(boneCounts.back(), 7u);
    endCounts.push_back(graph.CountDegree(1));
    EXPECT_EQ(endCounts.back(), 5u) << "ends: four limbs and the head";

    std::set<std::int64_t> limbBones;
    for (const FigurePart limb : { LeftArm, RightArm, LeftLeg, RightLeg })
    {
      std::map<std::int64_t, std::size_t> faces;
      std::size_t total = 0;
      for (std::size_t f = 0; f < result.Figure.FaceParts.size(); ++f)
      {
        if (result.Figure.FaceParts[f] == limb)
        {
          ++faces[skeleton.FaceBoneId[f]];
          ++total;
        }
      }
      const auto majority = std::max_element(faces.begin(), faces.end(),
        [](const auto& a, const auto& b) { return a.second < b.second; });
      EXPECT_GT(static_cast<double>(majority->second), 0.6 * static_cast<double>(total))
        << "limb " << limb;
      limbBones.insert(majority->first);
      // The limb's bone reaches its tip: its farthest node from the pivot lies within two
      // limb radii of the capsule's far cap centre.
      const FigureLimb geometry = ArticulatedFigureTemplate::Limb(limb);
      const double angle = limb == LeftArm ? pose.LeftArm
        : limb == RightArm                 ? pose.RightArm
        : limb == LeftLeg                  ? pose.LeftLeg
                                           : pose.RightLeg;
      const Eigen::Vector3d direction =
        Eigen::AngleAxisd(angle, geometry.BendAxis) * geometry.Direction;
      const Eigen::Vector3d capCentre =
        geometry.Pivot + (geometry.Length - geometry.Radius) * direction;
      double nearestToTip = std::numeric_limits<double>::infinity();
      for (std::size_t p = 0; p < skeleton.Polylines.size(); ++p)
      {
        if (skeleton.BoneId[p] != majority->first)
        {
          continue;
        }
        for (const std::int64_t node : skeleton.Polylines[p])
        {
          nearestToTip = std::min(nearestToTip,
            (skeleton.NodePositions.row(node).transpose() - capCentre).norm());
        }
      }
      EXPECT_LT(nearestToTip, 2.0 * geometry.Radius) << "limb " << limb;
    }
    EXPECT_EQ(limbBones.size(), 4u) << "the four limbs have four distinct bones";
  }
  EXPECT_EQ(boneCounts[0], boneCounts[1]);
  EXPECT_EQ(endCounts[0], endCounts[1]);
}

// ---------------------------------------------------------------------------------------------
// Degenerate and invalid input

TEST(Skeleton, EmptyMeshGivesEmptyResult)
{
  const SkeletonResult result = ComputeSkeleton(PointMatrix(0, 3), TriangleMatrix(0, 3), {});
  EXPECT_EQ(result.NodePositions.rows(), 0);
  EXPECT_TRUE(result.Polylines.empty());
  EXPECT_TRUE(result.FaceNodeId.empty());
  EXPECT_FALSE(result.Aborted);
}

TEST(Skeleton, TinyAndDegenerateMeshesAreDefined)
{
  PointMatrix points(4, 3);
  points << 0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0;
  TriangleMatrix one(1, 3);
  one << 0, 1, 2;
  const SkeletonResult single = ComputeSkeleton(points, one, { 0.3 });
  ExpectWellFormed(single, 1);
  EXPECT_GE(single.NodePositions.rows(), 1);

  // Zero SDF: radius 0 everywhere, no neighbourhoods.
  const TestMesh capsule = MakeCapsule(1.0, 2.0, 16, 4, 8);
  const std::vector<double> zeros(static_cast<std::size_t>(capsule.Faces()), 0.0);
  const SkeletonResult flat = ComputeSkeleton(capsule.Points, capsule.Triangles, zeros);
  ExpectWellFormed(flat, capsule.Faces());
  EXPECT_EQ(flat.NodePositions.rows(), 1);

  // Only degenerate faces: no samples, one fallback node.
  TriangleMatrix degenerate(2, 3);
  degenerate << 0, 1, 3, 1, 3, 0;
  const SkeletonResult none = ComputeSkeleton(points, degenerate, { 1.0, 1.0 });
  ExpectWellFormed(none, 2);
  EXPECT_EQ(none.NodePositions.rows(), 1);
  EXPECT_TRUE(none.CloudPositions.rows() == 0);

  // A few samples only.
  SkeletonOptions options;
  options.Sampling.NumberOfSamples = 1;
  const SkeletonResult sparse = RunSkeleton(capsule, options);
  ExpectWellFormed(sparse, capsule.Faces());
  EXPECT_EQ(sparse.NodePositions.rows(), 1);
}

TEST(Skeleton, InvalidInputThrows)
{
  const TestMesh capsule = MakeCapsule(1.0, 2.0, 16, 4, 8);
  TriangleMatrix badIndex = capsule.Triangles;
  badIndex(3, 1) = capsule.Points.rows();
  EXPECT_THROW(ComputeSkeleton(capsule.Points, badIndex, capsule.Sdf), Error);
  badIndex(3, 1) = -1;
  EXPECT_THROW(ComputeSkeleton(capsule.Points, badIndex, capsule.Sdf), Error);
  PointMatrix nanPoints = capsule.Points;
  nanPoints(2, 0) = std::nan("");
  EXPECT_THROW(ComputeSkeleton(nanPoints, capsule.Triangles, capsule.Sdf), Error);
  std::vector<double> sdf = capsule.Sdf;
  sdf[5] = std::numeric_limits<double>::infinity();
  EXPECT_THROW(ComputeSkeleton(capsule.Points, capsule.Triangles, sdf), Error);
  sdf[5] = -1.0;
  EXPECT_THROW(ComputeSkeleton(capsule.Points, capsule.Triangles, sdf), Error);
  sdf.pop_back();
  EXPECT_THROW(ComputeSkeleton(capsule.Points, capsule.Triangles, sdf), Error);
  EXPECT_THROW(ComputeSkeleton(capsule.Points, capsule.Triangles, capsule.Sdf, PointMatrix(3, 3),
                 {}, {}, SerialFor),
    Error);
  EXPECT_THROW(ComputeSkeleton(capsule.Points, capsule.Triangles, capsule.Sdf, PointMatrix(),
                 { 1, 2 }, {}, SerialFor),
    Error);
  SkeletonOptions options;
  options.Sampling.NumberOfSamples = 0;
  EXPECT_THROW(RunSkeleton(capsule, options), Error);
  options = {};
  options.Segments.AngularToleranceDegrees = 90.0;
  EXPECT_THROW(RunSkeleton(capsule, options), Error);
  options = {};
  options.Connection.NumberOfNeighbors = 0;
  EXPECT_THROW(RunSkeleton(capsule, options), Error);
  for (const double share : { -0.1, 1.5, std::nan("") })
  {
    options = {};
    options.OwnBoneShare = share;
    EXPECT_THROW(RunSkeleton(capsule, options), Error) << share;
  }
}

TEST(Skeleton, ProgressAndAbort)
{
  const TestMesh capsule = MakeCapsule(1.0, 3.0, 24, 6, 16);
  std::vector<double> fractions;
  const SkeletonResult complete = ComputeSkeleton(capsule.Points, capsule.Triangles, capsule.Sdf,
    PointMatrix(), {}, {}, SerialFor, [&fractions](double f) {
      fractions.push_back(f);
      return true;
    });
  EXPECT_FALSE(complete.Aborted);
  ASSERT_GE(fractions.size(), 5u);
  EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));
  EXPECT_GE(fractions.front(), 0.0);
  EXPECT_EQ(fractions.back(), 1.0);
  for (const double stopAt : { 0.0, 0.3, 0.8, 0.95 })
  {
    const SkeletonResult aborted = ComputeSkeleton(capsule.Points, capsule.Triangles, capsule.Sdf,
      PointMatrix(), {}, {}, SerialFor, [stopAt](double f) { return f < stopAt; });
    EXPECT_TRUE(aborted.Aborted) << stopAt;
    EXPECT_EQ(aborted.NodePositions.rows(), 0);
    EXPECT_TRUE(aborted.FaceNodeId.empty());
  }
}

} // namespace
