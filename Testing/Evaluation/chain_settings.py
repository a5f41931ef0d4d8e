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
    """--hit-rule, --cluster-model, --clusters, --lambda; None = the filter's default."""
    parser.add_argument("--hit-rule", type=int, default=None, help="vtkShapeDiameterFilter HitRule (default: the filter's)")
    parser.add_argument("--cluster-model", type=int, default=None, help="vtkSDFGMMPartition ClusterModel (0 EM, 1 modes)")
    parser.add_argument("--clusters", type=int, default=None, help="NumberOfClusters (default: the filter's)")
    parser.add_argument("--lambda", dest="smoothness", type=float, default=None, help="Lambda (default: the filter's)")


def shape_diameter(arguments):
    sdf = shapediameter.vtkShapeDiameterFilter()
    if arguments.hit_rule is not None:
        sdf.SetHitRule(arguments.hit_rule)
    return sdf


def partition(arguments):
    parts = shapediameter.vtkSDFGMMPartition()
    if arguments.cluster_model is not None:
        parts.SetClusterModel(arguments.cluster_model)
    if arguments.clusters is not None:
        parts.SetNumberOfClusters(arguments.clusters)
    if arguments.smoothness is not None:
        parts.SetLambda(arguments.smoothness)
    return parts
