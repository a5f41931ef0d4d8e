// SPDX-License-Identifier: BSD-3-Clause
#include "Skeleton/Skeleton.h"

#include "RayCasting/EmbreeRayCaster.h"

#include <algorithm>
#include <map>
#include <optional>
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

/// The number of dense labels 0.. (0 when there are none).
std::size_t LabelCount(const std::vector<std::int64_t>& labels)
{
  return labels.empty() ? 0 : static_cast<std::size_t>(*std::max_element(labels.begin(), labels.end()) + 1);
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
  const std::size_t parts = LabelCount(part);
  const std::vector<PartOverlap> overlaps = MergeOverlaps({ OverlapPartialsOf(part, nearestBone, faceArea, {}) });
  const std::vector<std::int64_t> partBone = PartBonesFromOverlaps(overlaps, parts, ownBoneShare, partHasOwnBone);
  std::vector<std::int64_t> faceBone(faceParts.size());
  for (std::size_t f = 0; f < faceParts.size(); ++f)
  {
    faceBone[f] = partBone[static_cast<std::size_t>(part[f])];
  }
  return faceBone;
}

namespace
{

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

/// A single node at the projected centre of the largest face of every component that has no
/// node (no samples: tiny area, or only degenerate faces); each becomes a bone of its own.
void AddFallbackNodes(SkeletonGraph& graph, SurfaceLink& link, std::size_t components)
{
  std::vector<char> componentHasNode(components, 0);
  for (const std::int64_t c : graph.NodeComponent)
  {
    componentHasNode[static_cast<std::size_t>(c)] = 1;
  }
  const std::vector<LargestFace> largest = link.LargestFaces(componentHasNode);
  if (largest.empty())
  {
    return;
  }
  const Eigen::Index before = graph.NodePositions.rows();
  graph.NodePositions.conservativeResize(before + static_cast<Eigen::Index>(largest.size()), 3);
  for (std::size_t i = 0; i < largest.size(); ++i)
  {
    graph.NodePositions.row(before + static_cast<Eigen::Index>(i)) = largest[i].ProjectedCentre.transpose();
    graph.NodeRadius.push_back(0.5 * largest[i].Sdf);
    graph.NodeConfidence.push_back(0.0);
    graph.NodeCloudIndex.push_back(-1);
    graph.NodeComponent.push_back(largest[i].Component);
    graph.Polylines.push_back({ static_cast<std::int64_t>(graph.NodeRadius.size()) - 1 });
    graph.IsConnection.push_back(0);
  }
  AssignBranchBones(graph);
}

/// Number of points of P per part.
std::vector<std::size_t> PointsPerPart(const SampledSurface& surface)
{
  std::vector<std::size_t> partPoints(surface.Parts, 0);
  for (const std::int64_t part : surface.PointPart)
  {
    ++partPoints[static_cast<std::size_t>(part)];
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

/// The nearest-node link and, with parts, each part's bone (PartBonesFromOverlaps).
std::vector<std::int64_t> LinkNearestAndParts(
  const SkeletonGraph& graph, SurfaceLink& link, std::size_t parts, double ownBoneShare, std::vector<char>& hasOwnBone)
{
  link.LinkToNearestNodes(graph);
  if (parts == 0)
  {
    return {};
  }
  return PartBonesFromOverlaps(link.Overlaps(), parts, ownBoneShare, &hasOwnBone);
}

/// The surface link: nearest node of the same component to each projected face centre; with
/// part labels, every part then takes one bone (PartBonesFromOverlaps), after a branch into
/// every large part left without a bone of its own (ours; ReachPartsWithoutBones and the header
/// comment), largest part first, each part once; after each branch the junctions are cleaned
/// as after ReachUncoveredParts and both links are made again.
void LinkSurfaceToSkeleton(SkeletonGraph& graph, const CloudView& cloud, const SampledSurface& surface,
  const SkeletonOptions& options, const ParallelFor& parallelFor, SurfaceLink& link)
{
  std::vector<char> hasOwnBone;
  std::vector<std::int64_t> partBone = LinkNearestAndParts(graph, link, surface.Parts, options.OwnBoneShare, hasOwnBone);
  if (surface.Parts == 0)
  {
    return;
  }
  const std::vector<std::size_t> partPoints = PointsPerPart(surface);
  const double minimumPoints = options.Coverage.PartMinimumShare * static_cast<double>(cloud.Cloud.Size());
  std::vector<char> tried(partPoints.size(), 0);
  while (options.Coverage.PartUncoveredFactor > 0.0)
  {
    const std::int64_t target = LargestPartWithoutOwnBone(partPoints, hasOwnBone, tried, minimumPoints);
    if (target < 0)
    {
      break;
    }
    tried[static_cast<std::size_t>(target)] = 1;
    std::vector<char> inPart(cloud.Cloud.Size(), 0);
    for (std::size_t i = 0; i < cloud.Cloud.Size(); ++i)
    {
      inPart[i] = surface.PointPart[i] == target;
    }
    if (ReachPartsWithoutBones(graph, cloud.Cloud, cloud.Thinned, cloud.PointComponent, cloud.Neighbours, inPart,
          options.Coverage, parallelFor) > 0)
    {
      CleanGraphJunctions(graph, options.Connection.MinimumBranchFactor, LeafPruning::Keep);
      partBone = LinkNearestAndParts(graph, link, surface.Parts, options.OwnBoneShare, hasOwnBone);
    }
  }
  link.MoveFacesToPartBones(graph, partBone);
}

/// After the bones moved (SmoothBones): the bones numbered again by their smoothed lengths
/// (AssignBranchBones on the same topology gives the same branches, so only their order and
/// lengths can change); returns the new id of every old bone, for the faces' SkeletonBoneId.
std::vector<std::int64_t> RenumberBonesBySmoothedLength(SkeletonGraph& graph)
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
  return newBone;
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

EmbreeRayCasterOptions SkeletonVolumeOptions()
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

SampledSurface SampleSkeletonSurface(PointsView points, TrianglesView triangles, const std::vector<double>& faceSdf,
  PointsView faceNormals, const std::vector<std::int64_t>& faceComponent, const std::vector<std::int64_t>& facePart,
  const SkeletonSamplingOptions& options)
{
  SampledSurface surface;
  surface.Cloud = SampleProjectedCloud(points, triangles, faceSdf, faceNormals, options);
  surface.Components = LabelCount(faceComponent);
  surface.Parts = LabelCount(facePart);
  for (const std::int64_t face : surface.Cloud.SourceFace)
  {
    surface.PointComponent.push_back(faceComponent[static_cast<std::size_t>(face)]);
    if (!facePart.empty())
    {
      surface.PointPart.push_back(facePart[static_cast<std::size_t>(face)]);
    }
  }
  return surface;
}

SkeletonResult ComputeSkeletonOfSamples(const SampledSurface& surface, const RayCaster& volume,
  const SkeletonOptions& options, const ParallelFor& parallelFor, const ProgressCallback& progress,
  const SurfaceLinkSource& link, const RegressionProjector* projector)
{
  if (progress && !progress(0.05))
  {
    return AbortedResult();
  }
  const ProjectedCloud& cloud = surface.Cloud;
  const std::vector<std::int64_t>& pointComponent = surface.PointComponent;
  // Thinning keeps only points whose medial ball fits; growth, connection and coverage move
  // only through the volume.
  const ThinnedCloud thinned =
    ThinProjectedCloud(cloud, options.Thinning, parallelFor, SubProgress(progress, 0.05, 0.65), &volume, projector);
  if (thinned.Aborted)
  {
    return AbortedResult();
  }
  const std::vector<PolySegment> segments =
    GrowPolySegments(cloud, thinned, pointComponent, options.Segments, &volume, parallelFor);
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

  SurfaceLink& surfaceLink = link();
  AddFallbackNodes(graph, surfaceLink, surface.Components);
  LinkSurfaceToSkeleton(graph, cloudView, surface, options, parallelFor, surfaceLink);
  const bool smoothed = SmoothBones(graph, &volume, options.Smoothing).MovedNodes > 0;
  // Step 7b after the smoothing: the tips follow the smoothed bones' directions.
  const bool tipsAdded = ExtendLeavesToSurface(graph, volume, options.LeafExtension) > 0;
  if (smoothed || tipsAdded)
  {
    surfaceLink.RenameBones(RenumberBonesBySmoothedLength(graph));
    surfaceLink.LinkFacesToNodesOfTheirBones(graph);
  }

  SkeletonResult result;
  MoveIntoResult(graph, cloud, thinned, result);
  if (progress && !progress(1.0))
  {
    return AbortedResult();
  }
  return result;
}

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
  if (triangles.rows() == 0)
  {
    return SkeletonResult();
  }
  std::vector<std::int64_t> faceComponent = faceComponents.empty()
    ? LabelFaceComponents(triangles, static_cast<std::size_t>(points.rows()))
    : DenseLabels(faceComponents);
  std::vector<std::int64_t> facePart =
    faceParts.empty() ? std::vector<std::int64_t>() : PartsWithinComponents(faceParts, faceComponent);
  const SampledSurface surface =
    SampleSkeletonSurface(points, triangles, faceSdf, faceNormals, faceComponent, facePart, options.Sampling);
  const EmbreeRayCaster volume(points, triangles, SkeletonVolumeOptions());
  // The link over the mesh's faces, made once the connection is done.
  std::optional<FaceLink> faces;
  std::optional<LocalSurfaceLink> localLink;
  SkeletonResult result = ComputeSkeletonOfSamples(surface, volume, options, parallelFor, progress, [&]() -> SurfaceLink& {
    faces.emplace(points, triangles, faceSdf, faceNormals, std::move(faceComponent), std::move(facePart),
      std::vector<char>(), std::vector<std::int64_t>(), parallelFor);
    return localLink.emplace(*faces);
  });
  if (!result.Aborted && faces)
  {
    result.FaceNodeId = std::move(faces->FaceNodeId);
    result.FaceBoneId = std::move(faces->FaceBoneId);
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
