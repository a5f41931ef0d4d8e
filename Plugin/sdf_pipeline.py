# SPDX-License-Identifier: BSD-3-Clause
"""The ShapeDiameter pipeline command (run through Plugin/sdf-pipeline, in pvpython).

Reads each mesh, runs the stages the plugin provides (SDF, smoothing, partition,
skeleton), writes <name>.vtp, the PNG renderings and <name>_timings.json into
--output-dir. Errors: one line on stderr and a non-zero exit code.
"""
import argparse
import json
import os
import re
import sys
import time

PROG = "sdf-pipeline"
READABLE = (".off", ".ply", ".obj", ".stl", ".vtp", ".vtk")
# Inline (base64) data, not ParaView's default appended data: with Debian 12's current libexpat
# (2.5.0-1+deb12u5, "reparse deferral"; VTK issue 19258) ParaView 5.11's XML reader rejects
# every appended-data file, raw or base64-encoded (measured), so such files open only on
# machines that missed that security update. About a third larger than raw.
XML_WRITER_OPTIONS = {"DataMode": "Binary"}


class PipelineError(Exception):
    """A user-facing error: printed as one line, exit code 1."""


def parse_arguments(argv):
    parser = argparse.ArgumentParser(
        prog=PROG,
        description="Shape Diameter Function pipeline (Shapira, Shamir, Cohen-Or 2008): "
        "SDF, bilateral smoothing, GMM + graph-cut partition, curve skeleton.",
        formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    parser.add_argument("meshes", nargs="+", metavar="MESH",
                        help="input meshes: " + ", ".join(e[1:].upper() for e in READABLE))
    parser.add_argument("--output-dir", default="out", help="where results are written")
    parser.add_argument("--threads", type=int, default=os.cpu_count() or 1,
                        help="worker threads (default: all %(default)s cores)")
    parser.add_argument("--rays", type=int, default=30, help="rays per cone (SDF)")
    parser.add_argument("--cone-angle", type=float, default=120.0, help="cone opening angle in degrees (SDF)")
    parser.add_argument("--hit-rule", type=int, choices=(0, 1), default=argparse.SUPPRESS,
                        help="SDF: 0 = a ray's first hit, dropped unless the ray leaves the object there "
                             "(more pose-consistent); 1 = skip hits on faces turned like the origin's "
                             "(default: the filter's, 0)")
    parser.add_argument("--sdf-mode", choices=("exact", "adaptive"), default="exact",
                        help="SDF: 'exact' = every face casts its cone (the paper); 'adaptive' = a subset "
                             "of faces spaced at half the local SDF casts, refined where neighbours "
                             "disagree, the rest is interpolated (cost follows the shape, not the face "
                             "count; docs/adaptive-sdf.md)")
    parser.add_argument("--sdf-tolerance", type=float, default=argparse.SUPPRESS,
                        help="SDF, adaptive mode: relative difference between neighbouring cast faces "
                             "above which more faces are cast, in [0.001, 1] (default: the filter's, 0.15)")
    parser.add_argument("--cluster-model", choices=("em", "modes"), default=argparse.SUPPRESS,
                        help="partition: 'em' = k Gaussians fitted by EM (the paper), 'modes' = at most k "
                             "clusters from the modes of the SDF density (more pose-consistent) "
                             "(default: the filter's, modes)")
    parser.add_argument("--clusters", default="5", help="number of GMM clusters k, or 'auto'")
    parser.add_argument("--lambda", dest="smoothness", type=float, default=argparse.SUPPRESS,
                        help="graph-cut smoothness weight (default: the filter's, 0.12)")
    parser.add_argument("--samples", type=int, default=10000, help="skeleton surface samples")
    parser.add_argument("--family", action="store_true",
                        help="the meshes are one family: one normalisation range and one model "
                             "fitted on all of them, each partitioned with it")
    parser.add_argument("--plot", action="store_true", help="also write <name>_gmm.png")
    parser.add_argument("--skeleton-colors", choices=("bones", "pieces"), default="bones",
                        help="<name>_skeleton.png: 'bones' = each bone and the faces it serves in one "
                             "colour (default); 'pieces' = fitted segments vs connecting paths")
    parser.add_argument("--no-render", action="store_true", help="skip the PNG renderings")
    parser.add_argument("--quiet", action="store_true", help="print nothing but errors")
    # Read by the Plugin/sdf-pipeline wrapper before pvpython starts; listed here for --help.
    parser.add_argument("--no-setup", action="store_true",
                        help="skip the package check/installation and the build: run with the plugin "
                             "of the existing build directory ($SHAPEDIAMETER_BUILD_DIR, default build/)")
    arguments = parser.parse_args(argv)
    if arguments.threads < 1:
        parser.error("--threads must be >= 1")
    if arguments.rays < 1:
        parser.error("--rays must be >= 1")
    if not 0.0 < arguments.cone_angle < 180.0:
        parser.error("--cone-angle must be in (0, 180)")
    if hasattr(arguments, "sdf_tolerance") and not 0.001 <= arguments.sdf_tolerance <= 1.0:
        parser.error("--sdf-tolerance must be in [0.001, 1]")
    return arguments


def check_inputs(meshes):
    for mesh in meshes:
        if not os.path.isfile(mesh):
            raise PipelineError("no such file: %s" % mesh)
        if not os.access(mesh, os.R_OK):
            raise PipelineError("cannot read file: %s" % mesh)
        if os.path.splitext(mesh)[1].lower() not in READABLE:
            raise PipelineError("unsupported format: %s (expected %s)" % (mesh, ", ".join(READABLE)))


class VTKMessages:
    """Collects VTK's error/warning text so a failure becomes one line, not a dump.

    pvpython routes sys.stdout/sys.stderr through VTK's output window too, so this
    script writes to sys.__stdout__/sys.__stderr__ once the window is replaced."""

    def __init__(self):
        from vtkmodules.vtkCommonCore import vtkLogger, vtkOutputWindow, vtkStringOutputWindow
        # vtkErrorMacro also logs through vtkLogger straight to stderr: silence that copy.
        vtkLogger.SetStderrVerbosity(vtkLogger.VERBOSITY_OFF)
        self.window = vtkStringOutputWindow()
        vtkOutputWindow.SetInstance(self.window)
        self.consumed = 0

    def take(self):
        """The text logged since the previous call."""
        text = self.window.GetOutput() or ""
        new, self.consumed = text[self.consumed:], len(text)
        return new

    def last_error(self):
        lines = [line.strip() for line in self.take().splitlines() if line.strip()]
        for line in reversed(lines):
            if "Cannot read" in line or "rror" in line:
                return re.sub(r"^\w+ \(0x[0-9a-fA-F]+\): ", "", line)
        return lines[-1] if lines else "unknown error"


def frame_camera(view, source):
    """Looks along the thinnest extent of the bounding box, so the silhouette is largest."""
    bounds = source.GetDataInformation().GetBounds()
    extents = [bounds[2 * i + 1] - bounds[2 * i] for i in range(3)]
    thinnest = min(range(3), key=lambda i: extents[i])
    center = [(bounds[2 * i] + bounds[2 * i + 1]) / 2 for i in range(3)]
    direction = [0.0, 0.0, 0.0]
    direction[thinnest] = 1.0
    up = [0.0, 1.0, 0.0] if thinnest != 1 else [0.0, 0.0, 1.0]
    view.CameraFocalPoint = center
    view.CameraPosition = [c + d for c, d in zip(center, direction)]
    view.CameraViewUp = up
    view.ResetCamera()


def cluster_palette(simple):
    """The RGB triples of the plugin's categorical SDFCluster colour map (16 colours), the
    colours of the parts picture; other label pictures cycle through them."""
    colours = list(simple.GetColorTransferFunction("SDFCluster").IndexedColors)
    return [colours[i:i + 3] for i in range(0, len(colours) - 2, 3)]


def cluster_model(data):
    """(means, weights) of the partition's clusters from its field data (SDFGMMMeans/Weights)."""
    field = data.GetFieldData()
    count = int(field.GetArray("SDFClusterCount").GetValue(0))
    return tuple([field.GetArray(key).GetValue(c) for c in range(count)]
                 for key in ("SDFGMMMeans", "SDFGMMWeights"))


def show_cluster_chart(simple, partition, view, means, weights):
    """The paper's Fig. 7 in a ParaView line chart `view`: the histogram of SDFNormalized
    (output port 1 of the partition) with the fitted Gaussians. Component c is drawn in the
    colour of cluster c in the parts picture (the plugin's SDFCluster colour map) and labelled
    like its legend, with its mean and weight; the x axis is nsdf's [0, 1]. Used by the
    pipeline command's --plot and by the GUI test's window; returns the chart's display."""
    clusters = len(means)
    view.ChartTitle = "Clusters of the normalised SDF (k = %d)" % clusters
    view.LeftAxisTitle = "density (faces)"
    view.BottomAxisTitle = "SDFNormalized"
    view.BottomAxisUseCustomRange = 1
    view.BottomAxisRangeMinimum = 0.0
    view.BottomAxisRangeMaximum = 1.0
    chart = simple.Show(simple.OutputPort(partition, 1), view)
    chart.UseIndexForXAxis = 0
    chart.XArrayName = "BinCenter"
    components = ["Component%d" % c for c in range(clusters)]
    curves = ["Density", "Mixture"] + components
    chart.SeriesVisibility = curves
    labels = {"Density": "histogram", "Mixture": "mixture"}
    labels.update({name: "cluster %d (mean %.2f, weight %.2f)" % (c, means[c], weights[c])
                   for c, name in enumerate(components)})
    chart.SeriesLabel = sum([[c, labels[c]] for c in curves], [])
    chart.SeriesLineThickness = sum([[c, "4" if c == "Density" else "3"] for c in curves], [])
    chart.SeriesLineStyle = sum([[c, "2" if c == "Mixture" else "1"] for c in curves], [])
    palette = cluster_palette(simple)
    series_colours = ["Density", "0.72", "0.72", "0.72", "Mixture", "0", "0", "0"]
    for c, name in enumerate(components):
        series_colours += [name] + ["%.6f" % value for value in palette[c % len(palette)]]
    chart.SeriesColor = series_colours
    return chart


class Pipeline:
    def __init__(self, arguments):
        self.arguments = arguments
        from paraview import simple
        self.simple = simple
        # After paraview.simple: it installs its own output window on import.
        self.messages = VTKMessages()
        plugin = os.environ.get("SHAPEDIAMETER_PLUGIN", "")
        if not os.path.isfile(plugin):
            raise PipelineError("plugin not found: %r (set SHAPEDIAMETER_PLUGIN)" % plugin)
        simple.LoadPlugin(plugin, ns=vars(simple))
        from vtkmodules.vtkCommonCore import vtkSMPTools
        vtkSMPTools.SetBackend("STDThread")
        vtkSMPTools.Initialize(arguments.threads)

    def has(self, proxy_name):
        return hasattr(self.simple, proxy_name)

    def log(self, text):
        if not self.arguments.quiet:
            print(text, file=sys.__stdout__, flush=True)

    def timed(self, timings, key, function):
        start = time.perf_counter()
        result = function()
        timings[key] = round(time.perf_counter() - start, 6)
        return result

    def show_progress(self, proxy, stage):
        """A live per-stage progress line on a terminal's stderr, from the filter's own
        progress events (nothing with --quiet or when stderr is not a terminal)."""
        if self.arguments.quiet or not sys.__stderr__.isatty():
            return
        algorithm = proxy.GetClientSideObject()
        shown = [-1]

        def report(caller, event):
            percent = int(100 * caller.GetProgress())
            if percent != shown[0] and (percent - shown[0] >= 5 or percent == 100):
                shown[0] = percent
                end = "\n" if percent == 100 else ""
                print("\r%-10s %3d%%" % (stage, percent), end=end, file=sys.__stderr__, flush=True)

        algorithm.AddObserver("ProgressEvent", report)

    def read(self, path):
        simple = self.simple
        if path.lower().endswith(".off"):
            source = simple.SDFOFFReader(FileName=path)
        else:
            source = simple.OpenDataFile(path)
            if source is None:
                raise PipelineError("cannot open %s" % path)
        source.UpdatePipeline()
        data = simple.servermanager.Fetch(source)
        if data is None or data.GetNumberOfCells() == 0:
            raise PipelineError("cannot read %s: %s" % (path, self.messages.last_error()))
        if not data.IsA("vtkPolyData"):
            source = simple.ExtractSurface(Input=source)
        return source

    def surface_stages(self, source, timings):
        """SDF and smoothing, when the plugin provides them; skipped stages leave no key."""
        arguments = self.arguments
        current = source
        if self.has("ShapeDiameter"):
            current = self.simple.ShapeDiameter(Input=current, NumberOfRays=arguments.rays,
                                                ConeAngle=arguments.cone_angle,
                                                NumberOfThreads=arguments.threads)
            if hasattr(arguments, "hit_rule"):
                current.HitRule = arguments.hit_rule
            current.Mode = 1 if arguments.sdf_mode == "adaptive" else 0
            if hasattr(arguments, "sdf_tolerance"):
                current.Tolerance = arguments.sdf_tolerance
            self.show_progress(current, "sdf")
            self.timed(timings, "sdf", current.UpdatePipeline)
        if self.has("SDFBilateralSmooth"):
            current = self.simple.SDFBilateralSmooth(Input=current, NumberOfThreads=arguments.threads,
                                                     SDFArray=["CELLS", "SDF"])
            self.show_progress(current, "smooth")
            self.timed(timings, "smooth", current.UpdatePipeline)
        return current

    def partition(self, source, model=None):
        arguments = self.arguments
        clusters = 0 if arguments.clusters == "auto" else int(arguments.clusters)
        # The array is named explicitly: ParaView's default for an array selection depends on
        # what the session saw before, not only on this input.
        properties = dict(Input=source, NumberOfClusters=clusters, NumberOfThreads=arguments.threads,
                          NormalizedSDFArray=["CELLS", "SDFNormalized"])
        if hasattr(arguments, "smoothness"):
            properties["Lambda"] = arguments.smoothness
        if hasattr(arguments, "cluster_model"):
            properties["ClusterModel"] = 1 if arguments.cluster_model == "modes" else 0
        if model is not None:
            properties["Model"] = model
        partition = self.simple.SDFGMMPartition(**properties)
        self.show_progress(partition, "partition")
        partition.UpdatePipeline()
        return partition

    def render(self, source, png, color_array):
        simple = self.simple
        view = self.new_view()
        display = simple.Show(source, view)
        if color_array:
            simple.ColorBy(display, ("CELLS", color_array))
            display.RescaleTransferFunctionToDataRange(True, False)
            display.SetScalarBarVisibility(view, True)
            bar = simple.GetScalarBar(simple.GetColorTransferFunction(color_array), view)
            bar.TitleColor = [0, 0, 0]
            bar.LabelColor = [0, 0, 0]
        else:
            display.DiffuseColor = [0.75, 0.75, 0.8]
        frame_camera(view, source)
        simple.SaveScreenshot(png, view, ImageResolution=[1024, 768])
        simple.Delete(display)
        simple.Delete(view)

    def render_parts(self, source, png):
        """Clusters in categorical colours, unlit (flat colours identify parts exactly)."""
        simple = self.simple
        view = self.new_view()
        display = simple.Show(source, view)
        simple.ColorBy(display, ("CELLS", "SDFCluster"))
        # The plugin's default colour map for SDFCluster is categorical (ShapeDiameterColorDefaults).
        lut = simple.GetColorTransferFunction("SDFCluster")
        display.Ambient = 1.0
        display.Diffuse = 0.0
        display.SetScalarBarVisibility(view, True)
        bar = simple.GetScalarBar(lut, view)
        bar.Title = "SDFCluster"
        bar.TitleColor = [0, 0, 0]
        bar.LabelColor = [0, 0, 0]
        frame_camera(view, source)
        simple.SaveScreenshot(png, view, ImageResolution=[1024, 768])
        simple.Delete(display)
        simple.Delete(view)

    def new_view(self):
        view = self.simple.CreateRenderView()
        view.ViewSize = [1024, 768]
        view.OrientationAxesVisibility = 0
        view.Background = [1.0, 1.0, 1.0]
        try:
            view.UseColorPaletteForBackground = 0
        except AttributeError:
            pass
        return view

    def skeleton(self, source):
        skeleton = self.simple.SDFSkeleton(Input=source, NumberOfSamples=self.arguments.samples,
                                           NumberOfThreads=self.arguments.threads,
                                           SDFArray=["CELLS", "SDFSmoothed"])
        self.show_progress(skeleton, "skeleton")
        skeleton.UpdatePipeline()
        return skeleton

    def render_histogram(self, partition, png, means, weights):
        """The paper's Fig. 7 as a PNG (see show_cluster_chart)."""
        simple = self.simple
        view = simple.CreateView("XYChartView")
        view.ViewSize = [1024, 600]
        chart = show_cluster_chart(simple, partition, view, means, weights)
        simple.SaveScreenshot(png, view, ImageResolution=[1024, 600])
        simple.Delete(chart)
        simple.Delete(view)

    def render_skeleton(self, surface, skeleton, png):
        """The skeleton as tubes over a translucent surface. By bone (default): each bone in a
        categorical colour and every face tinted with the colour of its bone (SkeletonBoneId),
        so one sees which bone serves which part; "--skeleton-colors pieces": fitted segments
        vs connecting paths over a grey surface."""
        simple = self.simple
        by_bone = self.arguments.skeleton_colors == "bones"
        view = self.new_view()
        shell = simple.Show(simple.OutputPort(skeleton, 1) if by_bone else surface, view)
        shell.Opacity = 0.3 if by_bone else 0.25
        tubes = simple.Tube(Input=simple.OutputPort(skeleton, 0))
        bounds = surface.GetDataInformation().GetBounds()
        diagonal = sum((bounds[2 * i + 1] - bounds[2 * i]) ** 2 for i in range(3)) ** 0.5
        tubes.Radius = 0.004 * diagonal
        tubes.NumberofSides = 12
        bones = simple.Show(tubes, view)
        if by_bone:
            palette = cluster_palette(self.simple)
            count = int(tubes.CellData["BoneId"].GetRange(0)[1]) + 1
            for display, array in ((bones, "BoneId"), (shell, "SkeletonBoneId")):
                simple.ColorBy(display, ("CELLS", array))
                lut = simple.GetColorTransferFunction(array)
                lut.InterpretValuesAsCategories = 1
                lut.Annotations = sum([[str(b), "bone %d" % b] for b in range(count)], [])
                lut.IndexedColors = sum([palette[b % len(palette)] for b in range(count)], [])
            shell.Ambient = 0.6
            shell.Diffuse = 0.4
            legend = simple.GetColorTransferFunction("BoneId")
        else:
            simple.ColorBy(shell, None)
            shell.DiffuseColor = [0.75, 0.75, 0.8]
            simple.ColorBy(bones, ("CELLS", "IsConnection"))
            legend = simple.GetColorTransferFunction("IsConnection")
            legend.InterpretValuesAsCategories = 1
            legend.Annotations = ["0", "fitted segment", "1", "connection"]
            legend.IndexedColors = [0.85, 0.1, 0.1, 0.1, 0.3, 0.9]
        bones.SetScalarBarVisibility(view, True)
        bar = simple.GetScalarBar(legend, view)
        bar.Title = "BoneId" if by_bone else "Skeleton"
        bar.TitleColor = [0, 0, 0]
        bar.LabelColor = [0, 0, 0]
        frame_camera(view, surface)
        simple.SaveScreenshot(png, view, ImageResolution=[1024, 768])
        for proxy in (bones, shell, tubes, view):
            simple.Delete(proxy)

    def prepare(self, path):
        """Reads one mesh and runs the per-mesh stages before the partition."""
        mesh = {"path": path, "name": os.path.splitext(os.path.basename(path))[0],
                "timings": {}, "start": time.perf_counter()}
        source = self.timed(mesh["timings"], "read", lambda: self.read(path))
        mesh["surface"] = self.surface_stages(source, mesh["timings"])
        return mesh

    def share_normalization(self, meshes):
        """One nsdf range for the family: the widest of the members' SDFNormalizationRange."""
        ranges = []
        for mesh in meshes:
            info = mesh["surface"].FieldData["SDFNormalizationRange"]
            if info is None:
                raise PipelineError("smoothing %s gave no SDFNormalizationRange: %s" % (
                    mesh["path"], self.messages.last_error()))
            ranges.append(info.GetRange(0))  # two tuples, min and max: their range is [min, max]
        shared = [min(r[0] for r in ranges), max(r[1] for r in ranges)]
        self.log("family normalisation range of SDFSmoothed: [%.6g, %.6g]" % tuple(shared))
        for mesh in meshes:
            mesh["surface"].NormalizationRange = shared
            self.timed(mesh["timings"], "family_normalization", mesh["surface"].UpdatePipeline)

    def run(self, paths):
        meshes = [self.prepare(path) for path in paths]
        model = None
        if self.has("SDFBilateralSmooth") and self.arguments.family and len(meshes) > 1:
            self.share_normalization(meshes)
        if self.has("SDFGMMPartition") and self.arguments.family and len(meshes) > 1:
            # One mixture for the whole family: fitted on all faces of all meshes together.
            start = time.perf_counter()
            family = self.simple.AppendGeometry(Input=[mesh["surface"] for mesh in meshes])
            model = self.partition(family)
            shared = time.perf_counter() - start
            for mesh in meshes:
                mesh["timings"]["family_model"] = round(shared, 6)
        for mesh in meshes:
            result = mesh["surface"]
            if self.has("SDFGMMPartition"):
                result = self.timed(mesh["timings"], "partition", lambda: self.partition(result, model))
            skeleton = None
            if self.has("SDFSkeleton"):
                skeleton = self.timed(mesh["timings"], "skeleton", lambda: self.skeleton(result))
            self.finish(mesh, result, skeleton)

    def finish(self, mesh, result, skeleton=None):
        arguments = self.arguments
        name, timings, out = mesh["name"], mesh["timings"], arguments.output_dir
        data = self.simple.servermanager.Fetch(result)
        if data is None or data.GetNumberOfCells() == 0:
            raise PipelineError("processing %s failed: %s" % (mesh["path"], self.messages.last_error()))
        cells = data.GetCellData()

        def write():
            self.simple.SaveData(os.path.join(out, name + ".vtp"), proxy=result, **XML_WRITER_OPTIONS)
            if skeleton is not None:
                self.simple.SaveData(os.path.join(out, name + "_skeleton.vtp"),
                                     proxy=self.simple.OutputPort(skeleton, 0), **XML_WRITER_OPTIONS)
            segments = cells.GetArray("SDFSegment")
            if segments is not None:
                with open(os.path.join(out, name + ".seg"), "w") as stream:
                    stream.write("".join("%d\n" % segments.GetValue(i) for i in range(segments.GetNumberOfTuples())))

        self.timed(timings, "write", write)
        if not arguments.no_render:
            def render():
                sdf = "SDF" if cells.GetArray("SDF") is not None else None
                self.render(result, os.path.join(out, name + "_sdf.png"), sdf)
                if cells.GetArray("SDFCluster") is not None:
                    means, weights = cluster_model(data)
                    self.render_parts(result, os.path.join(out, name + "_parts.png"))
                    if arguments.plot:
                        self.render_histogram(result, os.path.join(out, name + "_gmm.png"), means, weights)
                if skeleton is not None:
                    self.render_skeleton(result, skeleton, os.path.join(out, name + "_skeleton.png"))
            self.timed(timings, "render", render)
        timings["total"] = round(time.perf_counter() - mesh["start"], 6)
        with open(os.path.join(out, name + "_timings.json"), "w") as stream:
            json.dump(timings, stream, indent=2, sort_keys=True)
            stream.write("\n")
        self.log("%s: %d faces -> %s  (%s)" % (
            name, data.GetNumberOfCells(), os.path.join(out, name + ".vtp"),
            ", ".join("%s %.3fs" % item for item in sorted(timings.items()))))


def main(argv):
    arguments = parse_arguments(argv)
    try:
        check_inputs(arguments.meshes)
        os.makedirs(arguments.output_dir, exist_ok=True)
        Pipeline(arguments).run(arguments.meshes)
    except PipelineError as error:
        print("%s: error: %s" % (PROG, error), file=sys.__stderr__, flush=True)
        return 1
    except Exception as error:  # never a traceback for the user
        print("%s: error: %s: %s" % (PROG, type(error).__name__, error), file=sys.__stderr__, flush=True)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
