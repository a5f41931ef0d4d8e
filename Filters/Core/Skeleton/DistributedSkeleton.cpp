// SPDX-License-Identifier: BSD-3-Clause
#include "Skeleton/DistributedSkeleton.h"

#include "Mesh/Orientation.h"
#include "Mesh/TrianglesOverProcesses.h"

#include <string>
#include <unordered_map>
#include <utility>

namespace shapediameter
{

namespace
{

enum SkeletonStatus : int
{
  Computed = 0,
  Aborted = 1
};

/// Where the first process asks for what it needs of the cloud's source triangles: per
/// process, the share's triangles it asks for, and per request, its cloud points.
struct SourceRequests
{
  std::vector<std::vector<double>> Triangles;
  std::vector<std::vector<std::vector<std::size_t>>> Points;
};

/// Each source triangle asked of the lowest process holding it (a cell several processes hold
/// is taken from the lowest, as the whole mesh takes it).
SourceRequests RequestSources(
  const std::vector<std::int64_t>& cloudSourceFace, const std::vector<std::vector<std::int64_t>>& processTriangles)
{
  std::unordered_map<std::int64_t, std::vector<std::size_t>> pointsOfSource;
  for (std::size_t p = 0; p < cloudSourceFace.size(); ++p)
  {
    pointsOfSource[cloudSourceFace[p]].push_back(p);
  }
  SourceRequests requests;
  requests.Triangles.resize(processTriangles.size());
  requests.Points.resize(processTriangles.size());
  for (std::size_t process = 0; process < processTriangles.size(); ++process)
  {
    const std::vector<std::int64_t>& triangles = processTriangles[process];
    for (std::size_t t = 0; t < triangles.size() && !pointsOfSource.empty(); ++t)
    {
      const auto found = pointsOfSource.find(triangles[t]);
      if (found != pointsOfSource.end())
      {
        requests.Triangles[process].push_back(static_cast<double>(t));
        requests.Points[process].push_back(std::move(found->second));
        pointsOfSource.erase(found);
      }
    }
  }
  return requests;
}

} // namespace

DistributedSkeletonResult ComputeSkeletonOverProcesses(const SkeletonShareInput& input,
  const SkeletonShare& share, const SkeletonOptions& options, const ParallelFor& parallelFor,
  const ProgressCallback& progress)
{
  ValidateSkeletonOptions(options);
  const ProcessGroup& group = share.Group;
  const bool first = group.Rank() == 0;
  // Parts and cloud labels are used when every process has them: a serial run links by parts
  // only when every face has a usable label. Every process's pair of flags, concatenated.
  const std::vector<double> having =
    group.AllGather({ input.TriangleParts.empty() ? 0.0 : 1.0, input.TriangleCloudLabels.empty() ? 0.0 : 1.0 });
  bool withParts = true, withCloudLabels = true;
  for (std::size_t p = 0; p + 1 < having.size(); p += 2)
  {
    withParts = withParts && having[p] != 0.0;
    withCloudLabels = withCloudLabels && having[p + 1] != 0.0;
  }
  const std::vector<double> parts = withParts
    ? std::vector<double>(input.TriangleParts.begin(), input.TriangleParts.end())
    : std::vector<double>();
  TriangleShare ownTriangles{ input.Points, input.Triangles, input.TriangleCell, share.CellGlobalIds,
    share.PointGlobalIds, { &input.TriangleSdf } };
  if (withParts)
  {
    ownTriangles.Columns.push_back(&parts);
  }
  WholeTriangles whole = GatherTrianglesOnFirst(ownTriangles, group);
  if (first && whole.Triangles.rows() == 0)
  {
    throw Error("the input has no polygon with three points"); // the adapter's serial wording
  }

  DistributedSkeletonResult result;
  SourceRequests sources;
  if (first)
  {
    // What the skeleton does not read is freed before it runs, on the process where it peaks:
    // the cells' ids and the cloud labels are asked of the owners for the cloud's sources only.
    whole.TriangleCellId = {};
    ApplyFlips(whole.Triangles, OrientOutward(whole.Points, whole.Triangles).Flip);
    std::vector<std::int64_t> wholeParts;
    if (withParts)
    {
      wholeParts.assign(whole.Columns[1].begin(), whole.Columns[1].end());
      whole.Columns.resize(1);
    }
    SkeletonResult skeleton = ComputeSkeleton(
      whole.Points, whole.Triangles, whole.Columns[0], PointMatrix(0, 3), {}, options, parallelFor, progress, wholeParts);
    whole.Points = PointMatrix();
    whole.Triangles = TriangleMatrix();
    whole.Columns = {};
    result.Aborted = skeleton.Aborted;
    result.Whole = std::move(skeleton);
    sources = RequestSources(result.Whole.CloudSourceFace, whole.ProcessTriangles);
  }
  // 4. Every process's triangles' links: status, node and bone per triangle, then the share's
  // triangles whose cell id (and cloud label) the first process asks for.
  const std::vector<double> part = group.ScatterFromFirst([&](int process) {
    std::vector<double> values{ static_cast<double>(result.Aborted ? Aborted : Computed) };
    if (!result.Aborted)
    {
      for (const std::int64_t w : whole.ProcessTriangles[static_cast<std::size_t>(process)])
      {
        values.push_back(static_cast<double>(result.Whole.FaceNodeId[static_cast<std::size_t>(w)]));
        values.push_back(static_cast<double>(result.Whole.FaceBoneId[static_cast<std::size_t>(w)]));
      }
      const std::vector<double>& asked = sources.Triangles[static_cast<std::size_t>(process)];
      values.insert(values.end(), asked.begin(), asked.end());
    }
    return values;
  });
  if (part.empty() || part[0] != Computed)
  {
    result = DistributedSkeletonResult();
    result.Aborted = true;
    return result;
  }
  const auto triangles = static_cast<std::size_t>(input.Triangles.rows());
  if (part.size() < 1 + 2 * triangles)
  {
    throw Error("skeleton: the first process returned " + std::to_string(part.size()) + " values for " +
      std::to_string(triangles) + " triangles");
  }
  result.FaceNodeId.resize(triangles);
  result.FaceBoneId.resize(triangles);
  for (std::size_t t = 0; t < triangles; ++t)
  {
    result.FaceNodeId[t] = static_cast<std::int64_t>(part[1 + 2 * t]);
    result.FaceBoneId[t] = static_cast<std::int64_t>(part[2 + 2 * t]);
  }
  // 5. The asked triangles' cell ids and cloud labels, back to the first process.
  std::vector<double> answers;
  for (std::size_t r = 1 + 2 * triangles; r < part.size(); ++r)
  {
    const auto t = static_cast<std::size_t>(part[r]);
    answers.push_back(static_cast<double>(share.CellGlobalIds[static_cast<std::size_t>(input.TriangleCell[t])]));
    answers.push_back(withCloudLabels ? input.TriangleCloudLabels[t] : 0.0);
  }
  const std::vector<std::vector<double>> answered = group.GatherOnFirst(answers);
  if (first)
  {
    result.Whole.FaceNodeId = {};
    result.Whole.FaceBoneId = {};
    const std::size_t points = result.Whole.CloudSourceFace.size();
    result.CloudSourceCellId.assign(points, -1);
    if (withCloudLabels)
    {
      result.CloudLabels.assign(points, 0.0);
    }
    for (std::size_t process = 0; process < answered.size(); ++process)
    {
      for (std::size_t r = 0; r < sources.Points[process].size(); ++r)
      {
        for (const std::size_t p : sources.Points[process][r])
        {
          result.CloudSourceCellId[p] = static_cast<std::int64_t>(answered[process][2 * r]);
          if (withCloudLabels)
          {
            result.CloudLabels[p] = answered[process][2 * r + 1];
          }
        }
      }
    }
  }
  return result;
}

} // namespace shapediameter
