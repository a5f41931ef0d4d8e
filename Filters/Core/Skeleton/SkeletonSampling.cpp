// SPDX-License-Identifier: BSD-3-Clause
#include "Skeleton/SkeletonSampling.h"

#include <Eigen/Geometry>

#include <cmath>
#include <numeric>
#include <random>
#include <string>

namespace shapediameter
{

namespace
{

/// Maps a 64-bit generator output to [0, 1) with 53 random bits, the same on every platform.
double UnitInterval(std::mt19937_64& generator)
{
  return static_cast<double>(generator() >> 11) * 0x1.0p-53;
}

Eigen::Vector3d TriangleCross(PointsView points, TrianglesView triangles, Eigen::Index face)
{
  const Eigen::Vector3d a = points.row(triangles(face, 0)).transpose();
  const Eigen::Vector3d b = points.row(triangles(face, 1)).transpose();
  const Eigen::Vector3d c = points.row(triangles(face, 2)).transpose();
  return (b - a).cross(c - a);
}

std::int64_t FindRoot(std::vector<std::int64_t>& parent, std::int64_t i)
{
  while (parent[i] != i)
  {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

} // namespace

PointMatrix ComputeFaceNormals(PointsView points, TrianglesView triangles)
{
  PointMatrix normals = PointMatrix::Zero(triangles.rows(), 3);
  for (Eigen::Index f = 0; f < triangles.rows(); ++f)
  {
    const Eigen::Vector3d cross = TriangleCross(points, triangles, f);
    const double length = cross.norm();
    if (length > 0.0 && std::isfinite(length))
    {
      normals.row(f) = (cross / length).transpose();
    }
  }
  return normals;
}

Eigen::Vector3d EffectiveFaceNormal(PointsView points, TrianglesView triangles,
  PointsView faceNormals, Eigen::Index face)
{
  if (faceNormals.rows() == triangles.rows())
  {
    const Eigen::Vector3d given = faceNormals.row(face).transpose();
    const double length = given.norm();
    if (std::isfinite(length) && length > 1e-12)
    {
      return given / length;
    }
  }
  const Eigen::Vector3d cross = TriangleCross(points, triangles, face);
  const double length = cross.norm();
  return (length > 0.0 && std::isfinite(length)) ? Eigen::Vector3d(cross / length)
                                                 : Eigen::Vector3d::Zero();
}

std::vector<std::int64_t> LabelFaceComponents(TrianglesView triangles, std::size_t numberOfPoints)
{
  std::vector<std::int64_t> parent(numberOfPoints);
  std::iota(parent.begin(), parent.end(), std::int64_t{ 0 });
  for (Eigen::Index f = 0; f < triangles.rows(); ++f)
  {
    const std::int64_t root0 = FindRoot(parent, triangles(f, 0));
    for (int corner = 1; corner < 3; ++corner)
    {
      const std::int64_t root = FindRoot(parent, triangles(f, corner));
      if (root != root0)
      {
        parent[std::max(root, root0)] = std::min(root, root0);
      }
    }
  }
  std::vector<std::int64_t> labelOfRoot(numberOfPoints, -1);
  std::vector<std::int64_t> labels(static_cast<std::size_t>(triangles.rows()));
  std::int64_t next = 0;
  for (Eigen::Index f = 0; f < triangles.rows(); ++f)
  {
    const std::int64_t root = FindRoot(parent, triangles(f, 0));
    if (labelOfRoot[root] < 0)
    {
      labelOfRoot[root] = next++;
    }
    labels[f] = labelOfRoot[root];
  }
  return labels;
}

void ValidateSkeletonInput(PointsView points, TrianglesView triangles,
  const std::vector<double>& faceSdf, PointsView faceNormals,
  const std::vector<std::int64_t>& faceComponents)
{
  const auto faces = static_cast<std::size_t>(triangles.rows());
  if (faceSdf.size() != faces)
  {
    throw Error("skeleton: SDF has " + std::to_string(faceSdf.size()) +
      " values for " + std::to_string(faces) + " triangles");
  }
  if (faceNormals.rows() != 0 && static_cast<std::size_t>(faceNormals.rows()) != faces)
  {
    throw Error("skeleton: face normals must have 0 or one row per triangle");
  }
  if (!faceComponents.empty() && faceComponents.size() != faces)
  {
    throw Error("skeleton: face component labels must be empty or one per triangle");
  }
  // The bound keeps squared distances and second moments finite in double precision.
  constexpr double largest = 1e150;
  if (!points.allFinite() || (points.size() > 0 && points.cwiseAbs().maxCoeff() > largest))
  {
    throw Error("skeleton: point coordinates must be finite with magnitude <= 1e150");
  }
  if (faces > 0 && (triangles.minCoeff() < 0 || triangles.maxCoeff() >= points.rows()))
  {
    throw Error("skeleton: triangle vertex index out of range");
  }
  for (const double value : faceSdf)
  {
    if (!std::isfinite(value) || value < 0.0 || value > largest)
    {
      throw Error("skeleton: SDF values must be finite, >= 0 and <= 1e150");
    }
  }
}

void ValidateSamplingOptions(const SkeletonSamplingOptions& options)
{
  CheckRange(options.NumberOfSamples, NumberOfSamplesRange, "skeleton: NumberOfSamples");
}

ProjectedCloud SampleProjectedCloud(PointsView points, TrianglesView triangles,
  const std::vector<double>& faceSdf, PointsView faceNormals,
  const SkeletonSamplingOptions& options)
{
  ProjectedCloud cloud;
  const Eigen::Index faces = triangles.rows();
  std::vector<double> cumulativeArea(static_cast<std::size_t>(faces));
  double totalArea = 0.0;
  Eigen::Index lastSampledFace = -1;
  for (Eigen::Index f = 0; f < faces; ++f)
  {
    const double area = 0.5 * TriangleCross(points, triangles, f).norm();
    if (area > 0.0 && std::isfinite(area))
    {
      totalArea += area;
      lastSampledFace = f;
    }
    cumulativeArea[f] = totalArea;
  }
  if (lastSampledFace < 0 || !(totalArea > 0.0) || !std::isfinite(totalArea))
  {
    return cloud;
  }

  const std::size_t count = options.NumberOfSamples;
  cloud.Positions.resize(static_cast<Eigen::Index>(count), 3);
  cloud.Radius.resize(count);
  cloud.SourceFace.resize(count);

  std::mt19937_64 generator(options.Seed);
  Eigen::Index face = 0;
  for (std::size_t i = 0; i < count; ++i)
  {
    const double abscissa = (static_cast<double>(i) + UnitInterval(generator)) /
      static_cast<double>(count) * totalArea;
    // Abscissas increase with i, so one forward walk visits each face once; strict '<='
    // skips zero-area faces, whose cumulative value equals their predecessor's.
    while (face < lastSampledFace && cumulativeArea[face] <= abscissa)
    {
      ++face;
    }
    const double s = std::sqrt(UnitInterval(generator));
    const double t = UnitInterval(generator);
    const Eigen::Vector3d a = points.row(triangles(face, 0)).transpose();
    const Eigen::Vector3d b = points.row(triangles(face, 1)).transpose();
    const Eigen::Vector3d c = points.row(triangles(face, 2)).transpose();
    const Eigen::Vector3d sample = (1.0 - s) * a + s * (1.0 - t) * b + s * t * c;
    const double radius = 0.5 * faceSdf[face];
    const Eigen::Vector3d normal = EffectiveFaceNormal(points, triangles, faceNormals, face);
    cloud.Positions.row(static_cast<Eigen::Index>(i)) = (sample - radius * normal).transpose();
    cloud.Radius[i] = radius;
    cloud.SourceFace[i] = face;
  }
  return cloud;
}

} // namespace shapediameter
