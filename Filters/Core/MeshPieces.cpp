// SPDX-License-Identifier: BSD-3-Clause
#include "MeshPieces.h"

#include <cstddef>
#include <stdexcept>
#include <string>

namespace shapediameter
{

namespace
{

template <typename T>
void AppendTuple(std::vector<T>& to, const std::vector<T>& from, std::size_t index, std::size_t width)
{
  to.insert(to.end(), from.begin() + static_cast<std::ptrdiff_t>(index * width),
    from.begin() + static_cast<std::ptrdiff_t>((index + 1) * width));
}

} // namespace

MeshPiece ExtractFacePiece(const OFFMesh& mesh, int piece, int pieces)
{
  if (pieces < 1 || piece < 0 || piece >= pieces)
  {
    throw std::invalid_argument("piece " + std::to_string(piece) + " of " + std::to_string(pieces) +
      " does not exist");
  }
  const std::size_t faceCount = mesh.FaceCount();
  const std::size_t vertexCount = mesh.VertexCount();
  // 64-bit products: F·pieces stays far below 2^63 for any mesh that fits in memory.
  const auto firstFace = static_cast<std::size_t>(
    static_cast<unsigned long long>(faceCount) * static_cast<unsigned>(piece) / static_cast<unsigned>(pieces));
  const auto endFace = static_cast<std::size_t>(
    static_cast<unsigned long long>(faceCount) * static_cast<unsigned>(piece + 1) / static_cast<unsigned>(pieces));

  // Which vertices this piece keeps, in file order: those its faces use; piece 0 also keeps
  // the vertices that no face uses.
  std::vector<char> kept(vertexCount, piece == 0 ? 1 : 0);
  if (piece == 0)
  {
    std::vector<char> used(vertexCount, 0);
    for (const std::int64_t vertex : mesh.faceConnectivity)
    {
      used[static_cast<std::size_t>(vertex)] = 1;
    }
    for (std::size_t v = 0; v < vertexCount; ++v)
    {
      kept[v] = static_cast<char>(!used[v]);
    }
  }
  const auto connectivityBegin = static_cast<std::size_t>(mesh.faceOffsets.empty() ? 0 : mesh.faceOffsets[firstFace]);
  const auto connectivityEnd = static_cast<std::size_t>(mesh.faceOffsets.empty() ? 0 : mesh.faceOffsets[endFace]);
  for (std::size_t i = connectivityBegin; i < connectivityEnd; ++i)
  {
    kept[static_cast<std::size_t>(mesh.faceConnectivity[i])] = 1;
  }

  MeshPiece result;
  std::vector<std::int64_t> localIndex(vertexCount, -1);
  for (std::size_t v = 0; v < vertexCount; ++v)
  {
    if (!kept[v])
    {
      continue;
    }
    localIndex[v] = static_cast<std::int64_t>(result.globalPointIds.size());
    result.globalPointIds.push_back(static_cast<std::int64_t>(v));
    AppendTuple(result.mesh.points, mesh.points, v, 3);
    if (!mesh.vertexNormals.empty())
    {
      AppendTuple(result.mesh.vertexNormals, mesh.vertexNormals, v, 3);
    }
    if (!mesh.vertexColors.empty())
    {
      AppendTuple(result.mesh.vertexColors, mesh.vertexColors, v, 4);
    }
  }

  result.mesh.faceOffsets.reserve(endFace - firstFace + 1);
  result.mesh.faceOffsets.push_back(0);
  result.mesh.faceConnectivity.reserve(connectivityEnd - connectivityBegin);
  for (std::size_t f = firstFace; f < endFace; ++f)
  {
    for (auto i = static_cast<std::size_t>(mesh.faceOffsets[f]); i < static_cast<std::size_t>(mesh.faceOffsets[f + 1]); ++i)
    {
      result.mesh.faceConnectivity.push_back(localIndex[static_cast<std::size_t>(mesh.faceConnectivity[i])]);
    }
    result.mesh.faceOffsets.push_back(static_cast<std::int64_t>(result.mesh.faceConnectivity.size()));
    result.globalFaceIds.push_back(static_cast<std::int64_t>(f));
    if (!mesh.faceColors.empty())
    {
      AppendTuple(result.mesh.faceColors, mesh.faceColors, f, 4);
    }
  }
  return result;
}

} // namespace shapediameter
