# SPDX-License-Identifier: BSD-3-Clause
"""How smooth the bones of the skeleton are: turning angles and length / chord per bone.

    pvpython Testing/Evaluation/measure_skeleton_smoothness.py MESH... [--peer-mcf PROGRAM]
             [--spacing 0.5] [--expect-p90-at-most DEGREES] [--hit-rule 0|1] [--set ...]

Each MESH (.obj[.gz], .off, .ply, .stl, .vtp; triangulated first) runs through the product
chain at the defaults (ShapeDiameter -> SDFBilateralSmooth -> SDFGMMPartition -> SDFSkeleton).
Printed per mesh, for the skeleton output (port 0), from skeleton_measures.py:

- bones: maximal paths between leaves and junctions;
- turning angle, median and 90th percentile: every bone resampled at --spacing x the local
  radius (the distance from the skeleton to the surface), the angle between consecutive edges
  at the resampled points, the bone's ends left out;
- the same angle at the skeleton's own nodes, not resampled ("as output");
- length / chord per bone: median, 90th percentile and largest.

--peer-mcf PROGRAM adds a row for CGAL's mean-curvature-flow skeleton of the same mesh, from
the optional peer program of Testing/Peers/cgal-mcf (built separately; never part of the
product). --expect-p90-at-most makes it a test (exit status 1 when any mesh's resampled 90th
percentile of ours exceeds it). A MESH that does not exist prints 'SKIP: ...'.

Needs PYTHONPATH to contain build/lib/python3.11/site-packages (the README's pvpython setup).
"""
import argparse
import os
import sys
import tempfile

import chain_settings
import skeleton_measures


def row(name, points, edges, surface, spacing):
    measures = skeleton_measures.smoothness(points, edges, skeleton_measures.surface_distances(surface, points), spacing)
    print("| %s | %d | %.1f° / %.1f° | %.1f° / %.1f° | %.3f / %.3f / %.3f |" % (
        name, measures["bones"], measures["turning_median"], measures["turning_p90"],
        measures["output_median"], measures["output_p90"],
        measures["chord_median"], measures["chord_p90"], measures["chord_max"]), flush=True)
    return measures


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("meshes", nargs="+", metavar="MESH")
    parser.add_argument("--peer-mcf", metavar="PROGRAM", help="Testing/Peers/cgal-mcf's sdf-peer-mcf")
    parser.add_argument("--spacing", type=float, default=0.5, help="resampling step, in local radii (default 0.5)")
    parser.add_argument("--expect-p90-at-most", type=float, default=None, metavar="DEGREES")
    chain_settings.add_arguments(parser)
    arguments = parser.parse_args()
    skeleton_measures.check_peer_program(parser, arguments.peer_mcf)
    print("| mesh | bones | turning angle, median / 90th pct (resampled at %g radii) | as output | length / chord: median / 90th pct / max |" % arguments.spacing)
    print("|---|---:|---:|---:|---:|")
    failed = []
    for path in arguments.meshes:
        if not os.path.exists(path):
            print("SKIP: %s does not exist" % path)
            continue
        name = os.path.basename(path)
        with tempfile.TemporaryDirectory() as scratch:
            surface = skeleton_measures.read_triangles(path, scratch)
            skeleton = skeleton_measures.product_skeleton(surface, arguments).GetSkeleton()
            points, edges = skeleton_measures.graph_of(skeleton)
            ours = row(name, points, edges, surface, arguments.spacing)
            if arguments.expect_p90_at_most is not None and not ours["turning_p90"] <= arguments.expect_p90_at_most:
                failed.append("%s: 90th percentile %.1f° above %.1f°" % (name, ours["turning_p90"], arguments.expect_p90_at_most))
            if arguments.peer_mcf:
                try:
                    points, edges, seconds = skeleton_measures.run_peer_mcf(arguments.peer_mcf, surface, scratch)
                    row("%s, CGAL MCF (%.1f s)" % (name, seconds), points, edges, surface, arguments.spacing)
                except (RuntimeError, ValueError) as error:
                    print("| %s, CGAL MCF | failed: %s | | | |" % (name, error))
    if failed:
        sys.exit("FAIL: " + "; ".join(failed))


if __name__ == "__main__":
    main()
