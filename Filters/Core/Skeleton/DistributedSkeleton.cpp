// SPDX-License-Identifier: BSD-3-Clause
#include "Skeleton/DistributedSkeleton.h"

#include "Mesh/Orientation.h"
#include "Mesh/TrianglesOverProcesses.h"
#include "Release.h"
#include "Skeleton/SkeletonLink.h"
#include "Skeleton/SkeletonPointTree.h"
#include "Skeleton/SkeletonSampling.h"
#include "Skeleton/SkeletonThinning.h"

#include <algorithm>
#include <functional>
#include <limits>
#include <memory>
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
  DoneCommand = 6,
  CastRaysCommand = 7,
  RegressionCommand = 8
};

/// What a process answers the first process's commands with: its own faces (the link's steps),
/// its own triangles' volume (the skeleton's rays) and the tree of the cloud the thinning's MLS
/// iterations query (sent with their first command; its rows are split over the processes).
struct OwnShare
{
  FaceLink& Faces;
  const EmbreeRayCaster& Volume;
  const ParallelFor& Parallel;
  std::unique_ptr<SkeletonPointTree>& Cloud;
};

/// Per row of a RegressionCommand's reply: position, axis, confidence, spread, normal.
constexpr std::size_t RegressionWidth = 13;

/// A ray in a command: point, normal, direction, minimum and maximum distance, rule.
constexpr std::size_t RayWidth = 12;

void PutRay(const Ray& ray, std::vector<double>& message)
{
  if (ray.Origin.SourceTriangle >= 0)
  {
    throw Error("skeleton: a ray of the volume over processes has a source triangle");
  }
  message.insert(message.end(), ray.Origin.Point, ray.Origin.Point + 3);
  message.insert(message.end(), ray.Origin.Normal, ray.Origin.Normal + 3);
  message.insert(message.end(), ray.Direction, ray.Direction + 3);
  message.insert(message.end(), { ray.Origin.MinDistance, ray.Origin.MaxDistance,
                                  ray.Origin.Rule == HitRule::SkipSameFacing ? 1.0 : 0.0 });
}

std::vector<Ray> TakeRays(const std::vector<double>& message, std::size_t at)
{
  std::vector<Ray> rays((message.size() - at) / RayWidth);
  for (Ray& ray : rays)
  {
    const double* values = message.data() + at;
    std::copy(values, values + 3, ray.Origin.Point);
    std::copy(values + 3, values + 6, ray.Origin.Normal);
    std::copy(values + 6, values + 9, ray.Direction);
    ray.Origin.MinDistance = values[9];
    ray.Origin.MaxDistance = values[10];
    ray.Origin.Rule = values[11] != 0.0 ? HitRule::SkipSameFacing : HitRule::FirstHitLeaving;
    at += RayWidth;
  }
  return rays;
}

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

/// One command run on a process's own faces or triangles; returns its reply.
std::vector<double> RunCommand(const OwnShare& own, const std::vector<double>& command)
{
  std::size_t at = 1;
  std::vector<double> reply;
  FaceLink& faces = own.Faces;
  switch (static_cast<int>(command.at(0)))
  {
    case CastRaysCommand:
    {
      // Per ray, the order of the closest hit among the own triangles and its answer.
      std::vector<double> distances;
      std::vector<float> order;
      own.Volume.CastRaysWithOrder(TakeRays(command, at), distances, order, own.Parallel);
      for (std::size_t r = 0; r < distances.size(); ++r)
      {
        reply.insert(reply.end(), { static_cast<double>(order[r]), distances[r] });
      }
      break;
    }
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
    case RegressionCommand:
    {
      // Minimum neighbours, the cloud's rows (none: unchanged), then per own row x y z h.
      const double minimumNeighbors = command.at(at++);
      const auto cloudRows = static_cast<Eigen::Index>(command.at(at++));
      if (cloudRows > 0)
      {
        PointMatrix cloud(cloudRows, 3);
        for (Eigen::Index i = 0; i < cloudRows; ++i, at += 3)
        {
          cloud.row(i) << command.at(at), command.at(at + 1), command.at(at + 2);
        }
        own.Cloud = std::make_unique<SkeletonPointTree>(cloud);
      }
      if (!own.Cloud)
      {
        throw Error("skeleton: an MLS step before its cloud");
      }
      const auto rows = static_cast<Eigen::Index>((command.size() - at) / 4);
      PointMatrix positions(rows, 3);
      std::vector<double> radii(static_cast<std::size_t>(rows));
      for (Eigen::Index i = 0; i < rows; ++i, at += 4)
      {
        positions.row(i) << command[at], command[at + 1], command[at + 2];
        radii[static_cast<std::size_t>(i)] = command[at + 3];
      }
      RegressionProjections answers = RegressionProjections::Zero(rows);
      ProjectOntoRegressionLines(
        *own.Cloud, positions, radii, minimumNeighbors, 0, static_cast<std::size_t>(rows), answers, own.Parallel);
      reply.reserve(RegressionWidth * static_cast<std::size_t>(rows));
      for (Eigen::Index i = 0; i < rows; ++i)
      {
        reply.insert(reply.end(), { answers.Positions(i, 0), answers.Positions(i, 1), answers.Positions(i, 2),
                                    answers.Axis(i, 0), answers.Axis(i, 1), answers.Axis(i, 2),
                                    answers.Confidence[static_cast<std::size_t>(i)], answers.Spread(i, 0),
                                    answers.Spread(i, 1), answers.Spread(i, 2), answers.Normal(i, 0),
                                    answers.Normal(i, 1), answers.Normal(i, 2) });
      }
      break;
    }
    case NodesOfOwnBonesCommand:
      faces.LinkFacesToNodesOfTheirBones(TakeGraph(command, at));
      break;
    default:
      throw Error("skeleton: an unknown link command");
  }
  return reply;
}

/// On the first process: a command sent to every process (the first included), each process's
/// reply in process order.
class CommandsToEveryProcess
{
public:
  CommandsToEveryProcess(const OwnShare& own, const ProcessGroup& group)
    : Own(own)
    , Group(group)
  {
  }

  std::vector<std::vector<double>> Run(const std::vector<double>& command) const
  {
    return this->RunEach([&](int) { return command; });
  }

  /// Each process its own command.
  std::vector<std::vector<double>> RunEach(const std::function<std::vector<double>(int)>& commandOf) const
  {
    const std::vector<double> own = this->Group.ScatterFromFirst(commandOf);
    return this->Group.GatherOnFirst(RunCommand(this->Own, own));
  }

private:
  const OwnShare& Own;
  const ProcessGroup& Group;
};

/// The volume over processes, as the first process's ComputeSkeletonOfSamples casts through it:
/// each ray of a batch sent to every process whose own triangles' box it may meet
/// (RayMayMeetBox; the others have no hit for it), cast against its own triangles, and each
/// ray's answer taken from the process whose closest hit Embree ranks first (the whole mesh's
/// answer, EmbreeRayCaster::CastRaysWithOrder; equal orders: the lowest process's). Unlike
/// RayCaster's other implementations it must be called from one thread (each call is an
/// exchange with every process): the skeleton's steps cast through CastRays from their own
/// thread, never from inside a parallel loop.
class VolumeOverProcesses final : public RayCaster
{
public:
  /// `boxes`: per process, the box of its own triangles.
  VolumeOverProcesses(
    const CommandsToEveryProcess& commands, std::vector<AxisBox> boxes, std::size_t triangles, double diagonal)
    : Commands(commands)
    , Boxes(std::move(boxes))
    , Triangles(triangles)
    , Diagonal(diagonal)
  {
  }

  double ClosestValidHit(const RayOrigin& origin, const double direction[3]) const override
  {
    Ray ray;
    ray.Origin = origin;
    std::copy(direction, direction + 3, ray.Direction);
    std::vector<double> distance;
    this->CastRays({ ray }, distance, SerialFor);
    return distance[0];
  }

  void CastRays(const std::vector<Ray>& rays, std::vector<double>& outDistances, const ParallelFor&) const override
  {
    // Batches of bounded size: the messages and the first process's copies of them stay small.
    constexpr std::size_t batch = 16384;
    outDistances.assign(rays.size(), std::numeric_limits<double>::infinity());
    std::vector<float> lowest(rays.size(), std::numeric_limits<float>::infinity());
    std::vector<std::vector<std::size_t>> sent(this->Boxes.size());
    for (std::size_t begin = 0; begin < rays.size(); begin += batch)
    {
      const std::size_t end = std::min(rays.size(), begin + batch);
      for (std::size_t process = 0; process < sent.size(); ++process)
      {
        sent[process].clear();
        const AxisBox& box = this->Boxes[process];
        const Eigen::Vector3d centre = 0.5 * (box.Low + box.High);
        for (std::size_t r = begin; r < end; ++r)
        {
          // Far above single precision's error on the hits (about 1e-7 of the coordinates
          // measured from the whole mesh's centre).
          const double margin = 1e-5 * (this->Diagonal + (Eigen::Vector3d(rays[r].Origin.Point) - centre).norm());
          if (RayMayMeetBox(rays[r], box, margin))
          {
            sent[process].push_back(r);
          }
        }
      }
      const std::vector<std::vector<double>> replies = this->Commands.RunEach([&](int process) {
        const std::vector<std::size_t>& own = sent[static_cast<std::size_t>(process)];
        std::vector<double> command{ CastRaysCommand };
        command.reserve(1 + RayWidth * own.size());
        for (const std::size_t r : own)
        {
          PutRay(rays[r], command);
        }
        return command;
      });
      for (std::size_t process = 0; process < replies.size(); ++process)
      {
        const std::vector<double>& reply = replies[process];
        const std::vector<std::size_t>& own = sent.at(process);
        if (reply.size() != 2 * own.size())
        {
          throw Error("skeleton: a process answered " + std::to_string(reply.size() / 2) + " of " +
            std::to_string(own.size()) + " rays");
        }
        for (std::size_t i = 0; i < own.size(); ++i)
        {
          const auto order = static_cast<float>(reply[2 * i]);
          if (order < lowest[own[i]])
          {
            lowest[own[i]] = order;
            outDistances[own[i]] = reply[2 * i + 1];
          }
        }
      }
    }
  }

  bool PrefersFewLargeBatches() const override { return true; }
  std::size_t GetNumberOfTriangles() const override { return this->Triangles; }
  double GetBoundingBoxDiagonal() const override { return this->Diagonal; }

private:
  const CommandsToEveryProcess& Commands;
  std::vector<AxisBox> Boxes;
  std::size_t Triangles;
  double Diagonal;
};

/// The thinning's MLS iterations over processes: process p projects the p-th of as many equal
/// ranges of the rows, against its own tree of the cloud (sent when it changes). Each row's
/// answer depends on the row and the cloud alone, so the answers are this process's own.
class RegressionOverProcesses final : public RegressionProjector
{
public:
  RegressionOverProcesses(const CommandsToEveryProcess& commands, std::size_t processes)
    : Commands(commands)
    , Processes(processes)
  {
  }

  RegressionProjections Project(const PointMatrix& cloud, bool cloudChanged, const PointMatrix& positions,
    const std::vector<double>& radii, double minimumNeighbors) const override
  {
    const auto rows = static_cast<std::size_t>(positions.rows());
    const auto firstRow = [&](std::size_t process) { return rows * process / this->Processes; };
    const std::vector<std::vector<double>> replies = this->Commands.RunEach([&](int process) {
      const auto p = static_cast<std::size_t>(process);
      std::vector<double> command{ RegressionCommand, minimumNeighbors, cloudChanged ? static_cast<double>(cloud.rows()) : 0.0 };
      command.reserve(command.size() + (cloudChanged ? 3 * static_cast<std::size_t>(cloud.rows()) : 0) +
        4 * (firstRow(p + 1) - firstRow(p)));
      for (Eigen::Index i = 0; cloudChanged && i < cloud.rows(); ++i)
      {
        command.insert(command.end(), { cloud(i, 0), cloud(i, 1), cloud(i, 2) });
      }
      for (std::size_t r = firstRow(p); r < firstRow(p + 1); ++r)
      {
        const auto i = static_cast<Eigen::Index>(r);
        command.insert(command.end(), { positions(i, 0), positions(i, 1), positions(i, 2), radii[r] });
      }
      return command;
    });
    RegressionProjections answers = RegressionProjections::Zero(positions.rows());
    for (std::size_t process = 0; process < replies.size(); ++process)
    {
      const std::vector<double>& reply = replies[process];
      const std::size_t begin = firstRow(process);
      if (process >= this->Processes || reply.size() != RegressionWidth * (firstRow(process + 1) - begin))
      {
        throw Error("skeleton: a process answered " + std::to_string(reply.size() / RegressionWidth) +
          " rows of an MLS step");
      }
      for (std::size_t r = begin, at = 0; r < firstRow(process + 1); ++r, at += RegressionWidth)
      {
        const auto i = static_cast<Eigen::Index>(r);
        answers.Positions.row(i) << reply[at], reply[at + 1], reply[at + 2];
        answers.Axis.row(i) << reply[at + 3], reply[at + 4], reply[at + 5];
        answers.Confidence[r] = reply[at + 6];
        answers.Spread.row(i) << reply[at + 7], reply[at + 8], reply[at + 9];
        answers.Normal.row(i) << reply[at + 10], reply[at + 11], reply[at + 12];
      }
    }
    return answers;
  }

private:
  const CommandsToEveryProcess& Commands;
  std::size_t Processes;
};

/// The link over processes, as the first process's ComputeSkeleton drives it: each step sent to
/// every process (the first included), run on its own faces, the replies completed here.
class LinkOverProcesses final : public SurfaceLink
{
public:
  explicit LinkOverProcesses(const CommandsToEveryProcess& commands)
    : Commands(commands)
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
  std::vector<std::vector<double>> Run(const std::vector<double>& command) { return this->Commands.Run(command); }

  const CommandsToEveryProcess& Commands;
};

/// On every process but the first: the link's and the volume's commands run on the own faces
/// and triangles until the first process is done; returns the Done command (status, then the
/// asked triangles).
std::vector<double> ServeCommands(const OwnShare& own, const ProcessGroup& group)
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
    group.GatherOnFirst(RunCommand(own, command));
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
    Release(whole.TriangleCellId);
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
  double wholeDiagonal = 0.0;
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
    // The whole mesh's bounding box: its centre to every process, whose volume's vertices are
    // translated by it as the whole mesh's would be (EmbreeRayCasterOptions::Centre).
    const Eigen::RowVector3d lowest = whole.Points.colwise().minCoeff(), highest = whole.Points.colwise().maxCoeff();
    const Eigen::RowVector3d centre = 0.5 * (highest + lowest);
    wholeDiagonal = (highest - lowest).norm();
    prepared = group.ScatterFromFirst([&](int process) {
      std::vector<double> rows{ centre(0), centre(1), centre(2) };
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
  if (prepared.size() != 3 + PreparedWidth * ownCount)
  {
    throw Error("skeleton: the first process sent " + std::to_string(prepared.size()) + " link values for " +
      std::to_string(ownCount) + " triangles");
  }
  EmbreeRayCasterOptions volumeOptions = SkeletonVolumeOptions();
  volumeOptions.Centre = { prepared[0], prepared[1], prepared[2] };
  prepared.erase(prepared.begin(), prepared.begin() + 3);
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
  Release(prepared);
  // The own triangles wound as in the whole mesh: the same corners in the same order, so the
  // projected centres and areas are the whole mesh's bits.
  ApplyFlips(orientedOwn, ownFlip);
  FaceLink ownFaces(input.Points, orientedOwn, input.TriangleSdf, PointMatrix(0, 3), std::move(ownComponent),
    std::move(ownPart), std::move(ownCounts), std::move(ownWholeIndex), parallelFor);
  // The own triangles' volume; on the first process once the whole mesh is freed (below).
  std::unique_ptr<EmbreeRayCaster> ownVolume;
  const auto buildOwnVolume = [&]() {
    ownVolume = std::make_unique<EmbreeRayCaster>(input.Points, orientedOwn, volumeOptions);
  };

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
    std::vector<AxisBox> boxes(whole.ProcessTriangles.size());
    for (std::size_t process = 0; process < boxes.size(); ++process)
    {
      for (const std::int64_t w : whole.ProcessTriangles[process])
      {
        for (int corner = 0; corner < 3; ++corner)
        {
          boxes[process].Extend(whole.Points.row(whole.Triangles(w, corner)).transpose());
        }
      }
    }
    Release(whole.ProcessTriangles);
    Release(whole.Columns);
    Release(wholeComponent);
    Release(wholeParts);
    const auto wholeTriangles = static_cast<std::size_t>(whole.Triangles.rows());
    whole.Points = PointMatrix();
    whole.Triangles = TriangleMatrix();
    buildOwnVolume();
    std::unique_ptr<SkeletonPointTree> cloud;
    const OwnShare own{ ownFaces, *ownVolume, parallelFor, cloud };
    const CommandsToEveryProcess commands(own, group);
    const std::size_t processes = boxes.size();
    const VolumeOverProcesses volume(commands, std::move(boxes), wholeTriangles, wholeDiagonal);
    LinkOverProcesses link(commands);
    const RegressionOverProcesses regression(commands, processes);
    SkeletonResult skeleton = ComputeSkeletonOfSamples(
      sampled, volume, options, parallelFor, progress, [&]() -> SurfaceLink& { return link; }, &regression);
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
    buildOwnVolume();
    std::unique_ptr<SkeletonPointTree> cloud;
    done = ServeCommands(OwnShare{ ownFaces, *ownVolume, parallelFor, cloud }, group);
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
