// SPDX-License-Identifier: BSD-3-Clause
// SDF-guided skeleton, step 4 of 4: connecting the poly-segments into one tree.
//
// What it computes
//   The poly-segments S of step 3 are joined by shortest paths through the projected cloud P
//   (whose points lie near the medial axis, hence good candidates for connecting paths):
//   1. Neighbour graph on P: each point linked to its NumberOfNeighbors nearest points of the
//      same surface component, edge weight = Euclidean length; when a volume is given (as
//      ComputeSkeleton does), an edge whose straight segment meets the surface is left out
//      (SegmentCrossesSurface, RayCaster.h), so that paths run through one part of the volume,
//      never from a trunk into the foot it touches or is pushed into. Deviation: the paper has
//      no such test (see SkeletonSegments.h for the measurement). If this graph splits a surface
//      component into several pieces, the pieces are linked by their shortest gaps
//      (Boruvka rounds), so that every surface component is one graph component.
//   2. k-terminal growth: the points of P within SeedRadiusFactor * radius(node) of a segment
//      node (and the nearest point of P to every node) start with their distance to that node
//      and belong to that segment. A priority queue (Dijkstra) grows all segments at once;
//      each settled point belongs to the segment that reached it first.
//   3. Where two growths meet (a graph edge between points of different segments), the two
//      segments can be joined at cost dist(a) + |ab| + dist(b). Joins are accepted cheapest
//      first unless the two segments are already linked (union-find: no cycles), which is the
//      order in which the paper's simultaneous growth meets, until every segment of a
//      component is linked.
//   4. Each accepted join becomes the path node -> points of P -> ... -> node. Paths that
//      share points of P are merged (they follow the same shortest-path tree), so three
//      segments meeting at a junction give one branching point instead of overlapping paths.
//      The merged paths are cut into polylines between segment nodes and branching points and
//      thinned to a node spacing of SpacingFactor * radius. They are the IsConnection = 1
//      polylines.
//   5. Junctions are cleaned, with f = MinimumBranchFactor, repeatedly until nothing changes:
//      a leaf branch (from a leaf node to the first node of degree >= 3) is removed if it is
//      shorter than f * radius at that junction, or if it is shorter than 2 f * radius(v) and
//      its end lies within f * radius(v) of a node v off the branch (a stub inside another
//      part's medial ball, typically a segment end overshooting the point where a connecting
//      path joins it); then an inner branch (between two junctions) shorter than f * the
//      larger radius of its junctions is contracted into the junction of larger radius, so
//      parts meeting at one place (two arms joining the torso a little apart) give one
//      junction and no spurious short bone. A tree that is a single path is never cut.
//      Deviation: the paper does not prune; without it, noisy SDF leaves stubs of a few nodes
//      beside junctions and splits junctions, so the number of branches (bones) would change
//      with noise and pose; a part shorter than its own radius is a bump rather than a limb.
//   6. Bones (AssignBranchBones): the polylines above are pieces of the algorithm (a fitted
//      segment may run through a junction where a connecting path ends on it), so they are
//      cut at junctions and grouped into the branches of the tree; see AssignBranchBones.
//   A surface component with points in P but no segment (a blob such as a sphere or a cube)
//   gets a single node: the point of P nearest to the mean of its points.
//
// Reference
//   Shapira, Shamir, Cohen-Or 2008, section 5, last two paragraphs (k-terminal shortest paths).
//   The cheapest-first acceptance of joins between growth regions is Mehlhorn's (1988) form of
//   the multi-terminal growth; the paper leaves the order open.
//
// Parameters (SkeletonConnectionOptions)
//   NumberOfNeighbors  k of the neighbour graph on P. Default 8; [1, 64].
//   SeedRadiusFactor    growth seeds within factor * radius(node) of a segment node. Default
//                       0.5; [0, 10] (0: only the nearest point of P to each node).
//   SpacingFactor       node spacing along connecting paths, * radius. Default 0.25 (the
//                       thinning's epsilon); [0, 10] (0 keeps every point of the path).
//   MinimumBranchFactor leaf branches shorter than factor * radius(junction) are pruned and
//                       inner branches that short contracted (see 5.). Default 1; [0, 10]
//                       (0 disables the cleaning).
//
// Output (SkeletonGraph)
//   Nodes: segment nodes first (at their MLS positions, in segment order), then connecting
//   path nodes (at their P positions). Polylines: the segments (IsConnection 0) in seed order,
//   then connecting polylines (IsConnection 1), then single-node polylines of blob components
//   (IsConnection 0); a polyline that runs through a junction is cut there into consecutive
//   pieces (same IsConnection). Bones are the branches of the forest (AssignBranchBones).
//   The result is a forest with one tree per surface component that has points in P.
#pragma once

#include "Parallel.h"
#include "RayCaster.h"
#include "SkeletonSampling.h"
#include "SkeletonSegments.h"
#include "SkeletonThinning.h"

#include <Eigen/Core>

#include <cstdint>
#include <functional>
#include <vector>

namespace shapediameter
{

struct SkeletonConnectionOptions
{
  /// k of the k-nearest-neighbour graph on P. [1, 64].
  int NumberOfNeighbors = 8;
  /// Growth seeds lie within SeedRadiusFactor * radius of a segment node. [0, 10].
  double SeedRadiusFactor = 0.5;
  /// Node spacing along connecting paths, * radius. [0, 10].
  double SpacingFactor = 0.25;
  /// Leaf branches shorter than MinimumBranchFactor * radius at their junction are removed,
  /// inner branches that short contracted (0 keeps every branch). [0, 10].
  double MinimumBranchFactor = 1.0;
};

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

/// Throws SkeletonError if an option is outside its documented range.
void ValidateConnectionOptions(const SkeletonConnectionOptions& options);

/// Step 5 on its own (exposed for tests): cleans the junctions of a forest given as polylines
/// of vertex ids (any integers), see 5. in the header comment. Leaf branches: removed if
/// shorter than factor * radiusOf(junction), or shorter than 2 * factor * radiusOf(v) with
/// their leaf within factor * radiusOf(v) of a vertex v off the branch and of the same
/// componentOf. Inner branches shorter than factor * the larger radius of their junctions:
/// contracted into the junction of larger radius (ties: lower id). Polylines left with fewer
/// than two vertices are dropped (single-vertex input polylines are kept unless removed).
/// factor <= 0 does nothing.
void CleanJunctions(std::vector<std::vector<std::int64_t>>& polylines,
  std::vector<int>& isConnection,
  const std::function<Eigen::Vector3d(std::int64_t)>& positionOf,
  const std::function<double(std::int64_t)>& radiusOf,
  const std::function<std::int64_t(std::int64_t)>& componentOf, double factor);

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
/// [0, NodePositions.rows()) (throws SkeletonError otherwise).
void AssignBranchBones(SkeletonGraph& graph);

/// Step 4: joins the poly-segments through P into one tree per surface component.
/// volume: the mesh's ray caster for the inside test of step 1, or null for none.
/// pointComponent: surface component of each cloud point, or empty for a single component.
/// progress receives fractions in [0, 1] of this step; returning false aborts (the returned
/// graph is then empty and `aborted` is set).
SkeletonGraph ConnectPolySegments(const ProjectedCloud& cloud, const ThinnedCloud& thinned,
  const std::vector<PolySegment>& segments, const std::vector<std::int64_t>& pointComponent,
  const SkeletonConnectionOptions& options, const ParallelFor& parallelFor,
  const ProgressCallback& progress, bool& aborted, const RayCaster* volume = nullptr);

} // namespace shapediameter
