# SPDX-License-Identifier: BSD-3-Clause
"""The evaluation CLIs on the pipeline's own output: a segmentation compared with itself is
perfect, with a relabelled copy too; a different segmentation is not."""
import json
import os
import subprocess
import sys
import tempfile

build = os.environ["SHAPEDIAMETER_BUILD_DIR"]
mesh = os.path.join(os.environ["SHAPEDIAMETER_DATA_DIR"], "hand.off")
metrics = os.path.join(build, "bin", "sdf-seg-metrics")
consistency = os.path.join(build, "bin", "sdf-pose-consistency")

faces = 2390
with tempfile.TemporaryDirectory() as work:
    def write(name, labels):
        path = os.path.join(work, name)
        with open(path, "w") as stream:
            stream.write("".join("%d\n" % label for label in labels))
        return path

    a = write("a.seg", [f * 7 // faces for f in range(faces)])
    relabelled = write("b.seg", [100 - f * 7 // faces for f in range(faces)])
    halves = write("c.seg", [f * 2 // faces for f in range(faces)])

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
    if any(abs(v) > 1e-12 for v in numbers):
        sys.exit("a relabelled segmentation must score 0 everywhere: %r" % same)
    other = run(metrics, mesh, a, halves, "--json")
    print("different:", other)
    if not min(other[key] for key in ("hammingDistance", "randIndexError")) > 0.01:
        sys.exit("different segmentations must not score 0: %r" % other)

    table = subprocess.run([consistency, a, relabelled, halves], capture_output=True, text=True)
    print(table.stdout)
    if table.returncode != 0 or "|" not in table.stdout:
        sys.exit("sdf-pose-consistency failed: %s" % table.stderr)

    bad = subprocess.run([metrics, mesh, a, write("short.seg", [0, 1])], capture_output=True, text=True)
    if bad.returncode == 0 or len(bad.stderr.strip().splitlines()) != 1:
        sys.exit("a label count mismatch must be one error line: %r" % bad.stderr)
