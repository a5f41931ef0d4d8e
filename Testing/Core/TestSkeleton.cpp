// SPDX-License-Identifier: BSD-3-Clause
// Tests of the SDF-guided skeleton core (paper section 5) on analytic shapes whose medial
// curve is known: capsule, prolate spheroid, torus, tripod of capsules, sphere; the bones
// (branches of the tree) on hand-made graphs; and the shared articulated figure in two poses
// with the real (ray-cast, smoothed) SDF.
#include "ArticulatedFigure.h"
#include "BilateralSmoothing.h"
#include "FaceGraph.h"
#include "ShapeDiameter.h"
#include "Skeleton.h"
#include "SkeletonPointTree.h"
#include "TestShapes.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <set>

namespace
{

using namespace shapediameter;
using namespace shapediameter::testshapes;

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

/// Checks the bones against the definition, computed independently of AssignBranchBones:
/// every polyline lies in one branch (no interior node of degree != 2), the number of bones is
/// the number of branches of the forest (half the sum of the degrees of ends and junctions,
/// plus isolated nodes), every bone is used, its length is the sum of its edges, lengths do
/// not increase, and a node's bone is the lowest bone among its edges.
void ExpectBonesAreBranches(const PointMatrix& nodes,
  const std::vector<std::vector<std::int64_t>>& polylines, const std::vector<std::int64_t>& boneId,
  const std::vector<std::int64_t>& nodeBone, const std::vector<double>& boneLength)
{
  const auto nodeCount = static_cast<std::size_t>(nodes.rows());
  ASSERT_EQ(boneId.size(), polylines.size());
  ASSERT_EQ(nodeBone.size(), nodeCount);
  std::map<std::pair<std::int64_t, std::int64_t>, std::int64_t> edgeBone;
  std::vector<std::set<std::int64_t>> neighbours(nodeCount);
  std::vector<std::int64_t> singleBone(nodeCount, -1);
  const auto bones = static_cast<std::int64_t>(boneLength.size());
  for (std::size_t p = 0; p < polylines.size(); ++p)
  {
    ASSERT_TRUE(boneId[p] >= 0 && boneId[p] < bones);
    const auto& polyline = polylines[p];
    ASSERT_FALSE(polyline.empty());
    if (polyline.size() == 1)
    {
      singleBone[polyline[0]] = boneId[p];
    }
    for (std::size_t i = 1; i < polyline.size(); ++i)
    {
      const auto edge = std::minmax(polyline[i - 1], polyline[i]);
      if (edge.first == edge.second)
      {
        continue;
      }
      const auto inserted = edgeBone.emplace(edge, boneId[p]);
      EXPECT_EQ(inserted.first->second, boneId[p]) << "an edge in two bones";
      neighbours[edge.first].insert(edge.second);
      neighbours[edge.second].insert(edge.first);
    }
  }
  std::size_t endDegrees = 0;
  std::size_t isolated = 0;
  for (std::size_t n = 0; n < nodeCount; ++n)
  {
    const std::size_t degree = neighbours[n].size();
    endDegrees += degree == 2 ? 0 : degree;
    isolated += degree == 0 ? 1 : 0;
  }
  EXPECT_EQ(static_cast<std::size_t>(bones), endDegrees / 2 + isolated);
  for (const auto& polyline : polylines)
  {
    for (std::size_t i = 1; i + 1 < polyline.size(); ++i)
    {
      EXPECT_EQ(neighbours[polyline[i]].size(), 2u) << "a polyline runs through a junction";
    }
  }
  std::vector<double> length(static_cast<std::size_t>(bones), 0.0);
  std::vector<std::int64_t> lowest(nodeCount, std::numeric_limits<std::int64_t>::max());
  for (const auto& [edge, bone] : edgeBone)
  {
    length[bone] += (nodes.row(edge.first) - nodes.row(edge.second)).norm();
    lowest[edge.first] = std::min(lowest[edge.first], bone);
    lowest[edge.second] = std::min(lowest[edge.second], bone);
  }
  std::set<std::int64_t> used(boneId.begin(), boneId.end());
  EXPECT_EQ(used.size(), static_cast<std::size_t>(bones)) << "a bone without a polyline";
  for (std::int64_t b = 0; b < bones; ++b)
  {
    EXPECT_TRUE(std::isfinite(boneLength[b]));
    EXPECT_NEAR(boneLength[b], length[b], 1e-9 * (1.0 + length[b]));
    if (b > 0)
    {
      EXPECT_GE(boneLength[b - 1], boneLength[b]);
    }
  }
  for (std::size_t n = 0; n < nodeCount; ++n)
  {
    EXPECT_EQ(nodeBone[n], neighbours[n].empty() ? singleBone[n] : lowest[n]) << "node " << n;
  }
}

/// Number of distinct bones used by the polylines.
std::size_t BoneCount(const SkeletonResult& result)
{
  return std::set<std::int64_t>(result.BoneId.begin(), result.BoneId.end()).size();
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
  ExpectBonesAreBranches(result.NodePositions, result.Polylines, result.BoneId,
    result.NodeBoneId, result.BoneLength);
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
  EXPECT_EQ(result.BoneLength.size(), 1u) << "a path is one bone";
  EXPECT_TRUE(std::all_of(result.FaceBoneId.begin(), result.FaceBoneId.end(),
    [](std::int64_t bone) { return bone == 0; }));
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
  EXPECT_THROW(ThinProjectedCloud(cloud, bad, SerialFor), SkeletonError);
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
  options.NeighborhoodScale = 0.0;
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
  EXPECT_EQ(result.BoneLength.size(), 1u) << "an open loop is one branch";
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
  // The longer capsule's axis (length 6) is bone 0, the shorter one's (length 4) bone 1.
  EXPECT_NEAR(result.BoneLength[0], 6.0, 0.6);
  EXPECT_NEAR(result.BoneLength[1], 4.0, 0.4);
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
// Bones: the branches of the tree

SkeletonGraph MakeGraph(const std::vector<Eigen::Vector3d>& positions,
  std::vector<std::vector<std::int64_t>> polylines, std::vector<int> isConnection)
{
  SkeletonGraph graph;
  graph.NodePositions.resize(static_cast<Eigen::Index>(positions.size()), 3);
  for (std::size_t i = 0; i < positions.size(); ++i)
  {
    graph.NodePositions.row(static_cast<Eigen::Index>(i)) = positions[i].transpose();
  }
  graph.Polylines = std::move(polylines);
  graph.IsConnection = std::move(isConnection);
  return graph;
}

TEST(SkeletonBones, PolylineThroughAJunctionIsCut)
{
  // A fitted segment 0-1-2-3-4 along x (2 units left of node 2, 3 units right of it), a
  // connecting path 2-5-6 leaving node 2 along y (1 unit), a blob node 7 and a node 8 that no
  // polyline holds. Branches: 2..4 (3), 0..2 (2), 2..6 (1), {7}, {8}.
  SkeletonGraph graph = MakeGraph({ { -2, 0, 0 }, { -1, 0, 0 }, { 0, 0, 0 }, { 1.5, 0, 0 },
                                    { 3, 0, 0 }, { 0, 0.5, 0 }, { 0, 1, 0 }, { 9, 9, 9 }, { 8, 8, 8 } },
    { { 0, 1, 2, 3, 4 }, { 2, 5, 6 }, { 7 } }, { 0, 1, 0 });
  AssignBranchBones(graph);
  const std::vector<std::vector<std::int64_t>> polylines{ { 0, 1, 2 }, { 2, 3, 4 }, { 2, 5, 6 },
    { 7 }, { 8 } };
  EXPECT_EQ(graph.Polylines, polylines);
  EXPECT_EQ(graph.IsConnection, (std::vector<int>{ 0, 0, 1, 0, 0 }));
  EXPECT_EQ(graph.PolylineBone, (std::vector<std::int64_t>{ 1, 0, 2, 3, 4 }));
  EXPECT_EQ(graph.BoneLength, (std::vector<double>{ 3.0, 2.0, 1.0, 0.0, 0.0 }));
  // The junction takes the lowest (longest) bone meeting there.
  EXPECT_EQ(graph.NodeBone, (std::vector<std::int64_t>{ 1, 1, 0, 0, 0, 2, 2, 3, 4 }));
  ExpectBonesAreBranches(graph.NodePositions, graph.Polylines, graph.PolylineBone,
    graph.NodeBone, graph.BoneLength);

  // Idempotent.
  const SkeletonGraph again = [&graph] {
    SkeletonGraph copy = graph;
    AssignBranchBones(copy);
    return copy;
  }();
  EXPECT_EQ(again.Polylines, graph.Polylines);
  EXPECT_EQ(again.PolylineBone, graph.PolylineBone);
  EXPECT_EQ(again.NodeBone, graph.NodeBone);
  EXPECT_EQ(again.BoneLength, graph.BoneLength);
}

TEST(SkeletonBones, PiecesOfOneBranchShareItsBone)
{
  // A path cut into three polylines (segment, connection, segment) is one bone; the same path
  // with a side branch at node 3 is three.
  std::vector<Eigen::Vector3d> positions;
  for (int i = 0; i < 7; ++i)
  {
    positions.emplace_back(i, 0, 0);
  }
  SkeletonGraph path = MakeGraph(positions, { { 0, 1, 2 }, { 2, 3, 4 }, { 4, 5, 6 } }, { 0, 1, 0 });
  AssignBranchBones(path);
  EXPECT_EQ(path.PolylineBone, (std::vector<std::int64_t>{ 0, 0, 0 }));
  EXPECT_EQ(path.Polylines.size(), 3u);
  EXPECT_EQ(path.BoneLength, std::vector<double>{ 6.0 });

  positions.emplace_back(3, 2, 0);
  SkeletonGraph branched =
    MakeGraph(positions, { { 0, 1, 2 }, { 2, 3, 4 }, { 4, 5, 6 }, { 3, 7 } }, { 0, 1, 0, 1 });
  AssignBranchBones(branched);
  // Branches 0..3 and 3..6 both have length 3: the one with the lower node (0) comes first.
  EXPECT_EQ(branched.Polylines, (std::vector<std::vector<std::int64_t>>{
                                  { 0, 1, 2 }, { 2, 3 }, { 3, 4 }, { 4, 5, 6 }, { 3, 7 } }));
  EXPECT_EQ(branched.IsConnection, (std::vector<int>{ 0, 1, 1, 0, 1 }));
  EXPECT_EQ(branched.PolylineBone, (std::vector<std::int64_t>{ 0, 0, 1, 1, 2 }));
  EXPECT_EQ(branched.BoneLength, (std::vector<double>{ 3.0, 3.0, 2.0 }));
  EXPECT_EQ(branched.NodeBone[3], 0);
  ExpectBonesAreBranches(branched.NodePositions, branched.Polylines, branched.PolylineBone,
    branched.NodeBone, branched.BoneLength);
}

TEST(SkeletonBones, LoopsRepeatsAndBadIndices)
{
  // A closed square (not produced by the steps, but accepted) is one bone cut at node 0; a
  // repeated node and an edge held by two polylines do not create bones.
  SkeletonGraph loop = MakeGraph({ { 0, 0, 0 }, { 1, 0, 0 }, { 1, 1, 0 }, { 0, 1, 0 } },
    { { 1, 2, 2, 3 }, { 3, 0, 1 }, { 0, 1 } }, { 0, 1, 1 });
  AssignBranchBones(loop);
  EXPECT_EQ(loop.BoneLength, std::vector<double>{ 4.0 });
  EXPECT_EQ(loop.PolylineBone, (std::vector<std::int64_t>{ 0, 0, 0 }));
  EXPECT_EQ(loop.NodeBone, (std::vector<std::int64_t>{ 0, 0, 0, 0 }));
  EXPECT_EQ(loop.Polylines[0], (std::vector<std::int64_t>{ 1, 2, 2, 3 }));

  SkeletonGraph empty = MakeGraph({}, {}, {});
  AssignBranchBones(empty);
  EXPECT_TRUE(empty.BoneLength.empty() && empty.Polylines.empty() && empty.NodeBone.empty());

  SkeletonGraph bad = MakeGraph({ { 0, 0, 0 } }, { { 0, 1 } }, { 0 });
  EXPECT_THROW(AssignBranchBones(bad), SkeletonError);
  bad = MakeGraph({ { 0, 0, 0 } }, { { 0 } }, {});
  EXPECT_THROW(AssignBranchBones(bad), SkeletonError);
}

TEST(SkeletonBones, JunctionCleaning)
{
  // A torso 0..9 along y (radius 2), an arm joining it at vertex 3 by a connecting path
  // 3-10-11-12 whose fitted segment 19-18-12-...-17 overshoots back towards the torso (stub
  // 12-18-19, longer than the arm's radius at 12 but ending inside the torso's ball), a second
  // arm joining at vertex 4 (one unit from 3: an inner branch shorter than the radius), a long
  // arm from 6 whose hand rests inside the torso's ball near vertex 2 (kept: longer than two
  // radii), and a big ball of another component (ignored).
  std::map<std::int64_t, Eigen::Vector3d> position;
  std::map<std::int64_t, double> radius;
  std::map<std::int64_t, std::int64_t> component;
  const auto add = [&](std::int64_t v, double x, double y, double r, std::int64_t c = 0) {
    position[v] = Eigen::Vector3d(x, y, 0);
    radius[v] = r;
    component[v] = c;
  };
  for (int i = 0; i <= 9; ++i)
  {
    add(i, 0, i, 2.0);
  }
  for (int i = 10; i <= 17; ++i)
  {
    add(i, i - 9, 3, 0.5);
  }
  add(18, 2.2, 3.3, 0.5);
  add(19, 1.5, 3.4, 0.5);
  for (int i = 50; i <= 55; ++i)
  {
    add(i, -(i - 49), 4, 0.5);
  }
  add(40, -1, 6, 0.5);
  add(41, -2, 6, 0.5);
  add(42, -3, 5, 0.5);
  add(43, -3, 4, 0.5);
  add(44, -3, 3, 0.5);
  add(45, -1.5, 1.8, 0.5);
  add(99, 8.5, 3, 5.0, 1);
  const std::vector<std::vector<std::int64_t>> input{ { 0, 1, 2, 3, 4, 5, 6, 7, 8, 9 },
    { 3, 10, 11, 12 }, { 19, 18, 12, 13, 14, 15, 16, 17 }, { 4, 50 }, { 50, 51, 52, 53, 54, 55 },
    { 6, 40, 41, 42, 43, 44, 45 }, { 99 } };
  const std::vector<int> inputIsConnection{ 0, 1, 0, 1, 0, 1, 0 };
  const auto positionOf = [&](std::int64_t v) { return position.at(v); };
  const auto radiusOf = [&](std::int64_t v) { return radius.at(v); };
  const auto componentOf = [&](std::int64_t v) { return component.at(v); };

  std::vector<std::vector<std::int64_t>> polylines = input;
  std::vector<int> isConnection = inputIsConnection;
  CleanJunctions(polylines, isConnection, positionOf, radiusOf, componentOf, 1.0);
  const std::vector<std::vector<std::int64_t>> expected{ { 0, 1, 2, 3, 5, 6, 7, 8, 9 },
    { 3, 10, 11, 12 }, { 12, 13, 14, 15, 16, 17 }, { 3, 50 }, { 50, 51, 52, 53, 54, 55 },
    { 6, 40, 41, 42, 43, 44, 45 }, { 99 } };
  EXPECT_EQ(polylines, expected);
  EXPECT_EQ(isConnection, inputIsConnection);

  // Factor 0 keeps everything; a single path is never cut.
  polylines = input;
  isConnection = inputIsConnection;
  CleanJunctions(polylines, isConnection, positionOf, radiusOf, componentOf, 0.0);
  EXPECT_EQ(polylines, input);
  polylines = { { 0, 1 } };
  isConnection = { 0 };
  CleanJunctions(polylines, isConnection, positionOf, radiusOf, componentOf, 10.0);
  EXPECT_EQ(polylines, (std::vector<std::vector<std::int64_t>>{ { 0, 1 } }));
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
  // skeleton ends in a stub above the torso (0.21-0.34 long, junction radius 0.23-0.25) that
  // the leaf pruning keeps in some poses and not in others (the bent pose keeps it with the
  // default HitRule 0; issue #22). So 5 or 6 bones are sane, plus one torso piece if arms and
  // legs met the torso at separate junctions, and the poses must agree on the long bones
  // (limbs 0.9-1.0, torso 0.6-0.7).
  using namespace shapediameter::testing;
  const ArticulatedFigureTemplate figure;
  FigurePose bent;
  bent.LeftArm = 0.9;
  bent.RightArm = -0.6;
  bent.LeftLeg = 0.5;
  bent.RightLeg = -0.4;
  std::vector<std::size_t> boneCounts, longBoneCounts;
  for (const FigurePose& pose : { FigurePose{}, bent })
  {
    const FigureSkeleton result = SkeletonOfFigure(figure, pose);
    const SkeletonResult& skeleton = result.Skeleton;
    ExpectWellFormed(skeleton, result.Figure.Triangles.rows());
    const GraphSummary graph = Summarise(skeleton);
    EXPECT_EQ(graph.Components, 1u);
    boneCounts.push_back(BoneCount(skeleton));
    EXPECT_EQ(boneCounts.back(), skeleton.BoneLength.size());
    longBoneCounts.push_back(static_cast<std::size_t>(std::count_if(skeleton.BoneLength.begin(),
      skeleton.BoneLength.end(), [](double length) { return length > 0.45; })));
    EXPECT_GE(boneCounts.back(), 5u);
    EXPECT_LE(boneCounts.back(), 7u);
    const std::size_t ends = graph.CountDegree(1);
    EXPECT_TRUE(ends == 4u || ends == 5u) << ends << " ends: four limbs, maybe the head";

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
  EXPECT_EQ(longBoneCounts[0], longBoneCounts[1]);
  EXPECT_GE(longBoneCounts[0], 5u) << "four limbs and the torso";
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
  options.Connection.NumberOfNeighbors = 0;
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
