// SPDX-License-Identifier: BSD-3-Clause
// The chunked piece reader's oracle, shared by TestOFFPieceReader and the seeded OFF fuzz test:
// ParseOFFPiece must give what ExtractFacePiece(ParseOFF(...)) gives, the same piece or the
// same error.
#pragma once

#include "IO/MeshPieces.h"
#include "IO/OFFParser.h"

#include <cstddef>
#include <cstdint>
#include <exception>
#include <string>
#include <typeinfo>
#include <vector>

namespace shapediameter::testing
{

/// A piece, or the error that stopped reading it ("<type>: <what()>").
struct PieceOutcome
{
  MeshPiece Piece;
  std::string Error;
};

template <typename Read>
PieceOutcome PieceOrError(Read read)
{
  PieceOutcome outcome;
  try
  {
    outcome.Piece = read();
  }
  catch (const OFFParseError& error)
  {
    outcome.Error = std::string("OFFParseError: ") + error.what();
  }
  catch (const std::exception& error)
  {
    outcome.Error = std::string(typeid(error).name()) + ": " + error.what();
  }
  return outcome;
}

/// Empty when both outcomes are the same error or the same piece, else the first difference.
inline std::string OutcomeDifference(const PieceOutcome& expected, const PieceOutcome& actual)
{
  if (expected.Error != actual.Error)
  {
    return "error '" + actual.Error + "', expected '" + expected.Error + "'";
  }
  const auto differ = [](const char* name, const auto& a, const auto& b)
  { return a == b ? std::string() : std::string(name) + " differ"; };
  const MeshPiece& a = expected.Piece;
  const MeshPiece& b = actual.Piece;
  for (const std::string& difference :
    { differ("points", a.Mesh.Points, b.Mesh.Points), differ("vertex normals", a.Mesh.VertexNormals, b.Mesh.VertexNormals),
      differ("vertex colours", a.Mesh.VertexColors, b.Mesh.VertexColors),
      differ("face offsets", a.Mesh.FaceOffsets, b.Mesh.FaceOffsets),
      differ("face connectivity", a.Mesh.FaceConnectivity, b.Mesh.FaceConnectivity),
      differ("face colours", a.Mesh.FaceColors, b.Mesh.FaceColors),
      differ("global point ids", a.GlobalPointIds, b.GlobalPointIds),
      differ("global face ids", a.GlobalFaceIds, b.GlobalFaceIds) })
  {
    if (!difference.empty())
    {
      return difference;
    }
  }
  return {};
}

/// Empty when ParseOFFPiece(text, piece, pieces, order, chunkBytes) gives what
/// ExtractFacePiece(ParseOFF(text), piece, pieces, order) gives, else what differs.
inline std::string PieceDifference(
  const std::string& text, int piece, int pieces, PieceOrder order, std::size_t chunkBytes)
{
  const PieceOutcome whole = PieceOrError([&] {
    return ExtractFacePiece(ParseOFF(text.data(), text.size()), piece, pieces, order);
  });
  const PieceOutcome chunked =
    PieceOrError([&] { return ParseOFFPiece(text.data(), text.size(), piece, pieces, order, chunkBytes); });
  const std::string difference = OutcomeDifference(whole, chunked);
  return difference.empty() ? difference
                            : difference + " (piece " + std::to_string(piece) + " of " + std::to_string(pieces) +
      (order == PieceOrder::Spatial ? ", spatial" : ", file order") + ", chunks of " +
      std::to_string(chunkBytes) + " bytes)";
}

} // namespace shapediameter::testing
