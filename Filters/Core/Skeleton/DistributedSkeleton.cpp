// SPDX-License-Identifier: BSD-3-Clause
#include "Skeleton/DistributedSkeleton.h"

#include "Mesh/Orientation.h"
#include "Mesh/TrianglesOverProcesses.h"
#include "Skeleton/SkeletonLink.h"
#include "Skeleton/SkeletonSampling.h"

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

/// The link's commands, from the first process to every process (one ScatterFromFirst each;
/// the replies come back with GatherOnFirst).
enum LinkCommand : int
{
  LargestFacesCommand = 0,
  NearestNodesCommand = 1,
  OverlapsCommand = 2,
  PartBonesCommand = 3,
  RenameBonesCommand = 4,
  NodesOfOwnBonesCommand = 5,
  DoneCommand = 6
};

/// What the link reads of the graph: node positions, components and bones, and the bone count.
void PutGraph(const SkeletonGraph& graph, std::vector<double>& message)
{
  const auto nodes = static_cast<std::size_t>(graph.NodePositions.rows());
  message.push_back(static_cast<double>(nodes));
  message.push_back(static_cast<double>(graph.BoneLength.size()));
  for (std::size_t n = 0; n < nodes; ++n)
  {
    for (int axis = 0; axis < 3; ++axis)
    {
      message.push_back(graph.NodePositions(static_cast<Eigen::Index>(n), axis));
    }
    message.push_back(static_cast<double>(graph.NodeComponent[n]));
    message.push_back(static_cast<double>(graph.NodeBone[n]));
  }
}

SkeletonGraph TakeGraph(const std::vector<double>& message, std::size_t& at)
{
  const auto nodes = static_cast<std::size_t>(message.at(at));
  SkeletonGraph graph;
  graph.BoneLength.assign(static_cast<std::size_t>(message.at(at + 1)), 0.0);
  at += 2;
  graph.NodePositions.resize(static_cast<Eigen::Index>(nodes), 3);
  for (std::size_t n = 0; n < nodes; ++n, at += 5)
  {
    for (int axis = 0; axis < 3; ++axis)
    {
      graph.NodePositions(static_cast<Eigen::Index>(n), axis) = message.at(at + static_cast<std::size_t>(axis));
    }
    graph.NodeComponent.push_back(static_cast<std::int64_t>(message.at(at + 3)));
    graph.NodeBone.push_back(static_cast<std::int64_t>(message.at(at + 4)));
  }
  return graph;
}

std::vector<std::int64_t> TakeIds(const std::vector<double>& message, std::size_t& at)
{
  const auto count = static_cast<std::size_t>(message.at(at++));
  std::vector<std::int64_t> ids(count);
  for (std::size_t i = 0; i < count; ++i)
  {
    ids[i] = static_cast<std::int64_t>(message.at(at++));
  }
  return ids;
}

void PutIds(const std::vector<std::int64_t>& ids, std::vector<double>& message)
{
  message.push_back(static_cast<double>(ids.size()));
  message.insert(message.end(), ids.begin(), ids.end());
}

/// One command run on a process's own faces; returns its reply.
std::vector<double> RunLinkCommand(FaceLink& faces, const std::vector<double>& command)
{
  std::size_t at = 1;
  std::vector<double> reply;
  switch (static_cast<int>(command.at(0)))
  {
    case LargestFacesCommand:
    {
      const std::vector<std::int64_t> hasNode = TakeIds(command, at);
      for (const LargestFace& face : faces.LargestFaces(std::vector<char>(hasNode.begin(), hasNode.end())))
      {
        reply.insert(reply.end(), { static_cast<double>(face.Component), face.Area, static_cast<double>(face.Face),
                                    face.ProjectedCentre(0), face.ProjectedCentre(1), face.ProjectedCentre(2), face.Sdf });
      }
      break;
    }
    case NearestNodesCommand:
      faces.LinkToNearestNodes(TakeGraph(command, at));
      break;
    case OverlapsCommand:
      for (const auto& [pair, partials] : faces.OverlapPartials())
      {
        reply.insert(reply.end(), { static_cast<double>(pair.first), static_cast<double>(pair.second),
                                    static_cast<double>(partials.size()) });
        reply.insert(reply.end(), partials.begin(), partials.end());
      }
      break;
    case PartBonesCommand:
    {
      const SkeletonGraph graph = TakeGraph(command, at);
      faces.MoveFacesToPartBones(graph, TakeIds(command, at));
      break;
    }
    case RenameBonesCommand:
      faces.RenameBones(TakeIds(command, at));
      break;
    case NodesOfOwnBonesCommand:
      faces.LinkFacesToNodesOfTheirBones(TakeGraph(command, at));
      break;
    default:
      throw Error("skeleton: an unknown link command");
  }
  return reply;
}

/// The link over processes, as the first process's ComputeSkeleton drives it: each step sent to
/// every process (the first included), run on its own faces, the replies completed here.
class LinkOverProcesses final : public SurfaceLink
{
public:
  LinkOverProcesses(FaceLink& ownFaces, const ProcessGroup& group)
    : OwnFaces(ownFaces)
    , Group(group)
  {
  }

  std::vector<LargestFace> LargestFaces(const std::vector<char>& componentHasNode) override
  {
    std::vector<double> command{ LargestFacesCommand };
    PutIds(std::vector<std::int64_t>(componentHasNode.begin(), componentHasNode.end()), command);
    std::vector<std::vector<LargestFace>> lists;
    for (const std::vector<double>& reply : this->Run(command))
    {
      lists.emplace_back();
      for (std::size_t at = 0; at + 7 <= reply.size(); at += 7)
      {
        lists.back().push_back({ static_cast<std::int64_t>(reply[at]), reply[at + 1], static_cast<std::int64_t>(reply[at + 2]),
          Eigen::Vector3d(reply[at + 3], reply[at + 4], reply[at + 5]), reply[at + 6] });
      }
    }
    return MergeLargestFaces(lists);
  }

  void LinkToNearestNodes(const SkeletonGraph& graph) override
  {
    std::vector<double> command{ NearestNodesCommand };
    PutGraph(graph, command);
    this->Run(command);
  }

  std::vector<PartOverlap> Overlaps() override
  {
    std::vector<OverlapPartialList> lists;
    for (const std::vector<double>& reply : this->Run({ OverlapsCommand }))
    {
      lists.emplace_back();
      for (std::size_t at = 0; at < reply.size();)
      {
        const auto count = static_cast<std::size_t>(reply.at(at + 2));
        lists.back().emplace_back(std::make_pair(static_cast<std::int64_t>(reply[at]), static_cast<std::int64_t>(reply[at + 1])),
          std::vector<double>(reply.begin() + static_cast<std::ptrdiff_t>(at + 3),
            reply.begin() + static_cast<std::ptrdiff_t>(at + 3 + count)));
        at += 3 + count;
      }
    }
    return MergeOverlaps(lists);
  }

  void MoveFacesToPartBones(const SkeletonGraph& graph, const std::vector<std::int64_t>& partBone) override
  {
    std::vector<double> command{ PartBonesCommand };
    PutGraph(graph, command);
    PutIds(partBone, command);
    this->Run(command);
  }

  void RenameBones(const std::vector<std::int64_t>& newBone) override
  {
    std::vector<double> command{ RenameBonesCommand };
    PutIds(newBone, command);
    this->Run(command);
  }

  void LinkFacesToNodesOfTheirBones(const SkeletonGraph& graph) override
  {
    std::vector<double> command{ NodesOfOwnBonesCommand };
    PutGraph(graph, command);
    this->Run(command);
  }

private:
  std::vector<std::vector<double>> Run(const std::vector<double>& command)
  {
    const std::vector<double> own = this->Group.ScatterFromFirst([&](int) { return command; });
    return this->Group.GatherOnFirst(RunLinkCommand(this->OwnFaces, own));
  }

  FaceLink& OwnFaces;
  const ProcessGroup& Group;
};

/// On every process but the first: the link's commands run on the own faces until the first
/// process is done; returns the Done command (status, then the asked triangles).
std::vector<double> ServeLink(FaceLink& ownFaces, const ProcessGroup& group)
{
  while (true)
  {
    std::vector<double> command = group.ScatterFromFirst([](int) { return std::vector<double>(); });
    if (command.empty())
    {
      throw Error("skeleton: the first process sent no link command");
    }
    if (static_cast<int>(command[0]) == DoneCommand)
    {
      return command;
    }
    group.GatherOnFirst(RunLinkCommand(ownFaces, command));
  }
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
  // The geometry first, the SDF and parts once the orientation's adjacency is freed: on the
  // first process the orientation is a peak of the skeleton's memory.
  WholeTriangles whole = GatherTrianglesOnFirst(TriangleShare{ input.Points, input.Triangles, input.TriangleCell,
                                                  share.CellGlobalIds, share.PointGlobalIds, {} },
    group);
  if (first && whole.Triangles.rows() == 0)
  {
    throw Error("the input has no polygon with three points"); // the adapter's serial wording
  }

  // 3. The first process orients the whole mesh and labels its components and parts; every
  // process gets, per own triangle, its flip, component, part, whether it counts in the link's
  // sums (a cell several processes hold counts on the lowest) and its index in the whole mesh.
  const auto ownCount = static_cast<std::size_t>(input.Triangles.rows());
  std::vector<std::int64_t> wholeComponent, wholeParts;
  std::vector<std::uint8_t> flip;
  if (first)
  {
    // What the skeleton does not read is freed before it runs, on the process where it peaks:
    // the cells' ids and the cloud labels are asked of the owners for the cloud's sources only.
    whole.TriangleCellId = {};
    flip = OrientOutward(whole.Points, whole.Triangles).Flip;
    ApplyFlips(whole.Triangles, flip);
    wholeComponent = LabelFaceComponents(whole.Triangles, static_cast<std::size_t>(whole.Points.rows()));
  }
  std::vector<const std::vector<double>*> columns{ &input.TriangleSdf };
  if (withParts)
  {
    columns.push_back(&parts);
  }
  whole.Columns = GatherTriangleColumnsOnFirst(
    columns, whole.ProcessTriangles, static_cast<std::size_t>(whole.Triangles.rows()), group);
  std::vector<double> prepared;
  if (first)
  {
    if (withParts)
    {
      // Dense labels of the (component, label) pairs: the link's part numbers, and the same
      // parts to the sampling.
      wholeParts = PartsWithinComponents(
        std::vector<std::int64_t>(whole.Columns[1].begin(), whole.Columns[1].end()), wholeComponent);
      whole.Columns.resize(1);
    }
    std::vector<std::int64_t> counter(static_cast<std::size_t>(whole.Triangles.rows()), -1);
    for (std::size_t process = 0; process < whole.ProcessTriangles.size(); ++process)
    {
      for (const std::int64_t w : whole.ProcessTriangles[process])
      {
        if (counter[static_cast<std::size_t>(w)] < 0)
        {
          counter[static_cast<std::size_t>(w)] = static_cast<std::int64_t>(process);
        }
      }
    }
    prepared = group.ScatterFromFirst([&](int process) {
      std::vector<double> rows;
      for (const std::int64_t w : whole.ProcessTriangles[static_cast<std::size_t>(process)])
      {
        const auto t = static_cast<std::size_t>(w);
        rows.insert(rows.end(), { static_cast<double>(flip[t]), static_cast<double>(wholeComponent[t]),
                                  wholeParts.empty() ? 0.0 : static_cast<double>(wholeParts[t]),
                                  counter[t] == process ? 1.0 : 0.0, static_cast<double>(w) });
      }
      return rows;
    });
  }
  else
  {
    prepared = group.ScatterFromFirst([](int) { return std::vector<double>(); });
  }
  constexpr std::size_t PreparedWidth = 5; // flip, component, part, counts, index in the whole mesh
  if (prepared.size() != PreparedWidth * ownCount)
  {
    throw Error("skeleton: the first process sent " + std::to_string(prepared.size()) + " link values for " +
      std::to_string(ownCount) + " triangles");
  }
  TriangleMatrix orientedOwn = input.Triangles;
  std::vector<std::uint8_t> ownFlip(ownCount);
  std::vector<std::int64_t> ownComponent(ownCount), ownPart(withParts ? ownCount : 0);
  std::vector<char> ownCounts(ownCount);
  std::vector<std::int64_t> ownWholeIndex(ownCount);
  for (std::size_t t = 0; t < ownCount; ++t)
  {
    const double* row = prepared.data() + PreparedWidth * t;
    ownFlip[t] = static_cast<std::uint8_t>(row[0]);
    ownComponent[t] = static_cast<std::int64_t>(row[1]);
    if (withParts)
    {
      ownPart[t] = static_cast<std::int64_t>(row[2]);
    }
    ownCounts[t] = row[3] != 0.0 ? 1 : 0;
    ownWholeIndex[t] = static_cast<std::int64_t>(row[4]);
  }
  prepared = {};
  // The own triangles wound as in the whole mesh: the same corners in the same order, so the
  // projected centres and areas are the whole mesh's bits.
  ApplyFlips(orientedOwn, ownFlip);
  FaceLink ownFaces(input.Points, orientedOwn, input.TriangleSdf, PointMatrix(0, 3), std::move(ownComponent),
    std::move(ownPart), std::move(ownCounts), std::move(ownWholeIndex), parallelFor);

  // 4. The skeleton on the first process, its link's steps run on every process's faces.
  DistributedSkeletonResult result;
  SourceRequests sources;
  std::vector<double> done;
  if (first)
  {
    // ComputeSkeleton's steps, with the whole mesh freed once it is sampled and copied into the
    // volume (before the volume's BVH is built, where this process peaks): past the sampling,
    // the skeleton reads the surface through the volume and the link alone.
    ValidateSkeletonInput(whole.Points, whole.Triangles, whole.Columns[0], PointMatrix(0, 3), wholeComponent);
    const SampledSurface sampled = SampleSkeletonSurface(
      whole.Points, whole.Triangles, whole.Columns[0], PointMatrix(0, 3), wholeComponent, wholeParts, options.Sampling);
    sources = RequestSources(sampled.Cloud.SourceFace, whole.ProcessTriangles);
    whole.ProcessTriangles = {};
    whole.Columns = {};
    wholeComponent = {};
    wholeParts = {};
    const EmbreeRayCaster volume(std::move(whole.Points), std::move(whole.Triangles), SkeletonVolumeOptions());
    LinkOverProcesses link(ownFaces, group);
    SkeletonResult skeleton =
      ComputeSkeletonOfSamples(sampled, volume, options, parallelFor, progress, [&]() -> SurfaceLink& { return link; });
    result.Aborted = skeleton.Aborted;
    result.Whole = std::move(skeleton);
    // Done: the status, then the share's triangles whose cell id (and cloud label) the first
    // process asks for.
    done = group.ScatterFromFirst([&](int process) {
      std::vector<double> values{ DoneCommand, static_cast<double>(result.Aborted ? Aborted : Computed) };
      const std::vector<double>& asked = sources.Triangles[static_cast<std::size_t>(process)];
      values.insert(values.end(), asked.begin(), asked.end());
      return values;
    });
  }
  else
  {
    done = ServeLink(ownFaces, group);
  }
  if (done.size() < 2 || done[1] != Computed)
  {
    result = DistributedSkeletonResult();
    result.Aborted = true;
    return result;
  }
  result.FaceNodeId = std::move(ownFaces.FaceNodeId);
  result.FaceBoneId = std::move(ownFaces.FaceBoneId);
  // 5. The asked triangles' cell ids and cloud labels, back to the first process.
  std::vector<double> answers;
  for (std::size_t r = 2; r < done.size(); ++r)
  {
    const auto t = static_cast<std::size_t>(done[r]);
    answers.push_back(static_cast<double>(share.CellGlobalIds[static_cast<std::size_t>(input.TriangleCell[t])]));
    answers.push_back(withCloudLabels ? input.TriangleCloudLabels[t] : 0.0);
  }
  const std::vector<std::vector<double>> answered = group.GatherOnFirst(answers);
  if (first)
  {
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
