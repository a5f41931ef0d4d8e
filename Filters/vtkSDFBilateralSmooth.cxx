// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSDFBilateralSmooth.h"

#include "DistributedSupport.h"
#include "Mesh/FaceGraph.h"
#include "Smoothing/SmoothAndNormalize.h"
#include "SurfaceConversion.h"
#include "SurfaceRequest.h"
#include "vtkShapeDiameterFilter.h"

#include "vtkCellData.h"
#include "vtkDataObject.h"
#include "vtkDataSetAttributes.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPolyData.h"

#include <algorithm>
#include <optional>

vtkStandardNewMacro(vtkSDFBilateralSmooth);

vtkSDFBilateralSmooth::vtkSDFBilateralSmooth()
  : vtkSDFSurfaceAlgorithm("smooth the SDF", "nothing to smooth", 0, false)
{
  // The defaults live in the core's options (SmoothAndNormalize.h: BilateralSmoothing.h,
  // Normalization.h); the XML mirrors them. NormalizationRange [0, 0] is the filter's own
  // "automatic".
  const shapediameter::SmoothAndNormalizeOptions defaults;
  this->NumberOfIterations = defaults.Smoothing.NumberOfIterations;
  this->SpatialSigma = defaults.Smoothing.SpatialSigma;
  this->NeighborhoodRadius = defaults.Smoothing.NeighborhoodRadius;
  this->RangeThreshold = defaults.Smoothing.RangeThreshold;
  this->Alpha = defaults.Normalization.Alpha;
  this->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS,
    vtkShapeDiameterFilter::SDF_ARRAY_NAME);
}

vtkSDFBilateralSmooth::~vtkSDFBilateralSmooth() = default;

std::vector<std::string> vtkSDFBilateralSmooth::CellArraysRead()
{
  return this->WithSelectedArray({ vtkShapeDiameterFilter::SDF_ARRAY_NAME });
}

namespace
{
/// The smoothed array's values (throws the reason when the input has none usable).
std::vector<double> SmoothedValues(vtkAlgorithm* filter, vtkPolyData* input)
{
  std::vector<double> values;
  std::string arrayName;
  const std::string reason = shapediameter::adapter::ReadCellScalars(
    filter, input, vtkShapeDiameterFilter::SDF_ARRAY_NAME, values, arrayName);
  if (!reason.empty())
  {
    throw shapediameter::Error(reason + "."); // reported as "Cannot <task>: <reason>."
  }
  return values;
}
} // namespace

double vtkSDFBilateralSmooth::HaloRadius(vtkPolyData* piece, const shapediameter::ProcessGroup& group)
{
  using namespace shapediameter;
  SmoothedValues(this, piece); // a piece without a usable array runs on process 0, which reports it
  const double meanEdgeLength = MeanEdgeLengthOverPieces(piece, group);
  BilateralSmoothingOptions smoothing;
  smoothing.NeighborhoodRadius = this->NeighborhoodRadius;
  smoothing.SpatialSigma = this->SpatialSigma;
  return NeighborhoodRadiusOf(smoothing, meanEdgeLength);
}

bool vtkSDFBilateralSmooth::ExecuteSurface(const shapediameter::adapter::SurfaceRequest& request)
{
  using namespace shapediameter;
  vtkPolyData* input = request.Input;
  vtkPolyData* output = request.Output;
  const std::vector<double> values = SmoothedValues(this, input);

  std::vector<std::int64_t> offsets, connectivity;
  adapter::PolygonCells(input, offsets, connectivity);
  // Normalise over the polygons only: other cells would drag min/max to their fill value.
  const auto [first, last] = adapter::PolygonCellRange(input);
  SmoothAndNormalizeOptions options;
  options.Smoothing.NumberOfIterations = this->NumberOfIterations;
  options.Smoothing.SpatialSigma = this->SpatialSigma;
  options.Smoothing.NeighborhoodRadius = this->NeighborhoodRadius;
  options.Smoothing.RangeThreshold = this->RangeThreshold;
  options.Normalization.Alpha = this->Alpha;
  // max <= min means automatic; anything else, a non-finite bound included, is a given range
  // (the core rejects a non-finite one).
  options.Normalization.UseGivenRange = !(this->NormalizationRange[1] <= this->NormalizationRange[0]);
  options.Normalization.RangeMinimum = this->NormalizationRange[0];
  options.Normalization.RangeMaximum = this->NormalizationRange[1];
  const PointMatrix points = adapter::PointsOf(input);
  std::optional<FaceShare> share;
  if (request.Halo)
  {
    share.emplace(FaceShare{ request.Halo->Own, *request.Halo->Group, &request.Halo->Counted, request.Halo->Width });
  }
  const SmoothAndNormalizeResult result = SmoothAndNormalize(
    SmoothAndNormalizeInput{ points, offsets, connectivity, values, static_cast<std::size_t>(first),
      static_cast<std::size_t>(last), share ? &*share : nullptr },
    options, request.Parallel, adapter::MakeProgress(this, 0.0, 1.0));
  if (result.Aborted)
  {
    return false;
  }
  // A halo run's graph is of this process's part only: no later filter gets the same surface.
  this->KeepFaceGraph(request.Halo ? nullptr : result.Graph);

  output->GetFieldData()->AddArray(adapter::MakeArray<vtkDoubleArray>(
    NORMALIZATION_RANGE_ARRAY_NAME, std::vector<double>{ result.RangeMinimum, result.RangeMaximum }));
  output->GetCellData()->AddArray(adapter::MakeArray<vtkDoubleArray>(SMOOTHED_ARRAY_NAME, result.Smoothed));
  vtkNew<vtkDoubleArray> normalizedArray;
  normalizedArray->SetName(NORMALIZED_ARRAY_NAME);
  normalizedArray->SetNumberOfTuples(static_cast<vtkIdType>(values.size()));
  normalizedArray->FillValue(0.0);
  std::copy(result.Normalized.begin(), result.Normalized.end(), normalizedArray->GetPointer(first));
  output->GetCellData()->AddArray(normalizedArray);
  // Active, so ParaView's array selection of the next stage (the partition) defaults to it.
  output->GetCellData()->SetActiveScalars(NORMALIZED_ARRAY_NAME);
  return true;
}

void vtkSDFBilateralSmooth::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "NumberOfIterations: " << this->NumberOfIterations << "\n";
  os << indent << "SpatialSigma: " << this->SpatialSigma << "\n";
  os << indent << "NeighborhoodRadius: " << this->NeighborhoodRadius << "\n";
  os << indent << "RangeThreshold: " << this->RangeThreshold << "\n";
  os << indent << "Alpha: " << this->Alpha << "\n";
  os << indent << "NormalizationRange: " << this->NormalizationRange[0] << " " << this->NormalizationRange[1] << "\n";
}
