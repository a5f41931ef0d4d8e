# SPDX-License-Identifier: BSD-3-Clause
"""Bit-identity check between two builds of the filters (e.g. before and after a refactor).

    pvpython Testing/compare-builds.py dump BUILD_DIR OUT.npz MESH.off... [--set Class.Property=value]...
    pvpython Testing/compare-builds.py compare A.npz B.npz                  (exact equality)

`dump` runs reader -> ShapeDiameter -> BilateralSmooth -> GMMPartition -> Skeleton at their
defaults (or with the given --set, e.g. --set vtkShapeDiameterFilter.Mode=1 for Adaptive, or
--set vtkSDFGMMPartition.ClusterModel=0 --set vtkShapeDiameterFilter.HitRule=1) on every mesh
and stores every output array (cell, point, field data, points and connectivity of every
port); `compare` lists every array that differs in any bit.

The family chain (one range and one model for several meshes) lives in Plugin/sdf_pipeline.py:
compare it by running `SHAPEDIAMETER_BUILD_DIR=<build> Plugin/sdf-pipeline --no-setup --no-render
--family --output-dir <dir> MESH...` for each build and `cmp` on the .vtp files written.
"""
import glob
import os
import sys


def split_settings(arguments):
    """(meshes, [(class, property, value)]) from 'MESH... --set Class.Property=value ...'."""
    meshes, settings = [], []
    iterator = iter(arguments)
    for argument in iterator:
        if argument != "--set":
            meshes.append(argument)
            continue
        text = next(iterator, "")
        name, equals, value = text.partition("=")
        klass, dot, prop = name.partition(".")
        if not equals or not dot:
            sys.exit("error: compare-builds: expected --set Class.Property=value, got %r" % text)
        settings.append((klass, prop, float(value) if "." in value else int(value)))
    return meshes, settings


def dump(build, out, arguments):
    meshes, settings = split_settings(arguments)
    sys.path.insert(0, glob.glob(os.path.join(build, "lib", "python3*", "site-packages"))[0])
    import numpy
    from vtkmodules.util.numpy_support import vtk_to_numpy
    import shapediameter as sd

    arrays = {}

    def store(prefix, data):
        if data.GetPoints() is not None and data.GetNumberOfPoints() > 0:
            arrays[prefix + "/points"] = vtk_to_numpy(data.GetPoints().GetData()).copy()
        for kind in ("Verts", "Lines", "Polys", "Strips"):
            cells = getattr(data, "Get" + kind)()
            if cells is not None and cells.GetNumberOfCells() > 0:
                arrays[prefix + "/" + kind] = vtk_to_numpy(cells.GetConnectivityArray()).copy()
        for name, attributes in (("cell", data.GetCellData()), ("point", data.GetPointData()),
                                 ("field", data.GetFieldData())):
            for i in range(attributes.GetNumberOfArrays()):
                array = attributes.GetArray(i)
                if array is not None:
                    arrays["%s/%s/%s" % (prefix, name, array.GetName())] = vtk_to_numpy(array).copy()

    for mesh in meshes:
        key = os.path.basename(mesh)
        reader = sd.vtkSDFOFFReader()
        reader.SetFileName(mesh)
        sdf = sd.vtkShapeDiameterFilter()
        sdf.SetInputConnection(reader.GetOutputPort())
        smooth = sd.vtkSDFBilateralSmooth()
        smooth.SetInputConnection(sdf.GetOutputPort())
        partition = sd.vtkSDFGMMPartition()
        partition.SetInputConnection(smooth.GetOutputPort())
        skeleton = sd.vtkSDFSkeleton()
        skeleton.SetInputConnection(partition.GetOutputPort())
        for klass, prop, value in settings:
            for stage in (sdf, smooth, partition, skeleton):
                if stage.GetClassName() == klass:
                    getattr(stage, "Set" + prop)(value)
        skeleton.Update()
        partition.Update()
        store(key + "/partition", partition.GetOutput())
        for port in range(3):
            store("%s/skeleton%d" % (key, port), skeleton.GetOutput(port))
    numpy.savez(out, **arrays)
    print("%s: %d arrays from %d meshes" % (out, len(arrays), len(meshes)))


def compare(a, b):
    import numpy
    first, second = numpy.load(a), numpy.load(b)
    differ = sorted(set(first.files) ^ set(second.files))
    for name in sorted(set(first.files) & set(second.files)):
        x, y = first[name], second[name]
        if x.shape != y.shape or x.dtype != y.dtype or x.tobytes() != y.tobytes():
            differ.append(name)
    print("%d arrays compared, %d differ" % (len(set(first.files) | set(second.files)), len(differ)))
    for name in differ:
        print("  differs:", name)
    return 1 if differ else 0


if __name__ == "__main__":
    if sys.argv[1] == "dump":
        dump(sys.argv[2], sys.argv[3], sys.argv[4:])
    else:
        sys.exit(compare(sys.argv[2], sys.argv[3]))
