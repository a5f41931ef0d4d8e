# SPDX-License-Identifier: BSD-3-Clause
"""The README's pipeline command end to end (renders through xvfb-run), plus its error contract."""
import json
import os
import subprocess
import sys
import tempfile

source = os.environ["SHAPEDIAMETER_SOURCE_DIR"]
command = os.path.join(source, "Plugin", "sdf-pipeline")
environment = dict(os.environ)
environment.pop("DISPLAY", None)  # exercise the xvfb-run path


def run(*arguments):
    return subprocess.run([command, *arguments], capture_output=True, text=True, env=environment, timeout=900)


def fail(message, result=None):
    if result is not None:
        message += "\nstdout:\n%s\nstderr:\n%s" % (result.stdout, result.stderr)
    sys.exit(message)


with tempfile.TemporaryDirectory() as out:
    mesh = os.path.join(source, "Data", "camel.off")
    result = run(mesh, "--output-dir", out, "--quiet")
    if result.returncode != 0:
        fail("pipeline failed", result)
    for suffix in (".vtp", "_sdf.png", "_timings.json"):
        if not os.path.isfile(os.path.join(out, "camel" + suffix)):
            fail("missing output camel%s" % suffix, result)
    with open(os.path.join(out, "camel_timings.json")) as stream:
        timings = json.load(stream)
    for key in ("read", "write", "render", "total"):
        if not isinstance(timings.get(key), (int, float)) or timings[key] < 0:
            fail("bad timing %r in %r" % (key, timings))

    from vtkmodules.vtkIOImage import vtkPNGReader
    png = vtkPNGReader()
    png.SetFileName(os.path.join(out, "camel_sdf.png"))
    png.Update()
    image = png.GetOutput()
    scalars = image.GetPointData().GetScalars()
    low, high = scalars.GetRange(0)
    dims = image.GetDimensions()
    print("png", dims, "red range", low, high)
    if dims[0] < 512 or high - low < 50:
        fail("PNG looks blank: dims %r red range %r" % (dims, (low, high)))
    # Count pixels different from the white background: the mesh must cover a real area.
    from vtkmodules.util.numpy_support import vtk_to_numpy
    pixels = vtk_to_numpy(scalars)
    covered = (pixels[:, :3].astype(int).sum(axis=1) < 3 * 250).mean()
    print("covered fraction", covered)
    if covered < 0.02:
        fail("PNG is almost empty: %.4f of pixels covered" % covered)

    # Error contract: one line on stderr, non-zero exit, no traceback.
    for bad in (os.path.join(out, "missing.off"), os.path.join(out, "garbage.off")):
        if bad.endswith("garbage.off"):
            with open(bad, "wb") as stream:
                stream.write(b"OFF\n3 1 0\n0 0 0\n1 0\n")
        result = run(bad, "--output-dir", out, "--no-render")
        lines = [line for line in result.stderr.splitlines() if line.strip()]
        if result.returncode == 0 or len(lines) != 1 or "Traceback" in result.stderr:
            fail("bad input %s not reported as one line" % bad, result)
        print("error line:", lines[0])
