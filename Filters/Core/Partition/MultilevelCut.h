// SPDX-License-Identifier: BSD-3-Clause
// The k-way graph cut of the SDF partitioning on large meshes: alpha-expansion on a coarsened
// graph, then alpha-expansion on a band around the part boundaries at full resolution.
//
// Why
//   With the resolution-independent energy (PartitionEnergy.h) the cut weight of an edge
//   grows as sqrt(faces) relative to a face's data cost, so every max-flow of a plain
//   alpha-expansion routes flow across whole parts and its cost grows as faces^1.5 (docs/performance.md). The energy approximates an integral over the surface, so its minimiser is
//   nearly the same on a coarser graph; only the exact position of the boundaries needs the
//   fine faces.
//
// What it computes
//   1. The most probable label of each face (MostProbableLabels).
//   2. Clusters: with the faces' cells (CoarseningCells.h, cubes of about ClusterSize faces;
//      the product's default, PartitionOnDualGraph passes them when the graph has face
//      centres) the connected sets of faces with the same most probable label inside one cube,
//      the cubes doubled at each coarser level (and doubled more, at most three times, while a
//      level would not halve the nodes). Each face's cluster is decided by where it lies and by
//      its neighbours in its cube, not by the face order: the same for any order of the faces
//      and for any split of the surface over processes (the way to a cut on every process's
//      faces, docs/distributed.md). Without cells: clusters of at most ClusterSize faces, grown
//      breadth-first in face order over faces with the same most probable label (what the
//      cut did before; used by the refinement's sub-problems and by callers without centres).
//   3. The coarse energy: a cluster's data cost is the sum of its faces', the weight between
//      two clusters the sum of the weights of the face pairs between them (pairs inside a
//      cluster are never cut by a labelling constant on clusters, so for such labellings the
//      coarse E equals the fine E). Solved by this same function (recursively, until at most
//      DirectBelowFaces nodes remain, then MinimizeByAlphaExpansion).
//   4. The coarse labels projected onto the faces; the band = faces within BandRings rings of
//      a face whose neighbour has another label, or of a connected region of at least
//      LostRegionFaces faces that the coarse solve labelled against their common most probable
//      label. Alpha-expansion (AlphaExpansion.h) on the band faces, from the projected labels,
//      with the faces outside the band fixed (their pairs with band faces become data costs of
//      the band faces). The second kind of band is for parts the coarse solve lost: a thin
//      part whose clusters have ragged boundaries costs more on the coarse graph than its
//      straight fine cut, vanishes there and leaves no boundary to refine from (seen on the
//      linear subdivisions of the camel and the man: docs/partition.md).
//      It also makes the result follow the energy as the plain alpha-expansion does: without
//      it the coarse solve smoothed more than λ asks (the elephant poses: docs/partition.md).
//   Graphs with at most DirectBelowFaces faces go straight to MinimizeByAlphaExpansion, so
//   small meshes get exactly the plain alpha-expansion.
//   The band's connected components (one per part boundary, typically) are independent once
//   the faces around them are fixed: each is solved on its own, concurrently through
//   `parallelFor`. The source side of a max-flow is the set reachable from s, so a move's cut
//   on a union of components is the union of their cuts: the labels are those of one
//   alpha-expansion on the whole band (checked bit-identical, labels and E, on eight meshes of
//   85k-208k faces, 1 and 2 threads), and do not depend on the thread count. Also tried:
//   solving coarse levels of 15k-60k nodes by coarsening once more (the coarse solve is the
//   largest serial step): a little faster, but a clearly higher E; not kept. Measurements:
//   docs/performance.md.
//
// Guarantees and deviation
//   E never exceeds the energy of the projected coarse labelling, which is the coarse
//   minimum's energy (above). It is not a local minimum of every expansion move of the whole
//   fine graph (faces outside the band are fixed): another local minimum than the plain
//   alpha-expansion finds: against the plain alpha-expansion, several times faster above
//   DirectBelowFaces for a slightly higher E and a few percent of the faces labelled
//   differently. Below DirectBelowFaces the plain alpha-expansion is used: there the multilevel
//   cut gained too little for the faces it moved. Measurements: docs/performance.md,
//   "Design measurements".
//
// Parameters (MultilevelOptions)
//   DirectBelowFaces  60000  [16, inf)  solve directly up to this many faces/nodes.
//   ClusterSize       8      [2, 1024]  the cells' side is sqrt(ClusterSize) mean spacings of
//                                        adjacent face centres (about half as many faces per
//                                        cluster, as labels and cubes split them); without
//                                        cells, faces per cluster at most. 16 was a little
//                                        faster but moved more faces; cells of sqrt(12) or more
//                                        lost a band of the elephant.
//   BandRings         8      [1, 64]    rings around the projected boundaries that are
//                                        re-solved; 4 raised E, 16 gained little over 8.
//   LostRegionFaces   1024   [1, inf)   smallest region off its most probable label that is
//                                        re-solved; smaller values enlarge the band for little
//                                        lower E and the same clusters.
//   (Measurements of the three: docs/performance.md.)
//
// Progress and abort: as MinimizeByAlphaExpansion (the coarse solve reports the first half).
// While bands run concurrently, `progress` is called from the worker threads, one call at a
// time (under a lock), with non-decreasing fractions; an abort stops every band.
#pragma once

#include "Partition/AlphaExpansion.h"

#include <cstdint>
#include <utility>
#include <vector>

namespace shapediameter
{

/// Cells doubled at most this often when a level's cell clusters coarsen the graph by less
/// than half.
inline constexpr int MaximumCellDoublings = 3;

struct MultilevelOptions
{
  std::size_t DirectBelowFaces = 60000;
  int ClusterSize = 8;
  int BandRings = 8;
  std::size_t LostRegionFaces = 1024;
};

/// See the header. Throws Error on an inconsistent energy or bad options.
/// faceCells (optional, per face; CoarseningCells.h): cluster by cells of space at every level
/// instead of breadth-first in face order.
AlphaExpansionResult MinimizeMultilevel(const PartitionEnergy& energy, const MultilevelOptions& multilevel = {},
  const AlphaExpansionOptions& options = {}, const ProgressCallback& progress = nullptr,
  const ParallelFor& parallelFor = SerialFor, const std::vector<std::uint64_t>& faceCells = {});

/// Step 4's lost regions: per node of `energy`'s graph, 1 when it lies in a connected region
/// (through nodes of the same most probable label) of nodes whose label is not their most
/// probable one, of at least `minimumRegion` in size (the sum of `sizes` over its nodes: faces
/// per cluster on a coarse graph; 1 each when empty).
std::vector<std::uint8_t> LostRegions(const PartitionEnergy& energy, const std::vector<int>& labels,
  const std::vector<int>& mostProbable, const std::vector<double>& sizes, std::size_t minimumRegion);

/// A face in no cluster (GrowClusters' `include` left it out).
inline constexpr std::size_t NoCluster = static_cast<std::size_t>(-1);

/// Step 2's clusters on an adjacency in CSR form (start: an offset per face and one more;
/// neighbor: the neighbour of each entry) over the faces `include` marks (null: all; the others
/// in NoCluster): grown breadth-first from the lowest face not yet in one; with `cells`, every
/// connected face of the seed's most probable label (`seedLabels`) in its cell (the same sets
/// for any face order), without, at most `size` faces of its label. Per face its cluster,
/// numbered by their lowest face, and the cluster count. A process's own faces
/// (DistributedCut.h) are clustered by the same function.
std::pair<std::vector<std::size_t>, std::size_t> GrowClusters(const std::size_t* start, const std::uint32_t* neighbor,
  const std::vector<int>& seedLabels, const std::vector<std::uint64_t>& cells, int size,
  const std::uint8_t* include = nullptr);

/// Step 2's clusters of the first level, with the faces' cells as given (not doubled) or, when
/// faceCells is empty, breadth-first: per face its cluster (numbered by their lowest face) and
/// the cluster count. What MinimizeMultilevel coarsens by; for tests and a coarsening run on
/// every process's faces.
std::pair<std::vector<std::size_t>, std::size_t> FirstLevelClusters(
  const PartitionEnergy& energy, const std::vector<std::uint64_t>& faceCells, int clusterSize);

} // namespace shapediameter
