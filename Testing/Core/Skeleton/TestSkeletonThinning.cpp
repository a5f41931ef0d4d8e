// SPDX-License-Identifier: BSD-3-Clause
// Step 2 of the skeleton (SkeletonThinning.h): MLS projection, confidence, the confident
// share and epsilon-thinning on lines, blobs and circles; option validation.
#include "RayCasting/EmbreeRayCaster.h"
#include "SDF/SDF.h"
#include "Skeleton/Skeleton.h"
#include "Skeleton/SkeletonPointTree.h"
#include "TestShapes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <random>

namespace
{

using namespace shapediameter;
using namespace shapediameter::testshapes;

TEST(SkeletonThinning, LineIsConfidentBlobIsNot)
{
  ProjectedCloud cloud;
  const int line = 200;
  cloud.Positions.resize(line + 60 + 3, 3);
  for (int i = 0; i < line; ++i)
  {
    // A slightly noisy straight line along x.
    cloud.Positions.row(i) << 0.05 * i, 0.01 * std::sin(7.0 * i), 0.01 * std::cos(5.0 * i);
  }
  for (int i = 0; i < 60; ++i)
  {
    cloud.Positions.row(line + i) << 50.0, 0.0, 0.0; // coincident blob
  }
  cloud.Positions.row(line + 60) << -50.0, 0.0, 0.0; // isolated triple
  cloud.Positions.row(line + 61) << -50.1, 0.0, 0.0;
  cloud.Positions.row(line + 62) << -50.0, 0.1, 0.0;
  cloud.Radius.assign(static_cast<std::size_t>(cloud.Positions.rows()), 1.0);
  cloud.SourceFace.assign(cloud.Radius.size(), 0);
  const ThinnedCloud thinned = ThinProjectedCloud(cloud, {}, SerialFor);
  ASSERT_FALSE(thinned.Aborted);
  for (int i = 20; i < line - 20; ++i)
  {
    EXPECT_GT(thinned.Confidence[i], 0.99);
    EXPECT_NEAR(std::abs(thinned.Axis(i, 0)), 1.0, 1e-3);
    EXPECT_LT(std::abs(thinned.Positions(i, 1)), 0.005); // noise projected away
  }
  for (int i = line; i < line + 63; ++i)
  {
    EXPECT_EQ(thinned.Confidence[i], 0.0);
    EXPECT_TRUE(thinned.Positions.row(i) == cloud.Positions.row(i));
  }
  // T: only line points, spaced at least epsilon = 0.25 apart.
  ASSERT_FALSE(thinned.Thinned.empty());
  for (std::size_t a = 0; a < thinned.Thinned.size(); ++a)
  {
    EXPECT_LT(thinned.Thinned[a], line);
    for (std::size_t b = a + 1; b < thinned.Thinned.size(); ++b)
    {
      EXPECT_GT((thinned.Positions.row(thinned.Thinned[a]) - thinned.Positions.row(thinned.Thinned[b])).norm(), 0.25);
    }
  }
  EXPECT_GE(thinned.Thinned.size(), 20u); // 10 units long, gaps at most 2 epsilon
}

TEST(SkeletonThinning, FixedDataProjectionDoesNotShrinkCircles)
{
  // Points on a circle of radius 6 with neighbourhood radius 1: the linear fit is biased
  // inward by about h^2 / (6 R) = 0.028 once; refitting the moved cloud accumulates it.
  ProjectedCloud cloud;
  const int count = 2000;
  cloud.Positions.resize(count, 3);
  for (int i = 0; i < count; ++i)
  {
    const double u = 2.0 * Pi * i / count;
    cloud.Positions.row(i) << 6.0 * std::cos(u), 6.0 * std::sin(u), 0.0;
  }
  cloud.Radius.assign(count, 1.0);
  cloud.SourceFace.assign(count, 0);
  SkeletonThinningOptions options;
  const ThinnedCloud fixed = ThinProjectedCloud(cloud, options, SerialFor);
  options.ContractCloud = true;
  const ThinnedCloud contracted = ThinProjectedCloud(cloud, options, SerialFor);
  double fixedWorst = 0.0;
  double contractedWorst = 0.0;
  for (int i = 0; i < count; ++i)
  {
    fixedWorst = std::max(fixedWorst, std::abs(fixed.Positions.row(i).norm() - 6.0));
    contractedWorst = std::max(contractedWorst, std::abs(contracted.Positions.row(i).norm() - 6.0));
  }
  EXPECT_LT(fixedWorst, 0.035);
  EXPECT_GT(contractedWorst, 0.06);
}

TEST(SkeletonThinning, MinimumConfidentShareLowersTheThresholdButNotBelowJunctions)
{
  // Thick stubs: short noisy tubes whose neighbourhoods are barely line-like (confidence about
  // 0.6-0.8), next to a ball (confidence near 1/3). A fixed threshold of 0.8 keeps almost
  // nothing; the share lowers it to the confidence at that share, never below 0.6.
  ProjectedCloud cloud;
  std::mt19937_64 generator(22);
  std::normal_distribution<double> normal(0.0, 1.0);
  const int tube = 600;
  const int ball = 600;
  cloud.Positions.resize(tube + ball, 3);
  for (int i = 0; i < tube; ++i)
  {
    cloud.Positions.row(i) << 0.005 * i, 0.28 * normal(generator), 0.28 * normal(generator);
  }
  for (int i = 0; i < ball; ++i)
  {
    cloud.Positions.row(tube + i) << 20.0 + 0.4 * normal(generator), 0.4 * normal(generator), 0.4 * normal(generator);
  }
  cloud.Radius.assign(static_cast<std::size_t>(tube + ball), 1.0);
  cloud.SourceFace.assign(cloud.Radius.size(), 0);
  SkeletonThinningOptions fixed;
  fixed.MinimumConfidentShare = 0.0;
  const ThinnedCloud alone = ThinProjectedCloud(cloud, fixed, SerialFor);
  EXPECT_EQ(alone.AppliedConfidenceThreshold, 0.8);
  std::vector<double> sorted = alone.Confidence;
  std::sort(sorted.begin(), sorted.end(), std::greater<double>());
  const std::size_t above = static_cast<std::size_t>(std::count_if(sorted.begin(), sorted.end(), [](double c) { return c >= 0.8; }));
  ASSERT_LT(above, sorted.size() / 10) << "the test needs a cloud that is mostly below 0.8";

  const ThinnedCloud shared = ThinProjectedCloud(cloud, {}, SerialFor); // share 0.2
  const double expected = std::max(0.6, sorted[static_cast<std::size_t>(std::ceil(0.2 * static_cast<double>(sorted.size()))) - 1]);
  EXPECT_EQ(shared.AppliedConfidenceThreshold, expected);
  EXPECT_LT(shared.AppliedConfidenceThreshold, 0.8);
  EXPECT_GT(shared.Thinned.size(), alone.Thinned.size());
  for (const std::int64_t kept : shared.Thinned)
  {
    EXPECT_GE(shared.Confidence[static_cast<std::size_t>(kept)], expected);
  }
  SkeletonThinningOptions everything;
  everything.MinimumConfidentShare = 1.0; // would take every point: floored at 0.6
  const ThinnedCloud floored = ThinProjectedCloud(cloud, everything, SerialFor);
  EXPECT_EQ(floored.AppliedConfidenceThreshold, 0.6);
  for (const std::int64_t kept : floored.Thinned)
  {
    EXPECT_LT(kept, tube) << "no point of the ball passes 0.6";
  }
  SkeletonThinningOptions bad;
  bad.MinimumConfidentShare = 1.5;
  EXPECT_THROW(ThinProjectedCloud(cloud, bad, SerialFor), Error);
}

TEST(SkeletonThinning, InvalidOptionsThrow)
{
  ProjectedCloud cloud;
  SkeletonThinningOptions options;
  options.NumberOfIterations = 0;
  EXPECT_THROW(ThinProjectedCloud(cloud, options, SerialFor), Error);
  options = {};
  options.ConfidenceThreshold = std::nan("");
  EXPECT_THROW(ThinProjectedCloud(cloud, options, SerialFor), Error);
  options = {};
  options.NeighborhoodScale = 0.0;
  EXPECT_THROW(ThinProjectedCloud(cloud, options, SerialFor), Error);
  options = SkeletonThinningOptions();
  options.MinimumClearance = 1.5;
  EXPECT_THROW(ThinProjectedCloud(cloud, options, SerialFor), Error);
}

TEST(SkeletonThinning, PointsLinedUpAlongABoxsEdgesAreNotInT)
{
  // A box's faces beside an edge have a short SDF: their projected points line up along the
  // edge, inside the ball of the face across it. With the volume, every point of T has its
  // ball: no face closer than MinimumClearance x radius (for a box the nearest face lies along
  // an axis, one of the rays, so the test is exact). Without it, many points of T hug the edges.
  const Eigen::Vector3d size(2.0, 1.5, 1.0);
  const TestMesh box = MakeBox(size, 16);
  const std::vector<double> sdf =
    ComputeFaceShapeDiameter(box.Points, box.Triangles, ShapeDiameterOptions(), SerialFor).Values;
  const ProjectedCloud cloud = SampleProjectedCloud(box.Points, box.Triangles, sdf, PointMatrix(), {});
  const EmbreeRayCaster volume(box.Points, box.Triangles);
  const auto clearanceShare = [&](std::int64_t k) {
    const Eigen::Vector3d p = cloud.Positions.row(k).transpose();
    return std::min({ p.minCoeff(), (size - p).minCoeff() }) / cloud.Radius[static_cast<std::size_t>(k)];
  };
  const SkeletonThinningOptions options;
  const ThinnedCloud plain = ThinProjectedCloud(cloud, options, SerialFor);
  const ThinnedCloud tested = ThinProjectedCloud(cloud, options, ThreadedFor(2), {}, &volume);
  const auto hugging = [&](const ThinnedCloud& thinned) {
    return std::count_if(thinned.Thinned.begin(), thinned.Thinned.end(),
      [&](std::int64_t k) { return clearanceShare(k) < options.MinimumClearance; });
  };
  ASSERT_GE(plain.Thinned.size(), 20u);
  EXPECT_GT(hugging(plain), static_cast<std::ptrdiff_t>(plain.Thinned.size() / 3)) << "the test has edges to remove";
  EXPECT_EQ(hugging(tested), 0);
  EXPECT_EQ(ThinProjectedCloud(cloud, options, SerialFor, {}, &volume).Thinned, tested.Thinned) << "threads";
  SkeletonThinningOptions off = options;
  off.MinimumClearance = 0.0;
  EXPECT_EQ(ThinProjectedCloud(cloud, off, SerialFor, {}, &volume).Thinned, plain.Thinned);
}

/// A projector that splits the rows into `parts` uneven ranges, each projected against its own
/// tree of the cloud, as the distributed skeleton's processes do; counts its calls and the
/// clouds it was sent.
class SplitProjector final : public RegressionProjector
{
public:
  explicit SplitProjector(std::size_t parts)
    : Parts(parts)
  {
  }

  RegressionProjections Project(const PointMatrix& cloud, bool cloudChanged, const PointMatrix& positions,
    const std::vector<double>& radii, double minimumNeighbors) const override
  {
    ++this->Calls;
    if (cloudChanged || this->Trees.empty())
    {
      ++this->Clouds;
      this->Trees.clear();
      for (std::size_t part = 0; part < this->Parts; ++part)
      {
        this->Trees.push_back(std::make_unique<SkeletonPointTree>(cloud));
      }
    }
    const auto rows = static_cast<std::size_t>(positions.rows());
    RegressionProjections all = RegressionProjections::Zero(positions.rows());
    for (std::size_t part = 0; part < this->Parts; ++part)
    {
      // Uneven: the square of the share.
      const auto bound = [&](std::size_t p) { return rows * p * p / (this->Parts * this->Parts); };
      ProjectOntoRegressionLines(
        *this->Trees[part], positions, radii, minimumNeighbors, bound(part), bound(part + 1), all, ThreadedFor(2));
    }
    return all;
  }

  std::size_t Parts;
  mutable std::vector<std::unique_ptr<SkeletonPointTree>> Trees;
  mutable int Calls = 0;
  mutable int Clouds = 0;
};

TEST(SkeletonThinning, ProjectionsSplitOverRowsAnswerAsOneLoop)
{
  // The MLS iterations of a box's cloud (lines, sheets and undefined points), split over
  // processes as the distributed skeleton does: the same cloud, bit for bit, with the cloud
  // fixed (sent once) and contracted (sent every iteration); progress once per iteration.
  const TestMesh box = MakeBox(Eigen::Vector3d(2.0, 1.5, 1.0), 12);
  const std::vector<double> sdf =
    ComputeFaceShapeDiameter(box.Points, box.Triangles, ShapeDiameterOptions(), SerialFor).Values;
  const ProjectedCloud cloud = SampleProjectedCloud(box.Points, box.Triangles, sdf, PointMatrix(), {});
  ASSERT_GT(cloud.Size(), 500u);
  for (const bool contract : { false, true })
  {
    SkeletonThinningOptions options;
    options.ContractCloud = contract;
    const ThinnedCloud here = ThinProjectedCloud(cloud, options, SerialFor);
    const SplitProjector split(3);
    std::vector<double> fractions;
    const ThinnedCloud over = ThinProjectedCloud(cloud, options, SerialFor,
      [&](double fraction) {
        fractions.push_back(fraction);
        return true;
      },
      nullptr, &split);
    EXPECT_EQ(split.Calls, options.NumberOfIterations);
    EXPECT_EQ(split.Clouds, contract ? options.NumberOfIterations : 1);
    const std::vector<double> expectedFractions{ 0.25, 0.5, 0.75, 1.0 }; // 3 iterations, then the thinning
    EXPECT_EQ(fractions, expectedFractions);
    EXPECT_TRUE(over.Positions == here.Positions) << contract;
    EXPECT_TRUE(over.Axis == here.Axis);
    EXPECT_EQ(over.Confidence, here.Confidence);
    EXPECT_TRUE(over.LocalSpread == here.LocalSpread);
    EXPECT_TRUE(over.LocalNormal == here.LocalNormal);
    EXPECT_EQ(over.Thinned, here.Thinned);
    EXPECT_GT(std::count(here.Confidence.begin(), here.Confidence.end(), 0.0), 0) << "undefined points too";
    ASSERT_FALSE(here.Thinned.empty());
    // An abort after the first iteration stops there.
    split.Calls = 0;
    const ThinnedCloud stopped =
      ThinProjectedCloud(cloud, options, SerialFor, [&](double) { return false; }, nullptr, &split);
    EXPECT_TRUE(stopped.Aborted);
    EXPECT_EQ(split.Calls, 1);
    EXPECT_TRUE(stopped.Thinned.empty());
  }
}

} // namespace
