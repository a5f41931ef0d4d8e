// SPDX-License-Identifier: BSD-3-Clause
#include "Skeleton/Skeleton.h"

#include "RayCasting/EmbreeRayCaster.h"
#include "Skeleton/SkeletonPointTree.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <unordered_map>
#include <utility>

namespace shapediameter
{

void ValidateSkeletonOptions(const SkeletonOptions& options)
{
  ValidateSamplingOptions(options.Sampling);
  ValidateThinningOptions(options.Thinning);
  ValidateSegmentOptions(options.Segments);
  ValidateConnectionOptions(options.Connection);
  ValidateLeafExtensionOptions(options.LeafExtension);
  ValidateCoverageOptions(options.Coverage);
  ValidateSmoothingOptions(options.Smoothing);
  CheckRange(options.OwnBoneShare, OwnBoneShareRange, "skeleton: OwnBoneShare");
}

namespace
{

/// Dense labels 0.. in order of first appearance, so that any integers can be passed in.
std::vector<std::int64_t> DenseLabels(const std::vector<std::int64_t>& labels)
{
  std::unordered_map<std::int64_t, std::int64_t> dense;
  std::vector<std::int64_t> result(labels.size());
  for (std::size_t i = 0; i < labels.size(); ++i)
  {
    result[i] = dense.try_emplace(labels[i], static_cast<std::int64_t>(dense.size())).first->second;
  }
  return result;
}

/// One dense label per (surface component, part label) pair, in order of first appearance: a
/// part is taken within one component (faceComponent: dense labels 0..). One pass, with no
/// per-face array but the result (the link's peak on the first process of a distributed run).
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

SkeletonResult AbortedResult()
{
  SkeletonResult result;
  result.Aborted = true;
  return result;
}

} // namespace

std::vector<std::int64_t> LinkPartsToBones(const std::vector<std::int64_t>& faceParts,
  const std::vector<std::int64_t>& faceComponent, const std::vector<double>& faceArea,
  const std::vector<std::int64_t>& nearestBone, double ownBoneShare, std::vector<char>* partHasOwnBone)
{
  const std::vector<std::int64_t> part = PartsWithinComponents(faceParts, faceComponent);
  const std::size_t parts =
    part.empty() ? 0 : static_cast<std::size_t>(*std::max_element(part.begin(), part.end()) + 1);

  // Area per (part, bone), each sum over its faces in face order, whatever the labels'
  // values; a map of the pairs rather than the faces sorted by pair (two arrays of the faces
  // less: on the first process of a distributed run, the link is the skeleton's peak).
  struct Overlap
  {
    double Area;
    std::size_t Part;
    std::int64_t Bone;
  };
  std::map<std::pair<std::int64_t, std::int64_t>, double> areaOfPair;
  for (std::size_t f = 0; f < faceParts.size(); ++f)
  {
    areaOfPair[{ part[f], nearestBone[f] }] += faceArea[f];
  }
  std::vector<Overlap> overlaps; // in (part, bone) order
  std::vector<std::int64_t> bestBone(parts, -1);
  std::vector<double> bestArea(parts, 0.0);
  std::vector<double> partArea(parts, 0.0);
  for (const auto& [pair, area] : areaOfPair)
  {
    const auto p = static_cast<std::size_t>(pair.first);
    overlaps.push_back({ area, p, pair.second });
    partArea[p] += area;
    // Bones come in increasing order within a part: a strictly larger area is needed to
    // replace the lower bone (ties: the lowest bone id).
    if (bestBone[p] < 0 || area > bestArea[p])
    {
      bestBone[p] = pair.second;
      bestArea[p] = area;
    }
  }

  // Own bones first. Why: a bone often runs through two parts (an ear's branch across the
  // head), and a part that holds less of it than its neighbour does would otherwise share it
  // in the poses where it is that part's largest, and not in the others.
  std::stable_sort(overlaps.begin(), overlaps.end(),
    [](const Overlap& a, const Overlap& b) { return a.Area > b.Area; });
  std::vector<char> hasOwnBone(parts, 0);
  std::set<std::int64_t> takenBones;
  for (const Overlap& overlap : overlaps)
  {
    if (hasOwnBone[overlap.Part] || overlap.Area < ownBoneShare * partArea[overlap.Part] ||
      !takenBones.insert(overlap.Bone).second)
    {
      continue;
    }
    hasOwnBone[overlap.Part] = 1;
    bestBone[overlap.Part] = overlap.Bone;
  }
  std::vector<std::int64_t> faceBone(faceParts.size());
  for (std::size_t f = 0; f < faceParts.size(); ++f)
  {
    faceBone[f] = bestBone[static_cast<std::size_t>(part[f])];
  }
  if (partHasOwnBone)
  {
    *partHasOwnBone = std::move(hasOwnBone);
  }
  return faceBone;
}

namespace
{

/// Surface component of each point of P: that of its source face.
std::vector<std::int64_t> PointComponents(
  const ProjectedCloud& cloud, const std::vector<std::int64_t>& faceComponent)
{
  std::vector<std::int64_t> pointComponent(cloud.Size());
  for (std::size_t i = 0; i < cloud.Size(); ++i)
  {
    pointComponent[i] = faceComponent[cloud.SourceFace[i]];
  }
  return pointComponent;
}

/// Build options of the volume that growth, connection and coverage test their segments
/// against.
EmbreeRayCasterOptions VolumeOptions()
{
  // Low build quality: the volume answers some 10^5 segment tests, so the build dominates and
  // the faster one wins (832k faces: skeleton 0.82 -> 0.62 s; same output, docs/performance.md
  // "Design measurements"); the SDF's 25 M rays keep Medium. Compact for the same reason: a
  // third less memory for the skeleton's largest allocation (docs/distributed.md).
  EmbreeRayCasterOptions volumeOptions;
  volumeOptions.BuildQuality = EmbreeBuildQuality::Low;
  volumeOptions.Compact = true;
  return volumeOptions;
}

/// ConnectPolySegments through the volume only, its neighbour graph on P kept for
/// ReachUncoveredParts and ReachPartsWithoutBones. Its junction cleaning is left to
/// ExtendLeavesAndCleanJunctions, so that a leaf branch is judged with its extension.
SkeletonGraph ConnectThroughVolume(const ProjectedCloud& cloud, const ThinnedCloud& thinned,
  const std::vector<PolySegment>& segments, const std::vector<std::int64_t>& pointComponent,
  const SkeletonOptions& options, const ParallelFor& parallelFor, const ProgressCallback& progress,
  bool& aborted, const RayCaster& volume, CloudNeighborGraph& neighbours)
{
  SkeletonConnectionOptions connection = options.Connection;
  connection.MinimumBranchFactor = 0.0;
  return ConnectPolySegments(cloud, thinned, segments, pointComponent, connection, parallelFor,
    progress, aborted, &volume, &neighbours);
}

/// Leaves carried on to their parts' ends (ours; SkeletonLeafExtension.h), then the
/// connection's junction cleaning and bones.
void ExtendLeavesAndCleanJunctions(
  SkeletonGraph& graph, const RayCaster& volume, const SkeletonOptions& options)
{
  ExtendLeavesToPartEnds(graph, volume, options.LeafExtension);
  CleanGraphJunctions(graph, options.Connection.MinimumBranchFactor);
}

/// What the coverage steps read of the cloud: P, its thinning, the component of each point and
/// the connection's neighbour graph on P.
struct CloudView
{
  const ProjectedCloud& Cloud;
  const ThinnedCloud& Thinned;
  const std::vector<std::int64_t>& PointComponent;
  const CloudNeighborGraph& Neighbours;
};

/// Branches into the parts the skeleton does not reach (ours; SkeletonCoverage.h).
/// Its branches join the nearest node, which may lie a node or two from a junction: their
/// junctions are cleaned too, but its leaves are not pruned: a branch reaching a part far
/// from the skeleton (an ear) can be shorter than the radius at its junction (the torso's).
void ReachUncoveredPartsAndCleanJunctions(SkeletonGraph& graph, const CloudView& cloud,
  const SkeletonOptions& options, const ParallelFor& parallelFor, const RayCaster* volume)
{
  if (ReachUncoveredParts(graph, cloud.Cloud, cloud.Thinned, cloud.PointComponent, cloud.Neighbours,
        options.Coverage, parallelFor, volume) > 0)
  {
    CleanGraphJunctions(graph, options.Connection.MinimumBranchFactor, LeafPruning::Keep);
  }
}

/// Face centres pushed inward by SDF/2 (the link to the skeleton, and the fallback node of a
/// component without samples), computed where they are read rather than stored: the link reads
/// each face's a few times, and a stored copy was 20 MB of the skeleton's peak at 832k faces
/// (docs/distributed.md). One function, so every read gives the same bits.
class ProjectedFaceCentres
{
public:
  ProjectedFaceCentres(PointsView points, TrianglesView triangles, const std::vector<double>& faceSdf,
    PointsView faceNormals)
    : Points(points)
    , Triangles(triangles)
    , FaceSdf(faceSdf)
    , FaceNormals(faceNormals)
  {
  }

  Eigen::Vector3d operator()(std::size_t f) const
  {
    const auto face = static_cast<Eigen::Index>(f);
    const Eigen::Vector3d a = Points.row(Triangles(face, 0)).transpose();
    const Eigen::Vector3d b = Points.row(Triangles(face, 1)).transpose();
    const Eigen::Vector3d c = Points.row(Triangles(face, 2)).transpose();
    const Eigen::Vector3d normal = EffectiveFaceNormal(Points, Triangles, FaceNormals, face);
    return (a + b + c) / 3.0 - 0.5 * FaceSdf[f] * normal;
  }

private:
  PointsView Points;
  TrianglesView Triangles;
  const std::vector<double>& FaceSdf;
  PointsView FaceNormals;
};

/// Face areas, 0 where not finite.
std::vector<double> FaceAreas(PointsView points, TrianglesView triangles, const ParallelFor& parallelFor)
{
  std::vector<double> faceArea(static_cast<std::size_t>(triangles.rows()));
  parallelFor(faceArea.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f)
    {
      const auto face = static_cast<Eigen::Index>(f);
      const Eigen::Vector3d a = points.row(triangles(face, 0)).transpose();
      const double area = 0.5 *
        (points.row(triangles(face, 1)).transpose() - a).cross(points.row(triangles(face, 2)).transpose() - a).norm();
      faceArea[f] = std::isfinite(area) ? area : 0.0;
    }
  });
  return faceArea;
}

/// What the surface link reads of the faces.
struct SurfaceFaces
{
  /// Surface component per face, dense labels 0.. (LabelFaceComponents, DenseLabels).
  const std::vector<std::int64_t>& Component;
  /// Part label per face, or empty.
  const std::vector<std::int64_t>& Parts;
  const ProjectedFaceCentres& ProjectedCentre;
  const std::vector<double>& Area;

  std::size_t Size() const { return Area.size(); }
};

/// A single node at the projected centre of the largest face of every component that has no
/// node (no samples: tiny area, or only degenerate faces); each becomes a bone of its own.
void AddFallbackNodes(
  SkeletonGraph& graph, const SurfaceFaces& surface, const std::vector<double>& faceSdf)
{
  const std::vector<std::int64_t>& faceComponent = surface.Component;
  std::vector<char> componentHasNode(
    static_cast<std::size_t>(*std::max_element(faceComponent.begin(), faceComponent.end()) + 1), 0);
  for (const std::int64_t c : graph.NodeComponent)
  {
    componentHasNode[static_cast<std::size_t>(c)] = 1;
  }
  std::map<std::int64_t, std::size_t> largestFace;
  for (std::size_t f = 0; f < surface.Size(); ++f)
  {
    const std::int64_t c = faceComponent[f];
    if (componentHasNode[static_cast<std::size_t>(c)])
    {
      continue;
    }
    const auto found = largestFace.find(c);
    if (found == largestFace.end() || surface.Area[found->second] < surface.Area[f])
    {
      largestFace[c] = f;
    }
  }
  std::vector<Eigen::Vector3d> extraPositions;
  for (const auto& [c, f] : largestFace)
  {
    extraPositions.push_back(surface.ProjectedCentre(f));
    graph.NodeRadius.push_back(0.5 * faceSdf[f]);
    graph.NodeConfidence.push_back(0.0);
    graph.NodeCloudIndex.push_back(-1);
    graph.NodeComponent.push_back(c);
    graph.Polylines.push_back({ static_cast<std::int64_t>(graph.NodeRadius.size()) - 1 });
    graph.IsConnection.push_back(0);
  }
  if (!extraPositions.empty())
  {
    const Eigen::Index before = graph.NodePositions.rows();
    graph.NodePositions.conservativeResize(before + static_cast<Eigen::Index>(extraPositions.size()), 3);
    for (std::size_t i = 0; i < extraPositions.size(); ++i)
    {
      graph.NodePositions.row(before + static_cast<Eigen::Index>(i)) = extraPositions[i].transpose();
    }
    AssignBranchBones(graph);
  }
}

/// The nearest-node link: every face to the node of its own component nearest to its
/// projected centre, and to that node's bone. Made again whenever ReachPartsWithoutOwnBones
/// adds a branch.
void LinkToNearestNodes(const SkeletonGraph& graph, const SurfaceFaces& surface,
  const ParallelFor& parallelFor, SkeletonResult& result)
{
  const std::vector<std::int64_t>& faceComponent = surface.Component;
  const bool singleComponent =
    *std::max_element(faceComponent.begin(), faceComponent.end()) == 0;
  const SkeletonPointTree nodeTree(graph.NodePositions);
  result.FaceNodeId.assign(surface.Size(), 0);
  result.FaceBoneId.assign(surface.Size(), 0);
  parallelFor(surface.Size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f)
    {
      const std::int64_t c = faceComponent[f];
      const Eigen::Vector3d centre = surface.ProjectedCentre(f);
      // One component: no predicate, so the search makes no call per candidate.
      const std::int64_t node = singleComponent
        ? nodeTree.NearestAccepted(centre, {})
        : nodeTree.NearestAccepted(centre, [&](std::int64_t n) { return graph.NodeComponent[n] == c; });
      result.FaceNodeId[f] = node;
      result.FaceBoneId[f] = graph.NodeBone[node];
    }
  });
}

/// The bone of every face's part (LinkPartsToBones) and whether each part got one of its own.
struct PartBones
{
  std::vector<std::int64_t> FaceBone;
  std::vector<char> HasOwnBone;
};

PartBones LinkParts(
  const SurfaceFaces& surface, const std::vector<std::int64_t>& faceBone, double ownBoneShare)
{
  PartBones parts;
  parts.FaceBone = LinkPartsToBones(
    surface.Parts, surface.Component, surface.Area, faceBone, ownBoneShare, &parts.HasOwnBone);
  return parts;
}

/// Number of points of P per part (PartsWithinComponents labels).
std::vector<std::size_t> PointsPerPart(
  const std::vector<std::int64_t>& part, const ProjectedCloud& cloud)
{
  std::vector<std::size_t> partPoints(
    static_cast<std::size_t>(*std::max_element(part.begin(), part.end()) + 1), 0);
  for (const std::int64_t face : cloud.SourceFace)
  {
    ++partPoints[static_cast<std::size_t>(part[static_cast<std::size_t>(face)])];
  }
  return partPoints;
}

/// The largest part not yet tried that has no bone of its own and at least minimumPoints
/// (and at least one) points of P; -1 if none (ties: the lowest part).
std::int64_t LargestPartWithoutOwnBone(const std::vector<std::size_t>& partPoints,
  const std::vector<char>& partHasOwnBone, const std::vector<char>& tried, double minimumPoints)
{
  std::int64_t target = -1;
  for (std::size_t q = 0; q < partPoints.size(); ++q)
  {
    if (!partHasOwnBone[q] && !tried[q] && static_cast<double>(partPoints[q]) >= minimumPoints && partPoints[q] > 0 &&
      (target < 0 || partPoints[q] > partPoints[static_cast<std::size_t>(target)]))
    {
      target = static_cast<std::int64_t>(q);
    }
  }
  return target;
}

/// A branch into every large part left without a bone of its own (ours; ReachPartsWithoutBones
/// and the header comment), largest part first, each part once; after each branch the
/// junctions are cleaned as after ReachUncoveredParts and both links are made again.
void ReachPartsWithoutOwnBones(SkeletonGraph& graph, const CloudView& cloud,
  const SurfaceFaces& surface, const SkeletonOptions& options, const ParallelFor& parallelFor,
  SkeletonResult& result, PartBones& partBones)
{
  const std::vector<std::int64_t> part = PartsWithinComponents(surface.Parts, surface.Component);
  const std::vector<std::size_t> partPoints = PointsPerPart(part, cloud.Cloud);
  const double minimumPoints =
    options.Coverage.PartMinimumShare * static_cast<double>(cloud.Cloud.Size());
  std::vector<char> tried(partPoints.size(), 0);
  while (options.Coverage.PartUncoveredFactor > 0.0)
  {
    const std::int64_t target =
      LargestPartWithoutOwnBone(partPoints, partBones.HasOwnBone, tried, minimumPoints);
    if (target < 0)
    {
      break;
    }
    tried[static_cast<std::size_t>(target)] = 1;
    std::vector<char> inPart(cloud.Cloud.Size(), 0);
    for (std::size_t i = 0; i < cloud.Cloud.Size(); ++i)
    {
      inPart[i] = part[static_cast<std::size_t>(cloud.Cloud.SourceFace[i])] == target;
    }
    if (ReachPartsWithoutBones(graph, cloud.Cloud, cloud.Thinned, cloud.PointComponent,
          cloud.Neighbours, inPart, options.Coverage, parallelFor) > 0)
    {
      CleanGraphJunctions(graph, options.Connection.MinimumBranchFactor, LeafPruning::Keep);
      LinkToNearestNodes(graph, surface, parallelFor, result);
      partBones = LinkParts(surface, result.FaceBoneId, options.OwnBoneShare);
    }
  }
}

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

/// The node of `nodes` nearest to `centre`, -1 for none: a scan in index order
/// (ties to the lower index, as the tree's search), far cheaper than a tree search whose
/// predicate rejects all but a few dozen nodes.
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

/// A face moved to its part's bone links to that bone's nearest node.
void MoveFacesToPartBones(const SkeletonGraph& graph, const SurfaceFaces& surface,
  const std::vector<std::int64_t>& partBone, const ParallelFor& parallelFor, SkeletonResult& result)
{
  const std::vector<std::vector<std::int64_t>> boneNodes = NodesOfBones(graph);
  parallelFor(surface.Size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f)
    {
      const std::int64_t bone = partBone[f];
      if (bone == result.FaceBoneId[f])
      {
        continue;
      }
      result.FaceNodeId[f] =
        NearestNodeAmong(graph, boneNodes[static_cast<std::size_t>(bone)], surface.ProjectedCentre(f));
      result.FaceBoneId[f] = bone;
    }
  });
}

/// The surface link: nearest node of the same component to each projected face centre; with
/// part labels, every part then takes one bone (LinkPartsToBones), after the parts without a
/// bone of their own got a branch (ReachPartsWithoutOwnBones).
void LinkSurfaceToSkeleton(SkeletonGraph& graph, const CloudView& cloud,
  const SurfaceFaces& surface, const SkeletonOptions& options, const ParallelFor& parallelFor,
  SkeletonResult& result)
{
  LinkToNearestNodes(graph, surface, parallelFor, result);
  if (surface.Parts.empty())
  {
    return;
  }
  PartBones partBones = LinkParts(surface, result.FaceBoneId, options.OwnBoneShare);
  ReachPartsWithoutOwnBones(graph, cloud, surface, options, parallelFor, result, partBones);
  MoveFacesToPartBones(graph, surface, partBones.FaceBone, parallelFor, result);
}

/// After the bones moved (SmoothBones): every face to the nearest node of the bone it is linked
/// to (its bone does not change).
void LinkFacesToNodesOfTheirBones(const SkeletonGraph& graph, const SurfaceFaces& surface,
  const ParallelFor& parallelFor, SkeletonResult& result)
{
  const std::vector<std::vector<std::int64_t>> boneNodes = NodesOfBones(graph);
  parallelFor(surface.Size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f)
    {
      const std::int64_t nearest = NearestNodeAmong(
        graph, boneNodes[static_cast<std::size_t>(result.FaceBoneId[f])], surface.ProjectedCentre(f));
      if (nearest >= 0)
      {
        result.FaceNodeId[f] = nearest;
      }
    }
  });
}

/// After the bones moved (SmoothBones): the bones numbered again by their smoothed lengths
/// (AssignBranchBones on the same topology gives the same branches, so only their order and
/// lengths can change) and every face's SkeletonBoneId renamed with them.
void RenumberBonesBySmoothedLength(SkeletonGraph& graph, SkeletonResult& result)
{
  std::map<std::pair<std::int64_t, std::int64_t>, std::int64_t> oldBoneOfEdge;
  for (std::size_t p = 0; p < graph.Polylines.size(); ++p)
  {
    const std::vector<std::int64_t>& polyline = graph.Polylines[p];
    if (polyline.size() >= 2)
    {
      oldBoneOfEdge[std::minmax(polyline[0], polyline[1])] = graph.PolylineBone[p];
    }
  }
  std::vector<std::int64_t> oldBoneOfNode = graph.NodeBone;
  AssignBranchBones(graph);
  std::vector<std::int64_t> newBone(graph.BoneLength.size(), -1);
  for (std::size_t p = 0; p < graph.Polylines.size(); ++p)
  {
    const std::vector<std::int64_t>& polyline = graph.Polylines[p];
    for (std::size_t i = 0; i + 1 < polyline.size(); ++i)
    {
      const auto old = oldBoneOfEdge.find(std::minmax(polyline[i], polyline[i + 1]));
      if (old != oldBoneOfEdge.end())
      {
        newBone[static_cast<std::size_t>(old->second)] = graph.PolylineBone[p];
      }
    }
    if (polyline.size() == 1)
    {
      newBone[static_cast<std::size_t>(oldBoneOfNode[static_cast<std::size_t>(polyline[0])])] =
        graph.PolylineBone[p];
    }
  }
  for (std::int64_t& bone : result.FaceBoneId)
  {
    if (bone >= 0)
    {
      bone = newBone[static_cast<std::size_t>(bone)];
    }
  }
}

/// The skeleton and the cloud into the result (the surface link is already there).
void MoveIntoResult(SkeletonGraph& graph, const ProjectedCloud& cloud, const ThinnedCloud& thinned,
  SkeletonResult& result)
{
  result.NodePositions = std::move(graph.NodePositions);
  result.NodeRadius = std::move(graph.NodeRadius);
  result.NodeConfidence = std::move(graph.NodeConfidence);
  result.NodeBoneId = std::move(graph.NodeBone);
  result.Polylines = std::move(graph.Polylines);
  result.IsConnection = std::move(graph.IsConnection);
  result.BoneId = std::move(graph.PolylineBone);
  result.BoneLength = std::move(graph.BoneLength);
  result.CloudPositions = cloud.Positions;
  result.CloudRadius = cloud.Radius;
  result.CloudConfidence = thinned.Confidence;
  result.CloudSourceFace = cloud.SourceFace;
}

} // namespace

SkeletonResult ComputeSkeleton(PointsView points, TrianglesView triangles,
  const std::vector<double>& faceSdf, PointsView faceNormals,
  const std::vector<std::int64_t>& faceComponents, const SkeletonOptions& options,
  const ParallelFor& parallelFor, const ProgressCallback& progress,
  const std::vector<std::int64_t>& faceParts)
{
  ValidateSkeletonOptions(options);
  ValidateSkeletonInput(points, triangles, faceSdf, faceNormals, faceComponents);
  if (!faceParts.empty() && faceParts.size() != static_cast<std::size_t>(triangles.rows()))
  {
    throw Error("skeleton: face part labels must be empty or one per triangle");
  }
  SkeletonResult result;
  if (triangles.rows() == 0)
  {
    return result;
  }
  const std::vector<std::int64_t> faceComponent = faceComponents.empty()
    ? LabelFaceComponents(triangles, static_cast<std::size_t>(points.rows()))
    : DenseLabels(faceComponents);

  const ProjectedCloud cloud =
    SampleProjectedCloud(points, triangles, faceSdf, faceNormals, options.Sampling);
  if (progress && !progress(0.05))
  {
    return AbortedResult();
  }
  const std::vector<std::int64_t> pointComponent = PointComponents(cloud, faceComponent);

  // Thinning keeps only points whose medial ball fits; growth, connection and coverage move
  // only through the volume.
  const EmbreeRayCaster volume(points, triangles, VolumeOptions());
  const ThinnedCloud thinned =
    ThinProjectedCloud(cloud, options.Thinning, parallelFor, SubProgress(progress, 0.05, 0.65), &volume);
  if (thinned.Aborted)
  {
    return AbortedResult();
  }
  const std::vector<PolySegment> segments =
    GrowPolySegments(cloud, thinned, pointComponent, options.Segments, &volume);
  if (progress && !progress(0.7))
  {
    return AbortedResult();
  }

  bool aborted = false;
  CloudNeighborGraph neighbours;
  SkeletonGraph graph = ConnectThroughVolume(cloud, thinned, segments, pointComponent, options,
    parallelFor, SubProgress(progress, 0.7, 0.9), aborted, volume, neighbours);
  if (aborted)
  {
    return AbortedResult();
  }
  ExtendLeavesAndCleanJunctions(graph, volume, options);
  const CloudView cloudView{ cloud, thinned, pointComponent, neighbours };
  ReachUncoveredPartsAndCleanJunctions(graph, cloudView, options, parallelFor, &volume);
  if (progress && !progress(0.92))
  {
    return AbortedResult();
  }

  const ProjectedFaceCentres projectedCentre(points, triangles, faceSdf, faceNormals);
  const std::vector<double> faceArea = FaceAreas(points, triangles, parallelFor);
  const SurfaceFaces surface{ faceComponent, faceParts, projectedCentre, faceArea };
  AddFallbackNodes(graph, surface, faceSdf);
  LinkSurfaceToSkeleton(graph, cloudView, surface, options, parallelFor, result);
  const bool smoothed = SmoothBones(graph, &volume, options.Smoothing).MovedNodes > 0;
  // Step 7b after the smoothing: the tips follow the smoothed bones' directions.
  const bool tipsAdded = ExtendLeavesToSurface(graph, volume, options.LeafExtension) > 0;
  if (smoothed || tipsAdded)
  {
    RenumberBonesBySmoothedLength(graph, result);
    LinkFacesToNodesOfTheirBones(graph, surface, parallelFor, result);
  }

  MoveIntoResult(graph, cloud, thinned, result);
  if (progress && !progress(1.0))
  {
    return AbortedResult();
  }
  return result;
}

SkeletonResult ComputeSkeleton(PointsView points, TrianglesView triangles,
  const std::vector<double>& faceSdf, const SkeletonOptions& options,
  const ParallelFor& parallelFor)
{
  return ComputeSkeleton(points, triangles, faceSdf, PointMatrix(), {}, options, parallelFor);
}

} // namespace shapediameter
