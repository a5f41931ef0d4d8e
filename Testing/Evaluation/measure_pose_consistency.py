# SPDX-License-Identifier: BSD-3-Clause
"""Pose consistency of the whole chain on a folder of poses (same connectivity in every pose).

    pvpython Testing/Evaluation/measure_pose_consistency.py FOLDER [--hit-rule 0|1]
             [--cluster-model 0|1] [--clusters K] [--lambda L] [--set Class.Property=value ...]
             [--family] [--expect-at-most PERCENT] [--expect-segment-change-at-most PERCENT]
             [--skeleton [--skeleton-link segment|nearest]
             [--skeleton-seeds S1,S2,...] [--expect-bone-change-at-most PERCENT]]

FOLDER holds the poses as .obj, .obj.gz, .off, .ply, .stl or .vtp files with identical
connectivity (face i is the same place in every pose), e.g. ../shared/data/poses/elephant.
Runs ShapeDiameter -> SDFBilateralSmooth -> SDFGMMPartition on each pose through the wrapped
classes (package shapediameter, from build/) and prints:

- the mean relative pose divergence of the raw and smoothed SDF per face (|v - mean over
  poses| / mean over poses), with its median and 90th percentile;
- the mean pose divergence of SDFNormalized (|nsdf - mean over poses|, the paper's Fig. 5
  measure, in percent of the [0, 1] range);
- the Table-2 measure of SDFCluster: mean over all pose pairs of the share of faces with a
  different cluster after the best one-to-one matching of labels (Hungarian, scipy);
- per pose: clusters covering at least 1 % of the area;
- the same Table-2 measure of SDFSegment (the connected parts the user sees: segments matched
  one to one by their shared faces, the faces of unmatched segments count as different), and
  per pose the segments and the segments covering at least 1 % of the area;
- with --skeleton: the skeleton of every pose (vtkSDFSkeleton at its defaults on the
  partitioned pose, as the pipeline command chains them): leaves and junctions per pose, and
  the Table-2 measure of SkeletonBoneId (faces changing bone; faces linked to no bone count as
  one more label). --skeleton-link nearest turns LinkBySegment off (each face takes the bone
  of its nearest node, not its SDFSegment's bone). --skeleton-seeds runs the skeletons once per
  sampling Seed listed and prints each run and the mean over them: the skeleton's topology
  changes with the seed about as much as with the pose (docs/skeleton.md), so
  one seed's number is partly luck.

--expect-bone-change-at-most applies to the mean over the seeds (the one run without
--skeleton-seeds).

--family normalises every pose with one range (the widest SDFNormalizationRange of the
poses) and partitions it with one model fitted on all poses together (the pipeline
command's --family). --expect-at-most makes it a test: exit status 1 when the Table-2 measure
of SDFCluster exceeds PERCENT; --expect-segment-change-at-most the same for SDFSegment.
--set Class.Property=value calls Set<Property> on every filter of that class of the chain
(chain_settings.py), e.g. --set vtkSDFGMMPartition.ModeProminence=0.05. A FOLDER that does not exist prints 'SKIP: ...' and exits 0 (ctest skips).

Needs PYTHONPATH to contain build/lib/python3.11/site-packages (the README's pvpython setup).
"""
import argparse
import itertools
import os
import sys
import tempfile

import numpy as np
from scipy.optimize import linear_sum_assignment

from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkFiltersCore import vtkAppendPolyData
from vtkmodules.vtkFiltersVerdict import vtkCellSizeFilter

import chain_settings
from chain_settings import READERS


def table2(labelings):
    """Mean over pairs of the share of faces labelled differently after the best matching."""
    shares = []
    for a, b in itertools.combinations(labelings, 2):
        size = int(max(a.max(), b.max())) + 1
        counts = np.zeros((size, size))
        np.add.at(counts, (a, b), 1)
        rows, columns = linear_sum_assignment(-counts)
        shares.append(1.0 - counts[rows, columns].sum() / len(a))
    return 100.0 * float(np.mean(shares))


def large_labels(labelings, areas, share=0.01):
    """Per labeling: the labels covering at least share of the area."""
    return [int((np.bincount(l, weights=a) / a.sum() >= share).sum()) for l, a in zip(labelings, areas)]


def pose_files(folder):
    """The mesh files of a pose folder (READERS' formats, optionally gzipped), 2 before 10."""
    suffixes = tuple(READERS) + tuple(s + ".gz" for s in READERS)
    return sorted((n for n in os.listdir(folder) if n.lower().endswith(suffixes)), key=lambda n: (len(n), n))


def share_normalization_range(smooths):
    """One normalisation for a family: every vtkSDFBilateralSmooth of `smooths` re-run with the
    widest range of SDFSmoothed over them."""
    ranges = [vtk_to_numpy(s.GetOutput().GetFieldData().GetArray("SDFNormalizationRange")) for s in smooths]
    shared = (min(r[0] for r in ranges), max(r[1] for r in ranges))
    for smooth in smooths:
        smooth.SetNormalizationRange(*shared)
        smooth.Update()


def partition_poses(surfaces, make_partition, family):
    """Per surface, the partition's output and its cell data with `Area`; family: every surface
    partitioned with one model, fitted on all of them appended (the filter's Model port)."""
    model = None
    if family:
        append = vtkAppendPolyData()
        for surface in surfaces:
            append.AddInputData(surface)
        model = make_partition()
        model.SetInputConnection(append.GetOutputPort())
        model.Update()
    results = []
    for surface in surfaces:
        partition = make_partition()
        partition.SetInputData(surface)
        if model is not None:
            partition.SetModelConnection(model.GetOutputPort())
        sizes = vtkCellSizeFilter()
        sizes.SetInputConnection(partition.GetOutputPort())
        sizes.Update()
        results.append((partition.GetOutput(), sizes.GetOutput().GetCellData()))
    return results


def leaves_and_junctions(skeleton):
    """Nodes of degree 1 and of degree >= 3 in the graph of the skeleton's polylines."""
    edges = {(min(a, b), max(a, b)) for a, b in chain_settings.skeleton_edges(skeleton) if a != b}
    degree = {}
    for a, b in edges:
        degree[a] = degree.get(a, 0) + 1
        degree[b] = degree.get(b, 0) + 1
    return (sum(1 for d in degree.values() if d == 1), sum(1 for d in degree.values() if d >= 3))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("folder")
    chain_settings.add_arguments(parser)
    parser.add_argument("--family", action="store_true", help="one normalisation range and one model for all poses")
    parser.add_argument("--expect-at-most", type=float, default=None, metavar="PERCENT",
                        help="fail (exit 1) when the Table-2 measure of SDFCluster exceeds PERCENT")
    parser.add_argument("--expect-segment-change-at-most", type=float, default=None, metavar="PERCENT",
                        help="fail (exit 1) when the Table-2 measure of SDFSegment exceeds PERCENT")
    parser.add_argument("--skeleton", action="store_true",
                        help="also the skeleton of every pose: leaves, junctions, faces changing SkeletonBoneId")
    parser.add_argument("--skeleton-link", choices=("segment", "nearest"), default="segment",
                        help="with --skeleton: vtkSDFSkeleton's LinkBySegment on (default) or off")
    parser.add_argument("--skeleton-seeds", default=None, metavar="S1,S2,...",
                        help="with --skeleton: one run per vtkSDFSkeleton Seed (default: the filter's seed)")
    parser.add_argument("--expect-bone-change-at-most", type=float, default=None, metavar="PERCENT",
                        help="with --skeleton: fail when more than PERCENT of the faces change bone")
    arguments = parser.parse_args()
    if not os.path.isdir(arguments.folder):
        print("SKIP: %s does not exist (the shared development data is not on this machine)" % arguments.folder)
        return
    names = pose_files(arguments.folder)
    if len(names) < 2:
        sys.exit("%s: fewer than two poses" % arguments.folder)
    columns = {"SDF": [], "SDFSmoothed": [], "SDFNormalized": [], "SDFCluster": [], "SDFSegment": [], "Area": []}

    smoothed = []
    with tempfile.TemporaryDirectory() as scratch:
        for name in names:
            sdf = chain_settings.shape_diameter(arguments)
            sdf.SetInputData(chain_settings.read_mesh(os.path.join(arguments.folder, name), scratch))
            smooth = chain_settings.smoothing(arguments)
            smooth.SetInputConnection(sdf.GetOutputPort())
            smooth.Update()
            smoothed.append(smooth)
            print("%s: %d faces" % (name, smooth.GetOutput().GetNumberOfCells()), flush=True)
    if arguments.family:
        share_normalization_range(smoothed)
    smoothed = [smooth.GetOutput() for smooth in smoothed]
    partitioned = []
    for output, cells in partition_poses(smoothed, lambda: chain_settings.partition(arguments), arguments.family):
        partitioned.append(output)
        for key in columns:
            columns[key].append(vtk_to_numpy(cells.GetArray(key)).copy())
    if len({len(c) for c in columns["SDF"]}) != 1:
        sys.exit("the poses differ in their face count: not one family")
    for key in ("SDF", "SDFSmoothed"):
        values = np.array(columns[key])
        mean = values.mean(axis=0)
        relative = np.abs(values - mean) / np.maximum(mean, 1e-300)
        print("%-12s relative pose divergence: mean %.2f %%, median %.2f %%, 90th percentile %.2f %%" % (
            key, 100 * relative.mean(), 100 * np.median(relative), 100 * np.percentile(relative, 90)))
    normalized = np.array(columns["SDFNormalized"])
    print("SDFNormalized pose divergence (paper, Fig. 5): %.2f %%" % (
        100 * np.abs(normalized - normalized.mean(axis=0)).mean()))
    labels = [c.astype(int) for c in columns["SDFCluster"]]
    measure = table2(labels)
    print("SDFCluster Table-2 measure%s: %.2f %% of the faces change cluster between poses" % (
        " (family model)" if arguments.family else "", measure))
    print("clusters covering >= 1 %% of the area, per pose: %s" % large_labels(labels, columns["Area"]))
    segments = [c.astype(int) for c in columns["SDFSegment"]]
    segment_change = table2(segments)
    print("SDFSegment Table-2 measure%s: %.2f %% of the faces change segment between poses" % (
        " (family model)" if arguments.family else "", segment_change))
    print("segments per pose: %s" % [len(np.unique(s)) for s in segments])
    print("segments covering >= 1 %% of the area, per pose: %s" % large_labels(segments, columns["Area"]))
    failures = []
    if arguments.expect_at_most is not None and not measure <= arguments.expect_at_most:
        failures.append("%.2f %% of the faces change cluster, more than %.2f %%" % (measure, arguments.expect_at_most))
    limit = arguments.expect_segment_change_at_most
    if limit is not None and not segment_change <= limit:
        failures.append("%.2f %% of the faces change segment, more than %.2f %%" % (segment_change, limit))
    if arguments.skeleton:
        seeds = [None] if arguments.skeleton_seeds is None else [int(s) for s in arguments.skeleton_seeds.split(",")]
        changes = []
        for seed in seeds:
            bones, shapes = [], []
            for surface in partitioned:
                skeleton = chain_settings.skeleton(arguments)
                skeleton.SetLinkBySegment(arguments.skeleton_link == "segment")
                if seed is not None:
                    skeleton.SetSeed(seed)
                skeleton.SetInputData(surface)
                skeleton.Update()
                bones.append(vtk_to_numpy(skeleton.GetSurface().GetCellData().GetArray("SkeletonBoneId")).astype(int) + 1)
                shapes.append(leaves_and_junctions(skeleton.GetSkeleton()))
            changes.append(table2(bones))
            label = "" if seed is None else " (seed %d)" % seed
            print("skeleton (leaves, junctions) per pose%s: %s" % (label, shapes))
            print("SkeletonBoneId Table-2 measure%s: %.2f %% of the faces change bone between poses" % (label, changes[-1]))
        bone_change = float(np.mean(changes))
        if len(seeds) > 1:
            print("SkeletonBoneId Table-2 measure, mean over %d seeds: %.2f %% (%.2f to %.2f %%)" % (
                len(seeds), bone_change, min(changes), max(changes)))
        limit = arguments.expect_bone_change_at_most
        if limit is not None and not bone_change <= limit:
            failures.append("%.2f %% of the faces change bone, more than %.2f %%" % (bone_change, limit))
    if failures:
        sys.exit("FAIL: " + "; ".join(failures))


if __name__ == "__main__":
    main()
