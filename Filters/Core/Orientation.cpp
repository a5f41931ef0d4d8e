// SPDX-License-Identifier: BSD-3-Clause
#include "Orientation.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <array>
#include <queue>
#include <stdexcept>
#include <tuple>

namespace shapediameter
{
namespace
{
struct DirectedEdge
{
  std::int64_t Low;
  std::int64_t High;
  std::int64_t Triangle;
  bool Forward; // the triangle runs the edge from Low to High
};

/// Total area of the component's triangles.
double Area(const PointsView& points, const TrianglesView& triangles, const std::vector<std::int64_t>& members)
{
  double area = 0.0;
  for (const std::int64_t t : members)
  {
    const Eigen::Vector3d a = points.row(triangles(t, 0)).transpose();
    area += 0.5 * (points.row(triangles(t, 1)).transpose() - a).cross(points.row(triangles(t, 2)).transpose() - a).norm();
  }
  return area;
}

double SignedVolume(const PointsView& points, const TrianglesView& triangles,
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
  for (const std::int64_t t : members)
  {
    const Eigen::Vector3d a = points.row(triangles(t, 0)).transpose() - centroid;
    Eigen::Vector3d b = points.row(triangles(t, 1)).transpose() - centroid;
    Eigen::Vector3d c = points.row(triangles(t, 2)).transpose() - centroid;
    if (flip[static_cast<std::size_t>(t)])
    {
      std::swap(b, c);
    }
    volume += a.dot(b.cross(c));
  }
  return volume / 6.0;
}
} // namespace

TriangleAdjacency BuildTriangleAdjacency(const TrianglesView& triangles)
{
  const std::int64_t count = triangles.rows();
  std::vector<DirectedEdge> edges;
  edges.reserve(static_cast<std::size_t>(count) * 3);
  for (std::int64_t t = 0; t < count; ++t)
  {
    for (int corner = 0; corner < 3; ++corner)
    {
      const std::int64_t a = triangles(t, corner);
      const std::int64_t b = triangles(t, (corner + 1) % 3);
      if (a != b)
      {
        edges.push_back({ std::min(a, b), std::max(a, b), t, a < b });
      }
    }
  }
  std::sort(edges.begin(), edges.end(), [](const DirectedEdge& x, const DirectedEdge& y) {
    return x.Low != y.Low ? x.Low < y.Low : x.High != y.High ? x.High < y.High : x.Triangle < y.Triangle;
  });
  // Manifold edges only: (triangle, neighbour, same direction) twice per edge, then CSR.
  std::vector<std::tuple<std::int64_t, std::int64_t, std::uint8_t>> links;
  links.reserve(edges.size());
  for (std::size_t begin = 0; begin < edges.size();)
  {
    std::size_t end = begin + 1;
    while (end < edges.size() && edges[end].Low == edges[begin].Low && edges[end].High == edges[begin].High)
    {
      ++end;
    }
    if (end - begin == 2 && edges[begin].Triangle != edges[begin + 1].Triangle)
    {
      const DirectedEdge& x = edges[begin];
      const DirectedEdge& y = edges[begin + 1];
      const std::uint8_t same = x.Forward == y.Forward;
      links.emplace_back(x.Triangle, y.Triangle, same);
      links.emplace_back(y.Triangle, x.Triangle, same);
    }
    begin = end;
  }
  std::sort(links.begin(), links.end());
  TriangleAdjacency adjacency;
  adjacency.Offsets.assign(static_cast<std::size_t>(count) + 1, 0);
  adjacency.Neighbors.reserve(links.size());
  adjacency.SameDirection.reserve(links.size());
  for (const auto& [triangle, neighbour, same] : links)
  {
    ++adjacency.Offsets[static_cast<std::size_t>(triangle) + 1];
    adjacency.Neighbors.push_back(neighbour);
    adjacency.SameDirection.push_back(same);
  }
  for (std::size_t t = 0; t < static_cast<std::size_t>(count); ++t)
  {
    adjacency.Offsets[t + 1] += adjacency.Offsets[t];
  }
  return adjacency;
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
  std::vector<std::int64_t> members;
  std::queue<std::int64_t> queue;
  for (std::int64_t seed = 0; seed < count; ++seed)
  {
    if (visited[static_cast<std::size_t>(seed)])
    {
      continue;
    }
    members.clear();
    bool orientable = true;
    visited[static_cast<std::size_t>(seed)] = 1;
    queue.push(seed);
    while (!queue.empty())
    {
      const std::int64_t t = queue.front();
      queue.pop();
      members.push_back(t);
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
          queue.push(neighbour);
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
    const double volume = SignedVolume(points, triangles, members, result.Flip);
    const double area = Area(points, triangles, members);
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
