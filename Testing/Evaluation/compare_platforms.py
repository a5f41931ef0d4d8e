# SPDX-License-Identifier: BSD-3-Clause
"""Do two builds (e.g. Debian 12 / ParaView 5.11 / Embree 3 and Debian 13 / 5.13 / Embree 4)
give the same results? Run the default chain with the wrapped classes on each platform, then
compare the dumps (numpy is needed: pvpython has it).

  PYTHONPATH=build/lib/python3.11/site-packages pvpython compare_platforms.py dump Data OUT12 MESH...
  PYTHONPATH=<13 build>/lib/python3.13/site-packages python3 compare_platforms.py dump Data OUT13 MESH...
  pvpython compare_platforms.py compare OUT12 OUT13 MESH...

MESH is a name in Data without .off. The comparison prints, per mesh, the largest relative
difference of SDF and SDFSmoothed per face and the faces above 1e-5, and how many faces differ
in SDFCluster and SDFSegment.
"""
import os
import sys

import numpy as np

ARRAYS = ("SDF", "SDFSmoothed", "SDFNormalized", "SDFCluster", "SDFSegment")


def dump(data, out, meshes):
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from shapediameter import (vtkSDFBilateralSmooth, vtkSDFGMMPartition, vtkSDFOFFReader,
                               vtkShapeDiameterFilter)
    os.makedirs(out, exist_ok=True)
    for name in meshes:
        reader = vtkSDFOFFReader()
        reader.SetFileName(os.path.join(data, name + ".off"))
        sdf = vtkShapeDiameterFilter()
        sdf.SetInputConnection(reader.GetOutputPort())
        smooth = vtkSDFBilateralSmooth()
        smooth.SetInputConnection(sdf.GetOutputPort())
        partition = vtkSDFGMMPartition()
        partition.SetInputConnection(smooth.GetOutputPort())
        partition.Update()
        cells = partition.GetOutput().GetCellData()
        np.savez(os.path.join(out, name + ".npz"),
                 **{k: vtk_to_numpy(cells.GetArray(k)).copy() for k in ARRAYS})
        print(name, partition.GetOutput().GetNumberOfCells(), "cells")


def compare(a_dir, b_dir, meshes):
    print("| mesh | faces | SDF max rel. diff. | > 1e-5 | SDFSmoothed max rel. diff. | > 1e-5 "
          "| SDFCluster differ | SDFSegment differ |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|")
    worst = 0
    for name in meshes:
        a = np.load(os.path.join(a_dir, name + ".npz"))
        b = np.load(os.path.join(b_dir, name + ".npz"))
        row = [name, str(len(a["SDF"]))]
        for k in ("SDF", "SDFSmoothed"):
            x, y = a[k].astype(float), b[k].astype(float)
            rel = np.abs(x - y) / np.maximum(np.abs(x), 1e-300)
            row += ["%.1e" % rel.max(), str(int((rel > 1e-5).sum()))]
            worst = max(worst, int((rel > 1e-5).sum()))
        for k in ("SDFCluster", "SDFSegment"):
            differ = int((a[k] != b[k]).sum())
            row.append(str(differ))
            worst = max(worst, differ)
        print("| " + " | ".join(row) + " |")
    return 1 if worst else 0


if __name__ == "__main__":
    if len(sys.argv) < 5 or sys.argv[1] not in ("dump", "compare"):
        sys.exit(__doc__)
    if sys.argv[1] == "dump":
        dump(sys.argv[2], sys.argv[3], sys.argv[4:])
    else:
        sys.exit(compare(sys.argv[2], sys.argv[3], sys.argv[4:]))
