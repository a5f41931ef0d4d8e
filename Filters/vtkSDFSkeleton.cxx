// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSDFSkeleton.h"

#include "DistributedSupport.h"
#include "Mesh/Orientation.h"
#include "Skeleton/DistributedSkeleton.h"
#include "Skeleton/Skeleton.h"
#include "SurfaceConversion.h"
#include "SurfaceRequest.h"
#include "vtkSDFBilateralSmooth.h"
#include "vtkSDFGMMPartition.h"
#include "vtkShapeDiameterFilter.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataObject.h"
#include "vtkDoubleArray.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <algorithm>
#include <cmath>

vtkStandardNewMacro(vtkSDFSkeleton);

namespace
{
using namespace shapediameter;

vtkSmartPointer<vtkDoubleArray> DoubleArray(const char* name, const std::vector<double>& values)
{
  return adapter::MakeArray<vtkDoubleArray>(name, values);
}

template <typename T>
vtkSmartPointer<vtkIdTypeArray> IdArray(const char* name, const std::vector<T>& values)
{
  return adapter::MakeArray<vtkIdTypeArray>(name, values);
}

vtkNew<vtkPoints> ToPoints(const PointMatrix& positions)
{
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(positions.rows());
  for (Eigen::Index p = 0; p < positions.rows(); ++p)
  {
    points->SetPoint(p, positions(p, 0), positions(p, 1), positions(p, 2));
  }
  return points;
}

/// Port 0: nodes, bones as polylines; single-node bones as vertices (VTK numbers vertex
/// cells before lines, so the cell arrays follow that order).
void WriteSkeleton(const SkeletonResult& skeleton, vtkPolyData* output)
{
  output->SetPoints(ToPoints(skeleton.NodePositions));
  output->GetPointData()->AddArray(DoubleArray(vtkSDFSkeleton::RADIUS_ARRAY_NAME, skeleton.NodeRadius));
  output->GetPointData()->AddArray(DoubleArray(vtkSDFSkeleton::CONFIDENCE_ARRAY_NAME, skeleton.NodeConfidence));
  vtkNew<vtkCellArray> vertices, lines;
  std::vector<std::int64_t> boneIds;
  std::vector<int> isConnection;
  for (const bool singles : { true, false })
  {
    for (std::size_t bone = 0; bone < skeleton.Polylines.size(); ++bone)
    {
      const auto& nodes = skeleton.Polylines[bone];
      if ((nodes.size() == 1) != singles || nodes.empty())
      {
        continue;
      }
      std::vector<vtkIdType> ids(nodes.begin(), nodes.end());
      (singles ? vertices : lines)->InsertNextCell(static_cast<vtkIdType>(ids.size()), ids.data());
      boneIds.push_back(skeleton.BoneId[bone]);
      isConnection.push_back(skeleton.IsConnection[bone]);
    }
  }
  output->SetVerts(vertices);
  output->SetLines(lines);
  output->GetCellData()->AddArray(IdArray(vtkSDFSkeleton::BONE_ID_ARRAY_NAME, boneIds));
  output->GetCellData()->SetActiveScalars(vtkSDFSkeleton::BONE_ID_ARRAY_NAME); // default colouring
  output->GetCellData()->AddArray(
    adapter::MakeArray<vtkIntArray>(vtkSDFSkeleton::IS_CONNECTION_ARRAY_NAME, isConnection));
}
/// SDFSegment per triangle, or empty (nearest-node link) when the input has no usable array.
std::vector<std::int64_t> TriangleSegments(vtkObject* self, vtkPolyData* input,
  const shapediameter::adapter::TriangulatedSurface& surface)
{
  if (!input->GetCellData()->GetArray(vtkSDFGMMPartition::SEGMENT_ARRAY_NAME))
  {
    return {};
  }
  std::vector<double> cellSegments;
  const std::string reason =
    adapter::ReadNamedCellScalars(input, cellSegments, vtkSDFGMMPartition::SEGMENT_ARRAY_NAME);
  if (!reason.empty())
  {
    vtkWarningWithObjectMacro(self, "Faces are linked to their nearest node: " << reason << ".");
    return {};
  }
  std::vector<std::int64_t> triangleSegments(surface.TriangleCell.size());
  for (std::size_t t = 0; t < triangleSegments.size(); ++t)
  {
    const double value = cellSegments[static_cast<std::size_t>(surface.TriangleCell[t])];
    if (!(std::abs(value) < 9e15)) // too large to be an integer label
    {
      vtkWarningWithObjectMacro(self, "The cell array '" << vtkSDFGMMPartition::SEGMENT_ARRAY_NAME
        << "' has huge values: faces are linked to their nearest node.");
      return {};
    }
    triangleSegments[t] = static_cast<std::int64_t>(value);
  }
  return triangleSegments;
}

/// Port 1: each cell takes the link of its first triangle (-1 for cells without one).
void WriteSurfaceLink(vtkPolyData* input, const shapediameter::adapter::TriangulatedSurface& surface,
  const std::vector<std::int64_t>& triangleNodes, const std::vector<std::int64_t>& triangleBones, vtkPolyData* output)
{
  const vtkIdType cellCount = input->GetNumberOfCells();
  std::vector<std::int64_t> nodeIds(static_cast<std::size_t>(cellCount), -1);
  std::vector<std::int64_t> boneIds(static_cast<std::size_t>(cellCount), -1);
  for (vtkIdType cell = 0; cell < cellCount; ++cell)
  {
    const auto first = surface.CellFirstTriangle[static_cast<std::size_t>(cell)];
    if (first < surface.CellFirstTriangle[static_cast<std::size_t>(cell) + 1])
    {
      nodeIds[static_cast<std::size_t>(cell)] = triangleNodes[static_cast<std::size_t>(first)];
      boneIds[static_cast<std::size_t>(cell)] = triangleBones[static_cast<std::size_t>(first)];
    }
  }
  output->GetCellData()->AddArray(IdArray(vtkSDFSkeleton::NODE_ID_ARRAY_NAME, nodeIds));
  output->GetCellData()->AddArray(IdArray(vtkSDFSkeleton::SURFACE_BONE_ID_ARRAY_NAME, boneIds));
  output->GetCellData()->SetActiveScalars(vtkSDFSkeleton::SURFACE_BONE_ID_ARRAY_NAME);
}

/// Port 2: the projected cloud, with the source cell of every point and, when given, its
/// cluster (SDFCluster of the source cell, one per point).
void WriteCloud(const SkeletonResult& skeleton, const std::vector<vtkIdType>& sourceCells,
  const std::vector<int>* clusters, vtkPolyData* output)
{
  output->SetPoints(ToPoints(skeleton.CloudPositions));
  const auto pointCount = static_cast<vtkIdType>(sourceCells.size());
  vtkNew<vtkCellArray> vertices;
  vertices->AllocateExact(pointCount, pointCount);
  for (vtkIdType p = 0; p < pointCount; ++p)
  {
    vertices->InsertNextCell(1, &p);
  }
  output->SetVerts(vertices);
  vtkPointData* cloudData = output->GetPointData();
  cloudData->AddArray(IdArray(vtkSDFSkeleton::SOURCE_FACE_ARRAY_NAME, sourceCells));
  cloudData->AddArray(DoubleArray(vtkSDFSkeleton::RADIUS_ARRAY_NAME, skeleton.CloudRadius));
  cloudData->AddArray(DoubleArray(vtkSDFSkeleton::CONFIDENCE_ARRAY_NAME, skeleton.CloudConfidence));
  cloudData->SetActiveScalars(vtkSDFSkeleton::CONFIDENCE_ARRAY_NAME); // how line-like each point's neighbourhood is
  if (clusters)
  {
    cloudData->AddArray(adapter::MakeArray<vtkIntArray>(vtkSDFGMMPartition::CLUSTER_ARRAY_NAME, *clusters));
  }
}

/// The documented warning when no sample could be placed.
void WarnWithoutArea(vtkObject* self, const SkeletonResult& skeleton)
{
  if (skeleton.CloudPositions.rows() == 0)
  {
    // Samples are placed in proportion to area: a surface whose triangles all have zero
    // area at double precision (coincident points, or lengths whose squares underflow)
    // gets none, and only the documented placeholder node per component.
    vtkWarningWithObjectMacro(self, "The surface has no area: no sample could be placed, the skeleton is one node per component.");
  }
}

/// A distributed run (vtkSDFSkeleton's CanRunWithHalo): each process's own cells, the skeleton
/// built on process 0 from what every process sends it (Skeleton/DistributedSkeleton.h).
bool ExecuteOverProcesses(vtkObject* self, const adapter::SurfaceRequest& request,
  const adapter::TriangulatedSurface& surface, const std::vector<double>& triangleSdf,
  const std::vector<std::int64_t>& triangleParts, const SkeletonOptions& options, const ProgressCallback& progress)
{
  vtkPolyData* input = request.Input;
  std::vector<double> triangleClusters;
  if (vtkDataArray* clusters = input->GetCellData()->GetArray(vtkSDFGMMPartition::CLUSTER_ARRAY_NAME))
  {
    for (const vtkIdType cell : surface.TriangleCell)
    {
      triangleClusters.push_back(clusters->GetComponent(cell, 0));
    }
  }
  const std::vector<std::int64_t> triangleCell(surface.TriangleCell.begin(), surface.TriangleCell.end());
  const distributed::HaloShare& halo = *request.Halo;
  const DistributedSkeletonResult result = ComputeSkeletonOverProcesses(
    SkeletonShareInput{ surface.Points, surface.Triangles, triangleCell, triangleSdf, triangleParts, triangleClusters },
    SkeletonShare{ halo.GlobalIds, halo.GlobalPointIds, *halo.Group }, options, request.Parallel, progress);
  if (result.Aborted)
  {
    return false;
  }
  WriteSurfaceLink(input, surface, result.FaceNodeId, result.FaceBoneId, request.Output);
  if (halo.Group->Rank() == 0)
  {
    // The skeleton and the cloud of the whole surface, on process 0 only; a cloud point's
    // source cell is the cell's global id.
    WarnWithoutArea(self, result.Whole);
    WriteSkeleton(result.Whole, vtkPolyData::GetData(request.OutputVector, 0));
    const std::vector<vtkIdType> sourceCells(result.CloudSourceCellId.begin(), result.CloudSourceCellId.end());
    const std::vector<int> cloudClusters(result.CloudLabels.begin(), result.CloudLabels.end());
    WriteCloud(result.Whole, sourceCells, result.CloudLabels.empty() ? nullptr : &cloudClusters,
      vtkPolyData::GetData(request.OutputVector, 2));
  }
  return true;
}

} // namespace

vtkSDFSkeleton::vtkSDFSkeleton()
  : vtkSDFSurfaceAlgorithm("compute the skeleton", "no skeleton", 1, true)
{
  // The defaults live in the core's options (Filters/Core/Skeleton*.h); the XML mirrors them.
  const shapediameter::SkeletonOptions defaults;
  this->NumberOfSamples = static_cast<int>(defaults.Sampling.NumberOfSamples);
  this->Seed = static_cast<int>(defaults.Sampling.Seed);
  this->NumberOfIterations = defaults.Thinning.NumberOfIterations;
  this->ConfidenceThreshold = defaults.Thinning.ConfidenceThreshold;
  this->MinimumConfidentShare = defaults.Thinning.MinimumConfidentShare;
  this->SpacingFactor = defaults.Thinning.SpacingFactor;
  this->MaximumExitAngle = defaults.LeafExtension.MaximumExitAngle;
  this->TipReach = defaults.LeafExtension.TipReach;
  this->UncoveredFactor = defaults.Coverage.UncoveredFactor;
  this->ThinLimbFactor = defaults.Coverage.ThinLimbFactor;
  this->OwnBoneShare = defaults.OwnBoneShare;
  this->PartUncoveredFactor = defaults.Coverage.PartUncoveredFactor;
  this->BoneSmoothing = defaults.Smoothing.Bandwidth;
  this->SetNumberOfOutputPorts(3);
  this->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS,
    vtkSDFBilateralSmooth::SMOOTHED_ARRAY_NAME);
}

vtkSDFSkeleton::~vtkSDFSkeleton() = default;

std::vector<std::string> vtkSDFSkeleton::CellArraysRead()
{
  return this->WithSelectedArray({ vtkSDFBilateralSmooth::SMOOTHED_ARRAY_NAME,
    vtkShapeDiameterFilter::SDF_ARRAY_NAME, vtkSDFGMMPartition::SEGMENT_ARRAY_NAME,
    vtkSDFGMMPartition::CLUSTER_ARRAY_NAME });
}

bool vtkSDFSkeleton::ExecuteSurface(const shapediameter::adapter::SurfaceRequest& request)
{
  using namespace shapediameter;
  vtkPolyData* input = request.Input;
  vtkPolyData* skeletonOutput = vtkPolyData::GetData(request.OutputVector, 0);
  vtkPolyData* surfaceOutput = request.Output;
  vtkPolyData* cloudOutput = vtkPolyData::GetData(request.OutputVector, 2);
  adapter::TriangulatedSurface surface;
  std::string reason = adapter::Triangulate(input, surface);
  if (reason.empty() && surface.Triangles.rows() == 0 && !request.Halo) // distributed: process 0 checks the whole
  {
    // Polygon cells of fewer than three points only: nothing to sample, not even a
    // placeholder node (one per component of triangles).
    reason = "the input has no polygon with three points";
  }
  std::vector<double> cellSdf;
  std::string arrayName;
  if (reason.empty())
  {
    reason = adapter::ReadCellScalars(this, input, vtkSDFBilateralSmooth::SMOOTHED_ARRAY_NAME, cellSdf, arrayName);
    if (!reason.empty() && arrayName == vtkSDFBilateralSmooth::SMOOTHED_ARRAY_NAME &&
      !input->GetCellData()->GetAbstractArray(arrayName.c_str()))
    {
      arrayName = vtkShapeDiameterFilter::SDF_ARRAY_NAME; // documented fallback
      reason = adapter::ReadNamedCellScalars(input, cellSdf, arrayName);
    }
  }
  if (reason.empty() && std::any_of(cellSdf.begin(), cellSdf.end(), [](double v) { return v < 0; }))
  {
    reason = "the cell array '" + arrayName + "' has negative values";
  }
  if (!reason.empty())
  {
    throw shapediameter::Error(reason + "."); // reported as "Cannot <task>: <reason>."
  }

  std::vector<double> triangleSdf(surface.TriangleCell.size());
  for (std::size_t t = 0; t < triangleSdf.size(); ++t)
  {
    triangleSdf[t] = cellSdf[static_cast<std::size_t>(surface.TriangleCell[t])];
  }
  SkeletonOptions options;
  options.Sampling.NumberOfSamples = static_cast<std::size_t>(this->NumberOfSamples);
  options.Sampling.Seed = static_cast<std::uint64_t>(static_cast<std::uint32_t>(this->Seed));
  options.Thinning.NumberOfIterations = this->NumberOfIterations;
  options.Thinning.ConfidenceThreshold = this->ConfidenceThreshold;
  options.Thinning.MinimumConfidentShare = this->MinimumConfidentShare;
  options.Thinning.SpacingFactor = this->SpacingFactor;
  options.LeafExtension.MaximumExitAngle = this->MaximumExitAngle;
  options.LeafExtension.TipReach = this->TipReach;
  options.Coverage.UncoveredFactor = this->UncoveredFactor;
  options.Coverage.ThinLimbFactor = this->ThinLimbFactor;
  options.OwnBoneShare = this->OwnBoneShare;
  options.Coverage.PartUncoveredFactor = this->PartUncoveredFactor;
  options.Smoothing.Bandwidth = this->BoneSmoothing;
  const std::vector<std::int64_t> triangleParts =
    this->LinkBySegment ? TriangleSegments(this, input, surface) : std::vector<std::int64_t>();
  const ProgressCallback progress = adapter::MakeProgress(this, 0.0, 0.95);
  if (request.Halo)
  {
    return ExecuteOverProcesses(this, request, surface, triangleSdf, triangleParts, options, progress);
  }
  vtkDataArray* clusters = input->GetCellData()->GetArray(vtkSDFGMMPartition::CLUSTER_ARRAY_NAME);

  ApplyFlips(surface.Triangles, OrientOutward(surface.Points, surface.Triangles).Flip);
  const SkeletonResult skeleton = ComputeSkeleton(surface.Points, surface.Triangles, triangleSdf,
    PointMatrix(0, 3), {}, options, request.Parallel, progress, triangleParts);
  if (skeleton.Aborted)
  {
    return false;
  }
  WarnWithoutArea(this, skeleton);
  WriteSkeleton(skeleton, skeletonOutput);
  WriteSurfaceLink(input, surface, skeleton.FaceNodeId, skeleton.FaceBoneId, surfaceOutput);
  std::vector<vtkIdType> sourceCells(skeleton.CloudSourceFace.size());
  std::vector<int> cloudClusters;
  for (std::size_t p = 0; p < sourceCells.size(); ++p)
  {
    sourceCells[p] = surface.TriangleCell[static_cast<std::size_t>(skeleton.CloudSourceFace[p])];
    if (clusters)
    {
      cloudClusters.push_back(static_cast<int>(clusters->GetComponent(sourceCells[p], 0)));
    }
  }
  WriteCloud(skeleton, sourceCells, clusters ? &cloudClusters : nullptr, cloudOutput);
  return true;
}

void vtkSDFSkeleton::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "NumberOfSamples: " << this->NumberOfSamples << "\n";
  os << indent << "NumberOfIterations: " << this->NumberOfIterations << "\n";
  os << indent << "ConfidenceThreshold: " << this->ConfidenceThreshold << "\n";
  os << indent << "MinimumConfidentShare: " << this->MinimumConfidentShare << "\n";
  os << indent << "SpacingFactor: " << this->SpacingFactor << "\n";
  os << indent << "MaximumExitAngle: " << this->MaximumExitAngle << "\n";
  os << indent << "TipReach: " << this->TipReach << "\n";
  os << indent << "UncoveredFactor: " << this->UncoveredFactor << "\n";
  os << indent << "ThinLimbFactor: " << this->ThinLimbFactor << "\n";
  os << indent << "LinkBySegment: " << this->LinkBySegment << "\n";
  os << indent << "OwnBoneShare: " << this->OwnBoneShare << "\n";
  os << indent << "PartUncoveredFactor: " << this->PartUncoveredFactor << "\n";
  os << indent << "BoneSmoothing: " << this->BoneSmoothing << "\n";
  os << indent << "Seed: " << this->Seed << "\n";
}
