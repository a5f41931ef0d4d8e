# SPDX-License-Identifier: BSD-3-Clause
"""Geometric measures of a curve skeleton given as a graph (node positions and edges).

Shared by measure_skeleton_smoothness.py and measure_rig_recall.py, for our skeleton and a
peer's (read_peer_skeleton: the text format of Testing/Peers/cgal-mcf).

- Bones: the maximal paths between nodes of degree other than 2 (leaves and junctions); a
  closed loop of degree-2 nodes is one bone that starts and ends at its lowest node.
- Turning angle: every bone resampled at a spacing of half the local radius (the distance
  from the skeleton to the surface, interpolated along the edges), then the angle between
  consecutive edges of the resampled polyline at its interior points (the bone's ends, at
  junctions and leaves, are left out). Also the same angle at the nodes as output.
- Length / chord: a bone's length over the distance between its ends (open bones only).
"""
import os
import subprocess

import numpy as np

import shapediameter
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import mutable
from vtkmodules.vtkCommonDataModel import vtkGenericCell, vtkStaticCellLocator
from vtkmodules.vtkFiltersCore import vtkTriangleFilter

import chain_settings


def read_triangles(path, scratch):
    """The triangulated surface of a mesh file (chain_settings.read_mesh formats)."""
    triangles = vtkTriangleFilter()
    triangles.SetInputData(chain_settings.read_mesh(path, scratch))
    triangles.Update()
    return triangles.GetOutput()


def product_skeleton(surface, arguments):
    """vtkSDFSkeleton after the product chain (SDF, smoothing, partition), updated; --set applies."""
    sdf = chain_settings.shape_diameter(arguments)
    sdf.SetInputData(surface)
    smooth = chain_settings.smoothing(arguments)
    smooth.SetInputConnection(sdf.GetOutputPort())
    parts = chain_settings.partition(arguments)
    parts.SetInputConnection(smooth.GetOutputPort())
    skeleton = chain_settings.skeleton(arguments)
    skeleton.SetInputConnection(parts.GetOutputPort())
    skeleton.Update()
    return skeleton


def write_off(surface, path):
    """The triangles of `surface` as an OFF file (the peer program's input)."""
    points = vtk_to_numpy(surface.GetPoints().GetData())
    polys = vtk_to_numpy(surface.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    with open(path, "w") as off:
        off.write("OFF\n%d %d 0\n" % (len(points), len(polys)))
        np.savetxt(off, points, fmt="%.17g")
        np.savetxt(off, np.hstack([np.full((len(polys), 1), 3), polys]), fmt="%d")


def run_peer_mcf(program, surface, scratch):
    """(positions, edges, seconds) of the peer program's skeleton of `surface` (Testing/Peers/cgal-mcf);
    raises RuntimeError with the program's message when it fails."""
    mesh = os.path.join(scratch, "peer-input.off")
    output = os.path.join(scratch, "peer-output.skel")
    write_off(surface, mesh)
    run = subprocess.run([program, mesh, output], capture_output=True, text=True)
    if run.returncode != 0:
        raise RuntimeError("%s: %s" % (os.path.basename(program), (run.stderr or run.stdout).strip()))
    words = run.stdout.split()
    seconds = float("nan")
    for word, following in zip(words, words[1:]):
        if following == "s":
            try:
                seconds = float(word)
            except ValueError:
                pass
    points, edges = read_peer_skeleton(output)
    return points, edges, seconds


def check_peer_program(parser, program):
    """argparse error unless --peer-mcf names an executable."""
    if program and not os.access(program, os.X_OK):
        parser.error("--peer-mcf %s: not an executable program (build Testing/Peers/cgal-mcf)" % program)


def graph_of(skeleton):
    """(positions n x 3, edges m x 2) of vtkSDFSkeleton's skeleton output."""
    count = skeleton.GetNumberOfPoints()
    points = vtk_to_numpy(skeleton.GetPoints().GetData()).astype(float) if count else np.zeros((0, 3))
    edges = np.array(chain_settings.skeleton_edges(skeleton), dtype=int).reshape(-1, 2)
    return points, edges


def read_peer_skeleton(path):
    """(positions, edges) of a peer skeleton file: 'v x y z' and 'e a b' lines (0-based), '#' comments."""
    points, edges = [], []
    with open(path) as text:
        for number, line in enumerate(text, 1):
            fields = line.split()
            if not fields or fields[0].startswith("#") or fields[0] == "r":
                continue
            if fields[0] == "v" and len(fields) >= 4:
                points.append([float(v) for v in fields[1:4]])
            elif fields[0] == "e" and len(fields) >= 3:
                edges.append([int(fields[1]), int(fields[2])])
            else:
                raise ValueError("%s:%d: expected 'v x y z', 'e a b' or 'r d'" % (path, number))
    points = np.array(points, dtype=float).reshape(-1, 3)
    edges = np.array(edges, dtype=int).reshape(-1, 2)
    if len(edges) and (edges.min() < 0 or edges.max() >= len(points)):
        raise ValueError("%s: an edge names a vertex that does not exist" % path)
    return points, edges


def bone_paths(node_count, edges):
    """The bones as lists of node ids (see the module comment); self-loops and repeated edges dropped."""
    neighbours = [set() for _ in range(node_count)]
    for a, b in edges:
        if a != b:
            neighbours[a].add(int(b))
            neighbours[b].add(int(a))
    neighbours = [sorted(n) for n in neighbours]
    used = set()
    paths = []

    def walk(start, first):
        path, previous, current = [start], start, first
        used.add((min(start, first), max(start, first)))
        while len(neighbours[current]) == 2 and current != start:
            path.append(current)
            following = neighbours[current][0] if neighbours[current][1] == previous else neighbours[current][1]
            previous, current = current, following
            key = (min(previous, current), max(previous, current))
            if key in used:
                break
            used.add(key)
        path.append(current)
        return path

    for node in range(node_count):
        if len(neighbours[node]) != 2:
            for other in neighbours[node]:
                if (min(node, other), max(node, other)) not in used:
                    paths.append(walk(node, other))
    for node in range(node_count):  # loops of degree-2 nodes only
        for other in neighbours[node]:
            if (min(node, other), max(node, other)) not in used:
                paths.append(walk(node, other))
    return paths


def closest_cells(surface, points):
    """(distance to the surface, id of the nearest cell) of every point (a vtkPolyData of triangles)."""
    locator = vtkStaticCellLocator()
    locator.SetDataSet(surface)
    locator.BuildLocator()
    closest, cell, cell_id, sub_id, distance2 = [0.0, 0.0, 0.0], vtkGenericCell(), mutable(0), mutable(0), mutable(0.0)
    distances = np.empty(len(points))
    cells = np.empty(len(points), dtype=np.int64)
    for i, point in enumerate(points):
        locator.FindClosestPoint(point.tolist(), closest, cell, cell_id, sub_id, distance2)
        distances[i] = np.sqrt(float(distance2))
        cells[i] = int(cell_id)
    return distances, cells


def surface_distances(surface, points):
    """Distance from every point to the surface (a vtkPolyData of triangles)."""
    return closest_cells(surface, points)[0]


def turning_angles(polyline):
    """Angles (degrees) between consecutive edges at the interior points of a polyline; zero-length edges skipped."""
    steps = np.diff(polyline, axis=0)
    lengths = np.linalg.norm(steps, axis=1)
    steps = steps[lengths > 0] / lengths[lengths > 0, None]
    if len(steps) < 2:
        return np.zeros(0)
    cosine = np.clip((steps[:-1] * steps[1:]).sum(axis=1), -1.0, 1.0)
    return np.degrees(np.arccos(cosine))


def resample(polyline, radii, spacing_factor=0.5):
    """Points along the polyline every spacing_factor x the local radius (radii at its vertices,
    linear along the edges), both ends included; a last step shorter than a quarter of the
    spacing is merged into the one before."""
    lengths = np.linalg.norm(np.diff(polyline, axis=0), axis=1)
    arc = np.concatenate([[0.0], np.cumsum(lengths)])
    total = arc[-1]
    if total <= 0:
        return polyline[:1].copy()
    samples = [0.0]
    while True:
        position = samples[-1]
        step = spacing_factor * float(np.interp(position, arc, radii))
        if position + step >= total:
            if total - position < 0.25 * step and len(samples) > 1:
                samples[-1] = total
            else:
                samples.append(total)
            break
        samples.append(position + step)
    samples = np.array(samples)
    return np.stack([np.interp(samples, arc, polyline[:, axis]) for axis in range(3)], axis=1)


def smoothness(points, edges, radii, spacing_factor=0.5):
    """Measures of a skeleton graph: bones, turning angles (resampled / as output), length / chord.

    radii: the local radius at every node (> 0), e.g. surface_distances of the nodes. Along a
    bone it is taken at least half the bone's median radius: a bone that ends on the surface (our
    tips, MCF's leaves) has radius 0 there, and spacing by it would put thousands of straight
    samples into its last edge."""
    radii = np.maximum(np.asarray(radii, dtype=float), 1e-12)
    resampled, output, ratios = [], [], []
    paths = bone_paths(len(points), edges)
    for path in paths:
        polyline = points[path]
        output.append(turning_angles(polyline))
        local = np.maximum(radii[path], 0.5 * np.median(radii[path]))
        resampled.append(turning_angles(resample(polyline, local, spacing_factor)))
        length = np.linalg.norm(np.diff(polyline, axis=0), axis=1).sum()
        chord = np.linalg.norm(polyline[-1] - polyline[0])
        if path[0] != path[-1] and chord > 0:
            ratios.append(length / chord)
    resampled = np.concatenate(resampled) if resampled else np.zeros(0)
    output = np.concatenate(output) if output else np.zeros(0)
    ratios = np.array(ratios)

    def percentiles(values):
        return (float(np.median(values)), float(np.percentile(values, 90))) if len(values) else (float("nan"),) * 2

    return {
        "bones": len(paths),
        "turning_median": percentiles(resampled)[0], "turning_p90": percentiles(resampled)[1],
        "turning_samples": int(len(resampled)),
        "output_median": percentiles(output)[0], "output_p90": percentiles(output)[1],
        "chord_median": percentiles(ratios)[0], "chord_p90": percentiles(ratios)[1],
        "chord_max": float(ratios.max()) if len(ratios) else float("nan"),
    }
