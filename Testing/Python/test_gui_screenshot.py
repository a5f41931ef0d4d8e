# SPDX-License-Identifier: BSD-3-Clause
"""A real ParaView GUI process (under xvfb-run) loads the plugin, builds the four-filter chain
(Testing/GUI/gui_chain.py) and is checked three ways:

1. The properties panel (ParaView's own GUI test player, a generated --test-script): for each
   filter, clicked in the pipeline browser, every property of the plugin XML has documentation
   and a widget; the basic ones are shown with their documented default (or the input array the
   script chose), the advanced ones are hidden until the panel's gear is pressed. ParaView exits
   non-zero when a check fails; its exit code must be 0.
2. The render view alone (unlit, white): coloured by SDFCluster with the plugin's categorical map
   without any colouring call, legend = the labels present, every frequent colour a palette entry.
3. The whole window (pipeline browser, panel, render view, histogram chart): compared with the
   baseline Testing/GUI/paraview-gui-window.png (vtkImageDifference, VTK's regression metric)
   on the platform it was made on (its .json: ParaView version, Debian codename); elsewhere
   only what does not depend on fonts and drivers: every cluster colour on screen (chart curves,
   legend) and the mesh covering part of the render view.
Regenerate the baseline: SHAPEDIAMETER_GUI_REBASELINE=1 ctest --test-dir build -R test_gui_screenshot
"""
import collections
import json
import os
import random
import shutil
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ElementTree

import numpy

from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOImage import vtkPNGReader

SOURCE_DIR = os.environ["SHAPEDIAMETER_SOURCE_DIR"]
PLUGIN = os.environ["SHAPEDIAMETER_PLUGIN"]
GUI_DIR = os.path.join(SOURCE_DIR, "Testing", "GUI")
BASELINE = os.path.join(GUI_DIR, "paraview-gui-window.png")
SCREEN = (1600, 1000)
# Positions in the pipeline browser (row paths of its model: builtin, reader, then each filter
# under its input; the skeleton hangs under the partition's first port) and the input arrays
# gui_chain.py names.
FILTERS = {"ShapeDiameter": ("/0:0/0:0/0:0", None),
           "SDFBilateralSmooth": ("/0:0/0:0/0:0/0:0", "SDF"),
           "SDFGMMPartition": ("/0:0/0:0/0:0/0:0/0:0", "SDFNormalized"),
           "SDFSkeleton": ("/0:0/0:0/0:0/0:0/0:0/0:0/0:0", "SDFSmoothed")}
PANEL = ("pqClientMainWindow/propertiesDock/propertiesPanel/scrollArea/qt_scrollarea_viewport/"
         "scrollAreaWidgetContents/PropertiesFrame/ProxyPanel")
BROWSER = "pqClientMainWindow/pipelineBrowserDock/pipelineBrowser"
GEAR = "pqClientMainWindow/propertiesDock/propertiesPanel/SearchBox/AdvancedButton"
# Before the checks: drag the left docks' edge from x = 294 to 480 so the panel's fields are
# readable (a miss on another layout changes nothing), then keep the GUI idle for grab_window.py
# (it starts 4 s after the script and needs ~2 s; the checks then click around the panel).
WINDOW_SET_UP = "\n".join(
    '<pqevent object="pqClientMainWindow" command="%s" arguments="%s" />' % event
    for event in (("mousePress", "1,1,0,294,500"), ("mouseMove", "1,1,0,400,500"),
                  ("mouseMove", "1,1,0,480,500"), ("mouseRelease", "1,0,0,480,500"),
                  ("process_events", "20000")))


def shown_number(text):
    """How ParaView's line edits print a default: the shortest round-trip form, no '.0'."""
    value = float(text)
    if value == int(value) and abs(value) < 1e15:
        return str(int(value))
    return repr(value)


def property_checks(prop, chosen_array):
    """(widget path, Qt property, expected text) telling that `prop` shows its default."""
    name, tag = prop.get("name"), prop.tag
    defaults = (prop.get("default_values") or "").split()
    domains = {child.tag for child in prop}
    if "ArrayListDomain" in domains:
        return [(name + "/ComboBox", "currentText", chosen_array)]
    if "BooleanDomain" in domains:
        return [(name + "/CheckBox", "checked", "true" if defaults[0] != "0" else "false")]
    if "EnumerationDomain" in domains:
        entries = {entry.get("value"): entry.get("text") for entry in prop.iter("Entry")}
        return [(name + "/ComboBox", "currentText", entries[defaults[0]])]
    ranged = [child for child in prop if child.tag in ("IntRangeDomain", "DoubleRangeDomain")]
    if ranged and ranged[0].get("min") is not None and ranged[0].get("max") is not None:
        widget = ("IntRangeWidget/LineEdit" if tag == "IntVectorProperty"
                  else "DoubleRangeWidget/DoubleLineEdit")
        return [(name + "/" + widget, "text", shown_number(defaults[0]))]
    edit = "LineEdit" if tag == "IntVectorProperty" else "DoubleLineEdit"
    return [("%s/%s%d" % (name, edit, i), "text", shown_number(value))
            for i, value in enumerate(defaults)]


def panel_script(plugin_xml):
    """The --test-script: click each filter, check its panel; leave the partition selected."""
    proxies = {proxy.get("name"): proxy for proxy in ElementTree.parse(plugin_xml).iter("SourceProxy")}
    events, count = [], 0

    def check(widget, qt_property, expected):
        events.append('<pqcheck object="%s/%s" property="%s" arguments="%s" />'
                      % (PANEL, widget, qt_property, expected))

    def click(row_path):
        for command, buttons in (("mousePress", 1), ("mouseRelease", 0)):
            events.append('<pqevent object="%s" command="%s" arguments="1,%d,0,30,5,%s" />'
                          % (BROWSER, command, buttons, row_path))

    for name, (row_path, chosen_array) in FILTERS.items():
        properties = [p for p in proxies[name] if p.tag.endswith("Property") and p.tag != "InputProperty"]
        undocumented = [p.get("name") for p in properties if p.find("Documentation") is None]
        if undocumented:
            sys.exit("%s: properties without documentation: %s" % (name, undocumented))
        click(row_path)
        advanced = [p for p in properties if p.get("panel_visibility") == "advanced"]
        for prop in properties:
            check(prop.get("name"), "visible", "false" if prop in advanced else "true")
        events.append('<pqevent object="%s" command="activate" arguments="" />' % GEAR)
        for prop in properties:
            check(prop.get("name"), "visible", "true")
            for widget, qt_property, expected in property_checks(prop, chosen_array):
                check(widget, qt_property, expected)
                count += 1
        events.append('<pqevent object="%s" command="activate" arguments="" />' % GEAR)
    click(FILTERS["SDFGMMPartition"][0])
    return ('<?xml version="1.0" ?>\n<pqevents>\n%s\n</pqevents>\n' % "\n".join(events)), count


def read_png(path):
    reader = vtkPNGReader()
    reader.SetFileName(path)
    reader.Update()
    image = reader.GetOutput()
    width, height, _ = image.GetDimensions()
    pixels = vtk_to_numpy(image.GetPointData().GetScalars())[:, :3]
    return image, width, height, pixels


def near(colour, entry, tolerance):
    return max(abs(int(a) - int(b)) for a, b in zip(colour, entry)) <= tolerance


def check_view(png, state):
    """The view-only screenshot: unlit flat colours, each exactly a palette entry."""
    k = state["ClusterCount"]
    if state["ColorArrayName"] != ["CELLS", "SDFCluster"] or state["InterpretValuesAsCategories"] != 1:
        sys.exit("the partition is not coloured by SDFCluster with a categorical map by default")
    # The cut may leave a cluster without faces: the legend lists the labels present.
    if state["ActiveAnnotatedValues"] != [str(label) for label in state["LabelsPresent"]]:
        sys.exit("legend values %r, expected the labels present %r" % (state["ActiveAnnotatedValues"], state["LabelsPresent"]))
    _, _, _, pixels = read_png(png)
    colours = collections.Counter(map(tuple, pixels))
    colours.pop((255, 255, 255), 0)
    covered = sum(colours.values()) / float(len(pixels))
    frequent = [c for c, n in colours.items() if n > 0.002 * len(pixels)]
    parts = [tuple(int(v) for v in c) for c, n in colours.items()
             if n >= 50 and any(near(c, p, 1) for p in state["palette"])]
    print("view: covered %.3f, %d part colours of %d clusters: %s" % (covered, len(parts), k, parts))
    if covered < 0.05:
        sys.exit("the view screenshot is blank (%.3f of pixels covered)" % covered)
    if len(parts) < len(state["LabelsPresent"]):
        sys.exit("expected %d part colours in the view, found %d" % (len(state["LabelsPresent"]), len(parts)))
    strangers = [c for c in frequent if not any(near(c, p, 1) for p in state["palette"])]
    if strangers:
        sys.exit("colours not from the categorical palette: %s" % strangers)


def check_window_anywhere(png, state):
    """What holds on any platform: the screen size, every cluster's colour drawn exactly (chart
    curves, legend swatches), the mesh covering part of the render view's background."""
    _, width, height, pixels = read_png(png)
    if (width, height) != SCREEN:
        sys.exit("window grab is %dx%d, expected %dx%d" % (width, height, SCREEN[0], SCREEN[1]))
    colours = collections.Counter(map(tuple, pixels))
    for label in range(state["ClusterCount"]):
        shown = sum(n for c, n in colours.items() if near(c, state["palette"][label], 2))
        if shown < 100:
            sys.exit("cluster %d's colour %s covers %d pixels of the window (chart curve and legend "
                     "expected)" % (label, state["palette"][label], shown))
    background = tuple(int(round(255 * c)) for c in state["Background"])
    grid = pixels.reshape(height, width, 3)
    is_background = numpy.all(numpy.abs(grid.astype(int) - background) <= 2, axis=2)
    rows, columns = numpy.nonzero(is_background)
    if len(rows) < 0.1 * width * height:
        sys.exit("the render view's background %s is missing from the window" % (background,))
    box = is_background[rows.min():rows.max() + 1, columns.min():columns.max() + 1]
    covered = 1.0 - box.mean()
    print("window: render view %dx%d, mesh covers %.3f" % (box.shape[1], box.shape[0], covered))
    if covered < 0.05:
        sys.exit("the render view shows no mesh (%.3f covered)" % covered)


def compare_with_baseline(png, kept):
    """VTK's image regression metric (vtkImageDifference's thresholded error, default settings)
    against the baseline. It forgives one-pixel shifts and anti-aliasing, so it catches changed
    colours, layouts and missing or moved widgets (a 10 x 10 px block: 6.8), not one changed
    letter or a line 2 px thinner (both 0, measured)."""
    from vtkmodules.vtkImagingCore import vtkImageDifference
    images = []
    for path in (png, BASELINE):
        image, width, height, _ = read_png(path)
        # Blank the status bar in both (VTK's rows start at the bottom): its memory meter
        # changes from run to run (9.6 of error alone).
        rows = vtk_to_numpy(image.GetPointData().GetScalars()).reshape(height, width, -1)
        rows[:STATUS_BAR_HEIGHT] = 0
        image.Modified()
        images.append(image)
    difference = vtkImageDifference()
    difference.SetInputData(images[0])
    difference.SetImageData(images[1])
    difference.Update()
    error = difference.GetThresholdedError()
    print("window vs baseline: thresholded error %.4f (at most %.2f)" % (error, BASELINE_THRESHOLD))
    if error > BASELINE_THRESHOLD:
        from vtkmodules.vtkIOImage import vtkPNGWriter
        writer = vtkPNGWriter()
        writer.SetInputConnection(difference.GetOutputPort())
        writer.SetFileName(os.path.join(kept, "difference.png"))
        writer.Write()
        sys.exit("the window differs from %s (error %.4f > %.2f); images in %s; if the change is "
                 "intended, regenerate: SHAPEDIAMETER_GUI_REBASELINE=1 ctest --test-dir build -R "
                 "test_gui_screenshot" % (BASELINE, error, BASELINE_THRESHOLD, kept))


# vtkTesting's default threshold since VTK 9.1 (the image difference's thresholded error).
BASELINE_THRESHOLD = 0.05
STATUS_BAR_HEIGHT = 30


def platform():
    from paraview.simple import GetParaViewVersion
    version = GetParaViewVersion()
    codename = ""
    if os.path.isfile("/etc/os-release"):
        for line in open("/etc/os-release"):
            if line.startswith("VERSION_CODENAME="):
                codename = line.split("=", 1)[1].strip()
    return {"paraview": "%d.%d" % (version.major, version.minor), "debian": codename}


def main():
    with tempfile.TemporaryDirectory() as work:
        view_png = os.path.join(work, "view.png")
        window_png = os.path.join(work, "window.png")
        script, count = panel_script(os.path.join(SOURCE_DIR, "Plugin", "ShapeDiameter.xml"))
        checks = os.path.join(work, "panel.xml")
        with open(checks, "w") as stream:
            stream.write(script.replace("<pqevents>", "<pqevents>\n" + WINDOW_SET_UP, 1))
        environment = dict(os.environ, SHAPEDIAMETER_GUI_SCREENSHOT=view_png, SHAPEDIAMETER_GUI_WINDOW=window_png)
        environment.pop("DISPLAY", None)
        command = ["xvfb-run", "-a", "-n", str(random.randint(100, 5100)),
                   "-s", "-screen 0 %dx%dx24 -noreset" % SCREEN, "paraview", "-geometry", "%dx%d+0+0" % SCREEN, "--dr",
                   "--plugin-search-paths=" + os.path.dirname(PLUGIN), "--plugins=ShapeDiameter",
                   "--script=" + os.path.join(GUI_DIR, "gui_chain.py"), "--test-script=" + checks, "--exit"]
        result = subprocess.run(command, env=environment, capture_output=True, text=True, timeout=600)
        output = result.stdout + result.stderr
        for error in (view_png + ".error", window_png + ".error"):
            if os.path.isfile(error):
                sys.exit("the GUI script failed:\n" + open(error).read())
        if result.returncode != 0:
            sys.exit("paraview exited with %d (a failed panel check or a crash):\n%s"
                     % (result.returncode, output[-6000:]))
        print("panel: %d documented properties checked in 4 filters, advanced ones behind the gear"
              % count)
        state = json.load(open(view_png + ".json"))
        state["palette"] = [tuple(int(round(255 * c)) for c in state["IndexedColors"][i:i + 3])
                            for i in range(0, len(state["IndexedColors"]), 3)]
        check_view(view_png, state)
        if not os.path.isfile(window_png):
            sys.exit("no window grab was written")
        kept = os.path.join(os.environ.get("SHAPEDIAMETER_BUILD_DIR", work), "Testing", "gui-window")
        os.makedirs(kept, exist_ok=True)
        shutil.copy(window_png, os.path.join(kept, "window.png"))
        check_window_anywhere(window_png, state)
        here = platform()
        if os.environ.get("SHAPEDIAMETER_GUI_REBASELINE"):
            shutil.copy(window_png, BASELINE)
            with open(os.path.splitext(BASELINE)[0] + ".json", "w") as stream:
                json.dump(here, stream, indent=2, sort_keys=True)
                stream.write("\n")
            print("baseline regenerated: %s (%s)" % (BASELINE, here))
            return
        made_on = json.load(open(os.path.splitext(BASELINE)[0] + ".json"))
        if made_on == here:
            compare_with_baseline(window_png, kept)
        else:
            print("baseline made on %s, running on %s: platform-independent window checks only"
                  % (made_on, here))


main()
