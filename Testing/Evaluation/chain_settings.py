# SPDX-License-Identifier: BSD-3-Clause
"""What the evaluation scripts share: the mesh readers, the chain settings they expose, skeleton edges."""
import gzip
import os

import shapediameter
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOGeometry import vtkOBJReader, vtkSTLReader
from vtkmodules.vtkIOPLY import vtkPLYReader
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

READERS = {".obj": vtkOBJReader, ".off": shapediameter.vtkSDFOFFReader, ".ply": vtkPLYReader,
           ".stl": vtkSTLReader, ".vtp": vtkXMLPolyDataReader}


def read_mesh(path, scratch):
    """The polydata of a mesh file in READERS' formats, optionally gzipped (unpacked into scratch)."""
    if path.endswith(".gz"):
        unpacked = os.path.join(scratch, os.path.basename(path)[:-3])
        with gzip.open(path, "rb") as source, open(unpacked, "wb") as target:
            target.write(source.read())
        path = unpacked
    reader = READERS[os.path.splitext(path)[1].lower()]()
    reader.SetFileName(path)
    reader.Update()
    return reader.GetOutput()


def skeleton_edges(skeleton):
    """(a, b) node ids of every pair of consecutive nodes along the skeleton's polylines."""
    lines = skeleton.GetLines()
    if lines.GetNumberOfCells() == 0:
        return []
    ids = vtk_to_numpy(lines.GetConnectivityArray())
    offsets = vtk_to_numpy(lines.GetOffsetsArray())
    return [(int(a), int(b)) for c in range(len(offsets) - 1)
            for a, b in zip(ids[offsets[c]:offsets[c + 1] - 1], ids[offsets[c] + 1:offsets[c + 1]])]


def add_arguments(parser):
    """--hit-rule, --cluster-model, --clusters, --lambda (None = the filter's default) and --set."""
    parser.add_argument("--hit-rule", type=int, default=None, help="vtkShapeDiameterFilter HitRule (default: the filter's)")
    parser.add_argument("--cluster-model", type=int, default=None, help="vtkSDFGMMPartition ClusterModel (0 EM, 1 modes)")
    parser.add_argument("--clusters", type=int, default=None, help="NumberOfClusters (default: the filter's)")
    parser.add_argument("--lambda", dest="smoothness", type=float, default=None, help="Lambda (default: the filter's)")
    parser.add_argument("--set", dest="settings", action="append", default=[], type=parse_setting,
                        metavar="Class.Property=value",
                        help="call Set<Property>(value) on every filter of that class, after the options above "
                             "(value: int, float or text; 'a,b' passes two arguments); repeatable, e.g. "
                             "--set vtkSDFGMMPartition.ModeProminence=0.05")


# The classes --set may name: the chain's filters.
SETTABLE = ("vtkShapeDiameterFilter", "vtkSDFBilateralSmooth", "vtkSDFGMMPartition", "vtkSDFSkeleton")


def parse_value(text):
    """int, else float, else the text itself."""
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


def parse_setting(text):
    """'Class.Property=value' -> (class, property, [values]); argparse reports a ValueError-free error."""
    import argparse
    name, equals, value = text.partition("=")
    klass, dot, prop = name.strip().partition(".")
    if not equals or not dot or not klass or not prop or not value.strip():
        raise argparse.ArgumentTypeError("expected Class.Property=value, got %r" % text)
    if klass not in SETTABLE:
        raise argparse.ArgumentTypeError("%s: the class is not one of %s" % (text, ", ".join(SETTABLE)))
    if not hasattr(getattr(shapediameter, klass), "Set" + prop):
        raise argparse.ArgumentTypeError("%s: %s has no Set%s" % (text, klass, prop))
    return klass, prop, [parse_value(v.strip()) for v in value.split(",")]


def apply_settings(algorithm, arguments):
    """Calls the --set settings that name algorithm's class on it; a value the filter clamped or
    rejected is an error (SystemExit with the reason), not a silent change of the experiment."""
    klass = algorithm.GetClassName()
    for name, prop, values in getattr(arguments, "settings", None) or []:
        if name != klass:
            continue
        try:
            getattr(algorithm, "Set" + prop)(*values)
        except TypeError as error:
            raise SystemExit("--set %s.%s: %s" % (name, prop, error))
        getter = getattr(algorithm, "Get" + prop, None)
        if getter is not None and len(values) == 1 and isinstance(values[0], (int, float)):
            now = getter()
            if isinstance(now, (int, float)) and now != values[0]:
                raise SystemExit("--set %s.%s=%s: the filter holds %s (out of its range?)" % (name, prop, values[0], now))
    return algorithm


def shape_diameter(arguments):
    sdf = shapediameter.vtkShapeDiameterFilter()
    if arguments.hit_rule is not None:
        sdf.SetHitRule(arguments.hit_rule)
    return apply_settings(sdf, arguments)


def smoothing(arguments):
    return apply_settings(shapediameter.vtkSDFBilateralSmooth(), arguments)


def partition(arguments):
    parts = shapediameter.vtkSDFGMMPartition()
    if arguments.cluster_model is not None:
        parts.SetClusterModel(arguments.cluster_model)
    if arguments.clusters is not None:
        parts.SetNumberOfClusters(arguments.clusters)
    if arguments.smoothness is not None:
        parts.SetLambda(arguments.smoothness)
    return apply_settings(parts, arguments)


def skeleton(arguments):
    return apply_settings(shapediameter.vtkSDFSkeleton(), arguments)
