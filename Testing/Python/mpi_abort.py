# SPDX-License-Identifier: BSD-3-Clause
"""An abort on one rank in the smoothing's halo run (and, when it is rank 0, in the partition's
cut): every rank stops, and the run ends.

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
input passed through (no SDFCluster).

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
                           vtkShapeDiameterFilter)

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
smooth = vtkSDFBilateralSmooth()
smooth.SetInputConnection(sdf.GetOutputPort())
smooth.UpdatePiece(rank, processes, 0)
piece = smooth.GetOutput()
check(piece.GetNumberOfCells() > 0 and piece.GetCellData().GetArray("SDFSmoothed") is not None,
      "the first run smooths this rank's %d faces" % piece.GetNumberOfCells())

aborted = []


def abort_here(caller, event):
    if not aborted:
        aborted.append(True)
        caller.SetAbortExecute(1)


if rank == args.abort_rank:
    smooth.AddObserver("ProgressEvent", abort_here)
smooth.SetRangeThreshold(smooth.GetRangeThreshold() * 0.5)  # a change, so that it runs again
smooth.UpdatePiece(rank, processes, 0)
piece = smooth.GetOutput()
if rank == args.abort_rank:
    check(bool(aborted), "this rank asked to abort")
check(piece.GetNumberOfCells() > 0 and piece.GetCellData().GetArray("SDFSmoothed") is None,
      "the aborted run passes this rank's %d faces through, without SDFSmoothed" % piece.GetNumberOfCells())

if args.abort_rank == 0:
    smooth.RemoveAllObservers()
    smooth.SetAbortExecute(0)  # VTK 9.2 keeps the flag: the next run would stop at once
    smooth.Modified()  # runs again, through: the aborted run left no SDFNormalized
    partition = vtkSDFGMMPartition()
    partition.SetInputConnection(smooth.GetOutputPort())
    partition.UpdatePiece(rank, processes, 0)
    piece = partition.GetOutput()
    check(piece.GetNumberOfCells() > 0 and piece.GetCellData().GetArray("SDFCluster") is not None,
          "the partition's first run labels this rank's %d faces" % piece.GetNumberOfCells())
    aborted.clear()
    if rank == 0:
        partition.AddObserver("ProgressEvent", abort_here)
    partition.SetLambda(partition.GetLambda() * 0.5)
    partition.UpdatePiece(rank, processes, 0)
    piece = partition.GetOutput()
    if rank == 0:
        check(bool(aborted), "rank 0 asked the partition to abort")
    check(piece.GetNumberOfCells() > 0 and piece.GetCellData().GetArray("SDFCluster") is None
          and piece.GetCellData().GetArray("SDFSmoothed") is not None,
          "the aborted partition passes this rank's %d faces through, without SDFCluster" % piece.GetNumberOfCells())
controller.Barrier()
check(True, "reached the end")
