// SPDX-License-Identifier: BSD-3-Clause
// SDF-guided skeleton, tree topology: junction cleaning and bones (the branches of the tree).
//
// What it computes
//   The last two stages of step 4 (SkeletonConnection.h), on the skeleton as a graph of
//   polylines; nothing here looks at the mesh or the cloud.
//   Junction cleaning (CleanJunctions), with f = MinimumBranchFactor, repeated until nothing
//   changes: a leaf branch (from a leaf node to the first node of degree >= 3) is removed if it
//   is shorter than f * radius at that junction, or if it is shorter than 2 f * radius(v) and
//   its end lies within f * radius(v) of a node v off the branch (a stub inside another part's
//   medial ball, typically a segment end overshooting the point where a connecting path joins
//   it); then an inner branch (between two junctions) shorter than f * the larger radius of its
//   junctions is contracted into the junction of larger radius, so parts meeting at one place
//   (two arms joining the torso a little apart) give one junction and no spurious short bone. A
//   tree that is a single path is never cut.
//   Deviation: the paper does not prune; without it, noisy SDF leaves stubs of a few nodes
//   beside junctions and splits junctions, so the number of branches (bones) would change with
//   noise and pose; a part shorter than its own radius is a bump rather than a limb.
//   Bones (AssignBranchBones): the branches of the forest, the maximal paths whose interior
//   nodes have degree 2; the polylines are cut where they pass from one branch to the next and
//   the bones numbered by decreasing length (details at AssignBranchBones below).
//
// Reference
//   None: the paper (Shapira, Shamir, Cohen-Or 2008, section 5) ends at the connected tree;
//   the cleaning and the bones are ours (see the deviation above and AssignBranchBones).
#pragma once

#include "Mesh/MeshTypes.h"
#include "Skeleton/SkeletonSampling.h"

#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <vector>

namespace shapediameter
{

/// The curve skeleton: nodes and the polylines through them.
struct SkeletonGraph
{
  /// Node positions, n x 3.
  PointMatrix NodePositions;
  /// Medial radius at each node (radius of its cloud point).
  std::vector<double> NodeRadius;
  /// MLS confidence of each node's cloud point, [0, 1].
  std::vector<double> NodeConfidence;
  /// Index into P of the cloud point each node comes from.
  std::vector<std::int64_t> NodeCloudIndex;
  /// Surface component of each node.
  std::vector<std::int64_t> NodeComponent;
  /// Bone (branch) of each node; a junction takes the lowest bone id meeting there.
  std::vector<std::int64_t> NodeBone;
  /// Polylines as lists of node indices, each within one bone.
  std::vector<std::vector<std::int64_t>> Polylines;
  /// 1 for a connecting path, 0 for a fitted poly-segment (or a single-node blob skeleton).
  std::vector<int> IsConnection;
  /// Bone (branch) of each polyline, in [0, BoneLength.size()).
  std::vector<std::int64_t> PolylineBone;
  /// Length of each bone (sum of its edge lengths; 0 for a single-node bone), non-increasing.
  std::vector<double> BoneLength;
};

/// Whether junction cleaning removes short leaf branches or only contracts short inner ones.
enum class LeafPruning
{
  Prune,
  Keep
};

/// Cleans the junctions of a forest given as polylines of vertex ids (any integers), see the
/// header comment. Leaf branches (unless leaves is LeafPruning::Keep): removed if shorter than
/// factor * radiusOf(junction), or shorter than 2 * factor * radiusOf(v) with their leaf within
/// factor * radiusOf(v) of a vertex v off the branch and of the same componentOf. Inner
/// branches shorter than factor * the larger radius of their junctions: contracted into the
/// junction of larger radius (ties: lower id). Polylines left with fewer than two vertices are
/// dropped (single-vertex input polylines are kept unless removed). factor <= 0 does nothing.
void CleanJunctions(std::vector<std::vector<std::int64_t>>& polylines,
  std::vector<int>& isConnection,
  const std::function<Eigen::Vector3d(std::int64_t)>& positionOf,
  const std::function<double(std::int64_t)>& radiusOf,
  const std::function<std::int64_t(std::int64_t)>& componentOf, double factor,
  LeafPruning leaves = LeafPruning::Prune);

/// CleanJunctions on the graph's polylines (positions, radii and components of its nodes),
/// then the nodes left in no polyline are dropped (the others keep their order) and the bones
/// assigned (AssignBranchBones). factor <= 0 cleans nothing but still assigns the bones.
void CleanGraphJunctions(SkeletonGraph& graph, double factor, LeafPruning leaves = LeafPruning::Prune);

/// Bones are the branches of the skeleton forest: the maximal paths whose interior nodes have
/// degree 2 in the skeleton graph (the union of the edges of all polylines), between nodes of
/// degree 1 (ends) or >= 3 (junctions). A node of degree 0 is a bone by itself (a blob's
/// single-node skeleton). A closed loop of degree-2 nodes (not produced by the connection
/// step, which builds trees, but accepted) is cut at its lowest node index into one bone.
/// Why topological: the polylines are pieces of the algorithm (how segments happened to be
/// grown), so their number changes with the pose of the same shape; the branches do not.
/// What it does to `graph`:
///   - every polyline is cut at the nodes where it passes from one branch to the next (the
///     cut node ends one piece and starts the next), so each polyline lies in exactly one
///     bone; pieces keep the IsConnection of their polyline and the polylines' order;
///   - bones are numbered by decreasing length, ties by the lowest node index of the branch,
///     then by its node sequence (oriented from its lower end): deterministic;
///   - PolylineBone[p] = bone of polyline p; BoneLength[b] = length of bone b;
///   - NodeBone[n] = bone of node n; a junction belongs to several branches and takes the
///     lowest id among them (so the longest branch through it);
///   - a node in no polyline (not produced by the steps) gets a single-node polyline, and an
///     empty polyline is dropped.
/// Idempotent: applying it twice gives the same graph. Polyline node indices must lie in
/// [0, NodePositions.rows()) (throws Error otherwise).
void AssignBranchBones(SkeletonGraph& graph);

} // namespace shapediameter
