// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkSDFSurfaceAlgorithm
 * @brief   Base of the module's surface filters: distributed runs, threads, input checks and
 *          the error → pass-through policy, once for all four.
 *
 * vtkShapeDiameterFilter, vtkSDFBilateralSmooth, vtkSDFGMMPartition and vtkSDFSkeleton read
 * a surface on input port 0 and pass it through, with new arrays, on one output port (their
 * surface port; other ports hold a skeleton, a point cloud or a histogram). RequestData runs,
 * in this order:
 * 1. Distributed runs (Filters/DistributedSupport.h): under MPI the rest runs once, on
 *    process 0, on the whole surface gathered in its original order; every process gets its
 *    own cells back on the surface port. A filter whose CanRunReplicated() is true runs it
 *    on every process instead, on the whole surface, each process computing its own cells;
 *    one whose CanRunWithHalo() is true runs it on every process on its own cells plus a halo
 *    of its neighbours' (HaloRadius wide, or the cells sharing a corner with its own when
 *    HaloOfSharedCorners() is true, or none when NeedsNoHalo() is true), without collecting
 *    the surface.
 * 2. The surface port starts as a shallow copy of the input.
 * 3. An input without cells: a warning, and that copy.
 * 4. An input without polygons (without polygons and triangle strips, for the filters that
 *    split strips into triangles): an error, and that copy.
 * 5. The filter's body (ExecuteSurface). A std::exception it throws becomes one
 *    vtkErrorMacro, "Cannot <task>: <reason>"; after an error or an abort the surface port
 *    is the pass-through copy of the input and every other output port is empty.
 *
 * NumberOfThreads (default 0 = all cores, range [0, 1024]) sets the workers of the body's
 * parallel loops (vtkSMPTools' STDThread backend, whatever backend the application selected,
 * because ParaView defaults to Sequential); no output depends on it.
 *
 * The face graph (the smoothing's and the partition's dual graph) is built once per surface
 * in a chain: a filter keeps the graph it used until its next execution or its deletion, and
 * a filter given the same points and polygons meanwhile reuses it (SharedFaceGraph in
 * Filters/Core/Mesh/FaceGraph.h; 0.3 s of the partition at 832k faces). Memory: one graph per
 * distinct surface while a filter that used it lives (about 160 bytes per face); a filter
 * whose ReleaseDataFlag is on keeps none (each filter then builds its own).
 *
 * Not meant to be used on its own (it has no New()); not a ParaView proxy.
 */
#ifndef vtkSDFSurfaceAlgorithm_h
#define vtkSDFSurfaceAlgorithm_h

#include "ShapeDiameterFiltersModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <memory> // for std::shared_ptr
#include <string> // for std::string
#include <vector> // for std::vector

namespace shapediameter
{
struct FaceGraph;   // Filters/Core/Mesh/FaceGraph.h
class ProcessGroup; // Filters/Core/ProcessGroup.h
namespace adapter
{
struct SurfaceRequest; // Filters/SurfaceRequest.h (private to the module)
}
namespace distributed
{
struct ReplicatedShare; // Filters/DistributedSupport.h (private to the module)
struct HaloShare;       // Filters/DistributedSupport.h (private to the module)
}
}

class SHAPEDIAMETERFILTERS_EXPORT vtkSDFSurfaceAlgorithm : public vtkPolyDataAlgorithm
{
public:
  vtkTypeMacro(vtkSDFSurfaceAlgorithm, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Worker threads, 0 = all cores (default 0, range [0, 1024]); the output does not depend
  /// on it.
  vtkSetClampMacro(NumberOfThreads, int, 0, 1024);
  vtkGetMacro(NumberOfThreads, int);
  ///@}

protected:
  /// `task` completes "Cannot ..." in error messages, `emptyNote` "The input is empty: ...";
  /// `surfacePort` is the output port that passes the input through; `acceptStrips`: triangle
  /// strips count as surface (else polygons only).
  vtkSDFSurfaceAlgorithm(const char* task, const char* emptyNote, int surfacePort, bool acceptStrips);
  ~vtkSDFSurfaceAlgorithm() override;

  /// Steps 1 to 5 of the class documentation; subclasses implement ExecuteSurface instead.
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) final;

  /**
   * The filter's own work on a checked input: read what it needs (throwing a
   * std::exception with a one-line reason on bad input), call the core, write the outputs.
   * Returns false when the user aborted (the base restores the pass-through).
   */
  virtual bool ExecuteSurface(const shapediameter::adapter::SurfaceRequest& request) = 0;

  /**
   * Distributed runs: true when ExecuteSurface, with the current settings, can run on the
   * whole surface on every process, computing only the cells of SurfaceRequest::Share and
   * combining them (distributed::RunOnReplicatedSurface); false (the default) runs it once on
   * process 0 (distributed::RunOnWholeSurface).
   */
  virtual bool CanRunReplicated() const { return false; }

  /**
   * Distributed runs: true when ExecuteSurface, with the current settings, can run on each
   * process's own cells plus a halo HaloRadius wide (distributed::RunOnHaloSurface), computing
   * only the cells SurfaceRequest::Halo flags as its own; false (the default) runs it once on
   * process 0. A halo run falls back to process 0 when a piece is not fit for it (cells other
   * than polygons, no global ids, bad input: the serial checks then report it).
   */
  virtual bool CanRunWithHalo() const { return false; }

  /**
   * The halo width CanRunWithHalo needs for `piece`, in the surface's units. Collective (every
   * process calls it with its own piece; whole-surface measures come from `group`); throws
   * only before its first collective, on a piece it cannot process.
   */
  virtual double HaloRadius(vtkPolyData* piece, const shapediameter::ProcessGroup& group);

  /**
   * Distributed runs with a halo: true when the body needs only the cells sharing a corner with
   * its own (the halo is then found by the corners' voxels, whatever the cells' sizes, and
   * HaloRadius gives the voxels' size); false (the default): the cells within HaloRadius.
   */
  virtual bool HaloOfSharedCorners() const { return false; }

  /**
   * Distributed runs with a halo: true when the body reads only its own cells (it gathers what
   * it needs of the others through SurfaceRequest::Halo's group): no cells are exchanged, and
   * HaloRadius is not used. False by default.
   */
  virtual bool NeedsNoHalo() const { return false; }

  /// For HaloRadius: the whole surface's mean edge length, from every process's `piece` (its
  /// polygons; collective, MeanEdgeLengthOverProcesses in Filters/Core/Mesh/FaceGraph.h).
  static double MeanEdgeLengthOverPieces(vtkPolyData* piece, const shapediameter::ProcessGroup& group);

  /**
   * Distributed runs on process 0: the cell arrays ExecuteSurface reads, so that only those
   * travel to process 0 (distributed::RunOnWholeSurface); empty (the default) = all of them.
   */
  virtual std::vector<std::string> CellArraysRead() { return {}; }

  /// `names` and the name of the array selected as input array 0 (when one is selected).
  std::vector<std::string> WithSelectedArray(std::vector<std::string> names);

  int NumberOfThreads = 0;

  /**
   * Keeps the face graph this execution used until the next execution or the filter's
   * deletion: while it is kept, the next filter of the chain given the same surface (the
   * partition after the smoothing, or this one re-executed on an unchanged surface) reuses it
   * instead of building its own (SharedFaceGraph in Filters/Core/Mesh/FaceGraph.h).
   */
  void KeepFaceGraph(std::shared_ptr<const shapediameter::FaceGraph> graph);

private:
  vtkSDFSurfaceAlgorithm(const vtkSDFSurfaceAlgorithm&) = delete;
  void operator=(const vtkSDFSurfaceAlgorithm&) = delete;

  /// Resets every output port to the documented result of a failed or aborted run.
  void PassThrough(vtkPolyData* input, vtkInformationVector* outputVector);

  const char* Task;
  const char* EmptyNote;
  int SurfacePort;
  bool AcceptStrips;
  std::shared_ptr<const shapediameter::FaceGraph> KeptFaceGraph;
  /// The share of the replicated run under way, else nullptr.
  const shapediameter::distributed::ReplicatedShare* ActiveShare = nullptr;
  /// The share of the halo run under way, else nullptr.
  const shapediameter::distributed::HaloShare* ActiveHalo = nullptr;
  /// The error the last run reported (empty: none): under MPI, process 0 sends it to the
  /// other processes, which report it too (distributed::RunOnWholeSurface).
  std::string LastFailure;
};

#endif
