# SPDX-License-Identifier: BSD-3-Clause
"""Wall time and memory of the chain per stage under MPI (pvbatch), for docs/distributed.md.

    mpiexec --bind-to none -n N pvbatch Testing/Benchmarks/mpi_chain.py MESH.off [--threads 1] [--repeats 3]
            [--memory] [--cpu]

The chain SDF OFF Reader -> Shape Diameter -> SDF Bilateral Smooth -> SDF GMM Partition ->
SDF Skeleton runs through the plugin's proxies on all ranks (the reader's spatial pieces), every
filter with NumberOfThreads = --threads. Each repeat builds the chain anew and updates one stage
after the other; printed on rank 0: one line per repeat with the seconds of each stage, then the
fastest of the repeats per stage ("min"), as a Python dict on a line starting with 'RESULT '.
Testing/Benchmarks/run-mpi-benchmarks runs it on 1 and 2 ranks and prints the ratios.
Needs SHAPEDIAMETER_PLUGIN (the plugin's .so) in the environment.

--memory (one repeat): every rank reads its VmRSS from /proc/self/status just before the reader
runs (plugin loaded, the chain's proxies created: the "baseline") and its VmHWM after each stage.
A ProgrammableSource run on every rank takes each reading (pvbatch runs this script on rank 0
only) and appends it to a file per rank in a temporary directory; rank 0 prints one line per
rank (MB: baseline, VmHWM after each stage, VmHWM - baseline after the reader and after the
chain) and the same as a list of dicts on a line starting with 'MEMORY '. VmHWM is the process's
high-water mark, so the figure after a stage is the peak of everything up to that stage.

--cpu (one repeat): the same probes also read every rank's CPU time (user + system, all its
threads); rank 0 prints each rank's CPU seconds in each stage beside the stage's wall time, and
for the ranks other than 0 the CPU they used while the partition and the skeleton ran on rank 0
(waiting, sending their piece and receiving their results) as a share of the chain's wall time
(issue 41's waiting bar: <= 10 %), on a line starting with 'CPU '.
"""
import argparse
import os
import shutil
import tempfile
import time

from paraview import simple
from vtkmodules.vtkParallelCore import vtkMultiProcessController

parser = argparse.ArgumentParser()
parser.add_argument("mesh")
parser.add_argument("--threads", type=int, default=1)
parser.add_argument("--repeats", type=int, default=3)
parser.add_argument("--memory", action="store_true",
                    help="one repeat; per-rank VmRSS before the reader and VmHWM after each stage")
parser.add_argument("--cpu", action="store_true",
                    help="one repeat; per-rank CPU time in each stage, and the waiting ranks' share")
args = parser.parse_args()

controller = vtkMultiProcessController.GetGlobalController()
processes = controller.GetNumberOfProcesses() if controller else 1
simple.LoadPlugin(os.environ["SHAPEDIAMETER_PLUGIN"], ns=vars(simple))

stages = ("read", "sdf", "smooth", "partition", "skeleton")

# Runs on every rank (the source is updated on all of them); appends "label rss hwm cpu" (kB,
# kB, seconds of CPU of the whole process).
PROBE_SCRIPT = """
import os
from vtkmodules.vtkParallelCore import vtkMultiProcessController
controller = vtkMultiProcessController.GetGlobalController()
rank = controller.GetLocalProcessId() if controller is not None else 0
status = dict(line.split(":", 1) for line in open("/proc/self/status") if ":" in line)
kilobytes = lambda key: int(status[key].split()[0])
# Not sum(): the programmable source's namespace has VTK's MPI-aware numpy_interface sum,
# which adds the value over all ranks.
cpu = os.times()
with open(os.path.join(%r, "rank%%d.txt" %% rank), "a") as readings:
    readings.write("%%s %%d %%d %%.3f\\n" %% (%r, kilobytes("VmRSS"), kilobytes("VmHWM"), cpu.user + cpu.system))
"""


def probe(directory, label):
    # On rank 0 the source's script runs in this module's namespace, after `from numpy import *`
    # (which shadows min, sum, all, ...): the namespace is put back as it was afterwards.
    saved = dict(globals())
    source = simple.ProgrammableSource(Script=PROBE_SCRIPT % (directory, label))
    source.UpdatePipeline()
    simple.Delete(source)
    for name in set(globals()) - set(saved):
        del globals()[name]
    globals().update(saved)


def read_probes(directory, timeout=60.0):
    """{rank: {label: (rss_kB, hwm_kB, cpu_s)}} once every rank has written its last reading."""
    deadline = time.time() + timeout
    while True:
        ranks = {}
        for rank in range(processes):
            path = os.path.join(directory, "rank%d.txt" % rank)
            lines = open(path).read().splitlines() if os.path.exists(path) else []
            ranks[rank] = {label: (int(rss), int(hwm), float(cpu)) for label, rss, hwm, cpu in
                           (line.split() for line in lines)}
        if all(stages[-1] in readings for readings in ranks.values()) or time.time() > deadline:
            return ranks
        time.sleep(0.2)


def report_memory(ranks):
    megabytes = lambda kilobytes: kilobytes / 1024.0
    rows = []
    for rank, readings in sorted(ranks.items()):
        if "baseline" not in readings or stages[-1] not in readings:
            print("rank %d: readings missing (%s)" % (rank, ", ".join(readings)), flush=True)
            continue
        baseline = megabytes(readings["baseline"][0])
        row = {"rank": rank, "baseline": baseline}
        row.update({stage: megabytes(readings[stage][1]) for stage in stages})
        row["reader_peak"] = row["read"] - baseline
        row["chain_peak"] = row[stages[-1]] - baseline
        rows.append(row)
    print("| rank | baseline RSS | " + " | ".join("VmHWM after %s" % s for s in stages) +
          " | reader: VmHWM - baseline | chain: VmHWM - baseline |", flush=True)
    print("|---:|" + "---:|" * (len(stages) + 3))
    for row in rows:
        print("| %d | " % row["rank"] + " | ".join("%.0f MB" % row[key] for key in
              ("baseline",) + stages + ("reader_peak", "chain_peak")) + " |", flush=True)
    print("MEMORY %r" % {"ranks": processes, "threads": args.threads, "per_rank": rows}, flush=True)


def report_cpu(ranks, seconds):
    """Each rank's CPU seconds per stage (between the probes around it) beside the wall time."""
    rows = []
    for rank, readings in sorted(ranks.items()):
        if "baseline" not in readings or stages[-1] not in readings:
            print("rank %d: readings missing (%s)" % (rank, ", ".join(readings)), flush=True)
            continue
        labels = ("baseline",) + stages
        row = {"rank": rank}
        row.update({stage: readings[stage][2] - readings[labels[i]][2] for i, stage in enumerate(stages)})
        rows.append(row)
    chain_wall = sum(seconds[stage] for stage in stages)
    on_rank_0 = ("partition", "skeleton")
    print("| rank | " + " | ".join("CPU in %s (wall %.2f s)" % (s, seconds[s]) for s in stages) +
          " | CPU in partition + skeleton / chain wall |", flush=True)
    print("|---:|" + "---:|" * (len(stages) + 1))
    for row in rows:
        waiting = sum(row[stage] for stage in on_rank_0) / chain_wall
        row["waiting_share"] = waiting
        print("| %d | " % row["rank"] + " | ".join("%.2f s" % row[s] for s in stages) +
              " | %.1f %% |" % (100.0 * waiting), flush=True)
    print("CPU %r" % {"ranks": processes, "threads": args.threads, "wall": seconds, "per_rank": rows}, flush=True)


def main():
    fastest = {}
    probing = args.memory or args.cpu
    for repeat in range(1 if probing else args.repeats):
        reader = simple.SDFOFFReader(FileName=args.mesh)
        sdf = simple.ShapeDiameter(Input=reader, NumberOfThreads=args.threads)
        smooth = simple.SDFBilateralSmooth(Input=sdf, NumberOfThreads=args.threads)
        partition = simple.SDFGMMPartition(Input=smooth, NumberOfThreads=args.threads)
        skeleton = simple.SDFSkeleton(Input=partition, NumberOfThreads=args.threads)
        directory = tempfile.mkdtemp(prefix="mpi_chain_memory_") if probing else None
        if probing:
            probe(directory, "baseline")
        seconds = {}
        for name, proxy in zip(stages, (reader, sdf, smooth, partition, skeleton)):
            start = time.perf_counter()
            proxy.UpdatePipeline()
            seconds[name] = time.perf_counter() - start
            if probing:
                probe(directory, name)
        seconds["chain"] = sum(seconds[name] for name in stages)
        print("ranks %d, threads %d, repeat %d: %s" % (processes, args.threads, repeat,
              ", ".join("%s %.3f s" % item for item in seconds.items())), flush=True)
        for name, value in seconds.items():
            fastest[name] = min(fastest.get(name, value), value)
        if probing:
            readings = read_probes(directory)
            if args.memory:
                report_memory(readings)
            if args.cpu:
                report_cpu(readings, seconds)
            shutil.rmtree(directory, ignore_errors=True)
        for proxy in (skeleton, partition, smooth, sdf, reader):
            simple.Delete(proxy)
    print("RESULT %r" % {"ranks": processes, "threads": args.threads, **fastest}, flush=True)


main()
