// SPDX-License-Identifier: BSD-3-Clause
// sdf-seg-metrics: compares two segmentations of one mesh with the Princeton Segmentation
// Benchmark metrics (Chen, Golovinskiy & Funkhouser 2009). See README.md in this directory
// and Testing/Evaluation/SegmentationMetrics.h for the definitions.
#include "IO/OFFParser.h"
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
  "Usage: sdf-seg-metrics MESH.off A.seg B.seg [--json] [--uniform] [--no-header]\n"
  "\n"
  "Compares segmentation A (e.g. computed, one label per face of MESH, one per line) with\n"
  "segmentation B (e.g. a human reference) with the Princeton Segmentation Benchmark metrics\n"
  "(Chen, Golovinskiy & Funkhouser 2009). Lower is better; 0 = identical.\n"
  "  CD    Cut Discrepancy: mean distance between the segment boundaries, along mesh edges,\n"
  "        over the mean radius of the surface (n/a when only one of A, B has boundaries)\n"
  "  Rm    missing rate, Rf false alarm rate, H = (Rm + Rf) / 2 (Hamming distance)\n"
  "  1-RI  one minus the Rand index\n"
  "  GCE   Global Consistency Error, LCE Local Consistency Error\n"
  "Faces are weighted by area (the benchmark's convention); polygons are fan-triangulated\n"
  "for the geometry but keep one label each. Labels are any integers.\n"
  "\n"
  "Options:\n"
  "  --json       print one JSON object instead of a Markdown table\n"
  "  --uniform    count faces (and cut vertices) instead of weighting them by area (length)\n"
  "  --no-header  Markdown: print only the table row (to append rows of several runs)\n"
  "  --help       print this help\n"
  "Errors: one line on stderr, exit status 1.\n";

struct Arguments
{
  std::vector<std::string> files;
  bool json = false;
  bool uniform = false;
  bool header = true;
  bool help = false;
};

class UsageError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

Arguments ParseArguments(int argc, char** argv)
{
  Arguments arguments;
  bool optionsEnded = false;
  for (int i = 1; i < argc; ++i)
  {
    const std::string argument = argv[i];
    if (!optionsEnded && argument == "--")
    {
      optionsEnded = true;
    }
    else if (!optionsEnded && (argument == "--help" || argument == "-h"))
    {
      arguments.help = true;
    }
    else if (!optionsEnded && argument == "--json")
    {
      arguments.json = true;
    }
    else if (!optionsEnded && argument == "--uniform")
    {
      arguments.uniform = true;
    }
    else if (!optionsEnded && argument == "--no-header")
    {
      arguments.header = false;
    }
    else if (!optionsEnded && argument.size() > 1 && argument[0] == '-')
    {
      throw UsageError("unknown option '" + argument + "' (see --help)");
    }
    else
    {
      arguments.files.push_back(argument);
    }
  }
  if (!arguments.help && arguments.files.size() != 3)
  {
    throw UsageError("expected MESH.off A.seg B.seg, got " + std::to_string(arguments.files.size()) +
      " file argument(s) (see --help)");
  }
  return arguments;
}

std::string Number(double value, const char* format)
{
  char text[64];
  std::snprintf(text, sizeof(text), format, value);
  return text;
}

std::vector<int> ReadLabels(const std::string& path, std::size_t faceCount)
{
  std::vector<int> labels = ReadSegFile(path);
  if (labels.size() != faceCount)
  {
    throw SegFileError(0, "has " + std::to_string(labels.size()) + " labels but the mesh has " +
        std::to_string(faceCount) + " faces", path);
  }
  return labels;
}

int Run(const Arguments& arguments)
{
  const std::string& meshPath = arguments.files[0];
  const OFFMesh mesh = ReadOFFFile(meshPath);
  const std::vector<int> labelsA = ReadLabels(arguments.files[1], mesh.FaceCount());
  const std::vector<int> labelsB = ReadLabels(arguments.files[2], mesh.FaceCount());

  const Eigen::Map<const PointMatrix> points(
    mesh.Points.data(), static_cast<Eigen::Index>(mesh.VertexCount()), 3);
  SegmentationMetricsOptions options;
  options.Weighting = arguments.uniform ? SegmentationWeighting::Uniform : SegmentationWeighting::FaceArea;
  const SegmentationComparison result =
    CompareSegmentations(points, mesh.FaceOffsets, mesh.FaceConnectivity, labelsA, labelsB, options);
  const PartitionComparison& p = result.Partition;
  const CutDiscrepancyResult& c = result.Cut;

  if (arguments.json)
  {
    const auto number = [](double value) { return Number(value, "%.10g"); };
    const auto cd = [&](double value) { return c.CutDiscrepancyDefined ? number(value) : std::string("null"); };
    std::printf("{\n");
    std::printf("  \"mesh\": %s,\n", JsonString(meshPath).c_str());
    std::printf("  \"a\": %s,\n", JsonString(arguments.files[1]).c_str());
    std::printf("  \"b\": %s,\n", JsonString(arguments.files[2]).c_str());
    std::printf("  \"weighting\": \"%s\",\n", p.UsedUniformWeights ? "uniform" : "area");
    std::printf("  \"faces\": %zu,\n", mesh.FaceCount());
    std::printf("  \"segmentsA\": %zu,\n", p.SegmentCountA);
    std::printf("  \"segmentsB\": %zu,\n", p.SegmentCountB);
    std::printf("  \"cutDiscrepancy\": %s,\n", cd(c.CutDiscrepancy).c_str());
    std::printf("  \"directionalCutDiscrepancyAB\": %s,\n", cd(c.DirectionalCutDiscrepancyAB).c_str());
    std::printf("  \"directionalCutDiscrepancyBA\": %s,\n", cd(c.DirectionalCutDiscrepancyBA).c_str());
    std::printf("  \"averageRadius\": %s,\n", number(c.AverageRadius).c_str());
    std::printf("  \"missingRate\": %s,\n", number(p.MissingRate).c_str());
    std::printf("  \"falseAlarmRate\": %s,\n", number(p.FalseAlarmRate).c_str());
    std::printf("  \"hammingDistance\": %s,\n", number(p.HammingDistance).c_str());
    std::printf("  \"randIndexError\": %s,\n", number(p.RandIndexError).c_str());
    std::printf("  \"globalConsistencyError\": %s,\n", number(p.GlobalConsistencyError).c_str());
    std::printf("  \"localConsistencyError\": %s\n", number(p.LocalConsistencyError).c_str());
    std::printf("}\n");
  }
  else
  {
    const auto number = [](double value) { return Number(value, "%.4f"); };
    if (arguments.header)
    {
      std::printf("| CD | Rm | Rf | H | 1-RI | GCE | LCE |\n");
      std::printf("|---:|---:|---:|---:|---:|---:|---:|\n");
    }
    std::printf("| %s | %s | %s | %s | %s | %s | %s |\n",
      c.CutDiscrepancyDefined ? number(c.CutDiscrepancy).c_str() : "n/a", number(p.MissingRate).c_str(),
      number(p.FalseAlarmRate).c_str(), number(p.HammingDistance).c_str(), number(p.RandIndexError).c_str(),
      number(p.GlobalConsistencyError).c_str(), number(p.LocalConsistencyError).c_str());
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
    const Arguments arguments = ParseArguments(argc, argv);
    if (arguments.help)
    {
      std::fputs(kUsage, stdout);
      return 0;
    }
    return Run(arguments);
  }
  catch (const std::exception& error)
  {
    std::fprintf(stderr, "sdf-seg-metrics: %s\n", error.what());
    return 1;
  }
}
