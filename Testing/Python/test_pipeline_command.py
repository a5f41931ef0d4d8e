# SPDX-License-Identifier: BSD-3-Clause
"""The README's pipeline command end to end (renders through xvfb-run), plus its error contract.

Runs it with --no-setup: no package installation and no build inside ctest; the wrapper uses the
plugin of the build tree ctest runs in (SHAPEDIAMETER_BUILD_DIR, set by Testing/CMakeLists.txt).
The wrapper does not repeat failed runs, so a crash while rendering (exit 134) fails this test."""
import json
import os
import shutil
import subprocess
import sys
import tempfile

import numpy

source = os.environ["SHAPEDIAMETER_SOURCE_DIR"]
command = os.path.join(source, "Plugin", "sdf-pipeline")
environment = dict(os.environ)
environment.pop("DISPLAY", None)  # exercise the xvfb-run path


def run(*arguments):
    return subprocess.run([command, "--no-setup", *arguments], capture_output=True, text=True, env=environment,
                          timeout=900)


def fail(message, result=None):
    if result is not None:
        message += "\nstdout:\n%s\nstderr:\n%s" % (result.stdout, result.stderr)
    sys.exit(message)


READ_BACK = r"""
import sys
from paraview import simple, servermanager
surface_path, skeleton_path = sys.argv[1:3]
with open(surface_path, "rb") as stream:
    if b"<AppendedData" in stream.read():
        sys.exit("%s: appended data, which ParaView 5.11 cannot read with Debian 12's current libexpat" % surface_path)
surface = servermanager.Fetch(simple.XMLPolyDataReader(FileName=[surface_path]))
skeleton = servermanager.Fetch(simple.XMLPolyDataReader(FileName=[skeleton_path]))
arrays = [surface.GetCellData().GetArrayName(i) for i in range(surface.GetCellData().GetNumberOfArrays())]
print("read back:", surface.GetNumberOfCells(), "faces,", skeleton.GetNumberOfCells(), "skeleton lines,", arrays)
if surface.GetNumberOfCells() != 19536 or skeleton.GetNumberOfCells() < 1:
    sys.exit("wrong cell counts")
for name in ("SDF", "SDFNormalized", "SDFCluster", "SDFSegment"):
    if name not in arrays:
        sys.exit("missing array " + name)
if skeleton.GetPointData().GetArray("Radius") is None:
    sys.exit("skeleton without Radius")
"""

with tempfile.TemporaryDirectory() as out:
    # --no-setup really skips the set-up: with SHAPEDIAMETER_BUILD_DIR naming a regular file (the
    # plugin comes from SHAPEDIAMETER_PLUGIN), any build step would fail at once (mkdir/configure).
    not_a_build = os.path.join(out, "not-a-build-directory")
    open(not_a_build, "w").close()
    result = subprocess.run([command, "--no-setup", "--help"], capture_output=True, text=True, timeout=300,
                            env=dict(environment, SHAPEDIAMETER_BUILD_DIR=not_a_build))
    if result.returncode != 0 or "--no-setup" not in result.stdout:
        fail("sdf-pipeline --no-setup --help with SHAPEDIAMETER_BUILD_DIR=%s (a file) exited %d: "
             "did it try to install or build?" % (not_a_build, result.returncode), result)

    mesh = os.path.join(source, "Data", "camel.off")
    result = run(mesh, "--output-dir", out, "--quiet", "--plot")
    if result.returncode != 0:
        fail("pipeline failed", result)
    for suffix in (".vtp", "_sdf.png", "_timings.json", ".seg", "_parts.png", "_skeleton.vtp", "_skeleton.png",
                   "_gmm.png"):
        if not os.path.isfile(os.path.join(out, "camel" + suffix)):
            fail("missing output camel%s" % suffix, result)
    with open(os.path.join(out, "camel_timings.json")) as stream:
        timings = json.load(stream)
    with open(os.path.join(out, "camel.seg")) as stream:
        labels = [int(line) for line in stream]
    if len(labels) != 19536 or min(labels) != 0:
        fail("camel.seg: %d labels, min %r" % (len(labels), min(labels) if labels else None))
    for key in ("read", "sdf", "smooth", "partition", "skeleton", "write", "render", "total"):
        if not isinstance(timings.get(key), (int, float)) or timings[key] < 0:
            fail("bad timing %r in %r" % (key, timings))

    # The written files open in ParaView's own XML reader, in a separate pvpython process with
    # the system's libexpat (Debian 12's current one rejects raw appended data: README).
    read_back = subprocess.run([shutil.which("pvpython"), "-c", READ_BACK, os.path.join(out, "camel.vtp"),
                                os.path.join(out, "camel_skeleton.vtp")],
                               capture_output=True, text=True, timeout=300)
    print(read_back.stdout.strip())
    if read_back.returncode != 0 or "ERROR" in read_back.stderr.upper():
        fail("written .vtp files do not read back in ParaView", read_back)

    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOImage import vtkPNGReader
    for picture in ("camel_sdf.png", "camel_parts.png", "camel_skeleton.png", "camel_gmm.png"):
        png = vtkPNGReader()
        png.SetFileName(os.path.join(out, picture))
        png.Update()
        image = png.GetOutput()
        dims = image.GetDimensions()
        # Pixels different from the white background: the mesh must cover a real area.
        pixels = vtk_to_numpy(image.GetPointData().GetScalars())
        covered = (pixels[:, :3].astype(int).sum(axis=1) < 3 * 250).mean()
        print(picture, dims, "covered fraction", covered)
        if dims[0] < 512 or covered < 0.02:
            fail("%s looks blank: dims %r, %.4f of pixels covered" % (picture, dims, covered))

    # The GMM chart draws cluster c's Gaussian in the colour cluster c has in the parts picture
    # (the plugin's SDFCluster colour map): every fitted cluster's colour covers pixels in both.
    from paraview import simple
    from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
    simple.LoadPlugin(os.environ["SHAPEDIAMETER_PLUGIN"], ns=vars(simple))
    colours = list(simple.GetColorTransferFunction("SDFCluster").IndexedColors)
    camel = vtkXMLPolyDataReader()
    camel.SetFileName(os.path.join(out, "camel.vtp"))
    camel.Update()
    clusters = int(camel.GetOutput().GetFieldData().GetArray("SDFClusterCount").GetValue(0))
    present = sorted(set(vtk_to_numpy(camel.GetOutput().GetCellData().GetArray("SDFCluster")).tolist()))
    for picture in ("camel_gmm.png", "camel_parts.png"):
        png = vtkPNGReader()
        png.SetFileName(os.path.join(out, picture))
        png.Update()
        pixels = vtk_to_numpy(png.GetOutput().GetPointData().GetScalars())[:, :3].astype(int)
        # The histogram draws every component; the parts only the clusters the cut kept faces in.
        labels = range(clusters) if picture == "camel_gmm.png" else present
        for c in labels:
            rgb = [round(255 * value) for value in colours[3 * c:3 * c + 3]]
            count = int((abs(pixels - rgb).max(axis=1) <= 12).sum())
            print("%s: cluster %d colour %r on %d pixels" % (picture, c, rgb, count))
            if count < 300:
                fail("%s: cluster %d's colour %r covers only %d pixels" % (picture, c, rgb, count))
        if picture == "camel_gmm.png":
            # The x axis is nsdf's [0, 1]: the histogram (grey, 0.72) starts at the left axis and
            # ends at the right of the plot. Near the x axis (where its ends run, the density
            # being small there) its leftmost and rightmost pixels span the plot; on a
            # [-0.3, 1.3] axis they would start ~19 % in and end ~81 % across.
            height, width = png.GetOutput().GetDimensions()[1], png.GetOutput().GetDimensions()[0]
            image = pixels.reshape(height, width, 3)[::-1]  # VTK rows start at the bottom
            dark = image.sum(axis=2) < 150
            axis_x = int(numpy.nonzero(dark.sum(axis=0) > 0.5 * height)[0][0])
            axis_y = int(numpy.nonzero(dark.sum(axis=1) > 0.5 * width)[0][-1])
            band = image[axis_y - 80:axis_y - 1, axis_x + 2:]
            columns = numpy.nonzero((abs(band - 184).max(axis=2) <= 3).any(axis=0))[0]
            plot_width = width - axis_x
            print("%s: axes at x=%d, y=%d; histogram from %d to %d of %d px"
                  % (picture, axis_x, axis_y, columns.min(), columns.max(), plot_width))
            if columns.min() > 0.05 * plot_width or columns.max() < 0.9 * plot_width:
                fail("%s: the histogram spans %d..%d of the %d px plot: the x axis is not [0, 1]"
                     % (picture, columns.min(), columns.max(), plot_width))

    # --family: one normalisation range (the widest of the members' SDFSmoothed) and one model.
    family_dir = os.path.join(out, "family")
    members = [os.path.join(source, "Data", name) for name in ("hand.off", "camel.off")]
    result = run(*members, "--family", "--output-dir", family_dir, "--no-render", "--quiet")
    if result.returncode != 0:
        fail("pipeline --family failed", result)
    fields, smoothed = [], []
    for name in ("hand", "camel"):
        reader = vtkXMLPolyDataReader()
        reader.SetFileName(os.path.join(family_dir, name + ".vtp"))
        reader.Update()
        data = reader.GetOutput()
        fields.append({key: tuple(vtk_to_numpy(data.GetFieldData().GetArray(key)).ravel())
                       for key in ("SDFNormalizationRange", "SDFGMMMeans")})
        smoothed.append(vtk_to_numpy(data.GetCellData().GetArray("SDFSmoothed")))
    widest = (min(v.min() for v in smoothed), max(v.max() for v in smoothed))
    print("family:", fields, "widest SDFSmoothed range", widest)
    if fields[0] != fields[1] or fields[0]["SDFNormalizationRange"] != widest:
        fail("--family did not share one normalisation range and one model: %r, widest %r" % (fields, widest))

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
