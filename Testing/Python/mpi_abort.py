# SPDX-License-Identifier: BSD-3-Clause
"""An abort on one rank in the smoothing's halo run (and, when it is rank 0, in the partition's
cut and in the skeleton): every rank stops, and the run ends.

    mpiexec -n N pvbatch --symmetric Testing/Python/mpi_abort.py MESH.off --abort-rank R

Every rank runs this script (--symmetric) with the wrapped classes: SDF OFF Reader -> Shape
Diameter -> SDF Bilateral Smooth, each rank updating its own piece of N (the module then runs
distributed: the smoothing on each rank's own faces plus a halo, Filters/DistributedSupport.h).
First the chain runs through: every rank's piece gets SDFSmoothed. Then the smoothing runs
again with an observer on rank R that sets AbortExecute at the first progress event: rank R's
core stops, the ranks agree on the abort in their next collective, and every rank ends with its
input passed through (no SDFSmoothed), none waiting for another. The filters' own header says
an abort gives the pass-through (vtkSDFSurfaceAlgorithm.h).
With --abort-rank 0 the partition then runs through once and again with an abort on rank 0,
which runs its cut (Filters/Core/Partition/DistributedPartition.h): every rank ends with its
input passed through (no SDFCluster); and so does the skeleton, built on rank 0 from every rank's
triangles (Filters/Core/Skeleton/DistributedSkeleton.h): no SkeletonBoneId.

Each rank prints 'PASS ...' / 'FAIL ...' lines prefixed by its rank; ctest fails on 'FAIL '.
"""
import argparse
import os
import sys

from paraview import simple
from vtkmodules.vtkParallelCore import vtkMultiProcessController

parser = argparse.ArgumentParser()
parser.add_argument("mesh")
parser.add_argument("--abort-rank", type=int, default=1)
args = parser.parse_args()

simple.LoadPlugin(os.environ["SHAPEDIAMETER_PLUGIN"], ns=vars(simple))
from shapediameter import (vtkSDFOFFReader, vtkSDFBilateralSmooth, vtkSDFGMMPartition,  # noqa: E402
                           vtkSDFSkeleton, vtkShapeDiameterFilter)

controller = vtkMultiProcessController.GetGlobalController()
rank = controller.GetLocalProcessId()
processes = controller.GetNumberOfProcesses()


def check(ok, message):
    print(("PASS " if ok else "FAIL ") + "rank %d: %s" % (rank, message), flush=True)


check(processes >= 2, "running on %d processes (>= 2)" % processes)
reader = vtkSDFOFFReader()
reader.SetFileName(args.mesh)
sdf = vtkShapeDiameterFilter()
sdf.SetInputConnection(reader.GetOutputPort())
aborted = []


def abort_here(caller, event):
    if not aborted:
        aborted.append(True)
        caller.SetAbortExecute(1)


def run_then_abort(stage, array, abort_rank, change, surface=lambda stage: stage.GetOutput()):
    """Runs `stage` through (its `surface` output has `array`), then again, after `change`, with an
    abort at its first progress event on `abort_rank`: every rank's surface output is its input
    passed through."""
    stage.UpdatePiece(rank, processes, 0)
    piece = surface(stage)
    name = stage.GetClassName()
    check(piece.GetNumberOfCells() > 0 and piece.GetCellData().GetArray(array) is not None,
          "%s's first run gives this rank's %d faces %s" % (name, piece.GetNumberOfCells(), array))
    aborted.clear()
    if rank == abort_rank:
        stage.AddObserver("ProgressEvent", abort_here)
    change()  # so that it runs again
    stage.UpdatePiece(rank, processes, 0)
    piece = surface(stage)
    if rank == abort_rank:
        check(bool(aborted), "this rank asked %s to abort" % name)
    check(piece.GetNumberOfCells() > 0 and piece.GetCellData().GetArray(array) is None,
          "the aborted %s passes this rank's %d faces through, without %s" % (name, piece.GetNumberOfCells(), array))
    stage.RemoveAllObservers()
    stage.SetAbortExecute(0)  # VTK 9.2 keeps the flag: the next run would stop at once


smooth = vtkSDFBilateralSmooth()
smooth.SetInputConnection(sdf.GetOutputPort())
run_then_abort(smooth, "SDFSmoothed", args.abort_rank,
               lambda: smooth.SetRangeThreshold(smooth.GetRangeThreshold() * 0.5))
if args.abort_rank == 0:
    smooth.Modified()  # runs again, through: the aborted run left no SDFNormalized
    partition = vtkSDFGMMPartition()
    partition.SetInputConnection(smooth.GetOutputPort())
    run_then_abort(partition, "SDFCluster", 0, lambda: partition.SetLambda(partition.GetLambda() * 0.5))
    partition.Modified()  # runs again, through: the aborted run left no SDFSegment
    skeleton = vtkSDFSkeleton()
    skeleton.SetInputConnection(partition.GetOutputPort())
    run_then_abort(skeleton, "SkeletonBoneId", 0, lambda: skeleton.SetSeed(skeleton.GetSeed() + 1),
                   lambda stage: stage.GetSurface())
controller.Barrier()
check(True, "reached the end")
