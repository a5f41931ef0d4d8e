// SPDX-License-Identifier: BSD-3-Clause
// Small helpers shared by the filter tests.
#pragma once

#include "Mesh/MeshTypes.h"

#include "vtkCellArray.h"
#include "vtkCommand.h"
#include "vtkObject.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkNew.h"
#include "vtkSmartPointer.h"

#include <cstdlib>
#include <string>

namespace shapediameter::testing
{

/// Counts ErrorEvent/WarningEvent invocations of one VTK object and keeps the last text,
/// so tests can assert that bad input is reported (and not printed to the console).
class MessageRecorder : public vtkCommand
{
public:
  static MessageRecorder* New() { return new MessageRecorder; }

  void Execute(vtkObject*, unsigned long event, void* callData) override
  {
    const std::string text = callData ? static_cast<const char*>(callData) : "";
    if (event == vtkCommand::ErrorEvent)
    {
      ++this->Errors;
      this->LastError = text;
    }
    else if (event == vtkCommand::WarningEvent)
    {
      ++this->Warnings;
      this->LastWarning = text;
    }
  }

  void Observe(vtkObject* object)
  {
    object->AddObserver(vtkCommand::ErrorEvent, this);
    object->AddObserver(vtkCommand::WarningEvent, this);
  }

  int Errors = 0;
  int Warnings = 0;
  std::string LastError;
  std::string LastWarning;
};

/// Directory holding the bundled meshes (Data/), set by ctest.
inline std::string DataFile(const std::string& name)
{
  const char* directory = std::getenv("SHAPEDIAMETER_DATA_DIR");
  return std::string(directory ? directory : "Data") + "/" + name;
}

/// A triangle mesh of the VTK-free fixtures as vtkPolyData.
inline vtkSmartPointer<vtkPolyData> ToPolyData(const PointMatrix& points, const TriangleMatrix& triangles)
{
  vtkNew<vtkPoints> vtkpoints;
  vtkpoints->SetDataTypeToDouble();
  vtkpoints->SetNumberOfPoints(points.rows());
  for (Eigen::Index p = 0; p < points.rows(); ++p)
  {
    vtkpoints->SetPoint(p, points(p, 0), points(p, 1), points(p, 2));
  }
  vtkNew<vtkCellArray> polygons;
  for (Eigen::Index t = 0; t < triangles.rows(); ++t)
  {
    const vtkIdType ids[3] = { triangles(t, 0), triangles(t, 1), triangles(t, 2) };
    polygons->InsertNextCell(3, ids);
  }
  auto mesh = vtkSmartPointer<vtkPolyData>::New();
  mesh->SetPoints(vtkpoints);
  mesh->SetPolys(polygons);
  return mesh;
}

} // namespace shapediameter::testing
