// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSDFGMMPartition.h"

#include "MultilevelCut.h"
#include "FaceGraph.h"
#include "DensityModes.h"
#include "GaussianMixture.h"
#include "PartitionEnergy.h"
#include "DistributedSupport.h"
#include "SurfaceConversion.h"
#include "vtkSDFBilateralSmooth.h"

#include "vtkCellData.h"
#include "vtkDataObject.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPolyData.h"
#include "vtkTable.h"

#include <algorithm>
#include <cmath>
#include <string>

vtkStandardNewMacro(vtkSDFGMMPartition);

namespace
{
using namespace shapediameter;

vtkSmartPointer<vtkDoubleArray> DoubleArray(const char* name, const std::vector<double>& values)
{
  return adapter::MakeArray<vtkDoubleArray>(name, values);
}

/// An int cell array over all cells: `fill` outside [first, first + values.size()).
vtkNew<vtkIntArray> CellIntArray(const std::string& name, vtkIdType cellCount, vtkIdType first,
  const std::vector<int>& values, int fill = -1)
{
  vtkNew<vtkIntArray> array;
  array->SetName(name.c_str());
  array->SetNumberOfTuples(cellCount);
  array->FillValue(fill);
  std::copy(values.begin(), values.end(), array->GetPointer(first));
  return array;
}

/// The histogram of the values and the weighted Gaussian densities (see the header).
void FillHistogram(const GaussianMixtureModel& model, const Eigen::Ref<const Eigen::VectorXd>& values, int bins,
  vtkTable* table)
{
  const double sigmaMax = *std::max_element(model.sigmas.begin(), model.sigmas.end());
  const double low = values.minCoeff() - 4.0 * sigmaMax;
  const double high = values.maxCoeff() + 4.0 * sigmaMax;
  const double width = (high - low) / bins;
  const auto count = static_cast<double>(values.size());
  std::vector<double> centers(static_cast<std::size_t>(bins)), counts(static_cast<std::size_t>(bins), 0.0);
  for (int b = 0; b < bins; ++b)
  {
    centers[static_cast<std::size_t>(b)] = low + (b + 0.5) * width;
  }
  for (Eigen::Index i = 0; i < values.size(); ++i)
  {
    const int bin = std::min(bins - 1, std::max(0, static_cast<int>((values[i] - low) / width)));
    counts[static_cast<std::size_t>(bin)] += 1.0;
  }
  std::vector<double> density(counts.size()), mixture(counts.size(), 0.0);
  std::transform(counts.begin(), counts.end(), density.begin(), [&](double c) { return c / (count * width); });
  table->AddColumn(DoubleArray("BinCenter", centers));
  table->AddColumn(DoubleArray("Count", counts));
  table->AddColumn(DoubleArray("Density", density));
  for (int c = 0; c < model.ComponentCount(); ++c)
  {
    std::vector<double> curve(counts.size());
    // The mean density over each bin (not its value at the centre): comparable with the
    // histogram bar, and exact for Gaussians narrower than a bin.
    const double scale = 1.0 / (model.sigmas[static_cast<std::size_t>(c)] * std::sqrt(2.0));
    auto cumulative = [&](double x) { return 0.5 * std::erf((x - model.means[static_cast<std::size_t>(c)]) * scale); };
    for (std::size_t b = 0; b < curve.size(); ++b)
    {
      const double left = centers[b] - 0.5 * width;
      curve[b] = model.weights[static_cast<std::size_t>(c)] * (cumulative(left + width) - cumulative(left)) / width;
      mixture[b] += curve[b];
    }
    table->AddColumn(DoubleArray(("Component" + std::to_string(c)).c_str(), curve));
  }
  table->AddColumn(DoubleArray("Mixture", mixture));
}

/// The mixture stored in a partition output's field data; empty reason on success.
std::string ReadModel(vtkDataObject* modelData, GaussianMixtureModel& model)
{
  vtkFieldData* field = modelData ? modelData->GetFieldData() : nullptr;
  auto read = [field](const char* name, std::vector<double>& values) {
    vtkDataArray* array = field ? vtkDataArray::SafeDownCast(field->GetAbstractArray(name)) : nullptr;
    values.clear();
    if (array && array->GetNumberOfComponents() == 1)
    {
      for (vtkIdType i = 0; i < array->GetNumberOfTuples(); ++i)
      {
        values.push_back(array->GetComponent(i, 0));
      }
    }
    return !values.empty();
  };
  if (!read(vtkSDFGMMPartition::MEANS_ARRAY_NAME, model.means) ||
    !read(vtkSDFGMMPartition::SIGMAS_ARRAY_NAME, model.sigmas) ||
    !read(vtkSDFGMMPartition::WEIGHTS_ARRAY_NAME, model.weights))
  {
    return "the Model input has no SDFGMMMeans/SDFGMMSigmas/SDFGMMWeights field arrays";
  }
  if (model.sigmas.size() != model.means.size() || model.weights.size() != model.means.size())
  {
    return "the Model's mixture arrays differ in length";
  }
  for (std::size_t c = 0; c < model.means.size(); ++c)
  {
    if (!std::isfinite(model.means[c]) || !(model.sigmas[c] > 0) || !std::isfinite(model.sigmas[c]) ||
      !(model.weights[c] > 0) || !std::isfinite(model.weights[c]))
    {
      return "the Model's mixture has a non-finite mean or a non-positive sigma or weight";
    }
  }
  return {};
}
} // namespace

vtkSDFGMMPartition::vtkSDFGMMPartition()
{
  this->SetNumberOfInputPorts(2);
  this->SetNumberOfOutputPorts(2);
  this->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS,
    vtkSDFBilateralSmooth::NORMALIZED_ARRAY_NAME);
}

vtkSDFGMMPartition::~vtkSDFGMMPartition() = default;

int vtkSDFGMMPartition::FillInputPortInformation(int port, vtkInformation* info)
{
  if (port == 1)
  {
    info->Set(vtkAlgorithm::INPUT_REQUIRED_DATA_TYPE(), "vtkDataObject");
    info->Set(vtkAlgorithm::INPUT_IS_OPTIONAL(), 1);
    return 1;
  }
  return this->Superclass::FillInputPortInformation(port, info);
}

int vtkSDFGMMPartition::FillOutputPortInformation(int port, vtkInformation* info)
{
  if (port == 1)
  {
    info->Set(vtkDataObject::DATA_TYPE_NAME(), "vtkTable");
    return 1;
  }
  return this->Superclass::FillOutputPortInformation(port, info);
}

vtkTable* vtkSDFGMMPartition::GetHistogram()
{
  return vtkTable::SafeDownCast(this->GetOutputDataObject(1));
}

int vtkSDFGMMPartition::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  // ---- Distributed runs (Filters/DistributedSupport.h): under MPI this serial body runs
  // once, on process 0, on the whole surface gathered in its original order; every process
  // gets its own cells back with the new arrays.
  if (shapediameter::distributed::IsDistributedRequest(inputVector, outputVector))
  {
    return shapediameter::distributed::RunOnWholeSurface(this, inputVector, outputVector, { 0 },
      [this](vtkInformationVector** in, vtkInformationVector* out) { return this->RequestData(nullptr, in, out); });
  }
  // ---- end of distributed runs
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector);
  output->ShallowCopy(input);
  if (input->GetNumberOfCells() == 0)
  {
    vtkWarningMacro("The input is empty: nothing to partition.");
    return 1;
  }
  if (input->GetNumberOfPolys() == 0)
  {
    vtkErrorMacro("Cannot partition: the input has no polygons.");
    return 1;
  }
  std::vector<double> values;
  std::string arrayName;
  std::string reason = adapter::ReadCellScalars(this, input, vtkSDFBilateralSmooth::NORMALIZED_ARRAY_NAME, values, arrayName);
  GaussianMixtureModel model;
  vtkDataObject* modelInput = this->GetNumberOfInputConnections(1) > 0
    ? inputVector[1]->GetInformationObject(0)->Get(vtkDataObject::DATA_OBJECT())
    : nullptr;
  if (reason.empty() && modelInput)
  {
    reason = ReadModel(modelInput, model);
  }
  if (!reason.empty())
  {
    vtkErrorMacro("Cannot partition: " << reason << ".");
    return 1;
  }

  try
  {
    const ParallelFor parallelFor = adapter::MakeSMPParallelFor(this->NumberOfThreads);
    // The polygon cells alone: verts and lines come first and have empty entries.
    std::vector<std::int64_t> offsets, connectivity;
    adapter::PolygonCells(input, offsets, connectivity);
    const auto [first, last] = adapter::PolygonCellRange(input);
    offsets.erase(offsets.begin() + last + 1, offsets.end());
    offsets.erase(offsets.begin(), offsets.begin() + first);
    const FaceGraph graph = BuildFaceGraph(adapter::PointsOf(input), offsets, connectivity, parallelFor);
    const Eigen::Map<const Eigen::VectorXd> faceValues(values.data() + first, last - first);
    this->UpdateProgress(0.1);

    if (!modelInput && this->ClusterModel == 1)
    {
      DensityModesOptions modes;
      modes.Bandwidth = this->ModeBandwidth;
      modes.MinimumProminence = this->ModeProminence;
      modes.MaximumModes = this->NumberOfClusters > 0 ? this->NumberOfClusters : this->MaximumClusters;
      const Eigen::Map<const Eigen::VectorXd> areas(graph.Areas.data(), static_cast<Eigen::Index>(graph.Areas.size()));
      model = FitDensityModes(faceValues, areas, modes).Model;
    }
    else if (!modelInput)
    {
      GaussianMixtureOptions fit;
      fit.restarts = this->Restarts;
      fit.maxIterations = this->MaximumIterations;
      fit.seed = static_cast<std::uint64_t>(static_cast<std::uint32_t>(this->Seed));
      model = this->NumberOfClusters == 0
        ? FitGaussianMixtureBic(faceValues, 2, this->MaximumClusters, fit).model
        : FitGaussianMixture(faceValues, this->NumberOfClusters, fit);
    }
    const int clusterCount = model.ComponentCount();
    const PosteriorMatrix posteriors = ComputePosteriors(model, faceValues, parallelFor);
    this->UpdateProgress(0.2);

    const DualGraphView view = MakeDualGraphView(graph);
    PartitionEnergyOptions energyOptions;
    energyOptions.lambda = this->Lambda;
    energyOptions.probabilityEpsilon = this->Epsilon;
    energyOptions.convexityFactor = this->ConvexityFactor;
    const PartitionEnergy energy = BuildPartitionEnergy(posteriors, view, energyOptions, parallelFor);
    const AlphaExpansionResult cut =
      MinimizeMultilevel(energy, MultilevelOptions(), AlphaExpansionOptions(), adapter::MakeProgress(this, 0.2, 0.95), parallelFor);
    if (cut.aborted)
    {
      output->ShallowCopy(input);
      return 1;
    }
    const ConnectedSegments segments = FindConnectedSegments(view, cut.labels, graph.Areas, parallelFor);

    const vtkIdType cellCount = input->GetNumberOfCells();
    vtkNew<vtkDoubleArray> probabilities;
    probabilities->SetName(PROBABILITIES_ARRAY_NAME);
    probabilities->SetNumberOfComponents(clusterCount);
    probabilities->SetNumberOfTuples(cellCount);
    probabilities->FillValue(0.0);
    std::copy(posteriors.data(), posteriors.data() + posteriors.size(),
      probabilities->GetPointer(first * clusterCount));
    vtkCellData* cellData = output->GetCellData();
    cellData->AddArray(probabilities);
    cellData->AddArray(CellIntArray(CLUSTER_ARRAY_NAME, cellCount, first, cut.labels));
    for (int level = 1; level < clusterCount; ++level)
    {
      cellData->AddArray(CellIntArray(LEVEL_ARRAY_PREFIX + std::to_string(level), cellCount, first,
        HierarchyLevel(cut.labels, level)));
    }
    cellData->AddArray(CellIntArray(SEGMENT_ARRAY_NAME, cellCount, first, segments.segment));
    cellData->SetActiveScalars(CLUSTER_ARRAY_NAME);

    vtkNew<vtkFieldData> field;
    field->ShallowCopy(input->GetFieldData());
    field->AddArray(DoubleArray(MEANS_ARRAY_NAME, model.means));
    field->AddArray(DoubleArray(SIGMAS_ARRAY_NAME, model.sigmas));
    field->AddArray(DoubleArray(WEIGHTS_ARRAY_NAME, model.weights));
    vtkNew<vtkIntArray> count;
    count->SetName(CLUSTER_COUNT_ARRAY_NAME);
    count->InsertNextValue(clusterCount);
    field->AddArray(count);
    field->AddArray(DoubleArray(ENERGY_ARRAY_NAME, { cut.energy }));
    output->SetFieldData(field);
    FillHistogram(model, faceValues, this->HistogramBins, vtkTable::GetData(outputVector, 1));
  }
  catch (const std::exception& error)
  {
    vtkErrorMacro("Cannot partition: " << error.what());
    output->ShallowCopy(input);
    return 1;
  }
  this->UpdateProgress(1.0);
  return 1;
}

void vtkSDFGMMPartition::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "NumberOfClusters: " << this->NumberOfClusters << "\n";
  os << indent << "MaximumClusters: " << this->MaximumClusters << "\n";
  os << indent << "Lambda: " << this->Lambda << "\n";
  os << indent << "Epsilon: " << this->Epsilon << "\n";
  os << indent << "ConvexityFactor: " << this->ConvexityFactor << "\n";
  os << indent << "Restarts: " << this->Restarts << "\n";
  os << indent << "MaximumIterations: " << this->MaximumIterations << "\n";
  os << indent << "Seed: " << this->Seed << "\n";
  os << indent << "HistogramBins: " << this->HistogramBins << "\n";
  os << indent << "ClusterModel: " << this->ClusterModel << "\n";
  os << indent << "ModeBandwidth: " << this->ModeBandwidth << "\n";
  os << indent << "ModeProminence: " << this->ModeProminence << "\n";
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
}
