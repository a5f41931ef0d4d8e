# SPDX-License-Identifier: BSD-3-Clause
"""A bad piece on one rank: every rank reports every filter's error, and the run ends.

    python3 Testing/Python/mpi_one_rank_fails.py --mpiexec MPIEXEC --pvbatch PVBATCH
            --ranks N --bad-rank R [--spoil point|sdf] MESH.off

Runs `MPIEXEC -n N PVBATCH <this file> --worker R --log-dir DIR MESH.off`: the reader splits
MESH over the ranks; on every rank a programmable filter sends the rank's log (warnings and
errors) to DIR/rank<r>.log, and on rank R it replaces one point of its piece by NaN (bad input
that only that rank holds); then ShapeDiameter -> SDFBilateralSmooth -> SDFGMMPartition ->
SDFSkeleton. The Shape Diameter runs replicated (each rank its own rays), the smoothing with a
halo on every rank, the others on rank 0's gathered surface (Filters/DistributedSupport.h).
With --spoil sdf the point stays and one SDF value of rank R's piece becomes NaN instead (after
the Shape Diameter): the smoothing's halo run finds it before its first exchange and leaves the
filter to rank 0's run, which names the cell (an abort inside the halo run: mpi_abort.py).
Each rank's errors are read from its own
log file: in the ranks' combined output, a line of one rank can be cut by another's (seen: a
rank's error split in two around rank 0's). Checked:

- it ends within the timeout (a rank left waiting would hang it) with exit status 0;
- every rank reports the Shape Diameter's error about the non-finite point, and every rank
  reports an error of each of the three later filters (their input lacks the arrays; the
  later filters run on rank 0, which sends its error to the others); with --spoil sdf, no rank
  reports a Shape Diameter error, every rank reports an error of each later filter, and rank R
  names the non-finite value;
- the script on rank 0 reaches its end, with the skeleton empty (the documented output of a
  failed run) and the surface passed through.

Prints 'PASS ...' / 'FAIL ...' lines; exit status 1 on any failure.
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile

FILTERS = ("vtkShapeDiameterFilter", "vtkSDFBilateralSmooth", "vtkSDFGMMPartition", "vtkSDFSkeleton")


SPOIL_SDF = """
import math
from vtkmodules.vtkParallelCore import vtkMultiProcessController
controller = vtkMultiProcessController.GetGlobalController()
rank = controller.GetLocalProcessId() if controller is not None else 0
output = self.GetOutput()
output.DeepCopy(self.GetInput())
sdf = output.GetCellData().GetArray("SDF")
if rank == %d and sdf is not None and sdf.GetNumberOfTuples() > 0:
    sdf.SetTuple1(sdf.GetNumberOfTuples() // 2, math.nan)
"""


def worker(bad_rank, mesh, log_dir, spoil):
    """The pvbatch side: the chain with one rank's piece made bad, each rank logging to a file."""
    from paraview import simple

    simple.LoadPlugin(os.environ["SHAPEDIAMETER_PLUGIN"], remote=True, ns=vars(simple))
    reader = simple.SDFOFFReader(FileName=mesh)
    spoiled = simple.ProgrammableFilter(Input=reader)
    spoiled.Script = """
import math
import os
from vtkmodules.vtkCommonCore import vtkLogger
from vtkmodules.vtkParallelCore import vtkMultiProcessController
controller = vtkMultiProcessController.GetGlobalController()
rank = controller.GetLocalProcessId() if controller is not None else 0
vtkLogger.LogToFile(os.path.join(%r, "rank%%d.log" %% rank), vtkLogger.TRUNCATE, vtkLogger.VERBOSITY_WARNING)
output = self.GetOutput()
output.DeepCopy(self.GetInput())
if rank == %d and output.GetNumberOfPoints() > 0:
    output.GetPoints().SetPoint(0, math.nan, 0.0, 0.0)
""" % (log_dir, bad_rank if spoil == "point" else -1)
    sdf = simple.ShapeDiameter(Input=spoiled)
    if spoil == "sdf":
        sdf = simple.ProgrammableFilter(Input=sdf, Script=SPOIL_SDF % bad_rank)
    smooth = simple.SDFBilateralSmooth(Input=sdf, SDFArray=["CELLS", "SDF"])
    parts = simple.SDFGMMPartition(Input=smooth, NormalizedSDFArray=["CELLS", "SDFNormalized"])
    skeleton = simple.SDFSkeleton(Input=parts, SDFArray=["CELLS", "SDFSmoothed"])
    skeleton.UpdatePipeline()
    skeleton_cells = skeleton.GetDataInformation(0).GetNumberOfCells()
    surface_cells = skeleton.GetDataInformation(1).GetNumberOfCells()
    with open(os.path.join(log_dir, "end.txt"), "w") as end:
        end.write("skeleton cells %d, surface cells %d\n" % (skeleton_cells, surface_cells))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("mesh")
    parser.add_argument("--worker", type=int, default=None, help=argparse.SUPPRESS)
    parser.add_argument("--log-dir", help=argparse.SUPPRESS)
    parser.add_argument("--mpiexec")
    parser.add_argument("--pvbatch")
    parser.add_argument("--ranks", type=int, default=2)
    parser.add_argument("--bad-rank", type=int, default=1)
    parser.add_argument("--spoil", choices=("point", "sdf"), default="point",
                        help="what turns bad on that rank: one point (NaN), or one SDF value (NaN)")
    parser.add_argument("--timeout", type=float, default=240.0)
    args = parser.parse_args()
    if args.worker is not None:
        worker(args.worker, args.mesh, args.log_dir, args.spoil)
        return None

    log_dir = tempfile.mkdtemp(prefix="one_rank_fails_")
    command = [args.mpiexec] + (["--oversubscribe"] if args.ranks > 2 else []) + \
        ["-n", str(args.ranks), args.pvbatch, __file__, "--worker", str(args.bad_rank),
         "--log-dir", log_dir, "--spoil", args.spoil, args.mesh]
    failures = 0

    def check(ok, message):
        nonlocal failures
        failures += 0 if ok else 1
        print(("PASS " if ok else "FAIL ") + message, flush=True)

    try:
        run = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                             timeout=args.timeout)
    except subprocess.TimeoutExpired as expired:
        print((expired.stdout or b"")[-4000:] if isinstance(expired.stdout, str) else "")
        check(False, "the run ended within %g s (a rank was left waiting)" % args.timeout)
        return 1
    output = run.stdout
    check(run.returncode == 0, "exit status 0 (got %d)" % run.returncode)

    def read(name):
        path = os.path.join(log_dir, name)
        return open(path, errors="replace").read() if os.path.exists(path) else ""

    for rank in range(args.ranks):
        # vtkLogger's lines: "... ERR| vtkClass (0x...): text".
        errors = re.findall(r"ERR\|\s*(\w+) \(0x[0-9a-f]+\): ([^\n]*)", read("rank%d.log" % rank))
        reported = {name for name, _ in errors}
        if args.spoil == "point":
            for name in FILTERS:
                check(name in reported, "rank %d reports an error of %s" % (rank, name))
            nan = [text for name, text in errors
                   if name == "vtkShapeDiameterFilter" and "non-finite coordinate" in text]
            check(bool(nan), "rank %d names the non-finite point" % rank)
        else:
            check(FILTERS[0] not in reported, "rank %d reports no error of %s" % (rank, FILTERS[0]))
            for name in FILTERS[1:]:
                check(name in reported, "rank %d reports an error of %s" % (rank, name))
            if rank == args.bad_rank:
                nan = [text for name, text in errors if name == FILTERS[1] and "non-finite" in text]
                check(bool(nan), "rank %d names the non-finite SDF value" % rank)
    end = re.search(r"skeleton cells (\d+), surface cells (\d+)", read("end.txt"))
    check(end is not None, "the script reached its end")
    if end:
        check(int(end.group(1)) == 0, "the skeleton of a failed run is empty (%s cells)" % end.group(1))
        check(int(end.group(2)) > 0, "the surface is passed through (%s cells)" % end.group(2))
    if failures:
        print(output[-6000:])
    else:
        shutil.rmtree(log_dir, ignore_errors=True)
    print("%s" % ("FAILED" if failures else "all passed"))
    return 1 if failures else 0


if __name__ == "__main__":
    # pvbatch under mpiexec: sys.exit() skips ParaView's MPI finalisation (mpiexec then reports
    # an abnormal exit), so the worker ends the script instead.
    status = main()
    if status is not None:
        sys.exit(status)
