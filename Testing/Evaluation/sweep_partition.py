# SPDX-License-Identifier: BSD-3-Clause
"""Partition settings against each other: the SDF and the smoothing once per mesh, then every
setting of a JSON file on the same smoothed surface.

    pvpython Testing/Evaluation/sweep_partition.py SETTINGS.json [--psb PSB_DIR] [--ids LIST]
             [--poses FOLDER] [--output-dir DIR] [--jobs N]

SETTINGS.json: {"name": {"Property": value, ...}, ...}; each property is set on
vtkSDFGMMPartition (Set<Property>) over the filter's defaults, e.g.
{"defaults": {}, "lambda 0.08": {"Lambda": 0.08}}.

--psb: every mesh of a PSB-layout folder (or --ids, as run_psb_chain.py) goes through the reader,
vtkShapeDiameterFilter and vtkSDFBilateralSmooth once (defaults, one thread per mesh, --jobs
meshes at once); each setting's SDFSegment goes to DIR/<name>/<id>.seg and is scored by
sdf-psb-benchmark (DIR/<name>/benchmark.json). Printed per setting: overall and articulated
1 - RI, the articulated share within a factor 1.5 of the humans' segment count, and 1 - RI per
category. Identical to Testing/Evaluation/psb-benchmark for the same settings (the chain is the
same; only the SDF is not recomputed).

--poses: a pose family (as measure_pose_consistency.py): each pose's own normalisation and the
family's shared range and model; printed per setting the Table-2 measure on SDFCluster and
SDFSegment, each pose alone and --family, and the clusters covering >= 1 % per pose.

Needs PYTHONPATH to contain build/lib/python3.11/site-packages (the README's pvpython setup)
and SHAPEDIAMETER_BUILD_DIR or build/ for sdf-psb-benchmark.
"""
import argparse
import json
import multiprocessing
import os
import subprocess
import sys
import tempfile

import numpy as np

import shapediameter
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkPolyData

import chain_settings
import run_psb_chain
from measure_pose_consistency import large_labels, partition_poses, pose_files, share_normalization_range, table2

SETTINGS = {}
OUTPUT = None


def partition(properties, threads=0):
    """A vtkSDFGMMPartition with the setting's properties over its defaults; as --set, a value
    the filter clamped is an error (chain_settings.apply_settings)."""
    algorithm = shapediameter.vtkSDFGMMPartition()
    algorithm.SetNumberOfThreads(threads)
    settings = []
    for name, value in properties.items():
        if not hasattr(algorithm, "Set" + name):
            raise SystemExit("vtkSDFGMMPartition has no property %s" % name)
        settings.append(("vtkSDFGMMPartition", name, value if isinstance(value, list) else [value]))
    return chain_settings.apply_settings(algorithm, argparse.Namespace(settings=settings))


def smoothed(path, scratch, threads):
    sdf = shapediameter.vtkShapeDiameterFilter()
    sdf.SetNumberOfThreads(threads)
    sdf.SetInputData(chain_settings.read_mesh(path, scratch))
    smooth = shapediameter.vtkSDFBilateralSmooth()
    smooth.SetNumberOfThreads(threads)
    smooth.SetInputConnection(sdf.GetOutputPort())
    smooth.Update()
    return smooth


def psb_mesh(task):
    """One PSB mesh: every setting's SDFSegment written; None or the error text."""
    mesh_id, path = task
    try:
        with tempfile.TemporaryDirectory() as scratch:
            surface = smoothed(path, scratch, 1).GetOutput()
        for name, properties in SETTINGS.items():
            algorithm = partition(properties, 1)
            algorithm.SetInputData(surface)
            algorithm.Update()
            segments = vtk_to_numpy(algorithm.GetOutput().GetCellData().GetArray("SDFSegment"))
            np.savetxt(os.path.join(OUTPUT, name, "%d.seg" % mesh_id), segments.astype(np.int64), fmt="%d")
        return mesh_id, None
    except Exception as error:  # reported per mesh, the others go on
        return mesh_id, str(error)


def sweep_psb(arguments):
    files = run_psb_chain.mesh_files(arguments.psb)
    ids = run_psb_chain.select_ids(arguments.ids, files, arguments.psb)
    for name in SETTINGS:
        os.makedirs(os.path.join(OUTPUT, name), exist_ok=True)
    largest_first = sorted(ids, key=lambda i: -os.path.getsize(files[i]))
    failed = []
    # close + join, not the context manager: its terminate() kills the workers with SIGTERM,
    # which ParaView's signal handler reports with a stack trace.
    pool = multiprocessing.get_context("fork").Pool(arguments.jobs, maxtasksperchild=50)
    for mesh_id, error in pool.imap_unordered(psb_mesh, [(i, files[i]) for i in largest_first]):
        if error:
            failed.append(mesh_id)
            print("mesh %d failed: %s" % (mesh_id, error), file=sys.stderr)
    pool.close()
    pool.join()
    build = os.environ.get("SHAPEDIAMETER_BUILD_DIR", os.path.join(os.path.dirname(__file__), "..", "..", "build"))
    scorer = os.path.join(build, "bin", "sdf-psb-benchmark")
    print("| setting | PSB 1 - RI | articulated | within 1.5x | per category |")
    print("|---|---:|---:|---:|---|")
    for name in SETTINGS:
        command = [scorer, arguments.psb, os.path.join(OUTPUT, name), "--json", "--allow-missing"]
        if arguments.ids:
            command += ["--ids", arguments.ids]
        result = subprocess.run(command, capture_output=True, text=True)
        if result.returncode != 0:
            raise SystemExit("sdf-psb-benchmark failed on %s: %s" % (name, result.stderr.strip()))
        with open(os.path.join(OUTPUT, name, "benchmark.json"), "w") as stream:
            stream.write(result.stdout)
        scores = json.loads(result.stdout)
        categories = " ".join("%s %.3f" % (c["name"], c["randIndexError"]) for c in scores["categories"])
        print("| %s | %.4f | %.4f | %.0f %% | %s |" % (name, scores["overall"]["randIndexError"],
              scores["articulated"]["randIndexError"], 100 * scores["articulated"]["withinFactorShare"], categories))
    return 1 if failed else 0


def sweep_poses(arguments):
    names = pose_files(arguments.poses)
    with tempfile.TemporaryDirectory() as scratch:
        smooths = [smoothed(os.path.join(arguments.poses, n), scratch, 0) for n in names]

    def outputs():
        copies = [vtkPolyData() for _ in smooths]
        for copy, smooth in zip(copies, smooths):
            copy.DeepCopy(smooth.GetOutput())
        return copies

    alone = outputs()
    share_normalization_range(smooths)
    family = outputs()
    print("| setting | alone: SDFCluster / SDFSegment | family | clusters >= 1 % per pose (alone) |")
    print("|---|---:|---:|---|")
    for name, properties in SETTINGS.items():
        row = []
        for surfaces, shared in ((alone, False), (family, True)):
            results = partition_poses(surfaces, lambda: partition(properties), shared)
            clusters = [vtk_to_numpy(cells.GetArray("SDFCluster")).astype(int) for _, cells in results]
            segments = [vtk_to_numpy(cells.GetArray("SDFSegment")).astype(int) for _, cells in results]
            areas = [vtk_to_numpy(cells.GetArray("Area")) for _, cells in results]
            row.append("%.2f / %.2f %%" % (table2(clusters), table2(segments)))
            if not shared:
                counts = sorted(set(large_labels(clusters, areas)))
        print("| %s | %s | %s | %s |" % (name, row[0], row[1], ", ".join(map(str, counts))))
    return 0


def main():
    global SETTINGS, OUTPUT
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("settings", help="JSON file {name: {Property: value}}")
    parser.add_argument("--psb", help="PSB-layout folder")
    parser.add_argument("--ids", help="PSB ids, e.g. 2-20,81 (default: all)")
    parser.add_argument("--poses", help="folder of one pose family")
    parser.add_argument("--output-dir", default=os.path.join("out", "sweep"))
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    arguments = parser.parse_args()
    with open(arguments.settings) as stream:
        SETTINGS = json.load(stream)
    if not isinstance(SETTINGS, dict) or not SETTINGS or not all(isinstance(p, dict) for p in SETTINGS.values()):
        raise SystemExit("%s: expected {name: {Property: value}, ...}" % arguments.settings)
    if not arguments.psb and not arguments.poses:
        raise SystemExit("nothing to measure: give --psb and/or --poses")
    for folder in (arguments.psb, arguments.poses):
        if folder and not os.path.isdir(folder):
            print("SKIP: %s does not exist" % folder)
            return 0
    OUTPUT = arguments.output_dir
    status = 0
    if arguments.psb:
        status |= sweep_psb(arguments)
    if arguments.poses:
        status |= sweep_poses(arguments)
    return status


if __name__ == "__main__":
    sys.exit(main())
