// SPDX-License-Identifier: BSD-3-Clause
// The shared test fixture: an articulated figure (torso, head, four capsule limbs) whose
// limbs bend about their joints while the mesh connectivity stays identical.
//
// Construction (one closed surface, not a union of overlapping components)
//   1. The rest pose is the zero set of an implicit field: capsule distance functions of
//      the six parts, joined with a polynomial smooth minimum (blend width 0.05), so limbs
//      grow out of the torso with small fillets and the head sits on a short neck.
//   2. Marching tetrahedra (six Kuhn tetrahedra per grid cell, a conforming split of the
//      grid) extracts a closed, watertight, 2-manifold, genus-0 triangle mesh; each
//      triangle is oriented combinatorially from the grid corners (outside = positive
//      field), so the orientation is consistent and outward by construction. The grid is
//      offset by a non-round fraction of a cell so no sample lands on the zero set.
//   3. A few iterations of Laplacian relaxation, each followed by a Newton projection back
//      onto the zero set, even out the triangles (the topology is untouched).
//   4. Poses move vertices only (linear blend skinning): every limb rotates rigidly about
//      its joint pivot; near the joint the weight blends smoothly into the torso over one
//      limb radius along the limb axis and between 1.4 and 1.9 limb radii across it.
//      The torso far from the joints and the head never move (bit-identical), the limb
//      beyond one radius from the pivot moves rigidly, and the connectivity, the face
//      order and the part labels are the same for every pose.
//   5. NonRigidPose() bends each limb over a long joint region instead: the rotation angle
//      grows smoothly along the limb axis (from one radius inside the torso to full over
//      NonRigidBend::JointLength radii) and the joint region lengthens by
//      NonRigidBend::Stretch, so triangles there shear, stretch on the outer side of the bend
//      and shorten on the inner side, as in a skinned character. Same connectivity as Rest().
//   Why: one connected surface is what real scans look like, so the partition, graph-cut
//   and skeleton tests see real part boundaries, and the SDF sees no hidden faces.
//
// Geometry (lengths; y up, the figure faces +z, its left side is +x), see FigureLimb:
//   torso   capsule y in [-0.35, 0.35], radius 0.25        (diameter 0.50)
//   head    sphere centre (0, 0.76, 0), radius 0.18         (diameter 0.36)
//   arms    capsules along +-x at y = 0.3, radius 0.07     (diameter 0.14), tips x = +-0.97
//   legs    capsules along -y at x = +-0.15, radius 0.1    (diameter 0.20), tips y = -1.4
// Angles (FigurePose, radians): positive raises an arm (rotation towards +y in the frontal
// plane) and swings a leg forwards (towards +z). Meant for |angle| <= pi / 3; larger
// angles are computed the same way but the skin near the joint may fold.
//
// Resolution: FigureOptions::CellSize (default 0.036) gives about 25k faces; the face count
// scales like 1 / CellSize^2. FigureOptions::GridAngle rotates the sampling grid, so a
// template with another CellSize and GridAngle is a different tessellation of the same
// surface (not a refinement of the same faces). Everything is deterministic.
#pragma once

#include "Mesh/MeshTypes.h"

#include <Eigen/Core>

#include <array>
#include <vector>

namespace shapediameter
{
namespace testing
{

enum FigurePart : int
{
  Torso = 0,
  Head = 1,
  LeftArm = 2,
  RightArm = 3,
  LeftLeg = 4,
  RightLeg = 5
};
constexpr int FigurePartCount = 6;

/// Bending angle of each limb about its joint, radians; 0 = rest pose (T-pose arms, legs down).
struct FigurePose
{
  double LeftArm = 0.0;
  double RightArm = 0.0;
  double LeftLeg = 0.0;
  double RightLeg = 0.0;
};

struct FigureOptions
{
  /// Edge of the marching-tetrahedra grid cell; (0.005, 0.1). 0.036 -> about 25k faces.
  double CellSize = 0.036;
  /// Relaxation + projection iterations; [0, 50].
  int RelaxationIterations = 8;
  /// Rotation of the sampling grid about the axis (1, 2, 3) / sqrt(14), radians; [-pi, pi].
  /// 0 = axis-aligned grid (the figure every other test uses).
  double GridAngle = 0.0;
};

/// How NonRigidPose() spreads a bend over the joint (lengths in limb radii).
struct NonRigidBend
{
  /// The bend angle grows from 0 at one radius inside the torso to the full angle over this
  /// length along the limb axis (a smoothstep); (0, 8]. The rigid Pose() blends over 2.
  double JointLength = 4.0;
  /// Extra length of the joint region as a fraction of JointLength, [0, 1): the local axial
  /// stretch peaks at 1 + 1.5 Stretch in the middle of the joint.
  double Stretch = 0.25;
};

/// A limb of the rest pose: the capsule axis runs from the pivot along Direction.
struct FigureLimb
{
  Eigen::Vector3d Pivot;
  /// Unit, pivot towards the tip, in the rest pose.
  Eigen::Vector3d Direction;
  /// Unit rotation axis; a positive pose angle rotates about it (right-hand rule).
  Eigen::Vector3d BendAxis;
  double Radius;
  /// From the pivot to the tip of the capsule (the end of its cap).
  double Length;
};

struct ArticulatedFigure
{
  PointMatrix Points;
  /// Counter-clockwise seen from outside.
  TriangleMatrix Triangles;
  /// FigurePart of every triangle (from the rest pose, so the same in every pose).
  std::vector<int> FaceParts;
};

/// Builds the rest-pose surface once; Pose() is cheap.
class ArticulatedFigureTemplate
{
public:
  explicit ArticulatedFigureTemplate(const FigureOptions& options = {});

  ArticulatedFigure Pose(const FigurePose& pose) const;
  /// Bends the limbs by `pose` smoothly over a long joint region with stretching (see the
  /// file comment, step 5): no part of a limb near the torso moves rigidly.
  ArticulatedFigure NonRigidPose(const FigurePose& pose, const NonRigidBend& bend = {}) const;

  const ArticulatedFigure& Rest() const { return RestFigure; }
  /// Skinning weight of vertex `point` for limb part `limb` (LeftArm .. RightLeg), in [0, 1].
  double SkinWeight(Eigen::Index point, FigurePart limb) const;

  /// The limb geometry for LeftArm, RightArm, LeftLeg or RightLeg.
  static FigureLimb Limb(FigurePart limb);
  /// Rest-pose implicit field, negative inside; its zero set is the rest surface.
  static double SignedField(const Eigen::Vector3d& point);
  /// Distance to the surface of one part's capsule, negative inside.
  static double PartDistance(const Eigen::Vector3d& point, FigurePart part);

private:
  ArticulatedFigure RestFigure;
  /// Row = vertex, column = limb (LeftArm - 2 .. RightLeg - 2), rows sum to <= 1.
  Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor> Weights;
};

/// One-shot helper: ArticulatedFigureTemplate(options).Pose(pose).
ArticulatedFigure MakeArticulatedFigure(const FigurePose& pose = {}, const FigureOptions& options = {});

} // namespace testing
} // namespace shapediameter
