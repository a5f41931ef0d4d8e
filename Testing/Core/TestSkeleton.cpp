// SPDX-License-Identifier: BSD-3-Clause
// Tests of the SDF-guided skeleton core (paper section 5) on analytic shapes whose medial
// curve is known: capsule, prolate spheroid, torus, tripod of capsules, sphere.
#include "Skeleton.h"
#include "SkeletonTestShapes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <set>

namespace
{

using namespace shapediameter;
using namespace shapediameter::skeletontest;

double LineDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b)
{
  const Eigen::Vector3d direction = (b - a).normalized();
  const Eigen::Vector3d offset = p - a;
  return (offset - offset.dot(direction) * direction).norm();
}

double SegmentDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b)
{
  const Eigen::Vector3d ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (p - (a + t * ab)).norm();
}

/// The skeleton as an undirected graph on its nodes.
struct GraphSummary
{
  std::size_t Components = 0;
  std::vector<std::size_t> Degree;
  double Length = 0.0;
  std::vector<std::int64_t> ComponentOfNode;

  std::size_t CountDegree(std::size_t d) const
  {
    return static_cast<std::size_t>(std::count(Degree.begin(), Degree.end(), d));
  }
  std::size_t MaxDegree() const
  {
    return Degree.empty() ? 0 : *std::max_element(Degree.begin(), Degree.end());
  }
};

GraphSummary Summarise(const SkeletonResult& result)
{
  GraphSummary summary;
  const auto nodes = static_cast<std::size_t>(result.NodePositions.rows());
  std::set<std::pair<std::int64_t, std::int64_t>> edges;
  for (const auto& polyline : result.Polylines)
  {
    for (std::size_t i = 1; i < polyline.size(); ++i)
    {
      if (polyline[i - 1] != polyline[i])
      {
        edges.emplace(std::min(polyline[i - 1], polyline[i]), std::max(polyline[i - 1], polyline[i]));
      }
    }
  }
  std::vector<std::int64_t> parent(nodes);
  std::iota(parent.begin(), parent.end(), 0);
  const std::function<std::int64_t(std::int64_t)> find = [&](std::int64_t i) {
    return parent[i] == i ? i : parent[i] = find(parent[i]);
  };
  summary.Degree.assign(nodes, 0);
  for (const auto& [a, b] : edges)
  {
    ++summary.Degree[a];
    ++summary.Degree[b];
    summary.Length += (result.NodePositions.row(a) - result.NodePositions.row(b)).norm();
    parent[find(a)] = find(b);
  }
  std::set<std::int64_t> roots;
  summary.ComponentOfNode.resize(nodes);
  for (std::size_t i = 0; i < nodes; ++i)
  {
    summary.ComponentOfNode[i] = find(static_cast<std::int64_t>(i));
    roots.insert(summary.ComponentOfNode[i]);
  }
  summary.Components = roots.size();
  // A tree has exactly nodes - components edges.
  EXPECT_EQ(edges.size() + summary.Components, nodes) << "the skeleton has a cycle";
  return summary;
}

template <typename Vector>
bool AllFinite(const Vector& values)
{
  return std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); });
}

void ExpectWellFormed(const SkeletonResult& result, Eigen::Index faces)
{
  const Eigen::Index nodes = result.NodePositions.rows();
  EXPECT_TRUE(result.NodePositions.allFinite());
  EXPECT_TRUE(AllFinite(result.NodeRadius));
  EXPECT_TRUE(AllFinite(result.NodeConfidence));
  EXPECT_TRUE(result.CloudPositions.allFinite());
  EXPECT_TRUE(AllFinite(result.CloudRadius));
  EXPECT_TRUE(AllFinite(result.CloudConfidence));
  EXPECT_EQ(result.NodeRadius.size(), static_cast<std::size_t>(nodes));
  EXPECT_EQ(result.NodeConfidence.size(), static_cast<std::size_t>(nodes));
  EXPECT_EQ(result.NodeBoneId.size(), static_cast<std::size_t>(nodes));
  EXPECT_EQ(result.BoneId.size(), result.Polylines.size());
  EXPECT_EQ(result.IsConnection.size(), result.Polylines.size());
  for (const auto& polyline : result.Polylines)
  {
    EXPECT_FALSE(polyline.empty());
    for (const std::int64_t node : polyline)
    {
      EXPECT_TRUE(node >= 0 && node < nodes);
    }
  }
  for (const double c : result.NodeConfidence)
  {
    EXPECT_TRUE(c >= 0.0 && c <= 1.0);
  }
  ASSERT_EQ(result.FaceNodeId.size(), static_cast<std::size_t>(faces));
  ASSERT_EQ(result.FaceBoneId.size(), static_cast<std::size_t>(faces));
  for (std::size_t f = 0; f < result.FaceNodeId.size(); ++f)
  {
    ASSERT_TRUE(result.FaceNodeId[f] >= 0 && result.FaceNodeId[f] < nodes);
    EXPECT_EQ(result.FaceBoneId[f], result.NodeBoneId[result.FaceNodeId[f]]);
  }
  EXPECT_EQ(result.CloudPositions.rows(), static_cast<Eigen::Index>(result.CloudRadius.size()));
  EXPECT_EQ(result.CloudSourceFace.size(), result.CloudRadius.size());
}

SkeletonResult RunSkeleton(const TestMesh& mesh, const SkeletonOptions& options = {},
  const ParallelFor& parallelFor = SerialFor)
{
  return ComputeSkeleton(mesh.Points, mesh.Triangles, mesh.Sdf, options, parallelFor);
}

/// Checks a single straight skeleton along the medial segment a-b: every node within
/// maxDistance of the axis (the line through a and b), one path, total length within
/// lengthTolerance of |ab| (the extent along the axis is checked by the length).
void ExpectStraightSkeleton(const SkeletonResult& result, const Eigen::Vector3d& a,
  const Eigen::Vector3d& b, double maxDistance, double lengthTolerance)
{
  double worst = 0.0;
  for (Eigen::Index n = 0; n < result.NodePositions.rows(); ++n)
  {
    worst = std::max(worst, LineDistance(result.NodePositions.row(n).transpose(), a, b));
  }
  EXPECT_LE(worst, maxDistance);
  const GraphSummary graph = Summarise(result);
  EXPECT_EQ(graph.Components, 1u);
  EXPECT_LE(graph.MaxDegree(), 2u) << "not a single polyline";
  EXPECT_EQ(graph.CountDegree(1), 2u) << "a path has two ends";
  const double expected = (b - a).norm();
  EXPECT_NEAR(graph.Length, expected, lengthTolerance * expected);
}

// ---------------------------------------------------------------------------------------------
// Test shapes themselves

TEST(SkeletonTestShapes, ClosedAndOutward)
{
  const double pi = Pi;
  EXPECT_NEAR(SignedVolume(MakeCapsule(1.0, 3.0, 96, 24, 40)),
    pi * 6.0 + 4.0 / 3.0 * pi, 0.02 * (6.0 * pi + 4.0 / 3.0 * pi));
  EXPECT_NEAR(SignedVolume(MakeTorus(6.0, 1.0)), 2.0 * pi * pi * 6.0, 0.03 * 2.0 * pi * pi * 6.0);
  EXPECT_NEAR(SignedVolume(MakeProlateSpheroid(5.0, 1.0)), 4.0 / 3.0 * pi * 5.0, 0.02 * 4.0 / 3.0 * pi * 5.0);
  EXPECT_GT(SignedVolume(MakeTripod(5.0, 1.0, 120, 60)), 3.0 * pi * 4.0);
  EXPECT_GT(SignedVolume(MakeSphere(1.0)), 0.0);
}

// ---------------------------------------------------------------------------------------------
// Step 1: sampling

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

// ---------------------------------------------------------------------------------------------
// The spatial index

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
    tree.NearestNeighbours(centre, 9, found, distances);
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
  blobTree.NearestNeighbours(Eigen::Vector3d::Constant(2.0), 5, found, distances);
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

// ---------------------------------------------------------------------------------------------
// Step 2: MLS thinning

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

TEST(SkeletonThinning, InvalidOptionsThrow)
{
  ProjectedCloud cloud;
  SkeletonThinningOptions options;
  options.NumberOfIterations = 0;
  EXPECT_THROW(ThinProjectedCloud(cloud, options, SerialFor), SkeletonError);
  options = {};
  options.ConfidenceThreshold = std::nan("");
  EXPECT_THROW(ThinProjectedCloud(cloud, options, SerialFor), SkeletonError);
  options = {};
  options.NeighbourhoodScale = 0.0;
  EXPECT_THROW(ThinProjectedCloud(cloud, options, SerialFor), SkeletonError);
}

// ---------------------------------------------------------------------------------------------
// Whole pipeline on analytic shapes

TEST(Skeleton, CapsuleIsItsAxis)
{
  // Cylinder radius r = 1, cap centres at z = -4 and z = +4: the medial curve is that segment.
  const TestMesh capsule = MakeCapsule(1.0, 4.0);
  const SkeletonResult result = RunSkeleton(capsule);
  ExpectWellFormed(result, capsule.Faces());
  ExpectStraightSkeleton(result, { 0, 0, -4 }, { 0, 0, 4 }, 0.05, 0.10);
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

TEST(Skeleton, CapsuleWithNoisySdf)
{
  // +-15 % noise on every face's SDF scatters P by up to 0.15 r across the axis.
  TestMesh capsule = MakeCapsule(1.0, 4.0);
  AddSdfNoise(capsule, 0.15);
  const SkeletonResult result = RunSkeleton(capsule);
  ExpectWellFormed(result, capsule.Faces());
  ExpectStraightSkeleton(result, { 0, 0, -4 }, { 0, 0, 4 }, 0.05, 0.10);
}

TEST(Skeleton, CapsuleWithRayCastSdf)
{
  // A coarse capsule with a brute-force cone SDF: shorter diameters near the caps, noise from
  // the facets. The skeleton stays on the axis; its ends may fall short of the cap centres.
  TestMesh capsule = MakeCapsule(1.0, 4.0, 24, 6, 16);
  capsule.Sdf = RayCastSdf(capsule);
  const SkeletonResult result = RunSkeleton(capsule);
  ExpectWellFormed(result, capsule.Faces());
  ExpectStraightSkeleton(result, { 0, 0, -4 }, { 0, 0, 4 }, 0.05, 0.10);
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
}

/// Three branches from the cap centres meeting in one junction near the origin.
/// Branch ends must lie within endTolerance of the cap centres.
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
  // Every node near one of the three axes, every branch end near a cap centre.
  const std::vector<Arm> arms = TripodArms(length, r);
  std::set<std::size_t> armsReached;
  for (Eigen::Index n = 0; n < result.NodePositions.rows(); ++n)
  {
    const Eigen::Vector3d p = result.NodePositions.row(n).transpose();
    double nearest = std::numeric_limits<double>::infinity();
    for (const Arm& arm : arms)
    {
      nearest = std::min(nearest, SegmentDistance(p, Eigen::Vector3d::Zero(), arm.Length * arm.Direction));
    }
    EXPECT_LE(nearest, 0.25 * r);
    if (graph.Degree[n] == 1)
    {
      for (std::size_t a = 0; a < arms.size(); ++a)
      {
        if ((p - arms[a].Length * arms[a].Direction).norm() < endTolerance)
        {
          armsReached.insert(a);
        }
      }
    }
  }
  EXPECT_EQ(armsReached.size(), 3u);
}

TEST(Skeleton, TripodHasThreeBranchesAndOneJunction)
{
  ExpectTripodSkeleton(MakeTripod(5.0, 1.0), 5.0, 1.0, 0.5);
}

TEST(Skeleton, TripodWithRayCastSdf)
{
  // Coarse tripod (7.5 degree facets), brute-force cone SDF: larger diameters and scattered
  // points at the junction, shorter diameters on the caps (the branches stop short of the cap
  // centres by about half a radius).
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
  // Faces link to nodes of their own capsule.
  for (Eigen::Index f = 0; f < both.Faces(); ++f)
  {
    const Eigen::Vector3d node = result.NodePositions.row(result.FaceNodeId[f]).transpose();
    const bool onFirst = std::hypot(node.x(), node.y()) < 0.1;
    ASSERT_EQ(onFirst, f < first.Faces());
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
  EXPECT_THROW(ComputeSkeleton(capsule.Points, badIndex, capsule.Sdf), SkeletonError);
  badIndex(3, 1) = -1;
  EXPECT_THROW(ComputeSkeleton(capsule.Points, badIndex, capsule.Sdf), SkeletonError);
  PointMatrix nanPoints = capsule.Points;
  nanPoints(2, 0) = std::nan("");
  EXPECT_THROW(ComputeSkeleton(nanPoints, capsule.Triangles, capsule.Sdf), SkeletonError);
  std::vector<double> sdf = capsule.Sdf;
  sdf[5] = std::numeric_limits<double>::infinity();
  EXPECT_THROW(ComputeSkeleton(capsule.Points, capsule.Triangles, sdf), SkeletonError);
  sdf[5] = -1.0;
  EXPECT_THROW(ComputeSkeleton(capsule.Points, capsule.Triangles, sdf), SkeletonError);
  sdf.pop_back();
  EXPECT_THROW(ComputeSkeleton(capsule.Points, capsule.Triangles, sdf), SkeletonError);
  EXPECT_THROW(ComputeSkeleton(capsule.Points, capsule.Triangles, capsule.Sdf, PointMatrix(3, 3),
                 {}, {}, SerialFor),
    SkeletonError);
  EXPECT_THROW(ComputeSkeleton(capsule.Points, capsule.Triangles, capsule.Sdf, PointMatrix(),
                 { 1, 2 }, {}, SerialFor),
    SkeletonError);
  SkeletonOptions options;
  options.Sampling.NumberOfSamples = 0;
  EXPECT_THROW(RunSkeleton(capsule, options), SkeletonError);
  options = {};
  options.Segments.AngularToleranceDegrees = 90.0;
  EXPECT_THROW(RunSkeleton(capsule, options), SkeletonError);
  options = {};
  options.Connection.NumberOfNeighbours = 0;
  EXPECT_THROW(RunSkeleton(capsule, options), SkeletonError);
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
