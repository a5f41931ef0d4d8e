# SPDX-License-Identifier: BSD-3-Clause
"""Resolution consistency: a mesh against its one-level subdivision, through the whole chain.

    pvpython Testing/Evaluation/measure_resolution_consistency.py MESH... [--hit-rule 0|1]
             [--cluster-model 0|1] [--clusters K] [--lambda L] [--expect-at-most PERCENT]

Each MESH (.off, .obj, .ply, .stl, .vtp; triangulated first) is subdivided once by Loop
(vtkLoopSubdivisionFilter: new shape, smoother) and once linearly (vtkLinearSubdivisionFilter:
the same surface with four times the faces). Both filters put faces 4i ... 4i+3 of the result
inside face i of the input, so every fine face has a coarse parent. ShapeDiameter ->
SDFBilateralSmooth -> SDFGMMPartition runs on all three meshes; printed per mesh and
subdivision: the share of the surface area whose SDFCluster differs from its parent's after the
best one-to-one matching of labels (Hungarian, scipy), and the clusters covering >= 1 % of the
area. --expect-at-most makes it a test: exit status 1 when any share exceeds PERCENT.

Needs PYTHONPATH to contain build/lib/python3.11/site-packages (the README's pvpython setup).
"""
import argparse
import os
import sys

import numpy as np
from scipy.optimize import linear_sum_assignment

import shapediameter
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkFiltersCore import vtkTriangleFilter
from vtkmodules.vtkFiltersModeling import vtkLinearSubdivisionFilter, vtkLoopSubdivisionFilter
from vtkmodules.vtkFiltersVerdict import vtkCellSizeFilter

import chain_settings
from chain_settings import READERS


def partition(source, arguments):
    """Cluster labels and face areas of the chain on `source` (an algorithm)."""
    sdf = chain_settings.shape_diameter(arguments)
    sdf.SetInputConnection(source.GetOutputPort())
    smooth = shapediameter.vtkSDFBilateralSmooth()
    smooth.SetInputConnection(sdf.GetOutputPort())
    parts = chain_settings.partition(arguments)
    parts.SetInputConnection(smooth.GetOutputPort())
    sizes = vtkCellSizeFilter()
    sizes.SetInputConnection(parts.GetOutputPort())
    sizes.Update()
    cells = sizes.GetOutput().GetCellData()
    return (vtk_to_numpy(cells.GetArray("SDFCluster")).astype(int),
            vtk_to_numpy(cells.GetArray("Area")).copy())


def changed_area(coarse, fine, fine_area):
    """Share (%) of the fine area whose label differs from its parent's after the best matching."""
    parent = coarse[np.arange(len(fine)) // 4]
    size = int(max(parent.max(), fine.max())) + 1
    overlap = np.zeros((size, size))
    np.add.at(overlap, (parent, fine), fine_area)
    rows, columns = linear_sum_assignment(-overlap)
    return 100.0 * (1.0 - overlap[rows, columns].sum() / fine_area.sum())


def large_clusters(labels, area):
    return int((np.bincount(labels, weights=area) / area.sum() >= 0.01).sum())


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("meshes", nargs="+")
    chain_settings.add_arguments(parser)
    parser.add_argument("--expect-at-most", type=float, default=None, metavar="PERCENT",
                        help="fail (exit 1) when a share exceeds PERCENT")
    arguments = parser.parse_args()
    worst = 0.0
    print("| mesh | faces | clusters | Loop: % area changed, clusters | linear: % area changed, clusters |")
    print("|---|---:|---:|---:|---:|")
    for path in arguments.meshes:
        extension = os.path.splitext(path)[1].lower()
        if extension not in READERS or not os.path.isfile(path):
            sys.exit("%s: not a readable mesh (%s)" % (path, ", ".join(sorted(READERS))))
        reader = READERS[extension]()
        reader.SetFileName(path)
        triangles = vtkTriangleFilter()
        triangles.SetInputConnection(reader.GetOutputPort())
        triangles.PassVertsOff()
        triangles.PassLinesOff()
        coarse, coarse_area = partition(triangles, arguments)
        row = [os.path.basename(path), str(len(coarse)), str(large_clusters(coarse, coarse_area))]
        for subdivision in (vtkLoopSubdivisionFilter, vtkLinearSubdivisionFilter):
            refine = subdivision()
            refine.SetNumberOfSubdivisions(1)
            refine.SetInputConnection(triangles.GetOutputPort())
            fine, fine_area = partition(refine, arguments)
            if len(fine) != 4 * len(coarse):
                sys.exit("%s: %s gave %d faces, not 4 x %d" % (path, subdivision.__name__, len(fine), len(coarse)))
            share = changed_area(coarse, fine, fine_area)
            worst = max(worst, share)
            row.append("%.2f %%, %d" % (share, large_clusters(fine, fine_area)))
        print("| " + " | ".join(row) + " |", flush=True)
    if arguments.expect_at_most is not None and not worst <= arguments.expect_at_most:
        sys.exit("FAIL: %.2f %% of the area changes cluster, more than %.2f %%" % (worst, arguments.expect_at_most))


if __name__ == "__main__":
    main()
