// SPDX-License-Identifier: BSD-3-Clause
// SDF -> smoothing -> partition on a mesh, using only the installed ShapeDiameter package.
#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkFieldData.h>
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
  partition->Update();
  vtkPolyData* parts = partition->GetOutput();
  vtkDataArray* clusters = parts->GetCellData()->GetArray(vtkSDFGMMPartition::CLUSTER_ARRAY_NAME);
  vtkDataArray* count = parts->GetFieldData()->GetArray("SDFClusterCount");
  // Defaults: at most 5 clusters, one per mode of the SDF's distribution; the cut may leave a
  // cluster without faces, but the hand keeps at least two (fingers and palm).
  if (!clusters || !count || count->GetComponent(0, 0) < 2 || count->GetComponent(0, 0) > 5 ||
    clusters->GetRange()[0] < 0 || clusters->GetRange()[1] > count->GetComponent(0, 0) - 1 ||
    clusters->GetRange()[1] <= clusters->GetRange()[0])
  {
    std::cerr << "consumer: no partition into 2 to 5 clusters\n";
    return 1;
  }
  std::cout << parts->GetNumberOfCells() << " faces in clusters " << clusters->GetRange()[0] << ".." << clusters->GetRange()[1] << "\n";
  return 0;
}
