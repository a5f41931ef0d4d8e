// SPDX-License-Identifier: BSD-3-Clause
// The partition's one entry point (Partition.h) against its steps called one by one, its
// histogram, progress, abort and bad input.
#include "Partition/Partition.h"

#include "TestShapes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <vector>

namespace
{

using namespace shapediameter;

/// A capsule along z whose values say "thick" above z = 0 and "thin" below, with a smooth
/// ripple so the fits have something to do.
struct TwoLevelCapsule
{
  testshapes::TestMesh Mesh = testshapes::MakeCapsule(0.3, 1.0, 24, 6, 16);
  Eigen::VectorXd Values;

  TwoLevelCapsule()
  {
    Values.resize(Mesh.Triangles.rows());
    for (Eigen::Index f = 0; f < Mesh.Triangles.rows(); ++f)
    {
      Eigen::Vector3d centre = Eigen::Vector3d::Zero();
      for (int corner = 0; corner < 3; ++corner)
      {
        centre += Mesh.Points.row(Mesh.Triangles(f, corner)).transpose() / 3.0;
      }
      Values[f] = (centre.z() > 0 ? 0.75 : 0.25) + 0.03 * std::sin(7 * centre.x() + 3 * centre.y());
    }
  }
};

/// The steps of section 4 one by one, as vtkSDFGMMPartition ran them before the entry point.
struct StepByStep
{
  GaussianMixtureModel Model;
  PosteriorMatrix Posteriors;
  AlphaExpansionResult Cut;
  double ReportedEnergy = 0.0; ///< E of the cut's labels as an exact sum
  ConnectedSegments Segments;
};

StepByStep RunSteps(const TwoLevelCapsule& shape, const PartitionOptions& options, const ParallelFor& parallelFor)
{
  StepByStep steps;
  const FaceGraph graph = BuildFaceGraph(shape.Mesh.Points, shape.Mesh.Triangles, parallelFor);
  if (options.ClusterModel == PartitionClusterModel::DensityModes)
  {
    DensityModesOptions modes = options.Modes;
    modes.MaximumModes = options.NumberOfClusters;
    const Eigen::Map<const Eigen::VectorXd> areas(graph.Areas.data(), static_cast<Eigen::Index>(graph.Areas.size()));
    steps.Model = FitDensityModes(shape.Values, areas, modes).Model;
  }
  else
  {
    steps.Model = FitGaussianMixture(shape.Values, options.NumberOfClusters, options.Mixture);
  }
  steps.Posteriors = ComputePosteriors(steps.Model, shape.Values, parallelFor);
  const DualGraphView view = MakeDualGraphView(graph);
  const PartitionEnergy energy = BuildPartitionEnergy(steps.Posteriors, view, options.Energy, parallelFor);
  steps.Cut = MinimizeMultilevel(energy, options.Multilevel, options.AlphaExpansion, nullptr, parallelFor);
  steps.ReportedEnergy = energy.EvaluateExactly(steps.Cut.Labels);
  steps.Segments = FindConnectedSegments(view, steps.Cut.Labels, graph.Areas, parallelFor);
  return steps;
}

TEST(Partition, OneCallEqualsTheStepsOneByOne)
{
  const TwoLevelCapsule shape;
  for (const PartitionClusterModel clusterModel :
    { PartitionClusterModel::DensityModes, PartitionClusterModel::ExpectationMaximization })
  {
    for (const ParallelFor& parallelFor : { ParallelFor(SerialFor), ThreadedFor(3) })
    {
      PartitionOptions options;
      options.ClusterModel = clusterModel;
      options.NumberOfClusters = 3;
      options.Refinement.Enabled = false; // the steps of section 4 alone (the fine level: TestPartRefinement)
      const StepByStep steps = RunSteps(shape, options, parallelFor);
      const PartitionResult result =
        PartitionBySDF(shape.Mesh.Points, shape.Mesh.Triangles, shape.Values, options, parallelFor);
      ASSERT_FALSE(result.Aborted);
      EXPECT_EQ(result.Model.Means, steps.Model.Means);
      EXPECT_EQ(result.Model.Sigmas, steps.Model.Sigmas);
      EXPECT_EQ(result.Model.Weights, steps.Model.Weights);
      EXPECT_TRUE(result.Probabilities == steps.Posteriors);
      EXPECT_EQ(result.Bands, steps.Cut.Labels);
      EXPECT_EQ(result.Labels, steps.Cut.Labels); // refinement off: the fine labels are the bands
      EXPECT_EQ(result.Energy, steps.ReportedEnergy);
      EXPECT_NEAR(result.Energy, steps.Cut.Energy, 1e-12 * result.Energy);
      EXPECT_EQ(result.CutMoves, steps.Cut.Moves);
      EXPECT_EQ(result.Segments.Segment, steps.Segments.Segment);
      EXPECT_EQ(result.Segments.Area, steps.Segments.Area);
      const int k = result.Model.ComponentCount();
      ASSERT_EQ(result.Levels.size(), static_cast<std::size_t>(k - 1));
      for (int level = 1; level < k; ++level)
      {
        EXPECT_EQ(result.Levels[static_cast<std::size_t>(level - 1)], HierarchyLevel(result.Labels, level));
      }
      // The two halves: at least two clusters, the thick half in cluster 0.
      EXPECT_GE(k, 2);
      EXPECT_GE(result.Segments.SegmentCount(), 2);
      EXPECT_GE(result.Timings.CutMs, 0.0);
    }
  }
}

// A caller that owns the graph may free its angles, concave flags and edge lengths once the
// energy is built (a distributed run's process 0): the result is the same, and nothing reads
// them afterwards (freed vectors and null pointers would crash or differ). With the
// refinement on, which reads them, the caller is not asked.
TEST(Partition, EdgeGeometryIsReleasedAfterTheEnergyUnlessTheRefinementReadsIt)
{
  const TwoLevelCapsule shape;
  const FaceGraph graph = BuildFaceGraph(shape.Mesh.Points, shape.Mesh.Triangles);
  for (const bool refine : { false, true })
  {
    PartitionOptions options;
    options.Refinement.Enabled = refine;
    const PartitionResult kept =
      PartitionOnDualGraph(MakeDualGraphView(graph), graph.Areas, shape.Values, nullptr, options);
    std::vector<double> angles = graph.NormalAngles;
    std::vector<double> lengths = graph.SharedEdgeLengths;
    std::vector<std::uint8_t> concave = graph.Concave;
    DualGraphView view = MakeDualGraphView(graph);
    view.NormalAngle = angles.data();
    view.EdgeLength = lengths.data();
    view.Concave = concave.data();
    int releases = 0;
    const PartitionResult released = PartitionOnDualGraph(view, graph.Areas, shape.Values, nullptr, options,
      SerialFor, {}, [&] {
        ++releases;
        std::vector<double>().swap(angles);
        std::vector<double>().swap(lengths);
        std::vector<std::uint8_t>().swap(concave);
      });
    EXPECT_EQ(releases, refine ? 0 : 1) << "refinement " << refine;
    EXPECT_EQ(released.Labels, kept.Labels);
    EXPECT_EQ(released.Bands, kept.Bands);
    EXPECT_EQ(released.Energy, kept.Energy);
    EXPECT_TRUE(released.Probabilities == kept.Probabilities);
    EXPECT_EQ(released.Segments.Segment, kept.Segments.Segment);
    EXPECT_EQ(released.Segments.Area, kept.Segments.Area);
  }
}

TEST(Partition, AFamilyModelIsUsedAsIs)
{
  const TwoLevelCapsule shape;
  GaussianMixtureModel family;
  family.Means = { 0.8, 0.5, 0.2 };
  family.Sigmas = { 0.05, 0.05, 0.05 };
  family.Weights = { 0.3, 0.4, 0.3 };
  PartitionOptions options;
  options.NumberOfClusters = 2; // not read with a family model
  std::vector<std::int64_t> offsets, connectivity;
  TriangleFaces(shape.Mesh.Triangles, offsets, connectivity);
  const PartitionResult result =
    PartitionBySDF(PartitionInput{ shape.Mesh.Points, offsets, connectivity, shape.Values, &family }, options);
  EXPECT_EQ(result.Model.Means, family.Means);
  EXPECT_EQ(result.Probabilities.cols(), 3);
  EXPECT_EQ(result.Levels.size(), 2U);
  EXPECT_EQ(result.Histogram.Components.size(), 3U);
}

TEST(Partition, HistogramCountsEveryValueAndEachCurveIntegratesToItsWeight)
{
  const TwoLevelCapsule shape;
  PartitionOptions options;
  options.HistogramBins = 37;
  const PartitionResult result = PartitionBySDF(shape.Mesh.Points, shape.Mesh.Triangles, shape.Values, options);
  const PartitionHistogram& histogram = result.Histogram;
  ASSERT_EQ(histogram.BinCenters.size(), 37U);
  const double width = histogram.BinCenters[1] - histogram.BinCenters[0];
  EXPECT_EQ(std::accumulate(histogram.Counts.begin(), histogram.Counts.end(), 0.0),
    static_cast<double>(shape.Values.size()));
  EXPECT_NEAR(std::accumulate(histogram.Density.begin(), histogram.Density.end(), 0.0) * width, 1.0, 1e-12);
  ASSERT_EQ(histogram.Components.size(), static_cast<std::size_t>(result.Model.ComponentCount()));
  for (std::size_t c = 0; c < histogram.Components.size(); ++c)
  {
    // The bins reach 4 sigma_max beyond the values: the tails outside hold < 1e-4.
    const double integral =
      std::accumulate(histogram.Components[c].begin(), histogram.Components[c].end(), 0.0) * width;
    EXPECT_NEAR(integral, result.Model.Weights[c], 1e-4) << "component " << c;
  }
  for (std::size_t b = 0; b < histogram.Mixture.size(); ++b)
  {
    double sum = 0.0;
    for (const auto& curve : histogram.Components)
    {
      sum += curve[b];
    }
    EXPECT_EQ(histogram.Mixture[b], sum);
  }
  EXPECT_THROW(MixtureHistogram(result.Model, shape.Values, 0), Error);
  EXPECT_THROW(MixtureHistogram(GaussianMixtureModel(), shape.Values, 8), Error);
}

TEST(Partition, ProgressRisesToOneAndFalseAborts)
{
  const TwoLevelCapsule shape;
  std::vector<double> fractions;
  const PartitionResult done = PartitionBySDF(shape.Mesh.Points, shape.Mesh.Triangles, shape.Values, {}, SerialFor,
    [&](double fraction) {
      fractions.push_back(fraction);
      return true;
    });
  ASSERT_FALSE(done.Aborted);
  ASSERT_GE(fractions.size(), 3U);
  EXPECT_EQ(fractions.front(), 0.1);
  EXPECT_EQ(fractions.back(), 1.0);
  EXPECT_TRUE(std::is_sorted(fractions.begin(), fractions.end()));

  for (const double stopAt : { 0.1, 0.2, 0.21 }) // after the graph, the posteriors, a move
  {
    const PartitionResult aborted = PartitionBySDF(shape.Mesh.Points, shape.Mesh.Triangles, shape.Values, {},
      SerialFor, [stopAt](double fraction) { return fraction < stopAt; });
    EXPECT_TRUE(aborted.Aborted) << stopAt;
    EXPECT_TRUE(aborted.Labels.empty());
    EXPECT_EQ(aborted.Probabilities.size(), 0);
  }
}

TEST(Partition, BadInputThrows)
{
  const TwoLevelCapsule shape;
  const Eigen::VectorXd tooFew = shape.Values.head(shape.Values.size() - 1);
  EXPECT_THROW(PartitionBySDF(shape.Mesh.Points, shape.Mesh.Triangles, tooFew), Error);
  EXPECT_THROW(PartitionBySDF(shape.Mesh.Points, TriangleMatrix(0, 3), Eigen::VectorXd()), Error);
  PartitionOptions options;
  options.HistogramBins = 0;
  EXPECT_THROW(ValidatePartitionOptions(options), Error);
  EXPECT_THROW(PartitionBySDF(shape.Mesh.Points, shape.Mesh.Triangles, shape.Values, options), Error);
  options = PartitionOptions();
  options.NumberOfClusters = -1;
  EXPECT_THROW(PartitionBySDF(shape.Mesh.Points, shape.Mesh.Triangles, shape.Values, options), Error);
  Eigen::VectorXd notFinite = shape.Values;
  notFinite[3] = std::nan("");
  EXPECT_THROW(PartitionBySDF(shape.Mesh.Points, shape.Mesh.Triangles, notFinite), std::runtime_error);
}

} // namespace
