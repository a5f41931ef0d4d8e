// SPDX-License-Identifier: BSD-3-Clause
// The pieces of a distributed (MPI) run: split from a parsed mesh (ExtractFacePiece), or read
// from an OFF file keeping only the piece (ReadOFFPiece), with the same result.
#pragma once

#include "IO/OFFParser.h"

#include <cstddef>
#include <cstdint>
#include <string>
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
  /// Contiguous ranges of a Morton (Z-order) curve through the face centroids (over the
  /// bounding cube of the mesh's points): each piece is
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

/**
 * ExtractFacePiece(ReadOFFFile(path), piece, pieces, order), identical in every array and in
 * every error (the same OFFParseError messages, prefixed with the path; std::invalid_argument
 * for a piece that does not exist), without holding the file or the whole mesh: the file is
 * read chunkBytes at a time (ScanOFF, RescanOFF in OFFParser.h), in two or three passes:
 *   1. every line checked as ParseOFF checks it; kept: every point (3 doubles per vertex) and,
 *      for PieceOrder::Spatial, each face's Morton key (8 bytes per face; the points, and with
 *      them the curve's cube, come before the faces), from which the piece's faces are chosen
 *      (a bit per face; the keys are then released);
 *   2. the faces again: the piece's faces with their colours, and which vertices they use;
 *   3. (NOFF / COFF only) the vertices again: the normals and colours of the piece's vertices.
 * Memory besides the piece: the points, a chunk plus the longest line, one byte per vertex,
 * and while the faces are chosen two keys per face. Cost: reading the file 2-3 times instead
 * of once (832k faces, piece 0 of 2 / of 4: 0.20 / 0.17 s, 0.24-0.27 / 0.21-0.22 s with the
 * keys in a pass of their own; the whole file parsed once: 0.09 s).
 * A file changed between the passes gives an OFFParseError or a piece of the changed file,
 * never an out-of-range index.
 */
MeshPiece ReadOFFPiece(const std::string& path, int piece, int pieces, PieceOrder order = PieceOrder::FileOrder,
  std::size_t chunkBytes = kOFFChunkBytes);

/// ReadOFFPiece on text held in memory (ParseOFF's errors, without a path), read through the
/// same chunked passes: what the tests compare against ExtractFacePiece(ParseOFF(...)).
MeshPiece ParseOFFPiece(const char* data, std::size_t size, int piece, int pieces,
  PieceOrder order = PieceOrder::FileOrder, std::size_t chunkBytes = kOFFChunkBytes);

/// The faces of `mesh` along a Morton curve through their centroids (21 bits per axis over the
/// bounding cube of the mesh's points, used or not), ties by file index. Faces without
/// vertices sort first.
std::vector<std::int64_t> MortonFaceOrder(const OFFMesh& mesh);

} // namespace shapediameter
