// SPDX-License-Identifier: BSD-3-Clause
// SDF-guided curve skeleton: the four steps of the paper's section 5, in order, and ours.
//
// What it computes
//   A curve skeleton (nodes with a medial radius and a confidence, joined by polylines) of a
//   closed, outward-oriented triangle mesh from its per-face shape diameter, and the link
//   between the skeleton and the surface:
//     1. SampleProjectedCloud  - N area-weighted samples pushed inward by SDF/2 -> cloud P
//     2. ThinProjectedCloud    - MLS projection onto local regression lines, confidence,
//                                (ours) only points whose medial ball fits, epsilon-thinning
//                                -> T
//     3. GrowPolySegments      - ordered poly-segments grown through T
//     4. ConnectPolySegments   - k-terminal shortest paths through P join the segments into
//                                one tree per connected surface component
//    4b. ExtendLeavesToPartEnds - (ours) a leaf whose branch points head-on at the end of its
//                                part gets one node where a ball of its radius touches that
//                                end; then the junctions are cleaned (CleanGraphJunctions),
//                                so that a stub is judged by its part's length
//     5. ReachUncoveredParts   - (ours) a branch into every large group of projected points
//                                far from the tree and into each other limb of such a group
//                                (a side limb: an ear beside a snout), and into every thin
//                                limb (a small group along a line, far out: a tail): parts
//                                with no confident segment (a bent or stubby limb, an ear)
//                                still get one, in every pose;
//                                then the inner branches it made shorter than
//                                MinimumBranchFactor radii are contracted (CleanGraphJunctions
//                                without leaf pruning), so the output keeps step 4's rule
//     6. ReachPartsWithoutBones - (ours, with part labels) after the part link below: a part
//                                holding at least PartMinimumShare (3 %) of P's points that
//                                got no bone of its own, and whose point farthest from the
//                                skeleton lies more than PartUncoveredFactor (2) of its radii
//                                away, gets a branch from that point to where the part ends
//                                (SkeletonCoverage.h); largest part first, each once, the
//                                junctions cleaned as after step 5 and the link made again.
//                                Why: a part whose bones all belong to its neighbours (an
//                                elephant's lowered head whose nearest branches are the
//                                ears') otherwise shares a neighbour's bone in some poses only.
//     7. SmoothBones           - (ours) after the link: every bone's nodes onto a local
//                                quadratic fit along the bone, held inside the volume
//                                (SkeletonSmoothing.h); the bones are numbered again by their
//                                smoothed lengths and every face is linked again to the
//                                nearest node of its own bone.
//    7b. ExtendLeavesToSurface - (ours) every leaf whose smoothed bone meets its part's end
//                                head-on gets one more node TipReach (1) of the way to the
//                                surface, in its bone (SkeletonLeafExtension.h): a rig's end
//                                joints sit at the tips, the medial axis ends a radius inside.
//   Steps 3, 4 and 5 move only through the volume: an Embree BVH of the mesh (EmbreeRayCaster)
//   rejects growth steps and neighbour-graph edges whose straight segment meets the surface
//   (the face link below does not use it: it made no measurable difference and costs two rays
//   per face).
//   Then every face is linked to the skeleton node nearest to its projected centre (face
//   centroid - normal * SDF/2) among the nodes of its own surface component. This rule is the
//   same for faces with and without samples, so a face's link does not depend on N or on the
//   seed; it is the point of P the face would have produced at its centre.
//   With part labels (faceParts, e.g. the partition's SDFSegment), every part is then linked
//   to one bone, and each face of the part to the nearest node of that bone (faces whose
//   nearest node is on that bone keep it). Why: a junction's position along the torso moves
//   with the pose, so the nearest-node boundary between two bones sweeps across the body,
//   while the partition's boundaries sit at the concave creases where limbs meet it and
//   hardly move (measurements: docs/skeleton.md). Which bone: from the area
//   each bone holds of each part under the nearest-node link, the parts first get bones of
//   their own, largest overlaps first, from the bones holding at least OwnBoneShare (0.15)
//   of their area; a part left without one shares the bone holding most of it (ties: the
//   lowest bone id). Why own bones first: a bone often runs through two parts (an elephant
//   ear's branch across the head), and with the largest overlap alone the smaller part
//   shared its neighbour's bone in some poses and not in others (the head with an ear in two
//   of the ten elephant poses, the trunk with both tusks in one; docs/skeleton.md). The areas
//   are exact sums (ExactSum), so the link split over processes gives the same parts' bones
//   (SkeletonLink.h holds the link's steps).
//
// Bones
//   Bones are the branches of the tree: the maximal paths of the skeleton graph (the union of
//   the polylines' edges) between nodes whose degree is not 2, i.e. between ends (degree 1)
//   and junctions (degree >= 3); a single-node skeleton (blob, fallback) is one bone. They are
//   numbered 0.. by decreasing length (ties: lowest node index), so a figure in two poses has
//   the same bones as long as its skeleton has the same branching, whatever way the steps
//   happened to grow segments and connecting paths. The polylines remain the algorithm's
//   pieces (IsConnection tells fitted segment from connecting path), but each one is cut at
//   the junctions it passes through, so every polyline lies in exactly one bone (BoneId).
//   A junction node belongs to all the branches meeting there; its NodeBoneId (and the
//   SkeletonBoneId of the faces linked to it) is the lowest bone id among them, i.e. the
//   longest. See AssignBranchBones in SkeletonBones.h.
//
// Reference
//   Shapira, Shamir, Cohen-Or 2008, "Consistent mesh partitioning and skeletonisation using
//   the shape diameter function", The Visual Computer 24(4), section 5.
//
// Inputs
//   points, triangles  the mesh (already triangulated, outward oriented).
//   faceSdf            per-face shape diameter (length units, finite, >= 0); the VTK adapter
//                      passes SDFSmoothed, else SDF.
//   faceNormals        unit outward normal per face, or an empty matrix to compute them.
//   faceComponents     surface component label per face (any integers), or empty to label
//                      faces connected through shared vertices. The skeleton never joins two
//                      components: each gets its own tree.
//   faceParts          part label per face (any integers; a part is taken within one surface
//                      component), or empty for the nearest-node link alone.
//   A per-face cluster label (SDFCluster) is not needed here: the adapter reads it through
//   CloudSourceFace for the cloud output.
//
// Parameters: SkeletonOptions gathers the options of the steps; their defaults and valid
// ranges are documented in SkeletonSampling.h, SkeletonThinning.h, SkeletonSegments.h,
// SkeletonConnection.h, SkeletonLeafExtension.h and SkeletonCoverage.h. All lengths are relative to the local medial
// radius SDF/2, so the result does not depend on the mesh's scale.
//
// Degenerate input
//   No triangles -> empty result (not an error). Invalid input -> Error (see
//   ValidateSkeletonInput). A component whose cloud has no curve-like part (sphere, cube) gets
//   a single-node skeleton at the point of P nearest to its mean; a component without samples
//   (tiny area, or only degenerate faces) gets a single node at the projected centre of its
//   largest face. So every face is linked to a node of its own component, and every output
//   is finite.
//
// Cost
//   Steps 2-6 work on the N points of P, so at fixed N their cost hardly grows with the face
//   count; the parts linear in the faces are the volume's BVH build, the face normals and
//   components, and the face link (one nearest-node query per face).
//
// Threading and determinism
//   parallelFor runs the MLS loop, the neighbour graph and the face link. For a fixed seed the
//   result is bit-identical for any ParallelFor. progress receives [0, 1]; returning false
//   aborts: the result is then empty with Aborted = true.
#pragma once

#include "Errors.h"
#include "Mesh/MeshTypes.h"
#include "Parallel.h"
#include "RayCasting/EmbreeRayCaster.h"
#include "Skeleton/SkeletonConnection.h"
#include "Skeleton/SkeletonCoverage.h"
#include "Skeleton/SkeletonLeafExtension.h"
#include "Skeleton/SkeletonLink.h"
#include "Skeleton/SkeletonSampling.h"
#include "Skeleton/SkeletonSegments.h"
#include "Skeleton/SkeletonSmoothing.h"
#include "Skeleton/SkeletonThinning.h"

#include <cstdint>
#include <functional>
#include <vector>

namespace shapediameter
{

struct SkeletonOptions
{
  SkeletonSamplingOptions Sampling;
  SkeletonThinningOptions Thinning;
  SkeletonSegmentOptions Segments;
  SkeletonConnectionOptions Connection;
  SkeletonLeafExtensionOptions LeafExtension;
  SkeletonCoverageOptions Coverage;
  /// Step 7, the bones made smooth curves (SkeletonSmoothing.h).
  SkeletonSmoothingOptions Smoothing;
  /// With part labels: a part takes a bone no other part has taken when that bone holds at
  /// least this share of its area under the nearest-node link (larger overlaps first); else
  /// it shares the bone holding most of it. Default 0.15, range [0, 1]; any value above 0.5
  /// gives every part the bone holding most of it (shared or not). See the header comment
  /// (the part link) for why; the evidence is in docs/skeleton.md.
  double OwnBoneShare = 0.15;
};

/// OwnBoneShare, checked by ValidateSkeletonOptions; vtkSDFSkeleton's vtkSetClampMacro repeats it
/// (Testing/Filters/TestParameterRanges.cxx).
inline constexpr Range<double> OwnBoneShareRange{ 0.0, 1.0 };

struct SkeletonResult
{
  // Skeleton (vtkSDFSkeleton port 0).
  /// Node positions, one row per node.
  PointMatrix NodePositions;
  /// "Radius": medial radius SDF/2 at each node.
  std::vector<double> NodeRadius;
  /// "Confidence": MLS confidence in [0, 1] of each node (0 for a fallback node).
  std::vector<double> NodeConfidence;
  /// Polylines as node index lists (a single-node list is a blob's skeleton); each lies in
  /// exactly one bone. Fitted segments first, then connecting paths, then fallback nodes;
  /// the pieces of a polyline cut at junctions follow each other.
  std::vector<std::vector<std::int64_t>> Polylines;
  /// "BoneId" of each polyline: the branch of the tree it lies in, in [0, BoneLength.size()).
  std::vector<std::int64_t> BoneId;
  /// "IsConnection" of each polyline: 1 = connecting path, 0 = fitted poly-segment.
  std::vector<int> IsConnection;
  /// Bone of each node; a junction node takes the lowest bone id meeting there.
  std::vector<std::int64_t> NodeBoneId;
  /// Length of each bone (0 for a single-node bone), non-increasing; its size is the number
  /// of bones.
  std::vector<double> BoneLength;

  // Surface link (port 1), one value per input face.
  /// "SkeletonNodeId": node nearest to the face's projected centre, same component (with
  /// faceParts: among the nodes of the part's bone).
  std::vector<std::int64_t> FaceNodeId;
  /// "SkeletonBoneId": bone of that node (with faceParts: the part's bone).
  std::vector<std::int64_t> FaceBoneId;

  // Projected cloud P (port 2).
  PointMatrix CloudPositions;
  /// "Radius" = SDF/2 of the source face.
  std::vector<double> CloudRadius;
  /// "Confidence" of the last MLS iteration, [0, 1] (0 where undefined).
  std::vector<double> CloudConfidence;
  /// "SourceFaceId".
  std::vector<std::int64_t> CloudSourceFace;
  /// True if the progress callback aborted the computation (all arrays are then empty).
  bool Aborted = false;
};

/// Throws Error if any option is outside its documented range.
void ValidateSkeletonOptions(const SkeletonOptions& options);

/// The SDF-guided skeleton of section 5. See the header comment for inputs and guarantees.
SkeletonResult ComputeSkeleton(PointsView points, TrianglesView triangles,
  const std::vector<double>& faceSdf, PointsView faceNormals,
  const std::vector<std::int64_t>& faceComponents, const SkeletonOptions& options,
  const ParallelFor& parallelFor, const ProgressCallback& progress = {},
  const std::vector<std::int64_t>& faceParts = {});

/// What the skeleton's steps read of the surface once it is sampled (step 1): the projected
/// cloud P, and per point of P its source face's surface component and part.
struct SampledSurface
{
  ProjectedCloud Cloud;
  std::vector<std::int64_t> PointComponent;
  /// Dense labels of PartsWithinComponents; empty without parts.
  std::vector<std::int64_t> PointPart;
  std::size_t Components = 0;
  /// 0 without parts.
  std::size_t Parts = 0;
};

/// Step 1 of ComputeSkeleton. faceComponent: dense labels 0.. per face; facePart: dense labels
/// of PartsWithinComponents per face, or empty. Inputs as ComputeSkeleton's (not validated).
SampledSurface SampleSkeletonSurface(PointsView points, TrianglesView triangles, const std::vector<double>& faceSdf,
  PointsView faceNormals, const std::vector<std::int64_t>& faceComponent, const std::vector<std::int64_t>& facePart,
  const SkeletonSamplingOptions& options);

/// Build options of the volume (the surface's BVH) that the thinning, growth, connection,
/// coverage, smoothing and leaf extensions test against.
EmbreeRayCasterOptions SkeletonVolumeOptions();

/// The surface link of the steps after the connection: made when first needed.
using SurfaceLinkSource = std::function<SurfaceLink&()>;

/// Steps 2 onwards of ComputeSkeleton, from the sampled surface and its volume, the link
/// through `link` (ComputeSkeleton: over the mesh's faces; a distributed run: over processes,
/// DistributedSkeleton.cpp). The result's FaceNodeId and FaceBoneId stay empty (the link holds
/// them). What the surface itself is no longer needed for: the process where a distributed
/// skeleton peaks frees its whole mesh before it builds the volume. `projector`: where step 2's
/// MLS iterations run (ThinProjectedCloud; a distributed run: over processes), else here.
SkeletonResult ComputeSkeletonOfSamples(const SampledSurface& surface, const RayCaster& volume,
  const SkeletonOptions& options, const ParallelFor& parallelFor, const ProgressCallback& progress,
  const SurfaceLinkSource& link, const RegressionProjector* projector = nullptr);

/// The part link (exposed for tests): the bone of every face's part, a part being the faces
/// with one label within one surface component (faceComponent: dense labels 0..), from the
/// area each bone holds of each part under the nearest-node link (nearestBone per face). First
/// every part gets a bone of its own where it can: (part, bone) pairs are visited by decreasing
/// area (ties: the part seen first in face order, then the lower bone), and a pair whose bone
/// holds at least ownBoneShare of the part's area gives the part that bone unless the part or
/// the bone is taken. A part left without one shares the bone holding most of its area (ties:
/// the lowest bone id). Returns the bone per face; partHasOwnBone, if given, receives per part
/// (dense labels of the (component, label) pairs in order of first appearance in face order)
/// whether it got a bone of its own.
std::vector<std::int64_t> LinkPartsToBones(const std::vector<std::int64_t>& faceParts,
  const std::vector<std::int64_t>& faceComponent, const std::vector<double>& faceArea,
  const std::vector<std::int64_t>& nearestBone, double ownBoneShare,
  std::vector<char>* partHasOwnBone = nullptr);

/// Convenience: normals computed from the triangles, components from shared vertices.
SkeletonResult ComputeSkeleton(PointsView points, TrianglesView triangles,
  const std::vector<double>& faceSdf, const SkeletonOptions& options = {},
  const ParallelFor& parallelFor = SerialFor);

} // namespace shapediameter
