// SPDX-License-Identifier: BSD-3-Clause
#include "Partition/DistributedPartition.h"

#include "GatheredOrder.h"
#include "Mesh/FaceGraph.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
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
    view.FaceCount = this->Areas.size();
    return view;
  }
};

/// Per-face values of the used rows, in the whole graph's order.
std::vector<double> WholeFaceField(const std::vector<std::vector<double>>& processValues, const WholeGraph& whole)
{
  std::vector<double> field(whole.Order.Ids.size(), 0.0);
  for (std::size_t p = 0; p < processValues.size(); ++p)
  {
    for (std::size_t i = 0; i < processValues[p].size(); ++i)
    {
      if (whole.Order.Used[p][i])
      {
        field[static_cast<std::size_t>(whole.Order.Index[p][i])] = processValues[p][i];
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

/// Step 2 of the header, the topology: every process's ids, values, areas, open sides and
/// neighbours to the first process, assembled there (the order, the faces' values and areas,
/// the CSR of neighbours; the halo checks). Returns every process's degrees on the first (the
/// geometry's layout), nothing elsewhere. Each gathered field is freed once converted.
std::vector<std::vector<double>> GatherTopology(const OwnRows& rows, const ProcessGroup& group, WholeGraph& whole)
{
  const bool first = group.Rank() == 0;
  if (first)
  {
    whole.Order = OrderGatheredIds(group.GatherOnFirst(rows.Ids));
    whole.Values = WholeFaceField(group.GatherOnFirst(rows.Values), whole);
    whole.Areas = WholeFaceField(group.GatherOnFirst(rows.Areas), whole);
  }
  else
  {
    for (const std::vector<double>* field : { &rows.Ids, &rows.Values, &rows.Areas })
    {
      group.GatherOnFirst(*field);
    }
  }
  const std::vector<std::vector<double>> openSides = group.GatherOnFirst(rows.OpenSides);
  if (first)
  {
    whole.HaloProblem = CheckOpenSides(openSides);
  }
  std::vector<std::vector<double>> degrees = group.GatherOnFirst(rows.Degrees);
  if (!first)
  {
    group.GatherOnFirst(rows.Neighbors);
    return degrees;
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
  whole.Order.IndexOfId = {};
  if (whole.HaloProblem.empty())
  {
    whole.HaloProblem = CheckSymmetric(whole);
  }
  return degrees;
}

/// The rest of step 2 when the first process partitions the whole graph: the normal angles,
/// edge lengths and concave flags of every adjacency.
void GatherGeometry(const OwnRows& rows, const std::vector<std::vector<double>>& degrees, const ProcessGroup& group,
  WholeGraph& whole)
{
  if (group.Rank() != 0)
  {
    for (const std::vector<double>* field : { &rows.NormalAngles, &rows.EdgeLengths, &rows.Concave })
    {
      group.GatherOnFirst(*field);
    }
    return;
  }
  const auto same = [](double value) { return value; };
  whole.NormalAngles = WholeEntryField<double>(group.GatherOnFirst(rows.NormalAngles), degrees, whole, same);
  whole.EdgeLengths = WholeEntryField<double>(group.GatherOnFirst(rows.EdgeLengths), degrees, whole, same);
  whole.Concave = WholeEntryField<std::uint8_t>(group.GatherOnFirst(rows.Concave), degrees, whole,
    [](double value) { return static_cast<std::uint8_t>(value != 0.0); });
}

/// What the first process tells the others, as the first value of a message.
enum PartStatus : int
{
  Partitioned = 0,
  Aborted = 1,
  HaloTooNarrow = 2,
  /// The first process partitions the whole graph (the refinement, or a surface without
  /// area): every process sends it the edge geometry as well.
  GatherEdgeGeometry = 3,
  /// With the model and the whole surface's area that follow, every process computes its own
  /// faces' energy; the first process cuts, reading their data costs as it needs them.
  CutOverProcesses = 4,
  /// A request, during the cut, for the data costs of some of the process's own faces.
  CostRows = 5
};

/// A problem every process reports, as a message.
std::vector<double> ProblemMessage(const std::string& problem)
{
  std::vector<double> part{ HaloTooNarrow };
  part.insert(part.end(), problem.begin(), problem.end());
  return part;
}

void AppendModel(const GaussianMixtureModel& model, std::vector<double>& part)
{
  part.push_back(static_cast<double>(model.ComponentCount()));
  part.insert(part.end(), model.Means.begin(), model.Means.end());
  part.insert(part.end(), model.Sigmas.begin(), model.Sigmas.end());
  part.insert(part.end(), model.Weights.begin(), model.Weights.end());
}

/// Reads what AppendModel wrote at `at`, and moves `at` past it.
GaussianMixtureModel ReadModel(const std::vector<double>& part, std::size_t& at)
{
  const auto k = static_cast<std::size_t>(part.at(at++));
  const auto read = [&]() {
    if (at + k > part.size())
    {
      throw Error("partition: a truncated message from the first process");
    }
    std::vector<double> values(part.begin() + static_cast<std::ptrdiff_t>(at), part.begin() + static_cast<std::ptrdiff_t>(at + k));
    at += k;
    return values;
  };
  GaussianMixtureModel model;
  model.Means = read();
  model.Sigmas = read();
  model.Weights = read();
  return model;
}

/// What every process gets back (step 4 of the header), as doubles: the whole-surface part,
/// then per own face of `process` its probabilities (unless the process computed them), band,
/// fine label and segment.
std::vector<double> PartOfProcess(
  const PartitionResult& result, const WholeGraph& whole, std::size_t process, bool withProbabilities)
{
  if (!whole.HaloProblem.empty())
  {
    return ProblemMessage(whole.HaloProblem);
  }
  if (result.Aborted)
  {
    return { Aborted };
  }
  const GaussianMixtureModel& model = result.Model;
  std::vector<double> part{ Partitioned };
  AppendModel(model, part);
  part.push_back(result.Energy);
  part.push_back(static_cast<double>(result.CutMoves));
  part.push_back(static_cast<double>(result.LabelBands.size()));
  part.insert(part.end(), result.LabelBands.begin(), result.LabelBands.end());
  part.push_back(static_cast<double>(result.Segments.Area.size()));
  part.insert(part.end(), result.Segments.Area.begin(), result.Segments.Area.end());
  part.insert(part.end(), result.Segments.Label.begin(), result.Segments.Label.end());
  const auto k = static_cast<Eigen::Index>(model.ComponentCount());
  for (const std::int64_t face : whole.Order.Index[process])
  {
    const auto f = static_cast<std::size_t>(face);
    for (Eigen::Index c = 0; withProbabilities && c < k; ++c)
    {
      part.push_back(result.Probabilities(static_cast<Eigen::Index>(face), c));
    }
    part.push_back(result.Bands[f]);
    part.push_back(result.Labels[f]);
    part.push_back(result.Segments.Segment[f]);
  }
  return part;
}

/// Throws the problem a HaloTooNarrow message carries.
[[noreturn]] void ThrowProblem(const std::vector<double>& part)
{
  std::string problem;
  for (std::size_t i = 1; i < part.size(); ++i)
  {
    problem += static_cast<char>(part[i]);
  }
  throw HaloTooNarrowError(problem); // on every process
}

/// Reads PartOfProcess on the process it was sent to: the result over the share's faces.
/// `probabilities`: the share's own posteriors when the part does not carry them.
PartitionResult ResultOfShare(const std::vector<double>& part, const PartitionShare& share,
  PosteriorMatrix* probabilities = nullptr)
{
  PartitionResult result;
  if (!part.empty() && part[0] == HaloTooNarrow)
  {
    ThrowProblem(part);
  }
  if (part.empty() || part[0] != Partitioned)
  {
    result.Aborted = true;
    return result;
  }
  std::size_t at = 1;
  const auto next = [&]() { return part.at(at++); };
  const auto read = [&](std::size_t count) {
    std::vector<double> values(part.begin() + static_cast<std::ptrdiff_t>(at),
      part.begin() + static_cast<std::ptrdiff_t>(at + count));
    at += count;
    return values;
  };
  result.Model = ReadModel(part, at);
  const std::size_t k = result.Model.Means.size();
  result.Energy = next();
  result.CutMoves = static_cast<int>(next());
  const std::vector<double> labelBands = read(static_cast<std::size_t>(next()));
  result.LabelBands.assign(labelBands.begin(), labelBands.end());
  const auto segments = static_cast<std::size_t>(next());
  result.Segments.Area = read(segments);
  const std::vector<double> segmentLabels = read(segments);
  result.Segments.Label.assign(segmentLabels.begin(), segmentLabels.end());

  const std::size_t faces = share.Own.size();
  if (probabilities)
  {
    result.Probabilities = std::move(*probabilities);
  }
  else
  {
    result.Probabilities = PosteriorMatrix::Zero(static_cast<Eigen::Index>(faces), static_cast<Eigen::Index>(k));
  }
  result.Bands.assign(faces, -1);
  result.Labels.assign(faces, -1);
  result.Segments.Segment.assign(faces, -1);
  for (std::size_t f = 0; f < faces; ++f)
  {
    if (!share.Own[f])
    {
      if (probabilities)
      {
        result.Probabilities.row(static_cast<Eigen::Index>(f)).setZero();
      }
      continue;
    }
    for (std::size_t c = 0; !probabilities && c < k; ++c)
    {
      result.Probabilities(static_cast<Eigen::Index>(f), static_cast<Eigen::Index>(c)) = next();
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

/// A process's own faces' part of the whole surface's energy (CutOverProcesses).
struct OwnEnergy
{
  /// Per own face, in the share's order: its data costs (k each).
  std::vector<double> Costs;
  /// Per own face, in the share's order, per adjacency to a face after it (a pair it is the
  /// lower face of), in the row's order: the pair's weight.
  std::vector<double> PairWeights;
  /// The share's posteriors (the result's probabilities).
  PosteriorMatrix Posteriors;
  std::size_t LabelCount = 0;
};

OwnEnergy EnergyOfOwnFaces(const PartitionInput& input, const FaceGraph& graph, const PartitionShare& share,
  const GaussianMixtureModel& model, const WholeSurfaceArea& wholeArea, const PartitionOptions& options,
  const ParallelFor& parallelFor)
{
  const DualGraphView view = MakeDualGraphView(graph);
  ValidateDualGraph(view, options.Energy.GeometricWeights, parallelFor);
  OwnEnergy own;
  own.Posteriors = ComputePosteriors(model, input.FaceValues, parallelFor);
  const PartitionEnergy energy = BuildPartitionEnergyOfPart(own.Posteriors, view, wholeArea, options.Energy, parallelFor);
  own.LabelCount = static_cast<std::size_t>(energy.LabelCount);
  for (std::size_t f = 0; f < energy.FaceCount; ++f)
  {
    if (share.Own[f])
    {
      own.Costs.insert(own.Costs.end(), energy.DataCosts.begin() + static_cast<std::ptrdiff_t>(f * own.LabelCount),
        energy.DataCosts.begin() + static_cast<std::ptrdiff_t>((f + 1) * own.LabelCount));
    }
  }
  for (std::size_t p = 0; p < energy.PairWeight.size(); ++p)
  {
    if (share.Own[static_cast<std::size_t>(energy.PairFirst[p])])
    {
      own.PairWeights.push_back(energy.PairWeight[p]);
    }
  }
  return own;
}

/// The rows a CostRows request asks for: [CostRows, position, ...] -> the positions' costs.
std::vector<double> RequestedRows(const OwnEnergy& own, const std::vector<double>& request)
{
  std::vector<double> rows;
  rows.reserve((request.size() - 1) * own.LabelCount);
  for (std::size_t i = 1; i < request.size(); ++i)
  {
    const auto at = static_cast<std::size_t>(request[i]) * own.LabelCount;
    if (at + own.LabelCount > own.Costs.size())
    {
      throw Error("partition: the data costs of a face this process does not own were requested");
    }
    rows.insert(rows.end(), own.Costs.begin() + static_cast<std::ptrdiff_t>(at),
      own.Costs.begin() + static_cast<std::ptrdiff_t>(at + own.LabelCount));
  }
  return rows;
}

/// On the processes other than the first, during the cut: answers its CostRows requests until
/// it sends something else, which is returned (the result).
std::vector<double> ServeCostRows(const OwnEnergy& own, const ProcessGroup& group)
{
  for (;;)
  {
    std::vector<double> message = group.ScatterFromFirst([](int) { return std::vector<double>{}; });
    if (message.empty() || message[0] != CostRows)
    {
      return message;
    }
    group.GatherOnFirst(RequestedRows(own, message));
  }
}

/// On the first process: the data costs of the whole surface's faces, asked of the processes
/// that own them, at most Range faces at a time (the cut's DataCostSource).
class CostsOverProcesses final : public DataCostSource
{
public:
  CostsOverProcesses(const WholeGraph& whole, const OwnEnergy& own, const ProcessGroup& group)
    : Own(own)
    , Group(group)
    , Processes(whole.Order.Index.size())
    // A quarter of the faces at a time (each range is a round trip to every process), at most
    // 2^17 (5 MB of costs at k = 5, and as much again while they are assembled).
    , Range(std::clamp<std::size_t>(whole.Order.Ids.size() / 4, 256, std::size_t{ 1 } << 17))
    , Owner(whole.Order.Ids.size(), 0)
    , Position(whole.Order.Ids.size(), 0)
  {
    for (std::size_t p = 0; p < whole.Order.Index.size(); ++p)
    {
      for (std::size_t i = 0; i < whole.Order.Index[p].size(); ++i)
      {
        if (whole.Order.Used[p][i])
        {
          const auto w = static_cast<std::size_t>(whole.Order.Index[p][i]);
          this->Owner[w] = static_cast<std::uint32_t>(p);
          this->Position[w] = static_cast<std::uint32_t>(i);
        }
      }
    }
  }

  void VisitInOrder(const std::function<void(std::size_t, const std::vector<double>&)>& visit) const override
  {
    std::vector<std::size_t> faces;
    for (std::size_t first = 0; first < this->Owner.size(); first += this->Range)
    {
      faces.resize(std::min(this->Range, this->Owner.size() - first));
      std::iota(faces.begin(), faces.end(), first);
      visit(first, this->Rows(faces));
    }
  }

  std::vector<double> Rows(const std::vector<std::size_t>& faces) const override
  {
    const std::size_t processes = this->Processes;
    std::vector<std::vector<double>> requests(processes, std::vector<double>{ CostRows });
    for (const std::size_t w : faces)
    {
      requests[this->Owner[w]].push_back(this->Position[w]);
    }
    const std::vector<double> mine = this->Group.ScatterFromFirst([&](int process) {
      return std::move(requests[static_cast<std::size_t>(process)]);
    });
    const std::vector<std::vector<double>> replies = this->Group.GatherOnFirst(RequestedRows(this->Own, mine));
    const std::size_t k = this->Own.LabelCount;
    std::vector<std::size_t> next(processes, 0);
    std::vector<double> rows;
    rows.reserve(faces.size() * k);
    for (const std::size_t w : faces)
    {
      const std::size_t p = this->Owner[w];
      const std::size_t at = next[p]++ * k;
      if (at + k > replies[p].size())
      {
        throw Error("partition: a process sent fewer data costs than asked");
      }
      rows.insert(rows.end(), replies[p].begin() + static_cast<std::ptrdiff_t>(at),
        replies[p].begin() + static_cast<std::ptrdiff_t>(at + k));
    }
    return rows;
  }

private:
  const OwnEnergy& Own;
  const ProcessGroup& Group;
  std::size_t Processes;
  std::size_t Range;
  /// Per face of the whole surface: the process whose copy is used, and the copy's place among
  /// that process's own faces.
  std::vector<std::uint32_t> Owner;
  std::vector<std::uint32_t> Position;
};

/// On the first process: the whole surface's pairs (PartitionEnergy without data costs) in the
/// serial order (by lower face, then by its row), with the weights every process computed.
PartitionEnergy PairsOfWholeSurface(
  const WholeGraph& whole, const std::vector<std::vector<double>>& processWeights, int labelCount)
{
  const std::size_t n = whole.Order.Ids.size();
  const auto higher = [&](std::size_t w) {
    std::size_t count = 0;
    for (auto e = whole.Offsets[w]; e < whole.Offsets[w + 1]; ++e)
    {
      count += whole.Neighbors[static_cast<std::size_t>(e)] > static_cast<std::int64_t>(w) ? 1 : 0;
    }
    return count;
  };
  // Where each used row's weights start in its process's list.
  std::vector<std::size_t> start(n, 0);
  for (std::size_t p = 0; p < whole.Order.Index.size(); ++p)
  {
    std::size_t at = 0;
    for (std::size_t i = 0; i < whole.Order.Index[p].size(); ++i)
    {
      const auto w = static_cast<std::size_t>(whole.Order.Index[p][i]);
      if (whole.Order.Used[p][i])
      {
        start[w] = at;
      }
      at += higher(w);
    }
    if (at != processWeights[p].size())
    {
      throw Error("partition: process " + std::to_string(p) + " sent " + std::to_string(processWeights[p].size()) +
        " pair weights for " + std::to_string(at) + " pairs");
    }
  }
  std::vector<std::uint32_t> owner(n, 0);
  for (std::size_t p = 0; p < whole.Order.Index.size(); ++p)
  {
    for (std::size_t i = 0; i < whole.Order.Index[p].size(); ++i)
    {
      if (whole.Order.Used[p][i])
      {
        owner[static_cast<std::size_t>(whole.Order.Index[p][i])] = static_cast<std::uint32_t>(p);
      }
    }
  }
  PartitionEnergy pairs;
  pairs.FaceCount = n;
  pairs.LabelCount = labelCount;
  for (std::size_t w = 0; w < n; ++w)
  {
    const std::vector<double>& weights = processWeights[owner[w]];
    std::size_t at = start[w];
    for (auto e = whole.Offsets[w]; e < whole.Offsets[w + 1]; ++e)
    {
      const std::int64_t g = whole.Neighbors[static_cast<std::size_t>(e)];
      if (g > static_cast<std::int64_t>(w))
      {
        pairs.PairFirst.push_back(static_cast<std::int64_t>(w));
        pairs.PairSecond.push_back(g);
        pairs.PairWeight.push_back(weights[at++]);
      }
    }
  }
  return pairs;
}

using Clock = std::chrono::steady_clock;

double Lap(Clock::time_point& start)
{
  const Clock::time_point now = Clock::now();
  const double ms = std::chrono::duration<double, std::milli>(now - start).count();
  start = now;
  return ms;
}

/// The CutOverProcesses path on the first process once every process has its own energy: the
/// pairs assembled, the cut (reading the processes' data costs), the hierarchy and the
/// segments. `result` holds the model and the histogram already.
void CutOnFirstProcess(WholeGraph& whole, const OwnEnergy& own, const std::vector<std::vector<double>>& weights,
  const ProcessGroup& group, const PartitionOptions& options, const ParallelFor& parallelFor,
  const ProgressCallback& progress, PartitionResult& result)
{
  Clock::time_point start = Clock::now();
  std::optional<PartitionEnergy> pairs =
    PairsOfWholeSurface(whole, weights, static_cast<int>(result.Model.ComponentCount()));
  result.Timings.EnergyMs += Lap(start);
  if (progress && !progress(0.2))
  {
    result.Aborted = true;
    return;
  }
  AlphaExpansionResult cut = MinimizeMultilevel(*pairs, CostsOverProcesses(whole, own, group), options.Multilevel,
    options.AlphaExpansion, SubProgress(progress, 0.2, 0.95), parallelFor);
  pairs.reset();
  result.Timings.CutMs = Lap(start);
  if (cut.Aborted)
  {
    result.Aborted = true;
    return;
  }
  result.Energy = cut.Energy;
  result.CutMoves = cut.Moves;
  result.Bands = std::move(cut.Labels);
  DualGraphView view;
  view.Offsets = whole.Offsets.data();
  view.Neighbors = whole.Neighbors.data();
  view.FaceCount = whole.Order.Ids.size();
  result.Segments = FindConnectedSegmentsOnValidGraph(view, result.Bands, whole.Areas);
  result.Labels = result.Bands;
  for (int band = 0; band < result.Model.ComponentCount(); ++band)
  {
    result.LabelBands.push_back(band);
  }
  result.Timings.SegmentsMs = Lap(start);
}

/// The first process's decision once it holds the whole graph's topology, values and areas: a
/// problem to report, the whole graph partitioned there (GatherEdgeGeometry), or the cut over
/// the processes, with the model and the whole surface's area (CutOverProcesses; `result`
/// receives the model and the histogram).
std::vector<double> DecideOnFirstProcess(WholeGraph& whole, const GaussianMixtureModel* familyModel,
  const PartitionOptions& options, const ProgressCallback& progress, PartitionResult& result)
{
  if (!whole.HaloProblem.empty())
  {
    return ProblemMessage(whole.HaloProblem);
  }
  if (progress && !progress(0.1))
  {
    return { Aborted };
  }
  const double totalArea = std::accumulate(whole.Areas.begin(), whole.Areas.end(), 0.0);
  if (options.Refinement.Enabled || (options.Energy.GeometricWeights && !(totalArea > 0.0 && std::isfinite(totalArea))))
  {
    return { GatherEdgeGeometry };
  }
  Clock::time_point start = Clock::now();
  const Eigen::Map<const Eigen::VectorXd> values(whole.Values.data(), static_cast<Eigen::Index>(whole.Values.size()));
  result.Model = familyModel ? *familyModel : FitClusterModel(values, whole.Areas, options);
  result.Timings.ClusterModelMs = Lap(start);
  result.Histogram = MixtureHistogram(result.Model, values, options.HistogramBins);
  result.Timings.HistogramMs = Lap(start);
  whole.Values = {};
  std::vector<double> message{ CutOverProcesses, totalArea, static_cast<double>(whole.Areas.size()) };
  AppendModel(result.Model, message);
  return message;
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
  const ProcessGroup& group = share.Group;
  const bool first = group.Rank() == 0;
  std::optional<FaceGraph> graph = BuildFaceGraph(input.Points, input.FaceOffsets, input.FaceConnectivity, parallelFor);
  std::optional<OwnRows> rows = RowsOfOwnFaces(input, *graph, share);
  WholeGraph whole;
  const std::vector<std::vector<double>> degrees = GatherTopology(*rows, group, whole);

  PartitionResult wholeResult;
  const std::vector<double> firstDecision =
    first ? DecideOnFirstProcess(whole, input.FamilyModel, options, progress, wholeResult) : std::vector<double>{};
  const std::vector<double> decision = group.ScatterFromFirst([&](int) { return firstDecision; });
  const int status = decision.empty() ? Aborted : static_cast<int>(decision[0]);
  if (status == HaloTooNarrow)
  {
    ThrowProblem(decision);
  }
  if (status == Aborted)
  {
    PartitionResult aborted;
    aborted.Aborted = true;
    return aborted;
  }

  if (status == CutOverProcesses)
  {
    // Every process its own faces' energy; the first process cuts, asking for their data costs.
    rows.reset();
    std::size_t at = 3;
    const GaussianMixtureModel model = ReadModel(decision, at);
    const WholeSurfaceArea wholeArea{ decision.at(1), static_cast<std::size_t>(decision.at(2)) };
    Clock::time_point start = Clock::now();
    OwnEnergy own = EnergyOfOwnFaces(input, *graph, share, model, wholeArea, options, parallelFor);
    graph.reset();
    const double energyMs = Lap(start);
    const std::vector<std::vector<double>> weights = group.GatherOnFirst(own.PairWeights);
    own.PairWeights = {};
    std::vector<double> part;
    if (first)
    {
      wholeResult.Timings.EnergyMs = energyMs;
      CutOnFirstProcess(whole, own, weights, group, options, parallelFor, progress, wholeResult);
      part = group.ScatterFromFirst([&](int process) {
        return PartOfProcess(wholeResult, whole, static_cast<std::size_t>(process), false);
      });
    }
    else
    {
      part = ServeCostRows(own, group);
    }
    PartitionResult result = ResultOfShare(part, share, &own.Posteriors);
    if (first && !result.Aborted)
    {
      result.Histogram = std::move(wholeResult.Histogram);
      result.Timings = wholeResult.Timings;
      if (progress)
      {
        progress(1.0);
      }
    }
    return result;
  }

  // The first process partitions the whole graph.
  graph.reset();
  GatherGeometry(*rows, degrees, group, whole);
  rows.reset();
  if (first)
  {
    const auto releaseEdgeGeometry = [&whole] {
      whole.NormalAngles = {};
      whole.EdgeLengths = {};
      whole.Concave = {};
    };
    const Eigen::Map<const Eigen::VectorXd> values(whole.Values.data(), static_cast<Eigen::Index>(whole.Values.size()));
    wholeResult = PartitionOnDualGraph(
      whole.View(), whole.Areas, values, input.FamilyModel, options, parallelFor, progress, releaseEdgeGeometry);
    // What the other processes do not need, before the parts are made (the edge geometry
    // already, unless the refinement read it).
    whole.Neighbors = {};
    releaseEdgeGeometry();
  }
  PartitionResult result = ResultOfShare(group.ScatterFromFirst([&](int process) {
    return PartOfProcess(wholeResult, whole, static_cast<std::size_t>(process), true);
  }),
    share);
  if (first && !result.Aborted)
  {
    result.Histogram = std::move(wholeResult.Histogram);
    result.Timings = wholeResult.Timings;
  }
  return result;
}

} // namespace shapediameter
