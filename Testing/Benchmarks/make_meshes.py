# SPDX-License-Identifier: BSD-3-Clause
"""Writes the large benchmark meshes: Loop subdivisions of Data/armadillo.off.

    pvpython make_meshes.py OUTPUT_DIR [--source MESH.off]

writes OUTPUT_DIR/armadillo-208k.off (1 Loop subdivision, 4 x 52,000 faces) and
OUTPUT_DIR/armadillo-832k.off (2 subdivisions, 16 x 52,000 faces). Files that already
exist are kept (delete them to regenerate). Each file is written under a temporary name
and renamed, so an interrupted run never leaves a truncated mesh behind.

The source is read with the project's wrapped reader (`from shapediameter import
vtkSDFOFFReader`, needs PYTHONPATH=<build>/lib/python3.11/site-packages) when it is
importable, else with a small numpy parser for triangle-only OFF files. Subdivision is
vtkLoopSubdivisionFilter, which keeps the winding (outward stays outward).
"""

import argparse
import os
import sys

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, numpy_to_vtkIdTypeArray, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
from vtkmodules.vtkFiltersModeling import vtkLoopSubdivisionFilter

SUBDIVISIONS = {1: "armadillo-208k.off", 2: "armadillo-832k.off"}


def read_off_numpy(path):
    """Points (n x 3 float64) and triangles (m x 3 int64) of an ASCII triangle OFF file."""
    with open(path, encoding="ascii") as stream:
        tokens = []
        for line in stream:
            line = line.split("#", 1)[0].strip()
            if line:
                tokens.append(line)
    if not tokens or not tokens[0].startswith("OFF"):
        raise ValueError(f"{path}: not an OFF file")
    header = tokens[0][3:].split() or tokens.pop(1).split()
    n_points, n_faces = int(header[0]), int(header[1])
    body = tokens[1:]
    if len(body) < n_points + n_faces:
        raise ValueError(f"{path}: truncated ({len(body)} lines for {n_points + n_faces} records)")
    points = np.array([row.split()[:3] for row in body[:n_points]], dtype=np.float64)
    faces = [row.split() for row in body[n_points:n_points + n_faces]]
    if any(face[0] != "3" for face in faces):
        raise ValueError(f"{path}: the numpy fallback reads triangle meshes only")
    triangles = np.array([face[1:4] for face in faces], dtype=np.int64)
    return points, triangles


def to_polydata(points, triangles):
    polydata = vtkPolyData()
    vtk_points = vtkPoints()
    vtk_points.SetData(numpy_to_vtk(np.ascontiguousarray(points), deep=True))
    polydata.SetPoints(vtk_points)
    offsets = np.arange(0, 3 * len(triangles) + 1, 3, dtype=np.int64)
    cells = vtkCellArray()
    cells.SetData(numpy_to_vtkIdTypeArray(offsets, deep=True),
                  numpy_to_vtkIdTypeArray(np.ascontiguousarray(triangles.ravel()), deep=True))
    polydata.SetPolys(cells)
    return polydata


def read_source(path):
    try:
        from shapediameter import vtkSDFOFFReader  # noqa: PLC0415 (optional dependency)
    except ImportError:
        print(f"make_meshes: shapediameter not importable, parsing {path} with numpy")
        return to_polydata(*read_off_numpy(path))
    reader = vtkSDFOFFReader()
    reader.SetFileName(path)
    reader.Update()
    polydata = reader.GetOutput()
    if polydata.GetNumberOfPolys() == 0:
        raise RuntimeError(f"vtkSDFOFFReader read no polygon from {path}")
    return polydata


def triangles_of(polydata):
    polys = polydata.GetPolys()
    offsets = vtk_to_numpy(polys.GetOffsetsArray())
    if not np.all(np.diff(offsets) == 3):
        raise RuntimeError("the subdivided mesh is not a triangle mesh")
    return vtk_to_numpy(polys.GetConnectivityArray()).reshape(-1, 3)


def write_off(path, points, triangles):
    temporary = path + ".partial"
    with open(temporary, "w", encoding="ascii") as stream:
        stream.write(f"OFF\n{len(points)} {len(triangles)} 0\n")
        # %.9g round-trips single precision; the subdivided points are averages of the
        # source's 6-digit coordinates, so nothing meaningful is lost.
        np.savetxt(stream, points, fmt="%.9g")
        np.savetxt(stream, np.hstack([np.full((len(triangles), 1), 3, dtype=np.int64), triangles]),
                   fmt="%d")
    os.replace(temporary, path)


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("output_dir")
    parser.add_argument("--source", default=os.path.join(here, "..", "..", "Data", "armadillo.off"))
    args = parser.parse_args()
    os.makedirs(args.output_dir, exist_ok=True)

    todo = {n: os.path.join(args.output_dir, name) for n, name in SUBDIVISIONS.items()
            if not os.path.exists(os.path.join(args.output_dir, name))}
    for name in SUBDIVISIONS.values():
        if os.path.join(args.output_dir, name) not in todo.values():
            print(f"make_meshes: {os.path.join(args.output_dir, name)} exists, kept")
    if not todo:
        return 0

    source = read_source(os.path.abspath(args.source))
    source_faces = source.GetNumberOfPolys()
    for subdivisions, path in todo.items():
        loop = vtkLoopSubdivisionFilter()
        loop.SetNumberOfSubdivisions(subdivisions)
        loop.SetInputData(source)
        loop.Update()
        output = loop.GetOutput()
        points = vtk_to_numpy(output.GetPoints().GetData())
        triangles = triangles_of(output)
        expected = source_faces * 4 ** subdivisions
        if len(triangles) != expected:
            raise RuntimeError(f"{path}: {len(triangles)} faces after subdivision, expected {expected}")
        write_off(path, points, triangles)
        print(f"make_meshes: wrote {path} ({len(points)} points, {len(triangles)} faces)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
