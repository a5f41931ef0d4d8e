// SPDX-License-Identifier: BSD-3-Clause
#include "IO/MeshPieces.h"

#include "Release.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <functional>
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

using Vector3 = std::array<double, 3>;

/// Mean of the `size` (> 0) points of `vertices`; points holds x y z per vertex.
Vector3 Centroid(const double* points, const std::int64_t* vertices, std::size_t size)
{
  Vector3 centroid{ 0.0, 0.0, 0.0 };
  for (std::size_t i = 0; i < size; ++i)
  {
    const auto vertex = static_cast<std::size_t>(vertices[i]);
    for (int axis = 0; axis < 3; ++axis)
    {
      centroid[axis] += points[3 * vertex + axis];
    }
  }
  for (int axis = 0; axis < 3; ++axis)
  {
    centroid[axis] /= static_cast<double>(size);
  }
  return centroid;
}

/// The Morton curve through the face centroids over the bounding cube of the mesh's points:
/// every point first (Add; an OFF file lists them before the faces, so a reader knows the
/// cube when the faces come), then the key of each face's centroid (Key). The one definition
/// of the order MortonFaceOrder and ReadOFFPiece share.
class MortonCurve
{
public:
  MortonCurve()
  {
    this->Low.fill(std::numeric_limits<double>::infinity());
    this->High.fill(-std::numeric_limits<double>::infinity());
  }

  void Add(const double* point)
  {
    for (int axis = 0; axis < 3; ++axis)
    {
      this->Low[axis] = std::min(this->Low[axis], point[axis]);
      this->High[axis] = std::max(this->High[axis], point[axis]);
    }
  }

  /// 21 bits per axis over the bounding cube of the points added (all of them before the first
  /// key); a face without vertices: 0.
  std::uint64_t Key(const double* points, const std::int64_t* vertices, std::size_t size)
  {
    if (size == 0)
    {
      return 0;
    }
    const Vector3 centroid = Centroid(points, vertices, size);
    if (!this->Scaled)
    {
      // One scale for all axes (a cube), so the curve's cells are cubes and pieces stay round.
      double extent = 0.0;
      for (int axis = 0; axis < 3; ++axis)
      {
        extent = std::max(extent, this->High[axis] - this->Low[axis]);
      }
      this->Scale = extent > 0.0 && std::isfinite(extent) ? kCells / extent : 0.0;
      this->Scaled = true;
    }
    std::uint64_t code = 0;
    for (int axis = 0; axis < 3; ++axis)
    {
      const double cell = std::clamp((centroid[axis] - this->Low[axis]) * this->Scale, 0.0, kCells);
      code |= SpreadBits(static_cast<std::uint64_t>(cell)) << axis;
    }
    return code;
  }

private:
  static constexpr double kCells = static_cast<double>((1u << 21) - 1);
  Vector3 Low;
  Vector3 High;
  double Scale = 0.0;
  bool Scaled = false;
};

void CheckPieceRequest(int piece, int pieces)
{
  if (pieces < 1 || piece < 0 || piece >= pieces)
  {
    throw std::invalid_argument("piece " + std::to_string(piece) + " of " + std::to_string(pieces) +
      " does not exist");
  }
}

/// Positions [first, end) of piece `piece` of `pieces` along an order of `faceCount` faces.
std::pair<std::size_t, std::size_t> PiecePositions(std::size_t faceCount, int piece, int pieces)
{
  // 64-bit products: F·pieces stays far below 2^63 for any mesh that fits in memory.
  const auto at = [&](int p)
  {
    return static_cast<std::size_t>(
      static_cast<unsigned long long>(faceCount) * static_cast<unsigned>(p) / static_cast<unsigned>(pieces));
  };
  return { at(piece), at(piece + 1) };
}

} // namespace

std::vector<std::int64_t> MortonFaceOrder(const OFFMesh& mesh)
{
  const std::size_t faceCount = mesh.FaceCount();
  MortonCurve curve;
  for (std::size_t v = 0; v < mesh.VertexCount(); ++v)
  {
    curve.Add(mesh.Points.data() + 3 * v);
  }
  std::vector<std::pair<std::uint64_t, std::int64_t>> keyed(faceCount);
  for (std::size_t f = 0; f < faceCount; ++f)
  {
    const auto begin = static_cast<std::size_t>(mesh.FaceOffsets[f]);
    const auto end = static_cast<std::size_t>(mesh.FaceOffsets[f + 1]);
    keyed[f] = { curve.Key(mesh.Points.data(), mesh.FaceConnectivity.data() + begin, end - begin),
      static_cast<std::int64_t>(f) };
  }
  std::sort(keyed.begin(), keyed.end());
  std::vector<std::int64_t> order(faceCount);
  std::transform(keyed.begin(), keyed.end(), order.begin(), [](const auto& entry) { return entry.second; });
  return order;
}

MeshPiece ExtractFacePiece(const OFFMesh& mesh, int piece, int pieces, PieceOrder order)
{
  CheckPieceRequest(piece, pieces);
  const std::size_t faceCount = mesh.FaceCount();
  const std::size_t vertexCount = mesh.VertexCount();
  const auto [firstPosition, endPosition] = PiecePositions(faceCount, piece, pieces);

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

namespace
{

/// Pass 1 of ReadOFFPiece: every point and, for spatial pieces, each face's key on the curve
/// (the points, and so the curve's cube, come before the faces).
class PointsAndKeys : public OFFElementVisitor
{
public:
  explicit PointsAndKeys(bool keys)
    : WithKeys(keys)
  {
  }
  void Counts(std::int64_t vertices, std::int64_t faces) override
  {
    this->Points.resize(3 * static_cast<std::size_t>(vertices));
    this->Keys.resize(this->WithKeys ? static_cast<std::size_t>(faces) : 0);
  }
  void Vertex(std::int64_t v, const double* point, const double*, const std::uint8_t*) override
  {
    std::copy(point, point + 3, this->Points.begin() + 3 * v);
    this->Curve.Add(point);
  }
  void Face(std::int64_t f, const std::int64_t* vertices, std::size_t size, const std::uint8_t*) override
  {
    if (this->WithKeys)
    {
      this->Keys[static_cast<std::size_t>(f)] = this->Curve.Key(this->Points.data(), vertices, size);
    }
  }

  std::vector<double> Points;
  std::vector<std::uint64_t> Keys;

private:
  bool WithKeys;
  MortonCurve Curve;
};

using KeyedFace = std::pair<std::uint64_t, std::int64_t>;

/// The pair at position k of the pairs (keys[f], f) in increasing order (k < keys.size());
/// `scratch` holds a permutation of keys and is reordered.
KeyedFace KeyedFaceAt(const std::vector<std::uint64_t>& keys, std::vector<std::uint64_t>& scratch, std::size_t k)
{
  std::nth_element(scratch.begin(), scratch.begin() + static_cast<std::ptrdiff_t>(k), scratch.end());
  const std::uint64_t key = scratch[k];
  const auto smaller = static_cast<std::size_t>(
    std::count_if(keys.begin(), keys.end(), [key](std::uint64_t other) { return other < key; }));
  std::size_t rank = k - smaller; // among the faces with this key, in file order
  for (std::size_t f = 0; f < keys.size(); ++f)
  {
    if (keys[f] == key && rank-- == 0)
    {
      return { key, static_cast<std::int64_t>(f) };
    }
  }
  return { key, static_cast<std::int64_t>(keys.size()) }; // not reached
}

/// The faces at positions [first, end) of the Morton order, one bit per face (what
/// ExtractFacePiece takes from MortonFaceOrder, without sorting every face).
std::vector<bool> SpatialSelection(const std::vector<std::uint64_t>& keys, std::size_t first, std::size_t end)
{
  std::vector<bool> selected(keys.size(), false);
  if (first == end)
  {
    return selected;
  }
  std::vector<std::uint64_t> scratch = keys;
  const KeyedFace low = KeyedFaceAt(keys, scratch, first);
  const KeyedFace high = end < keys.size() ? KeyedFaceAt(keys, scratch, end)
                                           : KeyedFace{ std::numeric_limits<std::uint64_t>::max(), 0 };
  for (std::size_t f = 0; f < keys.size(); ++f)
  {
    const KeyedFace face{ keys[f], static_cast<std::int64_t>(f) };
    selected[f] = !(face < low) && face < high;
  }
  return selected;
}

/// Pass 3: the piece's faces (vertex indices still global) and which vertices faces use.
class PieceFaces : public OFFElementVisitor
{
public:
  static constexpr std::uint8_t kUsed = 1;  ///< by some face
  static constexpr std::uint8_t kInPiece = 2; ///< by a face of the piece

  PieceFaces(std::size_t vertices, bool faceColors, std::function<bool(std::int64_t)> selected, MeshPiece& piece)
    : Flags(vertices, 0)
    , FaceColors(faceColors)
    , Selected(std::move(selected))
    , Piece(piece)
  {
    this->Piece.Mesh.FaceOffsets.assign(1, 0);
  }
  void Vertex(std::int64_t, const double*, const double*, const std::uint8_t*) override {}
  void Face(std::int64_t f, const std::int64_t* vertices, std::size_t size, const std::uint8_t* color) override
  {
    const bool selected = this->Selected(f);
    const std::uint8_t flag = selected ? kUsed | kInPiece : kUsed;
    for (std::size_t i = 0; i < size; ++i)
    {
      this->Flags[static_cast<std::size_t>(vertices[i])] |= flag;
    }
    if (!selected)
    {
      return;
    }
    OFFMesh& mesh = this->Piece.Mesh;
    mesh.FaceConnectivity.insert(mesh.FaceConnectivity.end(), vertices, vertices + size);
    mesh.FaceOffsets.push_back(static_cast<std::int64_t>(mesh.FaceConnectivity.size()));
    this->Piece.GlobalFaceIds.push_back(f);
    if (this->FaceColors)
    {
      const std::uint8_t* rgba = color != nullptr ? color : kOFFDefaultFaceColor.data();
      mesh.FaceColors.insert(mesh.FaceColors.end(), rgba, rgba + 4);
    }
  }

  std::vector<std::uint8_t> Flags;

private:
  bool FaceColors;
  std::function<bool(std::int64_t)> Selected;
  MeshPiece& Piece;
};

/// Pass 4 (NOFF / COFF): the normals and colours of the piece's vertices.
class PieceVertexAttributes : public OFFElementVisitor
{
public:
  explicit PieceVertexAttributes(MeshPiece& piece)
    : Piece(piece)
  {
  }
  void Vertex(std::int64_t v, const double*, const double* normal, const std::uint8_t* color) override
  {
    const std::vector<std::int64_t>& ids = this->Piece.GlobalPointIds;
    if (this->Next == ids.size() || ids[this->Next] != v)
    {
      return;
    }
    ++this->Next;
    if (normal != nullptr)
    {
      this->Piece.Mesh.VertexNormals.insert(this->Piece.Mesh.VertexNormals.end(), normal, normal + 3);
    }
    if (color != nullptr)
    {
      this->Piece.Mesh.VertexColors.insert(this->Piece.Mesh.VertexColors.end(), color, color + 4);
    }
  }
  void Face(std::int64_t, const std::int64_t*, std::size_t, const std::uint8_t*) override {}

private:
  MeshPiece& Piece;
  std::size_t Next = 0;
};

MeshPiece ReadPiece(OFFTextSource& source, int piece, int pieces, PieceOrder order, std::size_t chunkBytes)
{
  const bool spatial = order == PieceOrder::Spatial;
  PointsAndKeys whole(spatial);
  const OFFLayout layout = ScanOFF(source, whole, chunkBytes);
  CheckPieceRequest(piece, pieces);
  const auto faceCount = static_cast<std::size_t>(layout.FaceCount);
  const auto vertexCount = static_cast<std::size_t>(layout.VertexCount);
  const auto [first, end] = PiecePositions(faceCount, piece, pieces);

  std::function<bool(std::int64_t)> selected;
  if (spatial)
  {
    selected = [bits = SpatialSelection(whole.Keys, first, end)](std::int64_t f)
    { return static_cast<bool>(bits[static_cast<std::size_t>(f)]); };
    Release(whole.Keys);
  }
  else
  {
    selected = [first = first, end = end](std::int64_t f)
    { return static_cast<std::size_t>(f) >= first && static_cast<std::size_t>(f) < end; };
  }

  MeshPiece result;
  PieceFaces faces(vertexCount, layout.FaceColors, std::move(selected), result);
  RescanOFF(source, layout, OFFSection::Faces, faces, chunkBytes);

  // The vertices the piece's faces use, in file order; piece 0 also keeps the vertices that
  // no face uses.
  for (std::size_t v = 0; v < vertexCount; ++v)
  {
    const std::uint8_t flags = faces.Flags[v];
    if ((flags & PieceFaces::kInPiece) != 0 || (piece == 0 && (flags & PieceFaces::kUsed) == 0))
    {
      result.GlobalPointIds.push_back(static_cast<std::int64_t>(v));
      AppendTuple(result.Mesh.Points, whole.Points, v, 3);
    }
  }
  Release(faces.Flags);
  Release(whole.Points);
  for (std::int64_t& vertex : result.Mesh.FaceConnectivity)
  {
    vertex = std::lower_bound(result.GlobalPointIds.begin(), result.GlobalPointIds.end(), vertex) -
      result.GlobalPointIds.begin();
  }
  if ((layout.Normals || layout.VertexColors) && !result.GlobalPointIds.empty())
  {
    PieceVertexAttributes attributes(result);
    RescanOFF(source, layout, OFFSection::Vertices, attributes, chunkBytes);
  }
  return result;
}

} // namespace

MeshPiece ReadOFFPiece(const std::string& path, int piece, int pieces, PieceOrder order, std::size_t chunkBytes)
{
  try
  {
    OFFFileSource source(path);
    return ReadPiece(source, piece, pieces, order, chunkBytes);
  }
  catch (const OFFParseError& error)
  {
    // As ReadOFFFile: the path before the line (file errors already name it).
    throw OFFParseError(error.Line(), error.Reason(), path);
  }
}

MeshPiece ParseOFFPiece(const char* data, std::size_t size, int piece, int pieces, PieceOrder order,
  std::size_t chunkBytes)
{
  OFFMemorySource source(data, size);
  return ReadPiece(source, piece, pieces, order, chunkBytes);
}

} // namespace shapediameter
