// SPDX-License-Identifier: BSD-3-Clause
// What the evaluation CLIs share for their --json output: a string as a JSON string literal.
#pragma once

#include <cstdio>
#include <string>

namespace shapediameter::evaluation
{

/// text as a JSON string literal: quotes and backslashes escaped, control bytes as \u00XX.
inline std::string JsonString(const std::string& text)
{
  std::string out = "\"";
  for (const char c : text)
  {
    const auto byte = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\')
    {
      out += '\\';
      out += c;
    }
    else if (byte < 0x20)
    {
      char escaped[8];
      std::snprintf(escaped, sizeof(escaped), "\\u%04x", byte);
      out += escaped;
    }
    else
    {
      out += c;
    }
  }
  return out + "\"";
}

} // namespace shapediameter::evaluation
