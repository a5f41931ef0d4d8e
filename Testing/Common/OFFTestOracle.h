// SPDX-License-Identifier: BSD-3-Clause
// The OFF parser's oracle, shared by the seeded fuzz test (Testing/Core/IO/TestOFFParserFuzz.cpp)
// and the libFuzzer target (Testing/Fuzz/FuzzOFFParser.cpp): the documented invariants of an
// accepted mesh and the writer of its round trip. Header-only, VTK-free: the libFuzzer target
// is a project of its own that compiles only the parser.
#pragma once

#include "IO/OFFParser.h"

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

namespace shapediameter::testing
{

/// Empty when the mesh satisfies every documented invariant, else the first violation.
inline std::string MeshViolation(const OFFMesh& mesh, std::size_t inputSize)
{
  if (mesh.Points.size() % 3 != 0)
  {
    return "points not a multiple of 3";
  }
  const std::size_t vertices = mesh.VertexCount();
  for (const double x : mesh.Points)
  {
    if (!std::isfinite(x))
    {
      return "non-finite coordinate";
    }
  }
  if (!mesh.VertexNormals.empty() && mesh.VertexNormals.size() != 3 * vertices)
  {
    return "normals size";
  }
  for (const double x : mesh.VertexNormals)
  {
    if (!std::isfinite(x))
    {
      return "non-finite normal";
    }
  }
  if (!mesh.VertexColors.empty() && mesh.VertexColors.size() != 4 * vertices)
  {
    return "vertex colours size";
  }
  if (mesh.FaceOffsets.empty() || mesh.FaceOffsets.front() != 0 ||
    mesh.FaceOffsets.back() != static_cast<std::int64_t>(mesh.FaceConnectivity.size()))
  {
    return "face offsets do not frame the connectivity";
  }
  for (std::size_t f = 0; f + 1 < mesh.FaceOffsets.size(); ++f)
  {
    if (mesh.FaceOffsets[f + 1] - mesh.FaceOffsets[f] < 3)
    {
      return "face " + std::to_string(f) + " has fewer than 3 vertices";
    }
  }
  for (const std::int64_t index : mesh.FaceConnectivity)
  {
    if (index < 0 || index >= static_cast<std::int64_t>(vertices))
    {
      return "index " + std::to_string(index) + " out of range";
    }
  }
  if (!mesh.FaceColors.empty() && mesh.FaceColors.size() != 4 * mesh.FaceCount())
  {
    return "face colours size";
  }
  // "Never an allocation larger than a small multiple of the input size."
  const std::size_t bytes = 8 * (mesh.Points.size() + mesh.VertexNormals.size() + mesh.FaceOffsets.size() +
                                  mesh.FaceConnectivity.size()) +
    mesh.VertexColors.size() + mesh.FaceColors.size();
  if (bytes > 64 * inputSize + 64)
  {
    return "mesh of " + std::to_string(bytes) + " bytes from " + std::to_string(inputSize) + " input bytes";
  }
  return {};
}

/// The mesh as OFF text that must parse back to the same mesh: %.17g for doubles,
/// colours as 0-255 integer literals (so they are not rescaled), four components.
inline std::string WriteOFF(const OFFMesh& mesh)
{
  std::string text;
  text += mesh.VertexColors.empty() ? "" : "C";
  text += mesh.VertexNormals.empty() ? "" : "N";
  text += "OFF\n" + std::to_string(mesh.VertexCount()) + " " + std::to_string(mesh.FaceCount()) + " 0\n";
  char buffer[64];
  for (std::size_t v = 0; v < mesh.VertexCount(); ++v)
  {
    for (int k = 0; k < 3; ++k)
    {
      std::snprintf(buffer, sizeof(buffer), "%.17g ", mesh.Points[3 * v + static_cast<std::size_t>(k)]);
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

inline bool SameMesh(const OFFMesh& a, const OFFMesh& b)
{
  return a.Points == b.Points && a.VertexNormals == b.VertexNormals && a.VertexColors == b.VertexColors &&
    a.FaceOffsets == b.FaceOffsets && a.FaceConnectivity == b.FaceConnectivity && a.FaceColors == b.FaceColors;
}

} // namespace shapediameter::testing
