// SPDX-License-Identifier: BSD-3-Clause
// libFuzzer entry point for the VTK-free OFF parser (Filters/Core/OFFParser.h).
//
// Build and run: see Testing/Fuzz/CMakeLists.txt (clang only), or by hand from the
// repository root:
//   clang++ -g -O1 -fsanitize=fuzzer,address,undefined -std=c++17 -I Filters/Core \
//     Filters/Core/OFFParser.cpp Testing/Fuzz/FuzzOFFParser.cpp -o /tmp/fuzz_off
//   /tmp/fuzz_off -max_total_time=60 -rss_limit_mb=512 CORPUS_DIR
//
// A finding is any of: a sanitizer report (out-of-bounds, use-after-free, UB, leak), an
// exception other than OFFParseError (libFuzzer reports the abort), an allocation above
// -rss_limit_mb / -malloc_limit_mb, a timeout, or an accepted mesh that breaks the
// documented invariants: indices in [0, V), finite coordinates and normals, faces of >= 3
// vertices, consistent array sizes, a size that is a small multiple of the input, and a
// lossless round trip (written back as OFF and parsed again, it is identical).
#include "OFFParser.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace
{
using shapediameter::OFFMesh;
using shapediameter::OFFParseError;
using shapediameter::ParseOFF;

[[noreturn]] void Violation(const char* what)
{
  std::fprintf(stderr, "OFF parser invariant violated: %s\n", what);
  std::abort();
}

void CheckMesh(const OFFMesh& mesh, std::size_t inputSize)
{
  if (mesh.Points.size() % 3 != 0)
  {
    Violation("points not a multiple of 3");
  }
  const std::size_t vertices = mesh.VertexCount();
  for (const double x : mesh.Points)
  {
    if (!std::isfinite(x))
    {
      Violation("non-finite coordinate");
    }
  }
  if (!mesh.VertexNormals.empty() && mesh.VertexNormals.size() != 3 * vertices)
  {
    Violation("normals size");
  }
  for (const double x : mesh.VertexNormals)
  {
    if (!std::isfinite(x))
    {
      Violation("non-finite normal");
    }
  }
  if (!mesh.VertexColors.empty() && mesh.VertexColors.size() != 4 * vertices)
  {
    Violation("vertex colours size");
  }
  if (mesh.FaceOffsets.empty() || mesh.FaceOffsets.front() != 0 ||
    mesh.FaceOffsets.back() != static_cast<std::int64_t>(mesh.FaceConnectivity.size()))
  {
    Violation("face offsets do not frame the connectivity");
  }
  for (std::size_t f = 0; f + 1 < mesh.FaceOffsets.size(); ++f)
  {
    if (mesh.FaceOffsets[f + 1] - mesh.FaceOffsets[f] < 3)
    {
      Violation("face with fewer than 3 vertices");
    }
  }
  for (const std::int64_t index : mesh.FaceConnectivity)
  {
    if (index < 0 || index >= static_cast<std::int64_t>(vertices))
    {
      Violation("vertex index out of range");
    }
  }
  if (!mesh.FaceColors.empty() && mesh.FaceColors.size() != 4 * mesh.FaceCount())
  {
    Violation("face colours size");
  }
  const std::size_t bytes = 8 * (mesh.Points.size() + mesh.VertexNormals.size() + mesh.FaceOffsets.size() +
                                  mesh.FaceConnectivity.size()) +
    mesh.VertexColors.size() + mesh.FaceColors.size();
  if (bytes > 64 * inputSize + 64)
  {
    Violation("mesh much larger than its input");
  }
}

/// The mesh as OFF text that must parse back to the same mesh.
std::string WriteOFF(const OFFMesh& mesh)
{
  std::string text;
  text += mesh.VertexColors.empty() ? "" : "C";
  text += mesh.VertexNormals.empty() ? "" : "N";
  text += "OFF\n" + std::to_string(mesh.VertexCount()) + " " + std::to_string(mesh.FaceCount()) + " 0\n";
  char buffer[64];
  for (std::size_t v = 0; v < mesh.VertexCount(); ++v)
  {
    for (std::size_t k = 0; k < 3; ++k)
    {
      std::snprintf(buffer, sizeof(buffer), "%.17g ", mesh.Points[3 * v + k]);
      text += buffer;
    }
    for (std::size_t k = 0; k < 3 && !mesh.VertexNormals.empty(); ++k)
    {
      std::snprintf(buffer, sizeof(buffer), "%.17g ", mesh.VertexNormals[3 * v + k]);
      text += buffer;
    }
    for (std::size_t k = 0; k < 4 && !mesh.VertexColors.empty(); ++k)
    {
      text += std::to_string(mesh.VertexColors[4 * v + k]) + " ";
    }
    text.back() = '\n';
  }
  for (std::size_t f = 0; f < mesh.FaceCount(); ++f)
  {
    text += std::to_string(mesh.FaceOffsets[f + 1] - mesh.FaceOffsets[f]);
    for (auto i = mesh.FaceOffsets[f]; i < mesh.FaceOffsets[f + 1]; ++i)
    {
      text += " " + std::to_string(mesh.FaceConnectivity[static_cast<std::size_t>(i)]);
    }
    for (std::size_t k = 0; k < 4 && !mesh.FaceColors.empty(); ++k)
    {
      text += " " + std::to_string(mesh.FaceColors[4 * f + k]);
    }
    text += "\n";
  }
  return text;
}
} // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  OFFMesh mesh;
  try
  {
    mesh = ParseOFF(reinterpret_cast<const char*>(data), size);
  }
  catch (const OFFParseError& error)
  {
    const std::string message = error.what();
    if (message.empty() || message.find('\n') != std::string::npos || error.Line() < 0)
    {
      Violation("error message empty, not one line, or negative line");
    }
    return 0;
  }
  CheckMesh(mesh, size);
  const std::string written = WriteOFF(mesh);
  OFFMesh again;
  try
  {
    again = ParseOFF(written.data(), written.size());
  }
  catch (const OFFParseError& error)
  {
    std::fprintf(stderr, "%s\n", error.what());
    Violation("an accepted mesh written back as OFF does not parse");
  }
  if (again.Points != mesh.Points || again.VertexNormals != mesh.VertexNormals ||
    again.VertexColors != mesh.VertexColors || again.FaceOffsets != mesh.FaceOffsets ||
    again.FaceConnectivity != mesh.FaceConnectivity || again.FaceColors != mesh.FaceColors)
  {
    Violation("round trip changed the mesh");
  }
  return 0;
}
