// SPDX-License-Identifier: BSD-3-Clause
// libFuzzer entry point for the VTK-free OFF parser (Filters/Core/IO/OFFParser.h).
//
// Build and run: see Testing/Fuzz/CMakeLists.txt (clang only), or by hand from the
// repository root:
//   clang++ -g -O1 -fsanitize=fuzzer,address,undefined -std=c++17 -I Filters/Core -I Testing/Common \
//     Filters/Core/IO/OFFParser.cpp Testing/Fuzz/FuzzOFFParser.cpp -o /tmp/fuzz_off
//   /tmp/fuzz_off -max_total_time=60 -rss_limit_mb=512 CORPUS_DIR
//
// A finding is any of: a sanitizer report (out-of-bounds, use-after-free, UB, leak), an
// exception other than OFFParseError (libFuzzer reports the abort), an allocation above
// -rss_limit_mb / -malloc_limit_mb, a timeout, or an accepted mesh that breaks the
// documented invariants: indices in [0, V), finite coordinates and normals, faces of >= 3
// vertices, consistent array sizes, a size that is a small multiple of the input, and a
// lossless round trip (written back as OFF and parsed again, it is identical).
#include "IO/OFFParser.h"
#include "OFFTestOracle.h"

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
  const std::string violation = shapediameter::testing::MeshViolation(mesh, inputSize);
  if (!violation.empty())
  {
    Violation(violation.c_str());
  }
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
  const std::string written = shapediameter::testing::WriteOFF(mesh);
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
  if (!shapediameter::testing::SameMesh(again, mesh))
  {
    Violation("round trip changed the mesh");
  }
  return 0;
}
