# SPDX-License-Identifier: BSD-3-Clause
"""The evaluation CLIs on the pipeline's own output: the camel partitioned through the plugin
(reader, SDF, smoothing, partition), its labels written as .seg files. The defaults' SDFSegment
compared with itself relabelled is perfect; with its own SDFCluster (segments are the connected
pieces of the clusters) it has the same boundaries and no consistency error but a Hamming
distance; with the paper's EM at k = 4 it is a different segmentation."""
import json
import os
import subprocess
import sys
import tempfile

from paraview import simple, servermanager

simple.LoadPlugin(os.environ["SHAPEDIAMETER_PLUGIN"], ns=vars(simple))
build = os.environ["SHAPEDIAMETER_BUILD_DIR"]
mesh = os.path.join(os.environ["SHAPEDIAMETER_DATA_DIR"], "camel.off")
metrics = os.path.join(build, "bin", "sdf-seg-metrics")
consistency = os.path.join(build, "bin", "sdf-pose-consistency")

reader = simple.SDFOFFReader(FileName=mesh)
sdf = simple.ShapeDiameter(Input=reader)
smooth = simple.SDFBilateralSmooth(Input=sdf, SDFArray=["CELLS", "SDF"])
partition = simple.SDFGMMPartition(Input=smooth, NormalizedSDFArray=["CELLS", "SDFNormalized"])
partition.UpdatePipeline()
output = servermanager.Fetch(partition)
em = simple.SDFGMMPartition(Input=smooth, NormalizedSDFArray=["CELLS", "SDFNormalized"], NumberOfClusters=4,
                            ClusterModel=0)
em.UpdatePipeline()
em_output = servermanager.Fetch(em)
faces = 19536  # the camel's face count: one label per face, in file order
if output.GetNumberOfCells() != faces:
    sys.exit("the pipeline output has %d cells, the camel %d faces" % (output.GetNumberOfCells(), faces))


def labels_of(name, data=output):
    array = data.GetCellData().GetArray(name)
    values = [int(array.GetValue(f)) for f in range(faces)]
    if min(values) < 0:
        sys.exit("%s has an unlabelled face" % name)
    return values


segments = labels_of("SDFSegment")
clusters = labels_of("SDFCluster")
em_segments = labels_of("SDFSegment", em_output)
print("pipeline output: %d segments, %d clusters" % (len(set(segments)), len(set(clusters))))
if len(set(segments)) < 5 or len(set(clusters)) >= len(set(segments)):
    sys.exit("implausible partition of the camel: %d segments, %d clusters" % (len(set(segments)), len(set(clusters))))

with tempfile.TemporaryDirectory() as work:
    def write(name, labels):
        path = os.path.join(work, name)
        with open(path, "w") as stream:
            stream.write("".join("%d\n" % label for label in labels))
        return path

    a = write("segments.seg", segments)
    relabelled = write("relabelled.seg", [1000 - 7 * label for label in segments])
    merged = write("clusters.seg", clusters)
    other = write("em.seg", em_segments)

    def run(*arguments):
        result = subprocess.run(arguments, capture_output=True, text=True)
        if result.returncode != 0:
            sys.exit("%s failed: %s" % (arguments[0], result.stderr))
        return json.loads(result.stdout)

    same = run(metrics, mesh, a, relabelled, "--json")
    print("relabelled:", same)
    scores = ("cutDiscrepancy", "missingRate", "falseAlarmRate", "hammingDistance", "randIndexError",
              "globalConsistencyError", "localConsistencyError")
    numbers = [same[key] for key in scores]
    if any(abs(v) > 1e-12 for v in numbers) or same["segmentsA"] != len(set(segments)):
        sys.exit("a relabelled segmentation must score 0 everywhere: %r" % same)
    # A cluster is a union of segments (its connected pieces): the same boundaries (CD 0), no
    # consistency error (one refines the other), but the region-based Hamming distance sees the
    # merged segments: Rm > 0.
    coarser = run(metrics, mesh, a, merged, "--json")
    print("segments vs clusters:", coarser)
    if (coarser["cutDiscrepancy"] > 1e-12 or coarser["globalConsistencyError"] > 1e-12
            or coarser["localConsistencyError"] > 1e-12 or not coarser["missingRate"] > 0.001):
        sys.exit("segments against their own clusters: expected CD = GCE = LCE = 0 < Rm: %r" % coarser)
    different = run(metrics, mesh, a, other, "--json")
    print("defaults vs EM k = 4:", different)
    if not min(different[key] for key in ("hammingDistance", "randIndexError")) > 0.01:
        sys.exit("different segmentations must not score 0: %r" % different)

    table = subprocess.run([consistency, a, relabelled, other], capture_output=True, text=True)
    print(table.stdout)
    if table.returncode != 0 or "|" not in table.stdout:
        sys.exit("sdf-pose-consistency failed: %s" % table.stderr)

    bad = subprocess.run([metrics, mesh, a, write("short.seg", [0, 1])], capture_output=True, text=True)
    if bad.returncode == 0 or len(bad.stderr.strip().splitlines()) != 1:
        sys.exit("a label count mismatch must be one error line: %r" % bad.stderr)
