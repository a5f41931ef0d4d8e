// SPDX-License-Identifier: BSD-3-Clause
#include "IO/MeshPieces.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>

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

/// The 21 low bits of `value` spread to every third bit (bit i moves to bit 3i).
std::uint64_t SpreadBits(std::uint64_t value)
{
  value &= 0x1fffffu;
  value = (value | value << 32) & 0x1f00000000ffffULL;
  value = (value | value << 16) & 0x1f0000ff0000ffULL;
  value = (value | value << 8) & 0x100f00f00f00f00fULL;
  value = (value | value << 4) & 0x10c30c30c30c30c3ULL;
  value = (value | value << 2) & 0x1249249249249249ULL;
  return value;
}

} // namespace

std::vector<std::int64_t> MortonFaceOrder(const OFFMesh& mesh)
{
  const std::size_t faceCount = mesh.FaceCount();
  std::vector<std::array<double, 3>> centroids(faceCount, std::array<double, 3>{ 0.0, 0.0, 0.0 });
  std::array<double, 3> low{}, high{};
  low.fill(std::numeric_limits<double>::infinity());
  high.fill(-std::numeric_limits<double>::infinity());
  for (std::size_t f = 0; f < faceCount; ++f)
  {
    const auto begin = static_cast<std::size_t>(mesh.FaceOffsets[f]);
    const auto end = static_cast<std::size_t>(mesh.FaceOffsets[f + 1]);
    if (begin == end)
    {
      continue;
    }
    for (std::size_t i = begin; i < end; ++i)
    {
      const auto vertex = static_cast<std::size_t>(mesh.FaceConnectivity[i]);
      for (int axis = 0; axis < 3; ++axis)
      {
        centroids[f][axis] += mesh.Points[3 * vertex + axis];
      }
    }
    for (int axis = 0; axis < 3; ++axis)
    {
      centroids[f][axis] /= static_cast<double>(end - begin);
      low[axis] = std::min(low[axis], centroids[f][axis]);
      high[axis] = std::max(high[axis], centroids[f][axis]);
    }
  }
  // One scale for all axes (a cube), so the curve's cells are cubes and pieces stay round.
  double extent = 0.0;
  for (int axis = 0; axis < 3; ++axis)
  {
    extent = std::max(extent, high[axis] - low[axis]);
  }
  constexpr double cells = static_cast<double>((1u << 21) - 1);
  const double scale = extent > 0.0 && std::isfinite(extent) ? cells / extent : 0.0;
  std::vector<std::pair<std::uint64_t, std::int64_t>> keyed(faceCount);
  for (std::size_t f = 0; f < faceCount; ++f)
  {
    std::uint64_t code = 0;
    const bool hasVertices = mesh.FaceOffsets[f] != mesh.FaceOffsets[f + 1];
    for (int axis = 0; hasVertices && axis < 3; ++axis)
    {
      const double cell = std::clamp((centroids[f][axis] - low[axis]) * scale, 0.0, cells);
      code |= SpreadBits(static_cast<std::uint64_t>(cell)) << axis;
    }
    keyed[f] = { code, static_cast<std::int64_t>(f) };
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<std::int64_t> order(faceCount);
  std::transform(keyed.begin(), keyed.end(), order.begin(), [](const auto& entry) { return entry.second; });
  return order;
}

MeshPiece ExtractFacePiece(const OFFMesh& mesh, int piece, int pieces, PieceOrder order)
{
  if (pieces < 1 || piece < 0 || piece >= pieces)
  {
    throw std::invalid_argument("piece " + std::to_string(piece) + " of " + std::to_string(pieces) +
      " does not exist");
  }
  const std::size_t faceCount = mesh.FaceCount();
  const std::size_t vertexCount = mesh.VertexCount();
  // 64-bit products: F·pieces stays far below 2^63 for any mesh that fits in memory.
  const auto firstPosition = static_cast<std::size_t>(
    static_cast<unsigned long long>(faceCount) * static_cast<unsigned>(piece) / static_cast<unsigned>(pieces));
  const auto endPosition = static_cast<std::size_t>(
    static_cast<unsigned long long>(faceCount) * static_cast<unsigned>(piece + 1) / static_cast<unsigned>(pieces));

  // The faces of this piece, in file order.
  std::vector<std::size_t> faces;
  faces.reserve(endPosition - firstPosition);
  if (order == PieceOrder::FileOrder)
  {
    faces.resize(endPosition - firstPosition);
    std::iota(faces.begin(), faces.end(), firstPosition);
  }
  else
  {
    const std::vector<std::int64_t> curve = MortonFaceOrder(mesh);
    for (std::size_t position = firstPosition; position < endPosition; ++position)
    {
      faces.push_back(static_cast<std::size_t>(curve[position]));
    }
    std::sort(faces.begin(), faces.end());
  }

  // Which vertices this piece keeps, in file order: those its faces use; piece 0 also keeps
  // the vertices that no face uses.
  std::vector<char> kept(vertexCount, piece == 0 ? 1 : 0);
  if (piece == 0)
  {
    std::vector<char> used(vertexCount, 0);
    for (const std::int64_t vertex : mesh.FaceConnectivity)
    {
      used[static_cast<std::size_t>(vertex)] = 1;
    }
    for (std::size_t v = 0; v < vertexCount; ++v)
    {
      kept[v] = static_cast<char>(!used[v]);
    }
  }
  std::size_t connectivitySize = 0;
  for (const std::size_t f : faces)
  {
    for (auto i = static_cast<std::size_t>(mesh.FaceOffsets[f]); i < static_cast<std::size_t>(mesh.FaceOffsets[f + 1]); ++i)
    {
      kept[static_cast<std::size_t>(mesh.FaceConnectivity[i])] = 1;
      ++connectivitySize;
    }
  }

  MeshPiece result;
  std::vector<std::int64_t> localIndex(vertexCount, -1);
  for (std::size_t v = 0; v < vertexCount; ++v)
  {
    if (!kept[v])
    {
      continue;
    }
    localIndex[v] = static_cast<std::int64_t>(result.GlobalPointIds.size());
    result.GlobalPointIds.push_back(static_cast<std::int64_t>(v));
    AppendTuple(result.Mesh.Points, mesh.Points, v, 3);
    if (!mesh.VertexNormals.empty())
    {
      AppendTuple(result.Mesh.VertexNormals, mesh.VertexNormals, v, 3);
    }
    if (!mesh.VertexColors.empty())
    {
      AppendTuple(result.Mesh.VertexColors, mesh.VertexColors, v, 4);
    }
  }

  result.Mesh.FaceOffsets.reserve(faces.size() + 1);
  result.Mesh.FaceOffsets.push_back(0);
  result.Mesh.FaceConnectivity.reserve(connectivitySize);
  for (const std::size_t f : faces)
  {
    for (auto i = static_cast<std::size_t>(mesh.FaceOffsets[f]); i < static_cast<std::size_t>(mesh.FaceOffsets[f + 1]); ++i)
    {
      result.Mesh.FaceConnectivity.push_back(localIndex[static_cast<std::size_t>(mesh.FaceConnectivity[i])]);
    }
    result.Mesh.FaceOffsets.push_back(static_cast<std::int64_t>(result.Mesh.FaceConnectivity.size()));
    result.GlobalFaceIds.push_back(static_cast<std::int64_t>(f));
    if (!mesh.FaceColors.empty())
    {
      AppendTuple(result.Mesh.FaceColors, mesh.FaceColors, f, 4);
    }
  }
  return result;
}

} // namespace shapediameter
