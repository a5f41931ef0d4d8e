// SPDX-License-Identifier: BSD-3-Clause
#include "TestShapes.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <random>
#include <stdexcept>
#include <utility>

namespace shapediameter
{
namespace testshapes
{

namespace
{

/// Orients every triangle so that its normal points away from `centre` (valid for the
/// star-shaped surfaces generated here).
void OrientAwayFrom(const std::vector<Eigen::Vector3d>& points,
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

/// Rotation taking the z axis to `axis` (Rodrigues; avoids Eigen's FromTwoVectors, whose SVD
/// path trips a false -Wmaybe-uninitialized in g++ 12).
Eigen::Matrix3d RotationFromZ(const Eigen::Vector3d& axis)
{
  const Eigen::Vector3d target = axis.normalized();
  const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d cross = z.cross(target);
  const double sine = cross.norm();
  const double cosine = z.dot(target);
  if (sine < 1e-12)
  {
    return cosine > 0.0 ? Eigen::Matrix3d::Identity()
                        : Eigen::Matrix3d(Eigen::Vector3d(1.0, -1.0, -1.0).asDiagonal());
  }
  return Eigen::AngleAxisd(std::atan2(sine, cosine), cross / sine).toRotationMatrix();
}

/// Closed surface of revolution about the z axis: the profile lists (z, rho) rings from the
/// south pole to the north pole, the poles excluded. Outward oriented.
TestMesh MakeRevolution(
  const std::vector<std::pair<double, double>>& profile, double southZ, double northZ, int around)
{
  TestMesh mesh;
  const auto rings = static_cast<Eigen::Index>(profile.size());
  mesh.Points.resize(rings * around + 2, 3);
  mesh.Points.row(0) << 0.0, 0.0, southZ;
  for (Eigen::Index i = 0; i < rings; ++i)
  {
    for (int k = 0; k < around; ++k)
    {
      const double phi = 2.0 * Pi * k / around;
      mesh.Points.row(1 + i * around + k) << profile[i].second * std::cos(phi),
        profile[i].second * std::sin(phi), profile[i].first;
    }
  }
  const Eigen::Index north = rings * around + 1;
  mesh.Points.row(north) << 0.0, 0.0, northZ;
  const auto vertex = [around](Eigen::Index ring, int k) {
    return static_cast<std::int64_t>(1 + ring * around + (k % around));
  };
  std::vector<std::array<std::int64_t, 3>> faces;
  for (int k = 0; k < around; ++k)
  {
    faces.push_back({ 0, vertex(0, k + 1), vertex(0, k) });
  }
  for (Eigen::Index i = 0; i + 1 < rings; ++i)
  {
    for (int k = 0; k < around; ++k)
    {
      faces.push_back({ vertex(i, k), vertex(i, k + 1), vertex(i + 1, k + 1) });
      faces.push_back({ vertex(i, k), vertex(i + 1, k + 1), vertex(i + 1, k) });
    }
  }
  for (int k = 0; k < around; ++k)
  {
    faces.push_back({ vertex(rings - 1, k), vertex(rings - 1, k + 1), north });
  }
  mesh.Triangles.resize(static_cast<Eigen::Index>(faces.size()), 3);
  for (std::size_t f = 0; f < faces.size(); ++f)
  {
    mesh.Triangles.row(static_cast<Eigen::Index>(f)) << faces[f][0], faces[f][1], faces[f][2];
  }
  return mesh;
}

/// Farthest point of a capsule along the ray t * omega from the origin (origin inside).
double CapsuleExit(const Arm& arm, const Eigen::Vector3d& omega)
{
  const double c = omega.dot(arm.Direction);
  double exit = arm.Radius; // ball at the origin
  if (c > 0.0)
  {
    const double sine = std::sqrt(std::max(0.0, 1.0 - c * c));
    const double toWall = sine > 0.0 ? arm.Radius / sine : arm.Length;
    exit = std::max(exit, std::min(toWall, arm.Length / c));
  }
  const double discriminant =
    arm.Length * arm.Length * c * c - arm.Length * arm.Length + arm.Radius * arm.Radius;
  if (discriminant >= 0.0)
  {
    exit = std::max(exit, arm.Length * c + std::sqrt(discriminant));
  }
  return exit;
}

} // namespace

TestMesh Assemble(const std::vector<Eigen::Vector3d>& points,
  const std::vector<std::array<std::int64_t, 3>>& triangles)
{
  TestMesh mesh;
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

TestMesh MakeIcosphere(int frequency, double radius,
  const Eigen::Vector3d& centre)
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
  OrientAwayFrom(points, triangles, centre);
  return Assemble(points, triangles);
}

TestMesh MakeBox(const Eigen::Vector3d& size, int divisions)
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
  OrientAwayFrom(points, triangles, size / 2);
  return Assemble(points, triangles);
}

TestMesh MakeCapsule(
  double radius, double halfLength, int around, int capRings, int cylinderRings)
{
  std::vector<std::pair<double, double>> profile;
  for (int i = 1; i <= capRings; ++i)
  {
    const double theta = 0.5 * Pi * i / capRings;
    profile.emplace_back(-halfLength - radius * std::cos(theta), radius * std::sin(theta));
  }
  for (int j = 1; j < cylinderRings; ++j)
  {
    profile.emplace_back(-halfLength + 2.0 * halfLength * j / cylinderRings, radius);
  }
  for (int i = capRings; i >= 1; --i)
  {
    const double theta = 0.5 * Pi * i / capRings;
    profile.emplace_back(halfLength + radius * std::cos(theta), radius * std::sin(theta));
  }
  TestMesh mesh = MakeRevolution(profile, -halfLength - radius, halfLength + radius, around);
  mesh.Sdf.assign(static_cast<std::size_t>(mesh.Faces()), 2.0 * radius);
  return mesh;
}

TestMesh MakeSphere(double radius, int around, int rings)
{
  std::vector<std::pair<double, double>> profile;
  for (int i = 1; i < rings; ++i)
  {
    const double theta = Pi * i / rings;
    profile.emplace_back(-radius * std::cos(theta), radius * std::sin(theta));
  }
  TestMesh mesh = MakeRevolution(profile, -radius, radius, around);
  mesh.Sdf.assign(static_cast<std::size_t>(mesh.Faces()), 2.0 * radius);
  return mesh;
}

TestMesh MakeProlateSpheroid(double a, double b, int around, int rings)
{
  std::vector<std::pair<double, double>> profile;
  for (int i = 1; i < rings; ++i)
  {
    const double theta = Pi * i / rings;
    profile.emplace_back(-a * std::cos(theta), b * std::sin(theta));
  }
  TestMesh mesh = MakeRevolution(profile, -a, a, around);
  mesh.Sdf.resize(static_cast<std::size_t>(mesh.Faces()));
  for (Eigen::Index f = 0; f < mesh.Faces(); ++f)
  {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int c = 0; c < 3; ++c)
    {
      centroid += mesh.Points.row(mesh.Triangles(f, c)).transpose() / 3.0;
    }
    const double scale = std::sqrt((centroid.x() * centroid.x() + centroid.y() * centroid.y()) /
        (b * b) + centroid.z() * centroid.z() / (a * a));
    const Eigen::Vector3d s = centroid / scale;
    const Eigen::Vector3d gradient(s.x() / (b * b), s.y() / (b * b), s.z() / (a * a));
    mesh.Sdf[f] = 2.0 * b * b * gradient.norm();
  }
  return mesh;
}

TestMesh MakeTorus(double coreRadius, double tubeRadius, int around, int tube)
{
  TestMesh mesh;
  mesh.Points.resize(around * tube, 3);
  for (int i = 0; i < around; ++i)
  {
    const double u = 2.0 * Pi * i / around;
    for (int j = 0; j < tube; ++j)
    {
      const double v = 2.0 * Pi * j / tube;
      mesh.Points.row(i * tube + j) << (coreRadius + tubeRadius * std::cos(v)) * std::cos(u),
        (coreRadius + tubeRadius * std::cos(v)) * std::sin(u), tubeRadius * std::sin(v);
    }
  }
  const auto vertex = [around, tube](int i, int j) {
    return static_cast<std::int64_t>((i % around) * tube + (j % tube));
  };
  mesh.Triangles.resize(2 * around * tube, 3);
  Eigen::Index f = 0;
  for (int i = 0; i < around; ++i)
  {
    for (int j = 0; j < tube; ++j)
    {
      mesh.Triangles.row(f++) << vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1);
      mesh.Triangles.row(f++) << vertex(i, j), vertex(i + 1, j + 1), vertex(i, j + 1);
    }
  }
  mesh.Sdf.assign(static_cast<std::size_t>(mesh.Faces()), 2.0 * tubeRadius);
  return mesh;
}

TestMesh MakeCapsuleStar(
  const std::vector<Arm>& arms, int around, int rings, const Eigen::Vector3d& pole)
{
  // A UV sphere about `pole`, so that arms away from the pole get regular triangles.
  std::vector<std::pair<double, double>> profile;
  for (int i = 1; i < rings; ++i)
  {
    const double theta = Pi * i / rings;
    profile.emplace_back(-std::cos(theta), std::sin(theta));
  }
  TestMesh mesh = MakeRevolution(profile, -1.0, 1.0, around);
  const Eigen::Matrix3d rotation = RotationFromZ(pole);
  std::vector<double> vertexRadius(static_cast<std::size_t>(mesh.Points.rows()));
  for (Eigen::Index v = 0; v < mesh.Points.rows(); ++v)
  {
    const Eigen::Vector3d omega = rotation * Eigen::Vector3d(mesh.Points.row(v).transpose());
    double best = 0.0;
    for (const Arm& arm : arms)
    {
      best = std::max(best, CapsuleExit(arm, omega));
    }
    mesh.Points.row(v) = (best * omega).transpose();
  }
  mesh.Sdf.resize(static_cast<std::size_t>(mesh.Faces()));
  for (Eigen::Index f = 0; f < mesh.Faces(); ++f)
  {
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (int c = 0; c < 3; ++c)
    {
      centroid += mesh.Points.row(mesh.Triangles(f, c)).transpose() / 3.0;
    }
    const Eigen::Vector3d omega = centroid.normalized();
    std::size_t owner = 0;
    double best = -1.0;
    for (std::size_t a = 0; a < arms.size(); ++a)
    {
      const double exit = CapsuleExit(arms[a], omega);
      if (exit > best)
      {
        best = exit;
        owner = a;
      }
    }
    mesh.Sdf[f] = 2.0 * arms[owner].Radius;
  }
  return mesh;
}

std::vector<Arm> TripodArms(double length, double radius)
{
  std::vector<Arm> arms;
  for (int k = 0; k < 3; ++k)
  {
    const double angle = 2.0 * Pi * k / 3.0;
    arms.push_back({ Eigen::Vector3d(std::cos(angle), std::sin(angle), 0.0), length, radius });
  }
  return arms;
}

TestMesh MakeTripod(double length, double radius, int around, int rings)
{
  return MakeCapsuleStar(TripodArms(length, radius), around, rings, Eigen::Vector3d::UnitZ());
}

TestMesh Concatenate(const TestMesh& first, const TestMesh& second)
{
  TestMesh mesh;
  mesh.Points.resize(first.Points.rows() + second.Points.rows(), 3);
  mesh.Points << first.Points, second.Points;
  mesh.Triangles.resize(first.Faces() + second.Faces(), 3);
  mesh.Triangles.topRows(first.Faces()) = first.Triangles;
  mesh.Triangles.bottomRows(second.Faces()) =
    second.Triangles.array() + static_cast<std::int64_t>(first.Points.rows());
  mesh.Sdf = first.Sdf;
  mesh.Sdf.insert(mesh.Sdf.end(), second.Sdf.begin(), second.Sdf.end());
  return mesh;
}

TestMesh Flipped(TestMesh mesh)
{
  mesh.Triangles.col(1).swap(mesh.Triangles.col(2));
  return mesh;
}

TestMesh Transformed(TestMesh mesh, const Eigen::Matrix3d& rotation,
  const Eigen::Vector3d& translation)
{
  for (Eigen::Index i = 0; i < mesh.Points.rows(); ++i)
  {
    const Eigen::Vector3d p = mesh.Points.row(i).transpose();
    mesh.Points.row(i) = (rotation * p + translation).transpose();
  }
  return mesh;
}

void Place(TestMesh& mesh, const Eigen::Vector3d& axis, const Eigen::Vector3d& offset)
{
  mesh = Transformed(std::move(mesh), RotationFromZ(axis), offset);
}

double SignedVolume(const TestMesh& mesh)
{
  double volume = 0.0;
  for (Eigen::Index f = 0; f < mesh.Faces(); ++f)
  {
    const Eigen::Vector3d a = mesh.Points.row(mesh.Triangles(f, 0)).transpose();
    const Eigen::Vector3d b = mesh.Points.row(mesh.Triangles(f, 1)).transpose();
    const Eigen::Vector3d c = mesh.Points.row(mesh.Triangles(f, 2)).transpose();
    volume += a.dot(b.cross(c)) / 6.0;
  }
  return volume;
}

void AddSdfNoise(TestMesh& mesh, double amplitude, std::uint64_t seed)
{
  std::mt19937_64 generator(seed);
  for (double& value : mesh.Sdf)
  {
    const double u = static_cast<double>(generator() >> 11) * 0x1.0p-53;
    value *= 1.0 + amplitude * (2.0 * u - 1.0);
  }
}

std::vector<double> RayCastSdf(const TestMesh& mesh)
{
  const Eigen::Index faces = mesh.Faces();
  std::vector<Eigen::Vector3d> a(faces), edge1(faces), edge2(faces), normal(faces), centroid(faces);
  for (Eigen::Index f = 0; f < faces; ++f)
  {
    a[f] = mesh.Points.row(mesh.Triangles(f, 0)).transpose();
    edge1[f] = mesh.Points.row(mesh.Triangles(f, 1)).transpose() - a[f];
    edge2[f] = mesh.Points.row(mesh.Triangles(f, 2)).transpose() - a[f];
    normal[f] = edge1[f].cross(edge2[f]).normalized();
    centroid[f] = a[f] + (edge1[f] + edge2[f]) / 3.0;
  }
  std::vector<double> sdf(static_cast<std::size_t>(faces), 0.0);
  for (Eigen::Index f = 0; f < faces; ++f)
  {
    const Eigen::Vector3d axis = -normal[f];
    const Eigen::Vector3d u = axis.unitOrthogonal();
    const Eigen::Vector3d v = axis.cross(u);
    std::vector<std::pair<Eigen::Vector3d, double>> rays{ { axis, 10.0 } };
    for (const double degrees : { 20.0, 40.0, 60.0 })
    {
      const double tilt = degrees * Pi / 180.0;
      for (int k = 0; k < 8; ++k)
      {
        const double spin = 2.0 * Pi * (k + 0.5 * (degrees == 40.0)) / 8.0;
        rays.emplace_back(std::cos(tilt) * axis +
            std::sin(tilt) * (std::cos(spin) * u + std::sin(spin) * v),
          degrees);
      }
    }
    std::vector<std::pair<double, double>> hits; // (length, weight)
    for (const auto& [direction, degrees] : rays)
    {
      double nearest = std::numeric_limits<double>::infinity();
      for (Eigen::Index g = 0; g < faces; ++g)
      {
        if (g == f || normal[g].dot(direction) <= 0.0)
        {
          continue;
        }
        const Eigen::Vector3d p = direction.cross(edge2[g]);
        const double det = edge1[g].dot(p);
        if (std::abs(det) < 1e-14)
        {
          continue;
        }
        const Eigen::Vector3d s = centroid[f] - a[g];
        const double bu = s.dot(p) / det;
        if (bu < 0.0 || bu > 1.0)
        {
          continue;
        }
        const Eigen::Vector3d q = s.cross(edge1[g]);
        const double bv = direction.dot(q) / det;
        if (bv < 0.0 || bu + bv > 1.0)
        {
          continue;
        }
        const double t = edge2[g].dot(q) / det;
        if (t > 1e-9 && t < nearest)
        {
          nearest = t;
        }
      }
      if (std::isfinite(nearest))
      {
        hits.emplace_back(nearest, 1.0 / degrees);
      }
    }
    if (hits.empty())
    {
      continue;
    }
    std::vector<double> lengths;
    for (const auto& hit : hits)
    {
      lengths.push_back(hit.first);
    }
    std::sort(lengths.begin(), lengths.end());
    const double median = lengths[lengths.size() / 2];
    const auto count = static_cast<double>(lengths.size());
    double mean = 0.0;
    for (const double l : lengths)
    {
      mean += l / count;
    }
    double variance = 0.0;
    for (const double l : lengths)
    {
      variance += (l - mean) * (l - mean) / count;
    }
    const double deviation = std::sqrt(variance);
    double sum = 0.0;
    double weights = 0.0;
    for (const auto& [length, weight] : hits)
    {
      if (std::abs(length - median) <= deviation)
      {
        sum += weight * length;
        weights += weight;
      }
    }
    sdf[f] = weights > 0.0 ? sum / weights : median;
  }
  return sdf;
}

void EdgeAdjacency(const TriangleMatrix& triangles, std::vector<std::int64_t>& offsets,
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
