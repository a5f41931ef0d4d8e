// SPDX-License-Identifier: BSD-3-Clause
// Splitting a parsed mesh into the pieces of a distributed (MPI) run.
#pragma once

#include "OFFParser.h"

#include <cstdint>
#include <vector>

namespace shapediameter
{

/// One piece of a mesh: a self-contained mesh plus, for each of its vertices and faces, the
/// index it has in the whole mesh (what VTK calls global ids).
struct MeshPiece
{
  OFFMesh mesh;
  std::vector<std::int64_t> globalPointIds; ///< one per vertex of `mesh`, increasing
  std::vector<std::int64_t> globalFaceIds;  ///< one per face of `mesh`, consecutive
};

/**
 * Piece `piece` of `pieces`: the faces [F·piece/pieces, F·(piece+1)/pieces) in file order
 * (contiguous ranges, sizes differing by at most one; pieces beyond F are empty), with the
 * vertices they use in file order and every per-vertex and per-face attribute. Vertices no
 * face uses go to piece 0, so the pieces together hold the whole file. Vertices on a border
 * between pieces appear in each piece that uses them, with the same global id.
 * Throws std::invalid_argument unless 0 <= piece < pieces.
 */
MeshPiece ExtractFacePiece(const OFFMesh& mesh, int piece, int pieces);

} // namespace shapediameter
