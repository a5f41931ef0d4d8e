# SPDX-License-Identifier: BSD-3-Clause
"""Loading the plugin gives the partition labels a categorical colour map by default, the user's
own settings still win, and other arrays keep ParaView's continuous default."""
import os
import sys

from paraview import simple, servermanager

simple.LoadPlugin(os.environ["SHAPEDIAMETER_PLUGIN"], ns=vars(simple))
failures = []

# Site settings (priority 1) and the user's own (higher) must override the plugin's defaults:
# give SDFLevel15 a site-level continuous map before its colour map is first created.
servermanager.vtkSMSettings.GetInstance().AddCollectionFromString(
    '{"array_lookup_tables": {"SDFLevel15": {"PVLookupTable": {"IndexedLookup": 0}}}}', 1.0)


def expect(condition, message):
    if not condition:
        failures.append(message)


for name in ["SDFCluster"] + ["SDFLevel%d" % level for level in range(1, 15)]:
    lut = simple.GetColorTransferFunction(name)
    colours = list(lut.IndexedColors)
    triples = {tuple(round(c, 3) for c in colours[i:i + 3]) for i in range(0, len(colours), 3)}
    expect(lut.InterpretValuesAsCategories == 1, "%s: not categorical" % name)
    expect(list(lut.Annotations)[:4] == ["0", "cluster 0", "1", "cluster 1"],
           "%s: annotations %r" % (name, list(lut.Annotations)[:4]))
    expect(len(lut.Annotations) == 32, "%s: %d annotation entries, expected 16 labels" % (name, len(lut.Annotations)))
    expect(len(triples) == 16 and len(colours) == 48, "%s: %d distinct colours, expected 16" % (name, len(triples)))
    expect(lut.ShowCategoricalColorsinDataRangeOnly == 1, "%s: legend lists absent labels" % name)
    expect(list(lut.NanColor) == [0.5, 0.5, 0.5], "%s: NaN colour %r" % (name, list(lut.NanColor)))

for name in ("SDF", "SDFNormalized", "SDFSegment", "BoneId", "SDFLevel16", "SDFLevel15"):
    expect(simple.GetColorTransferFunction(name).InterpretValuesAsCategories == 0,
           "%s: should keep the continuous default (or the site setting)" % name)

if failures:
    sys.exit("\n".join(failures))
print("categorical defaults for SDFCluster and SDFLevel1-14; site settings override them")
