# SPDX-License-Identifier: BSD-3-Clause
"""Run inside a real `paraview` GUI (--script): the four filters on a bundled mesh as a user
would set them up, one view-only screenshot and one grab of the whole window.

1. Reader -> ShapeDiameter -> SDFBilateralSmooth -> SDFGMMPartition -> SDFSkeleton, defaults
   except the input arrays (named explicitly, README "Use from pvpython").
2. The partition in the render view with no colouring call (the plugin's colour defaults are
   under test), saved unlit on white for the colour check: SHAPEDIAMETER_GUI_SCREENSHOT, and
   <screenshot>.json with the colouring state.
3. The window a user sees: the lit partition with its legend beside the line chart of the partition's histogram port in the cluster colours (the pipeline command's
   --plot styling); the partition active, so the properties panel shows its fields. A separate
   process (grab_window.py) grabs the screen once it has settled, after the test's first events
   (they widen the properties dock): SHAPEDIAMETER_GUI_WINDOW.

Environment: SHAPEDIAMETER_DATA_DIR, SHAPEDIAMETER_SOURCE_DIR, SHAPEDIAMETER_GUI_SCREENSHOT,
SHAPEDIAMETER_GUI_WINDOW. Script errors go to <screenshot>.error (the GUI swallows them).
"""
import json
import os
import subprocess
import sys
import traceback

from paraview import simple, servermanager

source_dir = os.environ["SHAPEDIAMETER_SOURCE_DIR"]
sys.path.insert(0, os.path.join(source_dir, "Plugin"))
import sdf_pipeline  # noqa: E402  (the pipeline command's chart styling and camera)


def build_chain():
    reader = simple.OpenDataFile(os.path.join(os.environ["SHAPEDIAMETER_DATA_DIR"], "camel.off"))
    sdf = simple.ShapeDiameter(Input=reader)
    smooth = simple.SDFBilateralSmooth(Input=sdf, SDFArray=["CELLS", "SDF"])
    parts = simple.SDFGMMPartition(Input=smooth, NormalizedSDFArray=["CELLS", "SDFNormalized"])
    simple.SDFSkeleton(Input=parts, SDFArray=["CELLS", "SDFSmoothed"])
    return parts


def save_unlit_view(view, display, cluster_count, present, screenshot):
    lut = simple.GetColorTransferFunction("SDFCluster")
    palette = simple.GetSettingsProxy("ColorPalette")
    background = palette.BackgroundColor if hasattr(palette, "BackgroundColor") else palette.Background
    with open(screenshot + ".json", "w") as stream:
        json.dump({"ClusterCount": cluster_count, "LabelsPresent": present, "Background": list(background),
                   "ColorArrayName": list(display.ColorArrayName),
                   "InterpretValuesAsCategories": lut.InterpretValuesAsCategories,
                   "ActiveAnnotatedValues": list(lut.ActiveAnnotatedValues),
                   "IndexedColors": list(lut.IndexedColors)}, stream)
    display.Ambient, display.Diffuse = 1.0, 0.0
    display.SetScalarBarVisibility(view, False)
    view.OrientationAxesVisibility = 0
    view.UseColorPaletteForBackground = 0
    view.Background = [1.0, 1.0, 1.0]
    simple.Render(view)
    simple.SaveScreenshot(screenshot, view, ImageResolution=[800, 600])
    # Back to what the GUI shows by default.
    display.Ambient, display.Diffuse = 0.0, 1.0
    view.OrientationAxesVisibility = 1
    view.UseColorPaletteForBackground = 1


def arrange_window(view, parts, display, means, weights):
    display.SetScalarBarVisibility(view, True)
    layout = simple.GetLayout(view)
    layout.SplitHorizontal(0, 0.55)
    chart = simple.CreateView("XYChartView")
    simple.AssignViewToLayout(view=chart, layout=layout, hint=2)
    sdf_pipeline.show_cluster_chart(simple, parts, chart, means, weights)
    simple.Render(chart)
    simple.SetActiveView(view)
    simple.SetActiveSource(parts)
    simple.Render(view)


def main():
    parts = build_chain()
    view = simple.GetActiveViewOrCreate("RenderView")
    display = simple.Show(parts, view)  # no ColorBy / LUT call: the default colouring is checked
    sdf_pipeline.frame_camera(view, parts)
    mesh = servermanager.Fetch(parts)  # the mesh, once
    means, weights = sdf_pipeline.cluster_model(mesh)
    clusters = mesh.GetCellData().GetArray("SDFCluster")
    present = sorted({int(clusters.GetValue(i)) for i in range(clusters.GetNumberOfTuples())} - {-1})
    save_unlit_view(view, display, len(means), present, os.environ["SHAPEDIAMETER_GUI_SCREENSHOT"])
    arrange_window(view, parts, display, means, weights)
    # /usr/bin/python3: Debian's, with python3-pil (ImageGrab over XCB).
    subprocess.Popen(["/usr/bin/python3", os.path.join(source_dir, "Testing", "GUI", "grab_window.py"),
                      os.environ["SHAPEDIAMETER_GUI_WINDOW"], "4", "40"])


try:
    main()
except Exception:  # the GUI swallows script errors: leave them where the test looks
    with open(os.environ["SHAPEDIAMETER_GUI_SCREENSHOT"] + ".error", "w") as stream:
        stream.write(traceback.format_exc())
