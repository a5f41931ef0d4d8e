# SPDX-License-Identifier: BSD-3-Clause
"""The wrapped VTK classes (package shapediameter), without the plugin: the full chain."""
import math
import os
import sys

from shapediameter import vtkSDFOFFReader, vtkSDFBilateralSmooth, vtkSDFGMMPartition, vtkShapeDiameterFilter

reader = vtkSDFOFFReader()
reader.SetFileName(os.path.join(os.environ["SHAPEDIAMETER_DATA_DIR"], "hand.off"))
sdf = vtkShapeDiameterFilter()
sdf.SetInputConnection(reader.GetOutputPort())
assert sdf.GetNumberOfRays() == 30 and sdf.GetConeAngle() == 120.0
smooth = vtkSDFBilateralSmooth()
smooth.SetInputConnection(sdf.GetOutputPort())
partition = vtkSDFGMMPartition()
partition.SetInputConnection(smooth.GetOutputPort())
partition.SetNumberOfClusters(3)
partition.Update()
mesh = partition.GetOutput()
cells = mesh.GetCellData()
if mesh.GetNumberOfCells() != 2390:
    sys.exit("expected 2390 cells, got %d" % mesh.GetNumberOfCells())
values = [cells.GetArray("SDF").GetValue(i) for i in range(mesh.GetNumberOfCells())]
if not all(math.isfinite(v) and v > 0 for v in values):
    sys.exit("SDF not finite and positive")
clusters = cells.GetArray("SDFCluster").GetRange()
count = mesh.GetFieldData().GetArray("SDFClusterCount").GetValue(0)
print("clusters", clusters, "of", count)
# The default density modes take at most k = 3 clusters; the hand has two thickness levels.
if count not in (2, 3) or clusters != (0.0, count - 1.0):
    sys.exit("expected 2 or 3 clusters numbered from 0, got %r of %r" % (clusters, count))
