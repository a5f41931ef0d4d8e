// SPDX-License-Identifier: BSD-3-Clause
#include "IO/OFFParser.h"
#include "IO/TextFiles.h"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <system_error>

#include <sys/stat.h>

namespace shapediameter
{

namespace
{

/// A whitespace-delimited token, [begin, end) inside the caller's buffer.
struct Token
{
  const char* begin;
  const char* end;

  std::size_t Size() const { return static_cast<std::size_t>(this->end - this->begin); }
  bool Equals(const char* text) const
  {
    const std::size_t length = std::strlen(text);
    return this->Size() == length && std::memcmp(this->begin, text, length) == 0;
  }
};

// '\0' and other control bytes are not whitespace: they end up inside a token and make it
// fail to parse, which is how binary garbage gets reported.
inline bool IsSpace(char c)
{
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

/// The token as it can be shown in a one-line message (TextFiles.h).
std::string Printable(const Token& token)
{
  return PrintableText(token.begin, token.begin + token.Size());
}

std::string Quoted(const Token& token)
{
  return "'" + Printable(token) + "'";
}

[[noreturn]] void Fail(std::int64_t line, const std::string& reason)
{
  throw OFFParseError(std::max<std::int64_t>(line, 1), reason);
}

/// Splits the input into lines, drops `#` comments and returns only lines that hold tokens.
/// The input is a buffer in memory, or an OFFTextSource read a chunk at a time: a line that
/// does not end inside the buffer is moved to the buffer's start and completed by the next
/// reads (the buffer grows only for a line longer than a chunk).
class LineReader
{
public:
  /// The whole input, in memory.
  LineReader(const char* data, std::size_t size)
    : Base(data)
    , Cursor(data)
    , End(data + size)
  {
    this->SkipByteOrderMark();
  }

  /// The input of `source` from byte `offset`, which follows `line` lines (a byte-order mark
  /// is looked for at offset 0 only). The source must be positioned at `offset`.
  LineReader(OFFTextSource& source, std::size_t chunkBytes, std::uint64_t offset, std::int64_t line)
    : Source(&source)
    , ChunkBytes(std::max<std::size_t>(chunkBytes, 1))
    , BaseOffset(offset)
    , TotalSize(source.Size())
    , LineNumber(line)
  {
    this->Buffer.resize(this->ChunkBytes);
    this->Base = this->Cursor = this->End = this->Buffer.data();
    if (offset == 0)
    {
      while (this->End - this->Cursor < 3 && this->Refill())
      {
      }
      this->SkipByteOrderMark();
    }
  }

  /// Advances to the next line with a token outside comments and splits it into tokens.
  /// Returns false at the end of the input. The tokens are valid until the next call.
  bool Next(std::vector<Token>& tokens)
  {
    for (;;)
    {
      const char* lineEnd = this->LineEnd();
      if (this->Cursor == this->End)
      {
        return false;
      }
      const char* begin = this->Cursor;
      this->Cursor = lineEnd < this->End ? lineEnd + 1 : this->End;
      ++this->LineNumber;

      const auto* hash =
        static_cast<const char*>(std::memchr(begin, '#', static_cast<std::size_t>(lineEnd - begin)));
      const char* contentEnd = hash != nullptr ? hash : lineEnd;
      tokens.clear();
      const char* p = begin;
      for (;;)
      {
        while (p < contentEnd && IsSpace(*p))
        {
          ++p;
        }
        if (p == contentEnd)
        {
          break;
        }
        const char* tokenBegin = p;
        while (p < contentEnd && !IsSpace(*p))
        {
          ++p;
        }
        tokens.push_back({ tokenBegin, p });
      }
      if (!tokens.empty())
      {
        return true;
      }
    }
  }

  /// 1-based number of the line last returned (or of the last line when at the end).
  std::int64_t Line() const { return this->LineNumber; }
  /// Byte offset in the input of the next line.
  std::uint64_t Offset() const { return this->BaseOffset + static_cast<std::uint64_t>(this->Cursor - this->Base); }
  std::size_t RemainingBytes() const
  {
    if (this->Source == nullptr)
    {
      return static_cast<std::size_t>(this->End - this->Cursor);
    }
    const std::uint64_t offset = this->Offset();
    return offset < this->TotalSize ? static_cast<std::size_t>(this->TotalSize - offset) : 0;
  }

private:
  void SkipByteOrderMark()
  {
    // A UTF-8 byte-order mark some Windows editors write.
    if (this->End - this->Cursor >= 3 && std::memcmp(this->Cursor, "\xEF\xBB\xBF", 3) == 0)
    {
      this->Cursor += 3;
    }
  }

  /// The '\n' that ends the line at Cursor, or End when the input ends without one; reads
  /// more of a source until then.
  const char* LineEnd()
  {
    std::size_t searched = 0;
    for (;;)
    {
      const char* from = this->Cursor + searched;
      if (from < this->End)
      {
        const auto* newline =
          static_cast<const char*>(std::memchr(from, '\n', static_cast<std::size_t>(this->End - from)));
        if (newline != nullptr)
        {
          return newline;
        }
      }
      searched = static_cast<std::size_t>(this->End - this->Cursor);
      if (!this->Refill())
      {
        return this->End;
      }
    }
  }

  /// Keeps [Cursor, End) at the buffer's start and appends up to one chunk of the source.
  /// False when nothing more was read.
  bool Refill()
  {
    if (this->Source == nullptr || this->Exhausted)
    {
      return false;
    }
    const auto kept = static_cast<std::size_t>(this->End - this->Cursor);
    if (this->Cursor != this->Buffer.data())
    {
      this->BaseOffset += static_cast<std::uint64_t>(this->Cursor - this->Base);
      std::memmove(this->Buffer.data(), this->Cursor, kept);
    }
    if (this->Buffer.size() < kept + this->ChunkBytes)
    {
      this->Buffer.resize(std::max(kept + this->ChunkBytes, 2 * this->Buffer.size()));
    }
    const std::size_t got = this->Source->Read(this->Buffer.data() + kept, this->ChunkBytes);
    this->Exhausted = got == 0;
    this->Base = this->Cursor = this->Buffer.data();
    this->End = this->Cursor + kept + got;
    return got > 0;
  }

  OFFTextSource* Source = nullptr;
  std::size_t ChunkBytes = 0;
  std::vector<char> Buffer;
  bool Exhausted = false;
  /// Offset in the input of Base, the buffer's first byte.
  std::uint64_t BaseOffset = 0;
  std::uint64_t TotalSize = 0;
  const char* Base = nullptr;
  const char* Cursor = nullptr;
  const char* End = nullptr;
  std::int64_t LineNumber = 0;
};

enum class NumberStatus
{
  Ok,
  Malformed,
  OutOfRange
};

/// from_chars rejects the leading '+' that some writers emit; accept exactly one.
inline const char* SkipPlus(const Token& token)
{
  if (token.Size() >= 2 && token.begin[0] == '+' && token.begin[1] != '-' && token.begin[1] != '+')
  {
    return token.begin + 1;
  }
  return token.begin;
}

NumberStatus ParseInteger(const Token& token, std::int64_t& value)
{
  const std::from_chars_result result = std::from_chars(SkipPlus(token), token.end, value);
  if (result.ec == std::errc::result_out_of_range && result.ptr == token.end)
  {
    return NumberStatus::OutOfRange;
  }
  return result.ec == std::errc() && result.ptr == token.end ? NumberStatus::Ok
                                                             : NumberStatus::Malformed;
}

NumberStatus ParseReal(const Token& token, double& value)
{
  const std::from_chars_result result =
    std::from_chars(SkipPlus(token), token.end, value, std::chars_format::general);
  if (result.ec == std::errc::result_out_of_range && result.ptr == token.end)
  {
    return NumberStatus::OutOfRange;
  }
  return result.ec == std::errc() && result.ptr == token.end ? NumberStatus::Ok
                                                             : NumberStatus::Malformed;
}

/// A finite double or an OFFParseError naming the element ("vertex 12").
double ReadFinite(const Token& token, std::int64_t line, const char* element, std::int64_t index)
{
  double value = 0.0;
  const NumberStatus status = ParseReal(token, value);
  if (status == NumberStatus::Ok && std::isfinite(value))
  {
    return value;
  }
  const std::string where = std::string(element) + " " + std::to_string(index) + ": ";
  if (status == NumberStatus::Malformed)
  {
    Fail(line, where + Quoted(token) + " is not a number");
  }
  Fail(line, where + Quoted(token) + " is not a finite number" +
      (status == NumberStatus::OutOfRange ? " (out of double range)" : ""));
}

/// Reads 3 or 4 colour components into rgba (alpha 255 when absent). All-integer components
/// are 0-255, otherwise floats in [0, 1]; both are clamped (see the header).
void ReadColor(const Token* components, std::size_t count, std::uint8_t* rgba, std::int64_t line,
  const char* element, std::int64_t index)
{
  std::int64_t integers[4] = { 0, 0, 0, 255 };
  bool allIntegers = true;
  for (std::size_t k = 0; k < count && allIntegers; ++k)
  {
    allIntegers = ParseInteger(components[k], integers[k]) == NumberStatus::Ok;
  }
  if (allIntegers)
  {
    for (std::size_t k = 0; k < 4; ++k)
    {
      rgba[k] = static_cast<std::uint8_t>(std::clamp<std::int64_t>(integers[k], 0, 255));
    }
    return;
  }
  rgba[3] = 255;
  for (std::size_t k = 0; k < count; ++k)
  {
    const double value = std::clamp(ReadFinite(components[k], line, element, index), 0.0, 1.0);
    rgba[k] = static_cast<std::uint8_t>(std::floor(value * 255.0 + 0.5));
  }
}

struct Header
{
  bool textureCoordinates = false; // ST
  bool colors = false;             // C
  bool normals = false;            // N
};

bool EndsWithOFF(const Token& token)
{
  return token.Size() >= 3 && std::memcmp(token.end - 3, "OFF", 3) == 0;
}

Header ParseKeyword(const Token& keyword, std::int64_t line)
{
  Header header;
  bool fourD = false;
  bool nD = false;
  const char* prefix = keyword.begin;
  const char* prefixEnd = keyword.end - 3;
  // Geomview's order is [ST][C][N][4][n]; writers also emit NCOFF, so any order is accepted.
  while (prefix < prefixEnd)
  {
    bool* flag = nullptr;
    int width = 1;
    switch (*prefix)
    {
      case 'S':
        if (prefix + 1 < prefixEnd && prefix[1] == 'T')
        {
          flag = &header.textureCoordinates;
          width = 2;
        }
        break;
      case 'C':
        flag = &header.colors;
        break;
      case 'N':
        flag = &header.normals;
        break;
      case '4':
        flag = &fourD;
        break;
      case 'n':
        flag = &nD;
        break;
      default:
        break;
    }
    if (flag == nullptr)
    {
      Fail(line, "unknown header keyword " + Quoted(keyword) + " (expected [ST][C][N]OFF)");
    }
    if (*flag)
    {
      Fail(line, "invalid header keyword " + Quoted(keyword) + ": a prefix is repeated");
    }
    *flag = true;
    prefix += width;
  }
  if (fourD || nD)
  {
    Fail(line, "header keyword " + Quoted(keyword) +
        ": 4-D and n-D OFF (4OFF, nOFF) are not supported");
  }
  return header;
}

std::int64_t ReadCount(const Token& token, std::int64_t line, const char* what)
{
  std::int64_t value = 0;
  switch (ParseInteger(token, value))
  {
    case NumberStatus::Malformed:
      Fail(line, std::string(what) + " " + Quoted(token) + " is not an integer");
    case NumberStatus::OutOfRange:
      Fail(line, std::string(what) + " " + Quoted(token) + " is too large");
    case NumberStatus::Ok:
      break;
  }
  if (value < 0)
  {
    Fail(line, std::string(what) + " " + std::to_string(value) + " is negative");
  }
  return value;
}

/// Values on a vertex line besides the colour: x y z, nx ny nz with N, s t with ST.
std::size_t ValuesBesidesColor(const Header& header)
{
  return 3 + (header.normals ? 3 : 0) + (header.textureCoordinates ? 2 : 0);
}

/// Where a parse puts the elements: the whole OFFMesh (ParseOFF).
struct MeshSink
{
  void BeginVertices(std::size_t vertices, const Header& header)
  {
    this->Mesh.Points.resize(3 * vertices);
    if (header.normals)
    {
      this->Mesh.VertexNormals.resize(3 * vertices);
    }
    if (header.colors)
    {
      this->Mesh.VertexColors.resize(4 * vertices);
    }
  }
  void Vertex(std::size_t v, const double* point, const double* normal, const std::uint8_t* color)
  {
    std::copy(point, point + 3, this->Mesh.Points.begin() + static_cast<std::ptrdiff_t>(3 * v));
    if (normal != nullptr)
    {
      std::copy(normal, normal + 3, this->Mesh.VertexNormals.begin() + static_cast<std::ptrdiff_t>(3 * v));
    }
    if (color != nullptr)
    {
      std::copy(color, color + 4, this->Mesh.VertexColors.begin() + static_cast<std::ptrdiff_t>(4 * v));
    }
  }
  void BeginFaces(std::size_t faces)
  {
    this->Faces = faces;
    this->Mesh.FaceOffsets.reserve(faces + 1);
    this->Mesh.FaceOffsets.push_back(0);
    this->Mesh.FaceConnectivity.reserve(3 * faces);
  }
  /// Where a face's indices are appended.
  std::vector<std::int64_t>& FaceIndices() { return this->Mesh.FaceConnectivity; }
  void Face(std::size_t f, const std::int64_t*, std::size_t, const std::uint8_t* color)
  {
    this->Mesh.FaceOffsets.push_back(static_cast<std::int64_t>(this->Mesh.FaceConnectivity.size()));
    if (color == nullptr)
    {
      return;
    }
    if (this->Mesh.FaceColors.empty())
    {
      this->Mesh.FaceColors.resize(4 * this->Faces);
      for (std::size_t g = 0; g < this->Faces; ++g)
      {
        std::copy(kOFFDefaultFaceColor.begin(), kOFFDefaultFaceColor.end(),
          this->Mesh.FaceColors.begin() + static_cast<std::ptrdiff_t>(4 * g));
      }
    }
    std::copy(color, color + 4, this->Mesh.FaceColors.begin() + static_cast<std::ptrdiff_t>(4 * f));
  }

  OFFMesh Mesh;
  std::size_t Faces = 0;
};

/// Where a chunked parse puts the elements: an OFFElementVisitor (ScanOFF, RescanOFF).
struct VisitorSink
{
  void BeginVertices(std::size_t, const Header&) {}
  void Vertex(std::size_t v, const double* point, const double* normal, const std::uint8_t* color)
  {
    this->Visitor.Vertex(static_cast<std::int64_t>(v), point, normal, color);
  }
  void BeginFaces(std::size_t) {}
  std::vector<std::int64_t>& FaceIndices()
  {
    this->Indices.clear();
    return this->Indices;
  }
  void Face(std::size_t f, const std::int64_t* vertices, std::size_t size, const std::uint8_t* color)
  {
    this->AnyFaceColor = this->AnyFaceColor || color != nullptr;
    this->Visitor.Face(static_cast<std::int64_t>(f), vertices, size, color);
  }

  OFFElementVisitor& Visitor;
  std::vector<std::int64_t> Indices;
  bool AnyFaceColor = false;
};

/// One parse: the input's lines, what the header declares, and the sink that receives the
/// elements. The steps run in order (ParseOFF, ScanOFF); each reads its lines through Reader
/// into Tokens.
template <typename Sink>
struct OFFReader
{
  OFFReader(LineReader& reader, Sink& sink)
    : Reader(reader)
    , Elements(sink)
  {
    this->Tokens.reserve(32);
  }

  /// Reads the header keyword (optional) and the line with the counts into Tokens; returns
  /// the index of the first count in Tokens.
  std::size_t ReadKeyword();

  /// Reads "nVertices nFaces [nEdges]" from Tokens[countsBegin, end).
  void ReadCounts(std::size_t countsBegin);

  /// Rejects counts the file cannot hold, before anything is allocated for them.
  void CheckCountsFitInput();

  /// Every vertex, into the sink.
  void ReadVertices();

  /// Vertex v's line: x y z [nx ny nz] [r g b [a]] [s t] (vertexLayout names them).
  void ReadVertex(std::size_t v, const std::string& vertexLayout);

  /// Every face, into the sink.
  void ReadFaces();

  /// Face f's line: n i_0 ... i_{n-1} [colour]; appends the indices to the sink's FaceIndices.
  void ReadFace(std::size_t f);

  /// The `count` values after face f's indices: none, a colour-map index or a colour. True
  /// when they are a colour, then in rgba.
  bool ReadFaceColor(std::size_t f, const Token* values, std::size_t count, std::int64_t line, std::uint8_t* rgba);

  LineReader& Reader;
  Sink& Elements;
  std::vector<Token> Tokens;
  Header Format;
  /// Line of the counts, where count errors are reported.
  std::int64_t CountsLine = 0;
  std::int64_t VertexCount = 0;
  std::int64_t FaceCount = 0;
  /// Values on a vertex line besides the colour: x y z, nx ny nz with N, s t with ST.
  std::size_t FixedVertexValues = 0;
};

template <typename Sink>
std::size_t OFFReader<Sink>::ReadKeyword()
{
  if (!this->Reader.Next(this->Tokens))
  {
    Fail(this->Reader.Line(), "empty file: no OFF header");
  }
  if (!EndsWithOFF(this->Tokens[0]))
  {
    // Geomview makes the keyword optional: a file may start with the counts.
    std::int64_t ignored = 0;
    if (ParseInteger(this->Tokens[0], ignored) == NumberStatus::Malformed)
    {
      Fail(this->Reader.Line(),
        "not an OFF file: expected a header keyword such as OFF or COFF, found " +
          Quoted(this->Tokens[0]));
    }
    return 0;
  }
  this->Format = ParseKeyword(this->Tokens[0], this->Reader.Line());
  if (this->Tokens.size() > 1 && this->Tokens[1].Equals("BINARY"))
  {
    Fail(this->Reader.Line(), "binary OFF is not supported (convert the file to ASCII OFF)");
  }
  if (this->Tokens.size() > 1)
  {
    return 1;
  }
  if (!this->Reader.Next(this->Tokens))
  {
    Fail(this->Reader.Line(), "unexpected end of file: the vertex, face and edge counts are missing");
  }
  return 0;
}

template <typename Sink>
void OFFReader<Sink>::ReadCounts(std::size_t countsBegin)
{
  const std::vector<Token>& tokens = this->Tokens;
  this->CountsLine = this->Reader.Line();
  const std::size_t countValues = tokens.size() - countsBegin;
  if (countValues < 2 || countValues > 3)
  {
    Fail(this->CountsLine,
      "expected the vertex, face and edge counts, found " + std::to_string(countValues) +
        (countValues == 1 ? " value" : " values"));
  }
  this->VertexCount = ReadCount(tokens[countsBegin], this->CountsLine, "vertex count");
  this->FaceCount = ReadCount(tokens[countsBegin + 1], this->CountsLine, "face count");
  if (countValues == 3)
  {
    // The edge count is informative only (often 0); a huge one is harmless.
    std::int64_t ignored = 0;
    if (ParseInteger(tokens[countsBegin + 2], ignored) == NumberStatus::Malformed)
    {
      Fail(this->CountsLine, "edge count " + Quoted(tokens[countsBegin + 2]) + " is not an integer");
    }
  }
}

template <typename Sink>
void OFFReader<Sink>::CheckCountsFitInput()
{
  const Header& header = this->Format;
  this->FixedVertexValues = ValuesBesidesColor(header);
  const std::size_t minimumVertexValues = this->FixedVertexValues + (header.colors ? 3 : 0);
  const std::uint64_t bytesPerVertex = 2 * minimumVertexValues; // "v " per value
  const std::uint64_t bytesPerFace = 8;                          // "3 0 1 2\n"
  const std::uint64_t available = this->Reader.RemainingBytes() + 1; // last line may lack '\n'
  const auto vertices = static_cast<std::uint64_t>(this->VertexCount);
  const auto faces = static_cast<std::uint64_t>(this->FaceCount);
  if (vertices > available / bytesPerVertex || faces > available / bytesPerFace ||
    vertices * bytesPerVertex + faces * bytesPerFace > available)
  {
    Fail(this->CountsLine,
      "the header declares " + std::to_string(this->VertexCount) + " vertices and " +
        std::to_string(this->FaceCount) + " faces but only " +
        std::to_string(this->Reader.RemainingBytes()) + " bytes follow, too few for them (a vertex " +
        "needs at least " + std::to_string(bytesPerVertex) + " bytes, a face " +
        std::to_string(bytesPerFace) + "): truncated file or wrong counts");
  }
}

template <typename Sink>
void OFFReader<Sink>::ReadVertices()
{
  const Header& header = this->Format;
  std::string vertexLayout = "x y z";
  vertexLayout += header.normals ? " nx ny nz" : "";
  vertexLayout += header.colors ? " r g b [a]" : "";
  vertexLayout += header.textureCoordinates ? " s t" : "";

  const auto vertices = static_cast<std::size_t>(this->VertexCount);
  this->Elements.BeginVertices(vertices, header);
  for (std::size_t v = 0; v < vertices; ++v)
  {
    this->ReadVertex(v, vertexLayout);
  }
}

template <typename Sink>
void OFFReader<Sink>::ReadVertex(std::size_t v, const std::string& vertexLayout)
{
  const Header& header = this->Format;
  const std::vector<Token>& tokens = this->Tokens;
  const std::size_t fixedVertexValues = this->FixedVertexValues;
  const auto index = static_cast<std::int64_t>(v);
  if (!this->Reader.Next(this->Tokens))
  {
    Fail(this->Reader.Line(),
      "unexpected end of file: " + std::to_string(v) + " of " + std::to_string(this->VertexCount) +
        " vertices read");
  }
  const std::int64_t line = this->Reader.Line();
  std::size_t colorValues = 0;
  if (header.colors)
  {
    colorValues = tokens.size() >= fixedVertexValues ? tokens.size() - fixedVertexValues : 0;
    if (colorValues != 3 && colorValues != 4)
    {
      Fail(line,
        "vertex " + std::to_string(v) + " has " + std::to_string(tokens.size()) +
          " values, expected " + std::to_string(fixedVertexValues + 3) + " or " +
          std::to_string(fixedVertexValues + 4) + " (" + vertexLayout + ")");
    }
  }
  else if (tokens.size() != fixedVertexValues)
  {
    Fail(line,
      "vertex " + std::to_string(v) + " has " + std::to_string(tokens.size()) +
        " values, expected " + std::to_string(fixedVertexValues) + " (" + vertexLayout + ")");
  }
  std::size_t t = 0;
  double point[3];
  double normal[3];
  std::uint8_t color[4];
  for (std::size_t k = 0; k < 3; ++k)
  {
    point[k] = ReadFinite(tokens[t++], line, "vertex", index);
  }
  if (header.normals)
  {
    for (std::size_t k = 0; k < 3; ++k)
    {
      normal[k] = ReadFinite(tokens[t++], line, "vertex", index);
    }
  }
  if (header.colors)
  {
    ReadColor(&tokens[t], colorValues, color, line, "vertex", index);
    t += colorValues;
  }
  if (header.textureCoordinates)
  {
    for (std::size_t k = 0; k < 2; ++k)
    {
      double dropped = 0.0;
      if (ParseReal(tokens[t], dropped) == NumberStatus::Malformed)
      {
        Fail(line, "vertex " + std::to_string(v) + ": " + Quoted(tokens[t]) + " is not a number");
      }
      ++t;
    }
  }
  this->Elements.Vertex(v, point, header.normals ? normal : nullptr, header.colors ? color : nullptr);
}

template <typename Sink>
void OFFReader<Sink>::ReadFaces()
{
  const auto faces = static_cast<std::size_t>(this->FaceCount);
  this->Elements.BeginFaces(faces);
  for (std::size_t f = 0; f < faces; ++f)
  {
    this->ReadFace(f);
  }
}

template <typename Sink>
void OFFReader<Sink>::ReadFace(std::size_t f)
{
  const std::vector<Token>& tokens = this->Tokens;
  // A local copy: the int64 index stores below may alias the member as far as the compiler
  // knows, and reloading it per index is measurably slower.
  const std::int64_t vertexCount = this->VertexCount;
  if (!this->Reader.Next(this->Tokens))
  {
    Fail(this->Reader.Line(),
      "unexpected end of file: " + std::to_string(f) + " of " + std::to_string(this->FaceCount) +
        " faces read");
  }
  const std::int64_t line = this->Reader.Line();
  const std::size_t valuesAfterSize = tokens.size() - 1;
  std::int64_t faceSize = 0;
  const NumberStatus sizeStatus = ParseInteger(tokens[0], faceSize);
  if (sizeStatus == NumberStatus::Malformed)
  {
    Fail(line, "face " + std::to_string(f) + ": vertex count " + Quoted(tokens[0]) +
        " is not an integer");
  }
  if (sizeStatus == NumberStatus::OutOfRange ||
    (faceSize >= 3 && static_cast<std::uint64_t>(faceSize) > valuesAfterSize))
  {
    Fail(line, "face " + std::to_string(f) + " declares " + Printable(tokens[0]) +
        " vertices but its line holds only " + std::to_string(valuesAfterSize) + " values");
  }
  if (faceSize < 3)
  {
    Fail(line, "face " + std::to_string(f) + " has " + std::to_string(faceSize) +
        " vertices; at least 3 are required");
  }
  const auto corners = static_cast<std::size_t>(faceSize);
  std::vector<std::int64_t>& indices = this->Elements.FaceIndices();
  const std::size_t first = indices.size();
  const std::size_t extra = valuesAfterSize - corners;
  if (extra == 2 || extra > 4)
  {
    Fail(line, "face " + std::to_string(f) + " has " + std::to_string(extra) +
        " values after its " + std::to_string(corners) +
        " indices; expected none, a colour-map index, or an r g b [a] colour");
  }
  for (std::size_t k = 1; k <= corners; ++k)
  {
    std::int64_t vertex = 0;
    const NumberStatus status = ParseInteger(tokens[k], vertex);
    if (status == NumberStatus::Malformed)
    {
      Fail(line, "face " + std::to_string(f) + ": vertex index " + Quoted(tokens[k]) +
          " is not an integer");
    }
    if (status == NumberStatus::OutOfRange || vertex < 0 || vertex >= vertexCount)
    {
      Fail(line, "face " + std::to_string(f) + ": vertex index " + Printable(tokens[k]) +
          " is out of range [0, " + std::to_string(vertexCount) + ")");
    }
    indices.push_back(vertex);
  }
  std::uint8_t rgba[4];
  const bool colored = this->ReadFaceColor(f, tokens.data() + corners + 1, extra, line, rgba);
  this->Elements.Face(f, indices.data() + first, corners, colored ? rgba : nullptr);
}

template <typename Sink>
bool OFFReader<Sink>::ReadFaceColor(
  std::size_t f, const Token* values, std::size_t count, std::int64_t line, std::uint8_t* rgba)
{
  if (count == 1)
  {
    // A Geomview colour-map index: no map to resolve it against, so the face has no colour.
    std::int64_t mapIndex = 0;
    if (ParseInteger(values[0], mapIndex) == NumberStatus::Malformed)
    {
      Fail(line, "face " + std::to_string(f) + ": colour-map index " + Quoted(values[0]) +
          " is not an integer");
    }
  }
  if (count < 3)
  {
    return false;
  }
  ReadColor(values, count, rgba, line, "face", static_cast<std::int64_t>(f));
  return true;
}
} // namespace

OFFParseError::OFFParseError(
  std::int64_t line, const std::string& reason, const std::string& source)
  : Error(LineMessage(line, reason, source))
  , LineNumber(line > 0 ? line : 0)
  , ReasonText(reason)
{
}

OFFMesh ParseOFF(const char* data, std::size_t size)
{
  if (data == nullptr)
  {
    size = 0;
  }
  LineReader lines(data, size);
  MeshSink sink;
  OFFReader<MeshSink> reader(lines, sink);
  reader.ReadCounts(reader.ReadKeyword());
  reader.CheckCountsFitInput();
  reader.ReadVertices();
  reader.ReadFaces();
  // Anything after the declared elements is ignored on purpose (see the header).
  return std::move(sink.Mesh);
}

OFFMesh ReadOFFFile(const std::string& path)
{
  std::string content;
  switch (ReadWholeFile(path, content))
  {
    case FileReadFailure::Open:
      throw OFFParseError(0, std::string("cannot open file: ") + std::strerror(errno), path);
    case FileReadFailure::Read:
      throw OFFParseError(0, std::string("cannot read file: ") + std::strerror(errno), path);
    case FileReadFailure::None:
      break;
  }
  try
  {
    return ParseOFF(content.data(), content.size());
  }
  catch (const OFFParseError& error)
  {
    throw OFFParseError(error.Line(), error.Reason(), path);
  }
}

OFFFileSource::OFFFileSource(const std::string& path)
  : Path(path)
{
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (file == nullptr)
  {
    throw OFFParseError(0, std::string("cannot open file: ") + std::strerror(errno), path);
  }
  this->File = file;
  struct stat status = {};
  if (fstat(fileno(file), &status) != 0)
  {
    const int cause = errno;
    std::fclose(file);
    throw OFFParseError(0, std::string("cannot read file: ") + std::strerror(cause), path);
  }
  this->Bytes = static_cast<std::uint64_t>(std::max<off_t>(status.st_size, 0));
}

OFFFileSource::~OFFFileSource()
{
  std::fclose(static_cast<std::FILE*>(this->File));
}

void OFFFileSource::Seek(std::uint64_t offset)
{
  auto* file = static_cast<std::FILE*>(this->File);
  std::clearerr(file);
  if (fseeko(file, static_cast<off_t>(offset), SEEK_SET) != 0)
  {
    throw OFFParseError(0, std::string("cannot read file: ") + std::strerror(errno), this->Path);
  }
}

std::size_t OFFFileSource::Read(char* into, std::size_t capacity)
{
  auto* file = static_cast<std::FILE*>(this->File);
  const std::size_t got = std::fread(into, 1, capacity, file);
  if (got < capacity && std::ferror(file) != 0)
  {
    throw OFFParseError(0, std::string("cannot read file: ") + std::strerror(errno), this->Path);
  }
  return got;
}

OFFMemorySource::OFFMemorySource(const char* data, std::size_t size)
  : Data(data)
  , Bytes(data == nullptr ? 0 : size)
{
}

void OFFMemorySource::Seek(std::uint64_t offset)
{
  this->Position = static_cast<std::size_t>(std::min<std::uint64_t>(offset, this->Bytes));
}

std::size_t OFFMemorySource::Read(char* into, std::size_t capacity)
{
  const std::size_t got = std::min(capacity, this->Bytes - this->Position);
  if (got > 0)
  {
    std::memcpy(into, this->Data + this->Position, got);
  }
  this->Position += got;
  return got;
}

OFFLayout ScanOFF(OFFTextSource& source, OFFElementVisitor& visitor, std::size_t chunkBytes)
{
  source.Seek(0);
  LineReader lines(source, chunkBytes, 0, 0);
  VisitorSink sink{ visitor, {}, false };
  OFFReader<VisitorSink> reader(lines, sink);
  reader.ReadCounts(reader.ReadKeyword());
  reader.CheckCountsFitInput();
  visitor.Counts(reader.VertexCount, reader.FaceCount);
  OFFLayout layout;
  layout.VertexCount = reader.VertexCount;
  layout.FaceCount = reader.FaceCount;
  layout.Normals = reader.Format.normals;
  layout.VertexColors = reader.Format.colors;
  layout.TextureCoordinates = reader.Format.textureCoordinates;
  layout.VerticesOffset = lines.Offset();
  layout.VerticesLine = lines.Line();
  reader.ReadVertices();
  layout.FacesOffset = lines.Offset();
  layout.FacesLine = lines.Line();
  reader.ReadFaces();
  layout.FaceColors = sink.AnyFaceColor;
  return layout;
}

void RescanOFF(OFFTextSource& source, const OFFLayout& layout, OFFSection section, OFFElementVisitor& visitor,
  std::size_t chunkBytes)
{
  const bool vertices = section == OFFSection::Vertices;
  const std::uint64_t offset = vertices ? layout.VerticesOffset : layout.FacesOffset;
  source.Seek(offset);
  LineReader lines(source, chunkBytes, offset, vertices ? layout.VerticesLine : layout.FacesLine);
  VisitorSink sink{ visitor, {}, false };
  OFFReader<VisitorSink> reader(lines, sink);
  reader.Format.normals = layout.Normals;
  reader.Format.colors = layout.VertexColors;
  reader.Format.textureCoordinates = layout.TextureCoordinates;
  reader.FixedVertexValues = ValuesBesidesColor(reader.Format);
  reader.VertexCount = layout.VertexCount;
  reader.FaceCount = layout.FaceCount;
  if (vertices)
  {
    reader.ReadVertices();
  }
  else
  {
    reader.ReadFaces();
  }
}

} // namespace shapediameter
