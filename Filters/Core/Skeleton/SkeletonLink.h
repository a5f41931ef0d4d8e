// SPDX-License-Identifier: BSD-3-Clause
// The surface link of the skeleton (Skeleton.h, "the face link" and "the part link"): the steps
// over the faces that ComputeSkeleton drives once the skeleton's graph exists.
//
// What it computes
//   Per face, the node nearest to its projected centre (face centroid - normal * SDF/2) among
//   the nodes of its own surface component, and that node's bone; with part labels, the area
//   each bone holds of each part under that link, from which every part gets one bone (the
//   decision, PartBonesFromOverlaps, is Skeleton.h's part link) and each face the nearest node
//   of its part's bone.
//
// Why an interface
//   Every step is a loop over the faces plus, for the part link, sums over them. FaceLink runs
//   the loops over any set of faces (the whole mesh, or one process's own faces); SurfaceLink
//   is what ComputeSkeleton calls: LocalSurfaceLink for one process, and the distributed
//   skeleton's link over processes (DistributedSkeleton.cpp), which runs each step on every
//   process's faces and completes the sums over the processes. The area per (part, bone) is an
//   exact sum (ExactSum), so it does not depend on how the faces are split or ordered: the
//   split result is the serial one bit for bit.
//
// Inputs of a FaceLink (one entry per face of the set)
//   the faces as triangles of points (outward oriented), their SDF and, optionally, unit
//   normals; their surface component (dense labels of the whole surface), their part (dense
//   labels of the whole surface's (component, label) pairs, or empty), whether each face
//   counts in the sums (a face two processes hold counts on one), and each face's index in
//   the whole surface (ties in LargestFaces go to the lowest).
#pragma once

#include "Mesh/MeshTypes.h"
#include "Parallel.h"
#include "Skeleton/SkeletonBones.h"

#include <cstdint>
#include <vector>

namespace shapediameter
{

/// The area one bone holds of one part under the nearest-node link.
struct PartOverlap
{
  std::int64_t Part = 0;
  std::int64_t Bone = 0;
  double Area = 0.0;
};

/// Per (part, bone) pair, in (part, bone) order, the partials of the exact sum (ExactSum) of
/// the areas the bone holds of the part.
using OverlapPartialList = std::vector<std::pair<std::pair<std::int64_t, std::int64_t>, std::vector<double>>>;

/// The largest face of a component (the fallback node of a component without samples sits at
/// its projected centre).
struct LargestFace
{
  std::int64_t Component = 0;
  double Area = 0.0;
  /// Index of the face in the whole surface.
  std::int64_t Face = 0;
  Eigen::Vector3d ProjectedCentre = Eigen::Vector3d::Zero();
  double Sdf = 0.0;
};

/// The link's steps, as ComputeSkeleton calls them (see the header comment).
class SurfaceLink
{
public:
  virtual ~SurfaceLink() = default;
  /// Per component whose componentHasNode entry is 0 and that has faces: its largest face
  /// (largest area; ties: the lowest face index), in increasing component order.
  virtual std::vector<LargestFace> LargestFaces(const std::vector<char>& componentHasNode) = 0;
  /// Every face to the nearest node of its component (the nodes' positions, components and
  /// bones) and to that node's bone.
  virtual void LinkToNearestNodes(const SkeletonGraph& graph) = 0;
  /// The area per (part, bone) under the current link, sorted by (part, bone); empty without
  /// parts.
  virtual std::vector<PartOverlap> Overlaps() = 0;
  /// Every face whose bone is not its part's bone (partBone per dense part) to the nearest node
  /// of its part's bone.
  virtual void MoveFacesToPartBones(const SkeletonGraph& graph, const std::vector<std::int64_t>& partBone) = 0;
  /// Every face's bone renamed (newBone per old bone; -1 stays).
  virtual void RenameBones(const std::vector<std::int64_t>& newBone) = 0;
  /// Every face to the nearest node of the bone it is linked to (its bone does not change).
  virtual void LinkFacesToNodesOfTheirBones(const SkeletonGraph& graph) = 0;
};

/// The faces of one process and the link's loops over them.
class FaceLink
{
public:
  /// See the header comment; faceNormals may be empty (normals from the triangles),
  /// faceParts, counts and wholeIndex may be empty (no parts; every face counts; index = row).
  FaceLink(PointsView points, TrianglesView triangles, const std::vector<double>& faceSdf, PointsView faceNormals,
    std::vector<std::int64_t> faceComponent, std::vector<std::int64_t> faceParts, std::vector<char> counts,
    std::vector<std::int64_t> wholeIndex, const ParallelFor& parallelFor);

  std::size_t Size() const { return this->Component.size(); }
  bool HasParts() const { return !this->Part.empty(); }
  /// The face's centre pushed inward by SDF/2; computed where read (a stored copy was 20 MB of
  /// the skeleton's peak at 832k faces), always by this one function, so the same bits.
  Eigen::Vector3d ProjectedCentre(std::size_t f) const;

  std::vector<LargestFace> LargestFaces(const std::vector<char>& componentHasNode) const;
  void LinkToNearestNodes(const SkeletonGraph& graph);
  /// Per (part, bone) pair, in (part, bone) order, the exact sum's partials of the areas of the
  /// faces that count.
  OverlapPartialList OverlapPartials() const;
  void MoveFacesToPartBones(const SkeletonGraph& graph, const std::vector<std::int64_t>& partBone);
  void RenameBones(const std::vector<std::int64_t>& newBone);
  void LinkFacesToNodesOfTheirBones(const SkeletonGraph& graph);

  /// The result, one per face of the set.
  std::vector<std::int64_t> FaceNodeId;
  std::vector<std::int64_t> FaceBoneId;

private:
  PointsView Points;
  TrianglesView Triangles;
  const std::vector<double>& FaceSdf;
  PointsView FaceNormals;
  std::vector<std::int64_t> Component;
  std::vector<std::int64_t> Part;
  std::vector<char> Counts;
  std::vector<std::int64_t> WholeIndex;
  std::vector<double> Area;
  ParallelFor Parallel;
};

/// The link of one process's faces: every step runs on FaceLink alone.
class LocalSurfaceLink final : public SurfaceLink
{
public:
  explicit LocalSurfaceLink(FaceLink& faces)
    : Faces(faces)
  {
  }
  std::vector<LargestFace> LargestFaces(const std::vector<char>& componentHasNode) override
  {
    return this->Faces.LargestFaces(componentHasNode);
  }
  void LinkToNearestNodes(const SkeletonGraph& graph) override { this->Faces.LinkToNearestNodes(graph); }
  std::vector<PartOverlap> Overlaps() override;
  void MoveFacesToPartBones(const SkeletonGraph& graph, const std::vector<std::int64_t>& partBone) override
  {
    this->Faces.MoveFacesToPartBones(graph, partBone);
  }
  void RenameBones(const std::vector<std::int64_t>& newBone) override { this->Faces.RenameBones(newBone); }
  void LinkFacesToNodesOfTheirBones(const SkeletonGraph& graph) override
  {
    this->Faces.LinkFacesToNodesOfTheirBones(graph);
  }

private:
  FaceLink& Faces;
};

/// Per (part, bone) pair of the faces that count (counts empty: every face), in (part, bone)
/// order, the exact sum's partials of their areas.
OverlapPartialList OverlapPartialsOf(
  const std::vector<std::int64_t>& facePart, const std::vector<std::int64_t>& faceBone,
  const std::vector<double>& faceArea, const std::vector<char>& counts);

/// Merges per-process overlap partials (each list in (part, bone) order) into the exact area
/// of every pair, in (part, bone) order.
std::vector<PartOverlap> MergeOverlaps(
  const std::vector<OverlapPartialList>& lists);

/// Per component, the largest of every process's largest faces (LargestFaces' rule: the
/// largest area, ties to the lowest face), in increasing component order.
std::vector<LargestFace> MergeLargestFaces(const std::vector<std::vector<LargestFace>>& lists);

/// The part link's decision (Skeleton.h): per dense part of `parts`, its bone. Own bones first:
/// (part, bone) pairs by decreasing area (ties: the pairs' (part, bone) order), a pair whose
/// area is at least ownBoneShare of its part's gives the part that bone unless the part or the
/// bone is taken; a part left without one shares the bone holding most of it (ties: the
/// lowest bone). partHasOwnBone, if given, receives per part whether it got one of its own. A
/// part with no overlap gets -1.
std::vector<std::int64_t> PartBonesFromOverlaps(const std::vector<PartOverlap>& overlaps, std::size_t parts,
  double ownBoneShare, std::vector<char>* partHasOwnBone = nullptr);

/// One dense label per (surface component, part label) pair, in order of first appearance.
std::vector<std::int64_t> PartsWithinComponents(
  const std::vector<std::int64_t>& faceParts, const std::vector<std::int64_t>& faceComponent);

} // namespace shapediameter
