// SPDX-License-Identifier: BSD-3-Clause
// The chunked piece reader (ReadOFFPiece, ParseOFFPiece) against the whole-file path
// ExtractFacePiece(ReadOFFFile / ParseOFF): the same piece in every array, or the same error,
// for 1 to 5 pieces, both orders, and chunks small enough to split lines, numbers and the
// byte-order mark, on generated meshes (normals, colours, n-gons, comments, CRLF), on bad
// input and on the meshes of SHAPEDIAMETER_DATA_DIR.
#include "IO/MeshPieces.h"
#include "IO/OFFParser.h"
#include "IO/OFFPieceOracle.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{

using shapediameter::ExtractFacePiece;
using shapediameter::kOFFChunkBytes;
using shapediameter::MeshPiece;
using shapediameter::OFFParseError;
using shapediameter::ParseOFFPiece;
using shapediameter::PieceOrder;
using shapediameter::ReadOFFFile;
using shapediameter::ReadOFFPiece;
using shapediameter::testing::OutcomeDifference;
using shapediameter::testing::PieceDifference;
using shapediameter::testing::PieceOrError;

constexpr PieceOrder kOrders[] = { PieceOrder::FileOrder, PieceOrder::Spatial };

/// Every piece of 1 to 5 pieces in both orders, read in chunks of each size.
void ExpectSameAsWholeFile(const std::string& text, const std::vector<std::size_t>& chunkSizes)
{
  for (const std::size_t chunkBytes : chunkSizes)
  {
    for (int pieces = 1; pieces <= 5; ++pieces)
    {
      for (int piece = 0; piece < pieces; ++piece)
      {
        for (const PieceOrder order : kOrders)
        {
          const std::string difference = PieceDifference(text, piece, pieces, order, chunkBytes);
          ASSERT_EQ(difference, "") << "input:\n" << text.substr(0, 400);
        }
      }
    }
  }
}

/// An n x n grid of unit squares in shuffled order (fixed seed): quads, triangles and a
/// pentagon, with normals, vertex colours, some face colours (integer, float with alpha, a
/// colour-map index), comments, blank lines, CRLF line ends, a byte-order mark, a vertex no
/// face uses in the middle of the vertices and one at their end.
std::string ColouredGrid(int n)
{
  const int gridVertices = (n + 1) * (n + 1);
  std::vector<std::string> faces;
  for (int y = 0; y < n; ++y)
  {
    for (int x = 0; x < n; ++x)
    {
      // Vertex indices above the unused vertex `gridVertices / 2` move up by one.
      const auto at = [&](int gx, int gy)
      {
        const int index = gy * (n + 1) + gx;
        return std::to_string(index >= gridVertices / 2 ? index + 1 : index);
      };
      const int kind = (x + 3 * y) % 5;
      std::string face;
      if (kind == 0)
      {
        face = "4 " + at(x, y) + " " + at(x + 1, y) + " " + at(x + 1, y + 1) + " " + at(x, y + 1) + " 255 0 0";
      }
      else if (kind == 1)
      {
        face = "3 " + at(x, y) + " " + at(x + 1, y) + " " + at(x + 1, y + 1) + " 0.25 0.5 1 0.5\n3 " + at(x, y) +
          " " + at(x + 1, y + 1) + " " + at(x, y + 1);
      }
      else if (kind == 2)
      {
        face = "5 " + at(x, y) + " " + at(x + 1, y) + " " + at(x + 1, y + 1) + " " + at(x, y + 1) + " " +
          at(x, y) + " 7 # colour-map index";
      }
      else
      {
        face = "4\t" + at(x, y) + " " + at(x + 1, y) + " " + at(x + 1, y + 1) + " " + at(x, y + 1);
      }
      faces.push_back(face);
    }
  }
  std::mt19937 random(11);
  std::shuffle(faces.begin(), faces.end(), random);
  std::string body;
  int faceCount = 0;
  for (const std::string& face : faces)
  {
    body += face + (faceCount % 7 == 0 ? "\r\n" : "\n");
    faceCount += face.find('\n') == std::string::npos ? 1 : 2;
  }
  std::string text = "\xEF\xBB\xBF# a grid\nCNOFF\n\n" + std::to_string(gridVertices + 2) + " " +
    std::to_string(faceCount) + " 0\n";
  for (int v = 0; v <= gridVertices; ++v)
  {
    if (v == gridVertices / 2)
    {
      text += "9 9 9  0 0 1  1 2 3 # no face uses this one\n";
      continue;
    }
    const int index = v > gridVertices / 2 ? v - 1 : v;
    text += std::to_string(index % (n + 1)) + " " + std::to_string(index / (n + 1)) + " 0.5  0 0 1  " +
      std::to_string(index % 256) + " 10 20" + (index % 3 == 0 ? " 128" : "") + (index % 4 == 0 ? "\r\n" : "\n");
    if (index == 5)
    {
      text += "\n   # a comment line\n";
    }
  }
  text += "-1 -1 -1  0 1 0  0.5 0.5 0.5 # unused too\n";
  return text + body;
}

TEST(OFFPieceReader, GeneratedMeshesInChunksThatSplitLines)
{
  std::string hexagons = "STOFF 9 2 # counts on the keyword line\n";
  for (int v = 0; v < 9; ++v)
  {
    hexagons += std::to_string(v) + " " + std::to_string(v * v % 5) + " " + std::to_string(v % 2) + " 0.5 0.5\n";
  }
  hexagons += "6 0 1 2 3 4 5\n7 3 4 5 6 7 8 0"; // no final newline
  std::string longLines = "OFF\n" + std::to_string(300) + " 1 0\n# " + std::string(5000, 'x') + "\n";
  std::string polygon = "300";
  for (int v = 0; v < 300; ++v)
  {
    longLines += std::to_string(v) + " " + std::to_string((v * 37) % 101) + ".125 -" + std::to_string(v % 7) + "e-1\n";
    polygon += " " + std::to_string(v);
  }
  longLines += polygon + "\n";
  const std::vector<std::string> texts = {
    ColouredGrid(9),
    hexagons,
    longLines,
    "4 2\n+1e0 -0.0 2.5E-1\n-1 0 0\n0 1e-3 0\n0 0 .5\n3 0 1 2\n3 1 2 3", // no keyword
    "OFF\n0 0 0\n",
    "NOFF\n3 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n", // vertices without faces
    "OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 1 2\nanything after the faces\n",
  };
  for (const std::string& text : texts)
  {
    ExpectSameAsWholeFile(text, { 1, 2, 3, 7, 61, 4096, kOFFChunkBytes });
  }
}

TEST(OFFPieceReader, BadInputGivesTheSameErrorWhereverTheChunksEnd)
{
  std::string lateError = ColouredGrid(6);
  lateError.replace(lateError.rfind("\n4\t") + 3, 1, "x"); // a vertex index of a late face
  const std::vector<std::string> texts = {
    "",
    "# only a comment\n\n",
    "\xEF\xBB\xBF",
    "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n",
    "OFF\n3 1 0\n0 0 0\n1 0 0\n",
    "OFF\n3 1 0\n0 0 nan\n1 0 0\n0 1 0\n3 0 1 2\n",
    "OFF\n3 1 0\n0 0 1e999\n1 0 0\n0 1 0\n3 0 1 2\n",
    "OFF BINARY\n3 1 0\n",
    "4OFF\n3 1 0\n",
    "OFF\n1099511627776 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
    "OFF\n3 1099511627776 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
    "OFF\n-3 1 0\n",
    "OFF\n3\n",
    "COFF\n3 1\n0 0 0 1 2\n1 0 0 1 2 3\n0 1 0 1 2 3\n3 0 1 2\n",
    "OFF\r\n3 1 0\r\n0 0 0\r\n1 0 0\r\n0 1 0\r\n2 0 1\r\n",
    "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 9 9\n",
    "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n",
    "OFF\n3 1 0\n0 0 0\n1 0 \x01\x80\n0 1 0\n3 0 1 2\n",
    std::string("\x7f" "ELF\x02\x01\x01\0\0\0", 10),
    "NCOFF\n1 0\n0 0 0 0 0 1 0.5 0.5 x\n",
    lateError,
  };
  for (const std::string& text : texts)
  {
    for (const std::size_t chunkBytes : { 1u, 5u, 4096u })
    {
      for (const int pieces : { 1, 3 })
      {
        for (const PieceOrder order : kOrders)
        {
          ASSERT_EQ(PieceDifference(text, pieces - 1, pieces, order, chunkBytes), "") << "input:\n" << text;
        }
      }
    }
    const auto outcome = PieceOrError([&] { return ParseOFFPiece(text.data(), text.size(), 0, 2); });
    EXPECT_EQ(outcome.Error.rfind("OFFParseError: line ", 0), 0u) << outcome.Error;
  }
}

TEST(OFFPieceReader, PiecesThatDoNotExist)
{
  const std::string text = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  for (const auto& [piece, pieces] : { std::pair{ 2, 2 }, std::pair{ -1, 2 }, std::pair{ 0, 0 } })
  {
    EXPECT_THROW(ParseOFFPiece(text.data(), text.size(), piece, pieces), std::invalid_argument);
    EXPECT_EQ(PieceDifference(text, piece, pieces, PieceOrder::Spatial, 3), "");
  }
  // More pieces than faces: empty pieces, the faces on the last ones.
  ExpectSameAsWholeFile(text, { 2 });
}

/// `text` written to a file of the test's temporary directory; removed by the caller.
std::string WriteFile(const std::string& name, const std::string& text)
{
  const std::string path = testing::TempDir() + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

TEST(OFFPieceReader, FilesAndFileErrorsAsReadOFFFile)
{
  const std::string good = WriteFile("TestOFFPieceReader_grid.off", ColouredGrid(5));
  const std::string bad = WriteFile("TestOFFPieceReader_bad.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
  const std::string missing = testing::TempDir() + "TestOFFPieceReader_does_not_exist.off";
  for (const std::string& path : { good, bad, missing, testing::TempDir() })
  {
    for (const PieceOrder order : kOrders)
    {
      for (const int pieces : { 1, 2, 3 })
      {
        const int piece = pieces - 1;
        const auto whole = PieceOrError([&] { return ExtractFacePiece(ReadOFFFile(path), piece, pieces, order); });
        const auto chunked = PieceOrError([&] { return ReadOFFPiece(path, piece, pieces, order, 13); });
        EXPECT_EQ(OutcomeDifference(whole, chunked), "") << path;
        EXPECT_EQ(path == good, chunked.Error.empty()) << chunked.Error;
      }
    }
  }
  try
  {
    ReadOFFPiece(bad, 0, 2);
    ADD_FAILURE() << "no error";
  }
  catch (const OFFParseError& error)
  {
    EXPECT_EQ(std::string(error.what()), bad + ": line 6: face 0: vertex index 7 is out of range [0, 3)");
    EXPECT_EQ(error.Line(), 6);
  }
  std::remove(good.c_str());
  std::remove(bad.c_str());
}

TEST(OFFPieceReader, MeshesOfTheDataDirectory)
{
  const char* directory = std::getenv("SHAPEDIAMETER_DATA_DIR");
  if (directory == nullptr)
  {
    GTEST_SKIP() << "SHAPEDIAMETER_DATA_DIR is not set";
  }
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(directory))
  {
    if (entry.path().extension() != ".off")
    {
      continue;
    }
    ++files;
    const std::string path = entry.path().string();
    const auto mesh = ReadOFFFile(path);
    for (const PieceOrder order : kOrders)
    {
      for (int pieces = 1; pieces <= 5; ++pieces)
      {
        // Small chunks (split lines everywhere) for some piece counts, the default for others.
        const std::size_t chunkBytes = pieces % 2 == 1 ? 4093 : kOFFChunkBytes;
        for (int piece = 0; piece < pieces; ++piece)
        {
          const auto whole = PieceOrError([&] { return ExtractFacePiece(mesh, piece, pieces, order); });
          const auto chunked = PieceOrError([&] { return ReadOFFPiece(path, piece, pieces, order, chunkBytes); });
          ASSERT_EQ(OutcomeDifference(whole, chunked), "")
            << path << ", piece " << piece << " of " << pieces << ", chunks of " << chunkBytes;
        }
      }
    }
  }
  EXPECT_GE(files, 5);
}

} // namespace
