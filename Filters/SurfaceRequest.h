// SPDX-License-Identifier: BSD-3-Clause
// What vtkSDFSurfaceAlgorithm hands to a filter's body (ExecuteSurface).
// Private to the module: not installed, not wrapped.
#pragma once

#include "Errors.h" // a body throws shapediameter::Error on bad input
#include "Parallel.h"

class vtkInformationVector;
class vtkPolyData;

namespace shapediameter::distributed
{
struct ReplicatedShare; // DistributedSupport.h
struct HaloShare;       // DistributedSupport.h
}

namespace shapediameter::adapter
{

struct SurfaceRequest
{
  /// Input port 0: at least one cell and one polygon (or triangle strip, if accepted).
  vtkPolyData* Input;
  /// The surface output port, a shallow copy of Input on entry.
  vtkPolyData* Output;
  /// All ports, for the filters with further inputs or outputs.
  vtkInformationVector** InputVector;
  vtkInformationVector* OutputVector;
  /// The core's parallel loop with the filter's NumberOfThreads.
  ParallelFor Parallel;
  /// In a replicated distributed run (vtkSDFSurfaceAlgorithm::CanRunReplicated): Input is the
  /// whole surface on every process, and the body computes the cells this share owns and
  /// combines them (DistributedSupport.h). nullptr otherwise.
  const distributed::ReplicatedShare* Share = nullptr;
  /// In a halo run (vtkSDFSurfaceAlgorithm::CanRunWithHalo): Input is this process's own cells
  /// plus a halo, the body computes the cells flagged as its own, with the whole surface's
  /// measures combined over the share's group (DistributedSupport.h). nullptr otherwise.
  const distributed::HaloShare* Halo = nullptr;
};

} // namespace shapediameter::adapter
