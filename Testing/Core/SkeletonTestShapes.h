// SPDX-License-Identifier: BSD-3-Clause
// Analytic test shapes for the skeleton core: closed, outward-oriented triangle meshes with a
// per-face "SDF" whose value is known (twice the distance from the face to the medial curve
// along the inward normal), plus a small brute-force ray-cast SDF for realistic noise.
//
// Used by TestSkeleton.cpp and BenchSkeleton.cpp only; header-only, everything inline.
#pragma once

#include "MeshTypes.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <utility>
#include <vector>

namespace shapediameter
{
namespace skeletontest
{

constexpr double Pi = 3.14159265358979323846;

struct TestMesh
{
  PointMatrix Points;
  TriangleMatrix Triangles;
  /// Per-face shape diameter.
  std::vector<double> Sdf;

  Eigen::Index Faces() const { return Triangles.rows(); }
};

/// Rotation taking the z axis to `axis` (Rodrigues; avoids Eigen's FromTwoVectors, whose SVD
/// path trips a false -Wmaybe-uninitialized in g++ 12).
inline Eigen::Matrix3d RotationFromZ(const Eigen::Vector3d& axis)
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
inline TestMesh MakeRevolution(
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

/// Capsule along z: cylinder of radius r between z = -halfLength and z = +halfLength, closed
/// by hemispheres. Medial curve: the axis segment between the cap centres. SDF = 2 r.
inline TestMesh MakeCapsule(
  double radius, double halfLength, int around = 48, int capRings = 12, int cylinderRings = 40)
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

/// Sphere of the given radius at the origin; SDF = diameter.
inline TestMesh MakeSphere(double radius, int around = 48, int rings = 24)
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

/// Prolate spheroid x^2/b^2 + y^2/b^2 + z^2/a^2 = 1 (a > b). Its medial curve is the axis
/// segment |z| <= a - b^2/a; the inward normal from a surface point s meets the axis after
/// t = b^2 |grad| with grad = (s_x/b^2, s_y/b^2, s_z/a^2), and SDF = 2 t (evaluated at the
/// face centroid scaled onto the surface).
inline TestMesh MakeProlateSpheroid(double a, double b, int around = 48, int rings = 120)
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

/// Torus about the z axis: core circle of radius R in the plane z = 0, tube radius r.
/// SDF = 2 r everywhere (every inward normal meets the core circle after r).
inline TestMesh MakeTorus(double coreRadius, double tubeRadius, int around = 144, int tube = 24)
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

/// A capsule from the origin to length * direction (unit), radius r.
struct Arm
{
  Eigen::Vector3d Direction;
  double Length;
  double Radius;
};

/// Farthest point of a capsule along the ray t * omega from the origin (origin inside).
inline double CapsuleExit(const Arm& arm, const Eigen::Vector3d& omega)
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

/// Star-shaped union of capsules that all start at the origin (each convex and containing the
/// origin, so the union is star-shaped about it): a UV sphere whose vertex in direction omega
/// is moved to the farthest capsule exit. Closed, one component, outward oriented. SDF of a
/// face = 2 * radius of the capsule whose surface it lies on (the one giving the exit).
inline TestMesh MakeCapsuleStar(
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

/// Three capsules of radius r and length L (origin to cap centre) in the xy plane at 120
/// degrees: junction at the origin, arm axes along the three directions.
inline std::vector<Arm> TripodArms(double length, double radius)
{
  std::vector<Arm> arms;
  for (int k = 0; k < 3; ++k)
  {
    const double angle = 2.0 * Pi * k / 3.0;
    arms.push_back({ Eigen::Vector3d(std::cos(angle), std::sin(angle), 0.0), length, radius });
  }
  return arms;
}

inline TestMesh MakeTripod(double length, double radius, int around = 240, int rings = 120)
{
  return MakeCapsuleStar(TripodArms(length, radius), around, rings, Eigen::Vector3d::UnitZ());
}

/// Moves a mesh rigidly: rotation taking z to `axis`, then translation.
inline void Place(TestMesh& mesh, const Eigen::Vector3d& axis, const Eigen::Vector3d& offset)
{
  const Eigen::Matrix3d rotation = RotationFromZ(axis);
  for (Eigen::Index v = 0; v < mesh.Points.rows(); ++v)
  {
    mesh.Points.row(v) = (rotation * Eigen::Vector3d(mesh.Points.row(v).transpose()) + offset).transpose();
  }
}

/// Disjoint union of two meshes.
inline TestMesh Concatenate(const TestMesh& first, const TestMesh& second)
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

/// Signed volume (positive for an outward-oriented closed mesh).
inline double SignedVolume(const TestMesh& mesh)
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

/// Multiplies every SDF value by 1 + amplitude * u, u uniform in [-1, 1) (fixed seed).
inline void AddSdfNoise(TestMesh& mesh, double amplitude, std::uint64_t seed = 7)
{
  std::mt19937_64 generator(seed);
  for (double& value : mesh.Sdf)
  {
    const double u = static_cast<double>(generator() >> 11) * 0x1.0p-53;
    value *= 1.0 + amplitude * (2.0 * u - 1.0);
  }
}

/// A brute-force SDF in the spirit of the paper's section 3 (not the production one): rays in
/// a cone of half-angle 60 degrees around the inward normal of each face centroid (the axis
/// and rings at 20, 40, 60 degrees of 8 rays), the nearest hit on a face seen from inside,
/// lengths outside median +- one standard deviation dropped, the rest averaged with weights
/// 1 / angle (the axis weighted as 10 degrees). O(faces^2): small meshes only.
inline std::vector<double> RayCastSdf(const TestMesh& mesh)
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

} // namespace skeletontest
} // namespace shapediameter
