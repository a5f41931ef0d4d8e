# SPDX-License-Identifier: BSD-3-Clause
"""Run inside a real `paraview` GUI (--script): the chain on a bundled mesh, one screenshot.

Environment: SHAPEDIAMETER_DATA_DIR, SHAPEDIAMETER_GUI_SCREENSHOT (PNG to write),
SHAPEDIAMETER_GUI_CLUSTERS (k). Writes <screenshot>.json: the colouring state.
"""
import json
import os
import traceback

from paraview import simple


def main():

    k = int(os.environ.get("SHAPEDIAMETER_GUI_CLUSTERS", "4"))
    reader = simple.OpenDataFile(os.path.join(os.environ["SHAPEDIAMETER_DATA_DIR"], "camel.off"))
    sdf = simple.ShapeDiameter(Input=reader)
    smooth = simple.SDFBilateralSmooth(Input=sdf, SDFArray=["CELLS", "SDF"])
    parts = simple.SDFGMMPartition(Input=smooth, NumberOfClusters=k,
                                   NormalizedSDFArray=["CELLS", "SDFNormalized"])
    view = simple.GetActiveViewOrCreate("RenderView")
    # No ColorBy / LUT calls: what is checked is the colouring a user gets by default.
    display = simple.Show(parts, view)
    lut = simple.GetColorTransferFunction("SDFCluster")
    with open(os.environ["SHAPEDIAMETER_GUI_SCREENSHOT"] + ".json", "w") as stream:
        json.dump({"ColorArrayName": list(display.ColorArrayName),
                   "InterpretValuesAsCategories": lut.InterpretValuesAsCategories,
                   "ActiveAnnotatedValues": list(lut.ActiveAnnotatedValues),
                   "IndexedColors": list(lut.IndexedColors)}, stream)
    display.Ambient = 1.0
    display.Diffuse = 0.0
    display.SetScalarBarVisibility(view, False)
    view.OrientationAxesVisibility = 0
    view.UseColorPaletteForBackground = 0
    view.Background = [1.0, 1.0, 1.0]
    view.CameraPosition = [1, 0, 0]
    view.CameraFocalPoint = [0, 0, 0]
    view.CameraViewUp = [0, 1, 0]
    view.ResetCamera()
    simple.Render(view)
    simple.SaveScreenshot(os.environ["SHAPEDIAMETER_GUI_SCREENSHOT"], view, ImageResolution=[800, 600])


try:
    main()
except Exception:  # the GUI swallows script errors: leave them where the test looks
    with open(os.environ["SHAPEDIAMETER_GUI_SCREENSHOT"] + ".error", "w") as stream:
        stream.write(traceback.format_exc())
