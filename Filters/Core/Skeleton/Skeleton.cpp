// SPDX-License-Identifier: BSD-3-Clause
#include "Skeleton/Skeleton.h"

#include "RayCasting/EmbreeRayCaster.h"
#include "Skeleton/SkeletonPointTree.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <set>
#include <tuple>
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
  if (!(options.OwnBoneShare >= 0.0 && options.OwnBoneShare <= 1.0))
  {
    throw SkeletonError("skeleton: OwnBoneShare must lie in [0, 1]");
  }
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
/// part is taken within one component (faceComponent: dense labels 0..).
std::vector<std::int64_t> PartsWithinComponents(
  const std::vector<std::int64_t>& faceParts, const std::vector<std::int64_t>& faceComponent)
{
  const std::vector<std::int64_t> densePart = DenseLabels(faceParts);
  const std::int64_t partCount =
    faceParts.empty() ? 0 : *std::max_element(densePart.begin(), densePart.end()) + 1;
  std::vector<std::int64_t> combined(faceParts.size());
  for (std::size_t f = 0; f < faceParts.size(); ++f)
  {
    combined[f] = faceComponent[f] * partCount + densePart[f];
  }
  return DenseLabels(combined);
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

  // Area per (part, bone): faces sorted by that pair, in face order within it (stable), so
  // each sum adds its faces in the same order whatever the labels' values.
  std::vector<std::size_t> order(faceParts.size());
  std::iota(order.begin(), order.end(), std::size_t{ 0 });
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return std::tie(part[a], nearestBone[a]) < std::tie(part[b], nearestBone[b]);
  });
  struct Overlap
  {
    double Area;
    std::size_t Part;
    std::int64_t Bone;
  };
  std::vector<Overlap> overlaps; // in (part, bone) order
  std::vector<std::int64_t> bestBone(parts, -1);
  std::vector<double> bestArea(parts, 0.0);
  std::vector<double> partArea(parts, 0.0);
  for (std::size_t i = 0; i < order.size();)
  {
    const std::size_t first = order[i];
    double area = 0.0;
    for (; i < order.size() && part[order[i]] == part[first] && nearestBone[order[i]] == nearestBone[first]; ++i)
    {
      area += faceArea[order[i]];
    }
    const auto p = static_cast<std::size_t>(part[first]);
    overlaps.push_back({ area, p, nearestBone[first] });
    partArea[p] += area;
    // Bones come in increasing order within a part: a strictly larger area is needed to
    // replace the lower bone (ties: the lowest bone id).
    if (bestBone[p] < 0 || area > bestArea[p])
    {
      bestBone[p] = nearestBone[first];
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
    throw SkeletonError("skeleton: face part labels must be empty or one per triangle");
  }
  SkeletonResult result;
  const auto faces = static_cast<std::size_t>(triangles.rows());
  if (faces == 0)
  {
    return result;
  }
  const std::vector<std::int64_t> faceComponent = faceComponents.empty()
    ? LabelFaceComponents(triangles, static_cast<std::size_t>(points.rows()))
    : DenseLabels(faceComponents);

  // 1. Projected cloud P.
  const ProjectedCloud cloud =
    SampleProjectedCloud(points, triangles, faceSdf, faceNormals, options.Sampling);
  if (progress && !progress(0.05))
  {
    return AbortedResult();
  }
  std::vector<std::int64_t> pointComponent(cloud.Size());
  for (std::size_t i = 0; i < cloud.Size(); ++i)
  {
    pointComponent[i] = faceComponent[cloud.SourceFace[i]];
  }

  // 2. MLS thinning -> T.
  const ThinnedCloud thinned =
    ThinProjectedCloud(cloud, options.Thinning, parallelFor, SubProgress(progress, 0.05, 0.65));
  if (thinned.Aborted)
  {
    return AbortedResult();
  }

  // 3. Poly-segments, through the volume only.
  // Low build quality: the volume answers some 10^5 segment tests, so the build dominates and
  // the faster one wins (832k faces: skeleton 0.82 -> 0.62 s; same output, README "Design
  // measurements"); the SDF's 25 M rays keep Medium.
  EmbreeRayCasterOptions volumeOptions;
  volumeOptions.BuildQuality = EmbreeBuildQuality::Low;
  const EmbreeRayCaster volume(points, triangles, volumeOptions);
  const std::vector<PolySegment> segments =
    GrowPolySegments(cloud, thinned, pointComponent, options.Segments, &volume);
  if (progress && !progress(0.7))
  {
    return AbortedResult();
  }

  // 4. Connection, through the volume only; its neighbour graph on P is kept for step 5. Its
  // junction cleaning waits for 4b, so that a leaf branch is judged with its extension.
  bool aborted = false;
  CloudNeighborGraph neighbours;
  SkeletonConnectionOptions connection = options.Connection;
  connection.MinimumBranchFactor = 0.0;
  SkeletonGraph graph = ConnectPolySegments(cloud, thinned, segments, pointComponent,
    connection, parallelFor, SubProgress(progress, 0.7, 0.9), aborted, &volume, &neighbours);
  if (aborted)
  {
    return AbortedResult();
  }

  // 4b. Leaves carried on to their parts' ends (ours; SkeletonLeafExtension.h), then the
  // connection's junction cleaning and bones.
  ExtendLeavesToPartEnds(graph, volume, options.LeafExtension);
  CleanGraphJunctions(graph, options.Connection.MinimumBranchFactor);

  // 5. Branches into the parts the skeleton does not reach (ours; SkeletonCoverage.h).
  // Its branches join the nearest node, which may lie a node or two from a junction: their
  // junctions are cleaned too, but its leaves are not pruned: a branch reaching a part far
  // from the skeleton (an ear) can be shorter than the radius at its junction (the torso's).
  if (ReachUncoveredParts(graph, cloud, thinned, pointComponent, neighbours, options.Coverage, parallelFor) > 0)
  {
    CleanGraphJunctions(graph, options.Connection.MinimumBranchFactor, LeafPruning::Keep);
  }
  if (progress && !progress(0.92))
  {
    return AbortedResult();
  }

  // Face centres pushed inward by SDF/2: the link to the skeleton, and the fallback node of a
  // component without samples.
  PointMatrix projectedCentres(static_cast<Eigen::Index>(faces), 3);
  std::vector<double> faceArea(faces);
  parallelFor(faces, [&](std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f)
    {
      const auto face = static_cast<Eigen::Index>(f);
      const Eigen::Vector3d a = points.row(triangles(face, 0)).transpose();
      const Eigen::Vector3d b = points.row(triangles(face, 1)).transpose();
      const Eigen::Vector3d c = points.row(triangles(face, 2)).transpose();
      const Eigen::Vector3d normal = EffectiveFaceNormal(points, triangles, faceNormals, face);
      projectedCentres.row(face) = ((a + b + c) / 3.0 - 0.5 * faceSdf[f] * normal).transpose();
      const double area = 0.5 * (b - a).cross(c - a).norm();
      faceArea[f] = std::isfinite(area) ? area : 0.0;
    }
  });
  // Surface components are dense labels (LabelFaceComponents, DenseLabels).
  std::vector<char> componentHasNode(
    static_cast<std::size_t>(*std::max_element(faceComponent.begin(), faceComponent.end()) + 1), 0);
  for (const std::int64_t c : graph.NodeComponent)
  {
    componentHasNode[static_cast<std::size_t>(c)] = 1;
  }
  std::map<std::int64_t, std::size_t> largestFace;
  for (std::size_t f = 0; f < faces; ++f)
  {
    const std::int64_t c = faceComponent[f];
    if (componentHasNode[static_cast<std::size_t>(c)])
    {
      continue;
    }
    const auto found = largestFace.find(c);
    if (found == largestFace.end() || faceArea[found->second] < faceArea[f])
    {
      largestFace[c] = f;
    }
  }
  std::vector<Eigen::Vector3d> extraPositions;
  for (const auto& [c, f] : largestFace)
  {
    extraPositions.emplace_back(projectedCentres.row(static_cast<Eigen::Index>(f)).transpose());
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
    AssignBranchBones(graph); // the fallback nodes become bones of their own
  }

  // Surface link: nearest node of the same component to each projected face centre; with part
  // labels, every part then takes one bone (see LinkPartsToBones).
  const bool singleComponent =
    *std::max_element(faceComponent.begin(), faceComponent.end()) == 0;
  // The tree of the current nodes: rebuilt (with the nearest-node link) whenever step 6 below
  // adds a branch.
  std::optional<SkeletonPointTree> nodeTree;
  const auto linkToNearestNodes = [&]() {
    nodeTree.emplace(graph.NodePositions);
    result.FaceNodeId.assign(faces, 0);
    result.FaceBoneId.assign(faces, 0);
    parallelFor(faces, [&](std::size_t begin, std::size_t end) {
      for (std::size_t f = begin; f < end; ++f)
      {
        const std::int64_t c = faceComponent[f];
        const Eigen::Vector3d centre = projectedCentres.row(static_cast<Eigen::Index>(f)).transpose();
        // One component: no predicate, so the search makes no call per candidate.
        const std::int64_t node = singleComponent
          ? nodeTree->NearestAccepted(centre, {})
          : nodeTree->NearestAccepted(centre, [&](std::int64_t n) { return graph.NodeComponent[n] == c; });
        result.FaceNodeId[f] = node;
        result.FaceBoneId[f] = graph.NodeBone[node];
      }
    });
  };
  linkToNearestNodes();
  if (!faceParts.empty())
  {
    std::vector<char> partHasOwnBone;
    std::vector<std::int64_t> partBone =
      LinkPartsToBones(faceParts, faceComponent, faceArea, result.FaceBoneId, options.OwnBoneShare, &partHasOwnBone);

    // 6. A branch into every large part left without a bone of its own (ours; header
    // comment), largest part first, each part once; the link is made again after each branch.
    const std::vector<std::int64_t> part = PartsWithinComponents(faceParts, faceComponent);
    std::vector<std::size_t> partPoints(static_cast<std::size_t>(*std::max_element(part.begin(), part.end()) + 1), 0);
    for (const std::int64_t face : cloud.SourceFace)
    {
      ++partPoints[static_cast<std::size_t>(part[static_cast<std::size_t>(face)])];
    }
    const double minimumPoints = options.Coverage.PartMinimumShare * static_cast<double>(cloud.Size());
    std::vector<char> tried(partPoints.size(), 0);
    while (options.Coverage.PartUncoveredFactor > 0.0)
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
      if (target < 0)
      {
        break;
      }
      tried[static_cast<std::size_t>(target)] = 1;
      std::vector<char> inPart(cloud.Size(), 0);
      for (std::size_t i = 0; i < cloud.Size(); ++i)
      {
        inPart[i] = part[static_cast<std::size_t>(cloud.SourceFace[i])] == target;
      }
      if (ReachPartsWithoutBones(graph, cloud, thinned, pointComponent, neighbours, inPart, options.Coverage, parallelFor) > 0)
      {
        CleanGraphJunctions(graph, options.Connection.MinimumBranchFactor, LeafPruning::Keep);
        linkToNearestNodes();
        partBone = LinkPartsToBones(
          faceParts, faceComponent, faceArea, result.FaceBoneId, options.OwnBoneShare, &partHasOwnBone);
      }
    }

    // A face moved to its part's bone links to that bone's nearest node: a scan of the bone's
    // nodes in index order (ties to the lower index, as the tree's search), far cheaper than
    // a tree search whose predicate rejects all but a few dozen nodes.
    std::vector<std::vector<std::int64_t>> boneNodes(graph.BoneLength.size());
    for (std::size_t n = 0; n < graph.NodeBone.size(); ++n)
    {
      boneNodes[static_cast<std::size_t>(graph.NodeBone[n])].push_back(static_cast<std::int64_t>(n));
    }
    parallelFor(faces, [&](std::size_t begin, std::size_t end) {
      for (std::size_t f = begin; f < end; ++f)
      {
        const std::int64_t bone = partBone[f];
        if (bone == result.FaceBoneId[f])
        {
          continue;
        }
        const auto row = static_cast<Eigen::Index>(f);
        double best = std::numeric_limits<double>::infinity();
        result.FaceNodeId[f] = -1;
        for (const std::int64_t n : boneNodes[static_cast<std::size_t>(bone)])
        {
          const double dx = graph.NodePositions(n, 0) - projectedCentres(row, 0);
          const double dy = graph.NodePositions(n, 1) - projectedCentres(row, 1);
          const double dz = graph.NodePositions(n, 2) - projectedCentres(row, 2);
          const double squared = dx * dx + dy * dy + dz * dz;
          if (squared < best)
          {
            best = squared;
            result.FaceNodeId[f] = n;
          }
        }
        result.FaceBoneId[f] = bone;
      }
    });
  }

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
