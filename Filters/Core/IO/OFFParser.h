// SPDX-License-Identifier: BSD-3-Clause
// VTK-free parser for the ASCII Object File Format (OFF) and its Geomview variants.
//
// What it reads
//   Header keyword [ST][C][N]OFF in any letter order (OFF, COFF, NOFF, CNOFF, NCOFF, STOFF,
//   STCOFF, STCNOFF, ...), followed by "nVertices nFaces [nEdges]" on the keyword line or on a
//   later line. The keyword itself is optional (Geomview allows that): a file whose first
//   token is an integer is read as plain OFF. nEdges is parsed and ignored; it may be omitted.
//   Then one vertex per line:  x y z [nx ny nz if N] [r g b [a] if C] [s t if ST]
//   and one face per line:     n i_0 ... i_{n-1} [colour]
//   where the optional face colour is 3 or 4 components (r g b [a]) or a single Geomview
//   colour-map index. Vertex indices are 0-based.
//   `#` starts a comment anywhere (to end of line); blank lines, tabs and CRLF line endings
//   are accepted; a UTF-8 byte-order mark is skipped; a leading '+' on numbers is accepted.
//
// Colours (vertex and face): a colour whose components are all integer literals is read as
//   0-255 (so "1 0 0" is almost black, not red); otherwise the components are floats in
//   [0, 1] scaled by 255 and rounded. Out-of-range values are clamped; NaN/Inf is an error.
//   A missing alpha is 255. Faces without a colour in a file where some face has one get
//   kOFFDefaultFaceColor. A colour-map index is not resolved (no colour map is available)
//   and counts as "no colour".
//
// Output (OFFMesh): points, and when present normals and RGBA colours, as flat arrays; faces as
//   offsets + connectivity (n-gons kept as they are, no triangulation). Every index is in
//   [0, vertex count), every coordinate and normal is finite, every face has >= 3 vertices.
//   Texture coordinates (ST) are checked to be numbers and dropped.
//
// Errors: every problem throws OFFParseError whose message starts with "line N: " (the
//   1-based line of the file) and states the reason in one line. Never a crash, a hang or an
//   allocation larger than a small multiple of the input size: the header counts are
//   checked against the bytes that follow (a vertex needs at least 2 bytes per value, a face
//   at least 8 bytes) before anything is allocated. Rejected:
//   - empty / comment-only input, binary garbage, an unknown header keyword;
//   - 4OFF / nOFF (4-D and n-D) and "OFF BINARY": "not supported";
//   - negative counts, counts too large for a 64-bit integer, counts that cannot fit the file;
//   - a missing vertex or face line (truncated file);
//   - a vertex line with the wrong number of values, a non-numeric token, NaN/Inf or
//     out-of-double-range coordinates or normals;
//   - a face with fewer than 3 vertices, a face size larger than the indices on its line,
//     a non-integer or out-of-range (negative or >= vertex count) index, a colour of 2 or
//     more than 4 components.
//   Accepted on purpose (lenient): anything after the declared vertices and faces is ignored
//   (many writers append blank lines or comments, some append garbage); faces that repeat a
//   vertex (zero area) are kept, downstream filters handle degenerate faces.
//
// Limits (documented, not errors to fix): each vertex and each face must be on one line
//   (elements spanning several lines are not supported); old Mac CR-only line endings are
//   not supported (the file reads as one line and is rejected).
//
// Cost: one pass over an in-memory buffer with std::from_chars, no iostreams: linear in the
//   file size.
//
// Chunked parsing (ScanOFF, RescanOFF; used by ReadOFFPiece in MeshPieces.h): the same grammar,
//   checks and messages read from an OFFTextSource in chunks of a given size (a line longer
//   than a chunk is carried over and completed by the next reads), handing each vertex and face
//   to a visitor instead of storing the mesh. Memory: one chunk plus the longest line. The
//   header counts are checked against the source's size exactly as against a buffer's.
#pragma once

#include "Errors.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace shapediameter
{

/// Malformed, truncated, unsupported or unreadable OFF input.
/// what() is "[source: ]line N: reason" ("[source: ]reason" when no line applies).
/// The one subclass of Error (Errors.h): it carries the line and the bare reason apart from the
/// message, which callers use (the reader points at the line, ParseOFFFile prefixes the path
/// while keeping the line, the fuzz tests check the line); catching Error catches it too.
class OFFParseError : public Error
{
public:
  /// line: 1-based line of the input, or 0 when the error is not tied to a line.
  /// source: prefix naming the input (e.g. the file path), or empty.
  OFFParseError(std::int64_t line, const std::string& reason, const std::string& source = {});

  /// 1-based line number, 0 when not tied to a line (e.g. the file cannot be opened).
  std::int64_t Line() const noexcept { return this->LineNumber; }
  /// The reason without the source and line prefix.
  const std::string& Reason() const noexcept { return this->ReasonText; }

private:
  std::int64_t LineNumber;
  std::string ReasonText;
};

/// RGBA given to faces without a colour in a file where some face has one: opaque light grey
/// (the grey the CGAL sample COFF files use for their vertices).
inline constexpr std::array<std::uint8_t, 4> kOFFDefaultFaceColor = { 192, 192, 192, 255 };

/// A polygon mesh as read from an OFF file. Sizes: V vertices, F faces.
struct OFFMesh
{
  std::vector<double> Points;             ///< 3 * V: x y z per vertex
  std::vector<double> VertexNormals;      ///< 3 * V when the header has N (NOFF), else empty
  std::vector<std::uint8_t> VertexColors; ///< 4 * V RGBA when the header has C (COFF), else empty
  std::vector<std::int64_t> FaceOffsets;  ///< F + 1, starts at 0; face f is [offsets[f], offsets[f+1])
  std::vector<std::int64_t> FaceConnectivity; ///< vertex indices of all faces, in [0, V)
  std::vector<std::uint8_t> FaceColors;   ///< 4 * F RGBA when any face has a colour, else empty

  std::size_t VertexCount() const noexcept { return this->Points.size() / 3; }
  std::size_t FaceCount() const noexcept
  {
    return this->FaceOffsets.empty() ? 0 : this->FaceOffsets.size() - 1;
  }
};

/// Parses a whole OFF file held in memory (data need not be NUL-terminated; data may be null
/// when size is 0). Throws OFFParseError on any malformed input (see the header comment).
OFFMesh ParseOFF(const char* data, std::size_t size);

/// Reads the file at path and parses it. Throws OFFParseError when the file cannot be opened
/// or read, and on malformed content; the message is then prefixed with the path.
OFFMesh ReadOFFFile(const std::string& path);

// ---- Chunked parsing: what a reader that keeps only part of the file builds on.

/// Bytes read at a time by the chunked parse unless told otherwise (a few MB: large enough
/// that reading costs what one read of the whole file costs, small beside any mesh).
inline constexpr std::size_t kOFFChunkBytes = std::size_t{ 4 } << 20;

/// Input of the chunked parse, read from the start or from an offset, possibly several times.
class OFFTextSource
{
public:
  virtual ~OFFTextSource() = default;
  /// Size in bytes (what the header counts are checked against).
  virtual std::uint64_t Size() const = 0;
  /// Moves to byte `offset`. Throws OFFParseError (line 0) when that fails.
  virtual void Seek(std::uint64_t offset) = 0;
  /// Reads up to `capacity` bytes at the current position into `into`; 0 at the end.
  /// Throws OFFParseError (line 0) on a read error.
  virtual std::size_t Read(char* into, std::size_t capacity) = 0;
};

/// An open file; errors as ReadOFFFile's ("cannot open file: ...", "cannot read file: ...",
/// with the path as the source).
class OFFFileSource : public OFFTextSource
{
public:
  explicit OFFFileSource(const std::string& path);
  ~OFFFileSource() override;
  OFFFileSource(const OFFFileSource&) = delete;
  OFFFileSource& operator=(const OFFFileSource&) = delete;
  std::uint64_t Size() const override { return this->Bytes; }
  void Seek(std::uint64_t offset) override;
  std::size_t Read(char* into, std::size_t capacity) override;

private:
  std::string Path;
  void* File = nullptr; // std::FILE*
  std::uint64_t Bytes = 0;
};

/// Text held in memory (data may be null when size is 0), read through the chunked path.
class OFFMemorySource : public OFFTextSource
{
public:
  OFFMemorySource(const char* data, std::size_t size);
  std::uint64_t Size() const override { return this->Bytes; }
  void Seek(std::uint64_t offset) override;
  std::size_t Read(char* into, std::size_t capacity) override;

private:
  const char* Data;
  std::size_t Bytes;
  std::size_t Position = 0;
};

/// Receives the elements of a chunked parse, in file order. The pointers are valid during the
/// call only.
class OFFElementVisitor
{
public:
  virtual ~OFFElementVisitor() = default;
  /// The header's counts, once they are known to fit the input (before any element).
  virtual void Counts(std::int64_t /*vertices*/, std::int64_t /*faces*/) {}
  /// Vertex `index`: point x y z; normal (NOFF) and RGBA colour (COFF) or null.
  virtual void Vertex(std::int64_t index, const double* point, const double* normal, const std::uint8_t* color) = 0;
  /// Face `index`: its `size` vertex indices (each checked to be in range); its RGBA colour,
  /// or null when the face has none or only a colour-map index.
  virtual void Face(std::int64_t index, const std::int64_t* vertices, std::size_t size, const std::uint8_t* color) = 0;
};

/// What ScanOFF learned of an accepted input: the header, and where the vertex and face lines
/// start, so that RescanOFF can visit one of them again.
struct OFFLayout
{
  std::int64_t VertexCount = 0;
  std::int64_t FaceCount = 0;
  bool Normals = false;            ///< N: the vertices carry normals
  bool VertexColors = false;       ///< C: the vertices carry colours
  bool TextureCoordinates = false; ///< ST
  bool FaceColors = false;         ///< some face has an r g b [a] colour (OFFMesh::FaceColors)
  std::uint64_t VerticesOffset = 0; ///< byte offset just after the counts' line
  std::int64_t VerticesLine = 0;    ///< the counts' line: lines before VerticesOffset
  std::uint64_t FacesOffset = 0;    ///< byte offset just after the last vertex's line
  std::int64_t FacesLine = 0;       ///< lines before FacesOffset
};

enum class OFFSection
{
  Vertices,
  Faces
};

/// Parses the source from its start as ParseOFF parses a buffer (the same checks in the same
/// order, the same OFFParseError messages), reading chunkBytes (>= 1) at a time, and visits
/// every vertex, then every face.
OFFLayout ScanOFF(OFFTextSource& source, OFFElementVisitor& visitor, std::size_t chunkBytes = kOFFChunkBytes);

/// Visits the vertices or the faces of an input ScanOFF accepted, reading only their lines.
/// Checks them again (a file changed in between gives an OFFParseError, never a bad index).
void RescanOFF(OFFTextSource& source, const OFFLayout& layout, OFFSection section, OFFElementVisitor& visitor,
  std::size_t chunkBytes = kOFFChunkBytes);

} // namespace shapediameter
