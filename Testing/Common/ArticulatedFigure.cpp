// SPDX-License-Identifier: BSD-3-Clause
#include "ArticulatedFigure.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <unordered_map>
#include <utility>

namespace shapediameter
{
namespace testing
{

namespace
{

using Vec3 = Eigen::Vector3d;

struct Capsule
{
  Vec3 A;
  Vec3 B;
  double Radius;
};

constexpr double Blend = 0.05;
// Skin blend across the limb axis, in limb radii.
constexpr double SkinInner = 1.4;
constexpr double SkinOuter = 1.9;

const std::array<Capsule, FigurePartCount>& PartCapsules()
{
  static const std::array<Capsule, FigurePartCount> capsules = { {
    { Vec3(0.0, -0.35, 0.0), Vec3(0.0, 0.35, 0.0), 0.25 },   // torso
    { Vec3(0.0, 0.76, 0.0), Vec3(0.0, 0.76, 0.0), 0.18 },    // head
    { Vec3(0.15, 0.3, 0.0), Vec3(0.90, 0.3, 0.0), 0.07 },    // left arm
    { Vec3(-0.15, 0.3, 0.0), Vec3(-0.90, 0.3, 0.0), 0.07 },  // right arm
    { Vec3(0.15, -0.45, 0.0), Vec3(0.15, -1.30, 0.0), 0.10 }, // left leg
    { Vec3(-0.15, -0.45, 0.0), Vec3(-0.15, -1.30, 0.0), 0.10 } // right leg
  } };
  return capsules;
}

double CapsuleDistance(const Vec3& p, const Capsule& capsule)
{
  const Vec3 axis = capsule.B - capsule.A;
  const double axisSquared = axis.squaredNorm();
  const double t = axisSquared > 0.0 ? std::clamp((p - capsule.A).dot(axis) / axisSquared, 0.0, 1.0) : 0.0;
  return (p - (capsule.A + t * axis)).norm() - capsule.Radius;
}

// Polynomial smooth minimum: equals min(a, b) when |a - b| >= k, C1 everywhere.
double SmoothMin(double a, double b, double k)
{
  const double h = std::max(k - std::abs(a - b), 0.0) / k;
  return std::min(a, b) - h * h * k * 0.25;
}

double SmoothStep(double x)
{
  x = std::clamp(x, 0.0, 1.0);
  return x * x * (3.0 - 2.0 * x);
}

/// A point's coordinates in a limb's frame: along the axis from the pivot, and off it.
struct LimbCoordinates
{
  double Along;
  double Across;
};

LimbCoordinates InLimbFrame(const Vec3& p, const FigureLimb& limb)
{
  const Vec3 relative = p - limb.Pivot;
  const double along = relative.dot(limb.Direction);
  return { along, (relative - along * limb.Direction).norm() };
}

Vec3 FieldGradient(const Vec3& p)
{
  constexpr double step = 1e-6;
  Vec3 gradient;
  for (int axis = 0; axis < 3; ++axis)
  {
    Vec3 forward = p;
    Vec3 backward = p;
    forward[axis] += step;
    backward[axis] -= step;
    gradient[axis] = (ArticulatedFigureTemplate::SignedField(forward) -
                       ArticulatedFigureTemplate::SignedField(backward)) / (2.0 * step);
  }
  return gradient;
}

Vec3 ProjectOntoSurface(Vec3 p)
{
  for (int iteration = 0; iteration < 6; ++iteration)
  {
    const double value = ArticulatedFigureTemplate::SignedField(p);
    const Vec3 gradient = FieldGradient(p);
    const double gradientSquared = gradient.squaredNorm();
    if (gradientSquared < 1e-12)
    {
      break;
    }
    p -= (value / gradientSquared) * gradient;
    if (std::abs(value) < 1e-13)
    {
      break;
    }
  }
  return p;
}

struct TriangleSoup
{
  std::vector<Vec3> Points;
  std::vector<std::array<std::int64_t, 3>> Triangles;
};

TriangleSoup MarchingTetrahedra(double cellSize, double gridAngle)
{
  // The grid lives in a frame rotated by gridToWorld; bounds are taken in that frame (a
  // capsule stays a capsule under rotation), so every part is inside the grid at any angle.
  const Eigen::Matrix3d gridToWorld =
    Eigen::AngleAxisd(gridAngle, Vec3(1.0, 2.0, 3.0).normalized()).toRotationMatrix();
  Vec3 lower = Vec3::Constant(1e300);
  Vec3 upper = Vec3::Constant(-1e300);
  for (const Capsule& capsule : PartCapsules())
  {
    const Vec3 a = gridToWorld.transpose() * capsule.A;
    const Vec3 b = gridToWorld.transpose() * capsule.B;
    lower = lower.cwiseMin(a.cwiseMin(b) - Vec3::Constant(capsule.Radius));
    upper = upper.cwiseMax(a.cwiseMax(b) + Vec3::Constant(capsule.Radius));
  }
  // A non-round offset keeps grid samples off the zero set (and off the symmetry planes).
  const Vec3 origin = lower - cellSize * Vec3(2.37, 2.61, 2.29);
  const Eigen::Array3i counts = (((upper - origin) / cellSize).array() + 3.0).floor().cast<int>();
  const std::int64_t nx = counts[0], ny = counts[1], nz = counts[2];
  auto gridIndex = [&](std::int64_t i, std::int64_t j, std::int64_t k) { return (k * ny + j) * nx + i; };
  auto gridPoint = [&](std::int64_t i, std::int64_t j, std::int64_t k) {
    return Vec3(gridToWorld * (origin + cellSize * Vec3(static_cast<double>(i), static_cast<double>(j), static_cast<double>(k))));
  };
  std::vector<double> field(static_cast<std::size_t>(nx * ny * nz));
  for (std::int64_t k = 0; k < nz; ++k)
  {
    for (std::int64_t j = 0; j < ny; ++j)
    {
      for (std::int64_t i = 0; i < nx; ++i)
      {
        field[static_cast<std::size_t>(gridIndex(i, j, k))] = ArticulatedFigureTemplate::SignedField(gridPoint(i, j, k));
      }
    }
  }

  TriangleSoup soup;
  std::unordered_map<std::uint64_t, std::int64_t> edgeVertices;
  const auto gridSize = static_cast<std::uint64_t>(nx * ny * nz);
  // Vertex on the grid edge (a, b), a < b the grid indices: shared by every tetrahedron.
  auto vertexOnEdge = [&](std::int64_t a, std::int64_t b, const Vec3& pa, const Vec3& pb) -> std::int64_t {
    const std::uint64_t key = static_cast<std::uint64_t>(a) * gridSize + static_cast<std::uint64_t>(b);
    const auto found = edgeVertices.find(key);
    if (found != edgeVertices.end())
    {
      return found->second;
    }
    const double fa = field[static_cast<std::size_t>(a)];
    const double fb = field[static_cast<std::size_t>(b)];
    const double t = std::clamp(fa / (fa - fb), 0.05, 0.95);
    const auto index = static_cast<std::int64_t>(soup.Points.size());
    soup.Points.push_back(pa + t * (pb - pa));
    edgeVertices.emplace(key, index);
    return index;
  };

  // Kuhn split: tetrahedron (0, e_p0, e_p0 + e_p1, 7) for each axis permutation p.
  static const int permutations[6][3] = { { 0, 1, 2 }, { 0, 2, 1 }, { 1, 0, 2 }, { 1, 2, 0 }, { 2, 0, 1 }, { 2, 1, 0 } };
  for (std::int64_t k = 0; k + 1 < nz; ++k)
  {
    for (std::int64_t j = 0; j + 1 < ny; ++j)
    {
      for (std::int64_t i = 0; i + 1 < nx; ++i)
      {
        for (const auto& permutation : permutations)
        {
          std::array<int, 4> cornerBits = { 0, 1 << permutation[0], 0, 7 };
          cornerBits[2] = cornerBits[1] | (1 << permutation[1]);
          std::array<std::int64_t, 4> ids;
          std::array<Eigen::Vector3d, 4> lattice; // integer grid coordinates, exact
          std::array<bool, 4> inside;
          int insideCount = 0;
          for (int c = 0; c < 4; ++c)
          {
            const std::int64_t ci = i + (cornerBits[c] & 1);
            const std::int64_t cj = j + ((cornerBits[c] >> 1) & 1);
            const std::int64_t ck = k + ((cornerBits[c] >> 2) & 1);
            ids[c] = gridIndex(ci, cj, ck);
            lattice[c] = Vec3(static_cast<double>(ci), static_cast<double>(cj), static_cast<double>(ck));
            inside[c] = field[static_cast<std::size_t>(ids[c])] < 0.0;
            insideCount += inside[c];
          }
          if (insideCount == 0 || insideCount == 4)
          {
            continue;
          }
          Vec3 insideMean = Vec3::Zero();
          Vec3 outsideMean = Vec3::Zero();
          for (int c = 0; c < 4; ++c)
          {
            (inside[c] ? insideMean : outsideMean) += lattice[c];
          }
          const Vec3 outward = outsideMean / (4.0 - insideCount) - insideMean / insideCount;
          // Emits the triangle over three cut edges, oriented so that the triangle of the
          // edge midpoints (never degenerate) faces `outward`.
          auto emit = [&](const std::array<std::pair<int, int>, 3>& edges) {
            std::array<std::int64_t, 3> triangle;
            std::array<Vec3, 3> midpoints;
            for (int e = 0; e < 3; ++e)
            {
              const int a = edges[e].first;
              const int b = edges[e].second;
              const bool ordered = ids[a] < ids[b];
              const int low = ordered ? a : b;
              const int high = ordered ? b : a;
              triangle[e] = vertexOnEdge(ids[low], ids[high], gridToWorld * (origin + cellSize * lattice[low]),
                gridToWorld * (origin + cellSize * lattice[high]));
              midpoints[e] = 0.5 * (lattice[a] + lattice[b]);
            }
            const Vec3 normal = (midpoints[1] - midpoints[0]).cross(midpoints[2] - midpoints[0]);
            if (normal.dot(outward) < 0.0)
            {
              std::swap(triangle[1], triangle[2]);
            }
            soup.Triangles.push_back(triangle);
          };
          if (insideCount == 1 || insideCount == 3)
          {
            int lone = 0;
            while (inside[lone] != (insideCount == 1))
            {
              ++lone;
            }
            std::array<int, 3> others;
            for (int c = 0, n = 0; c < 4; ++c)
            {
              if (c != lone)
              {
                others[n++] = c;
              }
            }
            emit({ { { lone, others[0] }, { lone, others[1] }, { lone, others[2] } } });
          }
          else
          {
            std::array<int, 2> in;
            std::array<int, 2> out;
            for (int c = 0, ni = 0, no = 0; c < 4; ++c)
            {
              (inside[c] ? in[ni++] : out[no++]) = c;
            }
            // The cut is the quad (in0 out0, in0 out1, in1 out1, in1 out0).
            emit({ { { in[0], out[0] }, { in[0], out[1] }, { in[1], out[1] } } });
            emit({ { { in[0], out[0] }, { in[1], out[1] }, { in[1], out[0] } } });
          }
        }
      }
    }
  }
  return soup;
}

void Relax(TriangleSoup& soup, int iterations)
{
  const std::size_t pointCount = soup.Points.size();
  std::vector<std::vector<std::int64_t>> neighbors(pointCount);
  for (const auto& triangle : soup.Triangles)
  {
    for (int c = 0; c < 3; ++c)
    {
      neighbors[static_cast<std::size_t>(triangle[c])].push_back(triangle[(c + 1) % 3]);
      neighbors[static_cast<std::size_t>(triangle[c])].push_back(triangle[(c + 2) % 3]);
    }
  }
  for (auto& list : neighbors)
  {
    std::sort(list.begin(), list.end());
    list.erase(std::unique(list.begin(), list.end()), list.end());
  }
  std::vector<Vec3> next(pointCount);
  for (int iteration = 0; iteration < iterations; ++iteration)
  {
    for (std::size_t v = 0; v < pointCount; ++v)
    {
      Vec3 mean = Vec3::Zero();
      for (std::int64_t w : neighbors[v])
      {
        mean += soup.Points[static_cast<std::size_t>(w)];
      }
      mean /= static_cast<double>(std::max<std::size_t>(1, neighbors[v].size()));
      next[v] = ProjectOntoSurface(soup.Points[v] + 0.5 * (mean - soup.Points[v]));
    }
    soup.Points.swap(next);
  }
}

} // namespace

double ArticulatedFigureTemplate::PartDistance(const Eigen::Vector3d& point, FigurePart part)
{
  return CapsuleDistance(point, PartCapsules()[static_cast<std::size_t>(part)]);
}

double ArticulatedFigureTemplate::SignedField(const Eigen::Vector3d& point)
{
  double value = PartDistance(point, Torso);
  for (int part = Head; part < FigurePartCount; ++part)
  {
    value = SmoothMin(value, PartDistance(point, static_cast<FigurePart>(part)), Blend);
  }
  return value;
}

FigureLimb ArticulatedFigureTemplate::Limb(FigurePart limb)
{
  switch (limb)
  {
    case LeftArm:
      return { Vec3(0.25, 0.3, 0.0), Vec3(1.0, 0.0, 0.0), Vec3(0.0, 0.0, 1.0), 0.07, 0.72 };
    case RightArm:
      return { Vec3(-0.25, 0.3, 0.0), Vec3(-1.0, 0.0, 0.0), Vec3(0.0, 0.0, -1.0), 0.07, 0.72 };
    case LeftLeg:
      return { Vec3(0.15, -0.55, 0.0), Vec3(0.0, -1.0, 0.0), Vec3(-1.0, 0.0, 0.0), 0.10, 0.85 };
    case RightLeg:
      return { Vec3(-0.15, -0.55, 0.0), Vec3(0.0, -1.0, 0.0), Vec3(-1.0, 0.0, 0.0), 0.10, 0.85 };
    default:
      throw std::invalid_argument("Limb() takes LeftArm, RightArm, LeftLeg or RightLeg");
  }
}

ArticulatedFigureTemplate::ArticulatedFigureTemplate(const FigureOptions& options)
{
  if (!(options.CellSize > 0.005 && options.CellSize < 0.1) || options.RelaxationIterations < 0 ||
    options.RelaxationIterations > 50 || !(std::abs(options.GridAngle) <= 3.14159265358979323846))
  {
    throw std::invalid_argument("FigureOptions out of range");
  }
  TriangleSoup soup = MarchingTetrahedra(options.CellSize, options.GridAngle);
  Relax(soup, options.RelaxationIterations);

  const auto pointCount = static_cast<Eigen::Index>(soup.Points.size());
  const auto triangleCount = static_cast<Eigen::Index>(soup.Triangles.size());
  RestFigure.Points.resize(pointCount, 3);
  for (Eigen::Index v = 0; v < pointCount; ++v)
  {
    RestFigure.Points.row(v) = soup.Points[static_cast<std::size_t>(v)].transpose();
  }
  RestFigure.Triangles.resize(triangleCount, 3);
  RestFigure.FaceParts.resize(static_cast<std::size_t>(triangleCount));
  for (Eigen::Index t = 0; t < triangleCount; ++t)
  {
    const auto& triangle = soup.Triangles[static_cast<std::size_t>(t)];
    Vec3 center = Vec3::Zero();
    for (int c = 0; c < 3; ++c)
    {
      RestFigure.Triangles(t, c) = triangle[c];
      center += soup.Points[static_cast<std::size_t>(triangle[c])];
    }
    center /= 3.0;
    int nearest = Torso;
    for (int part = Head; part < FigurePartCount; ++part)
    {
      if (PartDistance(center, static_cast<FigurePart>(part)) < PartDistance(center, static_cast<FigurePart>(nearest)))
      {
        nearest = part;
      }
    }
    RestFigure.FaceParts[static_cast<std::size_t>(t)] = nearest;
  }

  Weights.setZero(pointCount, 4);
  for (Eigen::Index v = 0; v < pointCount; ++v)
  {
    const Vec3 p = RestFigure.Points.row(v).transpose();
    double sum = 0.0;
    for (int limbIndex = 0; limbIndex < 4; ++limbIndex)
    {
      const FigureLimb limb = Limb(static_cast<FigurePart>(LeftArm + limbIndex));
      const auto [along, across] = InLimbFrame(p, limb);
      const double weight = SmoothStep((along + limb.Radius) / (2.0 * limb.Radius)) *
        (1.0 - SmoothStep((across - SkinInner * limb.Radius) / ((SkinOuter - SkinInner) * limb.Radius)));
      Weights(v, limbIndex) = weight;
      sum += weight;
    }
    if (sum > 1.0)
    {
      Weights.row(v) /= sum;
    }
  }
}

double ArticulatedFigureTemplate::SkinWeight(Eigen::Index point, FigurePart limb) const
{
  if (limb < LeftArm || limb > RightLeg)
  {
    throw std::invalid_argument("SkinWeight() takes a limb part");
  }
  return Weights(point, limb - LeftArm);
}

ArticulatedFigure ArticulatedFigureTemplate::Pose(const FigurePose& pose) const
{
  const std::array<double, 4> angles = { pose.LeftArm, pose.RightArm, pose.LeftLeg, pose.RightLeg };
  std::array<Eigen::Matrix3d, 4> rotations;
  std::array<Vec3, 4> pivots;
  for (int limbIndex = 0; limbIndex < 4; ++limbIndex)
  {
    const FigureLimb limb = Limb(static_cast<FigurePart>(LeftArm + limbIndex));
    rotations[limbIndex] = Eigen::AngleAxisd(angles[limbIndex], limb.BendAxis).toRotationMatrix();
    pivots[limbIndex] = limb.Pivot;
  }
  ArticulatedFigure posed = RestFigure;
  for (Eigen::Index v = 0; v < posed.Points.rows(); ++v)
  {
    const Vec3 rest = RestFigure.Points.row(v).transpose();
    Vec3 displacement = Vec3::Zero();
    bool moved = false;
    for (int limbIndex = 0; limbIndex < 4; ++limbIndex)
    {
      const double weight = Weights(v, limbIndex);
      if (weight > 0.0 && angles[limbIndex] != 0.0)
      {
        const Vec3 rotated = pivots[limbIndex] + rotations[limbIndex] * (rest - pivots[limbIndex]);
        displacement += weight * (rotated - rest);
        moved = true;
      }
    }
    if (moved)
    {
      posed.Points.row(v) = (rest + displacement).transpose();
    }
  }
  return posed;
}

ArticulatedFigure ArticulatedFigureTemplate::NonRigidPose(const FigurePose& pose, const NonRigidBend& bend) const
{
  if (!(bend.JointLength > 0.0 && bend.JointLength <= 8.0) || !(bend.Stretch >= 0.0 && bend.Stretch < 1.0))
  {
    throw std::invalid_argument("NonRigidBend out of range");
  }
  const std::array<double, 4> angles = { pose.LeftArm, pose.RightArm, pose.LeftLeg, pose.RightLeg };
  ArticulatedFigure posed = RestFigure;
  for (Eigen::Index v = 0; v < posed.Points.rows(); ++v)
  {
    const Vec3 rest = RestFigure.Points.row(v).transpose();
    std::array<double, 4> weights{};
    std::array<Vec3, 4> displacements;
    std::array<bool, 4> movesLimb{};
    double weightSum = 0.0;
    for (int limbIndex = 0; limbIndex < 4; ++limbIndex)
    {
      const FigureLimb limb = Limb(static_cast<FigurePart>(LeftArm + limbIndex));
      const Vec3 relative = rest - limb.Pivot;
      const auto [along, across] = InLimbFrame(rest, limb);
      // Across the axis the same fade into the torso as the rigid skinning, so the torso away
      // from the joints stays still; along it the weight is full a radius before the bend
      // starts, so the axis line beyond the pivot (through the torso and the opposite arm)
      // does not count, and the bend is spread over the joint instead of concentrated.
      weights[limbIndex] = SmoothStep((along + 2.0 * limb.Radius) / limb.Radius) *
        (1.0 - SmoothStep((across - SkinInner * limb.Radius) / ((SkinOuter - SkinInner) * limb.Radius)));
      const double jointLength = bend.JointLength * limb.Radius;
      const double progress = SmoothStep((along + limb.Radius) / jointLength);
      movesLimb[limbIndex] = progress > 0.0 && (angles[limbIndex] != 0.0 || bend.Stretch > 0.0);
      const double lengthening = bend.Stretch * jointLength * progress;
      const Eigen::Matrix3d rotation =
        Eigen::AngleAxisd(angles[limbIndex] * progress, limb.BendAxis).toRotationMatrix();
      displacements[limbIndex] = limb.Pivot + rotation * (relative + lengthening * limb.Direction) - rest;
      weightSum += weights[limbIndex];
    }
    Vec3 displacement = Vec3::Zero();
    bool moved = false;
    for (int limbIndex = 0; limbIndex < 4; ++limbIndex)
    {
      if (weights[limbIndex] > 0.0 && movesLimb[limbIndex])
      {
        displacement += weights[limbIndex] / std::max(1.0, weightSum) * displacements[limbIndex];
        moved = true;
      }
    }
    // Vertices outside every joint keep their coordinates bit for bit (pivot + (p - pivot)
    // need not round to p).
    if (moved)
    {
      posed.Points.row(v) = (rest + displacement).transpose();
    }
  }
  return posed;
}

ArticulatedFigure MakeArticulatedFigure(const FigurePose& pose, const FigureOptions& options)
{
  return ArticulatedFigureTemplate(options).Pose(pose);
}

} // namespace testing
} // namespace shapediameter
