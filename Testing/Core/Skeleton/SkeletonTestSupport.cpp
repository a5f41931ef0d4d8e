// SPDX-License-Identifier: BSD-3-Clause
#include "Skeleton/SkeletonTestSupport.h"

#include <gtest/gtest.h>

#include <functional>
#include <limits>
#include <map>
#include <numeric>
#include <set>
#include <utility>

namespace shapediameter
{
namespace skeletontests
{

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

SkeletonResult RunSkeleton(const testshapes::TestMesh& mesh, const SkeletonOptions& options,
  const ParallelFor& parallelFor)
{
  return ComputeSkeleton(mesh.Points, mesh.Triangles, mesh.Sdf, options, parallelFor);
}

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

} // namespace skeletontests
} // namespace shapediameter
