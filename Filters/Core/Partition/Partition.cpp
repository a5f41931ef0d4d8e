// SPDX-License-Identifier: BSD-3-Clause
#include "Partition/Partition.h"

#include "Partition/CoarseningCells.h"
#include "Partition/DistributedPartition.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <utility>

namespace shapediameter
{
namespace
{
using Clock = std::chrono::steady_clock;

/// Milliseconds since `start`, and restarts it.
double Lap(Clock::time_point& start)
{
  const Clock::time_point now = Clock::now();
  const double ms = std::chrono::duration<double, std::milli>(now - start).count();
  start = now;
  return ms;
}

PartitionResult AbortedResult()
{
  PartitionResult result;
  result.Aborted = true;
  return result;
}

/// Throws Error unless there is one value per face.
void CheckValueCount(ValuesView values, std::size_t faceCount)
{
  if (static_cast<std::size_t>(values.size()) != faceCount)
  {
    throw Error("partition: " + std::to_string(values.size()) + " values for " + std::to_string(faceCount) + " faces");
  }
}

/// The refinement's options with the partition's own energy and cut.
PartRefinementOptions RefinementOptions(const PartitionOptions& options)
{
  PartRefinementOptions refinement = options.Refinement;
  refinement.Energy = options.Energy;
  refinement.Multilevel = options.Multilevel;
  refinement.AlphaExpansion = options.AlphaExpansion;
  return refinement;
}

} // namespace

GaussianMixtureModel FitClusterModel(ValuesView values, const std::vector<double>& faceAreas, const PartitionOptions& options)
{
  if (options.ClusterModel == PartitionClusterModel::DensityModes)
  {
    DensityModesOptions modes = options.Modes;
    modes.MaximumModes = options.NumberOfClusters > 0 ? options.NumberOfClusters : options.MaximumClusters;
    const Eigen::Map<const Eigen::VectorXd> areas(faceAreas.data(), static_cast<Eigen::Index>(faceAreas.size()));
    return FitDensityModes(values, areas, modes).Model;
  }
  return options.NumberOfClusters == 0
    ? FitGaussianMixtureBic(values, 2, options.MaximumClusters, options.Mixture).Model
    : FitGaussianMixture(values, options.NumberOfClusters, options.Mixture);
}

void ValidatePartitionOptions(const PartitionOptions& options)
{
  CheckRange(options.NumberOfClusters, NumberOfClustersRange, "partition: NumberOfClusters");
  CheckRange(options.MaximumClusters, MaximumClustersRange, "partition: MaximumClusters");
  CheckRange(options.HistogramBins, HistogramBinsRange, "partition: HistogramBins");
  CheckRange(options.Modes.Bandwidth, ModeBandwidthRange, "partition: Modes.Bandwidth");
  CheckRange(options.Modes.MinimumProminence, ModeProminenceRange, "partition: Modes.MinimumProminence");
  CheckRange(options.Modes.MinimumValleyDepth, ModeValleyDepthRange, "partition: Modes.MinimumValleyDepth");
  ValidatePartRefinementOptions(options.Refinement);
}

PartitionResult PartitionBySDF(const PartitionInput& input, const PartitionOptions& options,
  const ParallelFor& parallelFor, const ProgressCallback& progress)
{
  ValidatePartitionOptions(options);
  const std::size_t faceCount = input.FaceOffsets.empty() ? 0 : input.FaceOffsets.size() - 1;
  if (faceCount == 0 && !input.Share)
  {
    throw Error("partition: no faces");
  }
  CheckValueCount(input.FaceValues, faceCount);
  if (input.Share)
  {
    return PartitionOverProcesses(input, *input.Share, options, parallelFor, progress);
  }
  Clock::time_point start = Clock::now();

  // 1. The dual graph.
  std::shared_ptr<const FaceGraph> graph =
    SharedFaceGraph(input.Points, input.FaceOffsets, input.FaceConnectivity, parallelFor);
  const double faceGraphMs = Lap(start);
  if (progress && !progress(0.1))
  {
    return AbortedResult();
  }
  PartitionResult result = PartitionOnDualGraph(
    MakeDualGraphView(*graph), graph->Areas, input.FaceValues, input.FamilyModel, options, parallelFor, progress);
  result.Graph = std::move(graph);
  result.Timings.FaceGraphMs = faceGraphMs;
  return result;
}

PartitionResult PartitionOnDualGraph(DualGraphView view, const std::vector<double>& areas, ValuesView faceValues,
  const GaussianMixtureModel* familyModel, const PartitionOptions& options, const ParallelFor& parallelFor,
  const ProgressCallback& progress, const std::function<void()>& releaseEdgeGeometry)
{
  ValidatePartitionOptions(options);
  if (view.FaceCount == 0)
  {
    throw Error("partition: no faces");
  }
  CheckValueCount(faceValues, view.FaceCount);
  if (areas.size() != view.FaceCount)
  {
    throw Error("partition: " + std::to_string(areas.size()) + " face areas for " + std::to_string(view.FaceCount) +
      " faces");
  }
  view.FaceArea = areas.data();
  PartitionResult result;
  Clock::time_point start = Clock::now();

  // 2. The cluster model, 3. the soft partition.
  result.Model = familyModel ? *familyModel : FitClusterModel(faceValues, areas, options);
  result.Timings.ClusterModelMs = Lap(start);
  result.Probabilities = ComputePosteriors(result.Model, faceValues, parallelFor);
  result.Timings.PosteriorsMs = Lap(start);
  if (progress && !progress(0.2))
  {
    return AbortedResult();
  }

  // 4. The energy; the graph is checked here once, for the energy and the segments.
  ValidateDualGraph(view, options.Energy.GeometricWeights, parallelFor);
  std::optional<PartitionEnergy> energy =
    BuildPartitionEnergyOnValidGraph(result.Probabilities, view, options.Energy, parallelFor);
  // The cut does not read the posteriors: they are freed during it and computed again after
  // it (the same function of the same values, so the same bits). The cut is the step's peak,
  // which this lowers by k doubles per face (33 MB at 832k faces and k = 5).
  result.Probabilities = PosteriorMatrix();
  std::vector<std::uint64_t> cells;
  if (view.FaceCount > options.Multilevel.DirectBelowFaces)
  {
    cells = CoarseningCells(view, options.Multilevel.ClusterSize);
  }
  if (releaseEdgeGeometry && !options.Refinement.Enabled)
  {
    releaseEdgeGeometry();
    view.NormalAngle = nullptr;
    view.Concave = nullptr;
    view.EdgeLength = nullptr;
    view.FaceCenter = nullptr;
  }
  result.Timings.EnergyMs = Lap(start);

  // 5. The k-way graph cut.
  AlphaExpansionResult cut = MinimizeMultilevel(
    *energy, options.Multilevel, options.AlphaExpansion, SubProgress(progress, 0.2, 0.95), parallelFor, cells);
  if (!cut.Aborted)
  {
    cut.Energy = energy->EvaluateExactly(cut.Labels);
  }
  energy.reset();
  cells = std::vector<std::uint64_t>();
  result.Timings.CutMs = Lap(start);
  if (cut.Aborted)
  {
    return AbortedResult();
  }
  result.Probabilities = ComputePosteriors(result.Model, faceValues, parallelFor);
  result.Timings.PosteriorsMs += Lap(start);
  result.Labels = std::move(cut.Labels);
  result.Energy = cut.Energy;
  result.CutMoves = cut.Moves;

  // 6. The hierarchy of the bands and their segments.
  result.Bands = std::move(result.Labels);
  result.Segments = FindConnectedSegmentsOnValidGraph(view, result.Bands, areas);
  for (int level = 1; level < result.Model.ComponentCount(); ++level)
  {
    result.Levels.push_back(HierarchyLevel(result.Bands, level));
  }
  result.Timings.SegmentsMs = Lap(start);

  // 7. The fine level.
  if (options.Refinement.Enabled)
  {
    PartRefinementResult fine = RefineParts(
      view, faceValues, result.Bands, result.Segments, RefinementOptions(options), parallelFor);
    result.Labels = std::move(fine.Labels);
    result.LabelBands = std::move(fine.LabelBand);
    result.Segments = FindConnectedSegmentsOnValidGraph(view, result.Labels, areas);
  }
  else
  {
    result.Labels = result.Bands;
    for (int band = 0; band < result.Model.ComponentCount(); ++band)
    {
      result.LabelBands.push_back(band);
    }
  }
  result.Timings.RefinementMs = Lap(start);

  // 8. The histogram with the fitted densities.
  result.Histogram = MixtureHistogram(result.Model, faceValues, options.HistogramBins);
  result.Timings.HistogramMs = Lap(start);
  if (progress)
  {
    progress(1.0); // the result is complete: an abort requested now has nothing left to stop
  }
  return result;
}

PartitionResult PartitionBySDF(PointsView points, TrianglesView triangles, ValuesView faceValues,
  const PartitionOptions& options, const ParallelFor& parallelFor, const ProgressCallback& progress)
{
  std::vector<std::int64_t> offsets, connectivity;
  TriangleFaces(triangles, offsets, connectivity);
  return PartitionBySDF(PartitionInput{ points, offsets, connectivity, faceValues }, options, parallelFor, progress);
}

PartitionHistogram MixtureHistogram(const GaussianMixtureModel& model, ValuesView values, int bins)
{
  if (values.size() == 0 || bins < 1 || model.ComponentCount() == 0 ||
    model.Sigmas.size() != model.Means.size() || model.Weights.size() != model.Means.size())
  {
    throw Error("histogram: needs values, bins >= 1 and a model with components");
  }
  const double sigmaMax = *std::max_element(model.Sigmas.begin(), model.Sigmas.end());
  const double low = values.minCoeff() - 4.0 * sigmaMax;
  const double high = values.maxCoeff() + 4.0 * sigmaMax;
  const double width = (high - low) / bins;
  const auto count = static_cast<double>(values.size());
  const auto binCount = static_cast<std::size_t>(bins);
  PartitionHistogram histogram;
  histogram.BinCenters.resize(binCount);
  histogram.Counts.assign(binCount, 0.0);
  histogram.Mixture.assign(binCount, 0.0);
  for (int b = 0; b < bins; ++b)
  {
    histogram.BinCenters[static_cast<std::size_t>(b)] = low + (b + 0.5) * width;
  }
  for (Eigen::Index i = 0; i < values.size(); ++i)
  {
    const int bin = std::min(bins - 1, std::max(0, static_cast<int>((values[i] - low) / width)));
    histogram.Counts[static_cast<std::size_t>(bin)] += 1.0;
  }
  histogram.Density.resize(binCount);
  std::transform(histogram.Counts.begin(), histogram.Counts.end(), histogram.Density.begin(),
    [&](double c) { return c / (count * width); });
  for (int c = 0; c < model.ComponentCount(); ++c)
  {
    const auto component = static_cast<std::size_t>(c);
    std::vector<double> curve(binCount);
    // The mean density over each bin (not its value at the centre): comparable with the
    // histogram bar, and exact for Gaussians narrower than a bin.
    const double scale = 1.0 / (model.Sigmas[component] * std::sqrt(2.0));
    auto cumulative = [&](double x) { return 0.5 * std::erf((x - model.Means[component]) * scale); };
    for (std::size_t b = 0; b < binCount; ++b)
    {
      const double left = histogram.BinCenters[b] - 0.5 * width;
      curve[b] = model.Weights[component] * (cumulative(left + width) - cumulative(left)) / width;
      histogram.Mixture[b] += curve[b];
    }
    histogram.Components.push_back(std::move(curve));
  }
  return histogram;
}

} // namespace shapediameter
