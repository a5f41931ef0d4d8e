# SPDX-License-Identifier: BSD-3-Clause
"""Skeleton against people's segmentations: does every limb a person cut get a skeleton leaf?

    pvpython Testing/Evaluation/measure_limb_reach.py PSB_FOLDER [--ids 1-20,81-100]
             [--minimum-area 0.005] [--peer-mcf PROGRAM] [--verbose]
             [--expect-reach-at-least PERCENT] [--expect-stray-at-most PERCENT]
             [--seeds S1,S2,...] [--hit-rule 0|1] [--set Class.Property=value ...]

PSB_FOLDER is the segmentation benchmark's layout (../shared/data/psb: <id>.off.gz and
<id>/<id>_<k>.seg.gz, one segment label per face). Every mesh runs through the product chain
at the defaults (ShapeDiameter -> SDFBilateralSmooth -> SDFGMMPartition -> SDFSkeleton; --set
changes a filter's property). For every human segmentation of a mesh:

- its limbs are the segments that touch exactly one other segment (across a shared edge) and
  hold at least --minimum-area of the surface: a hand, a foot, a head on a neck, a tail, an
  ear, a tentacle's end;
- a skeleton leaf (a node of degree 1) lands in the segment of the surface face nearest to it;
- reach = limbs with a leaf / limbs; stray = leaves in a segment that is not a limb / leaves
  (a leaf inside a torso, or a second leaf of a limb does not count as stray).

Each mesh's figures are the means over its segmentations; printed per mesh (--verbose), per
category (the benchmark's id ranges) and over all meshes. A rig measures where joints sit;
this measures only whether each limb has a branch, on the 345 development meshes with about
eleven segmentations each, so that a change is not judged on three rigs alone. --peer-mcf adds
the same figures for CGAL's mean-curvature-flow skeleton (Testing/Peers/cgal-mcf, built
separately; never part of the product). --expect-reach-at-least and --expect-stray-at-most make
the means over all meshes a test (exit status 1 beyond either). --seeds runs our skeleton again
with each sampling seed (vtkSDFSkeleton's Seed; the chain before it is not re-run): a column per
seed, and "ours" is then each mesh's mean over the seeds, which the expectations judge. One
seed's figures are one draw: a change judged on the default seed alone can look larger or
smaller than it is (docs/skeleton.md). A missing folder prints 'SKIP: ...' and exits 0.

Needs PYTHONPATH to contain build/lib/python3.11/site-packages (the README's pvpython setup).
"""
import argparse
import gzip
import os
import sys
import tempfile

import numpy as np

from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkFiltersVerdict import vtkCellSizeFilter

import chain_settings
import run_psb_chain
import skeleton_measures

CATEGORIES = [("Human", 1, 20), ("Cup", 21, 40), ("Glasses", 41, 60), ("Airplane", 61, 80),
              ("Ant", 81, 100), ("Chair", 101, 120), ("Octopus", 121, 140), ("Table", 141, 160),
              ("Teddy", 161, 180), ("Hand", 181, 200), ("Plier", 201, 220), ("Fish", 221, 240),
              ("Bird", 241, 260), ("Armadillo", 281, 300), ("Bust", 301, 320), ("Mech", 321, 340),
              ("Bearing", 341, 360), ("Vase", 361, 380), ("FourLeg", 381, 400)]


def category_of(mesh_id):
    for name, first, last in CATEGORIES:
        if first <= mesh_id <= last:
            return name
    return "other"


def read_labels(path, face_count):
    """One integer label per face of a .seg or .seg.gz file; raises ValueError when the count differs."""
    opener = gzip.open if path.endswith(".gz") else open
    with opener(path, "rt") as text:
        labels = np.array([int(line) for line in text if line.strip()], dtype=np.int64)
    if len(labels) != face_count:
        raise ValueError("%s: %d labels for %d faces" % (path, len(labels), face_count))
    return labels


def face_pairs(triangles):
    """The pairs of faces (i < j) that share an edge, as an m x 2 array."""
    edges = np.sort(np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]]), axis=1)
    faces = np.tile(np.arange(len(triangles)), 3)
    order = np.lexsort((edges[:, 1], edges[:, 0]))
    edges, faces = edges[order], faces[order]
    same = np.all(edges[1:] == edges[:-1], axis=1)
    return np.stack([faces[:-1][same], faces[1:][same]], axis=1)


def limbs_of(labels, pairs, areas, minimum_area):
    """The labels of the segments that touch exactly one other segment and hold at least
    minimum_area of the total area."""
    a, b = labels[pairs[:, 0]], labels[pairs[:, 1]]
    across = a != b
    neighbours = {}
    for x, y in zip(a[across], b[across]):
        neighbours.setdefault(int(x), set()).add(int(y))
        neighbours.setdefault(int(y), set()).add(int(x))
    total = areas.sum()
    limbs = set()
    for label, touching in neighbours.items():
        if len(touching) == 1 and areas[labels == label].sum() >= minimum_area * total:
            limbs.add(label)
    return limbs


def leaves_of(points, edges):
    """The positions of the nodes of degree 1."""
    degree = np.bincount(edges.ravel(), minlength=len(points)) if len(edges) else np.zeros(len(points), int)
    return points[degree == 1]


def reach_and_stray(leaf_faces, segmentations, pairs, areas, minimum_area):
    """(mean reach, mean stray, limbs per segmentation) of a skeleton's leaves (their nearest
    faces) against every segmentation; reach is None when no segmentation has a limb."""
    reaches, strays, limb_counts = [], [], []
    for labels in segmentations:
        limbs = limbs_of(labels, pairs, areas, minimum_area)
        limb_counts.append(len(limbs))
        landed = [int(labels[f]) for f in leaf_faces]
        if limbs:
            reaches.append(len(limbs & set(landed)) / len(limbs))
        if landed:
            strays.append(sum(1 for label in landed if label not in limbs) / len(landed))
    return (float(np.mean(reaches)) if reaches else None,
            float(np.mean(strays)) if strays else 0.0, limb_counts)


def measure_mesh(folder, mesh_id, path, arguments, scratch):
    """{name: (reach, stray, leaves)} for ours (and the peer), or None without segmentations."""
    surface = skeleton_measures.read_triangles(path, scratch)
    triangles = vtk_to_numpy(surface.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    sizes = vtkCellSizeFilter()
    sizes.SetInputData(surface)
    sizes.ComputeAreaOn()
    sizes.Update()
    areas = vtk_to_numpy(sizes.GetOutput().GetCellData().GetArray("Area")).astype(float)
    pairs = face_pairs(triangles)
    segmentation_dir = os.path.join(folder, str(mesh_id))
    segmentations = [read_labels(os.path.join(segmentation_dir, name), len(triangles))
                     for name in sorted(os.listdir(segmentation_dir)) if ".seg" in name]
    if not segmentations:
        return None
    skeleton = skeleton_measures.product_skeleton(surface, arguments)
    skeletons = {}
    for seed in arguments.seeds or [None]:
        if seed is not None:
            skeleton.SetSeed(seed)
            skeleton.Update()
        points, edges = skeleton_measures.graph_of(skeleton.GetSkeleton())
        skeletons["ours" if seed is None else "seed %d" % seed] = (np.array(points), np.array(edges))
    if arguments.peer_mcf:
        try:
            points, edges, _ = skeleton_measures.run_peer_mcf(arguments.peer_mcf, surface, scratch)
            skeletons["CGAL MCF"] = (points, edges)
        except (RuntimeError, ValueError) as error:
            print("%d: CGAL MCF failed: %s" % (mesh_id, error))
    figures = {}
    for name, (points, edges) in skeletons.items():
        leaves = leaves_of(points, edges)
        reach, stray, limb_counts = reach_and_stray(skeleton_measures.closest_cells(surface, leaves)[1], segmentations, pairs, areas,
                                                    arguments.minimum_area)
        figures[name] = (reach, stray, len(leaves), float(np.mean(limb_counts)))
    if arguments.seeds:
        draws = [figures["seed %d" % seed] for seed in arguments.seeds]
        reaches = [draw[0] for draw in draws]
        figures["ours"] = (None if None in reaches else float(np.mean(reaches)),
                           float(np.mean([draw[1] for draw in draws])), float(np.mean([draw[2] for draw in draws])), draws[0][3])
    return figures


def seed_list(text):
    """The sampling seeds of --seeds: distinct integers, comma separated."""
    try:
        seeds = [int(word) for word in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError("seeds are integers separated by commas: %r" % text)
    if not seeds or len(set(seeds)) != len(seeds):
        raise argparse.ArgumentTypeError("seeds must be distinct: %r" % text)
    return seeds


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("folder")
    parser.add_argument("--ids", default=None, help="mesh ids and ranges, e.g. 1-20,81-100 (default: all)")
    parser.add_argument("--minimum-area", type=float, default=0.005, help="a limb's least share of the area")
    parser.add_argument("--peer-mcf", metavar="PROGRAM", help="Testing/Peers/cgal-mcf's sdf-peer-mcf")
    parser.add_argument("--verbose", action="store_true", help="a line per mesh")
    parser.add_argument("--expect-reach-at-least", type=float, default=None, metavar="PERCENT")
    parser.add_argument("--expect-stray-at-most", type=float, default=None, metavar="PERCENT")
    parser.add_argument("--seeds", type=seed_list, default=None, metavar="S1,S2,...",
                        help="our skeleton with each sampling seed; 'ours' = the mean over them")
    chain_settings.add_arguments(parser)
    arguments = parser.parse_args()
    skeleton_measures.check_peer_program(parser, arguments.peer_mcf)
    if not os.path.isdir(arguments.folder):
        print("SKIP: %s does not exist (the shared development data is not on this machine)" % arguments.folder)
        return
    files = run_psb_chain.mesh_files(arguments.folder)
    per_category = {}
    with tempfile.TemporaryDirectory() as scratch:
        for mesh_id in run_psb_chain.select_ids(arguments.ids, files, arguments.folder):
            figures = measure_mesh(arguments.folder, mesh_id, files[mesh_id], arguments, scratch)
            if figures is None:
                continue
            for name, (reach, stray, leaves, limbs) in figures.items():
                if arguments.verbose:
                    print("%4d %-9s %-8s leaves %3d, limbs %4.1f, reach %s, stray %5.1f %%" % (
                        mesh_id, category_of(mesh_id), name, leaves, limbs,
                        "  -  " if reach is None else "%5.1f %%" % (100 * reach), 100 * stray))
                if reach is not None:
                    per_category.setdefault((name, category_of(mesh_id)), []).append((reach, stray, leaves, limbs))
    if not any(name == "ours" for name, _ in per_category):
        message = "no mesh with a limb among the ids measured"
        if arguments.expect_reach_at_least is not None or arguments.expect_stray_at_most is not None:
            sys.exit("FAIL: " + message)
        print(message)
        return
    present = {name for name, _ in per_category}
    names = [n for n in ["ours"] + ["seed %d" % seed for seed in arguments.seeds or []] if n in present]
    names += sorted(present - set(names))
    print("| category | meshes | limbs | " + " | ".join("%s: reach / stray / leaves" % n for n in names) + " |")
    print("|---|---:|---:|" + "---:|" * len(names))
    overall = {name: [] for name in names}
    for category, _, _ in CATEGORIES + [("other", 0, 0)]:
        rows = {name: per_category.get((name, category), []) for name in names}
        if not rows[names[0]]:
            continue
        cells = []
        for name in names:
            values = np.array(rows[name]) if rows[name] else np.zeros((0, 4))
            overall[name].extend(rows[name])
            cells.append("%.1f %% / %.1f %% / %.1f" % (100 * values[:, 0].mean(), 100 * values[:, 1].mean(), values[:, 2].mean())
                         if len(values) else "-")
        print("| %s | %d | %.1f | %s |" % (category, len(rows[names[0]]), np.mean([r[3] for r in rows[names[0]]]), " | ".join(cells)))
    for name in names:
        values = np.array(overall[name])
        print("%s over %d meshes with limbs: reach %.1f %%, stray %.1f %%, leaves %.1f" % (
            name, len(values), 100 * values[:, 0].mean(), 100 * values[:, 1].mean(), values[:, 2].mean()))
    ours = np.array(overall["ours"])
    failed = []
    if arguments.expect_reach_at_least is not None and not 100 * ours[:, 0].mean() >= arguments.expect_reach_at_least:
        failed.append("reach %.1f %% below %.1f %%" % (100 * ours[:, 0].mean(), arguments.expect_reach_at_least))
    if arguments.expect_stray_at_most is not None and not 100 * ours[:, 1].mean() <= arguments.expect_stray_at_most:
        failed.append("stray %.1f %% above %.1f %%" % (100 * ours[:, 1].mean(), arguments.expect_stray_at_most))
    if failed:
        sys.exit("FAIL: " + "; ".join(failed))


if __name__ == "__main__":
    main()
