// SPDX-License-Identifier: BSD-3-Clause
// sdf-pose-consistency: Table 2 of Shapira, Shamir & Cohen-Or 2008 for N segmentations of meshes
// with identical connectivity (e.g. poses): the percentage of faces with a different label
// between every pair, after the best one-to-one matching of labels. See README.md here and
// Testing/Evaluation/LabelMatching.h.
#include "LabelMatching.h"
#include "JsonText.h"
#include "SegmentationMetrics.h"

#include <cstdio>
#include <exception>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{
using namespace shapediameter;
using evaluation::JsonString;

const char* const kUsage =
  "Usage: sdf-pose-consistency POSE1.seg POSE2.seg [POSE3.seg ...] [--json]\n"
  "\n"
  "Table 2 of Shapira, Shamir & Cohen-Or 2008: for every pair of segmentations of meshes with\n"
  "identical connectivity (one label per face, one per line, e.g. the SDFCluster labels of\n"
  "several poses), the percentage of faces assigned to a different part after the best\n"
  "one-to-one matching of the labels (Hungarian algorithm). Labels are any integers.\n"
  "Prints the N x N matrix as Markdown, then two averages: over the off-diagonal entries, and\n"
  "over all N x N entries with the zero diagonal (the paper's caption average: its 2.2013 %\n"
  "is the mean of all 36 entries of its 6 x 6 table).\n"
  "\n"
  "Options:\n"
  "  --json   print one JSON object instead of Markdown\n"
  "  --help   print this help\n"
  "Errors: one line on stderr, exit status 1.\n";

class UsageError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

/// The text with Markdown table separators escaped.
std::string MarkdownCell(const std::string& text)
{
  std::string out;
  for (const char c : text)
  {
    if (c == '|')
    {
      out += "\\|";
    }
    else
    {
      out += c;
    }
  }
  return out;
}

int Run(const std::vector<std::string>& files, bool json)
{
  const std::size_t count = files.size();
  std::vector<std::vector<int>> labelings;
  labelings.reserve(count);
  for (const std::string& file : files)
  {
    labelings.push_back(ReadSegFile(file));
    if (labelings.back().size() != labelings.front().size())
    {
      throw SegFileError(0, "has " + std::to_string(labelings.back().size()) + " labels but " + files.front() +
          " has " + std::to_string(labelings.front().size()) + " (the meshes must have identical connectivity)",
        file);
    }
  }

  // The measure is symmetric; compute each pair once so that the printed matrix is exactly so.
  std::vector<std::vector<double>> percent(count, std::vector<double>(count, 0.0));
  double offDiagonalSum = 0.0;
  for (std::size_t i = 0; i < count; ++i)
  {
    for (std::size_t j = i + 1; j < count; ++j)
    {
      const double value = CompareLabelings(labelings[i], labelings[j]).PercentDifferent;
      percent[i][j] = percent[j][i] = value;
      offDiagonalSum += 2.0 * value;
    }
  }
  const double offDiagonalAverage = offDiagonalSum / static_cast<double>(count * (count - 1));
  const double allEntriesAverage = offDiagonalSum / static_cast<double>(count * count);

  if (json)
  {
    std::printf("{\n  \"files\": [");
    for (std::size_t i = 0; i < count; ++i)
    {
      std::printf("%s%s", i ? ", " : "", JsonString(files[i]).c_str());
    }
    std::printf("],\n  \"faces\": %zu,\n  \"percentDifferent\": [\n", labelings.front().size());
    for (std::size_t i = 0; i < count; ++i)
    {
      std::printf("    [");
      for (std::size_t j = 0; j < count; ++j)
      {
        std::printf("%s%.10g", j ? ", " : "", percent[i][j]);
      }
      std::printf("]%s\n", i + 1 < count ? "," : "");
    }
    std::printf("  ],\n  \"offDiagonalAverage\": %.10g,\n  \"allEntriesAverage\": %.10g\n}\n", offDiagonalAverage,
      allEntriesAverage);
  }
  else
  {
    std::printf("| Pose |");
    for (std::size_t j = 0; j < count; ++j)
    {
      std::printf(" %zu |", j + 1);
    }
    std::printf("\n|---|");
    for (std::size_t j = 0; j < count; ++j)
    {
      std::printf("---:|");
    }
    std::printf("\n");
    for (std::size_t i = 0; i < count; ++i)
    {
      std::printf("| %zu |", i + 1);
      for (std::size_t j = 0; j < count; ++j)
      {
        std::printf(" %.3f |", percent[i][j]);
      }
      std::printf("\n");
    }
    std::printf("\nPercent of faces assigned to a different part (%zu faces, best one-to-one label matching).\n",
      labelings.front().size());
    std::printf("Average of the off-diagonal entries: %.4f %%\n", offDiagonalAverage);
    std::printf("Average of all %zu x %zu entries, zero diagonal included (the paper's convention): %.4f %%\n",
      count, count, allEntriesAverage);
    std::printf("\nPoses:\n");
    for (std::size_t i = 0; i < count; ++i)
    {
      std::printf("%zu. %s\n", i + 1, MarkdownCell(files[i]).c_str());
    }
  }
  if (std::fflush(stdout) != 0)
  {
    throw std::runtime_error("cannot write the output");
  }
  return 0;
}

} // namespace

int main(int argc, char** argv)
{
  try
  {
    std::vector<std::string> files;
    bool json = false, optionsEnded = false;
    for (int i = 1; i < argc; ++i)
    {
      const std::string argument = argv[i];
      if (!optionsEnded && argument == "--")
      {
        optionsEnded = true;
      }
      else if (!optionsEnded && (argument == "--help" || argument == "-h"))
      {
        std::fputs(kUsage, stdout);
        return 0;
      }
      else if (!optionsEnded && argument == "--json")
      {
        json = true;
      }
      else if (!optionsEnded && argument.size() > 1 && argument[0] == '-')
      {
        throw UsageError("unknown option '" + argument + "' (see --help)");
      }
      else
      {
        files.push_back(argument);
      }
    }
    if (files.size() < 2)
    {
      throw UsageError("expected at least two .seg files, got " + std::to_string(files.size()) + " (see --help)");
    }
    return Run(files, json);
  }
  catch (const std::exception& error)
  {
    std::fprintf(stderr, "sdf-pose-consistency: %s\n", error.what());
    return 1;
  }
}
