// SPDX-License-Identifier: BSD-3-Clause
// SegmentationMetrics: the Princeton Segmentation Benchmark metrics and .seg files.
#include "SegmentationMetrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace
{
using namespace shapediameter;

/// A strip of quads in the plane z = offsetZ: column c spans [x[c], x[c+1]] x [0, 1].
/// Bottom vertices are 0..n, top vertices n+1..2n+1 (n = quad count).
struct Strip
{
  PointMatrix points;
  TriangleMatrix triangles;            ///< quad q -> triangles 2q (b_q b_q+1 t_q+1), 2q+1 (b_q t_q+1 t_q)
  std::vector<std::int64_t> quadOffsets; ///< the same quads as polygons (CSR)
  std::vector<std::int64_t> quadConnectivity;
};

Strip MakeStrip(const std::vector<double>& x, double offsetZ = 0.0)
{
  Strip strip;
  const auto n = static_cast<std::int64_t>(x.size()) - 1;
  strip.points.resize(2 * (n + 1), 3);
  for (std::int64_t i = 0; i <= n; ++i)
  {
    strip.points.row(i) << x[static_cast<std::size_t>(i)], 0.0, offsetZ;
    strip.points.row(n + 1 + i) << x[static_cast<std::size_t>(i)], 1.0, offsetZ;
  }
  strip.triangles.resize(2 * n, 3);
  strip.quadOffsets.push_back(0);
  for (std::int64_t q = 0; q < n; ++q)
  {
    const std::int64_t b0 = q, b1 = q + 1, t0 = n + 1 + q, t1 = n + 2 + q;
    strip.triangles.row(2 * q) << b0, b1, t1;
    strip.triangles.row(2 * q + 1) << b0, t1, t0;
    strip.quadConnectivity.insert(strip.quadConnectivity.end(), { b0, b1, t1, t0 });
    strip.quadOffsets.push_back(static_cast<std::int64_t>(strip.quadConnectivity.size()));
  }
  return strip;
}

/// Two disjoint meshes as one.
Strip Concatenate(const Strip& first, const Strip& second)
{
  Strip both;
  const auto offset = static_cast<std::int64_t>(first.points.rows());
  both.points.resize(first.points.rows() + second.points.rows(), 3);
  both.points << first.points, second.points;
  both.triangles.resize(first.triangles.rows() + second.triangles.rows(), 3);
  both.triangles << first.triangles, (second.triangles.array() + offset).matrix();
  return both;
}

/// Per-quad labels expanded to the two triangles of each quad.
std::vector<int> PerTriangle(const std::vector<int>& perQuad)
{
  std::vector<int> labels;
  for (int l : perQuad)
  {
    labels.push_back(l);
    labels.push_back(l);
  }
  return labels;
}

/// An nx x ny grid of cells of size cellX x cellY, each split into two triangles (alternating
/// diagonals), with a small bump in z unless flat.
Strip MakeGrid(int nx, int ny, double cellX = 1.0, double cellY = 1.0, bool flat = false)
{
  Strip grid;
  grid.points.resize((nx + 1) * (ny + 1), 3);
  for (int j = 0; j <= ny; ++j)
  {
    for (int i = 0; i <= nx; ++i)
    {
      grid.points.row(j * (nx + 1) + i) << cellX * i, cellY * j, flat ? 0.0 : 0.1 * std::sin(0.7 * i + 0.3 * j);
    }
  }
  grid.triangles.resize(2 * nx * ny, 3);
  int t = 0;
  for (int j = 0; j < ny; ++j)
  {
    for (int i = 0; i < nx; ++i)
    {
      const std::int64_t a = j * (nx + 1) + i, b = a + 1, c = a + nx + 1, d = c + 1;
      if ((i + j) % 2 == 0)
      {
        grid.triangles.row(t++) << a, b, d;
        grid.triangles.row(t++) << a, d, c;
      }
      else
      {
        grid.triangles.row(t++) << a, b, c;
        grid.triangles.row(t++) << b, d, c;
      }
    }
  }
  return grid;
}

/// Blocky random labels on a grid's triangles (so that there are cuts of all shapes).
std::vector<int> RandomLabels(std::mt19937_64& generator, std::size_t count, int labelCount)
{
  std::vector<int> labels(count);
  int current = 0;
  for (std::size_t f = 0; f < count; ++f)
  {
    if (generator() % 7 == 0)
    {
      current = static_cast<int>(generator() % static_cast<std::uint64_t>(labelCount));
    }
    labels[f] = current;
  }
  return labels;
}

/// Mean distance from the centre of a w x h rectangle, by a fine midpoint rule.
double RectangleAverageRadius(double w, double h)
{
  const int nx = 2000, ny = 1000;
  double sum = 0.0;
  for (int i = 0; i < nx; ++i)
  {
    for (int j = 0; j < ny; ++j)
    {
      const double x = (i + 0.5) / nx * w - 0.5 * w;
      const double y = (j + 0.5) / ny * h - 0.5 * h;
      sum += std::hypot(x, y);
    }
  }
  return sum / (static_cast<double>(nx) * ny);
}

void ExpectAllZero(const SegmentationComparison& r)
{
  EXPECT_EQ(r.Cut.CutDiscrepancy, 0.0);
  EXPECT_EQ(r.Cut.DirectionalCutDiscrepancyAB, 0.0);
  EXPECT_EQ(r.Cut.DirectionalCutDiscrepancyBA, 0.0);
  EXPECT_EQ(r.Partition.MissingRate, 0.0);
  EXPECT_EQ(r.Partition.FalseAlarmRate, 0.0);
  EXPECT_EQ(r.Partition.HammingDistance, 0.0);
  EXPECT_EQ(r.Partition.RandIndexError, 0.0);
  EXPECT_EQ(r.Partition.GlobalConsistencyError, 0.0);
  EXPECT_EQ(r.Partition.LocalConsistencyError, 0.0);
}

void ExpectSame(const SegmentationComparison& x, const SegmentationComparison& y)
{
  EXPECT_EQ(x.Cut.CutDiscrepancy, y.Cut.CutDiscrepancy);
  EXPECT_EQ(x.Cut.DirectionalCutDiscrepancyAB, y.Cut.DirectionalCutDiscrepancyAB);
  EXPECT_EQ(x.Cut.DirectionalCutDiscrepancyBA, y.Cut.DirectionalCutDiscrepancyBA);
  EXPECT_EQ(x.Cut.CutDiscrepancyDefined, y.Cut.CutDiscrepancyDefined);
  EXPECT_EQ(x.Partition.MissingRate, y.Partition.MissingRate);
  EXPECT_EQ(x.Partition.FalseAlarmRate, y.Partition.FalseAlarmRate);
  EXPECT_EQ(x.Partition.HammingDistance, y.Partition.HammingDistance);
  EXPECT_EQ(x.Partition.RandIndexError, y.Partition.RandIndexError);
  EXPECT_EQ(x.Partition.GlobalConsistencyError, y.Partition.GlobalConsistencyError);
  EXPECT_EQ(x.Partition.LocalConsistencyError, y.Partition.LocalConsistencyError);
}

const SegmentationMetricsOptions kUniform{ SegmentationWeighting::Uniform };

// ---------------------------------------------------------------------------------------------
// Hand-computed cases on a strip of 4 quads (as polygons, one label per quad).
// A = {q0 q1 | q2 q3}, B = {q0 | q1 q2 q3}. Cells: (A0,B0) = q0, (A0,B1) = q1, (A1,B1) = q2 q3.

TEST(SegmentationMetrics, HammingHandComputed)
{
  const Strip strip = MakeStrip({ 0, 1, 2, 3, 4 });
  const std::vector<int> a = { 0, 0, 1, 1 }, b = { 0, 1, 1, 1 };
  const PartitionComparison r =
    CompareSegmentations(strip.points, strip.quadOffsets, strip.quadConnectivity, a, b).Partition;
  // Rm: B1 (3 quads) best-overlaps A1 (2), misses 1. Rf: A0 (2) best-overlaps B0 or B1 (1).
  EXPECT_DOUBLE_EQ(r.MissingRate, 0.25);
  EXPECT_DOUBLE_EQ(r.FalseAlarmRate, 0.25);
  EXPECT_DOUBLE_EQ(r.HammingDistance, 0.25);
  EXPECT_EQ(r.SegmentCountA, 2u);
  EXPECT_EQ(r.SegmentCountB, 2u);

  // The paper's direction convention: A one segment, B two halves -> Rm = 0, Rf = 1/2.
  const PartitionComparison under = ComparePartitions({ 5, 5, 5, 5 }, { 1, 1, 2, 2 });
  EXPECT_DOUBLE_EQ(under.MissingRate, 0.0);
  EXPECT_DOUBLE_EQ(under.FalseAlarmRate, 0.5);
  EXPECT_DOUBLE_EQ(under.HammingDistance, 0.25);
  const PartitionComparison over = ComparePartitions({ 1, 1, 2, 2 }, { 5, 5, 5, 5 });
  EXPECT_DOUBLE_EQ(over.MissingRate, 0.5);
  EXPECT_DOUBLE_EQ(over.FalseAlarmRate, 0.0);
}

TEST(SegmentationMetrics, RandIndexHandComputed)
{
  const std::vector<int> a = { 0, 0, 1, 1 }, b = { 0, 1, 1, 1 };
  // Uniform: 6 pairs; together in A only: (q0,q1); in B only: (q1,q2), (q1,q3) -> 3/6.
  EXPECT_DOUBLE_EQ(ComparePartitions(a, b).RandIndexError, 0.5);
  // Point pairs, equal areas: (sum a^2 + sum b^2 - 2 sum n^2) / W^2 = (8 + 10 - 12) / 16.
  EXPECT_DOUBLE_EQ(ComparePartitions(a, b, { 1, 1, 1, 1 }).RandIndexError, 3.0 / 8.0);
  // Areas 1, 1, 2, 4: (40 + 50 - 2 * 38) / 64 = 14 / 64.
  EXPECT_DOUBLE_EQ(ComparePartitions(a, b, { 1, 1, 2, 4 }).RandIndexError, 7.0 / 32.0);

  // One segment vs two halves of n faces: (n/2)^2 / C(n, 2) = n / (2 (n - 1)).
  const std::vector<int> one(10, 3);
  std::vector<int> halves(10, 0);
  std::fill(halves.begin() + 5, halves.end(), 1);
  EXPECT_DOUBLE_EQ(ComparePartitions(one, halves).RandIndexError, 10.0 / 18.0);
  EXPECT_DOUBLE_EQ(ComparePartitions(one, halves, std::vector<double>(10, 2.0)).RandIndexError, 0.5);
}

TEST(SegmentationMetrics, ConsistencyErrorsHandComputed)
{
  const std::vector<int> a = { 0, 0, 1, 1 }, b = { 0, 1, 1, 1 };
  // E(A,B): q0 1/2, q1 1/2, q2 0, q3 0 (sum 1). E(B,A): q0 0, q1 2/3, q2 1/3, q3 1/3 (sum 4/3).
  const PartitionComparison r = ComparePartitions(a, b);
  EXPECT_DOUBLE_EQ(r.GlobalConsistencyError, 0.25);         // min(1, 4/3) / 4
  EXPECT_DOUBLE_EQ(r.LocalConsistencyError, 0.125);         // (0 + 1/2 + 0 + 0) / 4
  const PartitionComparison swapped = ComparePartitions(b, a);
  EXPECT_DOUBLE_EQ(swapped.GlobalConsistencyError, 0.25);
  EXPECT_DOUBLE_EQ(swapped.LocalConsistencyError, 0.125);
}

TEST(SegmentationMetrics, AreaWeightingMatters)
{
  // Quads of widths 1, 1, 2, 4 (areas 1, 1, 2, 4; W = 8), same labels as above.
  const Strip strip = MakeStrip({ 0, 1, 2, 4, 8 });
  const std::vector<int> a = { 0, 0, 1, 1 }, b = { 0, 1, 1, 1 };
  const PartitionComparison area =
    CompareSegmentations(strip.points, strip.quadOffsets, strip.quadConnectivity, a, b).Partition;
  const PartitionComparison uniform =
    CompareSegmentations(strip.points, strip.quadOffsets, strip.quadConnectivity, a, b, kUniform).Partition;
  EXPECT_FALSE(area.UsedUniformWeights);
  EXPECT_TRUE(uniform.UsedUniformWeights);
  // Rm: B1 (7) best A1 (6): 1/8; Rf: A0 (2) best 1: 1/8. Uniform: 1/4 each.
  EXPECT_NEAR(area.MissingRate, 1.0 / 8.0, 1e-15);
  EXPECT_NEAR(area.FalseAlarmRate, 1.0 / 8.0, 1e-15);
  EXPECT_NEAR(uniform.MissingRate, 0.25, 1e-15);
  // E(A,B) sum 1; E(B,A): q1 6/7 * 1 + q2 1/7 * 2 + q3 1/7 * 4 = 12/7. GCE = 1/8; LCE = (1/2) / 8.
  EXPECT_NEAR(area.GlobalConsistencyError, 1.0 / 8.0, 1e-15);
  EXPECT_NEAR(area.LocalConsistencyError, 1.0 / 16.0, 1e-15);
  EXPECT_NEAR(uniform.GlobalConsistencyError, 0.25, 1e-15);
  EXPECT_NEAR(uniform.LocalConsistencyError, 0.125, 1e-15);
  EXPECT_NEAR(area.RandIndexError, 7.0 / 32.0, 1e-15);
  EXPECT_NEAR(uniform.RandIndexError, 0.5, 1e-15);
}

// ---------------------------------------------------------------------------------------------
// Cut discrepancy on the strip of 4 unit quads (8 triangles), centroid (2, 0.5, 0).

TEST(SegmentationMetrics, AverageRadiusOfARectangle)
{
  const Strip strip = MakeStrip({ 0, 1, 2, 3, 4 });
  const std::vector<int> labels(8, 0);
  const double expected = RectangleAverageRadius(4.0, 1.0); // about 1.0608
  const CutDiscrepancyResult coarse = ComputeCutDiscrepancy(strip.points, strip.triangles, labels, labels);
  EXPECT_NEAR(coarse.AverageRadius, expected, 2e-3 * expected);

  // Refined in both directions, the quadrature converges (the kink of |x - c| at the centroid
  // is the only non-smooth spot).
  const Strip fine = MakeGrid(64, 16, 1.0 / 16.0, 1.0 / 16.0, true);
  const std::vector<int> fineLabels(2 * 64 * 16, 0);
  const CutDiscrepancyResult refined = ComputeCutDiscrepancy(fine.points, fine.triangles, fineLabels, fineLabels);
  EXPECT_NEAR(refined.AverageRadius, expected, 1e-5 * expected);
}

TEST(SegmentationMetrics, CutDiscrepancyHandComputed)
{
  const Strip strip = MakeStrip({ 0, 1, 2, 3, 4 });
  // A cuts at x = 2, B at x = 1: every cut vertex is one edge (length 1) from the other cut
  // (the diagonal b1-t2 is longer, sqrt 2).
  const std::vector<int> a = PerTriangle({ 0, 0, 1, 1 }), b = PerTriangle({ 0, 1, 1, 1 });
  const CutDiscrepancyResult r = ComputeCutDiscrepancy(strip.points, strip.triangles, a, b);
  const double radius = r.AverageRadius;
  ASSERT_GT(radius, 1.0);
  EXPECT_TRUE(r.CutDiscrepancyDefined);
  EXPECT_EQ(r.CutEdgeCountA, 1u);
  EXPECT_EQ(r.CutEdgeCountB, 1u);
  EXPECT_DOUBLE_EQ(r.CutLengthA, 1.0);
  EXPECT_DOUBLE_EQ(r.DirectionalCutDiscrepancyAB, 1.0 / radius);
  EXPECT_DOUBLE_EQ(r.DirectionalCutDiscrepancyBA, 1.0 / radius);
  EXPECT_DOUBLE_EQ(r.CutDiscrepancy, 1.0 / radius);
  EXPECT_EQ(r.CutPointsWithEuclideanDistance, 0u);

  // A cuts at x = 1 and x = 3, B at x = 1. A => B: (0 * 1 + 2 * 1) / 2 = 1 (t3 reaches t1
  // along the top, 2, shorter than via a diagonal, 1 + sqrt 2). B => A: 0. Pooled: 2 / 3.
  const std::vector<int> a2 = PerTriangle({ 0, 1, 1, 2 });
  for (const SegmentationMetricsOptions& options : { SegmentationMetricsOptions{}, kUniform })
  {
    const CutDiscrepancyResult s = ComputeCutDiscrepancy(strip.points, strip.triangles, a2, b, options);
    EXPECT_DOUBLE_EQ(s.DirectionalCutDiscrepancyAB, 1.0 / radius);
    EXPECT_DOUBLE_EQ(s.DirectionalCutDiscrepancyBA, 0.0);
    EXPECT_DOUBLE_EQ(s.CutDiscrepancy, 2.0 / 3.0 / radius);
    EXPECT_DOUBLE_EQ(s.CutLengthA, 2.0);
  }
}

TEST(SegmentationMetrics, CutDiscrepancyWeighsCutPointsByLength)
{
  // The unit strip with its top vertex at x = 3 raised to y = 3, so that the cut edge at
  // x = 3 has length 3 while the one at x = 1 keeps length 1.
  Strip strip = MakeStrip({ 0, 1, 2, 3, 4 });
  strip.points(5 + 3, 1) = 3.0; // t3 = (3, 3)
  const std::vector<int> a = PerTriangle({ 0, 1, 1, 2 }), b = PerTriangle({ 0, 1, 1, 1 });
  // A cut edges: x = 1 (length 1, distance 0) and b3-t3 (length 3). Distances to B's cut
  // {b1, t1}: b3 2 (bottom edges), t3: t1-t2 (1) + t2-t3 (sqrt(1 + 4)).
  const double t3 = 1.0 + std::sqrt(5.0);
  const CutDiscrepancyResult byLength = ComputeCutDiscrepancy(strip.points, strip.triangles, a, b);
  const double radius = byLength.AverageRadius;
  EXPECT_DOUBLE_EQ(byLength.DirectionalCutDiscrepancyAB, (3.0 * 0.5 * (2.0 + t3)) / 4.0 / radius);
  const CutDiscrepancyResult byVertex = ComputeCutDiscrepancy(strip.points, strip.triangles, a, b, kUniform);
  EXPECT_DOUBLE_EQ(byVertex.DirectionalCutDiscrepancyAB, (2.0 + t3) / 4.0 / radius);
  EXPECT_GT(byLength.DirectionalCutDiscrepancyAB, byVertex.DirectionalCutDiscrepancyAB);
}

TEST(SegmentationMetrics, CutDiscrepancyAcrossComponentsUsesEuclideanDistance)
{
  // Two strips 5 apart in z. A cuts both at x = 1; B cuts only the first one.
  const Strip both = Concatenate(MakeStrip({ 0, 1, 2, 3, 4 }), MakeStrip({ 0, 1, 2, 3, 4 }, 5.0));
  std::vector<int> a = PerTriangle({ 0, 1, 1, 1, 2, 3, 3, 3 });
  std::vector<int> b = PerTriangle({ 0, 1, 1, 1, 2, 2, 2, 2 });
  const CutDiscrepancyResult r = ComputeCutDiscrepancy(both.points, both.triangles, a, b);
  EXPECT_EQ(r.CutPointsWithEuclideanDistance, 2u);
  const double radius = r.AverageRadius;
  EXPECT_DOUBLE_EQ(r.DirectionalCutDiscrepancyAB, (0.0 + 5.0) / 2.0 / radius);
  EXPECT_DOUBLE_EQ(r.DirectionalCutDiscrepancyBA, 0.0);
  EXPECT_DOUBLE_EQ(r.CutDiscrepancy, 5.0 / 3.0 / radius);
  EXPECT_TRUE(std::isfinite(r.CutDiscrepancy));
}

TEST(SegmentationMetrics, CutDiscrepancyWithoutCuts)
{
  const Strip strip = MakeStrip({ 0, 1, 2, 3, 4 });
  const std::vector<int> single(8, 7);
  const CutDiscrepancyResult none = ComputeCutDiscrepancy(strip.points, strip.triangles, single, single);
  EXPECT_TRUE(none.CutDiscrepancyDefined);
  EXPECT_EQ(none.CutDiscrepancy, 0.0);

  const std::vector<int> halves = PerTriangle({ 0, 0, 1, 1 });
  for (const auto& [x, y] : { std::make_pair(single, halves), std::make_pair(halves, single) })
  {
    const CutDiscrepancyResult oneSided = ComputeCutDiscrepancy(strip.points, strip.triangles, x, y);
    EXPECT_FALSE(oneSided.CutDiscrepancyDefined);
    EXPECT_EQ(oneSided.CutDiscrepancy, 0.0);
    EXPECT_EQ(oneSided.DirectionalCutDiscrepancyAB, 0.0);
    EXPECT_EQ(oneSided.DirectionalCutDiscrepancyBA, 0.0);
  }
}

// ---------------------------------------------------------------------------------------------
// Properties on a bumpy 12 x 10 grid with blocky random labels.

TEST(SegmentationMetrics, IdenticalSegmentationsScorePerfect)
{
  const Strip grid = MakeGrid(12, 10);
  std::mt19937_64 generator(11);
  const std::vector<int> labels = RandomLabels(generator, 240, 6);
  for (const SegmentationMetricsOptions& options : { SegmentationMetricsOptions{}, kUniform })
  {
    const SegmentationComparison r = CompareSegmentations(grid.points, grid.triangles, labels, labels, options);
    ExpectAllZero(r);
    EXPECT_TRUE(r.Cut.CutDiscrepancyDefined);
    EXPECT_GT(r.Cut.CutEdgeCountA, 0u);
  }
}

TEST(SegmentationMetrics, RelabellingChangesNothing)
{
  const Strip grid = MakeGrid(12, 10);
  std::mt19937_64 generator(5);
  const std::vector<int> a = RandomLabels(generator, 240, 5);
  const std::vector<int> b = RandomLabels(generator, 240, 7);
  // A bijection onto arbitrary integers, including negative and extreme ones.
  const std::vector<int> newNames = { 1000000, -3, std::numeric_limits<int>::min(), 42,
    std::numeric_limits<int>::max(), 0, 17 };
  std::vector<int> renamedA(a.size()), renamedB(b.size());
  for (std::size_t f = 0; f < a.size(); ++f)
  {
    renamedA[f] = newNames[static_cast<std::size_t>(a[f])];
    renamedB[f] = newNames[static_cast<std::size_t>(6 - b[f])];
  }
  for (const SegmentationMetricsOptions& options : { SegmentationMetricsOptions{}, kUniform })
  {
    const SegmentationComparison reference = CompareSegmentations(grid.points, grid.triangles, a, b, options);
    EXPECT_GT(reference.Partition.HammingDistance, 0.05);
    EXPECT_GT(reference.Cut.CutDiscrepancy, 0.01);
    ExpectSame(reference, CompareSegmentations(grid.points, grid.triangles, renamedA, b, options));
    ExpectSame(reference, CompareSegmentations(grid.points, grid.triangles, a, renamedB, options));
    ExpectSame(reference, CompareSegmentations(grid.points, grid.triangles, renamedA, renamedB, options));
  }
}

TEST(SegmentationMetrics, SymmetricMetricsAreSymmetric)
{
  const Strip grid = MakeGrid(12, 10);
  std::mt19937_64 generator(8);
  const std::vector<int> a = RandomLabels(generator, 240, 4);
  const std::vector<int> b = RandomLabels(generator, 240, 6);
  for (const SegmentationMetricsOptions& options : { SegmentationMetricsOptions{}, kUniform })
  {
    const SegmentationComparison ab = CompareSegmentations(grid.points, grid.triangles, a, b, options);
    const SegmentationComparison ba = CompareSegmentations(grid.points, grid.triangles, b, a, options);
    EXPECT_GT(ab.Partition.RandIndexError, 0.05);
    EXPECT_NEAR(ab.Partition.RandIndexError, ba.Partition.RandIndexError, 1e-14);
    EXPECT_NEAR(ab.Partition.GlobalConsistencyError, ba.Partition.GlobalConsistencyError, 1e-14);
    EXPECT_NEAR(ab.Partition.LocalConsistencyError, ba.Partition.LocalConsistencyError, 1e-14);
    EXPECT_NEAR(ab.Partition.HammingDistance, ba.Partition.HammingDistance, 1e-14);
    EXPECT_NEAR(ab.Partition.MissingRate, ba.Partition.FalseAlarmRate, 1e-14);
    EXPECT_NEAR(ab.Cut.CutDiscrepancy, ba.Cut.CutDiscrepancy, 1e-14);
    EXPECT_NEAR(ab.Cut.DirectionalCutDiscrepancyAB, ba.Cut.DirectionalCutDiscrepancyBA, 1e-14);
    // Every value within its range; LCE <= GCE always.
    EXPECT_LE(ab.Partition.LocalConsistencyError, ab.Partition.GlobalConsistencyError);
    EXPECT_LE(ab.Partition.RandIndexError, 1.0);
  }
}

TEST(SegmentationMetrics, RefinementHasNoConsistencyError)
{
  const Strip grid = MakeGrid(12, 10);
  std::mt19937_64 generator(2);
  const std::vector<int> coarse = RandomLabels(generator, 240, 3);
  // Refine: split every coarse segment by the parity of the face index's row.
  std::vector<int> fine(coarse.size());
  for (std::size_t f = 0; f < coarse.size(); ++f)
  {
    fine[f] = 10 * coarse[f] + static_cast<int>((f / 24) % 2);
  }
  const std::vector<int> single(coarse.size(), 9);
  for (const SegmentationMetricsOptions& options : { SegmentationMetricsOptions{}, kUniform })
  {
    const PartitionComparison r = CompareSegmentations(grid.points, grid.triangles, fine, coarse, options).Partition;
    EXPECT_EQ(r.GlobalConsistencyError, 0.0);
    EXPECT_EQ(r.LocalConsistencyError, 0.0);
    EXPECT_GT(r.HammingDistance, 0.0);

    // Anything refines the single segment: GCE = LCE = 0, Rm = 0 (nothing of the single
    // segment is missed by its best match), Rf = 1 - (largest segment share).
    const SegmentationComparison s = CompareSegmentations(grid.points, grid.triangles, single, coarse, options);
    EXPECT_EQ(s.Partition.GlobalConsistencyError, 0.0);
    EXPECT_EQ(s.Partition.LocalConsistencyError, 0.0);
    EXPECT_EQ(s.Partition.MissingRate, 0.0);
    EXPECT_GT(s.Partition.FalseAlarmRate, 0.0);
    EXPECT_FALSE(s.Cut.CutDiscrepancyDefined);
  }
  // Uniform: Rf(single, halves) with halves of 120 + 120 faces = 1/2, Rm = 0;
  // 1 - RI = 120^2 / C(240, 2).
  std::vector<int> halves(240, 1);
  std::fill(halves.begin(), halves.begin() + 120, 4);
  const PartitionComparison h = ComparePartitions(single, halves);
  EXPECT_DOUBLE_EQ(h.MissingRate, 0.0);
  EXPECT_DOUBLE_EQ(h.FalseAlarmRate, 0.5);
  EXPECT_DOUBLE_EQ(h.RandIndexError, 14400.0 / 28680.0);
  EXPECT_EQ(h.GlobalConsistencyError, 0.0);
}

TEST(SegmentationMetrics, EveryFaceItsOwnSegment)
{
  // The benchmark's "Every" baseline against blocks: one segment per face refines anything.
  std::mt19937_64 generator(4);
  const std::size_t n = 5000;
  const std::vector<int> blocks = RandomLabels(generator, n, 9);
  std::vector<int> every(n);
  for (std::size_t f = 0; f < n; ++f)
  {
    every[f] = static_cast<int>(7 * f) - 1000;
  }
  std::vector<double> blockSizes(9, 0.0);
  for (int l : blocks)
  {
    blockSizes[static_cast<std::size_t>(l)] += 1.0;
  }
  double kB = 0.0, pairsB = 0.0;
  for (double s : blockSizes)
  {
    kB += s > 0.0 ? 1.0 : 0.0;
    pairsB += 0.5 * s * (s - 1.0);
  }
  const PartitionComparison r = ComparePartitions(every, blocks);
  EXPECT_EQ(r.SegmentCountA, n);
  EXPECT_DOUBLE_EQ(r.MissingRate, (static_cast<double>(n) - kB) / static_cast<double>(n));
  EXPECT_EQ(r.FalseAlarmRate, 0.0);
  EXPECT_EQ(r.GlobalConsistencyError, 0.0);
  EXPECT_EQ(r.LocalConsistencyError, 0.0);
  EXPECT_NEAR(r.RandIndexError, pairsB / (0.5 * n * (n - 1.0)), 1e-14);
}

TEST(SegmentationMetrics, PolygonsAndTheirTriangulationAgreeUnderAreaWeighting)
{
  const Strip strip = MakeStrip({ 0, 1, 2, 4, 8 });
  const std::vector<int> a = { 3, 3, 1, 1 }, b = { 0, 2, 2, 1 };
  const SegmentationComparison quads =
    CompareSegmentations(strip.points, strip.quadOffsets, strip.quadConnectivity, a, b);
  const SegmentationComparison triangles =
    CompareSegmentations(strip.points, strip.triangles, PerTriangle(a), PerTriangle(b));
  EXPECT_NEAR(quads.Partition.MissingRate, triangles.Partition.MissingRate, 1e-15);
  EXPECT_NEAR(quads.Partition.FalseAlarmRate, triangles.Partition.FalseAlarmRate, 1e-15);
  EXPECT_NEAR(quads.Partition.RandIndexError, triangles.Partition.RandIndexError, 1e-15);
  EXPECT_NEAR(quads.Partition.GlobalConsistencyError, triangles.Partition.GlobalConsistencyError, 1e-15);
  EXPECT_NEAR(quads.Partition.LocalConsistencyError, triangles.Partition.LocalConsistencyError, 1e-15);
  EXPECT_DOUBLE_EQ(quads.Cut.CutDiscrepancy, triangles.Cut.CutDiscrepancy);
  EXPECT_GT(quads.Cut.CutDiscrepancy, 0.0);
  // Fan diagonals are never cuts: A cuts at x = 2, B at x = 1 and x = 4.
  EXPECT_EQ(quads.Cut.CutEdgeCountA, 1u);
  EXPECT_EQ(quads.Cut.CutEdgeCountB, 2u);
  // Face areas of the quads.
  const std::vector<double> areas = ComputeFaceAreas(strip.points, strip.quadOffsets, strip.quadConnectivity);
  ASSERT_EQ(areas.size(), 4u);
  EXPECT_DOUBLE_EQ(areas[3], 4.0);
}

// ---------------------------------------------------------------------------------------------
// Degenerate and bad input.

TEST(SegmentationMetrics, DegenerateInputs)
{
  // No faces.
  const PointMatrix noPoints(0, 3);
  const TriangleMatrix noTriangles(0, 3);
  const SegmentationComparison empty = CompareSegmentations(noPoints, noTriangles, {}, {});
  ExpectAllZero(empty);
  EXPECT_TRUE(empty.Cut.CutDiscrepancyDefined);
  ExpectAllZero(CompareSegmentations(noPoints, std::vector<std::int64_t>{}, std::vector<std::int64_t>{}, {}, {}));

  // A single face.
  PointMatrix points(3, 3);
  points << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  TriangleMatrix one(1, 3);
  one << 0, 1, 2;
  ExpectAllZero(CompareSegmentations(points, one, { 4 }, { -4 }));

  // All faces of zero area: counted instead of weighted, values stay finite.
  PointMatrix flat(4, 3);
  flat << 0, 0, 0, 1, 0, 0, 2, 0, 0, 3, 0, 0;
  TriangleMatrix slivers(2, 3);
  slivers << 0, 1, 2, 1, 3, 2;
  const SegmentationComparison sliver = CompareSegmentations(flat, slivers, { 0, 1 }, { 0, 0 });
  EXPECT_TRUE(sliver.Partition.UsedUniformWeights);
  EXPECT_DOUBLE_EQ(sliver.Partition.FalseAlarmRate, 0.0);
  EXPECT_DOUBLE_EQ(sliver.Partition.MissingRate, 0.5);
  EXPECT_TRUE(std::isfinite(sliver.Cut.CutDiscrepancy));
  EXPECT_DOUBLE_EQ(sliver.Cut.AverageRadius, 1.0); // vertex fallback: mean |x - 1.5|

  // Polygons with fewer than 3 vertices: no area, label kept.
  const std::vector<std::int64_t> offsets = { 0, 3, 5 }, connectivity = { 0, 1, 2, 0, 1 };
  const SegmentationComparison mixed = CompareSegmentations(points, offsets, connectivity, { 1, 2 }, { 1, 1 });
  EXPECT_DOUBLE_EQ(mixed.Partition.MissingRate, 0.0); // the 2-gon has no area
}

TEST(SegmentationMetrics, BadInputThrows)
{
  const Strip strip = MakeStrip({ 0, 1, 2 });
  const std::vector<int> four(4, 0), three(3, 0);
  EXPECT_THROW(CompareSegmentations(strip.points, strip.triangles, four, three), SegmentationMetricsError);
  EXPECT_THROW(CompareSegmentations(strip.points, strip.triangles, three, three), SegmentationMetricsError);
  EXPECT_THROW(ComputeCutDiscrepancy(strip.points, strip.triangles, four, three), SegmentationMetricsError);
  EXPECT_THROW(ComparePartitions({ 1, 2 }, { 1 }), SegmentationMetricsError);
  EXPECT_THROW(ComparePartitions({ 1, 2 }, { 1, 2 }, { 1.0 }), SegmentationMetricsError);
  EXPECT_THROW(ComparePartitions({ 1, 2 }, { 1, 2 }, { 1.0, -1.0 }), SegmentationMetricsError);
  EXPECT_THROW(ComparePartitions({ 1, 2 }, { 1, 2 }, { 1.0, std::nan("") }), SegmentationMetricsError);

  TriangleMatrix outOfRange = strip.triangles;
  outOfRange(1, 2) = 99;
  EXPECT_THROW(CompareSegmentations(strip.points, outOfRange, four, four), SegmentationMetricsError);
  outOfRange(1, 2) = -1;
  EXPECT_THROW(CompareSegmentations(strip.points, outOfRange, four, four), SegmentationMetricsError);

  PointMatrix nanPoints = strip.points;
  nanPoints(2, 1) = std::nan("");
  EXPECT_THROW(CompareSegmentations(nanPoints, strip.triangles, four, four), SegmentationMetricsError);

  std::vector<std::int64_t> badOffsets = { 0, 4, 3, 8 };
  const std::vector<int> two(2, 0);
  EXPECT_THROW(
    CompareSegmentations(strip.points, badOffsets, strip.quadConnectivity, three, three), SegmentationMetricsError);
  badOffsets = { 1, 4, 8 };
  EXPECT_THROW(
    CompareSegmentations(strip.points, badOffsets, strip.quadConnectivity, two, two), SegmentationMetricsError);
  try
  {
    CompareSegmentations(strip.points, strip.triangles, three, three);
    FAIL() << "no exception";
  }
  catch (const SegmentationMetricsError& error)
  {
    EXPECT_NE(std::string(error.what()).find("3 labels but the mesh has 4 faces"), std::string::npos) << error.what();
  }
}

// ---------------------------------------------------------------------------------------------
// .seg files

std::vector<int> Parse(const std::string& text)
{
  return ParseSeg(text.data(), text.size(), "test.seg");
}

std::int64_t ErrorLine(const std::string& text)
{
  try
  {
    Parse(text);
  }
  catch (const SegFileError& error)
  {
    EXPECT_NE(std::string(error.what()).find("test.seg: line "), std::string::npos) << error.what();
    return error.Line();
  }
  return -1;
}

TEST(SegmentationMetrics, ParseSegAcceptsTolerableFormatting)
{
  EXPECT_EQ(Parse("1\n2\n3\n"), (std::vector<int>{ 1, 2, 3 }));
  EXPECT_EQ(Parse("1\n2\n3"), (std::vector<int>{ 1, 2, 3 }));
  EXPECT_EQ(Parse("\xEF\xBB\xBF  7 \r\n\t-2\t\r\n+5\r\n\n  \n"), (std::vector<int>{ 7, -2, 5 }));
  EXPECT_EQ(Parse("2147483647\n-2147483648\n"),
    (std::vector<int>{ std::numeric_limits<int>::max(), std::numeric_limits<int>::min() }));
  EXPECT_TRUE(Parse("").empty());
  EXPECT_TRUE(Parse("\n\n").empty());
}

TEST(SegmentationMetrics, ParseSegReportsTheLineOfGarbage)
{
  EXPECT_EQ(ErrorLine("1\n2\nabc\n4\n"), 3);
  EXPECT_EQ(ErrorLine("1\n2 3\n"), 2);
  EXPECT_EQ(ErrorLine("1.5\n"), 1);
  EXPECT_EQ(ErrorLine("1\n2147483648\n"), 2);
  EXPECT_EQ(ErrorLine("1\n\n2\n"), 3); // a blank line inside would shift every later face
  EXPECT_EQ(ErrorLine("1\n+-2\n"), 2);
  EXPECT_EQ(ErrorLine("1\n-\n"), 2);
  EXPECT_EQ(ErrorLine(std::string("1\n2\0", 4) + "\n"), 2);
  EXPECT_EQ(ErrorLine("1\r2\n"), 1); // CR-only line endings are not supported
}

TEST(SegmentationMetrics, SegFileRoundTrip)
{
  const std::string path = ::testing::TempDir() + "segmentation_metrics_roundtrip.seg";
  const std::vector<int> labels = { 0, 5, -1, 12, std::numeric_limits<int>::min() };
  WriteSegFile(path, labels);
  EXPECT_EQ(ReadSegFile(path), labels);
  std::remove(path.c_str());
  try
  {
    ReadSegFile(path);
    FAIL() << "no exception";
  }
  catch (const SegFileError& error)
  {
    EXPECT_EQ(error.Line(), 0);
    EXPECT_NE(std::string(error.what()).find(path), std::string::npos);
  }
  EXPECT_THROW(WriteSegFile("/nonexistent-directory/x.seg", labels), SegFileError);
}

} // namespace
