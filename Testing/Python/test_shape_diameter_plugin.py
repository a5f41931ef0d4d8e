# SPDX-License-Identifier: BSD-3-Clause
"""The ShapeDiameter proxy in a real pvpython: range and finiteness of SDF on a bundled mesh."""
import math
import os
import sys

from paraview import simple, servermanager

simple.LoadPlugin(os.environ["SHAPEDIAMETER_PLUGIN"], ns=vars(simple))
reader = simple.SDFOFFReader(FileName=os.path.join(os.environ["SHAPEDIAMETER_DATA_DIR"], "hand.off"))
sdf = simple.ShapeDiameter(Input=reader)
assert sdf.NumberOfRays == 30 and abs(sdf.ConeAngle - 120) < 1e-12 and sdf.AutoOrient == 1
sdf.UpdatePipeline()
mesh = servermanager.Fetch(sdf)
array = mesh.GetCellData().GetArray("SDF")
if array is None or array.GetNumberOfTuples() != 2390:
    sys.exit("SDF array missing or wrong size")
values = [array.GetValue(i) for i in range(array.GetNumberOfTuples())]
if not all(math.isfinite(v) for v in values):
    sys.exit("non-finite SDF")
bounds = mesh.GetBounds()
diagonal = math.sqrt(sum((bounds[2 * i + 1] - bounds[2 * i]) ** 2 for i in range(3)))
low, high = min(values), max(values)
print("SDF range", low, high, "diagonal", diagonal)
# A hand: fingers are thin, the palm thicker; nothing is thicker than the whole model.
if not (0 < low < high < diagonal and high / low > 3):
    sys.exit("implausible SDF range %g..%g (diagonal %g)" % (low, high, diagonal))

# The smoothing proxy chained after it: SDFNormalized spans [0, 1].
smooth = simple.SDFBilateralSmooth(Input=sdf)
assert smooth.NumberOfIterations == 3 and abs(smooth.Alpha - 4) < 1e-12
smooth.UpdatePipeline()
mesh = servermanager.Fetch(smooth)
normalized = mesh.GetCellData().GetArray("SDFNormalized")
smoothed = mesh.GetCellData().GetArray("SDFSmoothed")
if normalized is None or smoothed is None:
    sys.exit("smoothing arrays missing")
low, high = normalized.GetRange()
print("SDFNormalized range", low, high)
if abs(low) > 1e-12 or abs(high - 1) > 1e-12:
    sys.exit("SDFNormalized range %g..%g, expected 0..1" % (low, high))
