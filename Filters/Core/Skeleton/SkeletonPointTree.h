// SPDX-License-Identifier: BSD-3-Clause
// Static 3-D k-d tree over a point set, shared by the skeleton steps (thinning, segments,
// connection, and ComputeSkeleton's face-to-node assignment).
//
// What it answers
//   Radius queries (indices ascending), k nearest neighbours ordered by (distance, index), the
//   nearest point passing a predicate (with subtrees pruned by a per-node label), and the
//   moments (count, first and second moments) of all points inside a ball. Per-node moments
//   make a ball's moments cost O(log n + boundary) instead of O(points inside): the MLS step
//   queries neighbourhoods holding thousands of points. Balls and radii are closed (|x - c| <=
//   r). All queries are deterministic (fixed traversal order, ties broken by point index) and
//   thread-safe; an empty point set gives a tree where every query returns nothing.
//
// Why not nanoflann (already used by Testing/Evaluation)
//   nanoflann (1.4 and 1.7) has no per-node moments (BallMoments, the MLS step's query) and no
//   pruned "nearest accepted" search, and where it overlaps it answers differently: its radius
//   search keeps |x - c| < r (ours <=), and its k-nearest search admits a candidate only if
//   strictly closer than the current k-th, so which of several equidistant points is kept
//   depends on its traversal order, not on the index. Coincident points are common here (an exact SDF sends a
//   whole cap to one point), so switching would change skeletons; identity wins.
#pragma once

#include "Mesh/MeshTypes.h"

#include <Eigen/Core>

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace shapediameter
{

/// k-d tree over a fixed point set with ball moments; see the file comment.
class SkeletonPointTree
{
public:
  /// Moments of a point set about a centre c: Count, Sum of (x - c), Sum of (x - c)(x - c)^T.
  struct Moments
  {
    double Count = 0.0;
    Eigen::Vector3d Sum = Eigen::Vector3d::Zero();
    Eigen::Matrix3d SumOfSquares = Eigen::Matrix3d::Zero();
  };

  /// Copies the points. An empty point set gives a tree where every query returns nothing.
  explicit SkeletonPointTree(PointsView points);

  std::size_t Size() const { return Index.size(); }
  /// Moments about `centre` of all points x with |x - centre| <= radius. Stored per-node
  /// moments are about the node's own centre and shifted exactly, so there is no cancellation
  /// from large coordinates: the error is relative to radius^2.
  Moments BallMoments(const Eigen::Vector3d& centre, double radius) const;

  /// Indices of all points with |x - centre| <= radius, ascending.
  void RadiusSearch(
    const Eigen::Vector3d& centre, double radius, std::vector<std::int64_t>& indices) const;

  /// The k nearest points, ordered by (distance, index); fewer if the tree is smaller.
  void NearestNeighbors(const Eigen::Vector3d& centre, std::size_t k,
    std::vector<std::int64_t>& indices, std::vector<double>& squaredDistances) const;

  /// The nearest point for which accept(index) is true (an empty accept takes every point),
  /// ties to the lowest index; -1 if none. With nodeLabels (from NodeLabels), subtrees whose
  /// points all carry skipLabel are pruned without visiting them, which keeps "nearest point
  /// outside my own cluster" queries logarithmic instead of linear in the cluster size.
  std::int64_t NearestAccepted(const Eigen::Vector3d& centre,
    const std::function<bool(std::int64_t)>& accept,
    const std::vector<std::int64_t>* nodeLabels = nullptr, std::int64_t skipLabel = -1) const;

  /// Per tree node: the label shared by every point below it, or -1 if they differ.
  /// pointLabels holds one label >= 0 per input point.
  std::vector<std::int64_t> NodeLabels(const std::vector<std::int64_t>& pointLabels) const;

private:
  /// Count, sums of x, y, z and of xx, xy, xz, yy, yz, zz about a node's box centre.
  struct RawMoments
  {
    double Values[10] = {};
  };
  struct Node
  {
    double Lower[3];
    double Upper[3];
    double Centre[3];
    std::uint32_t Begin = 0;
    std::uint32_t End = 0;
    std::int32_t Left = -1;
    std::int32_t Right = -1;
    /// Lowest input index below the node: lets nearest searches prune exact distance ties
    /// (coincident points are common: an exact SDF sends a whole cap to one point).
    std::int64_t MinIndex = 0;
    RawMoments Sums;
  };

  std::int32_t Build(std::uint32_t begin, std::uint32_t end);

  std::vector<double> Coordinates;  // x, y, z of each point, in tree order
  std::vector<std::int64_t> Index;  // tree order -> input index
  std::vector<Node> Nodes;
};

} // namespace shapediameter
