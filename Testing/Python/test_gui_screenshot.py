# SPDX-License-Identifier: BSD-3-Clause
"""A real ParaView GUI process (under xvfb-run) loads the plugin, builds the chain and saves a
screenshot without any colouring call; by default the parts must be coloured by SDFCluster with the
plugin's categorical colour map, and the image must show at least k of its colours."""
import collections
import json
import os
import random
import subprocess
import sys
import tempfile

k = 4
plugin = os.environ["SHAPEDIAMETER_PLUGIN"]
script = os.path.join(os.environ["SHAPEDIAMETER_SOURCE_DIR"], "Testing", "GUI", "gui_chain.py")
with tempfile.TemporaryDirectory() as work:
    png = os.path.join(work, "gui.png")
    environment = dict(os.environ, SHAPEDIAMETER_GUI_SCREENSHOT=png, SHAPEDIAMETER_GUI_CLUSTERS=str(k))
    environment.pop("DISPLAY", None)
    command = ["xvfb-run", "-a", "-n", str(random.randint(100, 5100)), "-s", "-screen 0 1280x1024x24", "paraview", "--dr",
               "--plugin-search-paths=" + os.path.dirname(plugin), "--plugins=ShapeDiameter",
               "--script=" + script, "--exit"]
    result = subprocess.run(command, env=environment, capture_output=True, text=True, timeout=600)
    if not os.path.isfile(png):
        error = png + ".error"
        details = open(error).read() if os.path.isfile(error) else result.stdout + result.stderr
        sys.exit("the GUI wrote no screenshot (exit %d)\n%s" % (result.returncode, details))

    state = json.load(open(png + ".json"))
    print("default colouring:", {key: value for key, value in state.items() if key != "IndexedColors"})
    if state["ColorArrayName"] != ["CELLS", "SDFCluster"] or state["InterpretValuesAsCategories"] != 1:
        sys.exit("the partition is not coloured by SDFCluster with a categorical map by default")
    if state["ActiveAnnotatedValues"] != [str(label) for label in range(k)]:
        sys.exit("legend values %r, expected the %d labels present" % (state["ActiveAnnotatedValues"], k))
    palette = {tuple(int(round(255 * c)) for c in state["IndexedColors"][i:i + 3])
               for i in range(0, len(state["IndexedColors"]), 3)}

    from vtkmodules.vtkIOImage import vtkPNGReader
    from vtkmodules.util.numpy_support import vtk_to_numpy
    reader = vtkPNGReader()
    reader.SetFileName(png)
    reader.Update()
    pixels = vtk_to_numpy(reader.GetOutput().GetPointData().GetScalars())[:, :3]
    colours = collections.Counter(map(tuple, pixels))
    background = colours.pop((255, 255, 255), 0)
    covered = sum(colours.values()) / float(len(pixels))
    # Unlit flat colours: each part colour is one exact RGB value; edges blend (rare values).
    def in_palette(colour):
        return any(max(abs(a - b) for a, b in zip(colour, entry)) <= 1 for entry in palette)

    frequent = [c for c, n in colours.items() if n > 0.002 * len(pixels)]
    parts = [c for c, n in colours.items() if n >= 50 and in_palette(c)]  # small parts (ears) too
    print("covered %.3f, %d frequent colours: %s; %d palette colours shown: %s"
          % (covered, len(frequent), frequent, len(parts), parts))
    if covered < 0.05:
        sys.exit("the screenshot is blank (%.3f of pixels covered)" % covered)
    if len(parts) < k:
        sys.exit("expected at least %d part colours, found %d" % (k, len(parts)))
    # Unlit: every frequent colour is exactly a palette entry (±1 for 8-bit rounding).
    strangers = [c for c in frequent if not in_palette(c)]
    if strangers:
        sys.exit("colours not from the categorical palette: %s" % strangers)
