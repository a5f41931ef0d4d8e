// SPDX-License-Identifier: BSD-3-Clause
// Tests of the VTK-free OFF parser: every variant, comments, n-gons, colours, malformed input
// (each must give OFFParseError with a telling message), random mutations (never a crash)
// and the real meshes of SHAPEDIAMETER_DATA_DIR when that variable is set.
#include "IO/OFFParser.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <string>
#include <vector>

namespace
{

using shapediameter::kOFFDefaultFaceColor;
using shapediameter::OFFMesh;
using shapediameter::OFFParseError;
using shapediameter::ParseOFF;
using shapediameter::ReadOFFFile;

OFFMesh Parse(const std::string& text)
{
  return ParseOFF(text.data(), text.size());
}

/// Message of the OFFParseError thrown by parsing text; a test failure when none is thrown.
std::string ErrorOf(const std::string& text)
{
  try
  {
    Parse(text);
  }
  catch (const OFFParseError& error)
  {
    return error.what();
  }
  ADD_FAILURE() << "no OFFParseError for input:\n" << text;
  return {};
}

#define EXPECT_OFF_ERROR(text, substring)                                                       \
  do                                                                                            \
  {                                                                                             \
    const std::string message_ = ErrorOf(text);                                                 \
    EXPECT_NE(message_.find(substring), std::string::npos)                                      \
      << "message: '" << message_ << "' lacks '" << (substring) << "'";                         \
  } while (false)

std::vector<std::int64_t> FaceOf(const OFFMesh& mesh, std::size_t face)
{
  return { mesh.FaceConnectivity.begin() + mesh.FaceOffsets[face],
    mesh.FaceConnectivity.begin() + mesh.FaceOffsets[face + 1] };
}

std::vector<std::uint8_t> Rgba(const std::vector<std::uint8_t>& colors, std::size_t element)
{
  return { colors.begin() + 4 * element, colors.begin() + 4 * element + 4 };
}

/// The invariants every successfully parsed mesh must satisfy.
void ExpectValidMesh(const OFFMesh& mesh)
{
  ASSERT_EQ(mesh.Points.size() % 3, 0u);
  const std::size_t vertexCount = mesh.VertexCount();
  for (double value : mesh.Points)
  {
    ASSERT_TRUE(std::isfinite(value));
  }
  ASSERT_TRUE(mesh.VertexNormals.empty() || mesh.VertexNormals.size() == 3 * vertexCount);
  for (double value : mesh.VertexNormals)
  {
    ASSERT_TRUE(std::isfinite(value));
  }
  ASSERT_TRUE(mesh.VertexColors.empty() || mesh.VertexColors.size() == 4 * vertexCount);
  ASSERT_FALSE(mesh.FaceOffsets.empty());
  ASSERT_EQ(mesh.FaceOffsets.front(), 0);
  ASSERT_EQ(mesh.FaceOffsets.back(), static_cast<std::int64_t>(mesh.FaceConnectivity.size()));
  for (std::size_t f = 0; f + 1 < mesh.FaceOffsets.size(); ++f)
  {
    ASSERT_GE(mesh.FaceOffsets[f + 1] - mesh.FaceOffsets[f], 3);
  }
  for (std::int64_t index : mesh.FaceConnectivity)
  {
    ASSERT_GE(index, 0);
    ASSERT_LT(index, static_cast<std::int64_t>(vertexCount));
  }
  ASSERT_TRUE(mesh.FaceColors.empty() || mesh.FaceColors.size() == 4 * mesh.FaceCount());
}

const char* const kTetrahedron = "OFF\n"
                                 "4 4 6\n"
                                 "0 0 0\n"
                                 "1 0 0\n"
                                 "0 1 0\n"
                                 "0 0 1\n"
                                 "3 0 2 1\n"
                                 "3 0 1 3\n"
                                 "3 0 3 2\n"
                                 "3 1 2 3\n";

// ---------------------------------------------------------------- good files

TEST(TestOFFParser, PlainOFFTetrahedron)
{
  const OFFMesh mesh = Parse(kTetrahedron);
  ExpectValidMesh(mesh);
  EXPECT_EQ(mesh.VertexCount(), 4u);
  EXPECT_EQ(mesh.FaceCount(), 4u);
  EXPECT_EQ(mesh.Points, (std::vector<double>{ 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1 }));
  EXPECT_EQ(mesh.FaceOffsets, (std::vector<std::int64_t>{ 0, 3, 6, 9, 12 }));
  EXPECT_EQ(FaceOf(mesh, 3), (std::vector<std::int64_t>{ 1, 2, 3 }));
  EXPECT_TRUE(mesh.VertexNormals.empty());
  EXPECT_TRUE(mesh.VertexColors.empty());
  EXPECT_TRUE(mesh.FaceColors.empty());
}

TEST(TestOFFParser, CountsOnKeywordLineAndDecimalCoordinates)
{
  const OFFMesh mesh = Parse("OFF 3 1 0\n-1.5 2.25e1 +3\n.5 -0.125 1E-3\n7 8 9\n3 0 1 2\n");
  ExpectValidMesh(mesh);
  EXPECT_EQ(mesh.Points,
    (std::vector<double>{ -1.5, 22.5, 3.0, 0.5, -0.125, 1e-3, 7, 8, 9 }));
  EXPECT_EQ(mesh.FaceConnectivity, (std::vector<std::int64_t>{ 0, 1, 2 }));
}

TEST(TestOFFParser, CommentsBlankLinesTabsAndCRLF)
{
  const std::string text = "\xEF\xBB\xBF# leading comment\r\n"
                           "\r\n"
                           "OFF # keyword comment\r\n"
                           "# between header and counts\r\n"
                           "\t\r\n"
                           "3 1 0# counts comment without space\r\n"
                           "0 0 0 # vertex 0\r\n"
                           "\r\n"
                           "# a whole-line comment between vertices\r\n"
                           "1\t0  0\r\n"
                           "0 1 0#glued comment\r\n"
                           "#\r\n"
                           "3 2 1 0 # face\r\n"
                           "# trailing comment\r\n";
  const OFFMesh mesh = Parse(text);
  ExpectValidMesh(mesh);
  EXPECT_EQ(mesh.Points, (std::vector<double>{ 0, 0, 0, 1, 0, 0, 0, 1, 0 }));
  EXPECT_EQ(mesh.FaceConnectivity, (std::vector<std::int64_t>{ 2, 1, 0 }));
}

TEST(TestOFFParser, NoFinalNewline)
{
  const OFFMesh mesh = Parse("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2");
  EXPECT_EQ(mesh.FaceCount(), 1u);
}

TEST(TestOFFParser, EdgeCountOptionalAndIgnored)
{
  EXPECT_EQ(Parse("OFF\n3 1\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").FaceCount(), 1u);
  EXPECT_EQ(Parse("OFF\n3 1 12345\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n").FaceCount(), 1u);
}

TEST(TestOFFParser, KeywordOptional)
{
  const OFFMesh mesh = Parse("3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n");
  ExpectValidMesh(mesh);
  EXPECT_EQ(mesh.VertexCount(), 3u);
  EXPECT_EQ(mesh.FaceCount(), 1u);
}

TEST(TestOFFParser, EmptyMeshWithZeroCounts)
{
  const OFFMesh mesh = Parse("OFF\n0 0 0\n");
  ExpectValidMesh(mesh);
  EXPECT_EQ(mesh.VertexCount(), 0u);
  EXPECT_EQ(mesh.FaceCount(), 0u);
  EXPECT_EQ(mesh.FaceOffsets, (std::vector<std::int64_t>{ 0 }));
}

TEST(TestOFFParser, VerticesWithoutFaces)
{
  const OFFMesh mesh = Parse("OFF\n2 0 0\n1 2 3\n4 5 6\n");
  EXPECT_EQ(mesh.VertexCount(), 2u);
  EXPECT_EQ(mesh.FaceCount(), 0u);
}

TEST(TestOFFParser, NGonsKeepTheirSizes)
{
  const OFFMesh mesh = Parse("OFF\n"
                             "7 3 0\n"
                             "0 0 0\n1 0 0\n2 0 0\n2 1 0\n1 1 0\n0 1 0\n1 2 0\n"
                             "4 0 1 4 5\n"
                             "5 1 2 3 4 6\n"
                             "6 0 1 2 3 6 5\n");
  ExpectValidMesh(mesh);
  EXPECT_EQ(mesh.FaceOffsets, (std::vector<std::int64_t>{ 0, 4, 9, 15 }));
  EXPECT_EQ(FaceOf(mesh, 1), (std::vector<std::int64_t>{ 1, 2, 3, 4, 6 }));
  EXPECT_EQ(FaceOf(mesh, 2), (std::vector<std::int64_t>{ 0, 1, 2, 3, 6, 5 }));
}

TEST(TestOFFParser, COFFVertexColoursIntegerAndFloat)
{
  const OFFMesh mesh = Parse("COFF\n"
                             "4 1 0\n"
                             "0 0 0 255 0 0 255\n"   // ints, 4 components
                             "1 0 0 0 128 255\n"     // ints, 3 components: alpha 255
                             "0 1 0 0.5 1.0 0 0.25\n" // floats, 4 components
                             "0 0 1 1 0 0.0\n"       // a float among them: floats
                             "4 0 1 2 3\n");
  ExpectValidMesh(mesh);
  ASSERT_EQ(mesh.VertexColors.size(), 16u);
  EXPECT_EQ(Rgba(mesh.VertexColors, 0), (std::vector<std::uint8_t>{ 255, 0, 0, 255 }));
  EXPECT_EQ(Rgba(mesh.VertexColors, 1), (std::vector<std::uint8_t>{ 0, 128, 255, 255 }));
  EXPECT_EQ(Rgba(mesh.VertexColors, 2), (std::vector<std::uint8_t>{ 128, 255, 0, 64 }));
  EXPECT_EQ(Rgba(mesh.VertexColors, 3), (std::vector<std::uint8_t>{ 255, 0, 0, 255 }));
  EXPECT_EQ(mesh.Points[9], 0.0);
  EXPECT_EQ(mesh.Points[11], 1.0);
  EXPECT_TRUE(mesh.VertexNormals.empty());
  EXPECT_TRUE(mesh.FaceColors.empty());
}

TEST(TestOFFParser, ColoursAreClamped)
{
  const OFFMesh mesh = Parse("COFF\n1 0 0\n0 0 0 300 -4 12 1000\n");
  EXPECT_EQ(Rgba(mesh.VertexColors, 0), (std::vector<std::uint8_t>{ 255, 0, 12, 255 }));
  const OFFMesh floats = Parse("COFF\n1 0 0\n0 0 0 1.5 -0.5 0.5\n");
  EXPECT_EQ(Rgba(floats.VertexColors, 0), (std::vector<std::uint8_t>{ 255, 0, 128, 255 }));
}

TEST(TestOFFParser, NOFFNormals)
{
  const OFFMesh mesh = Parse("NOFF\n3 1 0\n"
                             "0 0 0 0 0 1\n"
                             "1 0 0 0 0.6 0.8\n"
                             "0 1 0 -1 0 0\n"
                             "3 0 1 2\n");
  ExpectValidMesh(mesh);
  EXPECT_EQ(mesh.VertexNormals, (std::vector<double>{ 0, 0, 1, 0, 0.6, 0.8, -1, 0, 0 }));
  EXPECT_EQ(mesh.Points, (std::vector<double>{ 0, 0, 0, 1, 0, 0, 0, 1, 0 }));
  EXPECT_TRUE(mesh.VertexColors.empty());
}

TEST(TestOFFParser, CNOFFAndNCOFFReadNormalsBeforeColours)
{
  for (const char* keyword : { "CNOFF", "NCOFF" })
  {
    const OFFMesh mesh = Parse(std::string(keyword) +
      "\n3 1 0\n"
      "0 0 0 0 0 1 10 20 30\n"
      "1 0 0 0 1 0 40 50 60 70\n"
      "0 1 0 1 0 0 0.0 1.0 0.0\n"
      "3 0 1 2\n");
    ExpectValidMesh(mesh);
    EXPECT_EQ(mesh.VertexNormals, (std::vector<double>{ 0, 0, 1, 0, 1, 0, 1, 0, 0 })) << keyword;
    EXPECT_EQ(Rgba(mesh.VertexColors, 0), (std::vector<std::uint8_t>{ 10, 20, 30, 255 }));
    EXPECT_EQ(Rgba(mesh.VertexColors, 1), (std::vector<std::uint8_t>{ 40, 50, 60, 70 }));
    EXPECT_EQ(Rgba(mesh.VertexColors, 2), (std::vector<std::uint8_t>{ 0, 255, 0, 255 }));
  }
}

TEST(TestOFFParser, STVariantsDropTextureCoordinates)
{
  const OFFMesh plain = Parse("STOFF\n3 1 0\n0 0 0 0.1 0.2\n1 0 0 0.3 0.4\n0 1 0 0.5 0.6\n3 0 1 2\n");
  ExpectValidMesh(plain);
  EXPECT_EQ(plain.Points, (std::vector<double>{ 0, 0, 0, 1, 0, 0, 0, 1, 0 }));
  EXPECT_TRUE(plain.VertexColors.empty());

  // Normals, then a 3- or 4-component colour, then s t.
  const OFFMesh all = Parse("STCNOFF\n3 1 0\n"
                            "0 0 0 0 0 1 1 2 3 0.1 0.2\n"
                            "1 0 0 0 0 1 4 5 6 7 0.3 0.4\n"
                            "0 1 0 0 0 1 8 9 10 0.5 0.6\n"
                            "3 0 1 2\n");
  ExpectValidMesh(all);
  EXPECT_EQ(all.Points, (std::vector<double>{ 0, 0, 0, 1, 0, 0, 0, 1, 0 }));
  EXPECT_EQ(all.VertexNormals.size(), 9u);
  EXPECT_EQ(Rgba(all.VertexColors, 0), (std::vector<std::uint8_t>{ 1, 2, 3, 255 }));
  EXPECT_EQ(Rgba(all.VertexColors, 1), (std::vector<std::uint8_t>{ 4, 5, 6, 7 }));
  EXPECT_EQ(Rgba(all.VertexColors, 2), (std::vector<std::uint8_t>{ 8, 9, 10, 255 }));
}

TEST(TestOFFParser, FaceColoursWithDefaultForUncolouredFaces)
{
  const OFFMesh mesh = Parse("OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
                             "3 0 2 1\n"                  // no colour: default
                             "3 0 1 3 255 0 0\n"          // int RGB
                             "3 0 3 2 0 0.5 1 0.5\n"      // float RGBA
                             "3 1 2 3 7\n");              // colour-map index: no colour
  ExpectValidMesh(mesh);
  ASSERT_EQ(mesh.FaceColors.size(), 16u);
  const std::vector<std::uint8_t> defaultColor(kOFFDefaultFaceColor.begin(), kOFFDefaultFaceColor.end());
  EXPECT_EQ(Rgba(mesh.FaceColors, 0), defaultColor);
  EXPECT_EQ(Rgba(mesh.FaceColors, 1), (std::vector<std::uint8_t>{ 255, 0, 0, 255 }));
  EXPECT_EQ(Rgba(mesh.FaceColors, 2), (std::vector<std::uint8_t>{ 0, 128, 255, 128 }));
  EXPECT_EQ(Rgba(mesh.FaceColors, 3), defaultColor);
  EXPECT_EQ(FaceOf(mesh, 3), (std::vector<std::int64_t>{ 1, 2, 3 }));
}

TEST(TestOFFParser, OnlyColourMapIndicesMeansNoFaceColours)
{
  const OFFMesh mesh = Parse("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 4\n");
  EXPECT_TRUE(mesh.FaceColors.empty());
}

TEST(TestOFFParser, ContentAfterDeclaredElementsIsIgnored)
{
  const OFFMesh mesh = Parse(std::string(kTetrahedron) + "\n# end\n3 9 9 9\nrandom trailing words\n");
  ExpectValidMesh(mesh);
  EXPECT_EQ(mesh.FaceCount(), 4u);
}

TEST(TestOFFParser, RepeatedVertexInFaceIsKept)
{
  const OFFMesh mesh = Parse("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 0 1\n");
  EXPECT_EQ(FaceOf(mesh, 0), (std::vector<std::int64_t>{ 0, 0, 1 }));
}

// ---------------------------------------------------------------- malformed files

TEST(TestOFFParser, EmptyInput)
{
  EXPECT_OFF_ERROR("", "empty");
  EXPECT_OFF_ERROR("   \n\n\t\n", "empty");
  EXPECT_OFF_ERROR("# only a comment\n# and another\n", "empty");
  EXPECT_THROW(ParseOFF(nullptr, 0), OFFParseError);
}

TEST(TestOFFParser, BinaryGarbage)
{
  std::string garbage("\x7f" "ELF\x02\x01\x01\0\0\0\xff\xfe\n\x01\x02", 15);
  EXPECT_OFF_ERROR(garbage, "line 1: not an OFF file");
  EXPECT_OFF_ERROR(std::string("\0\0\0\0", 4), "not an OFF file");
  EXPECT_OFF_ERROR("ply\nformat ascii 1.0\n", "not an OFF file");
}

TEST(TestOFFParser, UnsupportedVariants)
{
  EXPECT_OFF_ERROR("4OFF\n1 0 0\n0 0 0 0\n", "not supported");
  EXPECT_OFF_ERROR("nOFF\n4\n1 0 0\n0 0 0 0\n", "not supported");
  EXPECT_OFF_ERROR("C4OFF\n1 0 0\n0 0 0 0 1 1 1\n", "not supported");
  EXPECT_OFF_ERROR("OFF BINARY\n\x01\x02\x03", "binary OFF is not supported");
  EXPECT_OFF_ERROR("XOFF\n3 1 0\n", "header keyword");
  EXPECT_OFF_ERROR("CCOFF\n3 1 0\n", "header keyword");
}

TEST(TestOFFParser, NegativeCounts)
{
  EXPECT_OFF_ERROR("OFF\n-3 1 0\n0 0 0\n", "line 2: vertex count -3 is negative");
  EXPECT_OFF_ERROR("OFF\n3 -1 0\n0 0 0\n1 0 0\n0 1 0\n", "face count -1 is negative");
}

TEST(TestOFFParser, CountsThatCannotFitTheFileAreRejectedBeforeAllocating)
{
  // Would be 48 GB of doubles if allocated.
  EXPECT_OFF_ERROR("OFF\n2000000000 2000000000 0\n0 0 0\n", "bytes");
  EXPECT_OFF_ERROR("OFF\n3 1000000 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "truncated");
  EXPECT_OFF_ERROR("OFF\n9223372036854775807 9223372036854775807 0\n", "bytes");
}

TEST(TestOFFParser, CountOverflow)
{
  EXPECT_OFF_ERROR("OFF\n99999999999999999999 1 0\n", "too large");
  EXPECT_OFF_ERROR("OFF\n3 99999999999999999999 0\n", "too large");
}

TEST(TestOFFParser, MalformedCounts)
{
  EXPECT_OFF_ERROR("OFF\n", "end of file");
  EXPECT_OFF_ERROR("OFF\n3\n", "counts");
  EXPECT_OFF_ERROR("OFF\n3 1 0 5\n", "counts");
  EXPECT_OFF_ERROR("OFF\nthree 1 0\n", "not an integer");
  EXPECT_OFF_ERROR("OFF\n3.0 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "not an integer");
}

TEST(TestOFFParser, TruncatedFiles)
{
  // Missing vertex lines (a long comment gets the file past the byte-count check).
  EXPECT_OFF_ERROR("OFF\n4 1 0\n0 0 0\n1 0 0\n# long comment to pad the byte count\n",
    "2 of 4 vertices");
  // Missing face lines.
  EXPECT_OFF_ERROR("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2    \n            \n", "end of file");
  EXPECT_OFF_ERROR("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2    \n            \n", "1 of 2 faces");
  // A vertex line cut in the middle.
  EXPECT_OFF_ERROR("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1\n\n\n\n\n\n\n\n\n\n\n\n", "line 5: vertex 2 has 2 values");
}

TEST(TestOFFParser, IndexOutOfRange)
{
  EXPECT_OFF_ERROR("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n", "line 6: face 0: vertex index 3 is out of range");
  EXPECT_OFF_ERROR("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n", "out of range");
  EXPECT_OFF_ERROR("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 99999999999999999999\n", "out of range");
  EXPECT_OFF_ERROR("OFF\n0 1 0\n3 0 1 2\n", "out of range");
}

TEST(TestOFFParser, NonFiniteCoordinates)
{
  EXPECT_OFF_ERROR("OFF\n3 1 0\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n", "line 4: vertex 1");
  EXPECT_OFF_ERROR("OFF\n3 1 0\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n", "finite");
  EXPECT_OFF_ERROR("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 -inf\n3 0 1 2\n", "finite");
  EXPECT_OFF_ERROR("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 1e999\n3 0 1 2\n", "range");
  EXPECT_OFF_ERROR("NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 NaN 1\n3 0 1 2\n", "finite");
  EXPECT_OFF_ERROR("COFF\n3 1 0\n0 0 0 1 1 1\n1 0 0 1 1 1\n0 1 0 0.5 inf 1\n3 0 1 2\n", "finite");
}

TEST(TestOFFParser, FaceSizeBelowThree)
{
  EXPECT_OFF_ERROR("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1 # pad\n", "line 6: face 0 has 2 vertices; at least 3");
  EXPECT_OFF_ERROR("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n0\n      \n", "at least 3");
  EXPECT_OFF_ERROR("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n-3 0 1 2\n", "at least 3");
}

TEST(TestOFFParser, FaceSizeLargerThanItsLine)
{
  EXPECT_OFF_ERROR("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4 0 1 2\n", "declares 4 vertices");
  EXPECT_OFF_ERROR("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n9223372036854775807 0 1 2\n", "declares");
  EXPECT_OFF_ERROR("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 255 0\n", "colour");
}

TEST(TestOFFParser, NonNumericTokens)
{
  EXPECT_OFF_ERROR("OFF\n3 1 0\n0 0 0\n1 0 zero\n0 1 0\n3 0 1 2\n", "line 4: vertex 1: 'zero' is not a number");
  EXPECT_OFF_ERROR("OFF\n3 1 0\n0 0 0\n1 0 0.5x\n0 1 0\n3 0 1 2\n", "not a number");
  EXPECT_OFF_ERROR("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1.5 2\n", "not an integer");
  EXPECT_OFF_ERROR("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\nthree 0 1 2\n", "not an integer");
  EXPECT_OFF_ERROR("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2 red green blue\n", "not a number");
  EXPECT_OFF_ERROR("STOFF\n3 1 0\n0 0 0 0 0\n1 0 0 0 0\n0 1 0 u v\n3 0 1 2\n", "not a number");
}

TEST(TestOFFParser, WrongValueCountOnVertexLine)
{
  EXPECT_OFF_ERROR("OFF\n3 1 0\n0 0 0\n1 0 0 5\n0 1 0\n3 0 1 2\n", "vertex 1 has 4 values, expected 3");
  EXPECT_OFF_ERROR("COFF\n3 1 0\n0 0 0 1 1 1\n1 0 0 1 1\n0 1 0 1 1 1\n3 0 1 2 # pad\n", "vertex 1 has 5 values");
  // The vertex count is too small: a face line is read as a vertex.
  EXPECT_OFF_ERROR("OFF\n2 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "line 5: face 0");
}

TEST(TestOFFParser, ErrorCarriesLineNumber)
{
  try
  {
    Parse("OFF\n# comment\n3 1 0\n0 0 0\n\n1 0 0\n0 1 0\n3 0 1 5\n");
    FAIL() << "expected OFFParseError";
  }
  catch (const OFFParseError& error)
  {
    EXPECT_EQ(error.Line(), 8);
    EXPECT_EQ(std::string(error.what()).rfind("line 8: ", 0), 0u) << error.what();
    EXPECT_EQ(error.Reason().rfind("face 0", 0), 0u) << error.Reason();
  }
}

TEST(TestOFFParser, ErrorMessageShowsBinaryTokensPrintably)
{
  const std::string message = ErrorOf(std::string("OFF\n3 1 0\n0 0 0\n1 0 \x01\x80\n0 1 0\n3 0 1 2\n"));
  EXPECT_NE(message.find("\\x01\\x80"), std::string::npos) << message;
}

// ---------------------------------------------------------------- files

TEST(TestOFFParser, ReadFileRoundTripAndMissingFile)
{
  const std::string path = testing::TempDir() + "TestOFFParser_tetrahedron.off";
  {
    std::ofstream out(path, std::ios::binary);
    out << kTetrahedron;
  }
  const OFFMesh mesh = ReadOFFFile(path);
  EXPECT_EQ(mesh.VertexCount(), 4u);
  EXPECT_EQ(mesh.FaceCount(), 4u);
  std::remove(path.c_str());

  const std::string missing = testing::TempDir() + "TestOFFParser_does_not_exist.off";
  try
  {
    ReadOFFFile(missing);
    FAIL() << "expected OFFParseError";
  }
  catch (const OFFParseError& error)
  {
    EXPECT_NE(std::string(error.what()).find(missing), std::string::npos) << error.what();
    EXPECT_EQ(error.Line(), 0);
  }
  // A directory opens on Linux but cannot be read.
  EXPECT_THROW(ReadOFFFile(testing::TempDir()), OFFParseError);
}

TEST(TestOFFParser, FileErrorsNameTheFile)
{
  const std::string path = testing::TempDir() + "TestOFFParser_bad.off";
  {
    std::ofstream out(path, std::ios::binary);
    out << "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n";
  }
  try
  {
    ReadOFFFile(path);
    FAIL() << "expected OFFParseError";
  }
  catch (const OFFParseError& error)
  {
    EXPECT_EQ(std::string(error.what()).rfind(path + ": line 6: ", 0), 0u) << error.what();
    EXPECT_EQ(error.Line(), 6);
  }
  std::remove(path.c_str());
}

// ---------------------------------------------------------------- robustness

TEST(TestOFFParser, RandomMutationsNeverCrash)
{
  const std::vector<std::string> seeds = {
    kTetrahedron,
    "COFF\n# colours\n5 3 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0\n1 1 0 0.5 0.5 0.5 1\n"
    "0 1 0 1 1 1\n0.5 0.5 1 9 9 9 9\n4 0 1 2 3 255 255 0\n3 0 1 4\n3 1 2 4 0.1 0.2 0.3 0.4\n",
    "NOFF 4 2 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n1 1 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2 7\n3 0 2 3\n",
  };
  // Bytes a mutation writes: mostly the ones that matter to the grammar.
  static const char kInteresting[] = "0123456789-+.eE#\n\r \tnaif\0\xff";
  const std::string interesting(kInteresting, sizeof(kInteresting) - 1);
  std::mt19937_64 rng(20080611);
  int parsed = 0;
  int rejected = 0;
  for (int trial = 0; trial < 2000; ++trial)
  {
    std::string text = seeds[trial % seeds.size()];
    const int edits = 1 + static_cast<int>(rng() % 4);
    for (int e = 0; e < edits; ++e)
    {
      const std::size_t at = text.empty() ? 0 : static_cast<std::size_t>(rng() % text.size());
      const std::uint64_t pick = rng();
      const char byte = (pick >> 8) % 4 == 0 ? static_cast<char>(rng() & 0xff)
                                             : interesting[(pick >> 16) % interesting.size()];
      switch (pick % 4)
      {
        case 0: // replace
          if (!text.empty())
          {
            text[at] = byte;
          }
          break;
        case 1: // insert
          text.insert(text.begin() + static_cast<std::ptrdiff_t>(at), byte);
          break;
        case 2: // delete
          if (!text.empty())
          {
            text.erase(at, 1 + rng() % 3);
          }
          break;
        default: // truncate
          text.resize(at);
          break;
      }
    }
    try
    {
      const OFFMesh mesh = Parse(text);
      ExpectValidMesh(mesh);
      if (testing::Test::HasFatalFailure())
      {
        FAIL() << "invalid mesh from input:\n" << text;
      }
      ++parsed;
    }
    catch (const OFFParseError& error)
    {
      ASSERT_EQ(std::string(error.what()).rfind("line ", 0), 0u) << error.what();
      ++rejected;
    }
  }
  // Both outcomes occur, so the loop really explores the grammar.
  EXPECT_GT(parsed, 100);
  EXPECT_GT(rejected, 100);
}

// ---------------------------------------------------------------- real data

std::string DataFile(const char* name)
{
  const char* directory = std::getenv("SHAPEDIAMETER_DATA_DIR");
  return directory == nullptr ? std::string() : std::string(directory) + "/" + name;
}

TEST(TestOFFParser, CamelFromDataDirectory)
{
  const std::string path = DataFile("camel.off");
  if (path.empty())
  {
    GTEST_SKIP() << "SHAPEDIAMETER_DATA_DIR is not set";
  }
  const OFFMesh mesh = ReadOFFFile(path);
  ExpectValidMesh(mesh);
  EXPECT_EQ(mesh.VertexCount(), 9770u);
  EXPECT_EQ(mesh.FaceCount(), 19536u);
  EXPECT_EQ(mesh.FaceConnectivity.size(), 3u * 19536u);
  EXPECT_DOUBLE_EQ(mesh.Points[0], -0.0274279);
  EXPECT_EQ(mesh.FaceConnectivity.back(), 2045);
}

TEST(TestOFFParser, CactusCOFFFromDataDirectory)
{
  const std::string path = DataFile("cactus.off");
  if (path.empty())
  {
    GTEST_SKIP() << "SHAPEDIAMETER_DATA_DIR is not set";
  }
  const OFFMesh mesh = ReadOFFFile(path);
  ExpectValidMesh(mesh);
  EXPECT_EQ(mesh.VertexCount(), 620u);
  EXPECT_EQ(mesh.FaceCount(), 1236u);
  ASSERT_EQ(mesh.VertexColors.size(), 4u * 620u);
  EXPECT_EQ(Rgba(mesh.VertexColors, 0), (std::vector<std::uint8_t>{ 192, 192, 192, 255 }));
}

TEST(TestOFFParser, ArmadilloFromDataDirectory)
{
  const std::string path = DataFile("armadillo.off");
  if (path.empty())
  {
    GTEST_SKIP() << "SHAPEDIAMETER_DATA_DIR is not set";
  }
  const OFFMesh mesh = ReadOFFFile(path);
  ExpectValidMesh(mesh);
  EXPECT_EQ(mesh.VertexCount(), 26002u);
  EXPECT_EQ(mesh.FaceCount(), 52000u);
}

} // namespace
