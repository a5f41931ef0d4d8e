// SPDX-License-Identifier: BSD-3-Clause
// SDF: the shape diameter function as one call, exact or adaptive by options.Mode.
//
// ComputeShapeDiameter runs ComputeExactShapeDiameter (ShapeDiameter.h: every origin casts its
// cone, the paper) or ComputeAdaptiveShapeDiameter (AdaptiveShapeDiameter.h: a subset casts,
// the rest is interpolated). What is computed, the parameters and the degenerate cases are
// documented there; this file only chooses. Both modes check the options the same way
// (CheckShapeDiameterOptions: the ranges of either mode whatever Mode), so bad options throw
// the same Error in both.
#pragma once

#include "SDF/ShapeDiameter.h"

namespace shapediameter
{

/// The SDF of every origin, by options.Mode. Throws Error on bad options or
/// inconsistent sizes (and, in Adaptive mode, a missing or inconsistent neighbour graph).
ShapeDiameterResult ComputeShapeDiameter(const RayCaster& caster, const RayOrigins& origins,
  const ShapeDiameterOptions& options, const ParallelFor& parallelFor,
  const ProgressCallback& progress = ProgressCallback());

/// Convenience for the default per-face SDF: builds an EmbreeRayCaster over the mesh and
/// MakeFaceOrigins (plus the triangle adjacency in Adaptive mode), then ComputeShapeDiameter.
/// Throws Error (bad options before the BVH is built, or a bad mesh).
ShapeDiameterResult ComputeFaceShapeDiameter(const PointsView& points,
  const TrianglesView& triangles, const ShapeDiameterOptions& options,
  const ParallelFor& parallelFor, const ProgressCallback& progress = ProgressCallback());

} // namespace shapediameter
