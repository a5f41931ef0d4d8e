// SPDX-License-Identifier: BSD-3-Clause
// sdf-psb-benchmark: scores a folder of segmentations against the human segmentations of the
// Princeton Segmentation Benchmark (Chen, Golovinskiy & Funkhouser 2009), per mesh, per
// category and overall. The metrics are SegmentationMetrics' (CompareSegmentations at its
// defaults: area-weighted); this file only reads the folders and forms the averages. See
// README.md in this directory.
#include "IO/OFFParser.h"
#include "JsonText.h"
#include "SegmentationMetrics.h"

#include <zlib.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace
{
using namespace shapediameter;
using evaluation::JsonString;
namespace fs = std::filesystem;

const char* const kUsage =
  "Usage: sdf-psb-benchmark PSB_DIR SEG_DIR [--json] [--ids LIST] [--threads N]\n"
  "                         [--allow-missing] [--per-mesh]\n"
  "                         [--expect-rand-error-at-most X] [--expect-count-share-at-least P]\n"
  "\n"
  "Scores our segmentations SEG_DIR/<id>.seg (one label per face and line, e.g. SDFSegment)\n"
  "against every human segmentation of the Princeton Segmentation Benchmark in PSB_DIR\n"
  "(<id>.off[.gz] and <id>/<id>_<k>.seg[.gz]) with the benchmark's measures, area-weighted:\n"
  "  CD    Cut Discrepancy          1-RI  one minus the Rand index\n"
  "  GCE   Global Consistency Error LCE   Local Consistency Error\n"
  "  H     Hamming distance, Rm missing rate, Rf false alarm rate\n"
  "Each measure is averaged over the mesh's human segmentations, then over the meshes of a\n"
  "category; 'overall' is the mean of the category means, 'articulated' the mean over the\n"
  "categories Human, Ant, Octopus, Teddy, Hand, Armadillo, FourLeg, Bird, Fish, Plier.\n"
  "Segment counts: segments covering >= 0.5 % of the area, ours against the median of the\n"
  "humans' counts; a mesh is 'within' when ours / median is in [1/1.5, 1.5].\n"
  "\n"
  "Options:\n"
  "  --json                print one JSON object (with every mesh) instead of Markdown\n"
  "  --ids LIST            meshes to score, e.g. 2-20,81,385 (default: every mesh in PSB_DIR;\n"
  "                        ranges skip absent ids, single ids must exist)\n"
  "  --threads N           meshes scored at once (default: all cores)\n"
  "  --allow-missing       score the meshes that have a SEG_DIR/<id>.seg, list the others\n"
  "                        (default: a missing one is an error)\n"
  "  --per-mesh            Markdown: also a table of every mesh\n"
  "  --expect-rand-error-at-most X      exit 1 when the overall 1-RI exceeds X\n"
  "  --expect-count-share-at-least P    exit 1 when fewer than P % of the meshes of the\n"
  "                        articulated categories (of all meshes, if none is) are within 1.5x\n"
  "  --help                print this help\n"
  "Errors: one line on stderr, exit status 1.\n";

constexpr double kSegmentShare = 0.005; // segments covering >= 0.5 % of the area are counted
constexpr double kCountFactor = 1.5;    // ours within this factor of the humans' median

struct Category
{
  const char* Name;
  int First;
  int Last;
  bool Articulated;
};

// The benchmark's categories by id (20 meshes each; Spring, 261-280, is not in the benchmark).
const Category kCategories[] = {
  { "Human", 1, 20, true }, { "Cup", 21, 40, false }, { "Glasses", 41, 60, false },
  { "Airplane", 61, 80, false }, { "Ant", 81, 100, true }, { "Chair", 101, 120, false },
  { "Octopus", 121, 140, true }, { "Table", 141, 160, false }, { "Teddy", 161, 180, true },
  { "Hand", 181, 200, true }, { "Plier", 201, 220, true }, { "Fish", 221, 240, true },
  { "Bird", 241, 260, true }, { "Spring", 261, 280, false }, { "Armadillo", 281, 300, true },
  { "Bust", 301, 320, false }, { "Mech", 321, 340, false }, { "Bearing", 341, 360, false },
  { "Vase", 361, 380, false }, { "FourLeg", 381, 400, true },
};
constexpr int kOtherCategory = -1;

int CategoryOf(int id)
{
  for (int c = 0; c < static_cast<int>(std::size(kCategories)); ++c)
  {
    if (id >= kCategories[c].First && id <= kCategories[c].Last)
    {
      return c;
    }
  }
  return kOtherCategory;
}

class UsageError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

struct Arguments
{
  std::string psbDir;
  std::string segDir;
  std::string ids;
  bool json = false;
  bool allowMissing = false;
  bool perMesh = false;
  bool help = false;
  unsigned threads = 0;
  double maxRandError = -1.0;  // < 0: no check
  double minCountShare = -1.0; // percent, < 0: no check
};

double ParseNumber(const std::string& option, const std::string& text)
{
  char* end = nullptr;
  errno = 0;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || errno != 0 || !(value >= 0.0))
  {
    throw UsageError(option + " expects a number >= 0, got '" + text + "'");
  }
  return value;
}

Arguments ParseArguments(int argc, char** argv)
{
  Arguments arguments;
  std::vector<std::string> positional;
  for (int i = 1; i < argc; ++i)
  {
    const std::string argument = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc)
      {
        throw UsageError(argument + " needs a value (see --help)");
      }
      return argv[++i];
    };
    if (argument == "--help" || argument == "-h")
    {
      arguments.help = true;
    }
    else if (argument == "--json")
    {
      arguments.json = true;
    }
    else if (argument == "--allow-missing")
    {
      arguments.allowMissing = true;
    }
    else if (argument == "--per-mesh")
    {
      arguments.perMesh = true;
    }
    else if (argument == "--ids")
    {
      arguments.ids = value();
    }
    else if (argument == "--threads")
    {
      const double threads = ParseNumber(argument, value());
      if (threads < 1.0 || threads > 1024.0 || threads != static_cast<unsigned>(threads))
      {
        throw UsageError("--threads expects an integer in [1, 1024]");
      }
      arguments.threads = static_cast<unsigned>(threads);
    }
    else if (argument == "--expect-rand-error-at-most")
    {
      arguments.maxRandError = ParseNumber(argument, value());
    }
    else if (argument == "--expect-count-share-at-least")
    {
      arguments.minCountShare = ParseNumber(argument, value());
    }
    else if (argument.size() > 1 && argument[0] == '-')
    {
      throw UsageError("unknown option '" + argument + "' (see --help)");
    }
    else
    {
      positional.push_back(argument);
    }
  }
  if (arguments.help)
  {
    return arguments;
  }
  if (positional.size() != 2)
  {
    throw UsageError("expected PSB_DIR SEG_DIR, got " + std::to_string(positional.size()) +
      " argument(s) (see --help)");
  }
  arguments.psbDir = positional[0];
  arguments.segDir = positional[1];
  return arguments;
}

// ---- Files

/// The whole content of a file, gunzipped when it is gzip (zlib reads plain files as they are).
std::string ReadMaybeGzipped(const fs::path& path)
{
  gzFile file = gzopen(path.c_str(), "rb");
  if (!file)
  {
    throw std::runtime_error(path.string() + ": cannot open (" + std::strerror(errno) + ")");
  }
  std::string content;
  char buffer[1 << 16];
  for (;;)
  {
    const int read = gzread(file, buffer, sizeof(buffer));
    if (read < 0)
    {
      int code = 0;
      const std::string reason = gzerror(file, &code);
      gzclose(file);
      throw std::runtime_error(path.string() + ": cannot read (" + reason + ")");
    }
    if (read == 0)
    {
      break;
    }
    content.append(buffer, static_cast<std::size_t>(read));
  }
  gzclose(file);
  return content;
}

/// path + ".gz" when that exists and path does not; else path.
fs::path PlainOrGzipped(const fs::path& path)
{
  std::error_code error;
  if (!fs::exists(path, error))
  {
    fs::path gzipped = path;
    gzipped += ".gz";
    if (fs::exists(gzipped, error))
    {
      return gzipped;
    }
  }
  return path;
}

/// The id of "<digits>.off" / "<digits>.off.gz", or -1.
int MeshId(const std::string& name)
{
  std::size_t digits = 0;
  while (digits < name.size() && name[digits] >= '0' && name[digits] <= '9')
  {
    ++digits;
  }
  const std::string rest = name.substr(digits);
  if (digits == 0 || digits > 6 || (rest != ".off" && rest != ".off.gz"))
  {
    return -1;
  }
  return std::stoi(name.substr(0, digits));
}

std::set<int> MeshesIn(const fs::path& folder)
{
  std::error_code error;
  if (!fs::is_directory(folder, error))
  {
    throw std::runtime_error(folder.string() + ": not a folder");
  }
  std::set<int> ids;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder))
  {
    const int id = MeshId(entry.path().filename().string());
    if (id >= 0)
    {
      ids.insert(id);
    }
  }
  return ids;
}

/// "2-20,81" -> ids; ranges keep only the present ones, single ids must be present.
std::vector<int> SelectIds(const std::string& list, const std::set<int>& present, const std::string& psbDir)
{
  if (list.empty())
  {
    return { present.begin(), present.end() };
  }
  std::set<int> selected;
  std::size_t start = 0;
  while (start <= list.size())
  {
    std::size_t end = list.find(',', start);
    if (end == std::string::npos)
    {
      end = list.size();
    }
    const std::string item = list.substr(start, end - start);
    start = end + 1;
    const std::size_t dash = item.find('-');
    const auto number = [&](const std::string& text) {
      if (text.empty() || text.size() > 6 || text.find_first_not_of("0123456789") != std::string::npos)
      {
        throw UsageError("--ids: '" + item + "' is not an id or a range a-b");
      }
      return std::stoi(text);
    };
    if (dash == std::string::npos)
    {
      const int id = number(item);
      if (!present.count(id))
      {
        throw std::runtime_error("mesh " + std::to_string(id) + " is not in " + psbDir);
      }
      selected.insert(id);
    }
    else
    {
      const int first = number(item.substr(0, dash));
      const int last = number(item.substr(dash + 1));
      for (auto it = present.lower_bound(first); it != present.end() && *it <= last; ++it)
      {
        selected.insert(*it);
      }
    }
  }
  if (selected.empty())
  {
    throw std::runtime_error("--ids " + list + " selects no mesh of " + psbDir);
  }
  return { selected.begin(), selected.end() };
}

/// The human segmentations <id>/<id>_<k>.seg[.gz], by k.
std::vector<fs::path> HumanSegmentations(const fs::path& psbDir, int id)
{
  const fs::path folder = psbDir / std::to_string(id);
  const std::string prefix = std::to_string(id) + "_";
  std::map<int, fs::path> byIndex;
  std::error_code error;
  if (fs::is_directory(folder, error))
  {
    for (const fs::directory_entry& entry : fs::directory_iterator(folder))
    {
      const std::string name = entry.path().filename().string();
      if (name.compare(0, prefix.size(), prefix) != 0)
      {
        continue;
      }
      std::string rest = name.substr(prefix.size());
      const std::size_t digits = rest.find_first_not_of("0123456789");
      if (digits == 0 || digits == std::string::npos || digits > 6)
      {
        continue;
      }
      const std::string suffix = rest.substr(digits);
      if (suffix == ".seg" || suffix == ".seg.gz")
      {
        byIndex.emplace(std::stoi(rest.substr(0, digits)), entry.path());
      }
    }
  }
  std::vector<fs::path> paths;
  for (const auto& item : byIndex)
  {
    paths.push_back(item.second);
  }
  return paths;
}

std::vector<int> ReadLabels(const fs::path& path, std::size_t faceCount)
{
  const std::string text = ReadMaybeGzipped(path);
  std::vector<int> labels = ParseSeg(text.data(), text.size(), path.string());
  if (labels.size() != faceCount)
  {
    throw SegFileError(0, "has " + std::to_string(labels.size()) + " labels but the mesh has " +
        std::to_string(faceCount) + " faces", path.string());
  }
  return labels;
}

// ---- Scores

/// The benchmark's measures, or their means.
struct Measures
{
  double CutDiscrepancy = 0.0;
  double RandIndexError = 0.0;
  double GlobalConsistencyError = 0.0;
  double LocalConsistencyError = 0.0;
  double HammingDistance = 0.0;
  double MissingRate = 0.0;
  double FalseAlarmRate = 0.0;
};

struct MeshScore
{
  int Id = 0;
  int CategoryIndex = kOtherCategory;
  std::size_t Faces = 0;
  std::size_t Humans = 0;
  Measures Mean;             ///< over the human segmentations
  std::size_t CutDefined = 0; ///< comparisons whose CD is defined (CD is their mean; see README)
  std::size_t Segments = 0;   ///< ours, all
  std::size_t LargeSegments = 0; ///< ours, covering >= 0.5 % of the area
  double HumanMedianLarge = 0.0;
  bool WithinFactor = false;
  std::string Error; ///< set when the mesh could not be scored
};

double Median(std::vector<double> values)
{
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

MeshScore ScoreMesh(const fs::path& psbDir, const fs::path& ourSeg, int id)
{
  MeshScore score;
  score.Id = id;
  score.CategoryIndex = CategoryOf(id);
  const fs::path meshPath = PlainOrGzipped(psbDir / (std::to_string(id) + ".off"));
  const std::string text = ReadMaybeGzipped(meshPath);
  OFFMesh mesh;
  try
  {
    mesh = ParseOFF(text.data(), text.size());
  }
  catch (const OFFParseError& error)
  {
    throw std::runtime_error(meshPath.string() + ": " + error.what());
  }
  score.Faces = mesh.FaceCount();
  const Eigen::Map<const PointMatrix> points(
    mesh.Points.data(), static_cast<Eigen::Index>(mesh.VertexCount()), 3);
  const std::vector<double> areas = ComputeFaceAreas(points, mesh.FaceOffsets, mesh.FaceConnectivity);
  const std::vector<int> ours = ReadLabels(ourSeg, score.Faces);
  score.LargeSegments = CountSegmentsCovering(ours, areas, kSegmentShare);
  score.Segments = std::set<int>(ours.begin(), ours.end()).size();

  const std::vector<fs::path> humans = HumanSegmentations(psbDir, id);
  if (humans.empty())
  {
    throw std::runtime_error("mesh " + std::to_string(id) + " has no human segmentation " +
      (psbDir / std::to_string(id) / (std::to_string(id) + "_<k>.seg[.gz]")).string());
  }
  score.Humans = humans.size();
  std::vector<double> humanCounts;
  Measures sum;
  double cutSum = 0.0;
  for (const fs::path& path : humans)
  {
    const std::vector<int> human = ReadLabels(path, score.Faces);
    humanCounts.push_back(static_cast<double>(CountSegmentsCovering(human, areas, kSegmentShare)));
    const SegmentationComparison c =
      CompareSegmentations(points, mesh.FaceOffsets, mesh.FaceConnectivity, ours, human);
    if (c.Cut.CutDiscrepancyDefined)
    {
      cutSum += c.Cut.CutDiscrepancy;
      ++score.CutDefined;
    }
    sum.RandIndexError += c.Partition.RandIndexError;
    sum.GlobalConsistencyError += c.Partition.GlobalConsistencyError;
    sum.LocalConsistencyError += c.Partition.LocalConsistencyError;
    sum.HammingDistance += c.Partition.HammingDistance;
    sum.MissingRate += c.Partition.MissingRate;
    sum.FalseAlarmRate += c.Partition.FalseAlarmRate;
  }
  const double n = static_cast<double>(humans.size());
  score.Mean.CutDiscrepancy = score.CutDefined ? cutSum / static_cast<double>(score.CutDefined) : 0.0;
  score.Mean.RandIndexError = sum.RandIndexError / n;
  score.Mean.GlobalConsistencyError = sum.GlobalConsistencyError / n;
  score.Mean.LocalConsistencyError = sum.LocalConsistencyError / n;
  score.Mean.HammingDistance = sum.HammingDistance / n;
  score.Mean.MissingRate = sum.MissingRate / n;
  score.Mean.FalseAlarmRate = sum.FalseAlarmRate / n;
  score.HumanMedianLarge = Median(humanCounts);
  const double ratio = static_cast<double>(score.LargeSegments) / score.HumanMedianLarge;
  score.WithinFactor = ratio >= 1.0 / kCountFactor && ratio <= kCountFactor;
  return score;
}

/// Means over a group of meshes (a category) or of groups (overall).
struct GroupScore
{
  std::string Name;
  std::size_t Meshes = 0;
  Measures Mean;
  std::size_t CutMeshes = 0; ///< meshes (or groups) with a defined CD, over which CD is averaged
  std::size_t Within = 0;    ///< meshes within the factor
  double MedianLarge = 0.0;      ///< median over the meshes of ours (>= 0.5 %)
  double MedianHumanLarge = 0.0; ///< median over the meshes of the humans' medians
};

void Accumulate(Measures& sum, const Measures& value, double weight)
{
  sum.RandIndexError += weight * value.RandIndexError;
  sum.GlobalConsistencyError += weight * value.GlobalConsistencyError;
  sum.LocalConsistencyError += weight * value.LocalConsistencyError;
  sum.HammingDistance += weight * value.HammingDistance;
  sum.MissingRate += weight * value.MissingRate;
  sum.FalseAlarmRate += weight * value.FalseAlarmRate;
}

GroupScore ScoreCategory(const std::string& name, const std::vector<const MeshScore*>& meshes)
{
  GroupScore group;
  group.Name = name;
  group.Meshes = meshes.size();
  std::vector<double> ours, humans;
  double cutSum = 0.0;
  for (const MeshScore* mesh : meshes)
  {
    Accumulate(group.Mean, mesh->Mean, 1.0 / static_cast<double>(meshes.size()));
    if (mesh->CutDefined)
    {
      cutSum += mesh->Mean.CutDiscrepancy;
      ++group.CutMeshes;
    }
    group.Within += mesh->WithinFactor ? 1 : 0;
    ours.push_back(static_cast<double>(mesh->LargeSegments));
    humans.push_back(mesh->HumanMedianLarge);
  }
  group.Mean.CutDiscrepancy = group.CutMeshes ? cutSum / static_cast<double>(group.CutMeshes) : 0.0;
  group.MedianLarge = Median(ours);
  group.MedianHumanLarge = Median(humans);
  return group;
}

/// Mean of the category means; meshes, "within" and the medians pooled over the meshes.
GroupScore MeanOfCategories(const std::string& name, const std::vector<GroupScore>& categories,
  const std::vector<const MeshScore*>& meshes)
{
  GroupScore group = ScoreCategory(name, meshes);
  group.Mean = Measures{};
  group.CutMeshes = 0;
  double cutSum = 0.0;
  for (const GroupScore& category : categories)
  {
    Accumulate(group.Mean, category.Mean, 1.0 / static_cast<double>(categories.size()));
    if (category.CutMeshes)
    {
      cutSum += category.Mean.CutDiscrepancy;
      ++group.CutMeshes;
    }
  }
  group.Mean.CutDiscrepancy = group.CutMeshes ? cutSum / static_cast<double>(group.CutMeshes) : 0.0;
  return group;
}

// ---- Output

std::string Number(double value, const char* format = "%.4f")
{
  char text[64];
  std::snprintf(text, sizeof(text), format, value);
  return text;
}

std::string Json(double value)
{
  return Number(value, "%.10g");
}

std::string Share(std::size_t part, std::size_t whole)
{
  return std::to_string(part) + "/" + std::to_string(whole) + " (" +
    Number(whole ? 100.0 * static_cast<double>(part) / static_cast<double>(whole) : 0.0, "%.0f") + " %)";
}

std::string MeasuresJson(const Measures& m, bool cutDefined)
{
  return "\"cutDiscrepancy\": " + (cutDefined ? Json(m.CutDiscrepancy) : std::string("null")) +
    ", \"randIndexError\": " + Json(m.RandIndexError) + ", \"globalConsistencyError\": " +
    Json(m.GlobalConsistencyError) + ", \"localConsistencyError\": " + Json(m.LocalConsistencyError) +
    ", \"hammingDistance\": " + Json(m.HammingDistance) + ", \"missingRate\": " + Json(m.MissingRate) +
    ", \"falseAlarmRate\": " + Json(m.FalseAlarmRate);
}

std::string GroupJson(const GroupScore& g)
{
  return "{\"name\": " + JsonString(g.Name) + ", \"meshes\": " + std::to_string(g.Meshes) + ", " +
    MeasuresJson(g.Mean, g.CutMeshes > 0) + ", \"medianSegments\": " + Json(g.MedianLarge) +
    ", \"medianHumanSegments\": " + Json(g.MedianHumanLarge) + ", \"withinFactor\": " +
    std::to_string(g.Within) + ", \"withinFactorShare\": " +
    Json(g.Meshes ? static_cast<double>(g.Within) / static_cast<double>(g.Meshes) : 0.0) + "}";
}

std::string MeasureCells(const Measures& m, bool cutDefined)
{
  return "| " + (cutDefined ? Number(m.CutDiscrepancy) : std::string("n/a")) + " | " +
    Number(m.RandIndexError) + " | " + Number(m.GlobalConsistencyError) + " | " +
    Number(m.LocalConsistencyError) + " | " + Number(m.HammingDistance) + " | " + Number(m.MissingRate) +
    " | " + Number(m.FalseAlarmRate) + " |";
}

void PrintMarkdown(const std::vector<GroupScore>& categories, const GroupScore& overall,
  const GroupScore* articulated, const std::vector<MeshScore>& meshes, const std::vector<int>& missing,
  bool perMesh)
{
  std::printf("| Category | Meshes | CD | 1-RI | GCE | LCE | H | Rm | Rf | Segments >= 0.5 %% (median: ours / humans) | Within 1.5x |\n");
  std::printf("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  const auto row = [](const GroupScore& g, bool bold) {
    const char* b = bold ? "**" : "";
    std::printf("| %s%s%s | %zu %s %s / %s | %s |\n", b, g.Name.c_str(), b, g.Meshes,
      MeasureCells(g.Mean, g.CutMeshes > 0).c_str(), Number(g.MedianLarge, "%.1f").c_str(),
      Number(g.MedianHumanLarge, "%.1f").c_str(), Share(g.Within, g.Meshes).c_str());
  };
  for (const GroupScore& category : categories)
  {
    row(category, false);
  }
  if (articulated)
  {
    row(*articulated, true);
  }
  row(overall, true);
  std::printf("\nArea-weighted; each measure averaged over the human segmentations of a mesh, then over\n"
              "the meshes of a category; Overall = mean of the %zu category means, Articulated = mean of\n"
              "the articulated categories' means (Human, Ant, Octopus, Teddy, Hand, Armadillo, FourLeg,\n"
              "Bird, Fish, Plier). Within 1.5x: meshes whose count of segments covering >= 0.5 %% of the\n"
              "area is within a factor 1.5 of the humans' median count (pooled over the meshes).\n",
    categories.size());
  if (articulated)
  {
    std::printf("Articulated categories: 1-RI %s, within 1.5x on %s of their meshes.\n",
      Number(articulated->Mean.RandIndexError).c_str(), Share(articulated->Within, articulated->Meshes).c_str());
  }
  if (perMesh)
  {
    std::printf("\n| Mesh | Category | Faces | Humans | CD | 1-RI | GCE | LCE | H | Rm | Rf | Segments | >= 0.5 %% | Humans' median | Within |\n");
    std::printf("|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n");
    for (const MeshScore& m : meshes)
    {
      std::printf("| %d | %s | %zu | %zu %s %zu | %zu | %s | %s |\n", m.Id,
        m.CategoryIndex == kOtherCategory ? "Other" : kCategories[m.CategoryIndex].Name, m.Faces, m.Humans,
        MeasureCells(m.Mean, m.CutDefined > 0).c_str(), m.Segments, m.LargeSegments,
        Number(m.HumanMedianLarge, "%.1f").c_str(), m.WithinFactor ? "yes" : "no");
    }
  }
  if (!missing.empty())
  {
    std::string list;
    for (int id : missing)
    {
      list += (list.empty() ? "" : ", ") + std::to_string(id);
    }
    std::printf("\nNot scored, no segmentation of ours: %s\n", list.c_str());
  }
}

void PrintJson(const Arguments& arguments, const std::vector<GroupScore>& categories, const GroupScore& overall,
  const GroupScore* articulated, const std::vector<MeshScore>& meshes, const std::vector<int>& missing)
{
  std::printf("{\n  \"psbDir\": %s,\n  \"segDir\": %s,\n  \"weighting\": \"area\",\n",
    JsonString(arguments.psbDir).c_str(), JsonString(arguments.segDir).c_str());
  std::printf("  \"segmentShare\": %s,\n  \"countFactor\": %s,\n", Json(kSegmentShare).c_str(),
    Json(kCountFactor).c_str());
  std::printf("  \"overall\": %s,\n", GroupJson(overall).c_str());
  std::printf("  \"articulated\": %s,\n", articulated ? GroupJson(*articulated).c_str() : "null");
  std::printf("  \"categories\": [");
  for (std::size_t c = 0; c < categories.size(); ++c)
  {
    std::printf("%s\n    %s", c ? "," : "", GroupJson(categories[c]).c_str());
  }
  std::printf("\n  ],\n  \"meshes\": [");
  for (std::size_t i = 0; i < meshes.size(); ++i)
  {
    const MeshScore& m = meshes[i];
    std::printf("%s\n    {\"id\": %d, \"category\": \"%s\", \"faces\": %zu, \"humans\": %zu, %s, "
                "\"cutDiscrepancyDefined\": %zu, \"segments\": %zu, \"largeSegments\": %zu, "
                "\"humanMedianLargeSegments\": %s, \"withinFactor\": %s}",
      i ? "," : "", m.Id, m.CategoryIndex == kOtherCategory ? "Other" : kCategories[m.CategoryIndex].Name,
      m.Faces, m.Humans, MeasuresJson(m.Mean, m.CutDefined > 0).c_str(), m.CutDefined, m.Segments,
      m.LargeSegments, Json(m.HumanMedianLarge).c_str(), m.WithinFactor ? "true" : "false");
  }
  std::printf("\n  ],\n  \"missing\": [");
  for (std::size_t i = 0; i < missing.size(); ++i)
  {
    std::printf("%s%d", i ? ", " : "", missing[i]);
  }
  std::printf("]\n}\n");
}

int Run(const Arguments& arguments)
{
  const fs::path psbDir = arguments.psbDir;
  const fs::path segDir = arguments.segDir;
  const std::vector<int> ids = SelectIds(arguments.ids, MeshesIn(psbDir), arguments.psbDir);
  std::error_code error;
  if (!fs::is_directory(segDir, error))
  {
    throw std::runtime_error(segDir.string() + ": not a folder");
  }
  std::vector<int> scored, missing;
  std::vector<fs::path> ourSegs;
  for (int id : ids)
  {
    const fs::path seg = PlainOrGzipped(segDir / (std::to_string(id) + ".seg"));
    if (fs::exists(seg, error))
    {
      scored.push_back(id);
      ourSegs.push_back(seg);
    }
    else
    {
      missing.push_back(id);
    }
  }
  if (!missing.empty() && !arguments.allowMissing)
  {
    std::string list;
    for (std::size_t i = 0; i < missing.size() && i < 20; ++i)
    {
      list += (i ? ", " : "") + std::to_string(missing[i]);
    }
    throw std::runtime_error(std::to_string(missing.size()) + " of " + std::to_string(ids.size()) +
      " meshes have no segmentation in " + segDir.string() + " (" + list +
      (missing.size() > 20 ? ", ..." : "") + "; --allow-missing scores the others)");
  }
  if (scored.empty())
  {
    throw std::runtime_error("no mesh to score: " + segDir.string() + " has none of the segmentations");
  }

  // Meshes are scored in parallel, each into its own slot: the output does not depend on the
  // thread count.
  std::vector<MeshScore> meshes(scored.size());
  unsigned threads = arguments.threads ? arguments.threads : std::max(1u, std::thread::hardware_concurrency());
  threads = static_cast<unsigned>(std::min<std::size_t>(threads, scored.size()));
  std::atomic<std::size_t> next{ 0 };
  const auto work = [&]() {
    for (std::size_t i = next++; i < scored.size(); i = next++)
    {
      try
      {
        meshes[i] = ScoreMesh(psbDir, ourSegs[i], scored[i]);
      }
      catch (const std::exception& failure)
      {
        meshes[i].Id = scored[i];
        meshes[i].Error = failure.what();
      }
    }
  };
  std::vector<std::thread> pool;
  for (unsigned t = 1; t < threads; ++t)
  {
    pool.emplace_back(work);
  }
  work();
  for (std::thread& thread : pool)
  {
    thread.join();
  }
  for (const MeshScore& mesh : meshes)
  {
    if (!mesh.Error.empty())
    {
      throw std::runtime_error("mesh " + std::to_string(mesh.Id) + ": " + mesh.Error);
    }
  }

  std::vector<GroupScore> categories;
  std::vector<const MeshScore*> all, articulatedMeshes;
  std::vector<GroupScore> articulatedCategories;
  for (int c = kOtherCategory; c < static_cast<int>(std::size(kCategories)); ++c)
  {
    std::vector<const MeshScore*> members;
    for (const MeshScore& mesh : meshes)
    {
      if (mesh.CategoryIndex == c)
      {
        members.push_back(&mesh);
      }
    }
    if (members.empty())
    {
      continue;
    }
    categories.push_back(ScoreCategory(c == kOtherCategory ? "Other" : kCategories[c].Name, members));
    all.insert(all.end(), members.begin(), members.end());
    if (c != kOtherCategory && kCategories[c].Articulated)
    {
      articulatedCategories.push_back(categories.back());
      articulatedMeshes.insert(articulatedMeshes.end(), members.begin(), members.end());
    }
  }
  if (categories.front().Name == "Other")
  {
    std::rotate(categories.begin(), categories.begin() + 1, categories.end());
  }
  const GroupScore overall = MeanOfCategories("Overall", categories, all);
  GroupScore articulated;
  const bool hasArticulated = !articulatedCategories.empty();
  if (hasArticulated)
  {
    articulated = MeanOfCategories("Articulated", articulatedCategories, articulatedMeshes);
  }
  if (arguments.json)
  {
    PrintJson(arguments, categories, overall, hasArticulated ? &articulated : nullptr, meshes, missing);
  }
  else
  {
    PrintMarkdown(categories, overall, hasArticulated ? &articulated : nullptr, meshes, missing, arguments.perMesh);
  }
  if (std::fflush(stdout) != 0)
  {
    throw std::runtime_error("cannot write the output");
  }

  std::vector<std::string> failures;
  if (arguments.maxRandError >= 0.0 && !(overall.Mean.RandIndexError <= arguments.maxRandError))
  {
    failures.push_back("overall 1-RI " + Number(overall.Mean.RandIndexError) + " exceeds " +
      Number(arguments.maxRandError));
  }
  if (arguments.minCountShare >= 0.0)
  {
    const GroupScore& group = hasArticulated ? articulated : overall;
    const double share = 100.0 * static_cast<double>(group.Within) / static_cast<double>(group.Meshes);
    if (!(share >= arguments.minCountShare))
    {
      failures.push_back(std::string(hasArticulated ? "articulated" : "all") + " meshes within 1.5x of the humans' segment count: " +
        Number(share, "%.1f") + " %, fewer than " + Number(arguments.minCountShare, "%.1f") + " %");
    }
  }
  if (!failures.empty())
  {
    std::string message;
    for (const std::string& failure : failures)
    {
      message += (message.empty() ? "" : "; ") + failure;
    }
    std::fprintf(stderr, "sdf-psb-benchmark: FAIL: %s\n", message.c_str());
    return 1;
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
    std::fprintf(stderr, "sdf-psb-benchmark: %s\n", error.what());
    return 1;
  }
}
