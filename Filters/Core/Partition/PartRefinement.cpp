// SPDX-License-Identifier: BSD-3-Clause
#include "Partition/PartRefinement.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <tuple>

namespace shapediameter
{
namespace
{

/// The faces and inner edges of one part, in the part's own face numbering.
struct PartGraph
{
  std::vector<std::int64_t> Offsets{ 0 };
  std::vector<std::int64_t> Neighbors;
  std::vector<double> NormalAngle;
  std::vector<std::uint8_t> Concave;
  std::vector<double> EdgeLength;
  std::vector<double> FaceArea;

  DualGraphView View() const
  {
    DualGraphView view;
    view.Offsets = Offsets.data();
    view.Neighbors = Neighbors.data();
    view.NormalAngle = NormalAngle.data();
    view.Concave = Concave.data();
    view.EdgeLength = EdgeLength.empty() ? nullptr : EdgeLength.data();
    view.FaceArea = FaceArea.data();
    view.FaceCount = FaceArea.size();
    return view;
  }
};

PartGraph ExtractPart(const DualGraphView& graph, const std::vector<std::int64_t>& faces,
  const std::vector<int>& segmentOf, const std::vector<std::int64_t>& localIndex)
{
  PartGraph part;
  part.Offsets.reserve(faces.size() + 1);
  part.FaceArea.reserve(faces.size());
  for (const std::int64_t face : faces)
  {
    const auto f = static_cast<std::size_t>(face);
    for (std::int64_t e = graph.Offsets[f]; e < graph.Offsets[f + 1]; ++e)
    {
      const auto g = static_cast<std::size_t>(graph.Neighbors[e]);
      if (segmentOf[g] != segmentOf[f])
      {
        continue;
      }
      part.Neighbors.push_back(localIndex[g]);
      part.NormalAngle.push_back(graph.NormalAngle[e]);
      part.Concave.push_back(graph.Concave[e]);
      if (graph.EdgeLength)
      {
        part.EdgeLength.push_back(graph.EdgeLength[e]);
      }
    }
    part.Offsets.push_back(static_cast<std::int64_t>(part.Neighbors.size()));
    part.FaceArea.push_back(graph.FaceArea ? graph.FaceArea[f] : 1.0);
  }
  return part;
}

/// The fine labels of one part: local label per face (0 when it is kept whole) and one entry
/// per local label (more than one: the part was refined).
struct PartLabels
{
  std::vector<int> Local;
  int Count = 1;
};

PartLabels CutPart(const DualGraphView& graph, ValuesView values, const std::vector<std::int64_t>& faces,
  const std::vector<int>& segmentOf, const std::vector<std::int64_t>& localIndex, double totalArea,
  double valueRange, bool refine, const PartRefinementOptions& options)
{
  Eigen::VectorXd partValues(static_cast<Eigen::Index>(faces.size()));
  std::vector<double> areas(faces.size());
  for (std::size_t i = 0; i < faces.size(); ++i)
  {
    const auto f = static_cast<std::size_t>(faces[i]);
    partValues[static_cast<Eigen::Index>(i)] = values[static_cast<Eigen::Index>(f)];
    areas[i] = graph.FaceArea ? graph.FaceArea[f] : 1.0;
  }
  PartLabels labels{ std::vector<int>(faces.size(), 0), 1 };
  const double partArea = std::accumulate(areas.begin(), areas.end(), 0.0);
  const double partRange = partValues.maxCoeff() - partValues.minCoeff();
  if (!refine || faces.size() < 2 || !(partArea > 0.0) || !(partRange > 0.0) || !(valueRange > 0.0))
  {
    return labels;
  }
  DensityModesOptions modes = options.Modes;
  modes.Bandwidth = std::min(1.0, options.Modes.Bandwidth * valueRange / partRange);
  const Eigen::Map<const Eigen::VectorXd> weights(areas.data(), static_cast<Eigen::Index>(areas.size()));
  const GaussianMixtureModel model = FitDensityModes(partValues, weights, modes).Model;
  if (model.ComponentCount() < 2)
  {
    return labels;
  }
  const PartGraph part = ExtractPart(graph, faces, segmentOf, localIndex);
  PartitionEnergyOptions energyOptions = options.Energy;
  if (energyOptions.GeometricWeights)
  {
    energyOptions.Lambda *= std::sqrt(totalArea / partArea);
  }
  const PartitionEnergy energy =
    BuildPartitionEnergyOnValidGraph(ComputePosteriors(model, partValues), part.View(), energyOptions);
  labels.Local = MinimizeMultilevel(energy, options.Multilevel, options.AlphaExpansion).Labels;
  // The components the cut used, renumbered densely in the model's order (largest mean
  // first); one used = the part stays whole.
  std::vector<int> dense(static_cast<std::size_t>(model.ComponentCount()), -1);
  for (const int label : labels.Local)
  {
    dense[static_cast<std::size_t>(label)] = 0;
  }
  int used = 0;
  for (int& id : dense)
  {
    id = id < 0 ? -1 : used++;
  }
  for (int& label : labels.Local)
  {
    label = dense[static_cast<std::size_t>(label)];
  }
  if (used < 2)
  {
    std::fill(labels.Local.begin(), labels.Local.end(), 0);
    used = 1;
  }
  labels.Count = used;
  return labels;
}

} // namespace

void ValidatePartRefinementOptions(const PartRefinementOptions& options)
{
  CheckRange(options.MinimumAreaShare, RefinementMinimumAreaRange, "part refinement: MinimumAreaShare");
  if (options.Modes.MaximumModes < 1)
  {
    throw Error("part refinement: at least one mode per part");
  }
}

PartRefinementResult RefineParts(const DualGraphView& graph, ValuesView values, const std::vector<int>& bands,
  const ConnectedSegments& segments, const PartRefinementOptions& options, const ParallelFor& parallelFor,
  const ProgressCallback& progress)
{
  ValidatePartRefinementOptions(options);
  const std::size_t faceCount = graph.FaceCount;
  const auto partCount = static_cast<std::size_t>(segments.SegmentCount());
  PartRefinementResult result;
  if (progress && !progress(0.0))
  {
    result.Aborted = true;
    return result;
  }
  std::vector<std::vector<std::int64_t>> partFaces(partCount);
  std::vector<std::int64_t> localIndex(faceCount);
  for (std::size_t f = 0; f < faceCount; ++f)
  {
    auto& faces = partFaces[static_cast<std::size_t>(segments.Segment[f])];
    localIndex[f] = static_cast<std::int64_t>(faces.size());
    faces.push_back(static_cast<std::int64_t>(f));
  }
  const double totalArea = std::accumulate(segments.Area.begin(), segments.Area.end(), 0.0);
  const double valueRange = faceCount > 0 ? values.maxCoeff() - values.minCoeff() : 0.0;

  std::vector<PartLabels> parts(partCount);
  parallelFor(partCount, [&](std::size_t begin, std::size_t end) {
    for (std::size_t s = begin; s < end; ++s)
    {
      const bool refine = options.Enabled && segments.Area[s] >= options.MinimumAreaShare * totalArea;
      parts[s] = CutPart(graph, values, partFaces[s], segments.Segment, localIndex, totalArea, valueRange, refine, options);
    }
  });

  // Number the fine labels: one per (band, level within the part), level 0 = a part's
  // thickest fine label; in band order, then level order. A part kept whole is level 0 of its
  // band, so the fine labels of a band are its levels, the same kind of region in every part.
  std::vector<std::vector<int>> fineOf;
  for (std::size_t s = 0; s < partCount; ++s)
  {
    const auto band = static_cast<std::size_t>(segments.Label[s]);
    result.RefinedParts += parts[s].Count > 1 ? 1 : 0;
    if (fineOf.size() <= band)
    {
      fineOf.resize(band + 1);
    }
    if (fineOf[band].size() < static_cast<std::size_t>(parts[s].Count))
    {
      fineOf[band].resize(static_cast<std::size_t>(parts[s].Count), 0);
    }
  }
  int next = 0;
  for (std::size_t band = 0; band < fineOf.size(); ++band)
  {
    for (int& id : fineOf[band])
    {
      id = next++;
      result.LabelBand.push_back(static_cast<int>(band));
    }
  }
  std::vector<double> sum(result.LabelBand.size(), 0.0), weight(result.LabelBand.size(), 0.0);
  result.Labels.resize(faceCount);
  for (std::size_t f = 0; f < faceCount; ++f)
  {
    const auto s = static_cast<std::size_t>(segments.Segment[f]);
    const int level = parts[s].Local[static_cast<std::size_t>(localIndex[f])];
    const int fine = fineOf[static_cast<std::size_t>(segments.Label[s])][static_cast<std::size_t>(level)];
    result.Labels[f] = fine;
    const double area = graph.FaceArea ? graph.FaceArea[f] : 1.0;
    sum[static_cast<std::size_t>(fine)] += area * values[static_cast<Eigen::Index>(f)];
    weight[static_cast<std::size_t>(fine)] += area;
  }
  for (std::size_t label = 0; label < sum.size(); ++label)
  {
    result.LabelMean.push_back(weight[label] > 0.0 ? sum[label] / weight[label] : 0.0);
  }
  (void)bands;
  if (progress)
  {
    progress(1.0);
  }
  return result;
}

} // namespace shapediameter
