// SPDX-License-Identifier: BSD-3-Clause
#include "vtkShapeDiameterFilter.h"

#include "DistributedSupport.h"
#include "RayCasting/EmbreeRayCaster.h"
#include "Mesh/MeshGeometry.h"
#include "Mesh/Orientation.h"
#include "SDF/SDF.h"
#include "SDF/ShapeDiameter.h"
#include "SurfaceConversion.h"
#include "SurfaceRequest.h"

#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"

#include <algorithm>
#include <optional>

vtkStandardNewMacro(vtkShapeDiameterFilter);

namespace
{
using namespace shapediameter;
using adapter::TriangulatedSurface;

/// The input's polygons with the winding of every flipped cell reversed (a polygon's
/// triangles share its winding, so its first triangle decides).
vtkSmartPointer<vtkCellArray> ReorientedPolygons(
  vtkPolyData* input, const TriangulatedSurface& surface, const std::vector<std::uint8_t>& flip)
{
  auto polygons = vtkSmartPointer<vtkCellArray>::New();
  polygons->AllocateExact(input->GetNumberOfPolys(), input->GetPolys()->GetNumberOfConnectivityIds());
  vtkIdType cellId = input->GetNumberOfVerts() + input->GetNumberOfLines();
  std::vector<vtkIdType> ids;
  auto iterator = vtk::TakeSmartPointer(input->GetPolys()->NewIterator());
  for (iterator->GoToFirstCell(); !iterator->IsDoneWithTraversal(); iterator->GoToNextCell(), ++cellId)
  {
    vtkIdType count;
    const vtkIdType* cell;
    iterator->GetCurrentCell(count, cell);
    ids.assign(cell, cell + count);
    const auto first = surface.CellFirstTriangle[static_cast<std::size_t>(cellId)];
    if (first < surface.CellFirstTriangle[static_cast<std::size_t>(cellId) + 1] &&
      flip[static_cast<std::size_t>(first)])
    {
      std::reverse(ids.begin(), ids.end());
    }
    polygons->InsertNextCell(count, ids.data());
  }
  return polygons;
}
/// The rows `rows` of `triangles`.
TriangleMatrix OwnTriangles(const TriangleMatrix& triangles, const std::vector<std::int64_t>& rows)
{
  TriangleMatrix own(static_cast<Eigen::Index>(rows.size()), 3);
  for (std::size_t k = 0; k < rows.size(); ++k)
  {
    own.row(static_cast<Eigen::Index>(k)) = triangles.row(static_cast<Eigen::Index>(rows[k]));
  }
  return own;
}
} // namespace

vtkShapeDiameterFilter::vtkShapeDiameterFilter()
  : vtkSDFSurfaceAlgorithm("compute the SDF", "no SDF to compute", 0, true)
{
  // The defaults live in the core's options (Filters/Core/SDF/ShapeDiameter.h); the XML mirrors them.
  const ShapeDiameterOptions defaults;
  this->NumberOfRays = defaults.NumberOfRays;
  this->ConeAngle = defaults.ConeAngle;
  this->HitRule = defaults.Rule == shapediameter::HitRule::SkipSameFacing ? 1 : 0;
  this->Mode = defaults.Mode == ShapeDiameterMode::Adaptive ? ADAPTIVE : EXACT;
  this->Tolerance = defaults.Tolerance;
}

vtkShapeDiameterFilter::~vtkShapeDiameterFilter() = default;

bool vtkShapeDiameterFilter::ExecuteSurface(const shapediameter::adapter::SurfaceRequest& request)
{
  vtkPolyData* input = request.Input;
  vtkPolyData* output = request.Output;
  TriangulatedSurface surface;
  const std::string reason = adapter::Triangulate(input, surface);
  if (!reason.empty())
  {
    throw shapediameter::Error(reason + "."); // reported as "Cannot <task>: <reason>."
  }

  // Progress and abort between the serial steps before the ray loop as well: at 832k faces
  // the adjacency and orientation take ~1.2 s and the BVH 0.3 s (BenchPipeline's SDFAbort).
  // An abort leaves the documented pass-through copy (vtkSDFSurfaceAlgorithm).
  auto abortedAt = [this](double progress) {
    this->UpdateProgress(progress);
    return this->GetAbortExecute() != 0;
  };
  if (abortedAt(0.01))
  {
    return false;
  }

  // Triangle adjacency over manifold edges: orientation walks it, the adaptive mode
  // interpolates over it, the neighbour fill of faces without a valid ray uses it. Its
  // neighbours do not depend on the winding, so the one built for the orientation serves the
  // others, or is built again for the fill after it was released (below).
  std::optional<TriangleAdjacency> adjacency;
  auto triangleAdjacency = [&]() -> const TriangleAdjacency& {
    if (!adjacency)
    {
      adjacency = BuildTriangleAdjacency(surface.Triangles);
    }
    return *adjacency;
  };
  if (this->AutoOrient)
  {
    triangleAdjacency(); // built first, so that an abort can land between it and the walk
    if (abortedAt(0.03))
    {
      return false;
    }
    const OrientationResult orientation = OrientOutward(surface.Points, surface.Triangles, triangleAdjacency());
    if (orientation.FlippedTriangles > 0)
    {
      ApplyFlips(surface.Triangles, orientation.Flip);
      output->SetPolys(ReorientedPolygons(input, surface, orientation.Flip));
      vtkWarningMacro("AutoOrient reversed " << orientation.FlippedTriangles << " of "
                                             << surface.Triangles.rows() << " triangles ("
                                             << orientation.InconsistentComponents
                                             << " inconsistently wound and "
                                             << orientation.InwardComponents
                                             << " inward-facing components).");
    }
    // Not held through the BVH's build and the rays (about 35 bytes per face: 29 MB at 832k
    // faces, on every process of a distributed run) when only a fill might read it: most
    // surfaces need none, and building it again costs about 1 % of the SDF's time.
    if (this->Mode != ADAPTIVE)
    {
      adjacency.reset();
    }
  }
  if (abortedAt(0.05))
  {
    return false;
  }
  // A replicated run's whole surface as VTK data is not read again (the triangulated copy is):
  // freed before the BVH's build, every process's peak (ReplicatedShare::ReleaseGeometry).
  if (request.Share && request.Share->ReleaseGeometry)
  {
    request.Share->ReleaseGeometry(output);
  }

  const ParallelFor& parallelFor = request.Parallel;
  std::optional<EmbreeRayCaster> caster(std::in_place, surface.Points, surface.Triangles);
  if (abortedAt(0.1))
  {
    return false;
  }
  ShapeDiameterOptions options;
  options.NumberOfRays = this->NumberOfRays;
  options.ConeAngle = this->ConeAngle;
  options.Rule = this->HitRule == 1 ? shapediameter::HitRule::SkipSameFacing : shapediameter::HitRule::FirstHitLeaving;
  options.Mode = this->Mode == ADAPTIVE ? ShapeDiameterMode::Adaptive : ShapeDiameterMode::Exact;
  options.Tolerance = this->Tolerance;
  options.IgnoreBuriedFaces = this->IgnoreBuriedFaces != 0;
  // Replicated distributed run (CanRunReplicated): the whole surface on every process, each
  // casting from the triangles of its own cells only (`ownTriangles`, their origins alone: 81
  // bytes per triangle). Every origin's result depends on that origin alone, so the combined
  // values are the serial ones.
  std::vector<std::int64_t> ownTriangles;
  if (request.Share)
  {
    for (std::size_t cell = 0; cell + 1 < surface.CellFirstTriangle.size(); ++cell)
    {
      if (request.Share->Owned[cell])
      {
        for (std::int64_t t = surface.CellFirstTriangle[cell]; t < surface.CellFirstTriangle[cell + 1]; ++t)
        {
          ownTriangles.push_back(t);
        }
      }
    }
  }
  // MakeVertexOrigins normalises the area-weighted normals, and skips zero ones.
  RayOrigins origins;
  if (this->PerPoint)
  {
    origins = MakeVertexOrigins(surface.Points, AreaWeightedVertexNormals(surface.Points, surface.Triangles));
  }
  else if (request.Share)
  {
    origins = MakeFaceOrigins(surface.Points, OwnTriangles(surface.Triangles, ownTriangles));
    std::copy(ownTriangles.begin(), ownTriangles.end(), origins.SourceTriangles.begin());
  }
  else
  {
    origins = MakeFaceOrigins(surface.Points, surface.Triangles);
  }
  PointAdjacency pointAdjacency;
  if (this->PerPoint)
  {
    pointAdjacency = BuildPointAdjacency(surface.Points.rows(), surface.Triangles);
  }
  if (options.Mode == ShapeDiameterMode::Adaptive)
  {
    // The adaptive mode interpolates over the surface: the same graph as the fill below.
    origins.NeighborOffsets = this->PerPoint ? pointAdjacency.Offsets : triangleAdjacency().Offsets;
    origins.Neighbors = this->PerPoint ? pointAdjacency.Neighbors : triangleAdjacency().Neighbors;
  }
  ShapeDiameterResult result = ComputeShapeDiameter(
    *caster, origins, options, parallelFor, adapter::MakeProgress(this, 0.1, 0.9));
  // The BVH and the ray origins are released before the values are combined and written,
  // which would otherwise set the stage's peak on every process (832k faces on 4 processes:
  // the BVH's build is then the peak, 7-11 MB lower; docs/distributed.md).
  caster.reset();
  origins = RayOrigins();
  if (request.Share)
  {
    // Every triangle of the whole surface, 0 but on this process's own (x + 0 is exact).
    std::vector<double> values(static_cast<std::size_t>(surface.Triangles.rows()), 0.0);
    std::vector<int> validRays(values.size(), 0);
    for (std::size_t k = 0; k < ownTriangles.size() && !result.Values.empty(); ++k)
    {
      values[static_cast<std::size_t>(ownTriangles[k])] = result.Values[k];
      validRays[static_cast<std::size_t>(ownTriangles[k])] = result.ValidRays[k];
    }
    result.Values.swap(values);
    result.ValidRays.swap(validRays);
    request.Share->Combine(result.Values, result.ValidRays, result.Aborted);
  }
  if (result.Aborted)
  {
    return false;
  }

  if (this->PerPoint)
  {
    FillFromNeighbors(result.Values, result.ValidRays, pointAdjacency.Offsets, pointAdjacency.Neighbors);
    output->GetPointData()->AddArray(adapter::MakeArray<vtkDoubleArray>(SDF_ARRAY_NAME, result.Values));
    output->GetPointData()->AddArray(adapter::MakeArray<vtkIntArray>(VALID_RAYS_ARRAY_NAME, result.ValidRays));
    output->GetPointData()->SetActiveScalars(SDF_ARRAY_NAME);
  }
  else
  {
    if (std::find(result.ValidRays.begin(), result.ValidRays.end(), 0) != result.ValidRays.end())
    {
      FillFromNeighbors(
        result.Values, result.ValidRays, triangleAdjacency().Offsets, triangleAdjacency().Neighbors);
    }
    // Vertices and lines own no triangle: 0 (documented); a polygon: the area-weighted mean of
    // its triangles.
    output->GetCellData()->AddArray(adapter::MakeArray<vtkDoubleArray>(SDF_ARRAY_NAME,
      AreaWeightedCellMeans(surface.Points, surface.Triangles, surface.CellFirstTriangle, result.Values)));
    output->GetCellData()->AddArray(adapter::MakeArray<vtkIntArray>(
      VALID_RAYS_ARRAY_NAME, CellSums(surface.CellFirstTriangle, result.ValidRays)));
    output->GetCellData()->SetActiveScalars(SDF_ARRAY_NAME);
  }
  return true;
}

void vtkShapeDiameterFilter::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "NumberOfRays: " << this->NumberOfRays << "\n";
  os << indent << "ConeAngle: " << this->ConeAngle << "\n";
  os << indent << "PerPoint: " << this->PerPoint << "\n";
  os << indent << "HitRule: " << this->HitRule << "\n";
  os << indent << "AutoOrient: " << this->AutoOrient << "\n";
  os << indent << "IgnoreBuriedFaces: " << this->IgnoreBuriedFaces << "\n";
  os << indent << "Mode: " << (this->Mode == ADAPTIVE ? "Adaptive" : "Exact") << "\n";
  os << indent << "Tolerance: " << this->Tolerance << "\n";
}
