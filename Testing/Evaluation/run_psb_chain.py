# SPDX-License-Identifier: BSD-3-Clause
"""Runs the chain on every mesh of a PSB-layout folder and writes one SDFSegment .seg per mesh.

    pvpython Testing/Evaluation/run_psb_chain.py PSB_DIR OUT_DIR [--ids LIST] [--jobs N]
             [--hit-rule 0|1] [--cluster-model 0|1] [--clusters K] [--lambda L]
             [--set Class.Property=value ...]

PSB_DIR holds <id>.off.gz (or <id>.off) meshes, as ../shared/data/psb does. Each mesh goes
through vtkSDFOFFReader -> vtkShapeDiameterFilter -> vtkSDFBilateralSmooth ->
vtkSDFGMMPartition (the wrapped classes of package shapediameter, no rendering, no skeleton)
and OUT_DIR/<id>.seg gets its SDFSegment, one label per face and line, for sdf-psb-benchmark.

--ids: e.g. 2-20,81,385 (default: every mesh; ranges skip absent ids, single ids must exist).
--jobs N: meshes processed at once, in N worker processes, each filter with NumberOfThreads
max(1, cores / N) (default: the number of cores, one thread per mesh: on 2 cores, 90 PSB
meshes took 37 s with 2 jobs against 43 s with 1 job of 2 threads, as much of the chain is
serial). The options of chain_settings set the filters;
--set Class.Property=value calls Set<Property> on every filter of that class after them, e.g.
--set vtkSDFGMMPartition.ModeProminence=0.05 (int, float or text; 'a,b' passes two values).

A mesh that fails (unreadable, a filter error, no SDFSegment) is skipped and listed at the
end, with exit status 1. OUT_DIR/timings.json: the settings, the wall time, and per mesh its
faces and seconds per stage (read, sdf, smooth, partition, write). Progress: one line per mesh.

Needs PYTHONPATH to contain build/lib/python3.11/site-packages (the README's pvpython setup).
"""
import argparse
import json
import multiprocessing
import os
import re
import sys
import tempfile
import time

import numpy as np

import shapediameter
from vtkmodules.util.misc import calldata_type
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.util.vtkConstants import VTK_STRING

import chain_settings

DEFAULT_JOBS = os.cpu_count() or 1


def mesh_files(folder):
    """{id: path} of the <id>.off / <id>.off.gz files in folder (the .off when both exist)."""
    found = {}
    for name in os.listdir(folder):
        match = re.fullmatch(r"(\d{1,6})\.off(\.gz)?", name)
        if match and (int(match.group(1)) not in found or not match.group(2)):
            found[int(match.group(1))] = os.path.join(folder, name)
    return found


def select_ids(text, present, folder):
    """The ids of an --ids list ('2-20,81'); ranges keep the present ids, single ids must exist."""
    if text is None:
        return sorted(present)
    selected = set()
    for item in text.split(","):
        match = re.fullmatch(r"\s*(\d+)\s*(?:-\s*(\d+)\s*)?", item)
        if not match:
            raise SystemExit("--ids: %r is not an id or a range a-b" % item)
        if match.group(2) is None:
            if int(match.group(1)) not in present:
                raise SystemExit("mesh %s is not in %s" % (match.group(1), folder))
            selected.add(int(match.group(1)))
        else:
            selected.update(i for i in present if int(match.group(1)) <= i <= int(match.group(2)))
    if not selected:
        raise SystemExit("--ids %s selects no mesh of %s" % (text, folder))
    return sorted(selected)


class ErrorLog:
    """Collects the vtkErrorMacro messages of the filters it observes."""

    def __init__(self):
        self.messages = []

    def watch(self, algorithm):
        algorithm.AddObserver("ErrorEvent", self.record)
        return algorithm

    @calldata_type(VTK_STRING)
    def record(self, caller, event, message):
        text = str(message).strip().splitlines()
        self.messages.append("%s: %s" % (caller.GetClassName(), text[-1] if text else "error"))


def run_mesh(task):
    """(id, timings or None, error or None): the chain on one mesh, its .seg written."""
    mesh_id, path, out_dir, arguments, threads = task
    timings = {}
    errors = ErrorLog()
    target = os.path.join(out_dir, "%d.seg" % mesh_id)
    try:
        if os.path.exists(target):  # a failure must not leave an earlier run's labels behind
            os.remove(target)
        start = time.perf_counter()
        with tempfile.TemporaryDirectory() as scratch:
            surface = chain_settings.read_mesh(path, scratch)
        faces = surface.GetNumberOfCells()
        if surface.GetNumberOfPolys() == 0:
            return mesh_id, None, "no polygons read from %s" % path
        timings["faces"] = faces
        timings["read"] = time.perf_counter() - start
        stages = [("sdf", chain_settings.shape_diameter(arguments)),
                  ("smooth", chain_settings.smoothing(arguments)),
                  ("partition", chain_settings.partition(arguments))]
        data = surface
        for name, algorithm in stages:
            errors.watch(algorithm)
            algorithm.SetNumberOfThreads(threads)
            algorithm.SetInputData(data)
            start = time.perf_counter()
            algorithm.Update()
            timings[name] = time.perf_counter() - start
            if errors.messages:
                return mesh_id, None, "; ".join(errors.messages)
            data = algorithm.GetOutput()
        segments = data.GetCellData().GetArray("SDFSegment")
        if segments is None or segments.GetNumberOfTuples() != faces:
            return mesh_id, None, "the partition wrote no SDFSegment"
        start = time.perf_counter()
        partial = target + ".partial"
        np.savetxt(partial, vtk_to_numpy(segments).astype(np.int64), fmt="%d")
        os.replace(partial, target)
        timings["write"] = time.perf_counter() - start
        timings["total"] = sum(timings[k] for k in ("read", "sdf", "smooth", "partition", "write"))
        return mesh_id, timings, None
    except Exception as error:  # one mesh's failure must not end the run
        return mesh_id, None, "%s: %s" % (type(error).__name__, error)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("psb_dir")
    parser.add_argument("out_dir")
    parser.add_argument("--ids", default=None, metavar="LIST", help="e.g. 2-20,81 (default: every mesh)")
    parser.add_argument("--jobs", type=int, default=DEFAULT_JOBS, metavar="N",
                        help="meshes at once, in worker processes (default %d)" % DEFAULT_JOBS)
    parser.add_argument("--quiet", action="store_true", help="no line per mesh")
    chain_settings.add_arguments(parser)
    arguments = parser.parse_args()
    if not os.path.isdir(arguments.psb_dir):
        sys.exit("%s: not a folder" % arguments.psb_dir)
    if arguments.jobs < 1:
        sys.exit("--jobs must be at least 1")
    # Settings a filter rejects end the run here, not in every worker.
    for make in (chain_settings.shape_diameter, chain_settings.smoothing, chain_settings.partition):
        make(arguments)
    files = mesh_files(arguments.psb_dir)
    ids = select_ids(arguments.ids, files, arguments.psb_dir)
    os.makedirs(arguments.out_dir, exist_ok=True)
    cores = os.cpu_count() or 1
    jobs = min(arguments.jobs, len(ids))
    threads = max(1, cores // jobs)
    # The largest meshes first, so that no long one is left alone at the end; output order
    # does not matter (one file per mesh).
    order = sorted(ids, key=lambda i: -os.path.getsize(files[i]))
    tasks = [(i, files[i], arguments.out_dir, arguments, threads) for i in order]

    start = time.perf_counter()
    results = {}
    failed = {}

    def report(result):
        mesh_id, timings, error = result
        if error is None:
            results[mesh_id] = timings
            if not arguments.quiet:
                print("%d: %d faces, %.2f s (sdf %.2f, smooth %.2f, partition %.2f)" % (
                    mesh_id, timings["faces"], timings["total"], timings["sdf"], timings["smooth"],
                    timings["partition"]), flush=True)
        else:
            failed[mesh_id] = error
            print("%d: FAILED: %s" % (mesh_id, error), flush=True)

    if jobs == 1:
        for task in tasks:
            report(run_mesh(task))
    else:
        # fork: the workers inherit the loaded modules (the parent has run no filter, so no
        # thread pool is copied half-way). close + join, not the context manager's terminate:
        # pvpython prints a stack trace for every worker killed by SIGTERM.
        pool = multiprocessing.get_context("fork").Pool(jobs, maxtasksperchild=50)
        try:
            for result in pool.imap_unordered(run_mesh, tasks):
                report(result)
        except BaseException:
            pool.terminate()
            raise
        pool.close()
        pool.join()
    wall = time.perf_counter() - start

    settings = {"hit_rule": arguments.hit_rule, "cluster_model": arguments.cluster_model,
                "clusters": arguments.clusters, "lambda": arguments.smoothness,
                "set": ["%s.%s=%s" % (c, p, ",".join(str(v) for v in values)) for c, p, values in arguments.settings]}
    with open(os.path.join(arguments.out_dir, "timings.json"), "w") as out:
        json.dump({"psb_dir": arguments.psb_dir, "settings": settings, "jobs": jobs, "threads_per_job": threads,
                   "wall": wall, "meshes": {str(i): results[i] for i in sorted(results)},
                   "failed": {str(i): failed[i] for i in sorted(failed)}}, out, indent=1)
    stage_sums = {k: sum(t[k] for t in results.values()) for k in ("read", "sdf", "smooth", "partition", "write")}
    print("%d meshes in %.1f s (%d jobs x %d threads); summed per stage: %s" % (
        len(results), wall, jobs, threads, ", ".join("%s %.1f s" % kv for kv in stage_sums.items())), flush=True)
    if failed:
        sys.exit("%d of %d meshes failed: %s" % (len(failed), len(ids), ", ".join(str(i) for i in sorted(failed))))


if __name__ == "__main__":
    main()
