// SPDX-License-Identifier: BSD-3-Clause
// Tests of the shape diameter function core: cone pattern, robust statistics, SDF on
// analytic shapes, invariances, threading, abort, degenerate input and FillFromNeighbors.
#include "ArticulatedFigure.h"
#include "RayCasting/BruteForceRayCaster.h"
#include "RayCasting/ConeSampling.h"
#include "RayCasting/EmbreeRayCaster.h"
#include "TestShapes.h"
#include "SDF/SDF.h"
#include "SDF/ShapeDiameter.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <vector>

namespace
{
using namespace shapediameter;
using testshapes::TestMesh;

constexpr double kPi = 3.14159265358979323846;
const double kInfinity = std::numeric_limits<double>::infinity();

double Median(std::vector<double> values)
{
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

double Mean(const std::vector<double>& values)
{
  return std::accumulate(values.begin(), values.end(), 0.0) / static_cast<double>(values.size());
}

double CoefficientOfVariation(const std::vector<double>& values)
{
  const double mean = Mean(values);
  double squares = 0;
  for (const double v : values)
  {
    squares += (v - mean) * (v - mean);
  }
  return std::sqrt(squares / static_cast<double>(values.size())) / mean;
}

/// Independent re-statement of the SDF statistics (ShapeDiameter.h, steps 3-4) for the
/// expected values: finite lengths, keep |L - median| <= population standard deviation
/// (about the mean), weighted mean.
double ExpectedRobustMean(const std::vector<double>& lengths, const std::vector<double>& weights)
{
  std::vector<double> finite;
  for (const double length : lengths)
  {
    if (std::isfinite(length))
    {
      finite.push_back(length);
    }
  }
  const double mean = Mean(finite);
  double squares = 0;
  for (const double length : finite)
  {
    squares += (length - mean) * (length - mean);
  }
  const double sigma = std::sqrt(squares / static_cast<double>(finite.size()));
  const double median = Median(finite);
  // sigma >= half the gap of the two middle values in exact arithmetic; the header makes this
  // hold under rounding too (two values: both kept).
  std::sort(finite.begin(), finite.end());
  const std::size_t n = finite.size();
  const double halfGap =
    n % 2 == 0 ? std::max(median - finite[n / 2 - 1], finite[n / 2] - median) : 0.0;
  const double threshold = std::max(sigma, halfGap);
  double weighted = 0, weightSum = 0;
  for (std::size_t i = 0; i < lengths.size(); ++i)
  {
    if (std::isfinite(lengths[i]) && std::abs(lengths[i] - median) <= threshold)
    {
      weighted += weights[i] * lengths[i];
      weightSum += weights[i];
    }
  }
  return weighted / weightSum;
}

/// Expected SDF on a sphere of radius r: a ray at angle theta from the inward normal has the
/// chord 2 r cos(theta) and lands where the surface normal makes 180 - 2 theta degrees with
/// the origin normal: FirstHitLeaving keeps every ray, SkipSameFacing (RayCaster.h) rejects
/// every ray with theta >= 45 degrees.
double ExpectedSphereSDF(double radius, const ConePattern& pattern, HitRule rule = ShapeDiameterOptions().Rule)
{
  std::vector<double> lengths;
  for (const double theta : pattern.AnglesToAxis)
  {
    // Every ray leaves the sphere at its first hit; SkipSameFacing also rejects that hit
    // (and the ray then finds nothing) when theta >= 45 degrees.
    const bool valid = rule == HitRule::FirstHitLeaving || std::cos(2 * theta) > 0;
    lengths.push_back(valid ? 2 * radius * std::cos(theta) : kInfinity);
  }
  return ExpectedRobustMean(lengths, pattern.Weights);
}

ShapeDiameterResult FaceSDF(const TestMesh& mesh,
  const ShapeDiameterOptions& options = ShapeDiameterOptions(),
  const ParallelFor& parallelFor = SerialFor)
{
  return ComputeFaceShapeDiameter(mesh.Points, mesh.Triangles, options, parallelFor);
}

bool AllFinite(const std::vector<double>& values)
{
  return std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); });
}

// ---------------------------------------------------------------------------------------
// Cone pattern

TEST(ConeSampling, DefaultPatternCoversTheConeEvenly)
{
  const ConePattern pattern = MakeConePattern(30, 120);
  ASSERT_EQ(pattern.GetNumberOfRays(), 30);
  const double halfAngle = kPi / 3;
  double meanX = 0, meanY = 0;
  for (int i = 0; i < 30; ++i)
  {
    const double* d = pattern.LocalDirections.data() + 3 * i;
    EXPECT_NEAR(d[0] * d[0] + d[1] * d[1] + d[2] * d[2], 1.0, 1e-14);
    const double theta = pattern.AnglesToAxis[static_cast<std::size_t>(i)];
    EXPECT_NEAR(std::acos(d[2]), theta, 1e-12);
    EXPECT_GT(theta, 0.0);
    EXPECT_LT(theta, halfAngle);
    EXPECT_DOUBLE_EQ(pattern.Weights[static_cast<std::size_t>(i)], 1.0 / theta);
    // Uniform in solid angle: the i-th ray is at the middle of the i-th equal-area annulus.
    EXPECT_NEAR(1 - std::cos(theta), (1 - std::cos(halfAngle)) * (i + 0.5) / 30, 1e-14);
    meanX += d[0] / 30;
    meanY += d[1] / 30;
  }
  // The golden-angle spiral is balanced around the axis.
  EXPECT_LT(std::hypot(meanX, meanY), 0.03);
  EXPECT_NEAR(pattern.AnglesToAxis.front() * 180 / kPi, 7.40, 0.01);
  EXPECT_NEAR(pattern.AnglesToAxis.back() * 180 / kPi, 59.45, 0.01);
  EXPECT_LT(pattern.AxisAngleFloor, pattern.AnglesToAxis.front());
}

TEST(ConeSampling, SingleRayIsTheAxisWithAFiniteWeight)
{
  const ConePattern pattern = MakeConePattern(1, 120);
  ASSERT_EQ(pattern.GetNumberOfRays(), 1);
  EXPECT_EQ(pattern.LocalDirections[2], 1.0);
  EXPECT_EQ(pattern.AnglesToAxis[0], 0.0);
  // Floor = half the angular radius of the whole cap (solid angle / 1 ray) = 30 degrees.
  EXPECT_NEAR(pattern.AxisAngleFloor, 0.5 * kPi / 3, 1e-12);
  EXPECT_NEAR(pattern.Weights[0], 1.0 / (kPi / 6), 1e-12);
}

TEST(ConeSampling, RejectsBadParameters)
{
  EXPECT_THROW(MakeConePattern(0, 120), Error);
  EXPECT_THROW(MakeConePattern(kMaxConeRays + 1, 120), Error);
  EXPECT_THROW(MakeConePattern(30, 0), Error);
  EXPECT_THROW(MakeConePattern(30, 180), Error);
  EXPECT_THROW(MakeConePattern(30, std::numeric_limits<double>::quiet_NaN()), Error);
  EXPECT_NO_THROW(MakeConePattern(kMaxConeRays, 179.9));
}

TEST(ConeSampling, FramesAreRightHandedAndFollowTheEdge)
{
  const Eigen::Vector3d axis = Eigen::Vector3d(0.2, -0.5, 0.8).normalized();
  const Eigen::Vector3d edge(1, 2, 3);
  double x[3], y[3];
  MakeConeFrame(axis.data(), edge.data(), x, y);
  const Eigen::Map<const Eigen::Vector3d> X(x), Y(y);
  EXPECT_NEAR(X.norm(), 1, 1e-14);
  EXPECT_NEAR(Y.norm(), 1, 1e-14);
  EXPECT_NEAR(X.dot(axis), 0, 1e-14);
  EXPECT_NEAR(X.cross(Y).dot(axis), 1, 1e-14);
  const Eigen::Vector3d projected = (edge - edge.dot(axis) * axis).normalized();
  EXPECT_NEAR((X - projected).norm(), 0, 1e-14);

  // Edge along the axis, no edge, and axes at the poles: Duff et al. frame.
  for (const Eigen::Vector3d& a :
    { axis, Eigen::Vector3d(0, 0, 1), Eigen::Vector3d(0, 0, -1), Eigen::Vector3d(1, 0, 0) })
  {
    for (const double* preferred : { static_cast<const double*>(nullptr), a.data() })
    {
      MakeConeFrame(a.data(), preferred, x, y);
      EXPECT_NEAR(X.norm(), 1, 1e-14);
      EXPECT_NEAR(X.dot(a), 0, 1e-14);
      EXPECT_NEAR(X.cross(Y).dot(a), 1, 1e-14);
      EXPECT_TRUE(X.allFinite() && Y.allFinite());
    }
  }
}

// ---------------------------------------------------------------------------------------
// Robust statistics

TEST(RobustWeightedMean, HandComputedCases)
{
  int kept = -1;
  // mean 26.5, sigma 42.4, median 2.5: 100 is dropped.
  EXPECT_DOUBLE_EQ(RobustWeightedMean({ 1, 2, 3, 100 }, { 1, 1, 1, 1 }, kept), 2.0);
  EXPECT_EQ(kept, 3);
  // mean 2.8, sigma 3.6, median 1: 10 is dropped.
  EXPECT_DOUBLE_EQ(RobustWeightedMean({ 1, 1, 10, 1, 1 }, { 1, 2, 3, 4, 5 }, kept), 1.0);
  EXPECT_EQ(kept, 4);
  // Two values: sigma equals half their gap, both are kept; weights apply.
  EXPECT_DOUBLE_EQ(RobustWeightedMean({ 1, 3 }, { 3, 1 }, kept), 1.5);
  EXPECT_EQ(kept, 2);
  // Rays without a hit are dropped before the statistics.
  EXPECT_DOUBLE_EQ(RobustWeightedMean({ kInfinity, 5, kInfinity }, { 1, 1, 1 }, kept), 5.0);
  EXPECT_EQ(kept, 1);
  EXPECT_EQ(RobustWeightedMean({ kInfinity, kInfinity }, { 1, 1 }, kept), 0.0);
  EXPECT_EQ(kept, 0);
  EXPECT_EQ(RobustWeightedMean({}, {}, kept), 0.0);
  EXPECT_EQ(kept, 0);
  EXPECT_THROW(RobustWeightedMean({ 1 }, {}, kept), Error);
}

TEST(RobustWeightedMean, MatchesTheIndependentStatement)
{
  // Pseudo-random lengths (fixed LCG) including misses.
  std::uint64_t state = 12345;
  auto next = [&state] {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state >> 11) / 9007199254740992.0;
  };
  const ConePattern pattern = MakeConePattern(30, 120);
  for (int trial = 0; trial < 200; ++trial)
  {
    std::vector<double> lengths(30);
    for (double& length : lengths)
    {
      const double u = next();
      length = u < 0.1 ? kInfinity : 1 + 3 * next() * next();
    }
    int kept = 0;
    const double value = RobustWeightedMean(lengths, pattern.Weights, kept);
    EXPECT_NEAR(value, ExpectedRobustMean(lengths, pattern.Weights), 1e-12);
    EXPECT_GT(kept, 0);
  }
}

// ---------------------------------------------------------------------------------------
// SDF on analytic shapes

TEST(ShapeDiameter, SphereMatchesTheAnalyticValue)
{
  const double radius = 2.0;
  const TestMesh mesh = testshapes::MakeIcosphere(32, radius); // 20480 faces
  const ShapeDiameterResult result = FaceSDF(mesh);
  ASSERT_EQ(result.Values.size(), 20480u);
  EXPECT_FALSE(result.Aborted);
  // FirstHitLeaving (the default) keeps every ray (7-60 degrees off the normal): about 0.77 of
  // the diameter; SkipSameFacing only the rays 7-45 degrees off: 0.86.
  const double expected = ExpectedSphereSDF(radius, MakeConePattern(30, 120));
  EXPECT_NEAR(expected / (2 * radius), 0.77, 0.02);
  const double expectedSkipping = ExpectedSphereSDF(radius, MakeConePattern(30, 120), HitRule::SkipSameFacing);
  EXPECT_NEAR(expectedSkipping / (2 * radius), 0.86, 0.02);
  ShapeDiameterOptions skipping;
  skipping.Rule = HitRule::SkipSameFacing;
  const ShapeDiameterResult skippingResult = FaceSDF(mesh, skipping);
  EXPECT_NEAR(Mean(skippingResult.Values), expectedSkipping, 0.03 * expectedSkipping);
  EXPECT_TRUE(std::all_of(
    skippingResult.ValidRays.begin(), skippingResult.ValidRays.end(), [](int rays) { return rays >= 5; }));
  EXPECT_NEAR(Mean(result.Values), expected, 0.03 * expected);
  EXPECT_LT(CoefficientOfVariation(result.Values), 0.01);
  EXPECT_TRUE(std::all_of(
    result.ValidRays.begin(), result.ValidRays.end(), [](int rays) { return rays >= 5; }));
}

TEST(ShapeDiameter, OtherRayCountsAndConeAngles)
{
  const double radius = 1.0;
  const TestMesh mesh = testshapes::MakeIcosphere(16, radius);
  for (const auto& [rays, angle] : { std::make_pair(100, 60.0), std::make_pair(1, 120.0),
         std::make_pair(6, 170.0) })
  {
    ShapeDiameterOptions options;
    options.NumberOfRays = rays;
    options.ConeAngle = angle;
    const ShapeDiameterResult result = FaceSDF(mesh, options);
    const double expected = ExpectedSphereSDF(radius, MakeConePattern(rays, angle));
    EXPECT_NEAR(Mean(result.Values), expected, 0.03 * expected) << rays << " rays, " << angle;
    EXPECT_TRUE(AllFinite(result.Values));
  }
}

TEST(ShapeDiameter, SlabMatchesTheAnalyticValueExactly)
{
  // Thickness 1, so wide that every ray from the middle of the top lands on the bottom
  // plane, whose normal is opposite: every ray is valid with length 1 / cos(theta).
  const TestMesh mesh = testshapes::MakeBox(Eigen::Vector3d(10, 10, 1), 10);
  const ShapeDiameterResult result = FaceSDF(mesh);
  const RayOrigins origins = MakeFaceOrigins(mesh.Points, mesh.Triangles);
  const ConePattern pattern = MakeConePattern(30, 120);
  std::vector<double> lengths;
  for (const double theta : pattern.AnglesToAxis)
  {
    lengths.push_back(1 / std::cos(theta));
  }
  const double expected = ExpectedRobustMean(lengths, pattern.Weights);
  int checked = 0;
  for (Eigen::Index f = 0; f < origins.Points.rows(); ++f)
  {
    const Eigen::RowVector3d p = origins.Points.row(f);
    if (std::abs(p.z() - 1) < 1e-12 && (p.head<2>().array() - 5).abs().maxCoeff() < 2.5)
    {
      EXPECT_NEAR(result.Values[static_cast<std::size_t>(f)], expected, 1e-12);
      ++checked;
    }
  }
  EXPECT_GT(checked, 2 * 4 * 4);
}

TEST(ShapeDiameter, VertexOriginsOnASphere)
{
  const double radius = 1.5;
  const TestMesh mesh = testshapes::MakeIcosphere(24, radius);
  PointMatrix normals = mesh.Points / radius;
  const RayOrigins origins = MakeVertexOrigins(mesh.Points, normals);
  EXPECT_TRUE(origins.SourceTriangles.empty());
  const EmbreeRayCaster caster(mesh.Points, mesh.Triangles);
  const ShapeDiameterResult result =
    ComputeShapeDiameter(caster, origins, ShapeDiameterOptions(), SerialFor);
  const double expected = ExpectedSphereSDF(radius, MakeConePattern(30, 120));
  EXPECT_NEAR(Mean(result.Values), expected, 0.03 * expected);
  EXPECT_LT(CoefficientOfVariation(result.Values), 0.01);
  EXPECT_TRUE(std::all_of(
    result.ValidRays.begin(), result.ValidRays.end(), [](int rays) { return rays > 0; }));
}

TEST(ShapeDiameter, ScalesWithTheMesh)
{
  const TestMesh mesh = testshapes::MakeCapsule(0.5, 1.5, 32, 8, 12);
  TestMesh scaled = mesh;
  scaled.Points *= 4;
  const ShapeDiameterResult a = FaceSDF(mesh);
  const ShapeDiameterResult b = FaceSDF(scaled);
  EXPECT_NEAR(Median(b.Values) / Median(a.Values), 4.0, 4e-5);
  for (std::size_t f = 0; f < a.Values.size(); ++f)
  {
    ASSERT_NEAR(b.Values[f], 4 * a.Values[f], 1e-9 * b.Values[f]);
    ASSERT_EQ(a.ValidRays[f], b.ValidRays[f]);
  }
}

TEST(ShapeDiameter, InvariantToRigidMotion)
{
  const TestMesh mesh = testshapes::MakeCapsule(0.5, 1.5, 32, 8, 12);
  const Eigen::Matrix3d rotation =
    Eigen::AngleAxisd(1.1, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  const TestMesh moved =
    testshapes::Transformed(mesh, rotation, Eigen::Vector3d(3.5, -20.25, 7.0));
  const ShapeDiameterResult a = FaceSDF(mesh);
  const ShapeDiameterResult b = FaceSDF(moved);
  std::vector<double> relativeDifferences;
  for (std::size_t f = 0; f < a.Values.size(); ++f)
  {
    relativeDifferences.push_back(std::abs(b.Values[f] - a.Values[f]) / a.Values[f]);
  }
  EXPECT_LT(Median(relativeDifferences), 0.005);
  // The rays move with the faces, so the values agree far better than the requirement.
  EXPECT_LT(*std::max_element(relativeDifferences.begin(), relativeDifferences.end()), 1e-6);
}

TEST(ShapeDiameter, OpenSphereStaysFiniteAndUnchangedAwayFromTheHole)
{
  const TestMesh sphere = testshapes::MakeIcosphere(32, 1.0);
  const RayOrigins sphereOrigins = MakeFaceOrigins(sphere.Points, sphere.Triangles);
  const ShapeDiameterResult closed = FaceSDF(sphere);
  for (const double holeZ : { 0.9, 0.95 })
  {
    std::vector<Eigen::Index> kept;
    const TestMesh open = testshapes::KeepTriangles(sphere, [&](Eigen::Index t) {
      if (sphereOrigins.Points(t, 2) > holeZ)
      {
        return false;
      }
      kept.push_back(t);
      return true;
    });
    const ShapeDiameterResult result = FaceSDF(open);
    EXPECT_TRUE(AllFinite(result.Values));
    const double holeDegrees = std::acos(holeZ) * 180 / kPi;
    int nearHole = 0, farFromHole = 0;
    for (std::size_t i = 0; i < kept.size(); ++i)
    {
      const Eigen::Index f = kept[i];
      EXPECT_GT(result.ValidRays[i], 0);
      const double closedValue = closed.Values[static_cast<std::size_t>(f)];
      const double relative = std::abs(result.Values[i] - closedValue) / closedValue;
      const double polarDegrees =
        std::acos(sphereOrigins.Points(f, 2) / sphereOrigins.Points.row(f).norm()) * 180 / kPi;
      // Valid rays are at most 60 degrees off the normal (FirstHitLeaving), so they land within
      // 120 degrees of the antipode: faces with polar angle < 60 - hole - margin cannot see
      // the hole at all.
      if (polarDegrees > holeDegrees + 3 && polarDegrees < 60 - holeDegrees - 3)
      {
        EXPECT_LT(relative, 1e-9);
        ++nearHole;
      }
      // Faces on the far side look into the hole: some rays escape and are dropped.
      if (holeZ == 0.95 && polarDegrees > 90)
      {
        EXPECT_LT(relative, 0.05);
        ++farFromHole;
      }
    }
    EXPECT_GT(nearHole, 100); // about 210 faces for the larger hole
    EXPECT_TRUE(holeZ != 0.95 || farFromHole > 5000);
  }
}

TEST(ShapeDiameter, InvertedSphereHasNoValidRayAndGetsTheFallback)
{
  // Flipped triangles: the cone points outward, no ray hits anything, the whole mesh is
  // invalid; FillFromNeighbors finds no valid value anywhere and writes 0 everywhere. (The
  // VTK adapter orients meshes first; the core does not.)
  const TestMesh mesh = testshapes::Flipped(testshapes::MakeIcosphere(8, 1.0));
  ShapeDiameterResult result = FaceSDF(mesh);
  EXPECT_TRUE(std::all_of(
    result.ValidRays.begin(), result.ValidRays.end(), [](int rays) { return rays == 0; }));
  EXPECT_TRUE(AllFinite(result.Values));
  std::vector<std::int64_t> offsets, indices;
  testshapes::EdgeAdjacency(mesh.Triangles, offsets, indices);
  const FillFromNeighborsSummary summary =
    FillFromNeighbors(result.Values, result.ValidRays, offsets, indices);
  EXPECT_EQ(summary.FilledWithFallback, result.Values.size());
  EXPECT_EQ(summary.FallbackValue, 0.0);
  EXPECT_TRUE(std::all_of(
    result.Values.begin(), result.Values.end(), [](double v) { return v == 0.0; }));
}

TEST(ShapeDiameter, TwoDisjointSpheresEachGetTheirOwnDiameter)
{
  const TestMesh small = testshapes::MakeIcosphere(20, 1.0);
  const TestMesh large = testshapes::MakeIcosphere(20, 2.0, Eigen::Vector3d(10, 1, -2));
  const TestMesh both = testshapes::Concatenate(small, large);
  const ShapeDiameterResult result = FaceSDF(both);
  const ConePattern pattern = MakeConePattern(30, 120);
  const auto smallFaces = static_cast<std::size_t>(small.Triangles.rows());
  const std::vector<double> smallValues(result.Values.begin(), result.Values.begin() + smallFaces);
  const std::vector<double> largeValues(result.Values.begin() + smallFaces, result.Values.end());
  // Rays more than 45 degrees off the normal leave their own sphere through a rejected
  // ("same direction") wall, may reach the far wall of the other sphere, which is valid, and
  // then widen the median +- sigma window. That cross-talk is part of the paper's definition:
  // it moves some faces by up to ~4%, the bulk not at all.
  for (const auto& [values, radius] :
    { std::make_pair(smallValues, 1.0), std::make_pair(largeValues, 2.0) })
  {
    const double expected = ExpectedSphereSDF(radius, pattern);
    EXPECT_NEAR(Mean(values), expected, 0.03 * expected) << radius;
    const auto close = std::count_if(values.begin(), values.end(),
      [&](double v) { return std::abs(v - expected) < 0.015 * expected; });
    EXPECT_GT(close, static_cast<long>(values.size() * 8 / 10)) << radius;
    for (const double v : values)
    {
      ASSERT_NEAR(v, expected, 0.06 * expected) << radius;
    }
  }
}

TEST(ShapeDiameter, FacesBuriedInAnotherPartAreLeftForFilling)
{
  // Two unit spheres interpenetrating like a paw pushed into a torso: the faces of each that
  // lie inside the other measure the distance to the other's surface, not their own sphere.
  const Eigen::Vector3d otherCentre(1.2, 0, 0);
  const TestMesh sphere = testshapes::MakeIcosphere(20, 1.0);
  const TestMesh both = testshapes::Concatenate(sphere, testshapes::MakeIcosphere(20, 1.0, otherCentre));
  const auto faces = static_cast<std::size_t>(sphere.Triangles.rows());
  const double expected = ExpectedSphereSDF(1.0, MakeConePattern(30, 120));
  ShapeDiameterOptions paper;
  paper.IgnoreBuriedFaces = false;
  const ShapeDiameterResult own = FaceSDF(both, paper);
  const ShapeDiameterResult result = FaceSDF(both);
  std::vector<double> buriedOwn;
  std::size_t clearlyInside = 0, clearlyOutside = 0;
  for (std::size_t f = 0; f < faces; ++f)
  {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (int corner = 0; corner < 3; ++corner)
    {
      centre += sphere.Points.row(sphere.Triangles(static_cast<Eigen::Index>(f), corner)).transpose() / 3.0;
    }
    const double depth = 1.0 - (centre - otherCentre).norm(); // > 0: inside the other sphere
    if (depth > 0.02)
    {
      ++clearlyInside;
      buriedOwn.push_back(own.Values[f]);
      EXPECT_EQ(result.ValidRays[f], 0) << f;
      EXPECT_EQ(result.Values[f], 0.0) << f;
    }
    else if (depth < -0.02)
    {
      ++clearlyOutside;
      EXPECT_GT(result.ValidRays[f], 0) << f;
      EXPECT_EQ(result.Values[f], own.Values[f]) << "an unburied face keeps its value exactly";
    }
  }
  std::size_t newlyInvalid = 0, invalid = 0;
  for (std::size_t f = 0; f < result.ValidRays.size(); ++f)
  {
    newlyInvalid += result.ValidRays[f] == 0 && own.ValidRays[f] > 0 ? 1 : 0;
    invalid += result.ValidRays[f] == 0 ? 1 : 0;
  }
  ASSERT_GT(clearlyInside, faces / 20);
  ASSERT_GT(clearlyOutside, faces / 2);
  EXPECT_LT(Mean(buriedOwn), 0.5 * expected) << "the paper's value collapses on buried faces";
  EXPECT_GE(result.BuriedCount, newlyInvalid);
  EXPECT_LE(result.BuriedCount, invalid);
  EXPECT_GT(result.BuriedCount, clearlyInside) << "both spheres have a buried cap";
  EXPECT_EQ(own.BuriedCount, 0u);

  // Filled from the unburied neighbours, the buried cap gets about its own sphere's value.
  std::vector<double> values = result.Values;
  std::vector<std::int64_t> offsets, indices;
  testshapes::EdgeAdjacency(both.Triangles, offsets, indices);
  FillFromNeighbors(values, result.ValidRays, offsets, indices);
  std::vector<double> filled;
  for (std::size_t f = 0; f < faces; ++f)
  {
    if (result.ValidRays[f] == 0)
    {
      filled.push_back(values[f]);
    }
  }
  EXPECT_NEAR(Mean(filled), expected, 0.15 * expected);

  // A mesh without self-intersections has no buried face: the option changes nothing.
  const ShapeDiameterResult alone = FaceSDF(sphere);
  EXPECT_EQ(alone.BuriedCount, 0u);
  EXPECT_EQ(alone.Values, FaceSDF(sphere, paper).Values);
}

TEST(ShapeDiameter, AnArmPushedIntoTheTorsoKeepsItsDiameter)
{
  // The pose-consistency case of the rule above on a posed character: the test figure's left
  // arm lowered past its side (126 degrees) sinks into the torso, as skinned characters' limbs
  // do, and the sunken faces' own rays would measure the torso's surface instead of the arm.
  const shapediameter::testing::ArticulatedFigureTemplate figure;
  shapediameter::testing::FigurePose lowered;
  lowered.LeftArm = -2.2;
  const shapediameter::testing::ArticulatedFigure rest = figure.Rest();
  const shapediameter::testing::ArticulatedFigure pushed = figure.Pose(lowered);
  const auto filledSDF = [](const shapediameter::testing::ArticulatedFigure& mesh, bool ignoreBuried) {
    ShapeDiameterOptions options;
    options.IgnoreBuriedFaces = ignoreBuried;
    ShapeDiameterResult result = ComputeFaceShapeDiameter(mesh.Points, mesh.Triangles, options, SerialFor);
    std::vector<std::int64_t> offsets, indices;
    testshapes::EdgeAdjacency(mesh.Triangles, offsets, indices);
    FillFromNeighbors(result.Values, result.ValidRays, offsets, indices);
    return result.Values;
  };
  const std::vector<double> restValues = filledSDF(rest, true);
  EXPECT_EQ(restValues, filledSDF(rest, false)) << "the rest pose has no buried face";
  std::size_t collapsedWith[2] = { 0, 0 };
  for (const bool ignoreBuried : { false, true })
  {
    const std::vector<double> values = filledSDF(pushed, ignoreBuried);
    std::size_t arm = 0, collapsed = 0;
    for (std::size_t f = 0; f < values.size(); ++f)
    {
      if (rest.FaceParts[f] == shapediameter::testing::LeftArm)
      {
        ++arm;
        collapsed += values[f] < 0.5 * restValues[f] ? 1 : 0;
      }
    }
    std::printf("IgnoreBuriedFaces %d: %zu of %zu arm faces below half their rest SDF\n",
      static_cast<int>(ignoreBuried), collapsed, arm);
    collapsedWith[ignoreBuried ? 1 : 0] = collapsed;
  }
  // Measured: 39 faces without the rule, 6 with it (of 2082).
  EXPECT_GE(collapsedWith[0], 25u) << "the paper's value collapses where the arm is sunk";
  EXPECT_LE(collapsedWith[1], 12u);
}

TEST(ShapeDiameter, ThreadSplitsGiveBitIdenticalResults)
{
  const TestMesh mesh = testshapes::MakeCapsule(0.4, 1.0, 40, 10, 20); // 3120 faces
  const EmbreeRayCaster caster(mesh.Points, mesh.Triangles);
  const RayOrigins origins = MakeFaceOrigins(mesh.Points, mesh.Triangles);
  ShapeDiameterOptions options;
  const ShapeDiameterResult serial = ComputeShapeDiameter(caster, origins, options, SerialFor);
  for (const unsigned threads : { 2u, 3u })
  {
    for (const std::size_t chunk : { std::size_t(256), std::size_t(7), std::size_t(100000),
           std::numeric_limits<std::size_t>::max() })
    {
      options.OriginsPerChunk = chunk;
      const ShapeDiameterResult threaded =
        ComputeShapeDiameter(caster, origins, options, ThreadedFor(threads));
      EXPECT_EQ(threaded.Values, serial.Values) << threads << " threads, chunk " << chunk;
      EXPECT_EQ(threaded.ValidRays, serial.ValidRays);
      EXPECT_FALSE(threaded.Aborted);
    }
  }
}

TEST(ShapeDiameter, ProgressIsMonotoneAndAbortStopsEarly)
{
  const TestMesh mesh = testshapes::MakeIcosphere(16, 1.0); // 5120 faces, 20 chunks
  const EmbreeRayCaster caster(mesh.Points, mesh.Triangles);
  const RayOrigins origins = MakeFaceOrigins(mesh.Points, mesh.Triangles);
  for (const unsigned threads : { 1u, 2u })
  {
    std::vector<double> fractions;
    const ShapeDiameterResult complete = ComputeShapeDiameter(caster, origins,
      ShapeDiameterOptions(), ThreadedFor(threads), [&](double fraction) {
        fractions.push_back(fraction);
        return true;
      });
    EXPECT_FALSE(complete.Aborted);
    ASSERT_EQ(fractions.size(), 20u);
    EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));
    EXPECT_EQ(fractions.back(), 1.0);

    int calls = 0;
    const ShapeDiameterResult aborted = ComputeShapeDiameter(caster, origins,
      ShapeDiameterOptions(), ThreadedFor(threads), [&](double) { return ++calls < 3; });
    EXPECT_TRUE(aborted.Aborted);
    EXPECT_TRUE(AllFinite(aborted.Values));
    const auto processed = std::count_if(
      aborted.ValidRays.begin(), aborted.ValidRays.end(), [](int rays) { return rays > 0; });
    EXPECT_GE(processed, 3 * 256);
    EXPECT_LE(processed, static_cast<long>(3 + threads) * 256);
  }
}

TEST(ShapeDiameter, DegenerateFacesAndSkippedOriginsAreLeftForFilling)
{
  TestMesh mesh = testshapes::MakeIcosphere(8, 1.0);
  // Collapse triangle 5 (zero area) and poison the normal of another origin.
  mesh.Triangles(5, 2) = mesh.Triangles(5, 0);
  RayOrigins origins = MakeFaceOrigins(mesh.Points, mesh.Triangles);
  EXPECT_EQ(origins.Skip[5], 1);
  EXPECT_EQ(std::count(origins.Skip.begin(), origins.Skip.end(), 1), 1);
  origins.Normals(9, 1) = std::numeric_limits<double>::quiet_NaN();
  origins.Skip[11] = 1;
  const EmbreeRayCaster caster(mesh.Points, mesh.Triangles);
  ShapeDiameterResult result = ComputeShapeDiameter(caster, origins, {}, SerialFor);
  for (const std::size_t f : { 5u, 9u, 11u })
  {
    EXPECT_EQ(result.ValidRays[f], 0);
    EXPECT_EQ(result.Values[f], 0.0);
  }
  EXPECT_GT(result.ValidRays[10], 0);
  std::vector<std::int64_t> offsets, indices;
  testshapes::EdgeAdjacency(mesh.Triangles, offsets, indices);
  FillFromNeighbors(result.Values, result.ValidRays, offsets, indices);
  EXPECT_TRUE(AllFinite(result.Values));
  const double expected = ExpectedSphereSDF(1.0, MakeConePattern(30, 120));
  for (const std::size_t f : { 5u, 9u, 11u })
  {
    EXPECT_NEAR(result.Values[f], expected, 0.05 * expected);
  }
}

TEST(ShapeDiameter, BruteForceCasterGivesTheSameSDF)
{
  const TestMesh mesh = testshapes::MakeCapsule(0.5, 1.0, 16, 6, 4);
  const RayOrigins origins = MakeFaceOrigins(mesh.Points, mesh.Triangles);
  const ShapeDiameterResult embree = ComputeShapeDiameter(
    EmbreeRayCaster(mesh.Points, mesh.Triangles), origins, ShapeDiameterOptions(), SerialFor);
  const ShapeDiameterResult bruteForce = ComputeShapeDiameter(
    BruteForceRayCaster(mesh.Points, mesh.Triangles), origins, ShapeDiameterOptions(), SerialFor);
  EXPECT_EQ(embree.ValidRays, bruteForce.ValidRays);
  for (std::size_t f = 0; f < embree.Values.size(); ++f)
  {
    EXPECT_NEAR(embree.Values[f], bruteForce.Values[f], 1e-9 * bruteForce.Values[f]);
  }
}

TEST(ShapeDiameter, EmptyMeshesAndBadOptions)
{
  TestMesh empty;
  empty.Points.resize(0, 3);
  empty.Triangles.resize(0, 3);
  const ShapeDiameterResult result = FaceSDF(empty);
  EXPECT_TRUE(result.Values.empty());
  EXPECT_TRUE(result.ValidRays.empty());
  EXPECT_FALSE(result.Aborted);

  // A single triangle: the only possible hit is itself, so nothing is valid.
  TestMesh single;
  single.Points.resize(3, 3);
  single.Points << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  single.Triangles.resize(1, 3);
  single.Triangles << 0, 1, 2;
  const ShapeDiameterResult one = FaceSDF(single);
  ASSERT_EQ(one.Values.size(), 1u);
  EXPECT_EQ(one.ValidRays[0], 0);
  EXPECT_EQ(one.Values[0], 0.0);

  const TestMesh mesh = testshapes::MakeIcosphere(2);
  auto withOptions = [&](auto change) {
    ShapeDiameterOptions options;
    change(options);
    return FaceSDF(mesh, options);
  };
  EXPECT_THROW(withOptions([](ShapeDiameterOptions& o) { o.NumberOfRays = 0; }), Error);
  EXPECT_THROW(withOptions([](ShapeDiameterOptions& o) { o.ConeAngle = 180; }),
    Error);
  EXPECT_THROW(withOptions([](ShapeDiameterOptions& o) { o.ConeAngle = -1; }),
    Error);
  EXPECT_THROW(withOptions([](ShapeDiameterOptions& o) { o.VertexOriginOffset = -1; }),
    Error);
  EXPECT_THROW(withOptions([](ShapeDiameterOptions& o) { o.OriginsPerChunk = 0; }),
    Error);
  EXPECT_NO_THROW(withOptions([](ShapeDiameterOptions& o) { o.NumberOfRays = 1; }));

  const EmbreeRayCaster caster(mesh.Points, mesh.Triangles);
  RayOrigins origins = MakeFaceOrigins(mesh.Points, mesh.Triangles);
  origins.Skip.pop_back();
  EXPECT_THROW(ComputeShapeDiameter(caster, origins, {}, SerialFor), Error);
  origins = MakeFaceOrigins(mesh.Points, mesh.Triangles);
  origins.Normals.conservativeResize(3, 3);
  EXPECT_THROW(ComputeShapeDiameter(caster, origins, {}, SerialFor), Error);
  EXPECT_THROW(MakeVertexOrigins(mesh.Points, PointMatrix::Zero(2, 3)), Error);
  TriangleMatrix badTriangles = mesh.Triangles;
  badTriangles(0, 0) = mesh.Points.rows();
  EXPECT_THROW(MakeFaceOrigins(mesh.Points, badTriangles), Error);
}

// ---------------------------------------------------------------------------------------
// FillFromNeighbors

TEST(FillFromNeighbors, ChainIsFilledLayerByLayer)
{
  // 0 - 1 - 2 - 3 - 4, valid at both ends.
  std::vector<double> values = { 1, 0, 0, 0, 5 };
  const std::vector<int> validRays = { 7, 0, 0, 0, 9 };
  const std::vector<std::int64_t> offsets = { 0, 1, 3, 5, 7, 8 };
  const std::vector<std::int64_t> indices = { 1, 0, 2, 1, 3, 2, 4, 3 };
  const FillFromNeighborsSummary summary = FillFromNeighbors(values, validRays, offsets, indices);
  EXPECT_EQ(values, (std::vector<double>{ 1, 1, 3, 5, 5 }));
  EXPECT_EQ(summary.FilledFromNeighbors, 3u);
  EXPECT_EQ(summary.FilledWithFallback, 0u);
  EXPECT_EQ(summary.FallbackValue, 3.0);
}

TEST(FillFromNeighbors, IsolatedFaceAndInvalidComponentGetTheMedian)
{
  // Component {0, 1, 2} valid; face 3 isolated; component {4, 5} all invalid; face 6 has a
  // non-finite value although marked valid, and a self-loop.
  std::vector<double> values = { 2, 10, 4, 0, 0, 0, std::numeric_limits<double>::quiet_NaN() };
  const std::vector<int> validRays = { 3, 3, 3, 0, 0, 0, 3 };
  const std::vector<std::int64_t> offsets = { 0, 2, 4, 7, 7, 8, 9, 10 };
  const std::vector<std::int64_t> indices = { 1, 2, 0, 2, 0, 1, 6, 5, 4, 6 };
  // Face 2 lists 6 as a neighbour but 6 does not list 2: one-sided edges are allowed.
  const FillFromNeighborsSummary summary = FillFromNeighbors(values, validRays, offsets, indices);
  EXPECT_EQ(summary.FallbackValue, 4.0);
  EXPECT_EQ(summary.FilledWithFallback, 4u); // 3, 4, 5, 6 (6 only sees itself)
  EXPECT_EQ(summary.FilledFromNeighbors, 0u);
  EXPECT_EQ(values, (std::vector<double>{ 2, 10, 4, 4, 4, 4, 4 }));
}

TEST(FillFromNeighbors, AverageOfSeveralValidNeighborsAndEdgeCases)
{
  // Star: centre 0 invalid, leaves 1..3 valid.
  std::vector<double> values = { 0, 1, 2, 6 };
  const std::vector<int> validRays = { 0, 1, 1, 1 };
  const std::vector<std::int64_t> offsets = { 0, 3, 4, 5, 6 };
  const std::vector<std::int64_t> indices = { 1, 2, 3, 0, 0, 0 };
  FillFromNeighbors(values, validRays, offsets, indices);
  EXPECT_DOUBLE_EQ(values[0], 3.0);

  std::vector<double> none;
  EXPECT_NO_THROW(FillFromNeighbors(none, {}, {}, {}));
  EXPECT_NO_THROW(FillFromNeighbors(none, {}, { 0 }, {}));

  std::vector<double> allInvalid = { 0, 0 };
  const FillFromNeighborsSummary summary =
    FillFromNeighbors(allInvalid, { 0, 0 }, { 0, 1, 2 }, { 1, 0 });
  EXPECT_EQ(allInvalid, (std::vector<double>{ 0, 0 }));
  EXPECT_EQ(summary.FilledWithFallback, 2u);

  std::vector<double> two = { 1, 2 };
  EXPECT_THROW(FillFromNeighbors(two, { 1 }, { 0, 0, 0 }, {}), Error);
  EXPECT_THROW(FillFromNeighbors(two, { 1, 1 }, { 0, 0 }, {}), Error);
  EXPECT_THROW(FillFromNeighbors(two, { 1, 1 }, { 0, 1, 2 }, { 1, 2 }), Error);
  EXPECT_THROW(FillFromNeighbors(two, { 1, 1 }, { 0, 2, 1 }, { 1, 0 }), Error);
  EXPECT_THROW(FillFromNeighbors(two, { 1, 1 }, { 0, 1, 3 }, { 1, 0 }), Error);
}

TEST(FillFromNeighbors, ResultDoesNotDependOnNumbering)
{
  // A ring of 8 faces, valid at 0 (value 0) and 3 (value 8); renumber with a permutation and
  // compare.
  const int n = 8;
  const std::vector<int> permutation = { 5, 2, 7, 0, 3, 6, 1, 4 };
  auto ring = [&](const std::vector<int>& label, std::vector<double>& values,
                std::vector<int>& valid, std::vector<std::int64_t>& offsets,
                std::vector<std::int64_t>& indices) {
    values.assign(n, 0);
    valid.assign(n, 0);
    values[static_cast<std::size_t>(label[0])] = 0;
    valid[static_cast<std::size_t>(label[0])] = 1;
    values[static_cast<std::size_t>(label[3])] = 8;
    valid[static_cast<std::size_t>(label[3])] = 1;
    std::vector<std::vector<std::int64_t>> neighbours(n);
    for (int i = 0; i < n; ++i)
    {
      neighbours[static_cast<std::size_t>(label[i])] = { label[(i + 1) % n], label[(i + n - 1) % n] };
    }
    offsets = { 0 };
    indices.clear();
    for (auto& list : neighbours)
    {
      std::sort(list.begin(), list.end());
      indices.insert(indices.end(), list.begin(), list.end());
      offsets.push_back(static_cast<std::int64_t>(indices.size()));
    }
  };
  std::vector<int> identity(n);
  std::iota(identity.begin(), identity.end(), 0);
  std::vector<double> a, b;
  std::vector<int> validA, validB;
  std::vector<std::int64_t> offsetsA, indicesA, offsetsB, indicesB;
  ring(identity, a, validA, offsetsA, indicesA);
  ring(permutation, b, validB, offsetsB, indicesB);
  FillFromNeighbors(a, validA, offsetsA, indicesA);
  FillFromNeighbors(b, validB, offsetsB, indicesB);
  for (int i = 0; i < n; ++i)
  {
    EXPECT_EQ(a[static_cast<std::size_t>(i)], b[static_cast<std::size_t>(permutation[i])]);
  }
  // Ring 0(0) 1 2 3(8) 4 5 6 7: layer 1 = {1, 2, 4, 7}, layer 2 = {5, 6}, which do not see each other (Jacobi).
  EXPECT_EQ(a, (std::vector<double>{ 0, 0, 8, 8, 8, 8, 0, 0 }));
}

} // namespace
