// SPDX-License-Identifier: BSD-3-Clause
// The multilevel graph cut (MultilevelCut.h) of a surface split over processes, each process
// working on its own faces: the first process holds only the coarse graph and the bands.
//
// What it computes
//   Exactly MinimizeMultilevel of the whole surface's energy with its cells (the labels, the
//   moves), when the first level coarsens:
//     1. each process clusters its own faces (connected, one most probable label, one cell);
//        the first process joins clusters across processes from the pairs of adjacent faces
//        on the pieces' borders (each seen from both sides, or the halo was too narrow) whose
//        clusters share a cell and a label, and numbers the clusters by their lowest face id,
//        as the serial cut does; while the
//        clusters do not halve the faces, every process doubles its cells (at most three
//        times, as serially; then `Coarsened` is false and nothing was cut);
//     2. each process sums its faces' data costs per cluster and its pairs' weights per pair
//        of clusters, exactly (ExactSum.h: partial sums that add up to the serial ones in any
//        grouping); the first process assembles the coarse energy and solves it with
//        MinimizeMultilevel, the serial call, and finds the regions lost against their most
//        probable label on the coarse graph (a cluster is one label and one most probable
//        label, so such a region is a union of clusters);
//     3. the band: each process seeds it with its own faces next to another label or in a lost
//        region and grows it ring by ring; faces of the halo reached go to their owners
//        through the first process after every ring;
//     4. each process sends its band faces' sub-energy rows (data costs with the fixed
//        neighbours' terms, pairs to higher band faces, in the serial cut's adjacency order);
//        the first process forms the band's connected components and gives each to one
//        process (the largest first to the least loaded), which solves it as the serial cut
//        does; the labels go back through the first process.
//   The first process holds the borders' faces, the first coarse level (about a quarter of
//   the faces), the solve below it and the band, never the whole fine graph.
//
// Contract
//   Every process calls it at the same point with its share. Faces must be owned by exactly
//   one process (the caller checks). Progress and abort: the first process's callback (the
//   coarse solve the first half, its own band components the second); an abort makes every
//   process's result Aborted (the other processes' band components run to their end).
//   Errors: the group's rule (ProcessGroup.h).
#pragma once

#include "Partition/MultilevelCut.h"
#include "ProcessGroup.h"

#include <cstdint>
#include <vector>

namespace shapediameter
{

/// One process's part of the energy: its share's faces (own faces and a halo holding every
/// face adjacent to an own face), in increasing global id.
struct CutShare
{
  const std::vector<std::int64_t>& GlobalIds;
  const std::vector<std::uint8_t>& Own;
  int LabelCount = 0;
  /// Per share face (the halo's too), e1 at [f * LabelCount + l].
  std::vector<double> DataCosts;
  /// Per share face, its cell (CoarseningCells.h, the whole surface's grid).
  std::vector<std::uint64_t> Cells;
  /// Per own face, its pairs in the serial cut's order (the pairs with lower faces by their
  /// face, then those with higher faces in the graph's order): the neighbour (share index)
  /// and the pair's weight, from Start[f] to Start[f + 1] (empty for halo faces).
  std::vector<std::size_t> Start;
  std::vector<std::uint32_t> Neighbor;
  std::vector<double> Weight;
  /// Faces of the whole surface.
  std::size_t WholeFaceCount = 0;
};

struct CutOverProcessesResult
{
  /// False when the first level did not coarsen: nothing was cut (a serial cut would have
  /// solved the whole graph directly; the caller gathers it).
  bool Coarsened = true;
  bool Aborted = false;
  /// Per share face: the label of own faces and of the halo faces adjacent to them, -1 for
  /// the rest.
  std::vector<int> Labels;
  int Moves = 0;
};

/// See the header.
CutOverProcessesResult MinimizeMultilevelOverProcesses(const CutShare& share, const ProcessGroup& group,
  const MultilevelOptions& multilevel, const AlphaExpansionOptions& options, const ProgressCallback& progress,
  const ParallelFor& parallelFor);

} // namespace shapediameter
