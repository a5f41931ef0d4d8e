// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSDFGMMPartition.h"

#include "DistributedSupport.h"
#include "Partition/DistributedPartition.h"
#include "Partition/Partition.h"
#include "SurfaceConversion.h"
#include "SurfaceRequest.h"
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
#include <iostream>
#include <optional>
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

/// Output port 1: the histogram and the fitted densities as table columns (see the header).
void WriteHistogram(const PartitionHistogram& histogram, vtkTable* table)
{
  table->AddColumn(DoubleArray("BinCenter", histogram.BinCenters));
  table->AddColumn(DoubleArray("Count", histogram.Counts));
  table->AddColumn(DoubleArray("Density", histogram.Density));
  for (std::size_t c = 0; c < histogram.Components.size(); ++c)
  {
    table->AddColumn(DoubleArray(("Component" + std::to_string(c)).c_str(), histogram.Components[c]));
  }
  table->AddColumn(DoubleArray("Mixture", histogram.Mixture));
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
  if (!read(vtkSDFGMMPartition::MEANS_ARRAY_NAME, model.Means) ||
    !read(vtkSDFGMMPartition::SIGMAS_ARRAY_NAME, model.Sigmas) ||
    !read(vtkSDFGMMPartition::WEIGHTS_ARRAY_NAME, model.Weights))
  {
    return "the Model input has no SDFGMMMeans/SDFGMMSigmas/SDFGMMWeights field arrays";
  }
  if (model.Sigmas.size() != model.Means.size() || model.Weights.size() != model.Means.size())
  {
    return "the Model's mixture arrays differ in length";
  }
  for (std::size_t c = 0; c < model.Means.size(); ++c)
  {
    if (!std::isfinite(model.Means[c]) || !(model.Sigmas[c] > 0) || !std::isfinite(model.Sigmas[c]) ||
      !(model.Weights[c] > 0) || !std::isfinite(model.Weights[c]))
    {
      return "the Model's mixture has a non-finite mean or a non-positive sigma or weight";
    }
  }
  return {};
}
} // namespace

vtkSDFGMMPartition::vtkSDFGMMPartition()
  : vtkSDFSurfaceAlgorithm("partition", "nothing to partition", 0, false)
{
  // The defaults live in the core's options (Filters/Core/Partition/Partition.h); the XML mirrors them.
  const shapediameter::PartitionOptions defaults;
  this->NumberOfClusters = defaults.NumberOfClusters;
  this->MaximumClusters = defaults.MaximumClusters;
  this->Lambda = defaults.Energy.Lambda;
  this->Epsilon = defaults.Energy.Epsilon;
  this->ConvexityFactor = defaults.Energy.ConvexityFactor;
  this->Restarts = defaults.Mixture.Restarts;
  this->MaximumIterations = defaults.Mixture.MaximumIterations;
  this->Seed = static_cast<int>(defaults.Mixture.Seed);
  this->HistogramBins = defaults.HistogramBins;
  this->ClusterModel = defaults.ClusterModel == shapediameter::PartitionClusterModel::ExpectationMaximization ? 0 : 1;
  this->ModeBandwidth = defaults.Modes.Bandwidth;
  this->ModeProminence = defaults.Modes.MinimumProminence;
  this->ModeValleyDepth = defaults.Modes.MinimumValleyDepth;
  this->RefineParts = defaults.Refinement.Enabled;
  this->RefinementMinimumArea = defaults.Refinement.MinimumAreaShare;
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

std::vector<std::string> vtkSDFGMMPartition::CellArraysRead()
{
  return this->WithSelectedArray({ vtkSDFBilateralSmooth::NORMALIZED_ARRAY_NAME });
}

double vtkSDFGMMPartition::HaloRadius(vtkPolyData* piece, const shapediameter::ProcessGroup& group)
{
  // Any size finds every shared corner; about two edges gives a halo of one or two rings.
  return 2.0 * MeanEdgeLengthOverPieces(piece, group);
}

bool vtkSDFGMMPartition::ExecuteSurface(const shapediameter::adapter::SurfaceRequest& request)
{
  using namespace shapediameter;
  vtkPolyData* input = request.Input;
  vtkPolyData* output = request.Output;
  vtkInformationVector** inputVector = request.InputVector;
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
    throw shapediameter::Error(reason + "."); // reported as "Cannot <task>: <reason>."
  }

  std::vector<std::int64_t> offsets, connectivity;
  const auto [first, last] = adapter::PolygonFaces(input, offsets, connectivity);
  const PointMatrix points = adapter::PointsOf(input);
  const Eigen::Map<const Eigen::VectorXd> faceValues(values.data() + first, last - first);
  PartitionOptions options;
  options.ClusterModel = this->ClusterModel == 0 ? PartitionClusterModel::ExpectationMaximization
                                                 : PartitionClusterModel::DensityModes;
  options.NumberOfClusters = this->NumberOfClusters;
  options.MaximumClusters = this->MaximumClusters;
  options.Mixture.Restarts = this->Restarts;
  options.Mixture.MaximumIterations = this->MaximumIterations;
  options.Mixture.Seed = static_cast<std::uint64_t>(static_cast<std::uint32_t>(this->Seed));
  options.Modes.Bandwidth = this->ModeBandwidth;
  options.Modes.MinimumProminence = this->ModeProminence;
  options.Modes.MinimumValleyDepth = this->ModeValleyDepth;
  options.Energy.Lambda = this->Lambda;
  options.Energy.Epsilon = this->Epsilon;
  options.Energy.ConvexityFactor = this->ConvexityFactor;
  options.HistogramBins = this->HistogramBins;
  options.Refinement.Enabled = this->RefineParts;
  options.Refinement.MinimumAreaShare = this->RefinementMinimumArea;
  std::optional<PartitionShare> share;
  if (request.Halo)
  {
    if (first != 0 || last != input->GetNumberOfCells())
    {
      throw Error("a distributed share with cells other than polygons."); // RunOnHaloSurface rules them out
    }
    share.emplace(
      PartitionShare{ request.Halo->GlobalIds, request.Halo->Own, *request.Halo->Group, &request.Halo->GlobalPointIds });
  }
  const PartitionResult result = PartitionBySDF(
    PartitionInput{ points, offsets, connectivity, faceValues, modelInput ? &model : nullptr, share ? &*share : nullptr },
    options, request.Parallel, adapter::MakeProgress(this, 0.0, 1.0));
  if (result.Aborted)
  {
    return false;
  }
  // A halo run's graph is of this process's part only: no later filter gets the same surface.
  this->KeepFaceGraph(request.Halo ? nullptr : result.Graph);
  if (request.Halo && request.Halo->Group->Rank() == 0 && distributed::TimingReportsRequested())
  {
    std::cerr << "[ShapeDiameter distributed] vtkSDFGMMPartition: the graph cut ran "
              << (result.CutOverProcesses ? "on every process's faces" : "on process 0's gathered graph") << std::endl;
  }

  const int clusterCount = result.Model.ComponentCount();
  const vtkIdType cellCount = input->GetNumberOfCells();
  vtkNew<vtkDoubleArray> probabilities;
  probabilities->SetName(PROBABILITIES_ARRAY_NAME);
  probabilities->SetNumberOfComponents(clusterCount);
  probabilities->SetNumberOfTuples(cellCount);
  probabilities->FillValue(0.0);
  std::copy(result.Probabilities.data(), result.Probabilities.data() + result.Probabilities.size(),
    probabilities->GetPointer(first * clusterCount));
  vtkCellData* cellData = output->GetCellData();
  cellData->AddArray(probabilities);
  cellData->AddArray(CellIntArray(CLUSTER_ARRAY_NAME, cellCount, first, result.Labels));
  cellData->AddArray(CellIntArray(BAND_ARRAY_NAME, cellCount, first, result.Bands));
  for (std::size_t level = 0; level < result.Levels.size(); ++level)
  {
    cellData->AddArray(
      CellIntArray(LEVEL_ARRAY_PREFIX + std::to_string(level + 1), cellCount, first, result.Levels[level]));
  }
  cellData->AddArray(CellIntArray(SEGMENT_ARRAY_NAME, cellCount, first, result.Segments.Segment));
  cellData->SetActiveScalars(CLUSTER_ARRAY_NAME);

  vtkNew<vtkFieldData> field;
  field->ShallowCopy(input->GetFieldData());
  field->AddArray(DoubleArray(MEANS_ARRAY_NAME, result.Model.Means));
  field->AddArray(DoubleArray(SIGMAS_ARRAY_NAME, result.Model.Sigmas));
  field->AddArray(DoubleArray(WEIGHTS_ARRAY_NAME, result.Model.Weights));
  vtkNew<vtkIntArray> count;
  count->SetName(CLUSTER_COUNT_ARRAY_NAME);
  count->InsertNextValue(clusterCount);
  field->AddArray(count);
  field->AddArray(DoubleArray(ENERGY_ARRAY_NAME, { result.Energy }));
  output->SetFieldData(field);
  WriteHistogram(result.Histogram, vtkTable::GetData(request.OutputVector, 1));
  return true;
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
  os << indent << "ModeValleyDepth: " << this->ModeValleyDepth << "\n";
  os << indent << "RefineParts: " << this->RefineParts << "\n";
  os << indent << "RefinementMinimumArea: " << this->RefinementMinimumArea << "\n";
}
