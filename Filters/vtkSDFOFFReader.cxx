// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSDFOFFReader.h"

#include "IO/MeshPieces.h"
#include "IO/OFFParser.h"
#include "SurfaceConversion.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkIdTypeArray.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkNew.h"
#include "vtkObjectFactory.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStreamingDemandDrivenPipeline.h"
#include "vtkUnsignedCharArray.h"

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <utility>
#include <vector>

vtkStandardNewMacro(vtkSDFOFFReader);

namespace
{
using shapediameter::adapter::MakeArray;
} // namespace

vtkSDFOFFReader::vtkSDFOFFReader()
{
  this->SetNumberOfInputPorts(0);
}

vtkSDFOFFReader::~vtkSDFOFFReader() = default;

int vtkSDFOFFReader::CanReadFile(const char* fileName)
{
  std::ifstream file(fileName ? fileName : "", std::ios::binary);
  std::string keyword;
  while (file >> keyword)
  {
    if (keyword[0] == '#')
    {
      std::getline(file, keyword);
      continue;
    }
    return keyword.find("OFF") != std::string::npos ? 1 : 0;
  }
  return 0;
}

int vtkSDFOFFReader::RequestInformation(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  outputVector->GetInformationObject(0)->Set(CAN_HANDLE_PIECE_REQUEST(), 1);
  return 1;
}

int vtkSDFOFFReader::RequestData(
  vtkInformation*, vtkInformationVector**, vtkInformationVector* outputVector)
{
  vtkInformation* outInfo = outputVector->GetInformationObject(0);
  vtkPolyData* output = vtkPolyData::GetData(outInfo);
  const int piece = outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER())
    ? outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_PIECE_NUMBER())
    : 0;
  const int pieces = outInfo->Has(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES())
    ? outInfo->Get(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES())
    : 1;
  if (this->FileName.empty())
  {
    vtkErrorMacro("No FileName set.");
    return 0;
  }

  // ---- Distributed runs (Filters/DistributedSupport.h): each piece keeps its share of the
  // faces, and points and faces are numbered in file order (GlobalIds attributes
  // `GlobalPointIds`, `GlobalCellIds`) so the filters can rebuild the original mesh, in its
  // original order, from any distribution of the pieces. Serial runs get no extra array.
  // A piece is read keeping only what it needs (ReadOFFPiece); one piece parses the whole file
  // in one pass, which is faster and holds nothing more.
  shapediameter::OFFMesh mesh;
  std::vector<std::int64_t> globalPointIds;
  std::vector<std::int64_t> globalCellIds;
  try
  {
    if (pieces > 1)
    {
      shapediameter::MeshPiece share = shapediameter::ReadOFFPiece(this->FileName, piece, pieces,
        this->SpatialPieces ? shapediameter::PieceOrder::Spatial : shapediameter::PieceOrder::FileOrder);
      mesh = std::move(share.Mesh);
      globalPointIds = std::move(share.GlobalPointIds);
      globalCellIds = std::move(share.GlobalFaceIds);
    }
    else
    {
      mesh = shapediameter::ReadOFFFile(this->FileName);
    }
  }
  catch (const std::exception& error)
  {
    vtkErrorMacro("Cannot read OFF file " << error.what());
    return 0;
  }
  this->UpdateProgress(0.5);

  vtkNew<vtkPoints> points;
  points->SetData(MakeArray<vtkDoubleArray>("Points", mesh.Points, 3));
  output->SetPoints(points);

  vtkNew<vtkCellArray> polygons;
  polygons->SetData(MakeArray<vtkIdTypeArray>(nullptr, mesh.FaceOffsets),
    MakeArray<vtkIdTypeArray>(nullptr, mesh.FaceConnectivity));
  output->SetPolys(polygons);

  if (!mesh.VertexColors.empty())
  {
    output->GetPointData()->SetScalars(
      MakeArray<vtkUnsignedCharArray>("Colors", mesh.VertexColors, 4));
  }
  if (!mesh.VertexNormals.empty())
  {
    output->GetPointData()->SetNormals(
      MakeArray<vtkDoubleArray>("Normals", mesh.VertexNormals, 3));
  }
  if (!mesh.FaceColors.empty())
  {
    output->GetCellData()->SetScalars(
      MakeArray<vtkUnsignedCharArray>("Colors", mesh.FaceColors, 4));
  }

  if (pieces > 1)
  {
    output->GetPointData()->SetGlobalIds(MakeArray<vtkIdTypeArray>("GlobalPointIds", globalPointIds));
    output->GetCellData()->SetGlobalIds(MakeArray<vtkIdTypeArray>("GlobalCellIds", globalCellIds));
  }
  // ---- end of distributed runs
  this->UpdateProgress(1.0);
  return 1;
}

void vtkSDFOFFReader::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "FileName: " << this->FileName << "\n";
  os << indent << "SpatialPieces: " << this->SpatialPieces << "\n";
}
