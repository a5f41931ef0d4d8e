// SPDX-License-Identifier: BSD-3-Clause
// Seeded mutation fuzzing of the OFF parser (ParseOFF), run in ctest.
//
// Unlike TestOFFParser's fixed 2000-edit loop, this runs a fixed number of mutated inputs
// (kIterationsPerSeed for each of four fixed seeds, so every run parses the same inputs on
// every machine, however busy), starts from more valid variants (OFF, COFF,
// NOFF, CNOFF, ST, n-gons, face colours, CRLF, comments, no keyword), and applies both
// byte-level mutations (bit flips, random bytes, insertions, deletions, range
// duplication, crossover between seeds, truncation, line-ending changes) and
// token/line-level ones (huge counts, negative numbers, nan/inf and out-of-range floats,
// thousand-digit numbers, very long lines, swapped/duplicated/deleted lines, header
// keyword swaps, face sizes changed). Oracle per input:
//   - ParseOFF either throws OFFParseError (one-line message, line number within the
//     input) -- any other exception is a failure -- or
//   - returns a mesh that satisfies every documented invariant (indices in range,
//     finite coordinates and normals, faces of >= 3 vertices, consistent array sizes),
//     whose size is a small multiple of the input size, and which survives a round trip:
//     written back as OFF text and parsed again, it is identical.
// No parse may hang: a CPU-time watchdog (HangWatchdog) ends the test with the seed and the
// iteration when one parse uses more than kHangSeconds of its thread's CPU time, even if it
// never returns (a linear parse of the largest input, ~200 kB, takes about 1 ms of CPU even
// under ASan; the bound is thousands of times that and counts CPU time, not wall time, so
// other processes on the machine cannot trip it). Any other failure prints the seed, the
// iteration and the offending input (escaped), so it can be replayed.
//
// Each input also goes through the chunked piece reader (ParseOFFPiece, chunks of 1 to 61
// bytes, 1 to 4 pieces, both orders), which must give what ExtractFacePiece(ParseOFF(...))
// gives: the same piece or the same error (OFFPieceOracle.h).
//
// Separately: a header declaring 2^40 vertices (or faces) in a tiny file is rejected
// without allocating for the declared counts, by ParseOFF and by ParseOFFPiece (peak RSS
// growth checked with getrusage, and
// the address space is capped during the call so that even an untouched giant allocation
// would fail), and without looping over the declared counts (the same CPU-time bound).
#include "IO/OFFParser.h"
#include "IO/OFFPieceOracle.h"
#include "OFFTestOracle.h"

#include <gtest/gtest.h>

#include <csignal>
#include <sys/resource.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace
{

using shapediameter::OFFMesh;
using shapediameter::OFFParseError;
using shapediameter::ParseOFF;
using shapediameter::PieceOrder;
using shapediameter::testing::MeshViolation;
using shapediameter::testing::PieceDifference;
using shapediameter::testing::SameMesh;
using shapediameter::testing::WriteOFF;

/// Inputs per seed: a few seconds in the ASan/UBSan build (about 6000 inputs/s there).
constexpr std::uint64_t kIterationsPerSeed = 5000;

/// A hang, not a slow machine: CPU seconds of one parse (or rejection) and its round trip.
constexpr int kHangSeconds = 5;

/// CPU time of the calling thread, in seconds (unaffected by other processes' load).
double ThreadCpuSeconds()
{
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

/// What the watchdog reports; written before each parse (a signal handler may only read it).
char gHangContext[160] = "";

extern "C" void OnHang(int)
{
  static const char prefix[] = "\nOFF parser hang: more than 5 s of CPU time on ";
  static_assert(kHangSeconds == 5, "update the message");
  ssize_t ignored = write(STDERR_FILENO, prefix, sizeof(prefix) - 1);
  ignored = write(STDERR_FILENO, gHangContext, std::strlen(gHangContext));
  ignored = write(STDERR_FILENO, "\n", 1);
  static_cast<void>(ignored);
  _exit(1);
}

/// A timer on the calling thread's CPU clock, re-armed with Arm() before each parse: when a
/// parse uses kHangSeconds of CPU without returning, the process ends with gHangContext
/// (a check after the call would never run for a parse that does not return).
class HangWatchdog
{
public:
  HangWatchdog()
  {
    std::signal(SIGALRM, OnHang);
    sigevent event{};
    event.sigev_notify = SIGEV_SIGNAL;
    event.sigev_signo = SIGALRM;
    this->Valid = timer_create(CLOCK_THREAD_CPUTIME_ID, &event, &this->Timer) == 0;
    EXPECT_TRUE(this->Valid) << "timer_create failed: no hang detection";
  }
  ~HangWatchdog()
  {
    if (this->Valid)
    {
      timer_delete(this->Timer);
    }
    std::signal(SIGALRM, SIG_DFL);
  }
  HangWatchdog(const HangWatchdog&) = delete;
  HangWatchdog& operator=(const HangWatchdog&) = delete;

  /// Restarts the countdown for the parse described by the printf-style arguments.
  template <typename... Arguments>
  void Arm(const char* format, Arguments... arguments)
  {
    std::snprintf(gHangContext, sizeof(gHangContext), format, arguments...);
    itimerspec countdown{};
    countdown.it_value.tv_sec = kHangSeconds;
    if (this->Valid)
    {
      timer_settime(this->Timer, 0, &countdown, nullptr);
    }
  }

private:
  timer_t Timer{};
  bool Valid = false;
};

// ------------------------------------------------------------------ seeds

const std::vector<std::string>& SeedTexts()
{
  static const std::vector<std::string> seeds = {
    // Plain tetrahedron.
    "OFF\n4 4 6\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n",
    // Counts on the keyword line, n-gons, face colours (int, float, 3 and 4 components,
    // colour-map index), comments everywhere.
    "OFF 6 3 0 # a prism cap and two quads\n"
    "# vertices\n"
    "0 0 0\n1 0 0\n0.5 0.866 0\n0 0 1\n1 0 1 # comment\n0.5 0.866 1\n"
    "3 0 1 2 255 0 0\n"
    "4 0 1 4 3 0.5 0.5 0.5 1\n"
    "4 1 2 5 4 7\n",
    // COFF with integer and float vertex colours.
    "COFF\n4 2 0\n0 0 0 255 0 0 255\n1 0 0 0 255 0\n1 1 0 0.5 0.5 0.5 1\n0 1 0 10 20 30 40\n"
    "3 0 1 2\n3 0 2 3\n",
    // NOFF with normals.
    "NOFF\n3 1 0\n0 0 0 0 0 1\n1 0 0 0 0 1\n0 1 0 0 0 1\n3 0 1 2\n",
    // CNOFF: normals then colours; CRLF line endings; a BOM.
    "\xEF\xBB\xBF"
    "CNOFF\r\n3 1 0\r\n0 0 0 0 0 1 255 255 255\r\n1 0 0 0 0 1 0 0 0 128\r\n"
    "0 1 0 0 0 1 1 2 3\r\n3 0 1 2\r\n",
    // STOFF with texture coordinates, tabs, a hexagon.
    "STOFF\n6\t1\t0\n1 0 0 0 0\n0.5 0.866 0 1 0\n-0.5 0.866 0 1 1\n-1 0 0 0 1\n"
    "-0.5 -0.866 0 0.5 0.5\n0.5 -0.866 0 0.25 0.75\n6\t0 1 2 3 4 5\n",
    // No keyword (Geomview allows it), exponents, signs, no final newline.
    "4 2\n+1e0 -0.0 2.5E-1\n-1 0 0\n0 1e-3 0\n0 0 .5\n3 0 1 2\n3 1 2 3",
  };
  return seeds;
}

// Tokens that stress the number grammar and the count checks.
const char* const kHugeCounts[] = { "1099511627776", "4294967296", "4294967295", "2147483648",
  "9223372036854775807", "9223372036854775808", "18446744073709551615", "18446744073709551616",
  "99999999999999999999999999", "1e9", "65536" };
const char* const kNegatives[] = { "-1", "-0", "-3", "-2147483648", "-9223372036854775808",
  "-9223372036854775809", "-1e308", "-" };
const char* const kOddNumbers[] = { "nan", "NaN", "-nan", "inf", "-inf", "Infinity", "1e309",
  "-1e309", "1e-400", "4.9e-324", "0x10", "1,5", "1.2.3", "--1", "+-1", "+", ".", "e5", "1e",
  "1.", "3.0", "0003", "1e+308", "\xff", "\x00" };
const char* const kKeywords[] = { "OFF", "COFF", "NOFF", "CNOFF", "NCOFF", "STOFF", "STCNOFF",
  "4OFF", "nOFF", "OFF BINARY", "CCOFF", "off", "OF", "", "OFF OFF", "#OFF" };

// ------------------------------------------------------------------ the mutator

struct TokenSpan
{
  std::size_t Begin;
  std::size_t End;
};

bool IsSpace(char c)
{
  return c == ' ' || c == '\t' || c == '\r' || c == '\n';
}

std::vector<TokenSpan> Tokens(const std::string& text)
{
  std::vector<TokenSpan> tokens;
  std::size_t i = 0;
  while (i < text.size())
  {
    while (i < text.size() && IsSpace(text[i]))
    {
      ++i;
    }
    const std::size_t begin = i;
    while (i < text.size() && !IsSpace(text[i]))
    {
      ++i;
    }
    if (i > begin)
    {
      tokens.push_back({ begin, i });
    }
  }
  return tokens;
}

/// Lines as [begin, end) without their '\n'.
std::vector<TokenSpan> Lines(const std::string& text)
{
  std::vector<TokenSpan> lines;
  std::size_t begin = 0;
  for (std::size_t i = 0; i <= text.size(); ++i)
  {
    if (i == text.size() || text[i] == '\n')
    {
      lines.push_back({ begin, i });
      begin = i + 1;
    }
  }
  return lines;
}

class Mutator
{
public:
  explicit Mutator(std::uint64_t seed)
    : Random(seed)
  {
  }

  /// Uniform-enough integer in [0, n) (n > 0); modulo bias does not matter here.
  std::uint64_t Below(std::uint64_t n) { return n == 0 ? 0 : this->Random() % n; }

  template <typename T, std::size_t N>
  const T& Pick(const T (&items)[N])
  {
    return items[this->Below(N)];
  }

  std::string Mutated()
  {
    const std::vector<std::string>& seeds = SeedTexts();
    std::string text = seeds[this->Below(seeds.size())];
    const int edits = 1 + static_cast<int>(this->Below(6));
    for (int e = 0; e < edits; ++e)
    {
      this->MutateOnce(text);
    }
    return text;
  }

private:
  void ReplaceToken(std::string& text, const std::string& replacement)
  {
    const std::vector<TokenSpan> tokens = Tokens(text);
    if (tokens.empty())
    {
      text += replacement;
      return;
    }
    // Early tokens (keyword, counts) matter most: half the time pick among the first four.
    const std::size_t which = this->Below(2) == 0 ? this->Below(std::min<std::size_t>(4, tokens.size()))
                                                  : this->Below(tokens.size());
    const TokenSpan span = tokens[which];
    text.replace(span.Begin, span.End - span.Begin, replacement);
  }

  void MutateOnce(std::string& text)
  {
    const std::size_t at = this->Below(text.size() + 1);
    switch (this->Below(20))
    {
      case 0: // flip one bit
        if (!text.empty())
        {
          text[std::min(at, text.size() - 1)] ^= static_cast<char>(1u << this->Below(8));
        }
        break;
      case 1: // random byte
        if (!text.empty())
        {
          text[std::min(at, text.size() - 1)] = static_cast<char>(this->Below(256));
        }
        break;
      case 2: // insert a few bytes that matter to the grammar
      {
        static const char kGrammar[] = "0123456789-+.eE# \t\n\r";
        const std::size_t count = 1 + this->Below(8);
        for (std::size_t i = 0; i < count; ++i)
        {
          text.insert(text.begin() + static_cast<std::ptrdiff_t>(at), kGrammar[this->Below(sizeof(kGrammar) - 1)]);
        }
        break;
      }
      case 3: // delete a range
        text.erase(std::min(at, text.size()), 1 + this->Below(16));
        break;
      case 4: // duplicate a range elsewhere
      {
        if (text.empty())
        {
          break;
        }
        const std::size_t from = this->Below(text.size());
        const std::string chunk = text.substr(from, 1 + this->Below(64));
        text.insert(this->Below(text.size() + 1), chunk);
        break;
      }
      case 5: // overwrite a line with another one
      case 6: // duplicate a line
      case 7: // delete a line
      {
        const std::vector<TokenSpan> lines = Lines(text);
        const TokenSpan a = lines[this->Below(lines.size())];
        const TokenSpan b = lines[this->Below(lines.size())];
        const std::string lineA = text.substr(a.Begin, a.End - a.Begin);
        const std::string lineB = text.substr(b.Begin, b.End - b.Begin);
        const std::uint64_t kind = this->Below(3);
        if (kind == 0)
        {
          text.replace(a.Begin, a.End - a.Begin, lineB);
        }
        else if (kind == 1)
        {
          text.insert(a.Begin, lineA + "\n");
        }
        else
        {
          text.erase(a.Begin, std::min(text.size(), a.End + 1) - a.Begin);
        }
        break;
      }
      case 8:
        this->ReplaceToken(text, this->Pick(kHugeCounts));
        break;
      case 9:
        this->ReplaceToken(text, this->Pick(kNegatives));
        break;
      case 10:
      {
        const std::string odd = this->Pick(kOddNumbers);
        this->ReplaceToken(text, odd.empty() ? std::string(1, '\0') : odd);
        break;
      }
      case 11: // a very long line
      {
        const std::size_t length = 1000 + this->Below(100000);
        const char fill = " 0#9\t-"[this->Below(6)];
        text.insert(at, std::string(length, fill) + (this->Below(2) ? "\n" : ""));
        break;
      }
      case 12: // a thousand-digit number
      {
        const std::size_t length = 300 + this->Below(2000);
        std::string digits = this->Below(2) ? std::string(length, '9') : std::string(length, '0') + "1";
        if (this->Below(2))
        {
          digits.insert(this->Below(digits.size()), ".");
        }
        this->ReplaceToken(text, digits);
        break;
      }
      case 13: // truncate
        text.resize(std::min(at, text.size()));
        break;
      case 14: // swap the header keyword
      {
        const std::vector<TokenSpan> tokens = Tokens(text);
        const std::string keyword = this->Pick(kKeywords);
        if (!tokens.empty() && tokens[0].End - tokens[0].Begin <= 7)
        {
          text.replace(tokens[0].Begin, tokens[0].End - tokens[0].Begin, keyword);
        }
        else
        {
          text.insert(0, keyword + "\n");
        }
        break;
      }
      case 15: // line endings: CRLF, CR only, or none
      {
        const int kind = static_cast<int>(this->Below(3));
        std::string result;
        for (char c : text)
        {
          if (c == '\n')
          {
            result += kind == 0 ? "\r\n" : kind == 1 ? "\r" : " ";
          }
          else
          {
            result += c;
          }
        }
        text = result;
        break;
      }
      case 16: // crossover with another seed
      {
        const std::vector<std::string>& seeds = SeedTexts();
        const std::string& other = seeds[this->Below(seeds.size())];
        text = text.substr(0, std::min(at, text.size())) + other.substr(this->Below(other.size()));
        break;
      }
      case 17: // a comment in the middle of something
        text.insert(at, this->Below(2) ? "#" : "# comment 1 2 3\n");
        break;
      case 18: // change the first value of a line (often a face's vertex count)
      {
        const std::vector<TokenSpan> lines = Lines(text);
        const TokenSpan line = lines[this->Below(lines.size())];
        std::size_t begin = line.Begin;
        while (begin < line.End && IsSpace(text[begin]))
        {
          ++begin;
        }
        std::size_t end = begin;
        while (end < line.End && !IsSpace(text[end]))
        {
          ++end;
        }
        text.replace(begin, end - begin, std::to_string(this->Below(12)));
        break;
      }
      default: // repeat the whole body (more elements than declared)
        text += text.substr(std::min(at, text.size()));
        break;
    }
  }

  std::mt19937_64 Random;
};

// ------------------------------------------------------------------ the oracle

std::string Escaped(const std::string& text, std::size_t limit = 600)
{
  std::string out;
  for (std::size_t i = 0; i < text.size() && i < limit; ++i)
  {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c == '\n')
    {
      out += "\\n\n";
    }
    else if (c < 0x20 || c >= 0x7f)
    {
      char buffer[8];
      std::snprintf(buffer, sizeof(buffer), "\\x%02X", c);
      out += buffer;
    }
    else
    {
      out += static_cast<char>(c);
    }
  }
  if (text.size() > limit)
  {
    out += "... (" + std::to_string(text.size()) + " bytes)";
  }
  return out;
}

struct FuzzStatistics
{
  std::uint64_t Iterations = 0;
  std::uint64_t Parsed = 0;
  std::uint64_t Rejected = 0;
  double SlowestSeconds = 0.0;
  std::size_t SlowestInputSize = 0;
};

/// ParseOFF on a heap copy of exactly text.size() bytes: a std::string's buffer ends in a
/// '\0' (and often spare capacity) that would hide a read past the end from ASan.
OFFMesh ParseExact(const std::string& text)
{
  const std::unique_ptr<char[]> exact(new char[text.size()]);
  std::memcpy(exact.get(), text.data(), text.size());
  return ParseOFF(exact.get(), text.size());
}

/// Runs kIterationsPerSeed inputs from one seed; returns false (after reporting) at the first
/// violation.
bool FuzzSeed(std::uint64_t seed, FuzzStatistics& statistics)
{
  HangWatchdog watchdog;
  Mutator mutator(seed);
  for (std::uint64_t iteration = 0; iteration < kIterationsPerSeed; ++iteration)
  {
    const std::string text = mutator.Mutated();
    const std::size_t newlines = static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
    const auto context = [&] {
      return "seed " + std::to_string(seed) + ", iteration " + std::to_string(iteration) + ", input:\n" +
        Escaped(text);
    };
    ++statistics.Iterations;
    watchdog.Arm("seed %" PRIu64 ", iteration %" PRIu64 " (%zu bytes): replay with Mutator(seed)", seed,
      iteration, text.size());
    const double start = ThreadCpuSeconds();
    const int pieces = 1 + static_cast<int>(iteration % 4);
    const std::string pieceDifference = PieceDifference(text, static_cast<int>((iteration / 4) % pieces), pieces,
      iteration % 2 == 0 ? PieceOrder::Spatial : PieceOrder::FileOrder, 1 + (iteration * 7919) % 61);
    if (!pieceDifference.empty())
    {
      ADD_FAILURE() << "chunked piece reader: " << pieceDifference << " from " << context();
      return false;
    }
    try
    {
      const OFFMesh mesh = ParseExact(text);
      const std::string violation = MeshViolation(mesh, text.size());
      if (!violation.empty())
      {
        ADD_FAILURE() << "invalid mesh (" << violation << ") from " << context();
        return false;
      }
      const std::string written = WriteOFF(mesh);
      try
      {
        if (!SameMesh(ParseExact(written), mesh))
        {
          ADD_FAILURE() << "round trip changed the mesh; written:\n"
                        << Escaped(written) << "\nfrom " << context();
          return false;
        }
      }
      catch (const OFFParseError& error)
      {
        ADD_FAILURE() << "the parsed mesh written back does not parse (" << error.what() << "); written:\n"
                      << Escaped(written) << "\nfrom " << context();
        return false;
      }
      ++statistics.Parsed;
    }
    catch (const OFFParseError& error)
    {
      const std::string message = error.what();
      if (message.empty() || message.find('\n') != std::string::npos || error.Line() < 0 ||
        static_cast<std::size_t>(error.Line()) > newlines + 1)
      {
        ADD_FAILURE() << "bad error (line " << error.Line() << "): '" << Escaped(message) << "' from "
                      << context();
        return false;
      }
      ++statistics.Rejected;
    }
    catch (const std::exception& error)
    {
      ADD_FAILURE() << "unexpected exception " << typeid(error).name() << ": " << error.what() << " from "
                    << context();
      return false;
    }
    const double seconds = ThreadCpuSeconds() - start;
    if (seconds > statistics.SlowestSeconds)
    {
      statistics.SlowestSeconds = seconds;
      statistics.SlowestInputSize = text.size();
    }
  }
  return true;
}

TEST(OFFParserFuzz, FixedMutationsFromSeveralSeeds)
{
  const std::uint64_t seeds[] = { 1, 2008, 0x5DF2008, 0xC0FFEEULL << 20 };
  FuzzStatistics statistics;
  for (const std::uint64_t seed : seeds)
  {
    if (!FuzzSeed(seed, statistics))
    {
      break;
    }
  }
  std::printf("OFF fuzz: %" PRIu64 " inputs, %" PRIu64 " parsed, %" PRIu64 " rejected, slowest %.2f ms CPU (%zu bytes)\n",
    statistics.Iterations, statistics.Parsed, statistics.Rejected, 1e3 * statistics.SlowestSeconds,
    statistics.SlowestInputSize);
  // Both outcomes occur often, so the mutations really explore the grammar (the counts are
  // the same on every run: 1523 parsed and 18477 rejected of 20000 when this was written).
  EXPECT_GT(statistics.Parsed, 200u);
  EXPECT_GT(statistics.Rejected, 200u);
}

// ------------------------------------------------------------------ giant header counts

long PeakRSSKilobytes()
{
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss; // kilobytes on Linux
}

/// Current virtual size in bytes (VmSize of /proc/self/status), 0 when unknown.
std::uint64_t VirtualSizeBytes()
{
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
  {
    if (line.rfind("VmSize:", 0) == 0)
    {
      return std::stoull(line.substr(7)) * 1024;
    }
  }
  return 0;
}

/// Caps the address space at the current size + `headroom` for its lifetime, so that an
/// allocation for declared counts fails with bad_alloc even if it would never be touched.
class AddressSpaceCap
{
public:
  explicit AddressSpaceCap(std::uint64_t headroom)
  {
    const std::uint64_t now = VirtualSizeBytes();
    this->Active = now > 0 && getrlimit(RLIMIT_AS, &this->Saved) == 0;
    if (this->Active)
    {
      rlimit capped = this->Saved;
      capped.rlim_cur = std::min<rlim_t>(this->Saved.rlim_cur, static_cast<rlim_t>(now + headroom));
      this->Active = setrlimit(RLIMIT_AS, &capped) == 0;
    }
  }
  ~AddressSpaceCap()
  {
    if (this->Active)
    {
      setrlimit(RLIMIT_AS, &this->Saved);
    }
  }
  AddressSpaceCap(const AddressSpaceCap&) = delete;
  AddressSpaceCap& operator=(const AddressSpaceCap&) = delete;

private:
  rlimit Saved{};
  bool Active = false;
};

TEST(OFFParserFuzz, HeaderDeclaring2To40ElementsIsRejectedWithoutAllocating)
{
  // 2^40 = 1099511627776: 24 TiB of coordinates if believed.
  const std::vector<std::string> inputs = {
    "OFF\n1099511627776 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
    "OFF\n3 1099511627776 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
    "OFF 1099511627776 1099511627776 1099511627776\n0 0 0\n",
    "CNOFF\n1099511627776 0\n0 0 0 0 0 1 1 1 1\n",
    "1099511627776 0\n" + std::string(64 * 1024, ' ') + "\n", // no keyword, 64 kB of padding
    // Counts that would fit a 32-bit truncation of the count (2^40 + 3 -> 3).
    "OFF\n1099511627779 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
  };
  HangWatchdog watchdog;
  for (std::size_t i = 0; i < inputs.size(); ++i)
  {
    const std::string& text = inputs[i];
    SCOPED_TRACE(Escaped(text, 80));
    const long rssBefore = PeakRSSKilobytes();
    // A loop over the declared counts would hang rather than allocate.
    watchdog.Arm("giant-header input %zu", i);
    {
      for (const bool chunked : { false, true })
      {
        try
        {
          AddressSpaceCap cap(256ull << 20);
          if (chunked)
          {
            shapediameter::ParseOFFPiece(text.data(), text.size(), 1, 2, PieceOrder::Spatial, 7);
          }
          else
          {
            ParseExact(text);
          }
          ADD_FAILURE() << "accepted";
        }
        catch (const OFFParseError& error)
        {
          EXPECT_NE(std::string(error.what()).find("declares"), std::string::npos) << error.what();
        }
        catch (const std::exception& error)
        {
          ADD_FAILURE() << "not an OFFParseError: " << typeid(error).name() << ": " << error.what();
        }
      }
    }
    EXPECT_LT(PeakRSSKilobytes() - rssBefore, 50 * 1024) << "kB of peak RSS growth";
  }
}

} // namespace
