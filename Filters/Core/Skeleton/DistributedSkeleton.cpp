// SPDX-License-Identifier: BSD-3-Clause
#include "Skeleton/DistributedSkeleton.h"

#include "Mesh/Orientation.h"
#include "Mesh/TrianglesOverProcesses.h"

#include <string>
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
  if (withCloudLabels)
  {
    ownTriangles.Columns.push_back(&input.TriangleCloudLabels);
  }
  WholeTriangles whole = GatherTrianglesOnFirst(ownTriangles, group);
  if (first && whole.Triangles.rows() == 0)
  {
    throw Error("the input has no polygon with three points"); // the adapter's serial wording
  }

  DistributedSkeletonResult result;
  if (first)
  {
    ApplyFlips(whole.Triangles, OrientOutward(whole.Points, whole.Triangles).Flip);
    std::vector<std::int64_t> wholeParts;
    if (withParts)
    {
      wholeParts.assign(whole.Columns[1].begin(), whole.Columns[1].end());
    }
    SkeletonResult skeleton = ComputeSkeleton(
      whole.Points, whole.Triangles, whole.Columns[0], PointMatrix(0, 3), {}, options, parallelFor, progress, wholeParts);
    whole.Points = PointMatrix();
    whole.Triangles = TriangleMatrix();
    result.Aborted = skeleton.Aborted;
    result.Whole = std::move(skeleton);
    if (withCloudLabels)
    {
      const std::vector<double>& labels = whole.Columns.back();
      for (const std::int64_t source : result.Whole.CloudSourceFace)
      {
        result.CloudLabels.push_back(labels[static_cast<std::size_t>(source)]);
      }
    }
    whole.Columns = {};
  }
  // 4. Every process's triangles' links: status, then node and bone per triangle.
  const std::vector<double> part = group.ScatterFromFirst([&](int process) {
    std::vector<double> values{ static_cast<double>(result.Aborted ? Aborted : Computed) };
    if (!result.Aborted)
    {
      for (const std::int64_t w : whole.ProcessTriangles[static_cast<std::size_t>(process)])
      {
        values.push_back(static_cast<double>(result.Whole.FaceNodeId[static_cast<std::size_t>(w)]));
        values.push_back(static_cast<double>(result.Whole.FaceBoneId[static_cast<std::size_t>(w)]));
      }
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
  if (part.size() != 1 + 2 * triangles)
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
  if (first)
  {
    result.Whole.FaceNodeId = {};
    result.Whole.FaceBoneId = {};
    result.WholeTriangleCellId = std::move(whole.TriangleCellId);
  }
  return result;
}

} // namespace shapediameter
