// SPDX-License-Identifier: BSD-3-Clause
#include "Mesh/FaceGraph.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
#include <numeric>
#include <string>
#include <tuple>
#include <utility>

namespace shapediameter
{

namespace
{

using Vec3 = Eigen::Vector3d;
constexpr double Pi = 3.14159265358979323846;

// A polygon side seen from its lower vertex: sorting by (Other, Halfedge) groups the sides
// of one undirected edge together, in face order.
struct BucketEntry
{
  std::int64_t Other;
  std::int64_t Halfedge;
  bool operator<(const BucketEntry& rhs) const
  {
    return Other != rhs.Other ? Other < rhs.Other : Halfedge < rhs.Halfedge;
  }
};

// One edge-sharing incidence of a face, before duplicates (several shared edges) merge.
struct Candidate
{
  std::int64_t Neighbor;
  std::int64_t EdgeLow;
  std::int64_t EdgeHigh;
  double Length;
  bool operator<(const Candidate& rhs) const
  {
    if (Neighbor != rhs.Neighbor)
    {
      return Neighbor < rhs.Neighbor;
    }
    return EdgeLow != rhs.EdgeLow ? EdgeLow < rhs.EdgeLow : EdgeHigh < rhs.EdgeHigh;
  }
};

void ValidateInput(const PointsView& points, const std::vector<std::int64_t>& offsets,
  const std::vector<std::int64_t>& connectivity)
{
  if (offsets.empty())
  {
    if (!connectivity.empty())
    {
      throw Error("face connectivity given without face offsets");
    }
    return;
  }
  if (offsets.front() != 0)
  {
    throw Error("face offsets must start at 0");
  }
  for (std::size_t f = 1; f < offsets.size(); ++f)
  {
    if (offsets[f] < offsets[f - 1])
    {
      throw Error("face offsets decrease at face " + std::to_string(f - 1));
    }
  }
  if (offsets.back() != static_cast<std::int64_t>(connectivity.size()))
  {
    throw Error("last face offset differs from the connectivity size");
  }
  const std::int64_t pointCount = points.rows();
  for (std::int64_t index : connectivity)
  {
    if (index < 0 || index >= pointCount)
    {
      throw Error("point index " + std::to_string(index) + " out of range [0, " +
        std::to_string(pointCount) + ")");
    }
    if (!points.row(index).allFinite())
    {
      throw Error("non-finite coordinates at point " + std::to_string(index));
    }
  }
}

// The polygon sides (half-edges) of the input. Side h of its face runs from connectivity[h] to
// NextVertex(h); sides of faces with fewer than three vertices are not edges.
struct PolygonSides
{
  PolygonSides(const PointsView& points, const std::vector<std::int64_t>& offsets,
    const std::vector<std::int64_t>& connectivity)
    : Points(points)
    , Offsets(offsets)
    , Connectivity(connectivity)
    , FaceCount(offsets.empty() ? 0 : offsets.size() - 1)
    , HalfedgeFace(connectivity.size())
  {
    for (std::size_t f = 0; f < this->FaceCount; ++f)
    {
      std::fill(this->HalfedgeFace.begin() + offsets[f], this->HalfedgeFace.begin() + offsets[f + 1],
        static_cast<std::int64_t>(f));
    }
  }

  Vec3 Point(std::int64_t index) const { return this->Points.row(index).transpose(); }
  std::int64_t FaceSize(std::size_t f) const { return this->Offsets[f + 1] - this->Offsets[f]; }
  std::int64_t NextVertex(std::int64_t h) const
  {
    const std::size_t f = static_cast<std::size_t>(this->HalfedgeFace[static_cast<std::size_t>(h)]);
    return h + 1 < this->Offsets[f + 1] ? this->Connectivity[static_cast<std::size_t>(h + 1)]
                                        : this->Connectivity[static_cast<std::size_t>(this->Offsets[f])];
  }
  bool IsEdge(std::int64_t h) const
  {
    const std::size_t f = static_cast<std::size_t>(this->HalfedgeFace[static_cast<std::size_t>(h)]);
    return this->FaceSize(f) >= 3 && this->Connectivity[static_cast<std::size_t>(h)] != this->NextVertex(h);
  }

  const PointsView& Points;
  const std::vector<std::int64_t>& Offsets;
  const std::vector<std::int64_t>& Connectivity;
  const std::size_t FaceCount;
  std::vector<std::int64_t> HalfedgeFace;
};

/// The total length of face f's sides that are edges (in side order) and their number: the
/// one definition behind MeanEdgeLength and SumSideLengths, so both add the same terms.
std::pair<double, std::int64_t> FacePerimeter(const PolygonSides& sides, std::size_t f)
{
  double perimeter = 0.0;
  std::int64_t count = 0;
  const std::int64_t first = sides.Offsets[f];
  for (std::int64_t h = first; h < first + sides.FaceSize(f); ++h)
  {
    if (sides.IsEdge(h))
    {
      perimeter += (sides.Point(sides.NextVertex(h)) - sides.Point(sides.Connectivity[static_cast<std::size_t>(h)])).norm();
      ++count;
    }
  }
  return { perimeter, count };
}

/// Per face, the total length and the number of its sides that are edges.
struct FacePerimeters
{
  std::vector<double> Lengths;
  std::vector<std::int64_t> SideCounts;
};

/// Centers, Normals, Areas and Degenerate of `graph`; returns the face perimeters.
FacePerimeters ComputeFaceGeometry(const PolygonSides& sides, const ParallelFor& parallelFor, FaceGraph& graph)
{
  const std::size_t faceCount = sides.FaceCount;
  graph.Centers.setZero(static_cast<Eigen::Index>(faceCount), 3);
  graph.Normals.setZero(static_cast<Eigen::Index>(faceCount), 3);
  graph.Areas.assign(faceCount, 0.0);
  graph.Degenerate.assign(faceCount, 1);
  FacePerimeters result;
  std::vector<double>& perimeters = result.Lengths;
  std::vector<std::int64_t>& sideCounts = result.SideCounts;
  perimeters.assign(faceCount, 0.0);
  sideCounts.assign(faceCount, 0);
  parallelFor(faceCount, [&](std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f)
    {
      const std::int64_t first = sides.Offsets[f];
      const std::int64_t size = sides.FaceSize(f);
      if (size == 0)
      {
        continue;
      }
      Vec3 center = Vec3::Zero();
      for (std::int64_t h = first; h < first + size; ++h)
      {
        center += sides.Point(sides.Connectivity[static_cast<std::size_t>(h)]);
      }
      center /= static_cast<double>(size);
      graph.Centers.row(static_cast<Eigen::Index>(f)) = center.transpose();
      if (size < 3)
      {
        continue;
      }
      Vec3 areaVector = Vec3::Zero();
      double squaredSides = 0.0;
      for (std::int64_t h = first; h < first + size; ++h)
      {
        const Vec3 a = sides.Point(sides.Connectivity[static_cast<std::size_t>(h)]);
        const Vec3 b = sides.Point(sides.NextVertex(h));
        areaVector += (a - center).cross(b - center);
        squaredSides += (b - a).squaredNorm();
      }
      std::tie(perimeters[f], sideCounts[f]) = FacePerimeter(sides, f);
      areaVector *= 0.5;
      const double areaNorm = areaVector.norm();
      if (areaNorm > 1e-12 * squaredSides && areaNorm > 0.0)
      {
        graph.Areas[f] = areaNorm;
        graph.Normals.row(static_cast<Eigen::Index>(f)) = (areaVector / areaNorm).transpose();
        graph.Degenerate[f] = 0;
      }
    }
  });
  return result;
}

/// DegenerateFaceCount, MeanEdgeLength and BoundingBoxDiagonal of `graph`. The perimeters are
/// summed exactly (ExactSum): the mean then does not depend on the faces' order or on how they
/// are split between processes (SumSideLengths).
void ComputeMeshMeasures(const PolygonSides& sides, const FacePerimeters& perimeters, FaceGraph& graph)
{
  ExactSum perimeterSum;
  std::int64_t sideSum = 0;
  for (std::size_t f = 0; f < sides.FaceCount; ++f)
  {
    perimeterSum.Add(perimeters.Lengths[f]);
    sideSum += perimeters.SideCounts[f];
    graph.DegenerateFaceCount += graph.Degenerate[f];
  }
  graph.MeanEdgeLength = MeanEdgeLengthOf(perimeterSum.Rounded(), sideSum);
  if (!sides.Connectivity.empty())
  {
    Vec3 lower = Vec3::Constant(std::numeric_limits<double>::infinity());
    Vec3 upper = -lower;
    for (std::int64_t index : sides.Connectivity)
    {
      lower = lower.cwiseMin(sides.Point(index));
      upper = upper.cwiseMax(sides.Point(index));
    }
    graph.BoundingBoxDiagonal = (upper - lower).norm();
  }
}

// The sides of each undirected edge, side by side: Entries[GroupBegin[h], GroupEnd[h]) holds
// all sides of h's undirected edge (both -1 when h is not an edge).
struct EdgeGroups
{
  /// Entries[BucketOffsets[v], BucketOffsets[v + 1]) are the sides whose lower vertex is v.
  std::vector<std::int64_t> BucketOffsets;
  std::vector<BucketEntry> Entries;
  std::vector<std::int64_t> GroupBegin;
  std::vector<std::int64_t> GroupEnd;
};

// A counting sort by lower vertex, then a small sort per vertex bucket.
EdgeGroups GroupEdgeSides(const PolygonSides& sides, const ParallelFor& parallelFor)
{
  const std::size_t halfedgeCount = sides.Connectivity.size();
  const std::size_t pointCount = static_cast<std::size_t>(sides.Points.rows());
  EdgeGroups groups;
  std::vector<std::int64_t>& bucketOffsets = groups.BucketOffsets;
  bucketOffsets.assign(pointCount + 1, 0);
  for (std::size_t h = 0; h < halfedgeCount; ++h)
  {
    if (sides.IsEdge(static_cast<std::int64_t>(h)))
    {
      const std::int64_t low = std::min(sides.Connectivity[h], sides.NextVertex(static_cast<std::int64_t>(h)));
      ++bucketOffsets[static_cast<std::size_t>(low) + 1];
    }
  }
  std::partial_sum(bucketOffsets.begin(), bucketOffsets.end(), bucketOffsets.begin());
  std::vector<BucketEntry>& entries = groups.Entries;
  entries.resize(static_cast<std::size_t>(bucketOffsets.back()));
  {
    std::vector<std::int64_t> fill(bucketOffsets.begin(), bucketOffsets.end() - 1);
    for (std::size_t h = 0; h < halfedgeCount; ++h)
    {
      const auto hh = static_cast<std::int64_t>(h);
      if (sides.IsEdge(hh))
      {
        const std::int64_t a = sides.Connectivity[h];
        const std::int64_t b = sides.NextVertex(hh);
        entries[static_cast<std::size_t>(fill[static_cast<std::size_t>(std::min(a, b))]++)] =
          BucketEntry{ std::max(a, b), hh };
      }
    }
  }
  groups.GroupBegin.assign(halfedgeCount, -1);
  groups.GroupEnd.assign(halfedgeCount, -1);
  parallelFor(pointCount, [&](std::size_t begin, std::size_t end) {
    for (std::size_t v = begin; v < end; ++v)
    {
      const std::int64_t first = bucketOffsets[v];
      const std::int64_t last = bucketOffsets[v + 1];
      std::sort(entries.begin() + first, entries.begin() + last);
      for (std::int64_t groupFirst = first; groupFirst < last;)
      {
        std::int64_t groupLast = groupFirst + 1;
        while (groupLast < last &&
          entries[static_cast<std::size_t>(groupLast)].Other == entries[static_cast<std::size_t>(groupFirst)].Other)
        {
          ++groupLast;
        }
        for (std::int64_t p = groupFirst; p < groupLast; ++p)
        {
          const auto h = static_cast<std::size_t>(entries[static_cast<std::size_t>(p)].Halfedge);
          groups.GroupBegin[h] = groupFirst;
          groups.GroupEnd[h] = groupLast;
        }
        groupFirst = groupLast;
      }
    }
  });
  return groups;
}

/// EdgeCount, BoundaryEdgeCount and NonManifoldEdgeCount of `graph`.
void CountEdges(const EdgeGroups& groups, FaceGraph& graph)
{
  for (std::size_t p = 0; p < groups.Entries.size(); ++p)
  {
    const auto h = static_cast<std::size_t>(groups.Entries[p].Halfedge);
    if (groups.GroupBegin[h] == static_cast<std::int64_t>(p))
    {
      const std::int64_t sides = groups.GroupEnd[h] - groups.GroupBegin[h];
      ++graph.EdgeCount;
      graph.BoundaryEdgeCount += sides == 1;
      graph.NonManifoldEdgeCount += sides >= 3;
    }
  }
}

// The adjacency lists are built in one pass: each face's merged list goes to slots sized by an
// upper bound (its sides' other incidences), compacted afterwards only when merging left gaps.

/// Where each face's slots begin (faceCount + 1 entries); sizes the adjacency arrays of `graph`
/// to the total.
std::vector<std::int64_t> ReserveAdjacencySlots(
  const PolygonSides& sides, const EdgeGroups& groups, const ParallelFor& parallelFor, FaceGraph& graph)
{
  const std::size_t faceCount = sides.FaceCount;
  std::vector<std::int64_t> slotOffsets(faceCount + 1, 0);
  parallelFor(faceCount, [&](std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f)
    {
      std::int64_t bound = 0;
      for (std::int64_t h = sides.Offsets[f]; h < sides.Offsets[f + 1]; ++h)
      {
        const auto hh = static_cast<std::size_t>(h);
        bound += groups.GroupBegin[hh] < 0 ? 0 : groups.GroupEnd[hh] - groups.GroupBegin[hh] - 1;
      }
      slotOffsets[f + 1] = bound;
    }
  });
  std::partial_sum(slotOffsets.begin(), slotOffsets.end(), slotOffsets.begin());
  const auto slotCount = static_cast<std::size_t>(slotOffsets.back());
  graph.Neighbors.resize(slotCount);
  graph.SharedEdgeLengths.resize(slotCount);
  graph.CenterDistances.resize(slotCount);
  graph.NormalAngles.resize(slotCount);
  graph.Concave.resize(slotCount);
  return slotOffsets;
}

/// CenterDistances, NormalAngles and Concave at `slot`, the entry of neighbour candidate.Neighbor
/// in the list of face f.
void ComputePairGeometry(
  const PolygonSides& sides, std::size_t f, const Candidate& candidate, std::size_t slot, FaceGraph& graph)
{
  const Vec3 centerF = graph.Centers.row(static_cast<Eigen::Index>(f)).transpose();
  const Vec3 normalF = graph.Normals.row(static_cast<Eigen::Index>(f)).transpose();
  const Vec3 centerG = graph.Centers.row(static_cast<Eigen::Index>(candidate.Neighbor)).transpose();
  const Vec3 normalG = graph.Normals.row(static_cast<Eigen::Index>(candidate.Neighbor)).transpose();
  const Vec3 edgeMidpoint = 0.5 * (sides.Point(candidate.EdgeLow) + sides.Point(candidate.EdgeHigh));
  const double fold = normalF.dot(centerG - edgeMidpoint) + normalG.dot(centerF - edgeMidpoint);
  const double foldTolerance = 1e-12 * ((centerG - edgeMidpoint).norm() + (centerF - edgeMidpoint).norm());
  graph.CenterDistances[slot] = (centerG - centerF).norm();
  graph.NormalAngles[slot] = std::atan2(normalF.cross(normalG).norm(), normalF.dot(normalG));
  graph.Concave[slot] = fold > foldTolerance ? 1 : 0;
}

/// Writes each face's merged, sorted neighbour list to its slots; returns the list lengths.
std::vector<std::int64_t> FillAdjacencySlots(const PolygonSides& sides, const EdgeGroups& groups,
  const std::vector<std::int64_t>& slotOffsets, const ParallelFor& parallelFor, FaceGraph& graph)
{
  std::vector<std::int64_t> neighborCounts(sides.FaceCount, 0);
  parallelFor(sides.FaceCount, [&](std::size_t begin, std::size_t end) {
    std::vector<Candidate> candidates;
    for (std::size_t f = begin; f < end; ++f)
    {
      candidates.clear();
      for (std::int64_t h = sides.Offsets[f]; h < sides.Offsets[f + 1]; ++h)
      {
        const auto hh = static_cast<std::size_t>(h);
        if (groups.GroupBegin[hh] < 0)
        {
          continue;
        }
        const std::int64_t a = sides.Connectivity[hh];
        const std::int64_t b = sides.NextVertex(h);
        const double length = (sides.Point(b) - sides.Point(a)).norm();
        for (std::int64_t p = groups.GroupBegin[hh]; p < groups.GroupEnd[hh]; ++p)
        {
          const std::int64_t other =
            sides.HalfedgeFace[static_cast<std::size_t>(groups.Entries[static_cast<std::size_t>(p)].Halfedge)];
          if (other != static_cast<std::int64_t>(f))
          {
            candidates.push_back(Candidate{ other, std::min(a, b), std::max(a, b), length });
          }
        }
      }
      std::sort(candidates.begin(), candidates.end());
      // Merge repeats of one neighbour (several shared edges); the first, smallest edge stays.
      auto slot = static_cast<std::size_t>(slotOffsets[f]);
      const std::size_t first = slot;
      for (const Candidate& candidate : candidates)
      {
        if (slot > first && graph.Neighbors[slot - 1] == candidate.Neighbor)
        {
          graph.SharedEdgeLengths[slot - 1] += candidate.Length;
          continue;
        }
        // The pair's geometry is symmetric: computed once, by the lower face (see
        // CopyMirrorGeometry).
        graph.Neighbors[slot] = candidate.Neighbor;
        graph.SharedEdgeLengths[slot] = candidate.Length;
        if (candidate.Neighbor > static_cast<std::int64_t>(f))
        {
          ComputePairGeometry(sides, f, candidate, slot, graph);
        }
        ++slot;
      }
      neighborCounts[f] = static_cast<std::int64_t>(slot - first);
    }
  });
  return neighborCounts;
}

/// Offsets of `graph` from the list lengths; moves the lists down to them when faces sharing
/// several edges left unused slots.
void CompactAdjacency(
  const std::vector<std::int64_t>& slotOffsets, const std::vector<std::int64_t>& neighborCounts, FaceGraph& graph)
{
  const std::size_t faceCount = neighborCounts.size();
  graph.Offsets.assign(faceCount + 1, 0);
  for (std::size_t f = 0; f < faceCount; ++f)
  {
    graph.Offsets[f + 1] = graph.Offsets[f] + neighborCounts[f];
  }
  if (graph.Offsets.back() == slotOffsets.back())
  {
    return;
  }
  for (std::size_t f = 0; f < faceCount; ++f)
  {
    const auto from = static_cast<std::size_t>(slotOffsets[f]);
    const auto to = static_cast<std::size_t>(graph.Offsets[f]);
    for (std::size_t i = 0; i < static_cast<std::size_t>(neighborCounts[f]) && from != to; ++i)
    {
      graph.Neighbors[to + i] = graph.Neighbors[from + i];
      graph.SharedEdgeLengths[to + i] = graph.SharedEdgeLengths[from + i];
      graph.CenterDistances[to + i] = graph.CenterDistances[from + i];
      graph.NormalAngles[to + i] = graph.NormalAngles[from + i];
      graph.Concave[to + i] = graph.Concave[from + i];
    }
  }
  const auto adjacencyCount = static_cast<std::size_t>(graph.Offsets.back());
  graph.Neighbors.resize(adjacencyCount);
  graph.SharedEdgeLengths.resize(adjacencyCount);
  graph.CenterDistances.resize(adjacencyCount);
  graph.NormalAngles.resize(adjacencyCount);
  graph.Concave.resize(adjacencyCount);
}

// The higher face of each pair copies the lower one's geometry from its mirror entry (the
// values are symmetric in f and g, bit for bit: same operands, commuted). Lists are sorted by
// neighbour. Nothing is thrown inside the loop (worker threads): a missing mirror, which the
// construction rules out, is reported after it.
void CopyMirrorGeometry(const ParallelFor& parallelFor, FaceGraph& graph)
{
  std::atomic<bool> mirrorMissing{ false };
  parallelFor(graph.FaceCount(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t f = begin; f < end; ++f)
    {
      for (auto e = static_cast<std::size_t>(graph.Offsets[f]); e < static_cast<std::size_t>(graph.Offsets[f + 1]); ++e)
      {
        const auto g = static_cast<std::size_t>(graph.Neighbors[e]);
        if (g > f)
        {
          continue;
        }
        const auto listEnd = graph.Neighbors.begin() + graph.Offsets[g + 1];
        const auto mirror = std::lower_bound(graph.Neighbors.begin() + graph.Offsets[g], listEnd, static_cast<std::int64_t>(f));
        if (mirror == listEnd || *mirror != static_cast<std::int64_t>(f))
        {
          mirrorMissing = true;
          continue;
        }
        const auto m = static_cast<std::size_t>(mirror - graph.Neighbors.begin());
        graph.CenterDistances[e] = graph.CenterDistances[m];
        graph.NormalAngles[e] = graph.NormalAngles[m];
        graph.Concave[e] = graph.Concave[m];
      }
    }
  });
  if (mirrorMissing)
  {
    throw Error("internal error: the adjacency is not symmetric");
  }
}

} // namespace

double FaceGraph::DihedralAngle(std::int64_t entry) const
{
  const double angle = NormalAngles[static_cast<std::size_t>(entry)];
  return Concave[static_cast<std::size_t>(entry)] ? Pi + angle : Pi - angle;
}

FaceGraph BuildFaceGraph(const PointsView& points, const std::vector<std::int64_t>& faceOffsets,
  const std::vector<std::int64_t>& faceConnectivity, const ParallelFor& parallelFor)
{
  ValidateInput(points, faceOffsets, faceConnectivity);
  // The scratch arrays (sides, perimeters, groups, slot offsets, counts) all live until the
  // end: freeing some of them between the steps changes how glibc trims its heap, and repeated
  // builds got about 3x slower (page faults).
  FaceGraph graph;
  const PolygonSides sides(points, faceOffsets, faceConnectivity);
  const FacePerimeters perimeters = ComputeFaceGeometry(sides, parallelFor, graph);
  ComputeMeshMeasures(sides, perimeters, graph);
  const EdgeGroups groups = GroupEdgeSides(sides, parallelFor);
  CountEdges(groups, graph);
  const std::vector<std::int64_t> slotOffsets = ReserveAdjacencySlots(sides, groups, parallelFor, graph);
  const std::vector<std::int64_t> neighborCounts = FillAdjacencySlots(sides, groups, slotOffsets, parallelFor, graph);
  CompactAdjacency(slotOffsets, neighborCounts, graph);
  CopyMirrorGeometry(parallelFor, graph);
  return graph;
}

namespace
{
// Two independent multiply-xorshift streams over 64-bit words (not cryptographic: a guard
// against a changed mesh, not an adversary).
struct InputHash
{
  std::uint64_t First = 0x9E3779B97F4A7C15ULL;
  std::uint64_t Second = 0xC2B2AE3D27D4EB4FULL;

  void Add(std::uint64_t word)
  {
    First = (First ^ word) * 0x100000001B3ULL;
    First ^= First >> 29;
    Second = (Second + word) * 0xFF51AFD7ED558CCDULL;
    Second ^= Second >> 31;
  }
  void Add(const std::vector<std::int64_t>& words)
  {
    for (const std::int64_t word : words)
    {
      Add(static_cast<std::uint64_t>(word));
    }
  }
};

struct SharedGraphKey
{
  std::size_t PointCount = 0;
  std::size_t OffsetCount = 0;
  std::size_t ConnectivityCount = 0;
  std::uint64_t First = 0;
  std::uint64_t Second = 0;
  bool operator==(const SharedGraphKey& rhs) const
  {
    return PointCount == rhs.PointCount && OffsetCount == rhs.OffsetCount &&
      ConnectivityCount == rhs.ConnectivityCount && First == rhs.First && Second == rhs.Second;
  }
};

SharedGraphKey KeyOf(const PointsView& points, const std::vector<std::int64_t>& faceOffsets,
  const std::vector<std::int64_t>& faceConnectivity)
{
  InputHash hash;
  for (Eigen::Index row = 0; row < points.rows(); ++row)
  {
    for (int column = 0; column < 3; ++column)
    {
      const double coordinate = points(row, column);
      std::uint64_t bits = 0;
      std::memcpy(&bits, &coordinate, sizeof bits);
      hash.Add(bits);
    }
  }
  hash.Add(faceOffsets);
  hash.Add(faceConnectivity);
  return SharedGraphKey{ static_cast<std::size_t>(points.rows()), faceOffsets.size(), faceConnectivity.size(),
    hash.First, hash.Second };
}

struct SharedGraphEntry
{
  SharedGraphKey Key;
  std::weak_ptr<const FaceGraph> Graph;
};

std::mutex SharedGraphMutex;
std::vector<SharedGraphEntry> SharedGraphs; // guarded by SharedGraphMutex
} // namespace

SideLengthSum SumSideLengths(const PointsView& points, const std::vector<std::int64_t>& faceOffsets,
  const std::vector<std::int64_t>& faceConnectivity, const std::vector<std::uint8_t>& faces)
{
  ValidateInput(points, faceOffsets, faceConnectivity);
  const PolygonSides sides(points, faceOffsets, faceConnectivity);
  if (faces.size() != sides.FaceCount)
  {
    throw Error("side lengths: " + std::to_string(faces.size()) + " face flags for " +
      std::to_string(sides.FaceCount) + " faces");
  }
  SideLengthSum sum;
  for (std::size_t f = 0; f < sides.FaceCount; ++f)
  {
    if (faces[f] != 0)
    {
      const auto [perimeter, count] = FacePerimeter(sides, f);
      sum.Length.Add(perimeter);
      sum.Count += count;
    }
  }
  return sum;
}

double MeanEdgeLengthOverProcesses(const PointsView& points, const std::vector<std::int64_t>& faceOffsets,
  const std::vector<std::int64_t>& faceConnectivity, const std::vector<std::uint8_t>& faces,
  const ProcessGroup& group)
{
  const SideLengthSum sides = SumSideLengths(points, faceOffsets, faceConnectivity, faces);
  std::vector<std::int64_t> count{ sides.Count };
  group.SumInPlace(count);
  return MeanEdgeLengthOf(SumOverProcesses(sides.Length, group), count[0]);
}

std::shared_ptr<const FaceGraph> SharedFaceGraph(const PointsView& points,
  const std::vector<std::int64_t>& faceOffsets, const std::vector<std::int64_t>& faceConnectivity,
  const ParallelFor& parallelFor)
{
  const SharedGraphKey key = KeyOf(points, faceOffsets, faceConnectivity);
  {
    const std::lock_guard<std::mutex> lock(SharedGraphMutex);
    SharedGraphs.erase(std::remove_if(SharedGraphs.begin(), SharedGraphs.end(),
                         [](const SharedGraphEntry& entry) { return entry.Graph.expired(); }),
      SharedGraphs.end());
    for (const SharedGraphEntry& entry : SharedGraphs)
    {
      if (entry.Key == key)
      {
        if (std::shared_ptr<const FaceGraph> graph = entry.Graph.lock())
        {
          return graph;
        }
      }
    }
  }
  auto graph = std::make_shared<const FaceGraph>(BuildFaceGraph(points, faceOffsets, faceConnectivity, parallelFor));
  const std::lock_guard<std::mutex> lock(SharedGraphMutex);
  SharedGraphs.push_back(SharedGraphEntry{ key, graph });
  return graph;
}

void TriangleFaces(
  const TrianglesView& triangles, std::vector<std::int64_t>& faceOffsets, std::vector<std::int64_t>& faceConnectivity)
{
  const auto triangleCount = static_cast<std::size_t>(triangles.rows());
  faceOffsets.assign(triangleCount == 0 ? 0 : triangleCount + 1, 0);
  faceConnectivity.resize(3 * triangleCount);
  for (std::size_t t = 0; t < faceOffsets.size(); ++t)
  {
    faceOffsets[t] = static_cast<std::int64_t>(3 * t);
  }
  for (std::size_t t = 0; t < triangleCount; ++t)
  {
    for (int c = 0; c < 3; ++c)
    {
      faceConnectivity[3 * t + static_cast<std::size_t>(c)] = triangles(static_cast<Eigen::Index>(t), c);
    }
  }
}

FaceGraph BuildFaceGraph(const PointsView& points, const TrianglesView& triangles, const ParallelFor& parallelFor)
{
  std::vector<std::int64_t> offsets, connectivity;
  TriangleFaces(triangles, offsets, connectivity);
  return BuildFaceGraph(points, offsets, connectivity, parallelFor);
}

FaceComponents ComputeFaceComponents(const FaceGraph& graph)
{
  FaceComponents components;
  const std::size_t faceCount = graph.FaceCount();
  components.Labels.assign(faceCount, -1);
  std::vector<std::int64_t> stack;
  for (std::size_t seed = 0; seed < faceCount; ++seed)
  {
    if (components.Labels[seed] >= 0)
    {
      continue;
    }
    const auto label = static_cast<std::int64_t>(components.Count++);
    components.Labels[seed] = label;
    stack.assign(1, static_cast<std::int64_t>(seed));
    while (!stack.empty())
    {
      const std::int64_t face = stack.back();
      stack.pop_back();
      for (std::int64_t e = graph.NeighborBegin(face); e < graph.NeighborEnd(face); ++e)
      {
        const std::int64_t other = graph.Neighbors[static_cast<std::size_t>(e)];
        if (components.Labels[static_cast<std::size_t>(other)] < 0)
        {
          components.Labels[static_cast<std::size_t>(other)] = label;
          stack.push_back(other);
        }
      }
    }
  }
  return components;
}

// ---------------------------------------------------------------------------------------
DualGeodesicSearch::DualGeodesicSearch(const FaceGraph& graph)
  : Graph(graph)
  , Table(64, Slot{ -1, 0.0, false })
{
}

void DualGeodesicSearch::ClearTable()
{
  for (std::size_t index : UsedSlots)
  {
    Table[index].Face = -1;
  }
  UsedSlots.clear();
}

void DualGeodesicSearch::Grow()
{
  std::vector<Slot> old;
  old.swap(Table);
  Table.assign(2 * old.size(), Slot{ -1, 0.0, false });
  UsedSlots.clear();
  for (const Slot& slot : old)
  {
    if (slot.Face >= 0)
    {
      *FindOrInsert(slot.Face) = slot;
    }
  }
}

DualGeodesicSearch::Slot* DualGeodesicSearch::FindOrInsert(std::int64_t face)
{
  if (2 * (UsedSlots.size() + 1) > Table.size())
  {
    Grow();
  }
  const std::size_t mask = Table.size() - 1;
  std::size_t index = static_cast<std::size_t>((static_cast<std::uint64_t>(face) * 0x9E3779B97F4A7C15ULL) >> 20) & mask;
  while (Table[index].Face >= 0 && Table[index].Face != face)
  {
    index = (index + 1) & mask;
  }
  if (Table[index].Face < 0)
  {
    Table[index] = Slot{ face, std::numeric_limits<double>::infinity(), false };
    UsedSlots.push_back(index);
  }
  return &Table[index];
}

void DualGeodesicSearch::Run(
  std::int64_t source, double radius, std::size_t maxNeighbors, std::vector<GeodesicNeighbor>& neighbors)
{
  neighbors.clear();
  ClearTable();
  Heap.clear();
  if (maxNeighbors == 0 || !(radius >= 0.0) || source < 0 || static_cast<std::size_t>(source) >= Graph.FaceCount())
  {
    return;
  }
  const auto byDistanceThenFace = std::greater<std::pair<double, std::int64_t>>();
  FindOrInsert(source)->Distance = 0.0;
  Heap.emplace_back(0.0, source);
  while (!Heap.empty())
  {
    std::pop_heap(Heap.begin(), Heap.end(), byDistanceThenFace);
    const auto [distance, face] = Heap.back();
    Heap.pop_back();
    Slot* slot = FindOrInsert(face);
    if (slot->Settled || distance > slot->Distance)
    {
      continue; // stale heap entry
    }
    slot->Settled = true;
    if (face != source)
    {
      neighbors.push_back(GeodesicNeighbor{ face, distance });
      if (neighbors.size() >= maxNeighbors)
      {
        return;
      }
    }
    for (std::int64_t e = Graph.NeighborBegin(face); e < Graph.NeighborEnd(face); ++e)
    {
      const double candidate = distance + Graph.CenterDistances[static_cast<std::size_t>(e)];
      if (candidate > radius)
      {
        continue;
      }
      const std::int64_t other = Graph.Neighbors[static_cast<std::size_t>(e)];
      Slot* otherSlot = FindOrInsert(other);
      if (!otherSlot->Settled && candidate < otherSlot->Distance)
      {
        otherSlot->Distance = candidate;
        Heap.emplace_back(candidate, other);
        std::push_heap(Heap.begin(), Heap.end(), byDistanceThenFace);
      }
    }
  }
}

} // namespace shapediameter
