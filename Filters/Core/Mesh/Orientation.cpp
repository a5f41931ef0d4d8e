// SPDX-License-Identifier: BSD-3-Clause
#include "Mesh/Orientation.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <array>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <tuple>
#include <utility>

namespace shapediameter
{
namespace
{
/// A half-edge in the bucket of its lower vertex: 16 bytes (the lower vertex is the bucket's;
/// 32 bytes when it was stored, 80 MB at 832k triangles, the orientation's peak).
/// A half-edge in its lower vertex's bucket. Index: std::uint32_t when the mesh allows (8 bytes
/// per half-edge: 20 MB less at 832k faces, the adjacency's peak), else std::int64_t.
template <typename Index>
struct DirectedEdge
{
  Index High;
  Index TriangleAndDirection; ///< 2 triangle + 1 if the triangle runs low to high

  std::int64_t Triangle() const { return static_cast<std::int64_t>(TriangleAndDirection >> 1); }
  bool Forward() const { return (TriangleAndDirection & 1) != 0; }
};

/// Signed volume enclosed by the component's triangles (as flipped) and their total area, in
/// one pass after the centroid's.
std::pair<double, double> SignedVolumeAndArea(const PointsView& points, const TrianglesView& triangles,
  const std::vector<std::int64_t>& members, const std::vector<std::uint8_t>& flip)
{
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  for (const std::int64_t t : members)
  {
    for (int corner = 0; corner < 3; ++corner)
    {
      centroid += points.row(triangles(t, corner)).transpose();
    }
  }
  centroid /= 3.0 * static_cast<double>(members.size());
  double volume = 0.0;
  double area = 0.0;
  for (const std::int64_t t : members)
  {
    const Eigen::Vector3d a = points.row(triangles(t, 0)).transpose() - centroid;
    Eigen::Vector3d b = points.row(triangles(t, 1)).transpose() - centroid;
    Eigen::Vector3d c = points.row(triangles(t, 2)).transpose() - centroid;
    area += 0.5 * (b - a).cross(c - a).norm();
    if (flip[static_cast<std::size_t>(t)])
    {
      std::swap(b, c);
    }
    volume += a.dot(b.cross(c));
  }
  return { volume / 6.0, area };
}
/// BuildTriangleAdjacency from the half-edges' bucket offsets (by lower vertex).
template <typename Index>
TriangleAdjacency AdjacencyOfBuckets(
  const TrianglesView& triangles, const std::vector<std::int64_t>& bucket, std::int64_t vertexCount)
{
  const std::int64_t count = triangles.rows();
  std::vector<DirectedEdge<Index>> edges(static_cast<std::size_t>(bucket.back()));
  {
    std::vector<std::int64_t> cursor(bucket.begin(), bucket.end() - 1);
    for (std::int64_t t = 0; t < count; ++t)
    {
      for (int corner = 0; corner < 3; ++corner)
      {
        const std::int64_t a = triangles(t, corner);
        const std::int64_t b = triangles(t, (corner + 1) % 3);
        if (a != b)
        {
          edges[static_cast<std::size_t>(cursor[static_cast<std::size_t>(std::min(a, b))]++)] =
            { static_cast<Index>(std::max(a, b)), static_cast<Index>(2 * t + (a < b ? 1 : 0)) };
        }
      }
    }
  }
  for (std::size_t v = 0; v < static_cast<std::size_t>(vertexCount); ++v)
  {
    std::sort(edges.begin() + bucket[v], edges.begin() + bucket[v + 1],
      [](const DirectedEdge<Index>& x, const DirectedEdge<Index>& y) {
        return x.High != y.High ? x.High < y.High : x.TriangleAndDirection < y.TriangleAndDirection;
      });
  }

  // Manifold edges only: (triangle, neighbour, same direction) twice per edge, counted per
  // triangle into CSR, then each triangle's few links sorted by (neighbour, same direction).
  TriangleAdjacency adjacency;
  adjacency.Offsets.assign(static_cast<std::size_t>(count) + 1, 0);
  const auto forEachManifoldEdge = [&edges, &bucket, vertexCount](auto&& visit) {
    for (std::size_t v = 0; v < static_cast<std::size_t>(vertexCount); ++v)
    {
      const auto bucketEnd = static_cast<std::size_t>(bucket[v + 1]);
      for (auto begin = static_cast<std::size_t>(bucket[v]); begin < bucketEnd;)
      {
        std::size_t end = begin + 1;
        while (end < bucketEnd && edges[end].High == edges[begin].High)
        {
          ++end;
        }
        if (end - begin == 2 && edges[begin].Triangle() != edges[begin + 1].Triangle())
        {
          visit(edges[begin], edges[begin + 1]);
        }
        begin = end;
      }
    }
  };
  forEachManifoldEdge([&](const DirectedEdge<Index>& x, const DirectedEdge<Index>& y) {
    ++adjacency.Offsets[static_cast<std::size_t>(x.Triangle()) + 1];
    ++adjacency.Offsets[static_cast<std::size_t>(y.Triangle()) + 1];
  });
  for (std::size_t t = 0; t < static_cast<std::size_t>(count); ++t)
  {
    adjacency.Offsets[t + 1] += adjacency.Offsets[t];
  }
  adjacency.Neighbors.resize(static_cast<std::size_t>(adjacency.Offsets.back()));
  adjacency.SameDirection.resize(adjacency.Neighbors.size());
  std::vector<std::int64_t> cursor(adjacency.Offsets.begin(), adjacency.Offsets.end() - 1);
  forEachManifoldEdge([&](const DirectedEdge<Index>& x, const DirectedEdge<Index>& y) {
    const std::uint8_t same = x.Forward() == y.Forward();
    for (const auto& [from, to] : { std::pair(x.Triangle(), y.Triangle()), std::pair(y.Triangle(), x.Triangle()) })
    {
      const auto slot = static_cast<std::size_t>(cursor[static_cast<std::size_t>(from)]++);
      adjacency.Neighbors[slot] = to;
      adjacency.SameDirection[slot] = same;
    }
  });
  for (std::size_t t = 0; t < static_cast<std::size_t>(count); ++t)
  {
    // Insertion sort: a triangle has at most three manifold edges.
    const auto first = static_cast<std::size_t>(adjacency.Offsets[t]);
    const auto last = static_cast<std::size_t>(adjacency.Offsets[t + 1]);
    for (std::size_t i = first + 1; i < last; ++i)
    {
      for (std::size_t j = i; j > first &&
           std::tie(adjacency.Neighbors[j], adjacency.SameDirection[j]) <
             std::tie(adjacency.Neighbors[j - 1], adjacency.SameDirection[j - 1]);
           --j)
      {
        std::swap(adjacency.Neighbors[j], adjacency.Neighbors[j - 1]);
        std::swap(adjacency.SameDirection[j], adjacency.SameDirection[j - 1]);
      }
    }
  }
  return adjacency;
}

} // namespace

TriangleAdjacency BuildTriangleAdjacency(const TrianglesView& triangles)
{
  // The half-edges bucketed by their lower vertex (a counting sort, linear in the mesh); a
  // bucket holds a vertex's few edges, sorted by (higher vertex, triangle) in place. Same
  // order as one sort of all 3m half-edges by (low, high, triangle), which took most of the
  // filter's time before the rays at 832k faces (BenchPipeline SDFBreakdown, "orient").
  const std::int64_t count = triangles.rows();
  std::int64_t vertexCount = 0;
  for (std::int64_t t = 0; t < count; ++t)
  {
    for (int corner = 0; corner < 3; ++corner)
    {
      if (triangles(t, corner) < 0)
      {
        throw std::out_of_range("BuildTriangleAdjacency: negative vertex index");
      }
      vertexCount = std::max(vertexCount, triangles(t, corner) + 1);
    }
  }
  std::vector<std::int64_t> bucket(static_cast<std::size_t>(vertexCount) + 1, 0);
  for (std::int64_t t = 0; t < count; ++t)
  {
    for (int corner = 0; corner < 3; ++corner)
    {
      const std::int64_t a = triangles(t, corner);
      const std::int64_t b = triangles(t, (corner + 1) % 3);
      if (a != b)
      {
        ++bucket[static_cast<std::size_t>(std::min(a, b)) + 1];
      }
    }
  }
  for (std::size_t v = 0; v < static_cast<std::size_t>(vertexCount); ++v)
  {
    bucket[v + 1] += bucket[v];
  }
  const bool narrow = vertexCount <= std::numeric_limits<std::uint32_t>::max() &&
    2 * count + 1 <= static_cast<std::int64_t>(std::numeric_limits<std::uint32_t>::max());
  return narrow ? AdjacencyOfBuckets<std::uint32_t>(triangles, bucket, vertexCount)
                : AdjacencyOfBuckets<std::int64_t>(triangles, bucket, vertexCount);
}


OrientationResult OrientOutward(const PointsView& points, const TrianglesView& triangles)
{
  return OrientOutward(points, triangles, BuildTriangleAdjacency(triangles));
}

OrientationResult OrientOutward(
  const PointsView& points, const TrianglesView& triangles, const TriangleAdjacency& adjacency)
{
  const std::int64_t count = triangles.rows();
  for (std::int64_t t = 0; t < count; ++t)
  {
    for (int corner = 0; corner < 3; ++corner)
    {
      if (triangles(t, corner) < 0 || triangles(t, corner) >= points.rows())
      {
        throw std::out_of_range("OrientOutward: triangle vertex index out of range");
      }
    }
  }

  OrientationResult result;
  result.Flip.assign(static_cast<std::size_t>(count), 0);
  std::vector<std::uint8_t> visited(static_cast<std::size_t>(count), 0);
  std::vector<std::int64_t> members; // the component in breadth-first order, also the queue
  for (std::int64_t seed = 0; seed < count; ++seed)
  {
    if (visited[static_cast<std::size_t>(seed)])
    {
      continue;
    }
    members.clear();
    bool orientable = true;
    visited[static_cast<std::size_t>(seed)] = 1;
    members.push_back(seed);
    for (std::size_t next = 0; next < members.size(); ++next)
    {
      const std::int64_t t = members[next];
      for (auto entry = adjacency.Offsets[static_cast<std::size_t>(t)];
           entry < adjacency.Offsets[static_cast<std::size_t>(t) + 1]; ++entry)
      {
        const std::int64_t neighbour = adjacency.Neighbors[static_cast<std::size_t>(entry)];
        // Same direction on a shared edge means opposite windings: the neighbour must
        // end up with the other flip state than ours.
        const std::uint8_t wanted = adjacency.SameDirection[static_cast<std::size_t>(entry)]
          ? !result.Flip[static_cast<std::size_t>(t)]
          : result.Flip[static_cast<std::size_t>(t)];
        auto& other = result.Flip[static_cast<std::size_t>(neighbour)];
        if (!visited[static_cast<std::size_t>(neighbour)])
        {
          visited[static_cast<std::size_t>(neighbour)] = 1;
          other = wanted;
          members.push_back(neighbour);
        }
        else if (other != wanted)
        {
          orientable = false;
        }
      }
    }
    ++result.ComponentCount;
    result.NonOrientableComponents += orientable ? 0 : 1;
    const auto flippedHere = static_cast<std::size_t>(std::count_if(members.begin(), members.end(),
      [&](std::int64_t t) { return result.Flip[static_cast<std::size_t>(t)] != 0; }));
    result.InconsistentComponents += flippedHere > 0 ? 1 : 0;
    // A flat or single-triangle component encloses no volume: its sign is rounding noise,
    // so it keeps the winding it was given.
    const auto [volume, area] = SignedVolumeAndArea(points, triangles, members, result.Flip);
    if (volume < -1e-9 * area * std::sqrt(area))
    {
      for (const std::int64_t t : members)
      {
        result.Flip[static_cast<std::size_t>(t)] ^= 1;
      }
      ++result.InwardComponents;
    }
  }
  result.FlippedTriangles = static_cast<std::size_t>(std::count(result.Flip.begin(), result.Flip.end(), 1));
  return result;
}

void ApplyFlips(TriangleMatrix& triangles, const std::vector<std::uint8_t>& flip)
{
  for (std::int64_t t = 0; t < triangles.rows(); ++t)
  {
    if (flip[static_cast<std::size_t>(t)])
    {
      std::swap(triangles(t, 0), triangles(t, 2));
    }
  }
}

} // namespace shapediameter
