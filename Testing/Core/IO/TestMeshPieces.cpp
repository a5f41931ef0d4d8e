// SPDX-License-Identifier: BSD-3-Clause
// Splitting a mesh into the pieces of a distributed run: every face in exactly one piece, every
// vertex reference resolving to the same coordinates and attributes, global ids consistent.
#include "IO/MeshPieces.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{

using shapediameter::ExtractFacePiece;
using shapediameter::MeshPiece;
using shapediameter::OFFMesh;
using shapediameter::ParseOFF;
using shapediameter::PieceOrder;

/// A strip of `faces` coloured triangles over coloured, normal-carrying vertices, plus one
/// vertex no face uses (index 2 + faces: the last).
OFFMesh Strip(int faces)
{
  std::string text = "CNOFF\n" + std::to_string(faces + 3) + " " + std::to_string(faces) + " 0\n";
  for (int v = 0; v < faces + 3; ++v)
  {
    text += std::to_string(v / 2) + " " + std::to_string(v % 2) + " 0  0 0 1  " + std::to_string(v % 256) +
      " 0 0 255\n";
  }
  for (int f = 0; f < faces; ++f)
  {
    text += "3 " + std::to_string(f) + " " + std::to_string(f + 1) + " " + std::to_string(f + 2) + " " +
      std::to_string(f % 256) + " 10 20\n";
  }
  return ParseOFF(text.data(), text.size());
}

class MeshPiecesInEveryOrder : public ::testing::TestWithParam<PieceOrder>
{
};

TEST_P(MeshPiecesInEveryOrder, EveryFaceOnceWithItsVerticesAndAttributes)
{
  const OFFMesh whole = Strip(10);
  for (const int pieces : { 1, 2, 3, 4, 7, 10, 13 })
  {
    std::vector<int> faceSeen(whole.FaceCount(), 0);
    std::vector<int> vertexSeen(whole.VertexCount(), 0);
    std::size_t largest = 0;
    std::size_t smallest = whole.FaceCount();
    for (int piece = 0; piece < pieces; ++piece)
    {
      const MeshPiece part = ExtractFacePiece(whole, piece, pieces, GetParam());
      ASSERT_EQ(part.GlobalFaceIds.size(), part.Mesh.FaceCount());
      ASSERT_EQ(part.GlobalPointIds.size(), part.Mesh.VertexCount());
      ASSERT_EQ(part.Mesh.VertexNormals.size(), 3 * part.Mesh.VertexCount());
      ASSERT_EQ(part.Mesh.VertexColors.size(), 4 * part.Mesh.VertexCount());
      ASSERT_EQ(part.Mesh.FaceColors.size(), 4 * part.Mesh.FaceCount());
      largest = std::max(largest, part.Mesh.FaceCount());
      smallest = std::min(smallest, part.Mesh.FaceCount());
      for (std::size_t v = 0; v < part.GlobalPointIds.size(); ++v)
      {
        const auto global = static_cast<std::size_t>(part.GlobalPointIds[v]);
        ++vertexSeen[global];
        if (v > 0)
        {
          EXPECT_LT(part.GlobalPointIds[v - 1], part.GlobalPointIds[v]) << "vertices in file order";
        }
        for (int c = 0; c < 3; ++c)
        {
          EXPECT_EQ(part.Mesh.Points[3 * v + c], whole.Points[3 * global + c]);
          EXPECT_EQ(part.Mesh.VertexNormals[3 * v + c], whole.VertexNormals[3 * global + c]);
        }
        EXPECT_EQ(part.Mesh.VertexColors[4 * v], whole.VertexColors[4 * global]);
      }
      for (std::size_t f = 0; f < part.Mesh.FaceCount(); ++f)
      {
        const auto global = static_cast<std::size_t>(part.GlobalFaceIds[f]);
        ++faceSeen[global];
        if (f > 0)
        {
          EXPECT_LT(part.GlobalFaceIds[f - 1], part.GlobalFaceIds[f]) << "faces in file order";
        }
        ASSERT_EQ(part.Mesh.FaceOffsets[f + 1] - part.Mesh.FaceOffsets[f],
          whole.FaceOffsets[global + 1] - whole.FaceOffsets[global]);
        for (std::int64_t i = 0; i < part.Mesh.FaceOffsets[f + 1] - part.Mesh.FaceOffsets[f]; ++i)
        {
          const auto local = static_cast<std::size_t>(part.Mesh.FaceConnectivity[part.Mesh.FaceOffsets[f] + i]);
          ASSERT_LT(local, part.Mesh.VertexCount());
          EXPECT_EQ(part.GlobalPointIds[local], whole.FaceConnectivity[whole.FaceOffsets[global] + i]);
        }
        EXPECT_EQ(part.Mesh.FaceColors[4 * f], whole.FaceColors[4 * global]);
      }
    }
    for (std::size_t f = 0; f < faceSeen.size(); ++f)
    {
      EXPECT_EQ(faceSeen[f], 1) << "face " << f << " with " << pieces << " pieces";
    }
    for (std::size_t v = 0; v < vertexSeen.size(); ++v)
    {
      EXPECT_GE(vertexSeen[v], 1) << "vertex " << v << " with " << pieces << " pieces";
    }
    EXPECT_LE(largest - smallest, 1u) << "balanced pieces";
  }
}

INSTANTIATE_TEST_SUITE_P(Orders, MeshPiecesInEveryOrder,
  ::testing::Values(PieceOrder::FileOrder, PieceOrder::Spatial),
  [](const ::testing::TestParamInfo<PieceOrder>& info)
  { return info.param == PieceOrder::FileOrder ? std::string("FileOrder") : std::string("Spatial"); });

/// A 32 x 32 grid of unit squares (two triangles each) whose faces are listed in a shuffled
/// order (fixed seed), so file order says nothing about position.
OFFMesh ShuffledGrid()
{
  constexpr int n = 32;
  std::string text = "OFF\n" + std::to_string((n + 1) * (n + 1)) + " " + std::to_string(2 * n * n) + " 0\n";
  for (int y = 0; y <= n; ++y)
  {
    for (int x = 0; x <= n; ++x)
    {
      text += std::to_string(x) + " " + std::to_string(y) + " 0\n";
    }
  }
  std::vector<std::string> faces;
  for (int y = 0; y < n; ++y)
  {
    for (int x = 0; x < n; ++x)
    {
      const int corner = y * (n + 1) + x;
      faces.push_back("3 " + std::to_string(corner) + " " + std::to_string(corner + 1) + " " +
        std::to_string(corner + n + 2) + "\n");
      faces.push_back("3 " + std::to_string(corner) + " " + std::to_string(corner + n + 2) + " " +
        std::to_string(corner + n + 1) + "\n");
    }
  }
  std::mt19937 random(7);
  std::shuffle(faces.begin(), faces.end(), random);
  for (const std::string& face : faces)
  {
    text += face;
  }
  return ParseOFF(text.data(), text.size());
}

/// Mean area of the pieces' vertex bounding boxes, as a share of the whole grid's.
double MeanPieceBoxShare(const OFFMesh& whole, int pieces, PieceOrder order)
{
  double sum = 0.0;
  for (int piece = 0; piece < pieces; ++piece)
  {
    const MeshPiece part = ExtractFacePiece(whole, piece, pieces, order);
    double low[2] = { 1e300, 1e300 };
    double high[2] = { -1e300, -1e300 };
    for (std::size_t v = 0; v < part.Mesh.VertexCount(); ++v)
    {
      for (int axis = 0; axis < 2; ++axis)
      {
        low[axis] = std::min(low[axis], part.Mesh.Points[3 * v + axis]);
        high[axis] = std::max(high[axis], part.Mesh.Points[3 * v + axis]);
      }
    }
    sum += (high[0] - low[0]) * (high[1] - low[1]) / (32.0 * 32.0);
  }
  return sum / pieces;
}

TEST(MeshPieces, SpatialPiecesAreCompactWhateverTheFileOrder)
{
  const OFFMesh whole = ShuffledGrid();
  // Morton ranges of a square: 4 pieces are its quadrants (1/4 each), 16 pieces 1/16 each.
  EXPECT_LE(MeanPieceBoxShare(whole, 4, PieceOrder::Spatial), 0.30);
  EXPECT_LE(MeanPieceBoxShare(whole, 16, PieceOrder::Spatial), 0.09);
  // The same request in file order spans the whole grid: what the spatial order is for.
  EXPECT_GE(MeanPieceBoxShare(whole, 4, PieceOrder::FileOrder), 0.9);
}

TEST(MeshPieces, MortonOrderIsAPermutationAndDeterministic)
{
  const OFFMesh whole = ShuffledGrid();
  const std::vector<std::int64_t> order = shapediameter::MortonFaceOrder(whole);
  std::vector<std::int64_t> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t i = 0; i < sorted.size(); ++i)
  {
    ASSERT_EQ(sorted[i], static_cast<std::int64_t>(i));
  }
  EXPECT_EQ(order, shapediameter::MortonFaceOrder(whole));
  // A flat or single-point mesh (zero extent) still orders every face, by file index.
  const std::string point = "OFF\n3 2 0\n1 1 1\n1 1 1\n1 1 1\n3 0 1 2\n3 2 1 0\n";
  EXPECT_EQ(shapediameter::MortonFaceOrder(ParseOFF(point.data(), point.size())),
    (std::vector<std::int64_t>{ 0, 1 }));
}

TEST(MeshPieces, UnusedVerticesGoToPieceZeroOnly)
{
  const OFFMesh whole = Strip(6);
  const auto unused = static_cast<std::int64_t>(whole.VertexCount() - 1);
  const MeshPiece first = ExtractFacePiece(whole, 0, 3);
  const MeshPiece last = ExtractFacePiece(whole, 2, 3);
  EXPECT_EQ(first.GlobalPointIds.back(), unused);
  EXPECT_NE(last.GlobalPointIds.back(), unused);
  EXPECT_EQ(last.GlobalFaceIds, (std::vector<std::int64_t>{ 4, 5 }));
  // Border vertices are shared: face 1 (piece 0) and face 2 (piece 1) both use vertices 2 and 3.
  EXPECT_EQ(first.GlobalPointIds, (std::vector<std::int64_t>{ 0, 1, 2, 3, 8 }));
  EXPECT_EQ(ExtractFacePiece(whole, 1, 3).GlobalPointIds, (std::vector<std::int64_t>{ 2, 3, 4, 5 }));
}

TEST(MeshPieces, MorePiecesThanFacesAndBadRequests)
{
  const OFFMesh whole = Strip(2);
  EXPECT_EQ(ExtractFacePiece(whole, 0, 5).Mesh.FaceCount(), 0u);
  EXPECT_EQ(ExtractFacePiece(whole, 0, 5).GlobalPointIds, (std::vector<std::int64_t>{ 4 })) << "the unused vertex";
  EXPECT_EQ(ExtractFacePiece(whole, 4, 5).Mesh.FaceCount(), 1u);
  EXPECT_EQ(ExtractFacePiece(whole, 3, 5).Mesh.VertexCount(), 0u);
  EXPECT_THROW(ExtractFacePiece(whole, 5, 5), std::invalid_argument);
  EXPECT_THROW(ExtractFacePiece(whole, -1, 2), std::invalid_argument);
  EXPECT_THROW(ExtractFacePiece(whole, 0, 0), std::invalid_argument);
  const OFFMesh empty = ParseOFF("OFF\n0 0 0\n", 10);
  EXPECT_EQ(ExtractFacePiece(empty, 1, 2).Mesh.FaceCount(), 0u);
}

} // namespace
