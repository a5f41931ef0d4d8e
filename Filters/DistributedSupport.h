// SPDX-License-Identifier: BSD-3-Clause
// Distributed runs (ParaView's pvbatch / pvserver under mpiexec): every filter of the module
// needs more than a process's own cells (rays cross pieces, neighbourhoods and the face graph
// cross pieces, the mixture and the skeleton are global). Three ways, below: the whole surface
// on every process, each computing its own cells (RunOnReplicatedSurface: the SDF); each
// process's own cells with a halo (RunOnHaloSurface: smoothing, partition, skeleton, whose
// global steps are the core's ProcessGroup collectives); or the serial algorithm once, on
// process 0, on the whole surface gathered in its original cell and point order
// (RunOnWholeSurface: the fallback and the modes the others do not cover). With global ids on
// the input (vtkSDFOFFReader adds them under MPI) results are bit-identical to a serial run
// whatever the number of processes (Testing/Python/mpi_compare.py checks it).
//
// The MPI transport lives here (polydata travel as raw arrays, PolyDataTransfer.h); the
// whole-surface assembly and the scatter mapping are pure functions of VTK data in
// WholeSurface.h (unit-tested without MPI).
//
// Private to the module: not installed, not wrapped.
#pragma once

#include "ProcessGroup.h"

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

class vtkAlgorithm;
class vtkInformationVector;
class vtkPolyData;

namespace shapediameter::distributed
{

/**
 * True when the request is one piece of a distributed run: an output (or the first input)
 * asks for one of N > 1 pieces and the global vtkMultiProcessController has N processes.
 * Every process of such a run executes the filter together (ParaView updates all ranks),
 * which RunOnWholeSurface relies on. False in every serial run (no controller, one
 * process, or one piece requested, e.g. a filter updated by hand on one rank): then the
 * filter does nothing distributed, at no cost.
 */
bool IsDistributedRequest(vtkInformationVector** inputVector, vtkInformationVector* outputVector);

/// The filter's serial RequestData, called with substitute information vectors.
using SerialBody = std::function<int(vtkInformationVector** inputVector, vtkInformationVector* outputVector)>;

/**
 * Runs `serial` on the whole surface and hands each process its part. Collective: every
 * process of the global controller must call it.
 *
 * 1. The polydata on input port 0 of every process is sent to process 0 (point-to-point:
 *    vtkCommunicator splits messages above 2 GiB, a gather's MPI counts would overflow).
 * 2. Process 0 rebuilds the whole surface: cells sorted by their global id (the cell
 *    GlobalIds attribute, e.g. `GlobalCellIds` that vtkSDFOFFReader adds in distributed runs;
 *    else RedistributeDataSet's `vtkOriginalCellIds`, which are global when one process held
 *    the whole input, accepted when equal ids always mean the same corners; else process
 *    order), a cell present on several processes (BoundaryMode "Assign to all regions")
 *    kept once, points merged by their global id (point GlobalIds attribute, e.g. the
 *    reader's `GlobalPointIds`; else by identical coordinates, in order of first use) and
 *    sorted by it. With the reader's ids this is the original mesh in its original order,
 *    hence results bit-identical to a serial run; with the fallbacks, identical as long as
 *    the fallback reproduces the original order (vtkOriginalCellIds after a single-piece
 *    reader: checked on camel), otherwise valid but dependent on the decomposition.
 *    Ghost-type arrays are dropped from the whole surface.
 * 3. `serial` runs on process 0 only; the other input ports are passed unchanged.
 * 4. Every port listed in `scatteredPorts` (the input surface plus new arrays) goes back to
 *    each process as its own cells and points: its input, plus every cell and point array
 *    the filter made (arrays passed through stay the process's own), the field data of the
 *    whole result, and the polygon winding when the filter changed it (AutoOrient). The other output ports (skeleton, point cloud, histogram) are complete on
 *    process 0 and empty on the others, so that ParaView's gathering does not repeat them.
 *
 * Returns `serial`'s result (the same on every process).
 *
 * Gathered arrays: `cellArrays`, when not empty, names the cell arrays `serial` reads; the
 * other cell arrays stay on their process (the outputs keep them: each process's cells get
 * only the new arrays back), except the ones the assembly orders cells by (global ids,
 * `vtkOriginalCellIds`, ghosts). Empty: every array travels. Why: after the partition a piece
 * carries some 20 cell arrays the skeleton never reads, and copying them was most of its
 * distributed overhead (208k faces, 2 ranks: assembly 0.19 s against 0.06 s for the smoothing).
 *
 * Errors: `failure`, when given, is called on process 0 after `serial` and returns what the
 * filter reported as its failure there (empty: none; filters report bad input with an error
 * and return 1). That text, or the exception that stopped the assembly, is sent to every
 * other process with the status, and each reports it as an error of `algorithm` too, so a
 * bad piece on any process shows on every process (each keeps its input, as process 0 does).
 *
 * Memory: process 0 holds the received pieces, the whole surface and the filter's new
 * arrays on it at once (about 2x one copy of the surface with its arrays, plus the
 * algorithm's own working set on the whole surface, as in a serial run); every other process
 * holds its own piece and, while it is received, a copy of it with the new arrays.
 * Waiting processes sleep (with ParaView's MPI: polling a non-blocking receive) instead of
 * spinning, so process 0's threads keep the node's cores.
 * Setting SHAPEDIAMETER_DISTRIBUTED_TIMING=1 in the environment prints the time of each
 * step on process 0 (stderr).
 */
/// Whether SHAPEDIAMETER_DISTRIBUTED_TIMING asks for the distributed runs' reports (set and
/// not "0"): what each step took and which path it ran on, printed by process 0 (stderr).
bool TimingReportsRequested();

int RunOnWholeSurface(vtkAlgorithm* algorithm, vtkInformationVector** inputVector,
  vtkInformationVector* outputVector, const std::vector<int>& scatteredPorts, const SerialBody& serial,
  const std::function<std::string()>& failure = {}, const std::vector<std::string>& cellArrays = {});

/**
 * What a replicated run (RunOnReplicatedSurface) gives the filter's body: the whole surface is
 * its input on every process, Owned says which of its cells this process computes, and
 * Combine completes results that each process computed on its own cells only.
 */
struct ReplicatedShare
{
  /// Per cell of the whole surface: 1 when this process computes it. Every cell has exactly
  /// one owner (a cell held by several pieces: the lowest process holding it).
  std::vector<std::uint8_t> Owned;
  /**
   * Collective, called once by the body on every process after its own cells are done:
   * `values` and `counts` (the same length everywhere, zero outside this process's cells)
   * become their sums over the processes, i.e. every cell's owner's result (x + 0 is exact,
   * so the sums equal the serial values bit for bit). `aborted`: in, this process aborted;
   * out, some process did, and nothing was summed. Throws Error when another process stopped
   * (bad input, an exception) before it reached this point, so that every process reports it
   * instead of waiting.
   */
  std::function<void(std::vector<double>& values, std::vector<int>& counts, bool& aborted)> Combine;
  /**
   * Called by the body once it no longer reads the whole surface's points and cells (it holds
   * its own copy): they are freed, in the whole input and in `output` (the body's whole output,
   * which shares them), keeping both's point and cell data, which is all the scatter reads.
   * Nothing is freed when `output`'s polygons are not the input's (rewound: the scatter reads
   * them). Every process holds the whole surface during a replicated run: at 832k faces its
   * points and cells are 20-40 MB of each process's peak, the BVH's build. Not collective.
   */
  std::function<void(vtkPolyData* output)> ReleaseGeometry;
};

/// The filter's RequestData for a replicated run: `share` is valid during the call.
using ReplicatedBody = std::function<int(
  vtkInformationVector** inputVector, vtkInformationVector* outputVector, const ReplicatedShare& share)>;

/**
 * Runs `body` on the whole surface on EVERY process, each computing its own cells: for
 * filters whose per-cell work needs the whole surface only to read it (the SDF's rays).
 * Collective.
 *
 * 1. Every process sends its piece to every other (point to point, in one global order of
 *    the pairs).
 * 2. Every process assembles the whole surface in the original order (AssembleWholeSurface,
 *    the same on every process), finds each cell's owner and where its own cells and points
 *    are in it, and drops the other pieces. The processes agree that every assembly succeeded
 *    (else each reports its error and keeps its input).
 * 3. Every process runs `body` on the whole surface; the body calls ReplicatedShare::Combine
 *    once (a process that stops before it joins it from here, as stopped).
 * 4. Every process keeps its own cells of the result (LocalResult), with no further exchange;
 *    outputs other than `scatteredPorts` stay on process 0.
 *
 * Memory: every process holds the whole surface and the filter's working set on it (as a
 * serial run), and the pieces while it assembles them. Returns the lowest status.
 */
int RunOnReplicatedSurface(vtkAlgorithm* algorithm, vtkInformationVector** inputVector,
  vtkInformationVector* outputVector, const std::vector<int>& scatteredPorts, const ReplicatedBody& body);

/**
 * What a halo run (RunOnHaloSurface) gives the filter's body: its input is this process's own
 * cells plus a halo of the other processes' cells near them, in the whole surface's order.
 */
struct HaloShare
{
  /// Per cell of the body's input: 1 for this process's own cells, 0 for the halo.
  std::vector<std::uint8_t> Own;
  /// Per cell: 1 for the own cells this process counts in whole-surface measures: all of
  /// them, except the cells a lower process holds too (RedistributeDataSet's "assign to all
  /// regions"), which that process counts.
  std::vector<std::uint8_t> Counted;
  /// Per cell: its global id (the whole surface's cells are in the order of these ids).
  std::vector<std::int64_t> GlobalIds;
  /// Per point: its global id.
  std::vector<std::int64_t> GlobalPointIds;
  /// Every cell whose centre lies within this distance of an own cell's centre is in the
  /// input (0 for HaloKind::SharedCorners). A body that finds it needs more throws
  /// HaloTooNarrowError (ProcessGroup.h) on every process, and the run falls back to the whole
  /// surface (the result is empty).
  double Width = 0.0;
  /// The processes, for the whole surface's measures (collectives; never null in a body).
  const ProcessGroup* Group = nullptr;
};

/// Which cells of the other processes make a process's halo.
enum class HaloKind
{
  /// Every cell whose centre lies within the radius of an own cell's centre (and a few more).
  CentresWithin,
  /// Every cell sharing a corner with an own cell (and a few more: those with a corner in a
  /// voxel holding one of the process's points); the radius is only the voxels' size.
  SharedCorners,
  /// No halo: the body reads its own cells only (and the whole surface's through its own
  /// collectives); no cells are exchanged.
  None
};

/// The halo a filter needs: the distance within which its body reads other cells to compute
/// one cell (HaloKind::SharedCorners: the size of the voxels that find the shared corners). Collective (every process calls it with its own piece); throws only before its
/// first collective, on a piece it cannot process.
using HaloRadiusFunction = std::function<double(vtkPolyData* piece, const ProcessGroup& group)>;
/// The filter's RequestData for a halo run: `share` is valid during the call.
using HaloBody =
  std::function<int(vtkInformationVector** inputVector, vtkInformationVector* outputVector, const HaloShare& share)>;

/**
 * Runs `body` on every process on its own cells plus a halo, without collecting the surface:
 * for filters whose result on a cell depends only on the cells within a known distance of it
 * and on a few whole-surface measures the body combines over the processes (the smoothing's
 * neighbourhoods, its mean edge length and quantiles). Collective.
 *
 * 1. Every process's piece must hold polygons only (at least one) with global cell and point
 *    ids, and `radius` must succeed on every process; otherwise nothing is done and the result
 *    is empty: the caller then runs RunOnWholeSurface, which reports what was wrong.
 * 2. The processes' occupied voxels are exchanged; each process sends every other, point to
 *    point, the cells whose centre lies within `radius` of one of that process's cell centres
 *    (a superset of the cells within that distance, along the surface, of one of its cells), or
 *    with HaloKind::SharedCorners the cells sharing a corner with one of its cells.
 * 3. Each process assembles its cells and those it received in the whole surface's order
 *    (AssembleWholeSurface: by global ids), and runs `body` on them. Only the cell arrays in
 *    `cellArrays` (all when empty) travel.
 *    The halo is 10 % wider than `radius`; a body that finds it too narrow once it knows the
 *    whole surface's measures (HaloShare::Width) makes every process return empty, as in 1.
 * 4. Each process keeps its own cells of the result on the `scatteredPorts`; the other ports
 *    keep process 0's body output there (a whole-surface result such as the partition's
 *    histogram) and are emptied elsewhere. When the body failed or aborted on any process, every process keeps its
 *    input, and those that did not fail themselves report that another one did.
 *
 * A process that fails (bad input, an exception) makes the others' collectives throw instead
 * of waiting (the group exchanges each process's state before every collective, sleeping).
 * Memory per process: its piece, the halo, and the body's working set on both.
 */
std::optional<int> RunOnHaloSurface(vtkAlgorithm* algorithm, vtkInformationVector** inputVector,
  vtkInformationVector* outputVector, const std::vector<int>& scatteredPorts, HaloKind kind,
  const HaloRadiusFunction& radius, const HaloBody& body, const std::function<std::string()>& failure,
  const std::vector<std::string>& cellArrays);

} // namespace shapediameter::distributed
