// SPDX-License-Identifier: BSD-3-Clause
// Orientation: make triangle winding consistent and outward, per connected component.
//
// The SDF casts its cone around the INWARD normal, so a triangle wound the wrong way
// casts its rays out of the object and finds nothing (or the wrong side). Scans and
// converted meshes often mix windings; this step repairs that before ray casting.
//
// What it computes
//   1. Consistency: a breadth-first walk over edge-adjacent triangles (in triangle order,
//      so the result is deterministic) flips a neighbour whose shared edge runs in the
//      same direction as ours. Only manifold edges (exactly two triangles) propagate
//      orientation; non-manifold and boundary edges do not.
//   2. Outwardness: per component, the signed volume sum (1/6) v0 . (v1 x v2) taken about
//      the component's centroid. Negative = the component points inward: all its
//      triangles are flipped. For a closed component this is exact; for an open one (holes)
//      it is a heuristic that is right whenever the holes are small compared with the
//      surface, which is the case this product meets (scans with holes). A component whose
//      |volume| is below 1e-9 A^1.5 (A its area: flat patches, single triangles) encloses
//      nothing and keeps its winding.
//   A component whose orientation cannot be made consistent (a Moebius band, a Klein
//   bottle) keeps the first assignment found; it is counted in NonOrientableComponents.
//
// Degenerate triangles take part like any other (their edges still connect neighbours).
#pragma once

#include "Mesh/MeshTypes.h"

#include <cstdint>
#include <vector>

namespace shapediameter
{

struct OrientationResult
{
  /// 1 for every triangle whose winding must be reversed.
  std::vector<std::uint8_t> Flip;
  std::size_t FlippedTriangles = 0;
  std::size_t ComponentCount = 0;
  /// Components made consistent by flipping some, but not all, of their triangles.
  std::size_t InconsistentComponents = 0;
  /// Components whose triangles were all reversed because they pointed inward.
  std::size_t InwardComponents = 0;
  std::size_t NonOrientableComponents = 0;
};

/// Triangles sharing a manifold edge (exactly two triangles), CSR: the neighbours of t are
/// Neighbors[Offsets[t] .. Offsets[t + 1]), sorted. SameDirection tells, per entry, whether
/// the two triangles run the shared edge the same way (inconsistent winding).
struct TriangleAdjacency
{
  std::vector<std::int64_t> Offsets;
  std::vector<std::int64_t> Neighbors;
  std::vector<std::uint8_t> SameDirection;
};

/// The manifold-edge adjacency of a triangle mesh: the half-edges bucketed by their lower
/// vertex, linear in the mesh; each triangle's neighbours in increasing order. Throws
/// std::out_of_range on a negative vertex index.
TriangleAdjacency BuildTriangleAdjacency(const TrianglesView& triangles);

/// Computes which triangles to flip (see the header comment). Throws std::out_of_range on a
/// vertex index out of range.
OrientationResult OrientOutward(const PointsView& points, const TrianglesView& triangles);

/// The same with an adjacency already built by BuildTriangleAdjacency (callers that need the
/// adjacency for something else build it once).
OrientationResult OrientOutward(
  const PointsView& points, const TrianglesView& triangles, const TriangleAdjacency& adjacency);

/// Applies the flips in place: reverses the vertex order (a, b, c) -> (c, b, a) of every
/// flipped triangle, as reversing the polygon it came from does.
void ApplyFlips(TriangleMatrix& triangles, const std::vector<std::uint8_t>& flip);

} // namespace shapediameter
