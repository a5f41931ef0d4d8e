// SPDX-License-Identifier: BSD-3-Clause
// Face adjacency of a polygon mesh, per-face geometry, dihedral angles and
// geodesic neighbourhoods over the dual graph.
//
// What it computes
//   The dual graph of a polygon surface: one node per face, one adjacency per pair of
//   faces sharing an edge, in compressed sparse row (CSR) form. Per face: centre, unit
//   normal, area, a degenerate flag. Per adjacency: shared-edge length, distance between
//   the two face centres, the angle between the two face normals and a concave flag.
//   Used by the SDF neighbour fill, the bilateral smoothing (Shapira et al. 2008, sec. 3),
//   and the graph cut's smoothness term (sec. 4, theta(f, g)).
//
// Input
//   Points (n x 3) and polygons given as CSR: faceOffsets has faceCount + 1 entries,
//   offsets[0] = 0, non-decreasing, offsets[faceCount] = faceConnectivity.size(); face f
//   uses the point indices faceConnectivity[offsets[f] .. offsets[f + 1]). Any polygon size
//   is accepted; an empty faceOffsets vector means "no faces". Triangles can be passed as
//   a TrianglesView instead. Polygons are expected counter-clockwise seen from outside
//   (right-hand rule gives the outward normal).
//
// Definitions
//   centre        mean of the polygon's vertices (the area centroid for triangles).
//   normal, area  Newell's method: the area vector 1/2 sum (p_i - c) x (p_i+1 - c) is exact
//                 for planar polygons and a robust mean plane normal for warped ones.
//   degenerate    |area vector| <= 1e-12 * sum of squared side lengths, or fewer than three
//                 vertices. A degenerate face gets normal (0, 0, 0), area 0, keeps its centre
//                 and its adjacencies; every angle involving it is 0 and it is never concave.
//   NormalAngle   angle between the two unit normals, in [0, pi] (atan2 form: accurate near 0
//                 and pi). The interior dihedral angle of the solid is pi - NormalAngle at a
//                 convex edge and pi + NormalAngle at a concave one (see DihedralAngle()).
//   Concave       1 when the two faces fold towards their outward side (a valley):
//                 n_f . (c_g - m) + n_g . (c_f - m) > 0, m the midpoint of the shared edge.
//                 This is only meaningful with consistently oriented, outward normals.
//
// Degenerate input, all defined
//   - Open boundary edge (one polygon side): no adjacency; counted in BoundaryEdgeCount.
//   - Non-manifold edge (three or more sides): every pair of those faces becomes adjacent;
//     counted in NonManifoldEdgeCount. The graph stays symmetric.
//   - Two faces sharing several edges: one adjacency, SharedEdgeLength is the sum, the
//     concavity test uses the shared edge with the smallest (lower, higher) vertex pair,
//     so that both directions of the adjacency agree.
//   - Repeated consecutive vertices (zero-length sides) are skipped; a face is never its own
//     neighbour.
//   - Isolated faces and several components: faces simply have no / disjoint neighbours.
//   Neighbors of each face are sorted by face index (deterministic, split-independent).
//
// Bad input (throws Error): malformed offsets, point index out of range,
// non-finite coordinates of a referenced point.
//
// Cost: O(H log d) with H the number of polygon sides and d the vertex valence (half-edges
// are bucketed by their lower vertex with a counting sort, buckets sorted independently).
// The adjacency lists are written in one parallel pass into slots sized by an upper bound,
// and each pair's geometry (angle, concavity, centre distance) is computed once, by its lower
// face, then copied to the mirror entry (faster than a count-then-fill construction, with the
// same output; measurements: docs/performance.md).
#pragma once

#include "Errors.h"
#include "ExactSum.h"
#include "Mesh/MeshTypes.h"
#include "Parallel.h"
#include "ProcessGroup.h"

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <vector>

namespace shapediameter
{

struct FaceGraph
{
  // ---- per face (faceCount rows / entries)
  PointMatrix Centers;
  /// Unit normals; (0, 0, 0) for degenerate faces.
  PointMatrix Normals;
  std::vector<double> Areas;
  /// 1 for degenerate faces (zero area or fewer than 3 vertices).
  std::vector<std::uint8_t> Degenerate;

  // ---- adjacency, CSR: the neighbours of face f are the entries [Offsets[f], Offsets[f+1])
  std::vector<std::int64_t> Offsets;
  std::vector<std::int64_t> Neighbors;
  /// Total length of the edges shared with that neighbour.
  std::vector<double> SharedEdgeLengths;
  /// |c_f - c_g|, the dual-graph edge length used by the geodesic search.
  std::vector<double> CenterDistances;
  /// Angle between the two face normals in [0, pi].
  std::vector<double> NormalAngles;
  /// 1 at a concave (valley) adjacency, 0 at a convex or flat one.
  std::vector<std::uint8_t> Concave;

  // ---- whole-mesh measures (scale references for the other steps)
  /// Mean length of all polygon sides with distinct endpoints (the face perimeters summed
  /// exactly, so independent of the face order); 0 without such sides.
  double MeanEdgeLength = 0.0;
  /// Diagonal of the bounding box of the points referenced by faces; 0 without faces.
  double BoundingBoxDiagonal = 0.0;
  /// Undirected edges (distinct vertex pairs) by number of incident faces.
  std::size_t EdgeCount = 0;
  std::size_t BoundaryEdgeCount = 0;
  std::size_t NonManifoldEdgeCount = 0;
  std::size_t DegenerateFaceCount = 0;

  std::size_t FaceCount() const { return Areas.size(); }
  std::int64_t NeighborBegin(std::int64_t face) const { return Offsets[static_cast<std::size_t>(face)]; }
  std::int64_t NeighborEnd(std::int64_t face) const { return Offsets[static_cast<std::size_t>(face) + 1]; }
  /// Interior dihedral angle of adjacency `entry` in (0, 2 pi): pi at a flat edge, below pi
  /// at a convex edge, above pi at a concave one.
  double DihedralAngle(std::int64_t entry) const;
};

/// Builds the face graph of polygons given in CSR form (see the header comment).
FaceGraph BuildFaceGraph(const PointsView& points, const std::vector<std::int64_t>& faceOffsets,
  const std::vector<std::int64_t>& faceConnectivity, const ParallelFor& parallelFor = SerialFor);

/**
 * The face graph of this input, built once per surface in a chain: when a graph built here
 * from identical input is still held (by any owner of a pointer this function returned),
 * that graph; otherwise a new BuildFaceGraph, which later calls with identical input get for
 * as long as someone holds it. The smoothing and the partition of one chain see the same
 * surface and so build it once (docs/performance.md, "One face graph per chain").
 *
 * Identical input: the same point count, offsets and connectivity sizes, and the same two
 * independent 64-bit hashes over the bytes of the coordinates (all points, referenced or not)
 * and of the offsets and connectivity; a changed coordinate, index or face gives a new graph
 * (a different input with the same 128 bits of hash is the only way to be handed a wrong one).
 * Hashing costs about 1 % of a build. The registry keeps only weak references: it never keeps
 * a graph alive. Thread-safe; two callers building the same graph concurrently both build it.
 * Throws what BuildFaceGraph throws (nothing is then registered).
 */
std::shared_ptr<const FaceGraph> SharedFaceGraph(const PointsView& points,
  const std::vector<std::int64_t>& faceOffsets, const std::vector<std::int64_t>& faceConnectivity,
  const ParallelFor& parallelFor = SerialFor);

/// The side lengths of some faces, for a mean edge length over several processes' faces.
struct SideLengthSum
{
  /// The exact sum of the faces' perimeters (each the sum of its sides that are edges).
  ExactSum Length;
  /// The number of those sides.
  std::int64_t Count = 0;
};

/**
 * The perimeters and side counts of the faces f with `faces[f] != 0`, the terms that
 * FaceGraph::MeanEdgeLength adds: the mean edge length of a surface split between processes
 * is MeanEdgeLengthOf(SumOverProcesses(each's Length), the sum of the Counts), equal bit for
 * bit to BuildFaceGraph's on the whole surface. `faces` has one entry per face. Throws what
 * BuildFaceGraph throws on malformed input.
 */
SideLengthSum SumSideLengths(const PointsView& points, const std::vector<std::int64_t>& faceOffsets,
  const std::vector<std::int64_t>& faceConnectivity, const std::vector<std::uint8_t>& faces);

/// The mean of `count` sides of total length `length` (0 without sides).
inline double MeanEdgeLengthOf(double length, std::int64_t count)
{
  return count > 0 ? length / static_cast<double>(count) : 0.0;
}

/// FaceGraph::MeanEdgeLength of a surface split between the processes of `group`, each
/// passing its input and flagging its own faces in `faces`: equal bit for bit to the serial
/// value on the whole surface. Collective; throws what SumSideLengths throws before it.
double MeanEdgeLengthOverProcesses(const PointsView& points, const std::vector<std::int64_t>& faceOffsets,
  const std::vector<std::int64_t>& faceConnectivity, const std::vector<std::uint8_t>& faces,
  const ProcessGroup& group);

/// A triangle mesh's faces in that CSR form (3 corners per face; both empty without triangles).
void TriangleFaces(
  const TrianglesView& triangles, std::vector<std::int64_t>& faceOffsets, std::vector<std::int64_t>& faceConnectivity);

/// Same for a triangle mesh.
FaceGraph BuildFaceGraph(
  const PointsView& points, const TrianglesView& triangles, const ParallelFor& parallelFor = SerialFor);

/// Connected components of the face graph.
struct FaceComponents
{
  /// Component of each face, numbered 0, 1, ... in order of their lowest face index.
  std::vector<std::int64_t> Labels;
  std::size_t Count = 0;
};

FaceComponents ComputeFaceComponents(const FaceGraph& graph);

/// A face reached by a geodesic search and its distance from the source face.
struct GeodesicNeighbor
{
  std::int64_t Face;
  double Distance;
};

/// Approximate geodesic neighbourhoods: Dijkstra over the dual graph (face centres joined
/// across shared edges by straight segments, weight CenterDistances).
///
/// The dual path length is never shorter than the straight line between the centres and
/// over-estimates the surface geodesic by the zig-zag across faces: a few percent to 20 %
/// on irregular triangulations; on a regular right-triangle grid, in directions crossing
/// the diagonals, about 1.7x (up to 2.1x for the nearest faces). For the small
/// neighbourhoods it is used for, this is the usual approximation (no exact geodesics).
/// Faces beyond a non-manifold edge are reached (the graph links them); other components
/// never are.
///
/// One object per thread: it owns scratch memory (a small hash map and a heap) sized by the
/// neighbourhood, not by the mesh, so creating one per ParallelFor range is cheap.
class DualGeodesicSearch
{
public:
  explicit DualGeodesicSearch(const FaceGraph& graph);

  /// Fills `neighbors` (cleared first) with the faces whose dual distance from `source`
  /// is <= radius, nearest first (ties by face index), excluding the source itself, at
  /// most maxNeighbors of them. Deterministic. An invalid source face gives no neighbours.
  void Run(std::int64_t source, double radius, std::size_t maxNeighbors, std::vector<GeodesicNeighbor>& neighbors);

private:
  struct Slot
  {
    std::int64_t Face;
    double Distance;
    bool Settled;
  };
  Slot* FindOrInsert(std::int64_t face);
  void ClearTable();
  void Grow();

  const FaceGraph& Graph;
  std::vector<Slot> Table;
  std::vector<std::size_t> UsedSlots;
  std::vector<std::pair<double, std::int64_t>> Heap;
};

} // namespace shapediameter
