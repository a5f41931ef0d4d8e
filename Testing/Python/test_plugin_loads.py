# SPDX-License-Identifier: BSD-3-Clause
"""The plugin loads in a real pvpython and its OFF reader is what OpenDataFile picks."""
import os
import sys

from paraview import simple

plugin = os.environ["SHAPEDIAMETER_PLUGIN"]
data = os.environ["SHAPEDIAMETER_DATA_DIR"]
simple.LoadPlugin(plugin, ns=vars(simple))
assert hasattr(simple, "SDFOFFReader"), "SDFOFFReader proxy missing after LoadPlugin"

reader = simple.OpenDataFile(os.path.join(data, "camel.off"))
assert reader is not None, "OpenDataFile found no reader for .off"
assert reader.GetXMLName() == "SDFOFFReader", reader.GetXMLName()
reader.UpdatePipeline()
info = reader.GetDataInformation()
cells = info.GetNumberOfCells()
points = info.GetNumberOfPoints()
print("camel.off:", points, "points", cells, "cells")
if (points, cells) != (9770, 19536):
    sys.exit("unexpected counts %d points %d cells" % (points, cells))
