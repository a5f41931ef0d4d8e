// SPDX-License-Identifier: BSD-3-Clause
// Step 1 of the skeleton (SkeletonSampling.h): the projected cloud P, area-weighted samples
// pushed inward by half the SDF; supplied normals, degenerate faces and face components.
#include "Skeleton/Skeleton.h"
#include "TestShapes.h"

#include <gtest/gtest.h>

#include <algorithm>

namespace
{

using namespace shapediameter;
using namespace shapediameter::testshapes;

TEST(SkeletonSampling, AreaWeightedAndPushedInward)
{
  // Two separate triangles of area 0.5 and 1.5 in the plane z = 0, normal +z.
  PointMatrix points(6, 3);
  points << 0, 0, 0, 1, 0, 0, 0, 1, 0, 5, 0, 0, 8, 0, 0, 5, 1, 0;
  TriangleMatrix triangles(2, 3);
  triangles << 0, 1, 2, 3, 4, 5;
  const std::vector<double> sdf{ 0.4, 2.0 };
  SkeletonSamplingOptions options;
  options.NumberOfSamples = 1000;
  const ProjectedCloud cloud = SampleProjectedCloud(points, triangles, sdf, PointMatrix(), options);
  ASSERT_EQ(cloud.Size(), 1000u);
  const auto first = std::count(cloud.SourceFace.begin(), cloud.SourceFace.end(), 0);
  EXPECT_NEAR(static_cast<double>(first), 250.0, 1.0); // stratified: off by less than one
  for (std::size_t i = 0; i < cloud.Size(); ++i)
  {
    const double expectedRadius = 0.5 * sdf[cloud.SourceFace[i]];
    EXPECT_EQ(cloud.Radius[i], expectedRadius);
    EXPECT_NEAR(cloud.Positions(static_cast<Eigen::Index>(i), 2), -expectedRadius, 1e-12);
    const double x = cloud.Positions(static_cast<Eigen::Index>(i), 0);
    const double y = cloud.Positions(static_cast<Eigen::Index>(i), 1);
    if (cloud.SourceFace[i] == 0)
    {
      EXPECT_TRUE(x >= -1e-12 && y >= -1e-12 && x + y <= 1.0 + 1e-12);
    }
    else
    {
      EXPECT_TRUE(x >= 5.0 - 1e-12 && x <= 8.0 + 1e-12 && y >= -1e-12 && y <= 1.0 + 1e-12);
    }
  }
  // Deterministic, seed-dependent.
  const ProjectedCloud again = SampleProjectedCloud(points, triangles, sdf, PointMatrix(), options);
  EXPECT_TRUE(again.Positions == cloud.Positions);
  options.Seed += 1;
  const ProjectedCloud other = SampleProjectedCloud(points, triangles, sdf, PointMatrix(), options);
  EXPECT_FALSE(other.Positions == cloud.Positions);
}

TEST(SkeletonSampling, SuppliedNormalsAndDegenerateFaces)
{
  PointMatrix points(4, 3);
  points << 0, 0, 0, 1, 0, 0, 0, 1, 0, 2, 0, 0;
  TriangleMatrix triangles(2, 3);
  triangles << 0, 1, 2, 0, 1, 3; // the second face has zero area
  const std::vector<double> sdf{ 1.0, 1.0 };
  PointMatrix normals(2, 3);
  normals << 0, 0, 2, std::nan(""), 0, 0; // not unit; non-finite falls back
  SkeletonSamplingOptions options;
  options.NumberOfSamples = 50;
  const ProjectedCloud cloud = SampleProjectedCloud(points, triangles, sdf, normals, options);
  ASSERT_EQ(cloud.Size(), 50u);
  for (std::size_t i = 0; i < cloud.Size(); ++i)
  {
    EXPECT_EQ(cloud.SourceFace[i], 0);
    EXPECT_NEAR(cloud.Positions(static_cast<Eigen::Index>(i), 2), -0.5, 1e-12);
  }
  // Only degenerate faces: nothing to sample.
  TriangleMatrix flat(1, 3);
  flat << 0, 1, 3;
  EXPECT_EQ(SampleProjectedCloud(points, flat, { 1.0 }, PointMatrix(), options).Size(), 0u);
  EXPECT_EQ(SampleProjectedCloud(points, TriangleMatrix(0, 3), {}, PointMatrix(), options).Size(), 0u);
}

TEST(SkeletonSampling, FaceComponents)
{
  const TestMesh two = Concatenate(MakeCapsule(1.0, 2.0, 16, 4, 8), MakeSphere(1.0, 16, 8));
  const std::vector<std::int64_t> labels = LabelFaceComponents(two.Triangles, two.Points.rows());
  const Eigen::Index firstFaces = MakeCapsule(1.0, 2.0, 16, 4, 8).Faces();
  for (Eigen::Index f = 0; f < two.Faces(); ++f)
  {
    ASSERT_EQ(labels[f], f < firstFaces ? 0 : 1);
  }
}

} // namespace
