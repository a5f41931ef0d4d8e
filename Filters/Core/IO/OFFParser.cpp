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
class LineReader
{
public:
  LineReader(const char* data, std::size_t size)
    : Cursor(data)
    , End(data + size)
  {
    // A UTF-8 byte-order mark some Windows editors write.
    if (size >= 3 && std::memcmp(data, "\xEF\xBB\xBF", 3) == 0)
    {
      this->Cursor += 3;
    }
  }

  /// Advances to the next line with a token outside comments and splits it into tokens.
  /// Returns false at the end of the input.
  bool Next(std::vector<Token>& tokens)
  {
    while (this->Cursor < this->End)
    {
      const char* begin = this->Cursor;
      const auto remaining = static_cast<std::size_t>(this->End - begin);
      const auto* newline = static_cast<const char*>(std::memchr(begin, '\n', remaining));
      const char* lineEnd = newline != nullptr ? newline : this->End;
      this->Cursor = newline != nullptr ? newline + 1 : this->End;
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
    return false;
  }

  /// 1-based number of the line last returned (or of the last line when at the end).
  std::int64_t Line() const { return this->LineNumber; }
  std::size_t RemainingBytes() const { return static_cast<std::size_t>(this->End - this->Cursor); }

private:
  const char* Cursor;
  const char* End;
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

} // namespace

OFFParseError::OFFParseError(
  std::int64_t line, const std::string& reason, const std::string& source)
  : std::runtime_error(LineMessage(line, reason, source))
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
  LineReader reader(data, size);
  std::vector<Token> tokens;
  tokens.reserve(32);

  // ---- header keyword and counts
  if (!reader.Next(tokens))
  {
    Fail(reader.Line(), "empty file: no OFF header");
  }
  Header header;
  std::size_t countsBegin = 0;
  if (EndsWithOFF(tokens[0]))
  {
    header = ParseKeyword(tokens[0], reader.Line());
    if (tokens.size() > 1 && tokens[1].Equals("BINARY"))
    {
      Fail(reader.Line(), "binary OFF is not supported (convert the file to ASCII OFF)");
    }
    countsBegin = 1;
    if (tokens.size() == 1)
    {
      if (!reader.Next(tokens))
      {
        Fail(reader.Line(), "unexpected end of file: the vertex, face and edge counts are missing");
      }
      countsBegin = 0;
    }
  }
  else
  {
    // Geomview makes the keyword optional: a file may start with the counts.
    std::int64_t ignored = 0;
    if (ParseInteger(tokens[0], ignored) == NumberStatus::Malformed)
    {
      Fail(reader.Line(),
        "not an OFF file: expected a header keyword such as OFF or COFF, found " +
          Quoted(tokens[0]));
    }
  }
  const std::int64_t countsLine = reader.Line();
  const std::size_t countValues = tokens.size() - countsBegin;
  if (countValues < 2 || countValues > 3)
  {
    Fail(countsLine,
      "expected the vertex, face and edge counts, found " + std::to_string(countValues) +
        (countValues == 1 ? " value" : " values"));
  }
  const std::int64_t vertexCount = ReadCount(tokens[countsBegin], countsLine, "vertex count");
  const std::int64_t faceCount = ReadCount(tokens[countsBegin + 1], countsLine, "face count");
  if (countValues == 3)
  {
    // The edge count is informative only (often 0); a huge one is harmless.
    std::int64_t ignored = 0;
    if (ParseInteger(tokens[countsBegin + 2], ignored) == NumberStatus::Malformed)
    {
      Fail(countsLine, "edge count " + Quoted(tokens[countsBegin + 2]) + " is not an integer");
    }
  }

  // ---- reject counts the file cannot hold, before allocating anything for them
  const std::size_t fixedVertexValues =
    3 + (header.normals ? 3 : 0) + (header.textureCoordinates ? 2 : 0);
  const std::size_t minimumVertexValues = fixedVertexValues + (header.colors ? 3 : 0);
  {
    const std::uint64_t bytesPerVertex = 2 * minimumVertexValues; // "v " per value
    const std::uint64_t bytesPerFace = 8;                          // "3 0 1 2\n"
    const std::uint64_t available = reader.RemainingBytes() + 1; // last line may lack '\n'
    const auto vertices = static_cast<std::uint64_t>(vertexCount);
    const auto faces = static_cast<std::uint64_t>(faceCount);
    if (vertices > available / bytesPerVertex || faces > available / bytesPerFace ||
      vertices * bytesPerVertex + faces * bytesPerFace > available)
    {
      Fail(countsLine,
        "the header declares " + std::to_string(vertexCount) + " vertices and " +
          std::to_string(faceCount) + " faces but only " +
          std::to_string(reader.RemainingBytes()) + " bytes follow, too few for them (a vertex " +
          "needs at least " + std::to_string(bytesPerVertex) + " bytes, a face " +
          std::to_string(bytesPerFace) + "): truncated file or wrong counts");
    }
  }

  std::string vertexLayout = "x y z";
  vertexLayout += header.normals ? " nx ny nz" : "";
  vertexLayout += header.colors ? " r g b [a]" : "";
  vertexLayout += header.textureCoordinates ? " s t" : "";

  OFFMesh mesh;
  const auto vertices = static_cast<std::size_t>(vertexCount);
  const auto faces = static_cast<std::size_t>(faceCount);

  // ---- vertices
  mesh.Points.resize(3 * vertices);
  if (header.normals)
  {
    mesh.VertexNormals.resize(3 * vertices);
  }
  if (header.colors)
  {
    mesh.VertexColors.resize(4 * vertices);
  }
  for (std::size_t v = 0; v < vertices; ++v)
  {
    const auto index = static_cast<std::int64_t>(v);
    if (!reader.Next(tokens))
    {
      Fail(reader.Line(),
        "unexpected end of file: " + std::to_string(v) + " of " + std::to_string(vertexCount) +
          " vertices read");
    }
    const std::int64_t line = reader.Line();
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
    for (std::size_t k = 0; k < 3; ++k)
    {
      mesh.Points[3 * v + k] = ReadFinite(tokens[t++], line, "vertex", index);
    }
    if (header.normals)
    {
      for (std::size_t k = 0; k < 3; ++k)
      {
        mesh.VertexNormals[3 * v + k] = ReadFinite(tokens[t++], line, "vertex", index);
      }
    }
    if (header.colors)
    {
      ReadColor(&tokens[t], colorValues, &mesh.VertexColors[4 * v], line, "vertex", index);
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
  }

  // ---- faces
  mesh.FaceOffsets.reserve(faces + 1);
  mesh.FaceOffsets.push_back(0);
  mesh.FaceConnectivity.reserve(3 * faces);
  for (std::size_t f = 0; f < faces; ++f)
  {
    const auto index = static_cast<std::int64_t>(f);
    if (!reader.Next(tokens))
    {
      Fail(reader.Line(),
        "unexpected end of file: " + std::to_string(f) + " of " + std::to_string(faceCount) +
          " faces read");
    }
    const std::int64_t line = reader.Line();
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
      mesh.FaceConnectivity.push_back(vertex);
    }
    if (extra == 1)
    {
      // A Geomview colour-map index: no map to resolve it against, so the face has no colour.
      std::int64_t mapIndex = 0;
      if (ParseInteger(tokens[corners + 1], mapIndex) == NumberStatus::Malformed)
      {
        Fail(line, "face " + std::to_string(f) + ": colour-map index " +
            Quoted(tokens[corners + 1]) + " is not an integer");
      }
    }
    else if (extra >= 3)
    {
      if (mesh.FaceColors.empty())
      {
        mesh.FaceColors.resize(4 * faces);
        for (std::size_t g = 0; g < faces; ++g)
        {
          std::copy(kOFFDefaultFaceColor.begin(), kOFFDefaultFaceColor.end(),
            mesh.FaceColors.begin() + static_cast<std::ptrdiff_t>(4 * g));
        }
      }
      ReadColor(&tokens[corners + 1], extra, &mesh.FaceColors[4 * f], line, "face", index);
    }
    mesh.FaceOffsets.push_back(static_cast<std::int64_t>(mesh.FaceConnectivity.size()));
  }
  // Anything after the declared elements is ignored on purpose (see the header).
  return mesh;
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

} // namespace shapediameter
