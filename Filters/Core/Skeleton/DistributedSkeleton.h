// SPDX-License-Identifier: BSD-3-Clause
// The skeleton of a surface split over processes: the first process builds it from the
// triangles every process sends; every process links its own faces to it.
//
// What it computes
//   Exactly what the VTK adapter computes serially on the whole surface (bit for bit): the
//   whole triangle mesh oriented outward (OrientOutward, ApplyFlips) and ComputeSkeleton on
//   it (Skeleton.h), with the same triangles in the same order:
//     1. each process sends the first process, per cell of its share, the cell's global id and
//        triangle count, per triangle its corners' global point ids, and per point its global
//        id and coordinates (about 50 bytes per triangle; the triangles one process at a time);
//     2. the first process orders the cells by global id (a cell several processes hold is
//        taken once, from the lowest), the points by global id, and builds the whole mesh:
//        no polygons, point or cell arrays of the surface, only what the skeleton reads;
//     3. it orients the mesh outward and labels its surface components; only then do the
//        triangles' SDF and parts follow (GatherTriangleColumnsOnFirst: the orientation's
//        adjacency is one of this process's peaks); it labels the parts and sends
//        every process, per triangle of its share, the triangle's flip, component, part, index
//        in the whole mesh and whether it counts in the link's sums (a cell several processes
//        hold counts on the lowest); every process winds its triangles as the whole mesh does;
//     4. it samples the mesh (SampleSkeletonSurface), frees it and computes the rest of the
//        skeleton (ComputeSkeletonOfSamples) through three things spread over the processes:
//        - the volume: every process builds the BVH of its own triangles, wound as the whole
//          mesh's and translated by the whole mesh's centre (sent with step 3); each ray of a
//          batch of the skeleton's rays (RayCaster::CastRays) goes to every process whose own
//          triangles' box it may meet (RayMayMeetBox: the others have no hit), and each ray's
//          answer is the one whose closest hit Embree ranks first (CastRaysWithOrder; equal
//          orders: the lowest process's), the whole mesh's own answer (but for a ray whose two
//          closest triangles lie at the very same single-precision distance, where either
//          BVH's traversal order decides). No process holds the whole mesh's BVH;
//        - the surface link's steps (SkeletonLink.h) run on every process's own triangles
//          (LinkOverProcesses), the first process completing each step's result: the largest
//          face per component without samples (ties: the lowest face), the area per (part,
//          bone) as exact sums;
//        - the thinning's MLS iterations (RegressionOverProcesses): the cloud goes to every
//          process once, each builds its own tree of it and projects an equal range of the
//          points (ProjectOntoRegressionLines: a point's answer depends on it and the cloud
//          alone, so it is the serial one).
//        All three are commands every other process serves until the first is done: one
//        exchange per batch of rays (at most 16,384 rays; the volume PrefersFewLargeBatches, so
//        the growth tests all its possible steps in one batch), per link step and per MLS
//        iteration, about 35 in all;
//     5. it asks for the cell id and cloud label of the cloud points' source triangles (a
//        gather of at most NumberOfSamples pairs): the whole mesh needs neither.
//   The triangles of a cell are those the adapter makes of it (Triangulate), which depend on
//   the cell alone, so the whole mesh is the serial one: the same triangles, corners, order,
//   and every process's projected centres and areas are the whole mesh's bits.
//
// Why not more distributed
//   Orientation, components and sampling are whole-surface: the first process holds the mesh
//   until it is sampled and the skeleton's working set (at most NumberOfSamples points), but
//   not the VTK surface with its arrays, the volume's BVH, nor the faces' link
//   (docs/distributed.md: the plan for the rest).
//
// Contract
//   Every process calls ComputeSkeletonOverProcesses at the same point (the group's
//   collectives). Bad input found on the first process (non-finite points, negative SDF, no
//   triangles at all) throws Error there; the group makes the other processes' next collective
//   throw (ProcessGroup.h). Progress and abort: the first process's callback, as
//   ComputeSkeleton's; an abort there makes every process's result Aborted.
#pragma once

#include "Mesh/MeshTypes.h"
#include "Parallel.h"
#include "ProcessGroup.h"
#include "Skeleton/Skeleton.h"

#include <cstdint>
#include <vector>

namespace shapediameter
{

/// One process's share of a distributed skeleton: its own cells (a triangulated surface), in
/// the order of their global ids.
struct SkeletonShare
{
  /// Per cell of the share: its id in the whole surface (distinct within the share, in
  /// [0, 2^53)); the whole surface's cells are ordered by these ids.
  const std::vector<std::int64_t>& CellGlobalIds;
  /// Per point of the share: its id in the whole surface, in [0, 2^53).
  const std::vector<std::int64_t>& PointGlobalIds;
  const ProcessGroup& Group;
};

/// What one process's triangles carry to the whole mesh.
struct SkeletonShareInput
{
  PointsView Points;
  /// The share's triangles (point indices of Points), cell by cell in the share's cell order.
  TrianglesView Triangles;
  /// Per triangle: its cell (index into SkeletonShare::CellGlobalIds), non-decreasing.
  const std::vector<std::int64_t>& TriangleCell;
  /// Per triangle: its SDF (ComputeSkeleton's faceSdf).
  const std::vector<double>& TriangleSdf;
  /// Per triangle: its part label (ComputeSkeleton's faceParts), or empty; used when no
  /// process's is empty.
  const std::vector<std::int64_t>& TriangleParts;
  /// Per triangle: a label reported for each cloud point it sources (the adapter's SDFCluster),
  /// or empty; used when no process's is empty.
  const std::vector<double>& TriangleCloudLabels;
};

struct DistributedSkeletonResult
{
  /// On the first process: the skeleton and the projected cloud of the whole mesh
  /// (CloudSourceFace: a triangle of the whole mesh); FaceNodeId and FaceBoneId are empty
  /// (below). Empty elsewhere.
  SkeletonResult Whole;
  /// On the first process: per cloud point, its source triangle's cell's global id.
  std::vector<std::int64_t> CloudSourceCellId;
  /// On the first process, with cloud labels: per cloud point, its source triangle's label.
  std::vector<double> CloudLabels;
  /// Per triangle of this process's share: "SkeletonNodeId" and "SkeletonBoneId".
  std::vector<std::int64_t> FaceNodeId;
  std::vector<std::int64_t> FaceBoneId;
  /// True on every process if the first process's progress callback aborted.
  bool Aborted = false;
};

/// See the header comment.
DistributedSkeletonResult ComputeSkeletonOverProcesses(const SkeletonShareInput& input,
  const SkeletonShare& share, const SkeletonOptions& options, const ParallelFor& parallelFor,
  const ProgressCallback& progress = {});

} // namespace shapediameter
