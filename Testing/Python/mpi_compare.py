# SPDX-License-Identifier: BSD-3-Clause
"""Distributed run == serial run, face by face (pvbatch under mpiexec).

    mpiexec -n N pvbatch Testing/Python/mpi_compare.py MESH.off [--min-processes N]
            [--split reader | --split redistribute [--boundary-mode 0|1]]
    pvpython Testing/Python/mpi_compare.py MESH.off --connect HOST:PORT   (a pvserver under mpiexec)

Rank 0 runs the script (pvbatch's default, not --symmetric); the other ranks are
ParaView's satellites. The chain OFFReader [-> RedistributeDataSet -> ExtractSurface] ->
ShapeDiameter -> SDFBilateralSmooth -> SDFGMMPartition -> SDFSkeleton runs through the
plugin's proxies on all ranks, with the surface split across them (checked: every rank
holds faces) by the reader itself (--split reader, the default: contiguous face ranges) or
by ParaView's RedistributeDataSet (--split redistribute: spatial regions, every face
on one rank or, with --boundary-mode 1, border faces on every rank they touch). The results are fetched to rank 0 and compared, keyed by the global cell id
(`GlobalCellIds`, from the OFF reader), with the same chain run serially in this process
through the wrapped classes (package shapediameter): SDF within 1e-6 relative (it is in
fact identical), SDFValidRays, SDFSmoothed, SDFNormalized, SDFCluster, SDFLevel*,
SDFSegment, SDFProbabilities, SkeletonNodeId, SkeletonBoneId and the polygon winding
identical, the fitted mixture identical, the skeleton (nodes, radii, polylines) and the
projected point cloud identical.

Prints one line per check and a closing line 'N passed, N failed'; exit status 1 on any failure.
Set SHAPEDIAMETER_DISTRIBUTED_TIMING=1 to get the per-filter gather/build/serial/scatter
times from the module on stderr.
"""
import argparse
import os
import sys
import time

from paraview import servermanager, simple
from vtkmodules.vtkCommonCore import vtkIdList
from vtkmodules.vtkParallelCore import vtkMultiProcessController

parser = argparse.ArgumentParser()
parser.add_argument("mesh")
parser.add_argument("--min-processes", type=int, default=2)
parser.add_argument("--split", choices=("reader", "redistribute"), default="reader",
                    help="who splits the surface over the ranks: the OFF reader (its pieces) or "
                         "ParaView's RedistributeDataSet")
parser.add_argument("--boundary-mode", type=int, default=0, choices=(0, 1),
                    help="RedistributeDataSet's BoundaryMode: 0 assign each face to one rank (ParaView's "
                         "default), 1 duplicate boundary faces on every rank they touch")
parser.add_argument("--connect", metavar="HOST:PORT",
                    help="run the distributed chain on this pvserver (started with mpiexec -n N pvserver "
                         "--server-port=PORT); the serial reference runs in this client")
args = parser.parse_args()

results = {"passed": 0, "failed": 0}


def check(ok, message):
    results["passed" if ok else "failed"] += 1
    print(("PASS " if ok else "FAIL ") + message, flush=True)
    return ok


if args.connect:
    host, port = args.connect.rsplit(":", 1)
    simple.Connect(host, int(port))
    processes = servermanager.ActiveConnection.GetNumberOfDataPartitions()
    simple.LoadPlugin(os.environ["SHAPEDIAMETER_PLUGIN"], remote=True, ns=vars(simple))
else:
    controller = vtkMultiProcessController.GetGlobalController()
    processes = controller.GetNumberOfProcesses() if controller else 1
if not check(processes >= args.min_processes, f"running on {processes} MPI processes (>= {args.min_processes})"):
    print(f"{results['passed']} passed, {results['failed']} failed")
    sys.exit(1)
if not args.connect:
    simple.LoadPlugin(os.environ["SHAPEDIAMETER_PLUGIN"], ns=vars(simple))
from shapediameter import (  # noqa: E402  (after the plugin: same library)
    vtkOFFReader, vtkSDFBilateralSmooth, vtkSDFGMMPartition, vtkSDFSkeleton, vtkShapeDiameterFilter)

# ---- The distributed chain (ParaView proxies, every rank).
start = time.perf_counter()
reader = simple.OFFReader(FileName=args.mesh)
if args.split == "redistribute":
    redistributed = simple.RedistributeDataSet(Input=reader)
    redistributed.BoundaryMode = ["Assign to one region", "Assign to all regions"][args.boundary_mode]
    surface = simple.ExtractSurface(Input=redistributed)
else:
    surface = reader
sdf = simple.ShapeDiameter(Input=surface)
smooth = simple.SDFBilateralSmooth(Input=sdf)
partition = simple.SDFGMMPartition(Input=smooth)
skeleton = simple.SDFSkeleton(Input=partition)
stage_times = {}
for name, proxy in (("split", surface), ("sdf", sdf), ("smooth", smooth), ("partition", partition),
                    ("skeleton", skeleton)):
    t = time.perf_counter()
    proxy.UpdatePipeline()
    stage_times[name] = time.perf_counter() - t
distributed_seconds = time.perf_counter() - start

# The surface really is split: faces on every rank.
ids_proxy = simple.ProcessIds(Input=surface) if hasattr(simple, "ProcessIds") else simple.ProcessIdScalars(Input=surface)
owners = servermanager.Fetch(ids_proxy)
owner_array = owners.GetCellData().GetArray("ProcessId") or owners.GetPointData().GetArray("ProcessId")
if owners.GetCellData().GetArray("ProcessId"):
    per_rank = [0] * processes
    for c in range(owners.GetNumberOfCells()):
        per_rank[int(owner_array.GetTuple1(c))] += 1
else:  # point ids only: count the points instead
    per_rank = [0] * processes
    for p in range(owners.GetNumberOfPoints()):
        per_rank[int(owner_array.GetTuple1(p))] += 1
if args.split == "redistribute" and not all(n > 0 for n in per_rank):
    # ParaView's own RedistributeDataSet moved nothing: a precondition of this test, not
    # something of this project. Seen on Debian 12 with libexpat1 2.5.0-1+deb12u5 (a 2025
    # security update), whose stricter parser rejects the raw appended data of the XML
    # streams VTK 9.2's DIY exchange uses ("not well-formed (invalid token)" on the
    # receiving rank). ctest reports the test as skipped (SKIP_REGULAR_EXPRESSION).
    print(f"SKIP: RedistributeDataSet did not spread the surface over the ranks {per_rank}; "
          "ParaView's own data exchange does not work in this installation", flush=True)
    sys.exit(0)
check(all(n > 0 for n in per_rank), f"the surface is split across the ranks: {per_rank}")

fetched_surface = servermanager.Fetch(partition)
fetched_linked = servermanager.Fetch(skeleton, None, None, 1)
fetched_skeleton = servermanager.Fetch(skeleton, None, None, 0)
fetched_cloud = servermanager.Fetch(skeleton, None, None, 2)

# ---- The serial reference (wrapped classes, this process only: one piece, no MPI path).
start = time.perf_counter()
serial_reader = vtkOFFReader()
serial_reader.SetFileName(args.mesh)
serial_sdf = vtkShapeDiameterFilter()
serial_sdf.SetInputConnection(serial_reader.GetOutputPort())
serial_smooth = vtkSDFBilateralSmooth()
serial_smooth.SetInputConnection(serial_sdf.GetOutputPort())
serial_partition = vtkSDFGMMPartition()
serial_partition.SetInputConnection(serial_smooth.GetOutputPort())
serial_skeleton = vtkSDFSkeleton()
serial_skeleton.SetInputConnection(serial_partition.GetOutputPort())
serial_skeleton.Update()
serial_seconds = time.perf_counter() - start
reference = serial_partition.GetOutput()
reference_linked = serial_skeleton.GetOutput(1)
reference_skeleton = serial_skeleton.GetOutput(0)
reference_cloud = serial_skeleton.GetOutput(2)
face_count = reference.GetNumberOfCells()
check(reference.GetCellData().GetArray("GlobalCellIds") is None,
      "serial runs carry no global id arrays")


def by_global_id(data, label):
    """Row of each global cell id in `data`: every id present, each once apart from the copies
    of boundary faces (BoundaryMode 1), which must carry the same values as the first copy."""
    ids = data.GetCellData().GetArray("GlobalCellIds")
    if not check(ids is not None, f"{label}: GlobalCellIds present"):
        return None
    rows = [-1] * face_count
    copies = []
    for row in range(data.GetNumberOfCells()):
        g = int(ids.GetValue(row))
        if 0 <= g < face_count and rows[g] < 0:
            rows[g] = row
        else:
            copies.append(row)
    if not check(all(r >= 0 for r in rows) and (args.boundary_mode == 1 or not copies),
                 f"{label}: every global cell id of the {face_count} serial faces present "
                 f"({data.GetNumberOfCells()} faces, {len(copies)} copies of boundary faces)"):
        return None
    cd = data.GetCellData()
    disagreeing = 0
    for row in copies:
        g = int(ids.GetValue(row))
        disagreeing += any(cd.GetArray(i).GetTuple(row) != cd.GetArray(i).GetTuple(rows[g])
                           for i in range(cd.GetNumberOfArrays())
                           if cd.GetArrayName(i) not in ("vtkGhostType", "vtkOriginalCellIds"))
    check(disagreeing == 0, f"{label}: {disagreeing} copies of boundary faces differ from the first copy")
    return rows


def compare_cell_array(data, rows, name, tolerance=0.0):
    mine = data.GetCellData().GetArray(name)
    theirs = reference_cell_arrays.GetArray(name)
    if not check(mine is not None and theirs is not None and
                 mine.GetNumberOfComponents() == theirs.GetNumberOfComponents(),
                 f"cell array {name} present in both"):
        return
    worst, differing = 0.0, 0
    for g in range(face_count):
        for k in range(theirs.GetNumberOfComponents()):
            a = mine.GetComponent(rows[g], k)
            b = theirs.GetComponent(g, k)
            if a != b:
                relative = abs(a - b) / max(abs(b), 1e-300)
                worst = max(worst, relative)
                if relative > tolerance:
                    differing += 1
    check(differing == 0, f"{name}: {differing} of {face_count} faces differ "
          f"(max relative difference {worst:.3g}, allowed {tolerance:g})")


def compare_field(data, name):
    mine = data.GetFieldData().GetArray(name)
    theirs = reference.GetFieldData().GetArray(name)
    same = (mine is not None and theirs is not None and mine.GetNumberOfTuples() == theirs.GetNumberOfTuples() and
            all(mine.GetTuple1(i) == theirs.GetTuple1(i) for i in range(theirs.GetNumberOfTuples())))
    check(same, f"field array {name} identical")


rows = by_global_id(fetched_surface, "distributed partition output")
if rows:
    reference_cell_arrays = reference.GetCellData()
    compare_cell_array(fetched_surface, rows, "SDF", 1e-6)
    for name in ["SDFValidRays", "SDFSmoothed", "SDFNormalized", "SDFProbabilities", "SDFCluster", "SDFSegment"] + [
            reference_cell_arrays.GetArrayName(i) for i in range(reference_cell_arrays.GetNumberOfArrays())
            if reference_cell_arrays.GetArrayName(i).startswith("SDFLevel")]:
        compare_cell_array(fetched_surface, rows, name)
    for name in ("SDFGMMMeans", "SDFGMMSigmas", "SDFGMMWeights", "SDFClusterCount", "SDFEnergy"):
        compare_field(fetched_surface, name)
    # Winding and geometry of every face (AutoOrient may rewind polygons).
    mismatched = 0
    mine_ids, theirs_ids = vtkIdList(), vtkIdList()
    for g in range(face_count):
        fetched_surface.GetCellPoints(rows[g], mine_ids)
        reference.GetCellPoints(g, theirs_ids)
        if mine_ids.GetNumberOfIds() != theirs_ids.GetNumberOfIds() or any(
                fetched_surface.GetPoint(mine_ids.GetId(k)) != reference.GetPoint(theirs_ids.GetId(k))
                for k in range(theirs_ids.GetNumberOfIds())):
            mismatched += 1
    check(mismatched == 0, f"polygon corners and winding: {mismatched} of {face_count} faces differ")

linked_rows = by_global_id(fetched_linked, "distributed skeleton surface output")
if linked_rows:
    reference_cell_arrays = reference_linked.GetCellData()
    for name in ("SkeletonNodeId", "SkeletonBoneId"):
        compare_cell_array(fetched_linked, linked_rows, name)


def same_points(a, b, label, arrays):
    same = a.GetNumberOfPoints() == b.GetNumberOfPoints() and all(
        a.GetPoint(p) == b.GetPoint(p) for p in range(b.GetNumberOfPoints()))
    for name in arrays:
        x, y = a.GetPointData().GetArray(name), b.GetPointData().GetArray(name)
        same = same and x is not None and y is not None and x.GetNumberOfTuples() == y.GetNumberOfTuples() and all(
            x.GetTuple(i) == y.GetTuple(i) for i in range(y.GetNumberOfTuples()))
    check(same and b.GetNumberOfPoints() > 0,
          f"{label}: {a.GetNumberOfPoints()} points (serial {b.GetNumberOfPoints()}), positions and {arrays} identical")


same_points(fetched_skeleton, reference_skeleton, "skeleton nodes", ["Radius", "Confidence"])
lines_same = fetched_skeleton.GetNumberOfCells() == reference_skeleton.GetNumberOfCells()
a_ids, b_ids = vtkIdList(), vtkIdList()
for c in range(reference_skeleton.GetNumberOfCells() if lines_same else 0):
    fetched_skeleton.GetCellPoints(c, a_ids)
    reference_skeleton.GetCellPoints(c, b_ids)
    lines_same = lines_same and [a_ids.GetId(k) for k in range(a_ids.GetNumberOfIds())] == [
        b_ids.GetId(k) for k in range(b_ids.GetNumberOfIds())]
check(lines_same, f"skeleton polylines: {fetched_skeleton.GetNumberOfCells()} (serial "
      f"{reference_skeleton.GetNumberOfCells()}), identical")
same_points(fetched_cloud, reference_cloud, "projected points", ["SourceFaceId", "Radius"])

print(f"timings: {processes} processes, {face_count} faces: distributed chain {distributed_seconds:.2f} s "
      f"({', '.join(f'{k} {v:.2f}' for k, v in stage_times.items())}), serial chain in-process {serial_seconds:.2f} s")
print(f"{results['passed']} passed, {results['failed']} failed")
# pvbatch under mpiexec: sys.exit() skips ParaView's MPI finalisation (mpiexec then reports
# an abnormal exit, status 1), so it is only called on failure; success ends the script.
if results["failed"]:
    sys.exit(1)
