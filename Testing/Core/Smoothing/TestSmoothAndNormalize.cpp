// SPDX-License-Identifier: BSD-3-Clause
// SmoothAndNormalize: the face graph, the bilateral smoothing and the log normalisation as one
// call (paper sec. 3-4).
#include "Smoothing/SmoothAndNormalize.h"
#include "TestShapes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <vector>

namespace
{

using namespace shapediameter;

/// A capsule's triangles after `emptyFaces` faces without corners (as the VTK adapter passes
/// vertex and line cells), with a noisy SDF on the triangles and the fill value 0 on the
/// empty faces.
struct Surface
{
  testshapes::TestMesh Mesh = testshapes::MakeCapsule(0.5, 1.5, 24, 6, 10);
  std::vector<std::int64_t> Offsets, Connectivity;
  std::vector<double> Values;
  std::size_t First = 0;

  explicit Surface(std::size_t emptyFaces)
    : First(emptyFaces)
  {
    TriangleFaces(Mesh.Triangles, Offsets, Connectivity);
    Offsets.insert(Offsets.begin(), emptyFaces, 0);
    Values.assign(emptyFaces, 0.0);
    std::mt19937_64 random(7);
    for (Eigen::Index f = 0; f < Mesh.Faces(); ++f)
    {
      const double unit = static_cast<double>(random() >> 11) * 0x1.0p-53;
      Values.push_back((Mesh.Points(Mesh.Triangles(f, 0), 2) > 0.0 ? 1.0 : 0.6) * (1.0 + 0.1 * unit));
    }
  }
  std::size_t Last() const { return Values.size(); }
  SmoothAndNormalizeInput Input() const { return { Mesh.Points, Offsets, Connectivity, Values, First, Last() }; }
};

TEST(SmoothAndNormalize, IsTheThreeStepsOverTheGivenFaces)
{
  const Surface surface(2);
  SmoothAndNormalizeOptions options;
  options.Smoothing.NumberOfIterations = 4;
  options.Normalization.Alpha = 3.0;
  const SmoothAndNormalizeResult result = SmoothAndNormalize(surface.Input(), options);
  ASSERT_FALSE(result.Aborted);

  const FaceGraph graph = BuildFaceGraph(surface.Mesh.Points, surface.Offsets, surface.Connectivity);
  const std::vector<double> smoothed = SmoothBilateral(graph, surface.Values, options.Smoothing).Values;
  EXPECT_EQ(result.Smoothed, smoothed);
  const std::vector<double> polygons(smoothed.begin() + 2, smoothed.end());
  EXPECT_EQ(result.Normalized, NormalizeLogarithmic(polygons, options.Normalization));
  const auto [low, high] = NormalizationRange(polygons, options.Normalization);
  EXPECT_EQ(result.RangeMinimum, low);
  EXPECT_EQ(result.RangeMaximum, high);

  // The empty faces keep their fill value 0 and stay out of the range: its minimum is the
  // smallest smoothed polygon value (about 0.6), and the normalised values span [0, 1].
  EXPECT_EQ(result.Smoothed[0], 0.0);
  EXPECT_EQ(result.RangeMinimum, *std::min_element(polygons.begin(), polygons.end()));
  EXPECT_GT(result.RangeMinimum, 0.5);
  EXPECT_EQ(*std::min_element(result.Normalized.begin(), result.Normalized.end()), 0.0);
  EXPECT_EQ(*std::max_element(result.Normalized.begin(), result.Normalized.end()), 1.0);

  // The triangle overload normalises every face.
  const SmoothAndNormalizeResult triangles =
    SmoothAndNormalize(surface.Mesh.Points, surface.Mesh.Triangles, polygons, options);
  EXPECT_EQ(triangles.Normalized.size(), polygons.size());
}

TEST(SmoothAndNormalize, AGivenRangeIsUsedAsIs)
{
  const Surface surface(0);
  SmoothAndNormalizeOptions options;
  options.Normalization.UseGivenRange = true;
  options.Normalization.RangeMinimum = 0.0;
  options.Normalization.RangeMaximum = 4.0;
  const SmoothAndNormalizeResult result = SmoothAndNormalize(surface.Input(), options);
  EXPECT_EQ(result.RangeMinimum, 0.0);
  EXPECT_EQ(result.RangeMaximum, 4.0);
  EXPECT_LT(*std::max_element(result.Normalized.begin(), result.Normalized.end()), 0.6);
}

TEST(SmoothAndNormalize, SameResultForAnyThreadCount)
{
  const Surface surface(3);
  const SmoothAndNormalizeResult serial = SmoothAndNormalize(surface.Input());
  for (unsigned threads : { 2u, 3u, 7u })
  {
    const SmoothAndNormalizeResult threaded = SmoothAndNormalize(surface.Input(), {}, ThreadedFor(threads));
    EXPECT_EQ(threaded.Smoothed, serial.Smoothed) << threads;
    EXPECT_EQ(threaded.Normalized, serial.Normalized) << threads;
  }
}

TEST(SmoothAndNormalize, ProgressRisesToOneAndAnAbortEmptiesTheResult)
{
  const Surface surface(0);
  std::vector<double> fractions;
  const SmoothAndNormalizeResult done = SmoothAndNormalize(surface.Input(), {}, SerialFor, [&](double fraction) {
    fractions.push_back(fraction);
    return true;
  });
  ASSERT_GE(fractions.size(), 3u);
  EXPECT_EQ(fractions.front(), 0.1);
  EXPECT_EQ(fractions.back(), 1.0);
  EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));
  EXPECT_FALSE(done.Aborted);

  for (const int stopAfter : { 1, 3 })
  {
    int calls = 0;
    const SmoothAndNormalizeResult aborted =
      SmoothAndNormalize(surface.Input(), {}, SerialFor, [&](double) { return ++calls < stopAfter; });
    EXPECT_TRUE(aborted.Aborted) << stopAfter;
    EXPECT_TRUE(aborted.Smoothed.empty());
    EXPECT_TRUE(aborted.Normalized.empty());
  }
}

TEST(SmoothAndNormalize, BadInputThrowsTheStepsErrors)
{
  Surface surface(1);
  SmoothAndNormalizeInput input = surface.Input();
  input.NormalizedFirst = 5;
  input.NormalizedLast = 4;
  EXPECT_THROW(SmoothAndNormalize(input), Error);
  input.NormalizedFirst = 0;
  input.NormalizedLast = surface.Last() + 1;
  EXPECT_THROW(SmoothAndNormalize(input), Error);

  SmoothAndNormalizeOptions options;
  options.Smoothing.SpatialSigma = 0.0;
  EXPECT_THROW(SmoothAndNormalize(surface.Input(), options), Error);
  options = {};
  options.Normalization.Alpha = -1.0;
  EXPECT_THROW(SmoothAndNormalize(surface.Input(), options), Error);
  // The chain holds alpha to the filter's AlphaRange, narrower than NormalizeLogarithmic's own.
  for (const double alpha : { 1e-9, 2000.0 })
  {
    options.Normalization.Alpha = alpha;
    EXPECT_THROW(SmoothAndNormalize(surface.Input(), options), Error) << alpha;
  }
  for (const double alpha : { AlphaRange.Low, AlphaRange.High })
  {
    options.Normalization.Alpha = alpha;
    EXPECT_NO_THROW(SmoothAndNormalize(surface.Input(), options)) << alpha;
  }
  surface.Values.pop_back();
  EXPECT_THROW(SmoothAndNormalize(surface.Input()), Error);
}

TEST(SmoothAndNormalize, NoFacesGiveAnEmptyResult)
{
  const std::vector<std::int64_t> none;
  const std::vector<double> values;
  const SmoothAndNormalizeResult result = SmoothAndNormalize({ PointMatrix(), none, none, values, 0, 0 });
  EXPECT_FALSE(result.Aborted);
  EXPECT_TRUE(result.Smoothed.empty());
  EXPECT_TRUE(result.Normalized.empty());
}

} // namespace
