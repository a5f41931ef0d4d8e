// SPDX-License-Identifier: BSD-3-Clause
// Small helpers shared by the core's text-format readers (OFF, .seg).
#pragma once

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <algorithm>
#include <string>

namespace shapediameter
{

/// "source: line N: reason"; the source and line parts are left out when empty / 0.
inline std::string LineMessage(std::int64_t line, const std::string& reason, const std::string& source)
{
  std::string message;
  if (!source.empty())
  {
    message += source + ": ";
  }
  if (line > 0)
  {
    message += "line " + std::to_string(line) + ": ";
  }
  return message + reason;
}

/// Text of [begin, end) as it can be shown in a one-line message: bytes outside printable
/// ASCII as \xNN, at most 32 bytes shown and then "...", so that binary input cannot garble
/// a terminal or a log.
inline std::string PrintableText(const char* begin, const char* end)
{
  constexpr std::size_t limit = 32;
  std::string out;
  const auto size = static_cast<std::size_t>(end - begin);
  for (std::size_t i = 0; i < std::min(size, limit); ++i)
  {
    const auto c = static_cast<unsigned char>(begin[i]);
    if (c >= 0x20 && c < 0x7f)
    {
      out += static_cast<char>(c);
    }
    else
    {
      char escaped[8];
      std::snprintf(escaped, sizeof(escaped), "\\x%02x", c);
      out += escaped;
    }
  }
  if (size > limit)
  {
    out += "...";
  }
  return out;
}

enum class FileReadFailure
{
  None,
  Open,
  Read
};

/// Reads a whole file into `content`. On failure says which step failed; errno keeps the
/// cause for the caller's message.
inline FileReadFailure ReadWholeFile(const std::string& path, std::string& content)
{
  std::FILE* file = std::fopen(path.c_str(), "rb");
  if (!file)
  {
    return FileReadFailure::Open;
  }
  content.clear();
  char buffer[1 << 16];
  std::size_t got = 0;
  while ((got = std::fread(buffer, 1, sizeof(buffer), file)) > 0)
  {
    content.append(buffer, got);
  }
  const bool failed = std::ferror(file) != 0;
  const int cause = errno;
  std::fclose(file);
  errno = cause;
  return failed ? FileReadFailure::Read : FileReadFailure::None;
}

} // namespace shapediameter
