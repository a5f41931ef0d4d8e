# SPDX-License-Identifier: BSD-3-Clause
"""Skeleton against an artist's rig: how much of every rig bone has a skeleton branch nearby.

    pvpython Testing/Evaluation/measure_rig_recall.py MESH RIG.tgf [--samples-per-bone 21]
             [--tolerance 0.05] [--peer-mcf PROGRAM] [--expect-recall PERCENT]
             [--expect-leaves N] [--seeds 1,2,3 [--expect-seed-mean-recall PERCENT]]
             [--hit-rule 0|1] [--set Class.Property=value ...]

MESH (.obj, .obj.gz, .off, .ply, .stl, .vtp) runs through the product chain at the defaults
(ShapeDiameter -> SDFBilateralSmooth -> SDFGMMPartition -> SDFSkeleton; --set changes a
filter's property). RIG.tgf (Trivial Graph Format: "index x y z" joint lines, a '#' line, then
"a b" bone lines, a second '#' optional) is in the mesh's coordinates. Printed:

- recall: along every rig bone, samples evenly spaced (both ends included); a sample is
  recalled when its distance to the nearest skeleton edge (or node, for a single-node
  skeleton) is at most tolerance x the mesh's bounding-box diagonal; recall = recalled
  samples / all samples;
- leaves reached: rig joints of degree 1 whose position is within the same distance;
- per bone: its recall and the largest distance (as a share of the diagonal).

A rig is not a medial axis (joints sit where an animator wants them), but every limb of the
rig should have a branch near it. --peer-mcf PROGRAM adds the same figures for CGAL's
mean-curvature-flow skeleton of the mesh (the optional peer program of Testing/Peers/cgal-mcf,
built separately; never part of the product). --expect-recall / --expect-leaves make it a
test of ours (exit status 1 below either).

--seeds S1,S2,...: the skeleton again with each sampling seed (vtkSDFSkeleton's Seed; the chain
before it is not re-run), one line per seed and the mean, lowest and highest recall and the
fewest leaves reached. The skeleton's branches change with the seed about as much as with the
pose (the cheburashka at seeds 1-6: 84.0-92.2 %, 4 or 5 of 5 leaves), so one seed's figure is
one draw; --expect-seed-mean-recall makes the mean a test (a change cannot pass on one lucky
seed). A MESH or RIG that does not exist prints
'SKIP: ...' and exits 0.

Needs PYTHONPATH to contain build/lib/python3.11/site-packages (the README's pvpython setup).
"""
import argparse
import os
import sys
import tempfile

import numpy as np


import chain_settings
import skeleton_measures


def read_tgf(path):
    """Joints {index: xyz} and bones [(a, b)] of a TGF file; raises ValueError when malformed."""
    joints, bones, section = {}, [], 0
    with open(path) as text:
        for number, line in enumerate(text, 1):
            fields = line.split()
            if not fields:
                continue
            if fields[0] == "#":
                section += 1
                continue
            if section == 0:
                if len(fields) < 4:
                    raise ValueError("%s:%d: a joint needs 'index x y z'" % (path, number))
                joints[int(fields[0])] = np.array([float(v) for v in fields[1:4]])
            elif section == 1:
                if len(fields) < 2:
                    raise ValueError("%s:%d: a bone needs two joint indices" % (path, number))
                a, b = int(fields[0]), int(fields[1])
                if a not in joints or b not in joints:
                    raise ValueError("%s:%d: bone %d-%d names an unknown joint" % (path, number, a, b))
                bones.append((a, b))
    if not bones:
        raise ValueError("%s: no bones" % path)
    return joints, bones


def distances_to_segments(points, starts, ends):
    """Distance of every point to the nearest of the segments [starts[i], ends[i]]."""
    best = np.full(len(points), np.inf)
    direction = ends - starts
    length2 = np.maximum((direction ** 2).sum(axis=1), 1e-300)
    for chunk in range(0, len(starts), 4096):
        s, d, l2 = starts[chunk:chunk + 4096], direction[chunk:chunk + 4096], length2[chunk:chunk + 4096]
        t = np.clip(((points[:, None, :] - s[None]) * d[None]).sum(axis=2) / l2[None], 0.0, 1.0)
        nearest = s[None] + t[..., None] * d[None]
        best = np.minimum(best, np.sqrt(((points[:, None, :] - nearest) ** 2).sum(axis=2)).min(axis=1))
    return best


def skeleton_segments(points, edges):
    """Start and end points of every skeleton edge (no edges: every node as a zero-length segment)."""
    if len(edges) == 0:
        return points.copy(), points.copy()
    return points[edges[:, 0]], points[edges[:, 1]]


def rig_recall(points, edges, joints, bones, diagonal, samples_per_bone=21, tolerance=0.05):
    """(recall, leaves reached, leaf count, per-bone rows) of a skeleton graph against a rig."""
    starts, ends = skeleton_segments(points, edges)
    if len(starts) == 0:
        return 0.0, 0, 0, []
    limit = tolerance * diagonal
    rows, recalled, total = [], 0, 0
    for a, b in bones:
        t = np.linspace(0.0, 1.0, samples_per_bone)[:, None]
        samples = joints[a][None] * (1 - t) + joints[b][None] * t
        distance = distances_to_segments(samples, starts, ends)
        hits = int((distance <= limit).sum())
        recalled += hits
        total += len(samples)
        rows.append((a, b, hits / len(samples), distance.max() / diagonal))
    degree = {}
    for a, b in bones:
        degree[a] = degree.get(a, 0) + 1
        degree[b] = degree.get(b, 0) + 1
    leaves = [j for j, d in degree.items() if d == 1]
    leaf_distance = distances_to_segments(np.array([joints[j] for j in leaves]), starts, ends)
    reached = int((leaf_distance <= limit).sum())
    return recalled / total, reached, len(leaves), rows


def report(name, points, edges, joints, bones, diagonal, arguments):
    """Prints the per-bone rows and the summary line of one skeleton; returns (recall, reached)."""
    recall, reached, leaves, rows = rig_recall(points, edges, joints, bones, diagonal,
                                               arguments.samples_per_bone, arguments.tolerance)
    print("%s: skeleton %d nodes, %d bones" % (name, len(points), len(skeleton_measures.bone_paths(len(points), edges))))
    for a, b, share, worst in rows:
        print("  rig bone %d-%d: recall %5.1f %%, farthest sample %.3f of the diagonal" % (a, b, 100 * share, worst))
    print("%s recall@%g %%: %.1f %%, leaves reached: %d of %d" % (name, 100 * arguments.tolerance, 100 * recall, reached, leaves))
    return recall, reached


def seed_list(text):
    """'1,2,3' -> [1, 2, 3] (argparse type)."""
    try:
        seeds = [int(field) for field in text.split(",")]
    except ValueError:
        raise argparse.ArgumentTypeError("expected comma-separated integers, got %r" % text)
    return seeds


def seed_recalls(skeleton, joints, bones, diagonal, arguments):
    """Runs `skeleton` (updated) again with each of arguments.seeds, prints a line per seed and
    the summary; returns the mean recall. The filter keeps the last seed."""
    recalls, reached_counts, leaves = [], [], 0
    for seed in arguments.seeds:
        skeleton.SetSeed(seed)
        if skeleton.GetSeed() != seed:
            sys.exit("--seeds: the filter holds seed %d, not %d" % (skeleton.GetSeed(), seed))
        skeleton.Update()
        points, edges = skeleton_measures.graph_of(skeleton.GetSkeleton())
        recall, reached, leaves, _ = rig_recall(points, edges, joints, bones, diagonal,
                                                arguments.samples_per_bone, arguments.tolerance)
        recalls.append(recall)
        reached_counts.append(reached)
        print("ours, seed %d: recall %.1f %%, leaves reached: %d of %d" % (seed, 100 * recall, reached, leaves))
    mean = float(np.mean(recalls))
    print("ours over seeds %s: recall mean %.1f %% (%.1f-%.1f %%), leaves reached: at least %d of %d" % (
        ",".join(map(str, arguments.seeds)), 100 * mean, 100 * min(recalls), 100 * max(recalls),
        min(reached_counts), leaves))
    return mean


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("mesh")
    parser.add_argument("rig")
    parser.add_argument("--samples-per-bone", type=int, default=21)
    parser.add_argument("--tolerance", type=float, default=0.05, help="share of the bounding-box diagonal")
    parser.add_argument("--peer-mcf", metavar="PROGRAM", help="Testing/Peers/cgal-mcf's sdf-peer-mcf")
    parser.add_argument("--expect-recall", type=float, default=None, metavar="PERCENT")
    parser.add_argument("--expect-leaves", type=int, default=None, metavar="N")
    parser.add_argument("--seeds", type=seed_list, default=[], metavar="S1,S2,...",
                        help="also run the skeleton with each of these sampling seeds")
    parser.add_argument("--expect-seed-mean-recall", type=float, default=None, metavar="PERCENT",
                        help="the mean recall over --seeds at least this")
    chain_settings.add_arguments(parser)
    arguments = parser.parse_args()
    skeleton_measures.check_peer_program(parser, arguments.peer_mcf)
    if arguments.expect_seed_mean_recall is not None and not arguments.seeds:
        parser.error("--expect-seed-mean-recall needs --seeds")
    for path in (arguments.mesh, arguments.rig):
        if not os.path.exists(path):
            print("SKIP: %s does not exist (the shared development data is not on this machine)" % path)
            return
    joints, bones = read_tgf(arguments.rig)
    with tempfile.TemporaryDirectory() as scratch:
        surface = skeleton_measures.read_triangles(arguments.mesh, scratch)
        bounds = np.array(surface.GetBounds()).reshape(3, 2)
        diagonal = float(np.linalg.norm(bounds[:, 1] - bounds[:, 0]))
        print("%s: %d faces" % (os.path.basename(arguments.mesh), surface.GetNumberOfCells()))
        skeleton = skeleton_measures.product_skeleton(surface, arguments)
        points, edges = skeleton_measures.graph_of(skeleton.GetSkeleton())
        recall, reached = report("ours", points, edges, joints, bones, diagonal, arguments)
        seed_mean = seed_recalls(skeleton, joints, bones, diagonal, arguments) if arguments.seeds else None
        if arguments.peer_mcf:
            try:
                peer_points, peer_edges, seconds = skeleton_measures.run_peer_mcf(arguments.peer_mcf, surface, scratch)
                report("CGAL MCF (%.1f s)" % seconds, peer_points, peer_edges, joints, bones, diagonal, arguments)
            except (RuntimeError, ValueError) as error:
                print("CGAL MCF: failed: %s" % error)
    failed = []
    if arguments.expect_recall is not None and not 100 * recall >= arguments.expect_recall:
        failed.append("recall %.1f %% below %.1f %%" % (100 * recall, arguments.expect_recall))
    if arguments.expect_leaves is not None and reached < arguments.expect_leaves:
        failed.append("%d leaves reached, fewer than %d" % (reached, arguments.expect_leaves))
    if arguments.expect_seed_mean_recall is not None and not 100 * seed_mean >= arguments.expect_seed_mean_recall:
        failed.append("mean recall over seeds %s %.1f %% below %.1f %%" % (
            ",".join(map(str, arguments.seeds)), 100 * seed_mean, arguments.expect_seed_mean_recall))
    if failed:
        sys.exit("FAIL: " + "; ".join(failed))


if __name__ == "__main__":
    main()
