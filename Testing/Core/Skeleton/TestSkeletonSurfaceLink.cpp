// SPDX-License-Identifier: BSD-3-Clause
// Tests of the skeleton's surface link with part labels (ComputeSkeleton's faceParts): every
// part takes one bone (its own where one holds OwnBoneShare of it, else the one holding most
// of its area under the nearest-node link); faces keep a node of their bone; the labels are
// taken per surface component; bad labels throw.
#include "Skeleton/Skeleton.h"
#include "TestShapes.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>
#include <utility>
#include <vector>

namespace
{

using namespace shapediameter;
using namespace shapediameter::testshapes;

SkeletonResult Link(const TestMesh& mesh, const std::vector<std::int64_t>& parts,
  const ParallelFor& parallelFor = SerialFor, const std::vector<std::int64_t>& components = {})
{
  return ComputeSkeleton(mesh.Points, mesh.Triangles, mesh.Sdf, PointMatrix(), components, {},
    parallelFor, {}, parts);
}

/// Part of each face of a tripod: the arm whose axis is nearest to the face centre, 3 for
/// faces within 1.5 radii of the centre (the hub), so that the hub part overlaps the three
/// arms' bones near the junction.
std::vector<std::int64_t> TripodParts(const TestMesh& tripod, const std::vector<Arm>& arms, double radius)
{
  std::vector<std::int64_t> parts(static_cast<std::size_t>(tripod.Faces()));
  for (Eigen::Index f = 0; f < tripod.Faces(); ++f)
  {
    const Eigen::Vector3d centre = (tripod.Points.row(tripod.Triangles(f, 0)) +
      tripod.Points.row(tripod.Triangles(f, 1)) + tripod.Points.row(tripod.Triangles(f, 2))).transpose() / 3.0;
    if (centre.norm() < 1.5 * radius)
    {
      parts[static_cast<std::size_t>(f)] = 3;
      continue;
    }
    std::int64_t best = 0;
    for (std::size_t a = 1; a < arms.size(); ++a)
    {
      if (centre.dot(arms[a].Direction) > centre.dot(arms[static_cast<std::size_t>(best)].Direction))
      {
        best = static_cast<std::int64_t>(a);
      }
    }
    parts[static_cast<std::size_t>(f)] = best;
  }
  return parts;
}

} // namespace

TEST(SkeletonSurfaceLink, EveryPartTakesOneBoneAndFacesKeepANodeOfIt)
{
  const double radius = 0.5;
  const std::vector<Arm> arms = TripodArms(3.0, radius);
  const TestMesh tripod = MakeTripod(3.0, radius, 96, 48);
  const std::vector<std::int64_t> parts = TripodParts(tripod, arms, radius);
  const SkeletonResult nearest = Link(tripod, {});
  const SkeletonResult byPart = Link(tripod, parts);

  // The skeleton is the same; only the link changes.
  ASSERT_EQ(nearest.NodePositions.rows(), byPart.NodePositions.rows());
  EXPECT_TRUE(nearest.NodePositions == byPart.NodePositions);
  EXPECT_EQ(nearest.BoneLength, byPart.BoneLength);
  ASSERT_GE(byPart.BoneLength.size(), 3u);

  std::map<std::int64_t, std::set<std::int64_t>> bonesOfPart;
  std::map<std::int64_t, std::set<std::int64_t>> nearestBonesOfPart;
  std::size_t moved = 0;
  for (std::size_t f = 0; f < parts.size(); ++f)
  {
    bonesOfPart[parts[f]].insert(byPart.FaceBoneId[f]);
    nearestBonesOfPart[parts[f]].insert(nearest.FaceBoneId[f]);
    ASSERT_EQ(byPart.NodeBoneId[byPart.FaceNodeId[f]], byPart.FaceBoneId[f]) << "face " << f;
    if (byPart.FaceBoneId[f] == nearest.FaceBoneId[f])
    {
      ASSERT_EQ(byPart.FaceNodeId[f], nearest.FaceNodeId[f]) << "a face whose bone stays keeps its node";
    }
    else
    {
      ++moved;
    }
  }
  EXPECT_GT(nearestBonesOfPart[3].size(), 1u) << "the hub straddles bones under the nearest-node link";
  EXPECT_GT(moved, 0u);
  for (const auto& [part, bones] : bonesOfPart)
  {
    EXPECT_EQ(bones.size(), 1u) << "part " << part;
  }
  // The three arms keep three different bones.
  EXPECT_EQ((std::set<std::int64_t>{ *bonesOfPart[0].begin(), *bonesOfPart[1].begin(),
              *bonesOfPart[2].begin() }.size()),
    3u);

  // Thread count does not change the link.
  const SkeletonResult threaded = Link(tripod, parts, ThreadedFor(2));
  EXPECT_EQ(threaded.FaceNodeId, byPart.FaceNodeId);
  EXPECT_EQ(threaded.FaceBoneId, byPart.FaceBoneId);
}

TEST(SkeletonSurfaceLink, OneLabelPerFaceIsTheNearestNodeLinkAndOneLabelIsTheLargestBone)
{
  const TestMesh tripod = MakeTripod(3.0, 0.5, 96, 48);
  const SkeletonResult nearest = Link(tripod, {});
  std::vector<std::int64_t> ownLabel(static_cast<std::size_t>(tripod.Faces()));
  for (std::size_t f = 0; f < ownLabel.size(); ++f)
  {
    ownLabel[f] = static_cast<std::int64_t>(1000 + 7 * f); // any integers
  }
  const SkeletonResult own = Link(tripod, ownLabel);
  EXPECT_EQ(own.FaceNodeId, nearest.FaceNodeId);
  EXPECT_EQ(own.FaceBoneId, nearest.FaceBoneId);

  const SkeletonResult whole = Link(tripod, std::vector<std::int64_t>(ownLabel.size(), -5));
  std::map<std::int64_t, double> area;
  for (Eigen::Index f = 0; f < tripod.Faces(); ++f)
  {
    const Eigen::Vector3d a = tripod.Points.row(tripod.Triangles(f, 0)).transpose();
    const Eigen::Vector3d b = tripod.Points.row(tripod.Triangles(f, 1)).transpose();
    const Eigen::Vector3d c = tripod.Points.row(tripod.Triangles(f, 2)).transpose();
    area[nearest.FaceBoneId[static_cast<std::size_t>(f)]] += 0.5 * (b - a).cross(c - a).norm();
  }
  std::int64_t largest = area.begin()->first;
  for (const auto& [bone, value] : area)
  {
    largest = value > area[largest] ? bone : largest;
  }
  for (const std::int64_t bone : whole.FaceBoneId)
  {
    ASSERT_EQ(bone, largest);
  }
}

TEST(SkeletonSurfaceLink, LabelsAreTakenPerComponentAndBadLabelsThrow)
{
  TestMesh first = MakeCapsule(1.0, 3.0, 32, 8, 24);
  TestMesh second = MakeCapsule(0.5, 2.0, 32, 8, 24);
  Place(second, { 1, 0, 0 }, { 0, 3.0, 0 });
  const TestMesh both = Concatenate(first, second);
  // One label for both capsules: each still links to its own skeleton.
  const SkeletonResult result = Link(both, std::vector<std::int64_t>(static_cast<std::size_t>(both.Faces()), 0));
  for (Eigen::Index f = 0; f < both.Faces(); ++f)
  {
    ASSERT_EQ(result.FaceBoneId[static_cast<std::size_t>(f)], f < first.Faces() ? 0 : 1);
  }
  EXPECT_THROW(Link(both, { 1, 2, 3 }), Error);
}

TEST(SkeletonSurfaceLink, APartTakesABoneOfItsOwnBeforeSharingOne)
{
  // An ear (label 10) lies on bone 0 alone; the head (20) holds 4 of its 5.5 area units on the
  // ear's bone 0 and 1.5 on bone 1; a torso (30) lies on bone 2. Faces of label 20 in a second
  // surface component form a part of their own (on bone 0 only).
  const std::vector<std::int64_t> parts{ 10, 20, 30, 10, 20, 20, 30, 10, 30, 30, 20 };
  const std::vector<std::int64_t> components{ 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1 };
  const std::vector<double> area{ 2, 2, 3, 2, 2, 1.5, 3, 2, 3, 3, 1 };
  const std::vector<std::int64_t> nearest{ 0, 0, 2, 0, 0, 1, 2, 0, 2, 2, 0 };
  using Part = std::pair<std::int64_t, std::int64_t>; // (component, label)
  const auto boneOf = [&](double share) {
    const std::vector<std::int64_t> bone = LinkPartsToBones(parts, components, area, nearest, share);
    std::map<Part, std::set<std::int64_t>> byPart;
    for (std::size_t f = 0; f < parts.size(); ++f)
    {
      byPart[{ components[f], parts[f] }].insert(bone[f]);
    }
    std::map<Part, std::int64_t> result;
    for (const auto& [part, bones] : byPart)
    {
      EXPECT_EQ(bones.size(), 1u) << "one bone per part";
      result[part] = *bones.begin();
    }
    return result;
  };
  // 0.15: the torso (12) and the ear (6) take their bones first; the head's largest overlap
  // (bone 0) is taken, and bone 1 holds 1.5 / 5.5 = 27 % of it: its own bone.
  auto bone = boneOf(0.15);
  EXPECT_EQ(bone[Part(0, 10)], 0);
  EXPECT_EQ(bone[Part(0, 20)], 1);
  EXPECT_EQ(bone[Part(0, 30)], 2);
  EXPECT_EQ(bone[Part(1, 20)], 0) << "bone 0 is taken: the other component's part shares it";
  // 0.3: bone 1 holds too little of the head, which shares the ear's bone (the rule of every
  // value above 0.5: each part the bone holding most of it).
  for (const double share : { 0.3, 0.6, 1.0 })
  {
    bone = boneOf(share);
    EXPECT_EQ(bone[Part(0, 10)], 0);
    EXPECT_EQ(bone[Part(0, 20)], 0) << share;
    EXPECT_EQ(bone[Part(0, 30)], 2);
  }

  // Which parts got a bone of their own (step 6 gives the others a branch), dense part
  // labels in order of first appearance: ear, head, torso, then the other component's head.
  std::vector<char> own;
  LinkPartsToBones(parts, components, area, nearest, 0.15, &own);
  EXPECT_EQ(own, (std::vector<char>{ 1, 1, 1, 0 }));
  LinkPartsToBones(parts, components, area, nearest, 0.3, &own);
  EXPECT_EQ(own, (std::vector<char>{ 1, 0, 1, 0 }));
}
