// SPDX-License-Identifier: BSD-3-Clause
// The partition of a surface split over processes: each builds the dual graph of its own faces,
// one process partitions the whole graph, each gets its own faces' labels back; or, above
// MultilevelOptions::DirectBelowFaces (the defaults: 60,000 faces), with every face owned by
// one process and the refinement off, each process builds its own faces' energy and the graph
// cut runs on every process's faces (Partition/DistributedCut.h): the first process gathers
// only the values and areas (the model, the area sum, the histogram), the coarse graph, the
// bands' rows and, for the segments, the adjacency by ids. The same bits either way.
//
// What it computes (the gathered graph)
//   Exactly PartitionBySDF of the whole surface (bit for bit: the same graph, values, model,
//   cut, segments, refinement and histogram), with no process holding the whole surface's
//   polygons or face graph:
//     1. each process builds the face graph (FaceGraph.h) of its share: its own faces and a halo
//        that holds every face sharing an edge with one of them (the VTK adapter's halo: the
//        faces sharing a corner with an own face, Filters/DistributedSupport.h);
//     2. each process sends the first process the dual-graph rows of its own faces (the face's
//        value, area and centre; per neighbour its global id, normal angle, concave flag and
//        shared edge length): about 115 bytes per face;
//     3. the first process orders the rows by global id (a face several processes own is taken
//        once), checks that every adjacency is listed from both sides and that no two faces
//        report the same side as open (no face of their share has it: an adjacency both halos
//        missed; sides are compared by their corners' global ids, or coordinates), and runs
//        PartitionOnDualGraph, steps 2 to 8 of the partition;
//     4. it sends every process the model, the energy and, per own face, the probabilities, band,
//        fine label and segment (one process at a time); levels follow from the bands.
//   A row is the serial row: FaceGraph lists neighbours by index and the share keeps the whole
//   surface's order, so the rows, and everything computed from them, equal the serial ones.
//
// Why not more distributed
//   The graph cut (MultilevelCut.h) solves max-flows whose result depends on the whole graph.
//   Its clusters are decided by cells of space, the same for any split (CoarseningCells.h), so
//   a cut that clusters on every process, solves the coarse graph on one and refines the bands
//   where they lie can give the serial labels; it is not built yet (docs/distributed.md).
//   The first process holds the dual graph and the cut's working set, but not the polygons,
//   the points or the face geometry that the serial run's face graph has.
//
// Contract
//   Every process calls PartitionBySDF with a PartitionShare at the same point (the group's
//   collectives). A missing adjacency (the halo too narrow) throws HaloTooNarrowError on the
//   first process (never a silently different row); bad input throws Error where it is found; the group makes the other
//   processes' next collective throw (ProcessGroup.h). Progress and abort: the first process's
//   callback, as PartitionBySDF's; an abort there makes every process's result Aborted.
//   The result has no Graph (the share's is freed once its rows are sent). On processes other
//   than the first the result's Histogram and Timings are empty; per-face arrays cover
//   all the share's faces, the halo's with probability 0 and label, band and segment -1.
#pragma once

#include "Partition/Partition.h"
#include "ProcessGroup.h"

#include <cstdint>
#include <vector>

namespace shapediameter
{

/// One process's share of a distributed partition (PartitionInput::Share).
struct PartitionShare
{
  /// Per face of the share: its id in the whole surface (distinct, in [0, 2^53)); the whole
  /// surface's faces are ordered by these ids, and the share lists its faces in that order.
  const std::vector<std::int64_t>& GlobalIds;
  /// Per face of the share: 1 for this process's own faces, 0 for the halo.
  const std::vector<std::uint8_t>& Own;
  const ProcessGroup& Group;
  /// Optional, per point of the share: its id in the whole surface. With them the check for
  /// adjacencies both halos missed compares sides by their corners' ids, as the whole surface
  /// joins faces; without, by their coordinates, and two faces whose sides meet at distinct
  /// points with equal coordinates (a seam of duplicated points) are taken for a missed
  /// adjacency (the caller then partitions on one process).
  const std::vector<std::int64_t>* GlobalPointIds = nullptr;
};

/// PartitionBySDF with input.Share set (see the header comment); PartitionBySDF calls it.
PartitionResult PartitionOverProcesses(const PartitionInput& input, const PartitionShare& share,
  const PartitionOptions& options, const ParallelFor& parallelFor, const ProgressCallback& progress);

} // namespace shapediameter
