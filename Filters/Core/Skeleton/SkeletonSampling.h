// SPDX-License-Identifier: BSD-3-Clause
// SDF-guided skeleton, step 1 of 4: the projected point cloud P.
//
// What it computes
//   N points are sampled on the surface, area-weighted, and each is pushed along the inward
//   normal of its face by half of that face's shape diameter. Because the SDF approximates
//   twice the distance to the medial axis, the pushed points form a cloud P that lies near
//   the curve skeleton. Each point keeps radius(p) = SDF/2 (the local medial radius) and the
//   id of the face it came from, which is the link from the skeleton back to the surface.
//
// Reference
//   Shapira, Shamir, Cohen-Or 2008, "Consistent mesh partitioning and skeletonisation using
//   the shape diameter function", section 5, second paragraph.
//
// Parameters (SkeletonSamplingOptions)
//   NumberOfSamples  N, default 10000 (the paper: "not more than 10000"), valid [1, 1e6] (NumberOfSamplesRange).
//                    N is not capped by the face count: a coarse mesh (fewer faces than N)
//                    gets several samples per face, which the MLS step needs for density; a
//                    fine mesh leaves some faces without a sample (they are linked to the
//                    skeleton through their own projected centre, see Skeleton.h).
//   Seed             seed of the std::mt19937_64 generator, default 0x5DF5EED. Same seed,
//                    same mesh -> bit-identical cloud on every platform (the mapping from the
//                    64-bit generator output to [0, 1) is written out, not a std::
//                    distribution).
//
// Sampling scheme
//   Jittered systematic sampling of the cumulative area: sample i takes the area abscissa
//   (i + u_i) / N * A. Every sample is still uniformly distributed over the surface, but the
//   number of samples per face deviates from N * area / A by less than one, instead of the
//   binomial spread of independent draws; it also costs O(N + faces) without a search.
//
// Degenerate input
//   Empty mesh or zero total area -> empty cloud. Faces of zero area are never sampled. A face
//   whose supplied normal is missing, zero or non-finite uses the normal of its triangle.
//   Invalid input (indices out of range, non-finite coordinates, SDF of the wrong size,
//   negative or non-finite SDF) throws Error; see ValidateSkeletonInput.
#pragma once

#include "Errors.h"
#include "Mesh/MeshTypes.h"

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <vector>

namespace shapediameter
{

struct SkeletonSamplingOptions
{
  /// N, the number of surface samples (paper: at most 10000). NumberOfSamplesRange [1, 1e6].
  std::size_t NumberOfSamples = 10000;
  /// Seed of the deterministic generator.
  std::uint64_t Seed = 0x5DF5EED;
};

/// NumberOfSamples, checked by ValidateSamplingOptions; vtkSDFSkeleton's vtkSetClampMacro repeats
/// it (Testing/Filters/TestParameterRanges.cxx). Was [1, 1e7] in the core before; the filter has
/// always clamped to [1, 1e6].
inline constexpr Range<int> NumberOfSamplesRange{ 1, 1000000 };

/// The projected cloud P (paper: "a point cloud P inside the object").
struct ProjectedCloud
{
  /// Positions of P, one row per point: sample - normal * SDF / 2.
  PointMatrix Positions;
  /// radius(p) = SDF / 2 of the source face (length units, >= 0).
  std::vector<double> Radius;
  /// Index of the face the point was sampled on.
  std::vector<std::int64_t> SourceFace;

  std::size_t Size() const { return Radius.size(); }
};

/// Unit outward normal of each triangle (right-hand rule); a zero row for a degenerate face.
PointMatrix ComputeFaceNormals(PointsView points, TrianglesView triangles);

/// Label of the connected component of each face, faces being connected when they share a
/// vertex. Labels are 0.. in order of each component's first face.
std::vector<std::int64_t> LabelFaceComponents(TrianglesView triangles, std::size_t numberOfPoints);

/// Throws Error unless: indices lie in [0, points), coordinates are finite with
/// magnitude <= 1e150, sdf has one finite value in [0, 1e150] per face, faceNormals has 0 or
/// one row per face (bad rows fall back to the triangle normal), faceComponents is empty or
/// has one label per face.
void ValidateSkeletonInput(PointsView points, TrianglesView triangles,
  const std::vector<double>& faceSdf, PointsView faceNormals,
  const std::vector<std::int64_t>& faceComponents);

/// Throws Error if an option is outside its documented range.
void ValidateSamplingOptions(const SkeletonSamplingOptions& options);

/// Step 1: samples the surface and pushes each sample inward by half its face's SDF.
/// faceNormals: unit outward normals, one row per face, or an empty matrix to compute them.
/// The input is assumed valid (call ValidateSkeletonInput first).
ProjectedCloud SampleProjectedCloud(PointsView points, TrianglesView triangles,
  const std::vector<double>& faceSdf, PointsView faceNormals,
  const SkeletonSamplingOptions& options);

/// The normal used for face f: the supplied one if it is finite and non-zero (normalised),
/// else the triangle's own normal (zero for a degenerate face).
Eigen::Vector3d EffectiveFaceNormal(PointsView points, TrianglesView triangles,
  PointsView faceNormals, Eigen::Index face);

} // namespace shapediameter
