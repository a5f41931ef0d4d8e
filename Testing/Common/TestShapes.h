// SPDX-License-Identifier: BSD-3-Clause
// Analytic closed triangle meshes for the core tests and benchmarks (no VTK): spheres,
// capsule, box, prolate spheroid, torus, star-shaped unions of capsules (tripod, figure).
//
// Every generator returns a watertight, consistently oriented mesh whose triangles are
// counter-clockwise seen from outside (outward right-hand-rule normals, as MeshTypes.h
// requires), with shared vertices (no duplicated seam points), and is deterministic. Where the
// shape's medial curve is known, the generator also fills TestMesh::Sdf with the exact per-face
// shape diameter (twice the distance from the face to the medial curve along the inward
// normal); RayCastSdf gives a small brute-force ray-cast SDF with realistic noise.
#pragma once

#include "Mesh/MeshTypes.h"

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

namespace shapediameter
{
namespace testshapes
{

constexpr double Pi = 3.14159265358979323846;

struct TestMesh
{
  PointMatrix Points;
  TriangleMatrix Triangles;
  /// Per-face shape diameter where the generator knows it (see each one), else empty.
  std::vector<double> Sdf;

  Eigen::Index Faces() const { return Triangles.rows(); }
};

/// A mesh from lists of points and triangles (indices into points).
TestMesh Assemble(const std::vector<Eigen::Vector3d>& points,
  const std::vector<std::array<std::int64_t, 3>>& triangles);

// Shapes

/// Geodesic (class I) icosphere: each icosahedron face is split into frequency^2 triangles and
/// the vertices are projected onto the sphere. 20 * frequency^2 faces, 10 * frequency^2 + 2
/// vertices (frequency 32 -> 20480 faces, 51 -> 52020 faces). No Sdf.
TestMesh MakeIcosphere(int frequency, double radius = 1.0,
  const Eigen::Vector3d& centre = Eigen::Vector3d::Zero());

/// Latitude-longitude sphere of the given radius at the origin, `around` slices and `rings`
/// stacks from pole to pole: 2 * around * (rings - 1) faces. SDF = diameter.
TestMesh MakeSphere(double radius, int around = 48, int rings = 24);

/// Capsule along z: cylinder of radius r between z = -halfLength and z = +halfLength, closed
/// by hemispheres; `around` slices, `capRings` latitude steps per hemisphere, `cylinderRings`
/// steps along the cylinder: 2 * around * (2 * capRings + cylinderRings - 1) faces. Medial
/// curve: the axis segment between the cap centres. SDF = 2 r.
TestMesh MakeCapsule(
  double radius, double halfLength, int around = 48, int capRings = 12, int cylinderRings = 40);

/// Axis-aligned box [0, size.x] x [0, size.y] x [0, size.z] with each side split into
/// divisions x divisions quads (two triangles each): 12 * divisions^2 faces. No Sdf.
TestMesh MakeBox(const Eigen::Vector3d& size, int divisions);

/// Prolate spheroid x^2/b^2 + y^2/b^2 + z^2/a^2 = 1 (a > b). Its medial curve is the axis
/// segment |z| <= a - b^2/a; the inward normal from a surface point s meets the axis after
/// t = b^2 |grad| with grad = (s_x/b^2, s_y/b^2, s_z/a^2), and SDF = 2 t (evaluated at the
/// face centroid scaled onto the surface).
TestMesh MakeProlateSpheroid(double a, double b, int around = 48, int rings = 120);

/// Torus about the z axis: core circle of radius R in the plane z = 0, tube radius r.
/// SDF = 2 r everywhere (every inward normal meets the core circle after r).
TestMesh MakeTorus(double coreRadius, double tubeRadius, int around = 144, int tube = 24);

/// A capsule from the origin to length * direction (unit), radius r.
struct Arm
{
  Eigen::Vector3d Direction;
  double Length;
  double Radius;
};

/// Star-shaped union of capsules that all start at the origin (each convex and containing the
/// origin, so the union is star-shaped about it): a UV sphere about `pole` whose vertex in
/// direction omega is moved to the farthest capsule exit. Closed, one component, outward
/// oriented. SDF of a face = 2 * radius of the capsule whose surface it lies on (the one
/// giving the exit).
TestMesh MakeCapsuleStar(
  const std::vector<Arm>& arms, int around, int rings, const Eigen::Vector3d& pole);

/// Three capsules of radius r and length L (origin to cap centre) in the xy plane at 120
/// degrees: junction at the origin, arm axes along the three directions.
std::vector<Arm> TripodArms(double length, double radius);

/// MakeCapsuleStar of TripodArms, pole along z.
TestMesh MakeTripod(double length, double radius, int around = 240, int rings = 120);

// Operations

/// Disjoint union of two meshes (the second one's indices shifted, the Sdf values appended).
TestMesh Concatenate(const TestMesh& first, const TestMesh& second);

/// Reverses the vertex order of every triangle (normals point inward).
TestMesh Flipped(TestMesh mesh);

/// Applies p -> rotation * p + translation to every point.
TestMesh Transformed(TestMesh mesh, const Eigen::Matrix3d& rotation,
  const Eigen::Vector3d& translation);

/// Moves a mesh rigidly: rotation taking z to `axis`, then translation.
void Place(TestMesh& mesh, const Eigen::Vector3d& axis, const Eigen::Vector3d& offset);

/// Keeps only the triangles for which keep(triangle index) is true (points unchanged, so
/// unreferenced points may remain; no Sdf).
template <typename Predicate>
TestMesh KeepTriangles(const TestMesh& mesh, Predicate keep)
{
  std::vector<Eigen::Index> kept;
  for (Eigen::Index t = 0; t < mesh.Triangles.rows(); ++t)
  {
    if (keep(t))
    {
      kept.push_back(t);
    }
  }
  TestMesh result;
  result.Points = mesh.Points;
  result.Triangles.resize(static_cast<Eigen::Index>(kept.size()), 3);
  for (std::size_t i = 0; i < kept.size(); ++i)
  {
    result.Triangles.row(static_cast<Eigen::Index>(i)) = mesh.Triangles.row(kept[i]);
  }
  return result;
}

// Measures

/// Signed volume (positive for an outward-oriented closed mesh).
double SignedVolume(const TestMesh& mesh);

/// Multiplies every SDF value by 1 + amplitude * u, u uniform in [-1, 1) (fixed seed).
void AddSdfNoise(TestMesh& mesh, double amplitude, std::uint64_t seed = 7);

/// A brute-force SDF in the spirit of the paper's section 3 (not the production one): rays in
/// a cone of half-angle 60 degrees around the inward normal of each face centroid (the axis
/// and rings at 20, 40, 60 degrees of 8 rays), the nearest hit on a face seen from inside,
/// lengths outside median +- one standard deviation dropped, the rest averaged with weights
/// 1 / angle (the axis weighted as 10 degrees). O(faces^2): small meshes only.
std::vector<double> RayCastSdf(const TestMesh& mesh);

/// Face adjacency through shared edges as CSR (offsets has faceCount + 1 entries), in
/// increasing neighbour order. For tests only (the product's FaceGraph is elsewhere).
void EdgeAdjacency(const TriangleMatrix& triangles, std::vector<std::int64_t>& offsets,
  std::vector<std::int64_t>& indices);

} // namespace testshapes
} // namespace shapediameter
