# SPDX-License-Identifier: BSD-3-Clause
"""Wall time of the chain per stage under MPI (pvbatch), for docs/distributed.md.

    mpiexec --bind-to none -n N pvbatch Testing/Benchmarks/mpi_chain.py MESH.off [--threads 1] [--repeats 3]

The chain SDF OFF Reader -> Shape Diameter -> SDF Bilateral Smooth -> SDF GMM Partition ->
SDF Skeleton runs through the plugin's proxies on all ranks (the reader's spatial pieces), every
filter with NumberOfThreads = --threads. Each repeat builds the chain anew and updates one stage
after the other; printed on rank 0: one line per repeat with the seconds of each stage, then the
fastest of the repeats per stage ("min"), as a Python dict on a line starting with 'RESULT '.
Testing/Benchmarks/run-mpi-benchmarks runs it on 1 and 2 ranks and prints the ratios.
Needs SHAPEDIAMETER_PLUGIN (the plugin's .so) in the environment.
"""
import argparse
import os
import time

from paraview import simple
from vtkmodules.vtkParallelCore import vtkMultiProcessController

parser = argparse.ArgumentParser()
parser.add_argument("mesh")
parser.add_argument("--threads", type=int, default=1)
parser.add_argument("--repeats", type=int, default=3)
args = parser.parse_args()

controller = vtkMultiProcessController.GetGlobalController()
processes = controller.GetNumberOfProcesses() if controller else 1
simple.LoadPlugin(os.environ["SHAPEDIAMETER_PLUGIN"], ns=vars(simple))

stages = ("read", "sdf", "smooth", "partition", "skeleton")
fastest = {}
for repeat in range(args.repeats):
    reader = simple.SDFOFFReader(FileName=args.mesh)
    sdf = simple.ShapeDiameter(Input=reader, NumberOfThreads=args.threads)
    smooth = simple.SDFBilateralSmooth(Input=sdf, NumberOfThreads=args.threads)
    partition = simple.SDFGMMPartition(Input=smooth, NumberOfThreads=args.threads)
    skeleton = simple.SDFSkeleton(Input=partition, NumberOfThreads=args.threads)
    seconds = {}
    for name, proxy in zip(stages, (reader, sdf, smooth, partition, skeleton)):
        start = time.perf_counter()
        proxy.UpdatePipeline()
        seconds[name] = time.perf_counter() - start
    seconds["chain"] = sum(seconds[name] for name in stages)
    print("ranks %d, threads %d, repeat %d: %s" % (processes, args.threads, repeat,
          ", ".join("%s %.3f s" % item for item in seconds.items())), flush=True)
    for name, value in seconds.items():
        fastest[name] = min(fastest.get(name, value), value)
    for proxy in (skeleton, partition, smooth, sdf, reader):
        simple.Delete(proxy)
print("RESULT %r" % {"ranks": processes, "threads": args.threads, **fastest}, flush=True)
