// SPDX-License-Identifier: BSD-3-Clause
// The skeleton's k-d tree (SkeletonPointTree.h) against brute force: radius and nearest
// queries, ties, ball moments, pruned accepted-nearest search, the empty tree.
#include "Skeleton/SkeletonPointTree.h"
#include "Skeleton/SkeletonSampling.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>

namespace
{

using namespace shapediameter;

TEST(SkeletonPointTree, MatchesBruteForce)
{
  std::mt19937_64 generator(3);
  const auto unit = [&generator] { return static_cast<double>(generator() >> 11) * 0x1.0p-53; };
  PointMatrix points(700, 3);
  for (Eigen::Index i = 0; i < points.rows(); ++i)
  {
    points.row(i) << 100.0 + unit(), 50.0 + unit(), unit() * 0.1;
  }
  points.row(5) = points.row(6); // duplicates
  points.row(7) = points.row(6);
  const SkeletonPointTree tree(points);
  std::vector<std::int64_t> found;
  std::vector<double> distances;
  for (int query = 0; query < 50; ++query)
  {
    const Eigen::Vector3d centre = query == 0 ? Eigen::Vector3d(points.row(6).transpose())
                                              : Eigen::Vector3d(100.0 + unit(), 50.0 + unit(), 0.05);
    const double radius = 0.05 + 0.3 * unit();
    SkeletonPointTree::Moments expected;
    std::vector<std::int64_t> inside;
    std::vector<std::pair<double, std::int64_t>> all;
    for (Eigen::Index i = 0; i < points.rows(); ++i)
    {
      const Eigen::Vector3d d = points.row(i).transpose() - centre;
      all.emplace_back(d.squaredNorm(), i);
      if (d.norm() <= radius)
      {
        inside.push_back(i);
        expected.Count += 1;
        expected.Sum += d;
        expected.SumOfSquares += d * d.transpose();
      }
    }
    const SkeletonPointTree::Moments moments = tree.BallMoments(centre, radius);
    EXPECT_EQ(moments.Count, expected.Count);
    EXPECT_LE((moments.Sum - expected.Sum).norm(), 1e-10 * std::max(1.0, expected.Count));
    EXPECT_LE((moments.SumOfSquares - expected.SumOfSquares).norm(), 1e-10 * std::max(1.0, expected.Count));
    tree.RadiusSearch(centre, radius, found);
    EXPECT_EQ(found, inside);
    std::sort(all.begin(), all.end());
    tree.NearestNeighbors(centre, 9, found, distances);
    ASSERT_EQ(found.size(), 9u);
    for (std::size_t k = 0; k < 9; ++k)
    {
      EXPECT_EQ(found[k], all[k].second);
    }
    const std::int64_t odd = tree.NearestAccepted(centre, [](std::int64_t i) { return i % 2 == 1; });
    const auto firstOdd = std::find_if(all.begin(), all.end(), [](const auto& e) { return e.second % 2 == 1; });
    EXPECT_EQ(odd, firstOdd->second);
  }
  // A blob of coincident points: nearest queries break the distance ties by lowest index.
  PointMatrix blob = PointMatrix::Constant(400, 3, 2.0);
  for (Eigen::Index i = 0; i < 400; i += 2)
  {
    blob.row(i) << unit(), unit(), unit();
  }
  const SkeletonPointTree blobTree(blob);
  blobTree.NearestNeighbors(Eigen::Vector3d::Constant(2.0), 5, found, distances);
  EXPECT_EQ(found, (std::vector<std::int64_t>{ 1, 3, 5, 7, 9 }));
  EXPECT_EQ(blobTree.NearestAccepted(Eigen::Vector3d::Constant(2.0),
              [](std::int64_t i) { return i > 100; }),
    101);
  // Label pruning: the nearest point outside the own label.
  std::vector<std::int64_t> labels(400);
  for (std::size_t i = 0; i < 400; ++i)
  {
    labels[i] = i % 2; // 1 = the blob
  }
  const std::vector<std::int64_t> nodeLabels = blobTree.NodeLabels(labels);
  const std::int64_t outside = blobTree.NearestAccepted(
    Eigen::Vector3d::Constant(2.0), [&](std::int64_t i) { return labels[i] != 1; }, &nodeLabels, 1);
  std::int64_t expectedOutside = -1;
  double nearestOutside = std::numeric_limits<double>::infinity();
  for (Eigen::Index i = 0; i < 400; i += 2)
  {
    const double d = (blob.row(i) - Eigen::RowVector3d::Constant(2.0)).squaredNorm();
    if (d < nearestOutside)
    {
      nearestOutside = d;
      expectedOutside = i;
    }
  }
  EXPECT_EQ(outside, expectedOutside);

  const SkeletonPointTree empty{ PointMatrix(0, 3) };
  EXPECT_EQ(empty.BallMoments(Eigen::Vector3d::Zero(), 1.0).Count, 0.0);
  EXPECT_EQ(empty.NearestAccepted(Eigen::Vector3d::Zero(), [](std::int64_t) { return true; }), -1);
}

} // namespace
