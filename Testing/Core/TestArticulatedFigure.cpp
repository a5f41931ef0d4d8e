// SPDX-License-Identifier: BSD-3-Clause
// The shared articulated-figure fixture: closed, outward, same connectivity in every pose.
#include "ArticulatedFigure.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <numeric>
#include <utility>
#include <vector>

namespace
{

using namespace shapediameter;
using namespace shapediameter::testing;

constexpr double Pi = 3.14159265358979323846;

const ArticulatedFigureTemplate& SharedTemplate()
{
  static const ArticulatedFigureTemplate figure;
  return figure;
}

double SignedVolume(const ArticulatedFigure& figure)
{
  double volume = 0.0;
  for (Eigen::Index t = 0; t < figure.Triangles.rows(); ++t)
  {
    const Eigen::Vector3d a = figure.Points.row(figure.Triangles(t, 0)).transpose();
    const Eigen::Vector3d b = figure.Points.row(figure.Triangles(t, 1)).transpose();
    const Eigen::Vector3d c = figure.Points.row(figure.Triangles(t, 2)).transpose();
    volume += a.dot(b.cross(c)) / 6.0;
  }
  return volume;
}

Eigen::Vector3d FaceNormal(const ArticulatedFigure& figure, Eigen::Index t)
{
  const Eigen::Vector3d a = figure.Points.row(figure.Triangles(t, 0)).transpose();
  const Eigen::Vector3d b = figure.Points.row(figure.Triangles(t, 1)).transpose();
  const Eigen::Vector3d c = figure.Points.row(figure.Triangles(t, 2)).transpose();
  return (b - a).cross(c - a);
}

Eigen::Vector3d FaceCenter(const ArticulatedFigure& figure, Eigen::Index t)
{
  return (figure.Points.row(figure.Triangles(t, 0)) + figure.Points.row(figure.Triangles(t, 1)) +
           figure.Points.row(figure.Triangles(t, 2))).transpose() / 3.0;
}

std::size_t ComponentCount(const ArticulatedFigure& figure)
{
  std::vector<Eigen::Index> parent(static_cast<std::size_t>(figure.Points.rows()));
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&parent](Eigen::Index v) {
    while (parent[static_cast<std::size_t>(v)] != v)
    {
      v = parent[static_cast<std::size_t>(v)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(v)])];
    }
    return v;
  };
  for (Eigen::Index t = 0; t < figure.Triangles.rows(); ++t)
  {
    for (int c = 1; c < 3; ++c)
    {
      parent[static_cast<std::size_t>(find(figure.Triangles(t, c)))] = find(figure.Triangles(t, 0));
    }
  }
  std::size_t roots = 0;
  for (Eigen::Index v = 0; v < figure.Points.rows(); ++v)
  {
    roots += find(v) == v;
  }
  return roots;
}

/// Edges not used exactly once in each direction (0 = watertight, 2-manifold, consistent).
std::size_t BadEdgeCount(const ArticulatedFigure& figure, std::size_t* edgeCount = nullptr)
{
  std::map<std::pair<std::int64_t, std::int64_t>, int> directed;
  for (Eigen::Index t = 0; t < figure.Triangles.rows(); ++t)
  {
    for (int c = 0; c < 3; ++c)
    {
      ++directed[{ figure.Triangles(t, c), figure.Triangles(t, (c + 1) % 3) }];
    }
  }
  std::size_t bad = 0;
  for (const auto& [edge, count] : directed)
  {
    const auto reverse = directed.find({ edge.second, edge.first });
    bad += count != 1 || reverse == directed.end() || reverse->second != 1;
  }
  if (edgeCount)
  {
    *edgeCount = directed.size() / 2;
  }
  return bad;
}

/// Interior edges whose two faces' normals point more than 120 degrees apart: a fold.
std::size_t FoldedEdgeCount(const ArticulatedFigure& figure)
{
  std::map<std::pair<std::int64_t, std::int64_t>, Eigen::Index> faceOfEdge;
  std::size_t folded = 0;
  for (Eigen::Index t = 0; t < figure.Triangles.rows(); ++t)
  {
    for (int c = 0; c < 3; ++c)
    {
      const std::int64_t a = figure.Triangles(t, c);
      const std::int64_t b = figure.Triangles(t, (c + 1) % 3);
      const auto other = faceOfEdge.find({ b, a });
      if (other != faceOfEdge.end())
      {
        folded += FaceNormal(figure, t).normalized().dot(FaceNormal(figure, other->second).normalized()) < -0.5;
      }
      faceOfEdge[{ a, b }] = t;
    }
  }
  return folded;
}

/// Share of the faces whose area changed by more than `tolerance` (relative) between poses.
double ShareOfFacesResized(const ArticulatedFigure& rest, const ArticulatedFigure& posed, double tolerance)
{
  std::size_t resized = 0;
  for (Eigen::Index t = 0; t < rest.Triangles.rows(); ++t)
  {
    resized += std::abs(FaceNormal(posed, t).norm() / FaceNormal(rest, t).norm() - 1.0) > tolerance;
  }
  return static_cast<double>(resized) / static_cast<double>(rest.Triangles.rows());
}

} // namespace

TEST(ArticulatedFigure, RestPoseIsClosedManifoldOutwardGenusZero)
{
  const ArticulatedFigure& figure = SharedTemplate().Rest();
  const Eigen::Index faces = figure.Triangles.rows();
  EXPECT_GE(faces, 10000);
  EXPECT_LE(faces, 30000);
  // Each directed edge exactly once and its reverse exactly once: watertight, 2-manifold
  // along edges, consistently oriented.
  std::map<std::pair<std::int64_t, std::int64_t>, int> directed;
  for (Eigen::Index t = 0; t < faces; ++t)
  {
    for (int c = 0; c < 3; ++c)
    {
      ++directed[{ figure.Triangles(t, c), figure.Triangles(t, (c + 1) % 3) }];
    }
  }
  std::size_t badEdges = 0;
  for (const auto& [edge, count] : directed)
  {
    const auto reverse = directed.find({ edge.second, edge.first });
    badEdges += count != 1 || reverse == directed.end() || reverse->second != 1;
  }
  EXPECT_EQ(badEdges, 0u);
  const auto edges = static_cast<Eigen::Index>(directed.size() / 2);
  EXPECT_EQ(figure.Points.rows() - edges + faces, 2); // Euler characteristic of a sphere
  EXPECT_EQ(ComponentCount(figure), 1u);

  // Outward: positive volume near that of the union of the parts, and every face normal
  // along the gradient of the implicit field.
  const double volume = SignedVolume(figure);
  EXPECT_GT(volume, 0.28);
  EXPECT_LT(volume, 0.34);
  std::size_t against = 0;
  double smallestArea = 1e300;
  for (Eigen::Index t = 0; t < faces; ++t)
  {
    const Eigen::Vector3d center = (figure.Points.row(figure.Triangles(t, 0)) + figure.Points.row(figure.Triangles(t, 1)) +
                                     figure.Points.row(figure.Triangles(t, 2))).transpose() / 3.0;
    Eigen::Vector3d gradient;
    for (int axis = 0; axis < 3; ++axis)
    {
      Eigen::Vector3d step = Eigen::Vector3d::Zero();
      step[axis] = 1e-6;
      gradient[axis] = ArticulatedFigureTemplate::SignedField(center + step) -
        ArticulatedFigureTemplate::SignedField(center - step);
    }
    const Eigen::Vector3d normal = FaceNormal(figure, t);
    against += normal.normalized().dot(gradient.normalized()) < 0.5;
    smallestArea = std::min(smallestArea, 0.5 * normal.norm());
  }
  EXPECT_EQ(against, 0u);
  EXPECT_GT(smallestArea, 1e-6); // no degenerate triangles
  for (Eigen::Index v = 0; v < figure.Points.rows(); ++v)
  {
    ASSERT_LT(std::abs(ArticulatedFigureTemplate::SignedField(figure.Points.row(v).transpose())), 1e-9);
  }
}

TEST(ArticulatedFigure, PartLabelsCoverEveryPartSymmetrically)
{
  const ArticulatedFigure& figure = SharedTemplate().Rest();
  std::vector<int> counts(FigurePartCount, 0);
  for (int part : figure.FaceParts)
  {
    ASSERT_GE(part, 0);
    ASSERT_LT(part, FigurePartCount);
    ++counts[static_cast<std::size_t>(part)];
  }
  for (int count : counts)
  {
    EXPECT_GT(count, 300);
  }
  EXPECT_NEAR(counts[LeftArm], counts[RightArm], 0.05 * counts[LeftArm]);
  EXPECT_NEAR(counts[LeftLeg], counts[RightLeg], 0.05 * counts[LeftLeg]);
  EXPECT_GT(counts[Torso], counts[LeftLeg]);

  // Labels against the geometry of the header (not against PartDistance, which makes them):
  // regions that only one part reaches carry that part's label.
  std::vector<int> regionFaces(FigurePartCount, 0);
  std::size_t mislabelled = 0;
  for (Eigen::Index t = 0; t < figure.Triangles.rows(); ++t)
  {
    const Eigen::Vector3d c = FaceCenter(figure, t);
    int expected = -1;
    if (c.x() > 0.5 && std::abs(c.y() - 0.3) < 0.1)
    {
      expected = LeftArm; // the figure's left side is +x
    }
    else if (c.x() < -0.5 && std::abs(c.y() - 0.3) < 0.1)
    {
      expected = RightArm;
    }
    else if (c.y() < -0.8)
    {
      expected = c.x() > 0.0 ? LeftLeg : RightLeg;
    }
    else if (c.y() > 0.65)
    {
      expected = Head;
    }
    else if (std::abs(c.y()) < 0.1)
    {
      expected = Torso;
    }
    if (expected >= 0)
    {
      ++regionFaces[static_cast<std::size_t>(expected)];
      mislabelled += figure.FaceParts[static_cast<std::size_t>(t)] != expected ? 1 : 0;
    }
  }
  EXPECT_EQ(mislabelled, 0u);
  for (int part = 0; part < FigurePartCount; ++part)
  {
    EXPECT_GT(regionFaces[static_cast<std::size_t>(part)], 100) << "part " << part;
  }
}

TEST(ArticulatedFigure, MeshMatchesTheDocumentedGeometry)
{
  // The thickness classes the SDF tests rely on, measured on the surface: arm < leg < head <
  // torso (radii 0.07, 0.1, 0.18, 0.25 in the header); and Limb(), which the poses rotate
  // about, describes the limbs the mesh really has (radius about its axis, tip at Length).
  const ArticulatedFigureTemplate& figure = SharedTemplate();
  const ArticulatedFigure& rest = figure.Rest();
  std::vector<std::vector<double>> radii(FigurePartCount);
  std::vector<double> tips(FigurePartCount, -1e300);
  for (Eigen::Index v = 0; v < rest.Points.rows(); ++v)
  {
    const Eigen::Vector3d p = rest.Points.row(v).transpose();
    for (int part = LeftArm; part <= RightLeg; ++part)
    {
      if (figure.SkinWeight(v, static_cast<FigurePart>(part)) != 1.0)
      {
        continue; // near the joint the surface blends into the torso
      }
      const FigureLimb limb = ArticulatedFigureTemplate::Limb(static_cast<FigurePart>(part));
      const double along = (p - limb.Pivot).dot(limb.Direction);
      tips[static_cast<std::size_t>(part)] = std::max(tips[static_cast<std::size_t>(part)], along);
      if (along < limb.Length - limb.Radius) // the cylinder, not the tip cap
      {
        radii[static_cast<std::size_t>(part)].push_back((p - limb.Pivot - along * limb.Direction).norm());
      }
    }
    if (std::abs(p.y()) < 0.1)
    {
      radii[Torso].push_back(std::hypot(p.x(), p.z()));
    }
    if (p.y() > 0.7)
    {
      radii[Head].push_back((p - Eigen::Vector3d(0.0, 0.76, 0.0)).norm());
    }
  }
  std::vector<double> measured(FigurePartCount);
  for (int part = 0; part < FigurePartCount; ++part)
  {
    std::vector<double>& r = radii[static_cast<std::size_t>(part)];
    ASSERT_GT(r.size(), 50u) << "part " << part;
    std::nth_element(r.begin(), r.begin() + static_cast<std::ptrdiff_t>(r.size() / 2), r.end());
    measured[static_cast<std::size_t>(part)] = r[r.size() / 2];
  }
  // Vertices lie on the zero set (1e-9), so away from the blends the radius is exact up to
  // the projection; 1 % leaves room for the smooth minimum's reach (0.05) near the ends.
  const double documented[FigurePartCount] = { 0.25, 0.18, 0.07, 0.07, 0.10, 0.10 };
  std::printf("median radius torso %.4f head %.4f arms %.4f %.4f legs %.4f %.4f; tips %.4f %.4f %.4f %.4f\n",
    measured[Torso], measured[Head], measured[LeftArm], measured[RightArm], measured[LeftLeg], measured[RightLeg],
    tips[LeftArm], tips[RightArm], tips[LeftLeg], tips[RightLeg]);
  for (int part = 0; part < FigurePartCount; ++part)
  {
    EXPECT_NEAR(measured[static_cast<std::size_t>(part)], documented[part], 0.01 * documented[part]) << "part " << part;
  }
  for (int part = LeftArm; part <= RightLeg; ++part)
  {
    const FigureLimb limb = ArticulatedFigureTemplate::Limb(static_cast<FigurePart>(part));
    EXPECT_NEAR(measured[static_cast<std::size_t>(part)], limb.Radius, 0.01 * limb.Radius) << "limb " << part;
    // The tip vertex is within a fraction of a grid cell (0.036) of the cap's apex.
    EXPECT_NEAR(tips[static_cast<std::size_t>(part)], limb.Length, 0.01) << "limb " << part;
  }
  EXPECT_LT(measured[LeftArm], measured[LeftLeg]);
  EXPECT_LT(measured[LeftLeg], measured[Head]);
  EXPECT_LT(measured[Head], measured[Torso]);
}

TEST(ArticulatedFigure, PosesKeepConnectivityAndMoveOnlyTheBentLimb)
{
  const ArticulatedFigureTemplate& figure = SharedTemplate();
  const ArticulatedFigure& rest = figure.Rest();
  FigurePose pose;
  pose.LeftArm = Pi / 4;
  pose.RightLeg = -Pi / 6;
  const ArticulatedFigure bent = figure.Pose(pose);
  ASSERT_EQ(bent.Triangles.rows(), rest.Triangles.rows());
  EXPECT_TRUE(bent.Triangles == rest.Triangles);
  EXPECT_EQ(bent.FaceParts, rest.FaceParts);
  ASSERT_EQ(bent.Points.rows(), rest.Points.rows());

  const FigureLimb arm = ArticulatedFigureTemplate::Limb(LeftArm);
  const Eigen::Matrix3d armRotation = Eigen::AngleAxisd(pose.LeftArm, arm.BendAxis).toRotationMatrix();
  std::size_t rigidArmVertices = 0;
  std::size_t unchangedTorsoVertices = 0;
  for (Eigen::Index v = 0; v < rest.Points.rows(); ++v)
  {
    const Eigen::Vector3d p = rest.Points.row(v).transpose();
    const Eigen::Vector3d q = bent.Points.row(v).transpose();
    const double armWeight = figure.SkinWeight(v, LeftArm);
    const double legWeight = figure.SkinWeight(v, RightLeg);
    if (armWeight == 0.0 && legWeight == 0.0)
    {
      ASSERT_TRUE(p == q) << "vertex " << v << " moved without skin weight"; // bit-identical
    }
    if (armWeight == 1.0)
    {
      ++rigidArmVertices;
      EXPECT_LT((q - (arm.Pivot + armRotation * (p - arm.Pivot))).norm(), 1e-12);
      EXPECT_GT((q - p).norm(), 0.1 * (p - arm.Pivot).norm()); // moved by the 45 degree bend
    }
    // Torso away from shoulders and hips, the head and the unbent limbs never move.
    if ((std::abs(p.y() - 0.3) > 0.25 && p.y() > -0.35) || p.x() < -0.3 || (p.x() > 0.05 && p.y() < -0.6))
    {
      ASSERT_TRUE(p == q) << "vertex " << v;
      ++unchangedTorsoVertices;
    }
  }
  EXPECT_GT(rigidArmVertices, 500u);
  EXPECT_GT(unchangedTorsoVertices, 2000u);
  // The top of the left arm's tip cap is at the rotated cap centre plus one radius.
  double highestArmPoint = -1e300;
  for (Eigen::Index v = 0; v < bent.Points.rows(); ++v)
  {
    if (figure.SkinWeight(v, LeftArm) == 1.0)
    {
      highestArmPoint = std::max(highestArmPoint, bent.Points(v, 1));
    }
  }
  EXPECT_NEAR(highestArmPoint, arm.Pivot.y() + std::sin(Pi / 4) * (arm.Length - arm.Radius) + arm.Radius, 0.01);

  // Still a closed outward surface of about the same volume, no collapsed triangle.
  EXPECT_NEAR(SignedVolume(bent), SignedVolume(rest), 0.03 * SignedVolume(rest));
  for (Eigen::Index t = 0; t < bent.Triangles.rows(); ++t)
  {
    ASSERT_GT(FaceNormal(bent, t).norm(), 1e-7) << "triangle " << t;
  }
}

TEST(ArticulatedFigure, EveryLimbBendsBothWays)
{
  const ArticulatedFigureTemplate& figure = SharedTemplate();
  const ArticulatedFigure& rest = figure.Rest();
  for (int limb = LeftArm; limb <= RightLeg; ++limb)
  {
    for (double angle : { -Pi / 3, Pi / 3 })
    {
      FigurePose pose;
      (limb == LeftArm ? pose.LeftArm : limb == RightArm ? pose.RightArm : limb == LeftLeg ? pose.LeftLeg : pose.RightLeg) =
        angle;
      const ArticulatedFigure bent = figure.Pose(pose);
      const FigureLimb geometry = ArticulatedFigureTemplate::Limb(static_cast<FigurePart>(limb));
      // The tip (the rigid limb vertex farthest along the rest axis) moved by the chord.
      Eigen::Index tip = -1;
      double farthest = -1e300;
      for (Eigen::Index v = 0; v < rest.Points.rows(); ++v)
      {
        if (figure.SkinWeight(v, static_cast<FigurePart>(limb)) != 1.0)
        {
          continue;
        }
        const double along = (rest.Points.row(v).transpose() - geometry.Pivot).dot(geometry.Direction);
        if (along > farthest)
        {
          farthest = along;
          tip = v;
        }
      }
      const double moved = (bent.Points.row(tip) - rest.Points.row(tip)).norm();
      EXPECT_NEAR(moved, 2.0 * farthest * std::sin(std::abs(angle) / 2.0), 0.02) << "limb " << limb;
      EXPECT_NEAR(SignedVolume(bent), SignedVolume(rest), 0.03 * SignedVolume(rest)) << "limb " << limb;
    }
  }
  // Positive angles: arms up, legs forward.
  FigurePose up;
  up.LeftArm = up.RightArm = up.LeftLeg = up.RightLeg = 0.5;
  const ArticulatedFigure posed = figure.Pose(up);
  double leftArmY = 0.0, rightArmY = 0.0, leftLegZ = 0.0, rightLegZ = 0.0;
  for (Eigen::Index v = 0; v < rest.Points.rows(); ++v)
  {
    leftArmY += figure.SkinWeight(v, LeftArm) * (posed.Points(v, 1) - rest.Points(v, 1));
    rightArmY += figure.SkinWeight(v, RightArm) * (posed.Points(v, 1) - rest.Points(v, 1));
    leftLegZ += figure.SkinWeight(v, LeftLeg) * (posed.Points(v, 2) - rest.Points(v, 2));
    rightLegZ += figure.SkinWeight(v, RightLeg) * (posed.Points(v, 2) - rest.Points(v, 2));
  }
  EXPECT_GT(leftArmY, 0.0);
  EXPECT_GT(rightArmY, 0.0);
  EXPECT_GT(leftLegZ, 0.0);
  EXPECT_GT(rightLegZ, 0.0);
}

TEST(ArticulatedFigure, DeterministicResolutionAndBadOptions)
{
  const ArticulatedFigure a = MakeArticulatedFigure(FigurePose{ 0.1, 0.2, 0.3, 0.4 });
  const ArticulatedFigure b = MakeArticulatedFigure(FigurePose{ 0.1, 0.2, 0.3, 0.4 });
  EXPECT_TRUE(a.Points == b.Points);
  EXPECT_TRUE(a.Triangles == b.Triangles);
  FigureOptions coarse;
  coarse.CellSize = 0.072;
  const ArticulatedFigure low = MakeArticulatedFigure({}, coarse);
  EXPECT_NEAR(static_cast<double>(low.Triangles.rows()), 0.25 * static_cast<double>(a.Triangles.rows()),
    0.1 * static_cast<double>(a.Triangles.rows()));
  FigureOptions bad;
  bad.CellSize = 0.0;
  EXPECT_THROW(ArticulatedFigureTemplate{ bad }, std::invalid_argument);
  bad.CellSize = 0.03;
  bad.RelaxationIterations = -1;
  EXPECT_THROW(ArticulatedFigureTemplate{ bad }, std::invalid_argument);
  EXPECT_THROW(ArticulatedFigureTemplate::Limb(Torso), std::invalid_argument);
}

TEST(ArticulatedFigure, NonRigidPoseBendsAndStretchesAcrossTheJoints)
{
  const ArticulatedFigureTemplate& figure = SharedTemplate();
  const ArticulatedFigure& rest = figure.Rest();
  const FigurePose pose{ 0.7, -0.5, 0.6, -0.3 };
  const NonRigidBend bend;
  const ArticulatedFigure bent = figure.NonRigidPose(pose, bend);
  ASSERT_EQ(bent.Points.rows(), rest.Points.rows());
  EXPECT_TRUE(bent.Triangles == rest.Triangles);
  EXPECT_EQ(bent.FaceParts, rest.FaceParts);
  EXPECT_EQ(BadEdgeCount(bent), 0u);
  EXPECT_EQ(FoldedEdgeCount(rest), 0u);
  EXPECT_EQ(FoldedEdgeCount(bent), 0u);
  for (Eigen::Index t = 0; t < bent.Triangles.rows(); ++t)
  {
    ASSERT_GT(FaceNormal(bent, t).norm(), 1e-7) << "triangle " << t;
  }

  // The torso between shoulders and hips and the head do not move; every limb is longer by
  // the stretch of its joint (Stretch x JointLength radii), measured at its tip.
  for (Eigen::Index v = 0; v < rest.Points.rows(); ++v)
  {
    const double y = rest.Points(v, 1);
    if ((y > -0.25 && y < 0.1) || y > 0.6)
    {
      ASSERT_TRUE(rest.Points.row(v) == bent.Points.row(v)) << "vertex " << v;
    }
  }
  const std::array<double, 4> angles = { pose.LeftArm, pose.RightArm, pose.LeftLeg, pose.RightLeg };
  for (int limb = LeftArm; limb <= RightLeg; ++limb)
  {
    const FigureLimb geometry = ArticulatedFigureTemplate::Limb(static_cast<FigurePart>(limb));
    // The tip: the vertex farthest along the limb among those near its axis (both legs end
    // at the same height).
    Eigen::Index tip = -1;
    double farthest = -1e300;
    for (Eigen::Index v = 0; v < rest.Points.rows(); ++v)
    {
      const Eigen::Vector3d relative = rest.Points.row(v).transpose() - geometry.Pivot;
      const double along = relative.dot(geometry.Direction);
      if ((relative - along * geometry.Direction).norm() < 1.5 * geometry.Radius && along > farthest)
      {
        farthest = along;
        tip = v;
      }
    }
    const Eigen::Vector3d restTip = rest.Points.row(tip).transpose() - geometry.Pivot;
    const Eigen::Vector3d bentTip = bent.Points.row(tip).transpose() - geometry.Pivot;
    EXPECT_NEAR(bentTip.norm() - restTip.norm(), bend.Stretch * bend.JointLength * geometry.Radius, 0.005)
      << "limb " << limb;
    const double turned = std::acos(std::clamp(restTip.normalized().dot(bentTip.normalized()), -1.0, 1.0));
    EXPECT_NEAR(turned, std::abs(angles[static_cast<std::size_t>(limb - LeftArm)]), 0.02) << "limb " << limb;
  }

  // Not a rigid motion of the limbs: many faces change area, some edges stretch by a quarter
  // and more, where the rigid Pose() at the same angles changes far fewer faces.
  double longestStretch = 0.0;
  for (Eigen::Index t = 0; t < rest.Triangles.rows(); ++t)
  {
    for (int c = 0; c < 3; ++c)
    {
      const Eigen::Index a = rest.Triangles(t, c);
      const Eigen::Index b = rest.Triangles(t, (c + 1) % 3);
      longestStretch = std::max(longestStretch, (bent.Points.row(a) - bent.Points.row(b)).norm() /
          (rest.Points.row(a) - rest.Points.row(b)).norm());
    }
  }
  const double nonRigidResized = ShareOfFacesResized(rest, bent, 0.1);
  const double rigidResized = ShareOfFacesResized(rest, figure.Pose(pose), 0.1);
  std::printf("non-rigid pose: longest edge stretch %.3f, faces resized by > 10 %%: %.1f %% (rigid pose %.1f %%), "
              "volume %.4f (rest %.4f)\n",
    longestStretch, 100.0 * nonRigidResized, 100.0 * rigidResized, SignedVolume(bent), SignedVolume(rest));
  EXPECT_GT(longestStretch, 1.25);
  EXPECT_GT(nonRigidResized, 0.05);
  EXPECT_GT(nonRigidResized, 2.0 * rigidResized);
  // Longer limbs hold more volume: a cylinder of one radius per limb, about 2.5 % more.
  EXPECT_GT(SignedVolume(bent), SignedVolume(rest));
  EXPECT_LT(SignedVolume(bent), 1.06 * SignedVolume(rest));
  EXPECT_THROW(figure.NonRigidPose(pose, NonRigidBend{ 0.0, 0.25 }), std::invalid_argument);
  EXPECT_THROW(figure.NonRigidPose(pose, NonRigidBend{ 4.0, 1.0 }), std::invalid_argument);
}

TEST(ArticulatedFigure, RotatedCoarserGridIsAnotherTessellationOfTheSameSurface)
{
  const ArticulatedFigure& rest = SharedTemplate().Rest();
  FigureOptions other;
  other.CellSize = 0.042;
  other.GridAngle = 0.6;
  const ArticulatedFigureTemplate copyTemplate(other);
  const ArticulatedFigure& copy = copyTemplate.Rest();
  std::size_t edges = 0;
  EXPECT_EQ(BadEdgeCount(copy, &edges), 0u);
  EXPECT_EQ(copy.Points.rows() - static_cast<Eigen::Index>(edges) + copy.Triangles.rows(), 2);
  EXPECT_EQ(ComponentCount(copy), 1u);
  EXPECT_NEAR(SignedVolume(copy), SignedVolume(rest), 0.01 * SignedVolume(rest));
  for (Eigen::Index v = 0; v < copy.Points.rows(); ++v)
  {
    ASSERT_LT(std::abs(ArticulatedFigureTemplate::SignedField(copy.Points.row(v).transpose())), 1e-9);
  }
  // Face count about (0.036 / 0.042)^2 of the reference's, and not its vertices: the typical
  // copy vertex lies a good fraction of an edge away from every reference vertex.
  EXPECT_NEAR(static_cast<double>(copy.Triangles.rows()), 0.735 * static_cast<double>(rest.Triangles.rows()),
    0.1 * static_cast<double>(rest.Triangles.rows()));
  std::vector<double> nearest;
  for (Eigen::Index v = 0; v < copy.Points.rows(); v += 7)
  {
    nearest.push_back((rest.Points.rowwise() - copy.Points.row(v)).rowwise().norm().minCoeff());
  }
  std::nth_element(nearest.begin(), nearest.begin() + static_cast<std::ptrdiff_t>(nearest.size() / 2), nearest.end());
  EXPECT_GT(nearest[nearest.size() / 2], 0.005);
  FigureOptions bad;
  bad.GridAngle = 4.0;
  EXPECT_THROW(ArticulatedFigureTemplate{ bad }, std::invalid_argument);
}
