// SPDX-License-Identifier: BSD-3-Clause
// Splitting a parsed mesh into the pieces of a distributed (MPI) run.
#pragma once

#include "IO/OFFParser.h"

#include <cstdint>
#include <vector>

namespace shapediameter
{

/// One piece of a mesh: a self-contained mesh plus, for each of its vertices and faces, the
/// index it has in the whole mesh (what VTK calls global ids).
struct MeshPiece
{
  OFFMesh Mesh;
  std::vector<std::int64_t> GlobalPointIds; ///< one per vertex of `Mesh`, increasing
  std::vector<std::int64_t> GlobalFaceIds;  ///< one per face of `Mesh`, increasing
};

/// How faces are dealt out to the pieces.
enum class PieceOrder
{
  /// Contiguous ranges of the file's face order: cheap, but file order is rarely spatially
  /// compact (docs/distributed.md).
  FileOrder,
  /// Contiguous ranges of a Morton (Z-order) curve through the face centroids: each piece is
  /// a compact region of space, as a spatial redistribution would give, without any exchange.
  Spatial
};

/**
 * Piece `piece` of `pieces`: the faces at positions [F·piece/pieces, F·(piece+1)/pieces) of
 * `order` (sizes differing by at most one; pieces beyond F are empty), written in file order,
 * with the vertices they use in file order and every per-vertex and per-face attribute.
 * Vertices no face uses go to piece 0, so the pieces together hold the whole file. Vertices on
 * a border between pieces appear in each piece that uses them, with the same global id.
 * Deterministic: the Morton order breaks ties by file index.
 * Throws std::invalid_argument unless 0 <= piece < pieces.
 */
MeshPiece ExtractFacePiece(const OFFMesh& mesh, int piece, int pieces, PieceOrder order = PieceOrder::FileOrder);

/// The faces of `mesh` along a Morton curve through their centroids (21 bits per axis over the
/// bounding cube of the centroids), ties by file index. Faces without vertices sort first.
std::vector<std::int64_t> MortonFaceOrder(const OFFMesh& mesh);

} // namespace shapediameter
