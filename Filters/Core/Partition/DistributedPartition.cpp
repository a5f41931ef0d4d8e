// SPDX-License-Identifier: BSD-3-Clause
#include "Partition/DistributedPartition.h"

#include "ExactSum.h"
#include "GatheredOrder.h"
#include "Mesh/FaceGraph.h"
#include "Partition/CoarseningCells.h"
#include "Partition/DistributedCut.h"
#include "Release.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
#include <string>
#include <utility>

namespace shapediameter
{
namespace
{
/// The dual-graph rows of a process's own faces, field by field, as the collectives carry them.
struct OwnRows
{
  std::vector<double> Ids, Values, Areas, Degrees;
  /// Per own face its centre: x, y, z.
  std::vector<double> Centers;
  std::vector<double> Neighbors, NormalAngles, EdgeLengths, Concave;
  /// Per side of an own face that no other face of the share has: the face's id, then the
  /// side's two corners (lexicographically ordered, so both faces of a side give the same).
  std::vector<double> OpenSides;
};

/// Appends the open sides of face f (sides no neighbour in the share has) to `openSides`.
void AddOpenSides(const PartitionInput& input, const FaceGraph& graph, const PartitionShare& share, std::size_t f,
  std::vector<double>& openSides)
{
  const auto id = static_cast<double>(share.GlobalIds[f]);
  const auto corners = [&](std::size_t face) {
    return std::make_pair(input.FaceConnectivity.begin() + input.FaceOffsets[face],
      input.FaceConnectivity.begin() + input.FaceOffsets[face + 1]);
  };
  const auto [begin, end] = corners(f);
  const auto count = end - begin;
  for (std::ptrdiff_t i = 0; i < count; ++i)
  {
    const std::int64_t a = begin[i], b = begin[(i + 1) % count];
    if (a == b)
    {
      continue;
    }
    bool shared = false;
    for (auto e = graph.NeighborBegin(static_cast<std::int64_t>(f)); !shared && e < graph.NeighborEnd(static_cast<std::int64_t>(f)); ++e)
    {
      const auto [first, last] = corners(static_cast<std::size_t>(graph.Neighbors[static_cast<std::size_t>(e)]));
      shared = std::find(first, last, a) != last && std::find(first, last, b) != last;
    }
    if (!shared && share.GlobalPointIds)
    {
      // The corners' global ids: the whole surface joins exactly the faces whose corners share them.
      const auto [low, high] = std::minmax((*share.GlobalPointIds)[static_cast<std::size_t>(a)],
        (*share.GlobalPointIds)[static_cast<std::size_t>(b)]);
      openSides.insert(openSides.end(), { id, static_cast<double>(low), static_cast<double>(high), 0.0, 0.0, 0.0, 0.0 });
    }
    else if (!shared)
    {
      Eigen::RowVector3d p = input.Points.row(static_cast<Eigen::Index>(a));
      Eigen::RowVector3d q = input.Points.row(static_cast<Eigen::Index>(b));
      if (std::lexicographical_compare(q.data(), q.data() + 3, p.data(), p.data() + 3))
      {
        std::swap(p, q);
      }
      openSides.insert(openSides.end(), { id, p[0], p[1], p[2], q[0], q[1], q[2] });
    }
  }
}

OwnRows RowsOfOwnFaces(const PartitionInput& input, const FaceGraph& graph, const PartitionShare& share)
{
  OwnRows rows;
  const ValuesView& values = input.FaceValues;
  for (std::size_t f = 0; f < graph.FaceCount(); ++f)
  {
    if (!share.Own[f])
    {
      continue;
    }
    AddOpenSides(input, graph, share, f, rows.OpenSides);
    rows.Ids.push_back(static_cast<double>(share.GlobalIds[f]));
    rows.Values.push_back(values[static_cast<Eigen::Index>(f)]);
    rows.Areas.push_back(graph.Areas[f]);
    for (int axis = 0; axis < 3; ++axis)
    {
      rows.Centers.push_back(graph.Centers(static_cast<Eigen::Index>(f), axis));
    }
    const auto begin = static_cast<std::size_t>(graph.NeighborBegin(static_cast<std::int64_t>(f)));
    const auto end = static_cast<std::size_t>(graph.NeighborEnd(static_cast<std::int64_t>(f)));
    rows.Degrees.push_back(static_cast<double>(end - begin));
    for (std::size_t e = begin; e < end; ++e)
    {
      rows.Neighbors.push_back(static_cast<double>(share.GlobalIds[static_cast<std::size_t>(graph.Neighbors[e])]));
      rows.NormalAngles.push_back(graph.NormalAngles[e]);
      rows.EdgeLengths.push_back(graph.SharedEdgeLengths[e]);
      rows.Concave.push_back(graph.Concave[e]);
    }
  }
  return rows;
}

/// On the first process: the whole surface's dual graph, assembled from every process's rows.
struct WholeGraph
{
  /// The faces' order: face w of the whole graph has id Order.Ids[w]; per process, per own face
  /// in its order, the face's index and whether this copy's rows are the ones used (a face
  /// several processes own: the lowest one's).
  GatheredOrder Order;
  std::vector<std::int64_t> Offsets, Neighbors;
  std::vector<double> NormalAngles, EdgeLengths, Areas, Values;
  /// Per face x, y, z: read by the cut's coarsening (CoarseningCells.h).
  std::vector<double> Centers;
  std::vector<std::uint8_t> Concave;
  /// A missing adjacency found (empty: none): every process then throws HaloTooNarrowError.
  std::string HaloProblem;

  DualGraphView View() const
  {
    DualGraphView view;
    view.Offsets = this->Offsets.data();
    view.Neighbors = this->Neighbors.data();
    view.NormalAngle = this->NormalAngles.data();
    view.Concave = this->Concave.data();
    view.EdgeLength = this->EdgeLengths.data();
    view.FaceArea = this->Areas.data();
    view.FaceCenter = this->Centers.empty() ? nullptr : this->Centers.data();
    view.FaceCount = this->Areas.size();
    return view;
  }
};

/// Per-face values of the used rows (`width` per face), in the whole graph's order.
std::vector<double> WholeFaceField(
  const std::vector<std::vector<double>>& processValues, const WholeGraph& whole, std::size_t width = 1)
{
  std::vector<double> field(whole.Order.Ids.size() * width, 0.0);
  for (std::size_t p = 0; p < processValues.size(); ++p)
  {
    for (std::size_t i = 0; i < processValues[p].size() / width; ++i)
    {
      if (whole.Order.Used[p][i])
      {
        std::copy_n(processValues[p].begin() + static_cast<std::ptrdiff_t>(i * width), width,
          field.begin() + static_cast<std::ptrdiff_t>(static_cast<std::size_t>(whole.Order.Index[p][i]) * width));
      }
    }
  }
  return field;
}

/// Per-adjacency values of the used rows, in the whole graph's CSR order; `convert` maps a
/// gathered value to the stored one.
template <typename T, typename Convert>
std::vector<T> WholeEntryField(const std::vector<std::vector<double>>& processValues,
  const std::vector<std::vector<double>>& processDegrees, const WholeGraph& whole, const Convert& convert)
{
  std::vector<T> field(static_cast<std::size_t>(whole.Offsets.back()));
  for (std::size_t p = 0; p < processValues.size(); ++p)
  {
    std::size_t at = 0;
    for (std::size_t i = 0; i < processDegrees[p].size(); ++i)
    {
      const auto degree = static_cast<std::size_t>(processDegrees[p][i]);
      if (whole.Order.Used[p][i])
      {
        const auto to = static_cast<std::size_t>(whole.Offsets[static_cast<std::size_t>(whole.Order.Index[p][i])]);
        for (std::size_t k = 0; k < degree; ++k)
        {
          field[to + k] = convert(processValues[p][at + k]);
        }
      }
      at += degree;
    }
  }
  return field;
}

/// Every adjacency must be listed by both faces: a face's neighbour that a process's halo
/// missed would silently change its row. Returns what is wrong (empty: nothing).
std::string CheckSymmetric(const WholeGraph& whole)
{
  for (std::size_t f = 0; f < whole.Order.Ids.size(); ++f)
  {
    for (auto e = whole.Offsets[f]; e < whole.Offsets[f + 1]; ++e)
    {
      const auto g = static_cast<std::size_t>(whole.Neighbors[static_cast<std::size_t>(e)]);
      const auto first = whole.Neighbors.begin() + whole.Offsets[g];
      const auto last = whole.Neighbors.begin() + whole.Offsets[g + 1];
      if (!std::binary_search(first, last, static_cast<std::int64_t>(f)))
      {
        return "partition: face " + std::to_string(whole.Order.Ids[g]) + " does not list its neighbour " +
          std::to_string(whole.Order.Ids[f]) + " (the halo of its process was too narrow)";
      }
    }
  }
  return {};
}

/// Two faces whose shares both lack the other: they share a side that each reports open.
/// Returns what is wrong (empty: nothing).
std::string CheckOpenSides(const std::vector<std::vector<double>>& processSides)
{
  using Side = std::array<double, 7>; // corners first, then the face id
  std::vector<Side> sides;
  for (const std::vector<double>& part : processSides)
  {
    for (std::size_t at = 0; at + 7 <= part.size(); at += 7)
    {
      sides.push_back(Side{ part[at + 1], part[at + 2], part[at + 3], part[at + 4], part[at + 5], part[at + 6], part[at] });
    }
  }
  std::sort(sides.begin(), sides.end());
  for (std::size_t i = 1; i < sides.size(); ++i)
  {
    if (std::equal(sides[i].begin(), sides[i].begin() + 6, sides[i - 1].begin()) && sides[i][6] != sides[i - 1][6])
    {
      return "partition: faces " + std::to_string(static_cast<std::int64_t>(sides[i - 1][6])) + " and " +
        std::to_string(static_cast<std::int64_t>(sides[i][6])) +
        " share a side but neither process saw the other (the halo was too narrow)";
    }
  }
  return {};
}

/// Steps 1 and 2 of the header: every process's rows to the first process, assembled there.
/// Each gathered field is freed once converted (the first process never holds two at once).
WholeGraph GatherWholeGraph(const OwnRows& rows, const ProcessGroup& group)
{
  WholeGraph whole;
  const bool first = group.Rank() == 0;
  if (first)
  {
    whole.Order = OrderGatheredIds(group.GatherOnFirst(rows.Ids));
    whole.Values = WholeFaceField(group.GatherOnFirst(rows.Values), whole);
    whole.Areas = WholeFaceField(group.GatherOnFirst(rows.Areas), whole);
    whole.Centers = WholeFaceField(group.GatherOnFirst(rows.Centers), whole, 3);
  }
  else
  {
    for (const std::vector<double>* field : { &rows.Ids, &rows.Values, &rows.Areas, &rows.Centers })
    {
      group.GatherOnFirst(*field);
    }
  }
  const std::vector<std::vector<double>> openSides = group.GatherOnFirst(rows.OpenSides);
  if (first)
  {
    whole.HaloProblem = CheckOpenSides(openSides);
  }
  const std::vector<std::vector<double>> degrees = group.GatherOnFirst(rows.Degrees);
  if (!first)
  {
    for (const std::vector<double>* field : { &rows.Neighbors, &rows.NormalAngles, &rows.EdgeLengths, &rows.Concave })
    {
      group.GatherOnFirst(*field);
    }
    return whole;
  }
  const std::vector<double> wholeDegrees = WholeFaceField(degrees, whole);
  whole.Offsets.assign(whole.Order.Ids.size() + 1, 0);
  for (std::size_t f = 0; f < wholeDegrees.size(); ++f)
  {
    whole.Offsets[f + 1] = whole.Offsets[f] + static_cast<std::int64_t>(wholeDegrees[f]);
  }
  whole.Neighbors = WholeEntryField<std::int64_t>(group.GatherOnFirst(rows.Neighbors), degrees, whole, [&](double id) {
    const std::int64_t index = whole.Order.IndexOf(static_cast<std::int64_t>(id));
    if (index < 0)
    {
      throw Error("partition: face " + std::to_string(static_cast<std::int64_t>(id)) +
        " is a neighbour of an own face but no process's own face");
    }
    return index;
  });
  Release(whole.Order.IndexOfId);
  const auto same = [](double value) { return value; };
  whole.NormalAngles = WholeEntryField<double>(group.GatherOnFirst(rows.NormalAngles), degrees, whole, same);
  whole.EdgeLengths = WholeEntryField<double>(group.GatherOnFirst(rows.EdgeLengths), degrees, whole, same);
  whole.Concave = WholeEntryField<std::uint8_t>(group.GatherOnFirst(rows.Concave), degrees, whole,
    [](double value) { return static_cast<std::uint8_t>(value != 0.0); });
  if (whole.HaloProblem.empty())
  {
    whole.HaloProblem = CheckSymmetric(whole);
  }
  return whole;
}

/// What every process gets back (step 4 of the header), as doubles: the whole-surface part,
/// then per own face of `process` its probabilities, band, fine label and segment.
enum PartStatus : int
{
  Partitioned = 0,
  Aborted = 1,
  HaloTooNarrow = 2
};

std::vector<double> PartOfProcess(const PartitionResult& result, const std::string& haloProblem,
  const std::vector<std::int64_t>& ownFaces, bool withProbabilities = true)
{
  if (!haloProblem.empty())
  {
    std::vector<double> part{ HaloTooNarrow };
    part.insert(part.end(), haloProblem.begin(), haloProblem.end());
    return part;
  }
  if (result.Aborted)
  {
    return { Aborted };
  }
  const GaussianMixtureModel& model = result.Model;
  std::vector<double> part{ Partitioned, static_cast<double>(model.ComponentCount()) };
  part.insert(part.end(), model.Means.begin(), model.Means.end());
  part.insert(part.end(), model.Sigmas.begin(), model.Sigmas.end());
  part.insert(part.end(), model.Weights.begin(), model.Weights.end());
  part.push_back(result.Energy);
  part.push_back(static_cast<double>(result.CutMoves));
  part.push_back(static_cast<double>(result.LabelBands.size()));
  part.insert(part.end(), result.LabelBands.begin(), result.LabelBands.end());
  part.push_back(static_cast<double>(result.Segments.Area.size()));
  part.insert(part.end(), result.Segments.Area.begin(), result.Segments.Area.end());
  part.insert(part.end(), result.Segments.Label.begin(), result.Segments.Label.end());
  const auto k = static_cast<Eigen::Index>(model.ComponentCount());
  for (const std::int64_t face : ownFaces)
  {
    const auto f = static_cast<std::size_t>(face);
    for (Eigen::Index c = 0; c < k && withProbabilities; ++c)
    {
      part.push_back(result.Probabilities(static_cast<Eigen::Index>(face), c));
    }
    part.push_back(result.Bands[f]);
    part.push_back(result.Labels[f]);
    part.push_back(result.Segments.Segment[f]);
  }
  return part;
}

/// Reads PartOfProcess on the process it was sent to: the result over the share's faces.
/// With `probabilities` (the share's, computed by this process) the part has none.
PartitionResult ResultOfShare(
  const std::vector<double>& part, const PartitionShare& share, const PosteriorMatrix* probabilities = nullptr)
{
  PartitionResult result;
  if (!part.empty() && part[0] == HaloTooNarrow)
  {
    std::string problem;
    for (std::size_t i = 1; i < part.size(); ++i)
    {
      problem += static_cast<char>(part[i]);
    }
    throw HaloTooNarrowError(problem); // on every process
  }
  if (part.empty() || part[0] != Partitioned)
  {
    result.Aborted = true;
    return result;
  }
  std::size_t at = 1;
  const auto next = [&]() { return part.at(at++); };
  const auto k = static_cast<std::size_t>(next());
  const auto read = [&](std::size_t count) {
    std::vector<double> values(part.begin() + static_cast<std::ptrdiff_t>(at),
      part.begin() + static_cast<std::ptrdiff_t>(at + count));
    at += count;
    return values;
  };
  result.Model.Means = read(k);
  result.Model.Sigmas = read(k);
  result.Model.Weights = read(k);
  result.Energy = next();
  result.CutMoves = static_cast<int>(next());
  const std::vector<double> labelBands = read(static_cast<std::size_t>(next()));
  result.LabelBands.assign(labelBands.begin(), labelBands.end());
  const auto segments = static_cast<std::size_t>(next());
  result.Segments.Area = read(segments);
  const std::vector<double> segmentLabels = read(segments);
  result.Segments.Label.assign(segmentLabels.begin(), segmentLabels.end());

  const std::size_t faces = share.Own.size();
  result.Probabilities = PosteriorMatrix::Zero(static_cast<Eigen::Index>(faces), static_cast<Eigen::Index>(k));
  result.Bands.assign(faces, -1);
  result.Labels.assign(faces, -1);
  result.Segments.Segment.assign(faces, -1);
  for (std::size_t f = 0; f < faces; ++f)
  {
    if (!share.Own[f])
    {
      continue;
    }
    for (std::size_t c = 0; c < k; ++c)
    {
      result.Probabilities(static_cast<Eigen::Index>(f), static_cast<Eigen::Index>(c)) =
        probabilities ? (*probabilities)(static_cast<Eigen::Index>(f), static_cast<Eigen::Index>(c)) : next();
    }
    result.Bands[f] = static_cast<int>(next());
    result.Labels[f] = static_cast<int>(next());
    result.Segments.Segment[f] = static_cast<int>(next());
  }
  for (std::size_t level = 1; level < k; ++level)
  {
    std::vector<int> levels(result.Bands);
    for (int& band : levels)
    {
      band = band < 0 ? band : std::min(band, static_cast<int>(level));
    }
    result.Levels.push_back(std::move(levels));
  }
  return result;
}

/// The graph cut's rows of a share (DistributedCut.h): data costs of every share face, own
/// faces' pairs in the serial cut's order with their weights (BuildPartitionEnergy's terms),
/// and the cells of the whole surface's grid. Nothing when there is no grid (the serial cut would
/// not coarsen by cells; every process agrees, and the caller gathers).
std::optional<CutShare> ShareEnergy(const FaceGraph& graph, const PosteriorMatrix& posteriors, const PartitionShare& share,
  std::size_t wholeFaces, double totalArea, const PartitionOptions& options)
{
  const std::size_t n = graph.FaceCount();
  const auto k = static_cast<std::size_t>(posteriors.cols());
  CutShare cut{ share.GlobalIds, share.Own, static_cast<int>(k), {}, {}, {}, {}, {}, wholeFaces };
  const AreaScale scale = AreaScaleOf(totalArea, wholeFaces);
  cut.DataCosts.resize(n * k);
  for (std::size_t f = 0; f < n; ++f)
  {
    double faceWeight = graph.Areas[f];
    faceWeight /= scale.MeanArea;
    for (std::size_t l = 0; l < k; ++l)
    {
      cut.DataCosts[f * k + l] =
        WeightedDataCost(faceWeight, posteriors(static_cast<Eigen::Index>(f), static_cast<Eigen::Index>(l)), options.Energy);
    }
  }
  // A pair's terms come from the entry of its lower face, as in the whole graph (a face listed
  // twice, sharing two sides, makes two pairs: the occurrence-th entry's).
  const auto entryWeight = [&](std::size_t entry) {
    return PairWeight(graph.NormalAngles[entry], graph.Concave[entry] != 0, graph.SharedEdgeLengths[entry],
      scale.PerUnitLength, options.Energy);
  };
  const auto lowerEntry = [&](std::size_t low, std::size_t high, std::size_t occurrence) {
    for (std::int64_t e = graph.NeighborBegin(static_cast<std::int64_t>(low)); e < graph.NeighborEnd(static_cast<std::int64_t>(low)); ++e)
    {
      const auto entry = static_cast<std::size_t>(e);
      if (static_cast<std::size_t>(graph.Neighbors[entry]) == high && occurrence-- == 0)
      {
        return entry;
      }
    }
    throw HaloTooNarrowError("partition: a pair listed by one face only (the halo was too narrow)");
  };
  cut.Start.assign(n + 1, 0);
  std::vector<std::pair<std::size_t, std::size_t>> lower; // (neighbour, entry), CSR order within a neighbour
  for (std::size_t f = 0; f < n; ++f)
  {
    if (share.Own[f])
    {
      lower.clear();
      for (std::int64_t e = graph.NeighborBegin(static_cast<std::int64_t>(f)); e < graph.NeighborEnd(static_cast<std::int64_t>(f)); ++e)
      {
        const auto g = static_cast<std::size_t>(graph.Neighbors[static_cast<std::size_t>(e)]);
        if (g < f)
        {
          lower.emplace_back(g, static_cast<std::size_t>(e));
        }
      }
      std::sort(lower.begin(), lower.end());
      for (std::size_t i = 0; i < lower.size(); ++i)
      {
        const std::size_t g = lower[i].first;
        const auto firstOfG = static_cast<std::size_t>(
          std::lower_bound(lower.begin(), lower.end(), std::make_pair(g, std::size_t{ 0 })) - lower.begin());
        const std::size_t occurrence = i - firstOfG;
        cut.Neighbor.push_back(static_cast<std::uint32_t>(g));
        cut.Weight.push_back(entryWeight(lowerEntry(g, f, occurrence)));
      }
      for (std::int64_t e = graph.NeighborBegin(static_cast<std::int64_t>(f)); e < graph.NeighborEnd(static_cast<std::int64_t>(f)); ++e)
      {
        const auto g = static_cast<std::size_t>(graph.Neighbors[static_cast<std::size_t>(e)]);
        if (g > f)
        {
          cut.Neighbor.push_back(static_cast<std::uint32_t>(g));
          cut.Weight.push_back(entryWeight(static_cast<std::size_t>(e)));
        }
      }
    }
    cut.Start[f + 1] = cut.Neighbor.size();
  }

  // The grid of CoarseningCells over the whole surface: the extremes of every process's own
  // faces' centres, and its spacing sums (each pair counted by its lower face's owner); no grid
  // when a centre of any share is not finite, as a serial run over the whole surface has none.
  const DualGraphView view = MakeDualGraphView(graph);
  const CellGridTerms terms = CollectCellGridTerms(view, share.Own.data());
  std::vector<double> extremes{ -terms.Low[0], -terms.Low[1], -terms.Low[2], terms.High[0], terms.High[1],
    terms.High[2], terms.Finite ? 0.0 : 1.0 };
  std::vector<std::int64_t> pairs{ static_cast<std::int64_t>(terms.Pairs) };
  share.Group.MaxInPlace(extremes);
  share.Group.SumInPlace(pairs);
  const double spacing = SumOverProcesses(terms.Spacing, share.Group);
  if (pairs[0] == 0 || extremes[6] > 0.0)
  {
    return std::nullopt;
  }
  const CellGrid grid = MakeCellGrid({ -extremes[0], -extremes[1], -extremes[2] }, { extremes[3], extremes[4], extremes[5] },
    spacing / static_cast<double>(pairs[0]), options.Multilevel.ClusterSize);
  if (grid.Side == 0.0)
  {
    return std::nullopt;
  }
  cut.Cells.resize(n);
  for (std::size_t f = 0; f < n; ++f)
  {
    cut.Cells[f] = CellOf(grid, view.FaceCenter + 3 * f);
  }
  return cut;
}

/// The exact E of the labels (PartitionEnergy::EvaluateExactly) from every process's own faces
/// and pairs.
double EnergyOverProcesses(const CutShare& cut, const std::vector<int>& labels, const ProcessGroup& group)
{
  const auto k = static_cast<std::size_t>(cut.LabelCount);
  ExactSum sum;
  for (std::size_t f = 0; f < cut.GlobalIds.size(); ++f)
  {
    if (!cut.Own[f])
    {
      continue;
    }
    sum.Add(cut.DataCosts[f * k + static_cast<std::size_t>(labels[f])]);
    for (std::size_t e = cut.Start[f]; e < cut.Start[f + 1]; ++e)
    {
      if (cut.Neighbor[e] > f && labels[cut.Neighbor[e]] != labels[f])
      {
        sum.Add(cut.Weight[e]);
      }
    }
  }
  return SumOverProcesses(sum, group);
}

/// The partition with the graph cut on every process's faces (DistributedCut.h), when the
/// serial run would coarsen by cells: above DirectBelowFaces faces, geometric weights on, no
/// refinement, every face owned once, a surface of positive area. Otherwise (all processes
/// agree) nothing: the caller gathers the dual graph.
std::optional<PartitionResult> PartitionWithCutOnEveryProcess(const PartitionInput& input, const PartitionShare& share,
  const PartitionOptions& options, const ParallelFor& parallelFor, const ProgressCallback& progress)
{
  const ProcessGroup& group = share.Group;
  const bool first = group.Rank() == 0;
  std::vector<std::int64_t> ownFaces{ std::count(share.Own.begin(), share.Own.end(), std::uint8_t{ 1 }) };
  group.SumInPlace(ownFaces);
  const auto wholeFaces = static_cast<std::size_t>(ownFaces[0]);
  if (wholeFaces <= options.Multilevel.DirectBelowFaces || options.Refinement.Enabled ||
    !options.Energy.GeometricWeights)
  {
    return std::nullopt;
  }
  auto start = std::chrono::steady_clock::now();
  std::optional<FaceGraph> shareGraph = BuildFaceGraph(input.Points, input.FaceOffsets, input.FaceConnectivity, parallelFor);
  const FaceGraph& graph = *shareGraph;
  ValidateDualGraph(MakeDualGraphView(graph), true, parallelFor);
  const ValuesView& values = input.FaceValues;
  std::vector<double> rows, openSides;
  for (std::size_t f = 0; f < graph.FaceCount(); ++f)
  {
    if (share.Own[f])
    {
      rows.insert(rows.end(), { static_cast<double>(share.GlobalIds[f]), values[static_cast<Eigen::Index>(f)], graph.Areas[f] });
      AddOpenSides(input, graph, share, f, openSides);
    }
  }
  std::vector<std::vector<double>> gathered = group.GatherOnFirst(rows);
  Release(rows);
  const std::vector<std::vector<double>> sides = group.GatherOnFirst(openSides);
  Release(openSides);

  // The model and the surface's area on the first process (the serial steps 2 and the
  // weights' sums, on the values and areas in the whole surface's order).
  enum : int { Go = 0, Gather = 1, HaloProblem = 2, Abort = 3 };
  GatheredOrder order;
  std::vector<double> wholeValues, wholeAreas;
  PartitionResult firstResult;
  std::vector<double> decision;
  if (first)
  {
    order = OrderGatheredIds(gathered, 3);
    const std::string haloProblem = CheckOpenSides(sides);
    bool ownedOnce = order.Ids.size() == wholeFaces;
    wholeValues.assign(order.Ids.size(), 0.0);
    wholeAreas.assign(order.Ids.size(), 0.0);
    for (std::size_t p = 0; p < gathered.size(); ++p)
    {
      for (std::size_t i = 0; i < order.Index[p].size(); ++i)
      {
        const auto w = static_cast<std::size_t>(order.Index[p][i]);
        wholeValues[w] = gathered[p][3 * i + 1];
        wholeAreas[w] = gathered[p][3 * i + 2];
      }
    }
    Release(gathered);
    const double totalArea = std::accumulate(wholeAreas.begin(), wholeAreas.end(), 0.0);
    if (!haloProblem.empty())
    {
      decision.assign(1, HaloProblem);
      decision.insert(decision.end(), haloProblem.begin(), haloProblem.end());
    }
    else if (progress && !progress(0.1))
    {
      decision.assign(1, Abort);
    }
    else
    {
      const Eigen::Map<const Eigen::VectorXd> valueView(wholeValues.data(), static_cast<Eigen::Index>(wholeValues.size()));
      firstResult.Model = input.FamilyModel ? *input.FamilyModel : FitClusterModel(valueView, wholeAreas, options);
      const GaussianMixtureModel& model = firstResult.Model;
      const bool go = ownedOnce && totalArea > 0.0 && std::isfinite(totalArea) && model.ComponentCount() >= 2;
      if (go)
      {
        // The values are not held through the cut: their histogram (step 8) needs only them and
        // the model.
        firstResult.Histogram = MixtureHistogram(model, valueView, options.HistogramBins);
      }
      decision = { static_cast<double>(go ? Go : Gather), totalArea, static_cast<double>(model.ComponentCount()) };
      decision.insert(decision.end(), model.Means.begin(), model.Means.end());
      decision.insert(decision.end(), model.Sigmas.begin(), model.Sigmas.end());
      decision.insert(decision.end(), model.Weights.begin(), model.Weights.end());
    }
  }
  decision = group.ScatterFromFirst([&](int) { return decision; });
  // The areas come back with the segments' rows after the cut.
  Release(wholeValues);
  Release(wholeAreas);
  const int status = static_cast<int>(decision.at(0));
  if (status == HaloProblem)
  {
    throw HaloTooNarrowError(std::string(decision.begin() + 1, decision.end())); // on every process
  }
  if (status == Abort)
  {
    PartitionResult aborted;
    aborted.Aborted = true;
    return aborted;
  }
  if (status == Gather)
  {
    return std::nullopt;
  }
  const double totalArea = decision.at(1);
  const auto k = static_cast<std::size_t>(decision.at(2));
  GaussianMixtureModel model;
  model.Means.assign(decision.begin() + 3, decision.begin() + 3 + static_cast<std::ptrdiff_t>(k));
  model.Sigmas.assign(decision.begin() + 3 + static_cast<std::ptrdiff_t>(k), decision.begin() + 3 + static_cast<std::ptrdiff_t>(2 * k));
  model.Weights.assign(decision.begin() + 3 + static_cast<std::ptrdiff_t>(2 * k), decision.begin() + 3 + static_cast<std::ptrdiff_t>(3 * k));

  // Every process: its faces' posteriors, energy rows and cells; the cut over the processes.
  PosteriorMatrix posteriors = ComputePosteriors(model, values, parallelFor);
  const std::optional<CutShare> shareEnergy = ShareEnergy(graph, posteriors, share, wholeFaces, totalArea, options);
  if (!shareEnergy)
  {
    return std::nullopt;
  }
  const CutShare& cut = *shareEnergy;
  // The segments' rows (step 6 on the first process), then the graph is freed: per own face
  // its label (filled in after the cut), area and degree, and apart its neighbours' ids in the
  // graph's order.
  std::vector<double> segmentHeads, segmentNeighbors;
  for (std::size_t f = 0; f < graph.FaceCount(); ++f)
  {
    if (share.Own[f])
    {
      const auto face = static_cast<std::int64_t>(f);
      segmentHeads.insert(segmentHeads.end(),
        { 0.0, graph.Areas[f], static_cast<double>(graph.NeighborEnd(face) - graph.NeighborBegin(face)) });
      for (std::int64_t e = graph.NeighborBegin(face); e < graph.NeighborEnd(face); ++e)
      {
        segmentNeighbors.push_back(static_cast<double>(share.GlobalIds[static_cast<std::size_t>(graph.Neighbors[static_cast<std::size_t>(e)])]));
      }
    }
  }
  shareGraph.reset();
  const CutOverProcessesResult labels = MinimizeMultilevelOverProcesses(
    cut, group, options.Multilevel, options.AlphaExpansion, SubProgress(progress, 0.2, 0.95), parallelFor);
  if (!labels.Coarsened)
  {
    return std::nullopt;
  }
  if (labels.Aborted)
  {
    PartitionResult aborted;
    aborted.Aborted = true;
    return aborted;
  }
  const double energy = EnergyOverProcesses(cut, labels.Labels, group);

  // Segments and levels on the first process, from the labels, areas and adjacency (ids only)
  // of every own face, one process's at a time.
  for (std::size_t f = 0, own = 0; f < share.Own.size(); ++f)
  {
    if (share.Own[f])
    {
      segmentHeads[3 * own++] = labels.Labels[f];
    }
  }
  const std::size_t n = order.Ids.size();
  std::vector<int> wholeLabels(first ? n : 0, 0);
  std::vector<std::int64_t> offsets(first ? n + 1 : 0, 0);
  wholeAreas.assign(first ? n : 0, 0.0);
  GatherOnFirstInTurn([&]() { return std::move(segmentHeads); },
    [&](std::size_t process, std::vector<double>&& heads) {
      if (heads.size() != 3 * order.Index[process].size())
      {
        throw Error("partition: process " + std::to_string(process) + " sent " + std::to_string(heads.size() / 3) +
          " segment rows for " + std::to_string(order.Index[process].size()) + " faces");
      }
      for (std::size_t i = 0; i < order.Index[process].size(); ++i)
      {
        const auto w = static_cast<std::size_t>(order.Index[process][i]);
        wholeLabels[w] = static_cast<int>(heads[3 * i]);
        wholeAreas[w] = heads[3 * i + 1];
        offsets[w + 1] = static_cast<std::int64_t>(heads[3 * i + 2]);
      }
    },
    group);
  std::partial_sum(offsets.begin(), offsets.end(), offsets.begin());
  std::vector<std::int64_t> flat(first ? static_cast<std::size_t>(offsets[n]) : 0);
  GatherOnFirstInTurn([&]() { return std::move(segmentNeighbors); },
    [&](std::size_t process, std::vector<double>&& neighbors) {
      std::size_t expected = 0;
      for (const std::int64_t w : order.Index[process])
      {
        expected += static_cast<std::size_t>(offsets[static_cast<std::size_t>(w) + 1] - offsets[static_cast<std::size_t>(w)]);
      }
      if (neighbors.size() != expected)
      {
        throw Error("partition: process " + std::to_string(process) + " sent " + std::to_string(neighbors.size()) +
          " neighbours where its faces' degrees add up to " + std::to_string(expected));
      }
      std::size_t at = 0;
      for (const std::int64_t w : order.Index[process])
      {
        for (auto entry = offsets[static_cast<std::size_t>(w)]; entry < offsets[static_cast<std::size_t>(w) + 1]; ++entry)
        {
          const std::int64_t index = order.IndexOf(static_cast<std::int64_t>(neighbors[at++]));
          if (index < 0)
          {
            throw Error("partition: a neighbour of an own face is no process's own face");
          }
          flat[static_cast<std::size_t>(entry)] = index;
        }
      }
    },
    group);
  if (first)
  {
    DualGraphView view;
    view.Offsets = offsets.data();
    view.Neighbors = flat.data();
    view.FaceCount = n;
    firstResult.Energy = energy;
    firstResult.CutMoves = labels.Moves;
    firstResult.Segments = FindConnectedSegmentsOnValidGraph(view, wholeLabels, wholeAreas);
    firstResult.Bands = wholeLabels;
    firstResult.Labels = std::move(wholeLabels);
    for (int band = 0; band < firstResult.Model.ComponentCount(); ++band)
    {
      firstResult.LabelBands.push_back(band);
    }
    firstResult.Timings.CutMs = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  }
  for (Eigen::Index f = 0; f < posteriors.rows(); ++f)
  {
    if (!share.Own[static_cast<std::size_t>(f)])
    {
      posteriors.row(f).setZero();
    }
  }
  PartitionResult result = ResultOfShare(group.ScatterFromFirst([&](int process) {
    return PartOfProcess(firstResult, {}, order.Index[static_cast<std::size_t>(process)], false);
  }),
    share, &posteriors);
  result.CutOverProcesses = true;
  if (first)
  {
    result.Histogram = std::move(firstResult.Histogram);
    result.Timings = firstResult.Timings;
  }
  if (first && progress)
  {
    progress(1.0);
  }
  return result;
}
} // namespace

PartitionResult PartitionOverProcesses(const PartitionInput& input, const PartitionShare& share,
  const PartitionOptions& options, const ParallelFor& parallelFor, const ProgressCallback& progress)
{
  const std::size_t faceCount = input.FaceOffsets.empty() ? 0 : input.FaceOffsets.size() - 1;
  if (share.GlobalIds.size() != faceCount || share.Own.size() != faceCount)
  {
    throw Error("partition: the share's global ids or own flags do not match its faces");
  }
  if (share.GlobalPointIds && share.GlobalPointIds->size() != static_cast<std::size_t>(input.Points.rows()))
  {
    throw Error("partition: the share's global point ids do not match its points");
  }
  if (!std::all_of(share.GlobalIds.begin(), share.GlobalIds.end(), IsGatherableId))
  {
    throw Error("partition: a global face id outside [0, 2^53)");
  }
  if (std::optional<PartitionResult> result = PartitionWithCutOnEveryProcess(input, share, options, parallelFor, progress))
  {
    return *std::move(result);
  }
  const ProcessGroup& group = share.Group;
  // The share's graph is needed only for its rows: freed before the first process partitions.
  WholeGraph whole = GatherWholeGraph(
    RowsOfOwnFaces(input, BuildFaceGraph(input.Points, input.FaceOffsets, input.FaceConnectivity, parallelFor), share),
    group);

  PartitionResult wholeResult;
  if (group.Rank() == 0 && whole.HaloProblem.empty())
  {
    const auto releaseEdgeGeometry = [&whole] {
      Release(whole.NormalAngles);
      Release(whole.EdgeLengths);
      Release(whole.Concave);
      Release(whole.Centers);
    };
    if (progress && !progress(0.1))
    {
      wholeResult.Aborted = true;
    }
    else
    {
      const Eigen::Map<const Eigen::VectorXd> values(whole.Values.data(), static_cast<Eigen::Index>(whole.Values.size()));
      wholeResult = PartitionOnDualGraph(
        whole.View(), whole.Areas, values, input.FamilyModel, options, parallelFor, progress, releaseEdgeGeometry);
    }
    // What the other processes do not need, before the parts are made (the edge geometry
    // already, unless the refinement read it).
    Release(whole.Neighbors);
    releaseEdgeGeometry();
  }
  PartitionResult result = ResultOfShare(group.ScatterFromFirst([&](int process) {
    return PartOfProcess(wholeResult, whole.HaloProblem, whole.Order.Index[static_cast<std::size_t>(process)]);
  }),
    share);
  if (group.Rank() == 0 && !result.Aborted)
  {
    result.Histogram = std::move(wholeResult.Histogram);
    result.Timings = wholeResult.Timings;
  }
  return result;
}

} // namespace shapediameter
