# SPDX-License-Identifier: BSD-3-Clause
"""The full chain through the plugin proxies in pvpython, and the family model (Model input)."""
import os
import sys

from paraview import simple, servermanager

simple.LoadPlugin(os.environ["SHAPEDIAMETER_PLUGIN"], ns=vars(simple))
data = os.environ["SHAPEDIAMETER_DATA_DIR"]


def chain(name, model=None, k=4, cluster_model=0):
    reader = simple.SDFOFFReader(FileName=os.path.join(data, name))
    sdf = simple.ShapeDiameter(Input=reader)
    smooth = simple.SDFBilateralSmooth(Input=sdf, SDFArray=["CELLS", "SDF"])
    # ClusterModel 0 (the paper's EM) fits exactly k clusters; the default (1, density modes)
    # takes at most k.
    properties = dict(Input=smooth, NumberOfClusters=k, ClusterModel=cluster_model,
                      NormalizedSDFArray=["CELLS", "SDFNormalized"])
    if model is not None:
        properties["Model"] = model
    partition = simple.SDFGMMPartition(**properties)
    partition.UpdatePipeline()
    return partition


hand = chain("hand.off")
mesh = servermanager.Fetch(hand)
cells = mesh.GetCellData()
for name in ("SDF", "SDFSmoothed", "SDFNormalized", "SDFProbabilities", "SDFCluster", "SDFSegment",
             "SDFLevel1", "SDFLevel2", "SDFLevel3"):
    if cells.GetArray(name) is None:
        sys.exit("missing cell array %s" % name)
k = mesh.GetFieldData().GetArray("SDFClusterCount").GetValue(0)
if k != 4 or cells.GetArray("SDFProbabilities").GetNumberOfComponents() != 4:
    sys.exit("expected 4 clusters, got %d" % k)

# The defaults (density modes, at most 5 clusters) on the camel: legs, neck and head, humps and
# body are at least 8 connected parts over at least 3 thickness bands (measured: 11 segments,
# bands 1..4 of 5 fitted; the cut may leave a band, here the thickest, without faces).
defaults = servermanager.Fetch(chain("camel.off", k=5, cluster_model=1))
count = defaults.GetFieldData().GetArray("SDFClusterCount").GetValue(0)
low, high = defaults.GetCellData().GetArray("SDFCluster").GetRange()
segments = int(defaults.GetCellData().GetArray("SDFSegment").GetRange()[1]) + 1
print("camel, defaults: %d clusters, labels %d..%d, %d segments" % (count, low, high, segments))
if count < 3 or low < 0 or high > count - 1 or high - low < 2 or segments < 8:
    sys.exit("implausible partition of the camel: %d clusters, labels %d..%d, %d segments" % (count, low, high, segments))

# Family: the elephant partitioned with the hand's mixture reuses the same means.
elephant = servermanager.Fetch(chain("elephant-with-holes.off", model=hand))
means = [elephant.GetFieldData().GetArray("SDFGMMMeans").GetValue(i) for i in range(4)]
expected = [mesh.GetFieldData().GetArray("SDFGMMMeans").GetValue(i) for i in range(4)]
if means != expected:
    sys.exit("the Model's mixture was not reused: %r vs %r" % (means, expected))
print("family model reused:", means)
