// SPDX-License-Identifier: BSD-3-Clause
// SDF -> smoothing -> partition on a mesh, using only the installed ShapeDiameter package.
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkSDFOFFReader.h>
#include <vtkPolyData.h>
#include <vtkSDFBilateralSmooth.h>
#include <vtkSDFGMMPartition.h>
#include <vtkShapeDiameterFilter.h>

#include <iostream>

int main(int argc, char* argv[])
{
  if (argc != 2)
  {
    std::cerr << "usage: consumer MESH.off\n";
    return 2;
  }
  vtkNew<vtkSDFOFFReader> reader;
  reader->SetFileName(argv[1]);
  vtkNew<vtkShapeDiameterFilter> sdf;
  sdf->SetInputConnection(reader->GetOutputPort());
  vtkNew<vtkSDFBilateralSmooth> smooth;
  smooth->SetInputConnection(sdf->GetOutputPort());
  vtkNew<vtkSDFGMMPartition> partition;
  partition->SetInputConnection(smooth->GetOutputPort());
  partition->SetNumberOfClusters(3);
  partition->Update();
  vtkDataArray* clusters = partition->GetOutput()->GetCellData()->GetArray(vtkSDFGMMPartition::CLUSTER_ARRAY_NAME);
  if (!clusters || clusters->GetRange()[1] != 2)
  {
    std::cerr << "consumer: no partition into 3 clusters\n";
    return 1;
  }
  std::cout << partition->GetOutput()->GetNumberOfCells() << " faces in clusters 0.."
            << clusters->GetRange()[1] << "\n";
  return 0;
}
