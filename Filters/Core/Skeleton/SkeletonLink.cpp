// SPDX-License-Identifier: BSD-3-Clause
#include "Skeleton/SkeletonLink.h"

#include "ExactSum.h"
#include "Skeleton/SkeletonPointTree.h"
#include "Skeleton/SkeletonSampling.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <utility>

namespace shapediameter
{

namespace
{

/// The nodes of every bone, each list in index order.
std::vector<std::vector<std::int64_t>> NodesOfBones(const SkeletonGraph& graph)
{
  std::vector<std::vector<std::int64_t>> boneNodes(graph.BoneLength.size());
  for (std::size_t n = 0; n < graph.NodeBone.size(); ++n)
  {
    boneNodes[static_cast<std::size_t>(graph.NodeBone[n])].push_back(static_cast<std::int64_t>(n));
  }
  return boneNodes;
}

/// The node of `nodes` nearest to `centre`, -1 for none: a scan in index order (ties to the
/// lower index, as the tree's search), far cheaper than a tree search whose predicate rejects
/// all but a few dozen nodes.
std::int64_t NearestNodeAmong(
  const SkeletonGraph& graph, const std::vector<std::int64_t>& nodes, const Eigen::Vector3d& centre)
{
  double best = std::numeric_limits<double>::infinity();
  std::int64_t nearest = -1;
  for (const std::int64_t n : nodes)
  {
    const double dx = graph.NodePositions(n, 0) - centre(0);
    const double dy = graph.NodePositions(n, 1) - centre(1);
    const double dz = graph.NodePositions(n, 2) - centre(2);
    const double squared = dx * dx + dy * dy + dz * dz;
    if (squared < best)
    {
      best = squared;
      nearest = n;
    }
  }
  return nearest;
}

} // namespace

std::vector<std::int64_t> PartsWithinComponents(
  const std::vector<std::int64_t>& faceParts, const std::vector<std::int64_t>& faceComponent)
{
  std::map<std::pair<std::int64_t, std::int64_t>, std::int64_t> dense;
  std::vector<std::int64_t> result(faceParts.size());
  for (std::size_t f = 0; f < faceParts.size(); ++f)
  {
    result[f] = dense.try_emplace({ faceComponent[f], faceParts[f] }, static_cast<std::int64_t>(dense.size())).first->second;
  }
  return result;
}

FaceLink::FaceLink(PointsView points, TrianglesView triangles, const std::vector<double>& faceSdf,
  PointsView faceNormals, std::vector<std::int64_t> faceComponent, std::vector<std::int64_t> faceParts,
  std::vector<char> counts, std::vector<std::int64_t> wholeIndex, const ParallelFor& parallelFor)
  : Points(points)
  , Triangles(triangles)
  , FaceSdf(faceSdf)
  , FaceNormals(faceNormals)
  , Component(std::move(faceComponent))
  , Part(std::move(faceParts))
  , Counts(std::move(counts))
  , WholeIndex(std::move(wholeIndex))
  , Parallel(parallelFor)
{
  this->Area.resize(this->Component.size());
  parallelFor(this->Area.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f)
    {
      const auto face = static_cast<Eigen::Index>(f);
      const Eigen::Vector3d a = points.row(triangles(face, 0)).transpose();
      const Eigen::Vector3d b = points.row(triangles(face, 1)).transpose();
      const Eigen::Vector3d c = points.row(triangles(face, 2)).transpose();
      const double area = 0.5 * (b - a).cross(c - a).norm();
      this->Area[f] = std::isfinite(area) ? area : 0.0;
    }
  });
}

Eigen::Vector3d FaceLink::ProjectedCentre(std::size_t f) const
{
  const auto face = static_cast<Eigen::Index>(f);
  const Eigen::Vector3d a = this->Points.row(this->Triangles(face, 0)).transpose();
  const Eigen::Vector3d b = this->Points.row(this->Triangles(face, 1)).transpose();
  const Eigen::Vector3d c = this->Points.row(this->Triangles(face, 2)).transpose();
  const Eigen::Vector3d normal = EffectiveFaceNormal(this->Points, this->Triangles, this->FaceNormals, face);
  return (a + b + c) / 3.0 - 0.5 * this->FaceSdf[f] * normal;
}

std::vector<LargestFace> FaceLink::LargestFaces(const std::vector<char>& componentHasNode) const
{
  std::map<std::int64_t, std::size_t> largest;
  for (std::size_t f = 0; f < this->Size(); ++f)
  {
    const std::int64_t c = this->Component[f];
    if (componentHasNode[static_cast<std::size_t>(c)])
    {
      continue;
    }
    // Faces come in increasing whole index: a strictly larger area replaces (ties: the first).
    const auto found = largest.find(c);
    if (found == largest.end() || this->Area[found->second] < this->Area[f])
    {
      largest[c] = f;
    }
  }
  std::vector<LargestFace> faces;
  for (const auto& [c, f] : largest)
  {
    faces.push_back({ c, this->Area[f], this->WholeIndex.empty() ? static_cast<std::int64_t>(f) : this->WholeIndex[f],
      this->ProjectedCentre(f), this->FaceSdf[f] });
  }
  return faces;
}

void FaceLink::LinkToNearestNodes(const SkeletonGraph& graph)
{
  // Every component has a node once the fallback nodes are added: when every node lies in
  // component 0, so does every face, and the search needs no predicate (no call per candidate).
  const bool singleComponent = std::all_of(
    graph.NodeComponent.begin(), graph.NodeComponent.end(), [](std::int64_t c) { return c == 0; });
  const SkeletonPointTree nodeTree(graph.NodePositions);
  this->FaceNodeId.assign(this->Size(), 0);
  this->FaceBoneId.assign(this->Size(), 0);
  this->Parallel(this->Size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f)
    {
      const std::int64_t c = this->Component[f];
      const Eigen::Vector3d centre = this->ProjectedCentre(f);
      const std::int64_t node = singleComponent
        ? nodeTree.NearestAccepted(centre, {})
        : nodeTree.NearestAccepted(centre, [&](std::int64_t n) { return graph.NodeComponent[n] == c; });
      this->FaceNodeId[f] = node;
      this->FaceBoneId[f] = graph.NodeBone[node];
    }
  });
}

OverlapPartialList FaceLink::OverlapPartials() const
{
  return OverlapPartialsOf(this->Part, this->FaceBoneId, this->Area, this->Counts);
}

void FaceLink::MoveFacesToPartBones(const SkeletonGraph& graph, const std::vector<std::int64_t>& partBone)
{
  const std::vector<std::vector<std::int64_t>> boneNodes = NodesOfBones(graph);
  this->Parallel(this->Size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f)
    {
      const std::int64_t bone = partBone[static_cast<std::size_t>(this->Part[f])];
      if (bone == this->FaceBoneId[f])
      {
        continue;
      }
      this->FaceNodeId[f] =
        NearestNodeAmong(graph, boneNodes[static_cast<std::size_t>(bone)], this->ProjectedCentre(f));
      this->FaceBoneId[f] = bone;
    }
  });
}

void FaceLink::RenameBones(const std::vector<std::int64_t>& newBone)
{
  for (std::int64_t& bone : this->FaceBoneId)
  {
    if (bone >= 0)
    {
      bone = newBone[static_cast<std::size_t>(bone)];
    }
  }
}

void FaceLink::LinkFacesToNodesOfTheirBones(const SkeletonGraph& graph)
{
  const std::vector<std::vector<std::int64_t>> boneNodes = NodesOfBones(graph);
  this->Parallel(this->Size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f)
    {
      const std::int64_t nearest = NearestNodeAmong(
        graph, boneNodes[static_cast<std::size_t>(this->FaceBoneId[f])], this->ProjectedCentre(f));
      if (nearest >= 0)
      {
        this->FaceNodeId[f] = nearest;
      }
    }
  });
}

std::vector<PartOverlap> LocalSurfaceLink::Overlaps()
{
  return MergeOverlaps({ this->Faces.OverlapPartials() });
}

OverlapPartialList OverlapPartialsOf(
  const std::vector<std::int64_t>& facePart, const std::vector<std::int64_t>& faceBone,
  const std::vector<double>& faceArea, const std::vector<char>& counts)
{
  std::map<std::pair<std::int64_t, std::int64_t>, ExactSum> areaOfPair;
  for (std::size_t f = 0; f < facePart.size(); ++f)
  {
    if (counts.empty() || counts[f])
    {
      areaOfPair[{ facePart[f], faceBone[f] }].Add(faceArea[f]);
    }
  }
  OverlapPartialList partials;
  for (const auto& [pair, sum] : areaOfPair)
  {
    partials.emplace_back(pair, sum.Partials());
  }
  return partials;
}

std::vector<PartOverlap> MergeOverlaps(
  const std::vector<OverlapPartialList>& lists)
{
  std::map<std::pair<std::int64_t, std::int64_t>, ExactSum> areaOfPair;
  for (const auto& list : lists)
  {
    for (const auto& [pair, partials] : list)
    {
      areaOfPair[pair].Add(partials);
    }
  }
  std::vector<PartOverlap> overlaps;
  for (const auto& [pair, sum] : areaOfPair)
  {
    overlaps.push_back({ pair.first, pair.second, sum.Rounded() });
  }
  return overlaps;
}

std::vector<LargestFace> MergeLargestFaces(const std::vector<std::vector<LargestFace>>& lists)
{
  std::map<std::int64_t, LargestFace> largest;
  for (const std::vector<LargestFace>& list : lists)
  {
    for (const LargestFace& face : list)
    {
      const auto found = largest.find(face.Component);
      if (found == largest.end() || found->second.Area < face.Area ||
        (found->second.Area == face.Area && face.Face < found->second.Face))
      {
        largest[face.Component] = face;
      }
    }
  }
  std::vector<LargestFace> faces;
  for (const auto& entry : largest)
  {
    faces.push_back(entry.second);
  }
  return faces;
}

std::vector<std::int64_t> PartBonesFromOverlaps(
  const std::vector<PartOverlap>& overlaps, std::size_t parts, double ownBoneShare, std::vector<char>* partHasOwnBone)
{
  std::vector<std::int64_t> bestBone(parts, -1);
  std::vector<double> bestArea(parts, 0.0);
  std::vector<double> partArea(parts, 0.0);
  for (const PartOverlap& overlap : overlaps)
  {
    const auto p = static_cast<std::size_t>(overlap.Part);
    partArea[p] += overlap.Area;
    // Bones come in increasing order within a part: a strictly larger area is needed to
    // replace the lower bone (ties: the lowest bone id).
    if (bestBone[p] < 0 || overlap.Area > bestArea[p])
    {
      bestBone[p] = overlap.Bone;
      bestArea[p] = overlap.Area;
    }
  }
  // Own bones first. Why: a bone often runs through two parts (an ear's branch across the
  // head), and a part that holds less of it than its neighbour does would otherwise share it
  // in the poses where it is that part's largest, and not in the others.
  std::vector<PartOverlap> byArea = overlaps;
  std::stable_sort(
    byArea.begin(), byArea.end(), [](const PartOverlap& a, const PartOverlap& b) { return a.Area > b.Area; });
  std::vector<char> hasOwnBone(parts, 0);
  std::set<std::int64_t> takenBones;
  for (const PartOverlap& overlap : byArea)
  {
    const auto p = static_cast<std::size_t>(overlap.Part);
    if (hasOwnBone[p] || overlap.Area < ownBoneShare * partArea[p] || !takenBones.insert(overlap.Bone).second)
    {
      continue;
    }
    hasOwnBone[p] = 1;
    bestBone[p] = overlap.Bone;
  }
  if (partHasOwnBone)
  {
    *partHasOwnBone = std::move(hasOwnBone);
  }
  return bestBone;
}

} // namespace shapediameter
