// SPDX-License-Identifier: BSD-3-Clause
#include "SDF/SDF.h"

#include "Mesh/Orientation.h"
#include "RayCasting/EmbreeRayCaster.h"
#include "SDF/AdaptiveShapeDiameter.h"

#include <utility>

namespace shapediameter
{

ShapeDiameterResult ComputeShapeDiameter(const RayCaster& caster, const RayOrigins& origins,
  const ShapeDiameterOptions& options, const ParallelFor& parallelFor,
  const ProgressCallback& progress)
{
  // Both check the options and the origins first, the same way; an unknown Mode reaches the
  // Exact mode's check and throws there.
  if (options.Mode == ShapeDiameterMode::Adaptive)
  {
    return ComputeAdaptiveShapeDiameter(caster, origins, options, parallelFor, progress);
  }
  return ComputeExactShapeDiameter(caster, origins, options, parallelFor, progress);
}

ShapeDiameterResult ComputeFaceShapeDiameter(const PointsView& points,
  const TrianglesView& triangles, const ShapeDiameterOptions& options,
  const ParallelFor& parallelFor, const ProgressCallback& progress)
{
  CheckShapeDiameterOptions(options);
  const EmbreeRayCaster caster(points, triangles);
  RayOrigins origins = MakeFaceOrigins(points, triangles);
  if (options.Mode == ShapeDiameterMode::Adaptive)
  {
    TriangleAdjacency adjacency = BuildTriangleAdjacency(triangles);
    origins.NeighborOffsets = std::move(adjacency.Offsets);
    origins.Neighbors = std::move(adjacency.Neighbors);
  }
  return ComputeShapeDiameter(caster, origins, options, parallelFor, progress);
}

} // namespace shapediameter
