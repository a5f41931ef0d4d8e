// SPDX-License-Identifier: BSD-3-Clause
// Checks shared by the skeleton tests (TestSkeleton*.cpp): distances to the medial curve, the
// skeleton as a graph (components, degrees, length; a tree), the bones against their
// definition, and a well-formed SkeletonResult.
#pragma once

#include "Skeleton/Skeleton.h"
#include "TestShapes.h"

#include <Eigen/Core>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace shapediameter
{
namespace skeletontests
{

/// Distance from p to the line through a and b.
double LineDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b);

/// Distance from p to the segment ab.
double SegmentDistance(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b);

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

/// The graph of the skeleton's polylines; fails the test if it has a cycle.
GraphSummary Summarise(const SkeletonResult& result);

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
  const std::vector<std::int64_t>& nodeBone, const std::vector<double>& boneLength);

/// Number of distinct bones used by the polylines.
std::size_t BoneCount(const SkeletonResult& result);

/// Finite values, consistent sizes, node indices in range, faces linked to nodes and bones,
/// and the bones as ExpectBonesAreBranches wants them.
void ExpectWellFormed(const SkeletonResult& result, Eigen::Index faces);

/// ComputeSkeleton on a test mesh with its Sdf.
SkeletonResult RunSkeleton(const testshapes::TestMesh& mesh, const SkeletonOptions& options = {},
  const ParallelFor& parallelFor = SerialFor);

/// Checks a single straight skeleton along the medial segment a-b: every node within
/// maxDistance of the axis (the line through a and b), one path, total length within
/// lengthTolerance of |ab| (the extent along the axis is checked by the length).
void ExpectStraightSkeleton(const SkeletonResult& result, const Eigen::Vector3d& a,
  const Eigen::Vector3d& b, double maxDistance, double lengthTolerance);

} // namespace skeletontests
} // namespace shapediameter
