// SPDX-License-Identifier: BSD-3-Clause
// Analytic closed triangle meshes for the core tests and benchmarks (no VTK).
//
// Every generator returns a watertight, consistently oriented mesh whose triangles are
// counter-clockwise seen from outside (outward right-hand-rule normals, as MeshTypes.h
// requires), with shared vertices (no duplicated seam points), and is deterministic.
// Other test files may include this header read-only.
#pragma once

#include "MeshTypes.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <stdexcept>
#include <utility>
#include <vector>

namespace shapediameter
{
namespace testshapes
{

struct TriangleMesh
{
  PointMatrix Points;
  TriangleMatrix Triangles;
};

namespace detail
{
inline TriangleMesh Assemble(const std::vector<Eigen::Vector3d>& points,
  const std::vector<std::array<std::int64_t, 3>>& triangles)
{
  TriangleMesh mesh;
  mesh.Points.resize(static_cast<Eigen::Index>(points.size()), 3);
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    mesh.Points.row(static_cast<Eigen::Index>(i)) = points[i].transpose();
  }
  mesh.Triangles.resize(static_cast<Eigen::Index>(triangles.size()), 3);
  for (std::size_t i = 0; i < triangles.size(); ++i)
  {
    for (int c = 0; c < 3; ++c)
    {
      mesh.Triangles(static_cast<Eigen::Index>(i), c) = triangles[i][c];
    }
  }
  return mesh;
}

/// Orients every triangle so that its normal points away from `centre` (valid for the
/// star-shaped surfaces generated here).
inline void OrientAwayFrom(const std::vector<Eigen::Vector3d>& points,
  std::vector<std::array<std::int64_t, 3>>& triangles, const Eigen::Vector3d& centre)
{
  for (auto& t : triangles)
  {
    const Eigen::Vector3d a = points[t[0]], b = points[t[1]], c = points[t[2]];
    const Eigen::Vector3d normal = (b - a).cross(c - a);
    if (normal.dot((a + b + c) / 3.0 - centre) < 0)
    {
      std::swap(t[1], t[2]);
    }
  }
}
} // namespace detail

/// Geodesic (class I) icosphere: each icosahedron face is split into frequency^2 triangles and
/// the vertices are projected onto the sphere. 20 * frequency^2 faces, 10 * frequency^2 + 2
/// vertices (frequency 32 -> 20480 faces, 51 -> 52020 faces).
inline TriangleMesh MakeIcosphere(int frequency, double radius = 1.0,
  const Eigen::Vector3d& centre = Eigen::Vector3d::Zero())
{
  if (frequency < 1)
  {
    throw std::invalid_argument("MakeIcosphere: frequency must be >= 1");
  }
  const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
  const std::array<Eigen::Vector3d, 12> corners = { Eigen::Vector3d(-1, phi, 0),
    Eigen::Vector3d(1, phi, 0), Eigen::Vector3d(-1, -phi, 0), Eigen::Vector3d(1, -phi, 0),
    Eigen::Vector3d(0, -1, phi), Eigen::Vector3d(0, 1, phi), Eigen::Vector3d(0, -1, -phi),
    Eigen::Vector3d(0, 1, -phi), Eigen::Vector3d(phi, 0, -1), Eigen::Vector3d(phi, 0, 1),
    Eigen::Vector3d(-phi, 0, -1), Eigen::Vector3d(-phi, 0, 1) };
  const int faces[20][3] = { { 0, 11, 5 }, { 0, 5, 1 }, { 0, 1, 7 }, { 0, 7, 10 }, { 0, 10, 11 },
    { 1, 5, 9 }, { 5, 11, 4 }, { 11, 10, 2 }, { 10, 7, 6 }, { 7, 1, 8 }, { 3, 9, 4 }, { 3, 4, 2 },
    { 3, 2, 6 }, { 3, 6, 8 }, { 3, 8, 9 }, { 4, 9, 5 }, { 2, 4, 11 }, { 6, 2, 10 }, { 8, 6, 7 },
    { 9, 8, 1 } };

  // A grid point is identified by its (corner, integer weight) pairs sorted by corner, so
  // points on shared icosahedron edges get the same key (and bit-identical coordinates)
  // from both faces.
  using Key = std::vector<std::pair<int, int>>;
  std::map<Key, std::int64_t> indexOfKey;
  std::vector<Eigen::Vector3d> points;
  auto pointIndex = [&](const int corner[3], int i, int j, int k) {
    Key key;
    const int weights[3] = { i, j, k };
    for (int c = 0; c < 3; ++c)
    {
      if (weights[c] > 0)
      {
        key.emplace_back(corner[c], weights[c]);
      }
    }
    std::sort(key.begin(), key.end());
    auto found = indexOfKey.find(key);
    if (found != indexOfKey.end())
    {
      return found->second;
    }
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    for (const auto& [c, w] : key)
    {
      p += static_cast<double>(w) * corners[c];
    }
    p = centre + radius * p.normalized();
    const auto index = static_cast<std::int64_t>(points.size());
    points.push_back(p);
    indexOfKey.emplace(std::move(key), index);
    return index;
  };

  std::vector<std::array<std::int64_t, 3>> triangles;
  const int n = frequency;
  for (const auto& face : faces)
  {
    // Barycentric grid (i, j, k), i + j + k = n; row j walks from corner 0 to corner 1.
    for (int j = 0; j < n; ++j)
    {
      for (int k = 0; k < n - j; ++k)
      {
        const int i = n - j - k;
        const std::int64_t a = pointIndex(face, i, j, k);
        const std::int64_t b = pointIndex(face, i - 1, j + 1, k);
        const std::int64_t c = pointIndex(face, i - 1, j, k + 1);
        triangles.push_back({ a, b, c });
        if (k + j + 1 < n)
        {
          const std::int64_t d = pointIndex(face, i - 2, j + 1, k + 1);
          triangles.push_back({ b, d, c });
        }
      }
    }
  }
  detail::OrientAwayFrom(points, triangles, centre);
  return detail::Assemble(points, triangles);
}

/// Latitude-longitude sphere: `slices` around the z axis, `stacks` from pole to pole,
/// 2 * slices * (stacks - 1) faces.
inline TriangleMesh MakeUVSphere(int slices, int stacks, double radius = 1.0,
  const Eigen::Vector3d& centre = Eigen::Vector3d::Zero())
{
  if (slices < 3 || stacks < 2)
  {
    throw std::invalid_argument("MakeUVSphere: need slices >= 3 and stacks >= 2");
  }
  const double pi = 3.14159265358979323846;
  std::vector<Eigen::Vector3d> points;
  points.push_back(centre + Eigen::Vector3d(0, 0, radius));
  for (int s = 1; s < stacks; ++s)
  {
    const double polar = pi * s / stacks;
    for (int l = 0; l < slices; ++l)
    {
      const double azimuth = 2 * pi * l / slices;
      points.push_back(centre +
        radius *
          Eigen::Vector3d(std::sin(polar) * std::cos(azimuth),
            std::sin(polar) * std::sin(azimuth), std::cos(polar)));
    }
  }
  const auto south = static_cast<std::int64_t>(points.size());
  points.push_back(centre + Eigen::Vector3d(0, 0, -radius));
  auto ring = [&](int s, int l) -> std::int64_t { return 1 + (s - 1) * slices + (l % slices); };
  std::vector<std::array<std::int64_t, 3>> triangles;
  for (int l = 0; l < slices; ++l)
  {
    triangles.push_back({ 0, ring(1, l), ring(1, l + 1) });
    for (int s = 1; s + 1 < stacks; ++s)
    {
      triangles.push_back({ ring(s, l), ring(s + 1, l), ring(s + 1, l + 1) });
      triangles.push_back({ ring(s, l), ring(s + 1, l + 1), ring(s, l + 1) });
    }
    triangles.push_back({ south, ring(stacks - 1, l + 1), ring(stacks - 1, l) });
  }
  detail::OrientAwayFrom(points, triangles, centre);
  return detail::Assemble(points, triangles);
}

/// Capsule along z: a cylinder of `radius` between z = -halfLength and z = +halfLength closed
/// by two hemispheres. `slices` around the axis, `capStacks` latitude steps per hemisphere,
/// `bodyStacks` steps along the cylinder: 2 * slices * (2 * capStacks + bodyStacks - 1) faces.
inline TriangleMesh MakeCapsule(double radius, double halfLength, int slices, int capStacks,
  int bodyStacks)
{
  if (slices < 3 || capStacks < 1 || bodyStacks < 1 || radius <= 0 || halfLength < 0)
  {
    throw std::invalid_argument("MakeCapsule: bad parameters");
  }
  const double pi = 3.14159265358979323846;
  // Profile rings from the north pole (exclusive) to the south pole (exclusive).
  std::vector<std::pair<double, double>> rings; // (ring radius, z)
  for (int s = 1; s <= capStacks; ++s)
  {
    const double polar = 0.5 * pi * s / capStacks;
    rings.emplace_back(radius * std::sin(polar), halfLength + radius * std::cos(polar));
  }
  for (int s = 1; s < bodyStacks; ++s)
  {
    rings.emplace_back(radius, halfLength - 2 * halfLength * s / bodyStacks);
  }
  for (int s = 0; s < capStacks; ++s)
  {
    const double polar = 0.5 * pi + 0.5 * pi * s / capStacks;
    rings.emplace_back(radius * std::sin(polar), -halfLength + radius * std::cos(polar));
  }
  std::vector<Eigen::Vector3d> points;
  points.emplace_back(0, 0, halfLength + radius);
  for (const auto& [r, z] : rings)
  {
    for (int l = 0; l < slices; ++l)
    {
      const double azimuth = 2 * pi * l / slices;
      points.emplace_back(r * std::cos(azimuth), r * std::sin(azimuth), z);
    }
  }
  const auto south = static_cast<std::int64_t>(points.size());
  points.emplace_back(0, 0, -halfLength - radius);
  const int ringCount = static_cast<int>(rings.size());
  auto ring = [&](int s, int l) -> std::int64_t { return 1 + s * slices + (l % slices); };
  std::vector<std::array<std::int64_t, 3>> triangles;
  for (int l = 0; l < slices; ++l)
  {
    triangles.push_back({ 0, ring(0, l), ring(0, l + 1) });
    for (int s = 0; s + 1 < ringCount; ++s)
    {
      triangles.push_back({ ring(s, l), ring(s + 1, l), ring(s + 1, l + 1) });
      triangles.push_back({ ring(s, l), ring(s + 1, l + 1), ring(s, l + 1) });
    }
    triangles.push_back({ south, ring(ringCount - 1, l + 1), ring(ringCount - 1, l) });
  }
  // Orient each triangle away from the nearest point on the axis segment.
  for (auto& t : triangles)
  {
    const Eigen::Vector3d a = points[t[0]], b = points[t[1]], c = points[t[2]];
    const Eigen::Vector3d centroid = (a + b + c) / 3.0;
    const Eigen::Vector3d axisPoint(0, 0, std::clamp(centroid.z(), -halfLength, halfLength));
    if ((b - a).cross(c - a).dot(centroid - axisPoint) < 0)
    {
      std::swap(t[1], t[2]);
    }
  }
  return detail::Assemble(points, triangles);
}

/// Axis-aligned box [0, size.x] x [0, size.y] x [0, size.z] with each side split into
/// divisions x divisions quads (two triangles each): 12 * divisions^2 faces.
inline TriangleMesh MakeBox(const Eigen::Vector3d& size, int divisions)
{
  if (divisions < 1 || !(size.array() > 0).all())
  {
    throw std::invalid_argument("MakeBox: bad parameters");
  }
  const int n = divisions;
  std::map<std::array<int, 3>, std::int64_t> indexOfGridPoint;
  std::vector<Eigen::Vector3d> points;
  auto pointIndex = [&](const std::array<int, 3>& g) {
    auto found = indexOfGridPoint.find(g);
    if (found != indexOfGridPoint.end())
    {
      return found->second;
    }
    const auto index = static_cast<std::int64_t>(points.size());
    points.emplace_back(size.x() * g[0] / n, size.y() * g[1] / n, size.z() * g[2] / n);
    indexOfGridPoint.emplace(g, index);
    return index;
  };
  std::vector<std::array<std::int64_t, 3>> triangles;
  for (int axis = 0; axis < 3; ++axis)
  {
    const int u = (axis + 1) % 3, v = (axis + 2) % 3;
    for (int side = 0; side <= n; side += n)
    {
      for (int i = 0; i < n; ++i)
      {
        for (int j = 0; j < n; ++j)
        {
          std::array<int, 3> g00{}, g10{}, g11{}, g01{};
          for (auto* g : { &g00, &g10, &g11, &g01 })
          {
            (*g)[axis] = side;
          }
          g00[u] = i, g00[v] = j;
          g10[u] = i + 1, g10[v] = j;
          g11[u] = i + 1, g11[v] = j + 1;
          g01[u] = i, g01[v] = j + 1;
          triangles.push_back({ pointIndex(g00), pointIndex(g10), pointIndex(g11) });
          triangles.push_back({ pointIndex(g00), pointIndex(g11), pointIndex(g01) });
        }
      }
    }
  }
  detail::OrientAwayFrom(points, triangles, size / 2);
  return detail::Assemble(points, triangles);
}

/// Concatenates two meshes (the second one's indices shifted).
inline TriangleMesh Concatenate(const TriangleMesh& a, const TriangleMesh& b)
{
  TriangleMesh mesh;
  mesh.Points.resize(a.Points.rows() + b.Points.rows(), 3);
  mesh.Points << a.Points, b.Points;
  mesh.Triangles.resize(a.Triangles.rows() + b.Triangles.rows(), 3);
  mesh.Triangles << a.Triangles, (b.Triangles.array() + a.Points.rows()).matrix();
  return mesh;
}

/// Reverses the vertex order of every triangle (normals point inward).
inline TriangleMesh Flipped(TriangleMesh mesh)
{
  mesh.Triangles.col(1).swap(mesh.Triangles.col(2));
  return mesh;
}

/// Applies p -> rotation * p + translation to every point.
inline TriangleMesh Transformed(TriangleMesh mesh, const Eigen::Matrix3d& rotation,
  const Eigen::Vector3d& translation)
{
  for (Eigen::Index i = 0; i < mesh.Points.rows(); ++i)
  {
    const Eigen::Vector3d p = mesh.Points.row(i).transpose();
    mesh.Points.row(i) = (rotation * p + translation).transpose();
  }
  return mesh;
}

/// Keeps only the triangles for which keep(triangle index) is true (points unchanged, so
/// unreferenced points may remain).
template <typename Predicate>
TriangleMesh KeepTriangles(const TriangleMesh& mesh, Predicate keep)
{
  std::vector<Eigen::Index> kept;
  for (Eigen::Index t = 0; t < mesh.Triangles.rows(); ++t)
  {
    if (keep(t))
    {
      kept.push_back(t);
    }
  }
  TriangleMesh result;
  result.Points = mesh.Points;
  result.Triangles.resize(static_cast<Eigen::Index>(kept.size()), 3);
  for (std::size_t i = 0; i < kept.size(); ++i)
  {
    result.Triangles.row(static_cast<Eigen::Index>(i)) = mesh.Triangles.row(kept[i]);
  }
  return result;
}

/// Face adjacency through shared edges as CSR (offsets has faceCount + 1 entries), in
/// increasing neighbour order. For tests only (the product's FaceGraph is elsewhere).
inline void EdgeAdjacency(const TriangleMatrix& triangles, std::vector<std::int64_t>& offsets,
  std::vector<std::int64_t>& indices)
{
  std::map<std::pair<std::int64_t, std::int64_t>, std::vector<std::int64_t>> facesOfEdge;
  for (Eigen::Index t = 0; t < triangles.rows(); ++t)
  {
    for (int c = 0; c < 3; ++c)
    {
      std::int64_t a = triangles(t, c), b = triangles(t, (c + 1) % 3);
      facesOfEdge[{ std::min(a, b), std::max(a, b) }].push_back(t);
    }
  }
  std::vector<std::vector<std::int64_t>> neighbours(static_cast<std::size_t>(triangles.rows()));
  for (const auto& [edge, edgeFaces] : facesOfEdge)
  {
    for (auto f : edgeFaces)
    {
      for (auto g : edgeFaces)
      {
        if (f != g)
        {
          neighbours[static_cast<std::size_t>(f)].push_back(g);
        }
      }
    }
  }
  offsets.assign(1, 0);
  indices.clear();
  for (auto& list : neighbours)
  {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
    indices.insert(indices.end(), list.begin(), list.end());
    offsets.push_back(static_cast<std::int64_t>(indices.size()));
  }
}

} // namespace testshapes
} // namespace shapediameter
