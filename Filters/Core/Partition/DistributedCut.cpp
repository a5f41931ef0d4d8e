// SPDX-License-Identifier: BSD-3-Clause
#include "Partition/DistributedCut.h"

#include "ExactSum.h"
#include "Partition/CoarseningCells.h"
#include "Release.h"
#include "UnionFind.h"

#include <algorithm>
#include <array>
#include <limits>
#include <numeric>
#include <string>
#include <tuple>
#include <unordered_map>
#include <unordered_set>
#include <utility>

namespace shapediameter
{
namespace
{

/// A message of doubles, written and read in order.
struct Message
{
  std::vector<double> Values;
  std::size_t At = 0;

  void Put(double value) { Values.push_back(value); }
  void Put(std::uint64_t cell)
  {
    Put(static_cast<double>(cell & 0xffffffffu));
    Put(static_cast<double>(cell >> 32));
  }
  void PutParts(const ExactSum& sum)
  {
    Put(static_cast<double>(sum.Partials().size()));
    Values.insert(Values.end(), sum.Partials().begin(), sum.Partials().end());
  }
  double Next() { return Values.at(At++); }
  std::size_t NextIndex() { return static_cast<std::size_t>(Next()); }
  std::int64_t NextId() { return static_cast<std::int64_t>(Next()); }
  std::uint64_t NextCell()
  {
    const auto low = static_cast<std::uint64_t>(Next());
    return low | (static_cast<std::uint64_t>(Next()) << 32);
  }
  void AddParts(ExactSum& sum)
  {
    const std::size_t count = NextIndex();
    for (std::size_t i = 0; i < count; ++i)
    {
      sum.Add(Next());
    }
  }
  bool Done() const { return At >= Values.size(); }
};

enum Status : int
{
  Proceed = 0,
  DoubleCells = 1,
  NotCoarsened = 2,
  Aborted = 3,
  HaloTooNarrow = 4
};

/// What a process knows of its share beyond CutShare: most probable labels, the halo faces
/// next to own faces and the faces on its piece's border.
struct Local
{
  const CutShare& Share;
  std::size_t K;
  std::vector<int> MostProbable;
  std::vector<std::size_t> OwnFaces;
  std::vector<std::size_t> HaloNeighbors; ///< increasing share index
  std::vector<std::size_t> Boundary;      ///< own faces with a halo neighbour

  explicit Local(const CutShare& share)
    : Share(share)
    , K(static_cast<std::size_t>(share.LabelCount))
    , MostProbable(MostProbableLabels(share.DataCosts.data(), share.GlobalIds.size(), share.LabelCount))
  {
    const std::size_t n = share.GlobalIds.size();
    std::vector<std::uint8_t> isHaloNeighbor(n, 0);
    for (std::size_t f = 0; f < n; ++f)
    {
      if (!share.Own[f])
      {
        continue;
      }
      OwnFaces.push_back(f);
      bool border = false;
      for (std::size_t e = share.Start[f]; e < share.Start[f + 1]; ++e)
      {
        const std::size_t g = share.Neighbor[e];
        if (!share.Own[g])
        {
          border = true;
          isHaloNeighbor[g] = 1;
        }
      }
      if (border)
      {
        Boundary.push_back(f);
      }
    }
    for (std::size_t f = 0; f < n; ++f)
    {
      if (isHaloNeighbor[f])
      {
        HaloNeighbors.push_back(f);
      }
    }
  }

  std::size_t IndexOfId(std::int64_t id) const
  {
    const auto it = std::lower_bound(Share.GlobalIds.begin(), Share.GlobalIds.end(), id);
    if (it == Share.GlobalIds.end() || *it != id)
    {
      throw Error("distributed cut: face " + std::to_string(id) + " is not in this process's share");
    }
    return static_cast<std::size_t>(it - Share.GlobalIds.begin());
  }
};

/// Connected own faces of one most probable label and one cell (GrowClusters over the own
/// faces), numbered by their lowest face: per share face its local cluster (NoCluster for the
/// halo) and the members of each, increasing.
std::pair<std::vector<std::size_t>, std::vector<std::vector<std::size_t>>> LocalClusters(
  const Local& local, const std::vector<std::uint64_t>& cells)
{
  const CutShare& share = local.Share;
  auto [cluster, count] =
    GrowClusters(share.Start.data(), share.Neighbor.data(), local.MostProbable, cells, 0, share.Own.data());
  std::vector<std::vector<std::size_t>> members(count);
  for (const std::size_t f : local.OwnFaces)
  {
    members[cluster[f]].push_back(f);
  }
  return { std::move(cluster), std::move(members) };
}

/// The first process's picture of the clusters: every process's local clusters as nodes,
/// joined across the pieces' borders.
struct ClusterTable
{
  std::vector<std::size_t> Base; ///< per process, its first node
  std::vector<std::int64_t> LowestId;
  std::vector<double> FaceCount;
  std::vector<int> MostProbable;
  std::vector<std::uint64_t> Cell;
  std::unordered_map<std::int64_t, std::size_t> NodeOfBorderFace;
  std::vector<std::vector<std::int64_t>> HaloIds; ///< per process, its halo neighbours' ids
  std::vector<std::size_t> ClusterOfNode;
  std::vector<std::size_t> NodesOfCluster; ///< per cluster, how many nodes
  std::size_t ClusterCount = 0;
  /// An adjacency across the pieces that only one side's process saw (its owner's halo was
  /// too narrow): every process then throws HaloTooNarrowError.
  bool HaloProblem = false;

  /// The nodes of `process`: [Base[process], NodesEnd(process)).
  std::size_t NodesEnd(std::size_t process) const
  {
    return process + 1 < Base.size() ? Base[process + 1] : ClusterOfNode.size();
  }
  int ProcessOfNode(std::size_t node) const
  {
    return static_cast<int>(std::upper_bound(Base.begin(), Base.end(), node) - Base.begin()) - 1;
  }
  std::size_t NodeOfBorder(std::int64_t id) const
  {
    const auto it = NodeOfBorderFace.find(id);
    if (it == NodeOfBorderFace.end())
    {
      throw Error("distributed cut: face " + std::to_string(id) + " is in a halo but on no piece's border");
    }
    return it->second;
  }
};

/// The first process's reply to `process` about its clusters: the status, then, when it is
/// Proceed, two values per local cluster of the process (ofCluster) and one per halo neighbour
/// it sent (ofHaloCluster), each a function of the cluster the face lies in.
template <typename OfCluster, typename OfHaloCluster>
std::vector<double> ReplyAboutClusters(
  const ClusterTable& table, Status status, int process, OfCluster ofCluster, OfHaloCluster ofHaloCluster)
{
  std::vector<double> part{ static_cast<double>(status) };
  if (status != Proceed)
  {
    return part;
  }
  const auto p = static_cast<std::size_t>(process);
  for (std::size_t node = table.Base[p]; node < table.NodesEnd(p); ++node)
  {
    const std::array<double, 2> values = ofCluster(table.ClusterOfNode[node]);
    part.insert(part.end(), values.begin(), values.end());
  }
  for (const std::int64_t id : table.HaloIds[p])
  {
    part.push_back(ofHaloCluster(table.ClusterOfNode[table.NodeOfBorder(id)]));
  }
  return part;
}

ClusterTable JoinClusters(std::vector<std::vector<double>> messages)
{
  ClusterTable table;
  std::vector<std::tuple<std::int64_t, std::int64_t, int>> cross; // (lower id, higher id, +1 / -1: seen from which)
  for (std::vector<double>& values : messages)
  {
    Message message{ std::move(values) };
    const std::size_t base = table.LowestId.size();
    table.Base.push_back(base);
    const std::size_t locals = message.NextIndex();
    for (std::size_t c = 0; c < locals; ++c)
    {
      table.LowestId.push_back(message.NextId());
      table.FaceCount.push_back(message.Next());
      table.MostProbable.push_back(static_cast<int>(message.Next()));
      table.Cell.push_back(message.NextCell());
    }
    const std::size_t borders = message.NextIndex();
    for (std::size_t b = 0; b < borders; ++b)
    {
      const std::int64_t id = message.NextId();
      table.NodeOfBorderFace[id] = base + message.NextIndex();
    }
    std::vector<std::int64_t> halo(message.NextIndex());
    for (std::int64_t& id : halo)
    {
      id = message.NextId();
    }
    table.HaloIds.push_back(std::move(halo));
    const std::size_t crossCount = message.NextIndex();
    for (std::size_t c = 0; c < crossCount; ++c)
    {
      const std::int64_t own = message.NextId();
      const std::int64_t other = message.NextId();
      cross.emplace_back(std::min(own, other), std::max(own, other), own < other ? 1 : -1);
    }
  }
  // Every adjacency across the pieces must be seen from both sides, as many times; its two
  // faces' clusters join when they share a cell and a most probable label (a cluster is one
  // of each).
  std::sort(cross.begin(), cross.end());
  for (std::size_t i = 0; i < cross.size();)
  {
    int balance = 0;
    const auto key = std::make_pair(std::get<0>(cross[i]), std::get<1>(cross[i]));
    for (; i < cross.size() && std::make_pair(std::get<0>(cross[i]), std::get<1>(cross[i])) == key; ++i)
    {
      balance += std::get<2>(cross[i]);
    }
    table.HaloProblem = table.HaloProblem || balance != 0;
  }
  if (table.HaloProblem)
  {
    return table;
  }
  const std::size_t nodes = table.LowestId.size();
  UnionFind components(nodes);
  for (const auto& [low, high, side] : cross)
  {
    const std::size_t a = table.NodeOfBorder(low), b = table.NodeOfBorder(high);
    if (side > 0 && table.MostProbable[a] == table.MostProbable[b] && table.Cell[a] == table.Cell[b])
    {
      components.Unite(static_cast<std::int64_t>(a), static_cast<std::int64_t>(b));
    }
  }
  Release(cross);
  // Clusters numbered by their lowest face id, as the serial cut numbers them by their
  // lowest face.
  std::vector<std::int64_t> lowest(nodes, std::numeric_limits<std::int64_t>::max());
  for (std::size_t node = 0; node < nodes; ++node)
  {
    const auto root = static_cast<std::size_t>(components.Find(static_cast<std::int64_t>(node)));
    lowest[root] = std::min(lowest[root], table.LowestId[node]);
  }
  std::vector<std::size_t> roots;
  for (std::size_t node = 0; node < nodes; ++node)
  {
    if (components.Find(static_cast<std::int64_t>(node)) == static_cast<std::int64_t>(node))
    {
      roots.push_back(node);
    }
  }
  std::sort(roots.begin(), roots.end(), [&](std::size_t a, std::size_t b) { return lowest[a] < lowest[b]; });
  std::vector<std::size_t> clusterOfRoot(nodes, 0);
  for (std::size_t c = 0; c < roots.size(); ++c)
  {
    clusterOfRoot[roots[c]] = c;
  }
  table.ClusterCount = roots.size();
  table.ClusterOfNode.resize(nodes);
  table.NodesOfCluster.assign(roots.size(), 0);
  for (std::size_t node = 0; node < nodes; ++node)
  {
    table.ClusterOfNode[node] = clusterOfRoot[static_cast<std::size_t>(components.Find(static_cast<std::int64_t>(node)))];
    ++table.NodesOfCluster[table.ClusterOfNode[node]];
  }
  return table;
}

/// The coarse energy's data costs from every process's sums per cluster (step 2 of the
/// header): the rounded sum where one process held the whole cluster, else the partial sums.
PartitionEnergy CoarseDataCosts(const ClusterTable& table, std::size_t k, std::vector<std::vector<double>> messages)
{
  PartitionEnergy coarse;
  coarse.FaceCount = table.ClusterCount;
  coarse.LabelCount = static_cast<int>(k);
  coarse.DataCosts.assign(table.ClusterCount * k, 0.0);
  std::unordered_map<std::size_t, std::vector<ExactSum>> spanning;
  for (std::vector<double>& values : messages)
  {
    Message message{ std::move(values) };
    while (!message.Done())
    {
      const std::size_t c = message.NextIndex();
      if (message.Next() == 0.0)
      {
        for (std::size_t l = 0; l < k; ++l)
        {
          coarse.DataCosts[c * k + l] = message.Next();
        }
        continue;
      }
      std::vector<ExactSum>& sums = spanning[c];
      sums.resize(k);
      for (std::size_t l = 0; l < k; ++l)
      {
        message.AddParts(sums[l]);
      }
    }
  }
  for (const auto& [c, sums] : spanning)
  {
    for (std::size_t l = 0; l < k; ++l)
    {
      coarse.DataCosts[c * k + l] = sums[l].Rounded();
    }
  }
  return coarse;
}

/// The coarse energy's pairs from every process's partial sums per pair of clusters, each
/// process's list ordered by (a, b): merged in that order, as the serial CoarseEnergy lists them.
void AddCoarsePairs(PartitionEnergy& coarse, std::vector<std::vector<double>> messages)
{
  std::vector<Message> lists;
  for (std::vector<double>& values : messages)
  {
    lists.push_back(Message{ std::move(values) });
  }
  const auto key = [](const Message& list) {
    return std::make_pair(static_cast<std::size_t>(list.Values[list.At]), static_cast<std::size_t>(list.Values[list.At + 1]));
  };
  for (;;)
  {
    const Message* lowest = nullptr;
    for (const Message& list : lists)
    {
      if (!list.Done() && (!lowest || key(list) < key(*lowest)))
      {
        lowest = &list;
      }
    }
    if (!lowest)
    {
      return;
    }
    const auto [a, b] = key(*lowest);
    ExactSum sum;
    for (Message& list : lists)
    {
      if (!list.Done() && key(list) == std::make_pair(a, b))
      {
        list.At += 2;
        list.AddParts(sum);
      }
    }
    coarse.PairFirst.push_back(static_cast<std::int64_t>(a));
    coarse.PairSecond.push_back(static_cast<std::int64_t>(b));
    coarse.PairWeight.push_back(sum.Rounded());
  }
}

/// Sends lists of global ids to the processes that own them (through the first process, which
/// knows the owners of the border faces): every process gets the ids sent to it.
std::vector<std::int64_t> RouteToOwners(const std::vector<std::int64_t>& ids, const ProcessGroup& group, const ClusterTable* table)
{
  const std::vector<std::vector<double>> sent = group.GatherOnFirst(std::vector<double>(ids.begin(), ids.end()));
  std::vector<std::vector<double>> byOwner;
  if (group.Rank() == 0)
  {
    byOwner.resize(table->Base.size());
    for (const std::vector<double>& list : sent)
    {
      for (const double id : list)
      {
        byOwner[static_cast<std::size_t>(table->ProcessOfNode(table->NodeOfBorder(static_cast<std::int64_t>(id))))].push_back(id);
      }
    }
  }
  const std::vector<double> mine =
    group.ScatterFromFirst([&](int process) { return std::move(byOwner[static_cast<std::size_t>(process)]); });
  return std::vector<std::int64_t>(mine.begin(), mine.end());
}

/// A band face's row of the sub-energy (BandEnergy of MultilevelCut.cpp): its data costs with
/// the fixed neighbours' terms, and its pairs with higher band faces, in adjacency order.
void PutBandRow(const Local& local, std::size_t f, const std::vector<int>& labels, const std::vector<std::uint8_t>& inBand,
  Message& message)
{
  const CutShare& share = local.Share;
  const std::size_t k = local.K;
  std::vector<double> costs(share.DataCosts.begin() + static_cast<std::ptrdiff_t>(f * k),
    share.DataCosts.begin() + static_cast<std::ptrdiff_t>((f + 1) * k));
  std::vector<std::pair<std::int64_t, double>> up;
  for (std::size_t e = share.Start[f]; e < share.Start[f + 1]; ++e)
  {
    const std::size_t g = share.Neighbor[e];
    const double w = share.Weight[e];
    if (!inBand[g])
    {
      for (std::size_t l = 0; l < k; ++l)
      {
        costs[l] += static_cast<int>(l) != labels[g] ? w : 0.0;
      }
    }
    else if (g > f)
    {
      up.emplace_back(share.GlobalIds[g], w);
    }
  }
  message.Put(static_cast<double>(share.GlobalIds[f]));
  message.Put(static_cast<double>(labels[f]));
  for (const double cost : costs)
  {
    message.Put(cost);
  }
  message.Put(static_cast<double>(up.size()));
  for (const auto& [id, w] : up)
  {
    message.Put(static_cast<double>(id));
    message.Put(w);
  }
}

/// Every process: the band components sent to it (problemsOf in SolveBand), each solved as
/// MultilevelCut solves a band component; the first process gets every process's results
/// (per component: moves, aborted, labels). Progress and abort: the first process's components.
std::vector<std::vector<double>> SolveBandProblems(const std::vector<double>& problems, std::size_t k,
  const ProcessGroup& group, const AlphaExpansionOptions& options, const ProgressCallback& progress,
  const ParallelFor& parallelFor)
{
  std::vector<PartitionEnergy> parts;
  std::vector<std::vector<int>> initial;
  Message message{ problems };
  std::size_t total = 0;
  while (!message.Done())
  {
    PartitionEnergy part;
    part.FaceCount = message.NextIndex();
    part.LabelCount = static_cast<int>(k);
    const std::size_t pairCount = message.NextIndex();
    part.DataCosts.resize(part.FaceCount * k);
    for (double& cost : part.DataCosts)
    {
      cost = message.Next();
    }
    std::vector<int> labels(part.FaceCount);
    for (int& label : labels)
    {
      label = static_cast<int>(message.Next());
    }
    for (std::size_t q = 0; q < pairCount; ++q)
    {
      part.PairFirst.push_back(static_cast<std::int64_t>(message.Next()));
      part.PairSecond.push_back(static_cast<std::int64_t>(message.Next()));
      part.PairWeight.push_back(message.Next());
    }
    total += part.FaceCount;
    parts.push_back(std::move(part));
    initial.push_back(std::move(labels));
  }
  std::vector<AlphaExpansionResult> solved(parts.size());
  SharedProgress bandProgress(group.Rank() == 0 ? SubProgress(progress, 0.5, 1.0) : nullptr, total);
  parallelFor(parts.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t c = begin; c < end; ++c)
    {
      solved[c] = MinimizeByAlphaExpansion(parts[c], initial[c], options, bandProgress.ForPart(parts[c].FaceCount));
    }
  });
  Message results;
  for (const AlphaExpansionResult& result : solved)
  {
    results.Put(static_cast<double>(result.Moves));
    results.Put(result.Aborted ? 1.0 : 0.0);
    for (const int label : result.Labels)
    {
      results.Put(static_cast<double>(label));
    }
  }
  return group.GatherOnFirst(results.Values);
}

/// Every process calls it; the first passes every band face's row. Each connected component of
/// the band is solved as MultilevelCut solves it, on one of the processes (SolveBandProblems).
/// On the first process: per process the labels of the band faces it sent, then of its halo
/// neighbours in the band (-1: not in the band).
struct BandSolution
{
  bool Aborted = false;
  int Moves = 0;
  std::vector<std::vector<double>> Parts;
};

BandSolution SolveBand(std::vector<std::vector<double>> messages, const ClusterTable& table, std::size_t k,
  const ProcessGroup& group, const AlphaExpansionOptions& options, const ProgressCallback& progress,
  const ParallelFor& parallelFor)
{
  struct Row
  {
    std::int64_t id;
    int label;
    std::size_t costs; ///< index into costs
    std::size_t upBegin, upEnd;
    std::size_t process;
  };
  std::vector<Row> rows;
  std::vector<double> costs;
  std::vector<std::pair<std::int64_t, double>> ups;
  for (std::size_t p = 0; p < messages.size(); ++p)
  {
    Message message{ std::move(messages[p]) };
    while (!message.Done())
    {
      Row row{};
      row.id = message.NextId();
      row.label = static_cast<int>(message.Next());
      row.costs = costs.size();
      for (std::size_t l = 0; l < k; ++l)
      {
        costs.push_back(message.Next());
      }
      const std::size_t upCount = message.NextIndex();
      row.upBegin = ups.size();
      for (std::size_t u = 0; u < upCount; ++u)
      {
        const std::int64_t id = message.NextId();
        ups.emplace_back(id, message.Next());
      }
      row.upEnd = ups.size();
      row.process = p;
      rows.push_back(row);
    }
  }
  // Band faces in increasing id; each process sent its own in that order.
  std::vector<std::size_t> order(rows.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return rows[a].id < rows[b].id; });
  std::vector<std::int64_t> ids(rows.size());
  for (std::size_t i = 0; i < order.size(); ++i)
  {
    ids[i] = rows[order[i]].id;
  }
  const auto indexOf = [&](std::int64_t id) {
    const auto it = std::lower_bound(ids.begin(), ids.end(), id);
    if (it == ids.end() || *it != id)
    {
      throw Error("distributed cut: band face " + std::to_string(id) + " was sent by no process");
    }
    return static_cast<std::size_t>(it - ids.begin());
  };
  UnionFind components(rows.size());
  for (std::size_t i = 0; i < order.size(); ++i)
  {
    const Row& row = rows[order[i]];
    for (std::size_t u = row.upBegin; u < row.upEnd; ++u)
    {
      components.Unite(static_cast<std::int64_t>(i), static_cast<std::int64_t>(indexOf(ups[u].first)));
    }
  }
  // Components ordered by their lowest face, their faces increasing (as BandComponents).
  std::vector<std::vector<std::size_t>> faces;
  std::vector<std::size_t> componentOfRoot(rows.size(), static_cast<std::size_t>(-1));
  for (std::size_t i = 0; i < order.size(); ++i)
  {
    const auto root = static_cast<std::size_t>(components.Find(static_cast<std::int64_t>(i)));
    if (componentOfRoot[root] == static_cast<std::size_t>(-1))
    {
      componentOfRoot[root] = faces.size();
      faces.emplace_back();
    }
    faces[componentOfRoot[root]].push_back(i);
  }
  // Each component to one process, the largest first to the least loaded (deterministic; the
  // same labels whoever solves it): [faces, pairs, data costs, labels, pairs (a, b, weight)].
  std::vector<std::vector<std::size_t>> assigned(messages.size());
  {
    std::vector<std::size_t> bySize(faces.size());
    std::iota(bySize.begin(), bySize.end(), 0);
    std::stable_sort(bySize.begin(), bySize.end(),
      [&](std::size_t a, std::size_t b) { return faces[a].size() > faces[b].size(); });
    std::vector<std::size_t> load(messages.size(), 0);
    for (const std::size_t c : bySize)
    {
      const auto p = static_cast<std::size_t>(std::min_element(load.begin(), load.end()) - load.begin());
      assigned[p].push_back(c);
      load[p] += faces[c].size();
    }
  }
  const auto problemsOf = [&](int process) {
    Message problems;
    for (const std::size_t c : assigned[static_cast<std::size_t>(process)])
    {
      const std::vector<std::size_t>& members = faces[c];
      std::vector<double> pairs;
      for (std::size_t b = 0; b < members.size(); ++b)
      {
        const Row& row = rows[order[members[b]]];
        for (std::size_t u = row.upBegin; u < row.upEnd; ++u)
        {
          pairs.push_back(static_cast<double>(b));
          pairs.push_back(static_cast<double>(
            std::lower_bound(members.begin(), members.end(), indexOf(ups[u].first)) - members.begin()));
          pairs.push_back(ups[u].second);
        }
      }
      problems.Put(static_cast<double>(members.size()));
      problems.Put(static_cast<double>(pairs.size() / 3));
      for (const std::size_t member : members)
      {
        const Row& row = rows[order[member]];
        problems.Values.insert(problems.Values.end(), costs.begin() + static_cast<std::ptrdiff_t>(row.costs),
          costs.begin() + static_cast<std::ptrdiff_t>(row.costs + k));
      }
      for (const std::size_t member : members)
      {
        problems.Put(static_cast<double>(rows[order[member]].label));
      }
      problems.Values.insert(problems.Values.end(), pairs.begin(), pairs.end());
    }
    return problems.Values;
  };
  const std::vector<std::vector<double>> results = SolveBandProblems(group.ScatterFromFirst(problemsOf), k, group,
    options, progress, parallelFor);
  std::vector<AlphaExpansionResult> solved(faces.size());
  for (std::size_t p = 0; p < results.size(); ++p)
  {
    Message result{ results[p] };
    for (const std::size_t c : assigned[p])
    {
      solved[c].Moves = static_cast<int>(result.Next());
      solved[c].Aborted = result.Next() != 0.0;
      solved[c].Labels.resize(faces[c].size());
      for (int& label : solved[c].Labels)
      {
        label = static_cast<int>(result.Next());
      }
    }
  }
  BandSolution solution;
  std::vector<int> labelOf(rows.size(), -1); // by position in `ids`
  for (std::size_t c = 0; c < faces.size(); ++c)
  {
    for (std::size_t b = 0; b < faces[c].size(); ++b)
    {
      labelOf[faces[c][b]] = solved[c].Labels[b];
    }
    solution.Moves += solved[c].Moves;
    solution.Aborted = solution.Aborted || solved[c].Aborted;
  }
  solution.Parts.resize(messages.size());
  for (const Row& row : rows) // in the order each process sent them
  {
    solution.Parts[row.process].push_back(labelOf[indexOf(row.id)]);
  }
  for (std::size_t p = 0; p < messages.size(); ++p)
  {
    for (const std::int64_t id : table.HaloIds[p])
    {
      const auto it = std::lower_bound(ids.begin(), ids.end(), id);
      solution.Parts[p].push_back(it != ids.end() && *it == id ? labelOf[static_cast<std::size_t>(it - ids.begin())] : -1);
    }
  }
  return solution;
}

} // namespace

CutOverProcessesResult MinimizeMultilevelOverProcesses(const CutShare& share, const ProcessGroup& group,
  const MultilevelOptions& multilevel, const AlphaExpansionOptions& options, const ProgressCallback& progress,
  const ParallelFor& parallelFor)
{
  const bool first = group.Rank() == 0;
  const Local local(share);
  const std::size_t k = local.K;
  const std::size_t n = share.GlobalIds.size();
  CutOverProcessesResult result;
  std::vector<std::uint64_t> cells(share.Cells);

  // 1. Clusters: local ones, joined across the borders on the first process.
  std::vector<std::size_t> localCluster;
  std::vector<std::vector<std::size_t>> members;
  ClusterTable table;
  Message reply;
  for (int doubling = 0;; ++doubling)
  {
    std::tie(localCluster, members) = LocalClusters(local, cells);
    Message message;
    message.Put(static_cast<double>(members.size()));
    for (const std::vector<std::size_t>& cluster : members)
    {
      message.Put(static_cast<double>(share.GlobalIds[cluster.front()]));
      message.Put(static_cast<double>(cluster.size()));
      message.Put(static_cast<double>(local.MostProbable[cluster.front()]));
      message.Put(cells[cluster.front()]);
    }
    message.Put(static_cast<double>(local.Boundary.size()));
    for (const std::size_t f : local.Boundary)
    {
      message.Put(static_cast<double>(share.GlobalIds[f]));
      message.Put(static_cast<double>(localCluster[f]));
    }
    message.Put(static_cast<double>(local.HaloNeighbors.size()));
    for (const std::size_t g : local.HaloNeighbors)
    {
      message.Put(static_cast<double>(share.GlobalIds[g]));
    }
    std::vector<std::pair<std::int64_t, std::int64_t>> cross;
    for (const std::size_t f : local.Boundary)
    {
      for (std::size_t e = share.Start[f]; e < share.Start[f + 1]; ++e)
      {
        if (!share.Own[share.Neighbor[e]])
        {
          cross.emplace_back(share.GlobalIds[f], share.GlobalIds[share.Neighbor[e]]);
        }
      }
    }
    message.Put(static_cast<double>(cross.size()));
    for (const auto& [own, other] : cross)
    {
      message.Put(static_cast<double>(own));
      message.Put(static_cast<double>(other));
    }
    std::vector<std::vector<double>> gathered = group.GatherOnFirst(message.Values);
    message = Message();
    Status status = Proceed;
    if (first)
    {
      table = JoinClusters(std::move(gathered));
      if (table.HaloProblem)
      {
        status = HaloTooNarrow;
      }
      else if (2 * table.ClusterCount > share.WholeFaceCount)
      {
        status = doubling < MaximumCellDoublings ? DoubleCells : NotCoarsened;
      }
    }
    reply = Message{ group.ScatterFromFirst([&](int process) {
      return ReplyAboutClusters(table, status, process,
        [&](std::size_t c) { return std::array<double, 2>{ static_cast<double>(c), table.NodesOfCluster[c] > 1 ? 1.0 : 0.0 }; },
        [](std::size_t c) { return static_cast<double>(c); });
    }) };
    const auto received = static_cast<Status>(static_cast<int>(reply.Next()));
    if (received == Proceed)
    {
      break;
    }
    if (received == NotCoarsened)
    {
      result.Coarsened = false;
      return result;
    }
    if (received == HaloTooNarrow)
    {
      throw HaloTooNarrowError("partition: two faces on different processes share a side that only one of "
                               "them saw (the halo was too narrow)"); // on every process
    }
    std::transform(cells.begin(), cells.end(), cells.begin(), ParentCell);
  }
  std::vector<std::size_t> clusterOfLocal(members.size());
  std::vector<std::uint8_t> spans(members.size());
  for (std::size_t c = 0; c < members.size(); ++c)
  {
    clusterOfLocal[c] = reply.NextIndex();
    spans[c] = reply.Next() != 0.0 ? 1 : 0;
  }
  constexpr std::size_t none = static_cast<std::size_t>(-1);
  std::vector<std::size_t> cluster(n, none);
  for (const std::size_t f : local.OwnFaces)
  {
    cluster[f] = clusterOfLocal[localCluster[f]];
  }
  for (const std::size_t g : local.HaloNeighbors)
  {
    cluster[g] = reply.NextIndex();
  }

  // 2. Exact partial sums of the coarse energy; the coarse solve on the first process.
  Message costMessage;
  for (std::size_t c = 0; c < members.size(); ++c)
  {
    costMessage.Put(static_cast<double>(clusterOfLocal[c]));
    costMessage.Put(static_cast<double>(spans[c]));
    for (std::size_t l = 0; l < k; ++l)
    {
      ExactSum cost;
      for (const std::size_t f : members[c])
      {
        cost.Add(share.DataCosts[f * k + l]);
      }
      if (spans[c])
      {
        costMessage.PutParts(cost);
      }
      else
      {
        costMessage.Put(cost.Rounded());
      }
    }
  }
  std::vector<std::tuple<std::size_t, std::size_t, double>> links;
  for (const std::size_t f : local.OwnFaces)
  {
    for (std::size_t e = share.Start[f]; e < share.Start[f + 1]; ++e)
    {
      const std::size_t g = share.Neighbor[e];
      if (g > f && cluster[g] != cluster[f]) // each pair once: by the owner of its lower face
      {
        links.emplace_back(std::min(cluster[f], cluster[g]), std::max(cluster[f], cluster[g]), share.Weight[e]);
      }
    }
  }
  std::sort(links.begin(), links.end());
  Message pairMessage;
  for (std::size_t i = 0; i < links.size();)
  {
    const std::size_t a = std::get<0>(links[i]), b = std::get<1>(links[i]);
    ExactSum sum;
    for (; i < links.size() && std::get<0>(links[i]) == a && std::get<1>(links[i]) == b; ++i)
    {
      sum.Add(std::get<2>(links[i]));
    }
    pairMessage.Put(static_cast<double>(a));
    pairMessage.Put(static_cast<double>(b));
    pairMessage.PutParts(sum);
  }
  Release(links);
  PartitionEnergy coarse;
  {
    std::vector<std::vector<double>> costs = group.GatherOnFirst(costMessage.Values);
    costMessage = Message();
    if (first)
    {
      coarse = CoarseDataCosts(table, k, std::move(costs));
    }
  }
  {
    std::vector<std::vector<double>> pairs = group.GatherOnFirst(pairMessage.Values);
    pairMessage = Message();
    if (first)
    {
      AddCoarsePairs(coarse, std::move(pairs));
    }
  }
  Status status = Proceed;
  std::vector<int> coarseLabels;
  std::vector<std::uint8_t> lost;
  if (first)
  {
    std::vector<std::uint64_t> coarseCells(table.ClusterCount);
    std::vector<int> mostProbable(table.ClusterCount);
    for (std::size_t node = 0; node < table.ClusterOfNode.size(); ++node)
    {
      coarseCells[table.ClusterOfNode[node]] = ParentCell(table.Cell[node]);
      mostProbable[table.ClusterOfNode[node]] = table.MostProbable[node];
    }
    const AlphaExpansionResult coarseResult =
      MinimizeMultilevel(coarse, multilevel, options, SubProgress(progress, 0.0, 0.5), parallelFor, coarseCells);
    result.Moves = coarseResult.Moves;
    if (coarseResult.Aborted)
    {
      status = Aborted;
    }
    else
    {
      coarseLabels = coarseResult.Labels;
      std::vector<double> faces(table.ClusterCount, 0.0);
      for (std::size_t node = 0; node < table.ClusterOfNode.size(); ++node)
      {
        faces[table.ClusterOfNode[node]] += table.FaceCount[node];
      }
      lost = LostRegions(coarse, coarseLabels, mostProbable, faces, multilevel.LostRegionFaces);
    }
    coarse = PartitionEnergy();
  }
  reply = Message{ group.ScatterFromFirst([&](int process) {
    return ReplyAboutClusters(table, status, process,
      [&](std::size_t c) { return std::array<double, 2>{ static_cast<double>(coarseLabels[c]), static_cast<double>(lost[c]) }; },
      [&](std::size_t c) { return static_cast<double>(coarseLabels[c]); });
  }) };
  if (static_cast<Status>(static_cast<int>(reply.Next())) == Aborted)
  {
    result.Aborted = true;
    return result;
  }
  std::vector<int> labels(n, -1);
  std::vector<std::uint8_t> inBand(n, 0);
  std::vector<std::size_t> frontier;
  {
    std::vector<std::uint8_t> lostLocal(members.size());
    for (std::size_t c = 0; c < members.size(); ++c)
    {
      const int label = static_cast<int>(reply.Next());
      lostLocal[c] = reply.Next() != 0.0 ? 1 : 0;
      for (const std::size_t f : members[c])
      {
        labels[f] = label;
      }
    }
    for (const std::size_t g : local.HaloNeighbors)
    {
      labels[g] = static_cast<int>(reply.Next());
    }
    // 3. The band: seeds as BoundaryBand's, then ring by ring across the pieces.
    for (const std::size_t f : local.OwnFaces)
    {
      bool seed = lostLocal[localCluster[f]] != 0;
      for (std::size_t e = share.Start[f]; e < share.Start[f + 1] && !seed; ++e)
      {
        seed = labels[share.Neighbor[e]] != labels[f];
      }
      if (seed)
      {
        inBand[f] = 1;
        frontier.push_back(f);
      }
    }
  }
  Release(members);
  Release(localCluster);
  for (int ring = 1; ring < multilevel.BandRings; ++ring)
  {
    std::vector<std::size_t> next;
    std::vector<std::int64_t> reachedHalo;
    for (const std::size_t f : frontier)
    {
      for (std::size_t e = share.Start[f]; e < share.Start[f + 1]; ++e)
      {
        const std::size_t g = share.Neighbor[e];
        if (!inBand[g])
        {
          inBand[g] = 1;
          if (share.Own[g])
          {
            next.push_back(g);
          }
          else
          {
            reachedHalo.push_back(share.GlobalIds[g]);
          }
        }
      }
    }
    for (const std::int64_t id : RouteToOwners(reachedHalo, group, first ? &table : nullptr))
    {
      const std::size_t f = local.IndexOfId(id);
      if (!inBand[f])
      {
        inBand[f] = 1;
        next.push_back(f);
      }
    }
    frontier.swap(next);
  }
  {
    // The band's halo neighbours that their owners (not this process) put in the band.
    std::vector<double> borderInBand;
    for (const std::size_t f : local.Boundary)
    {
      if (inBand[f])
      {
        borderInBand.push_back(static_cast<double>(share.GlobalIds[f]));
      }
    }
    const std::vector<std::vector<double>> gathered = group.GatherOnFirst(borderInBand);
    std::unordered_set<std::int64_t> banded;
    for (const std::vector<double>& list : gathered)
    {
      for (const double id : list)
      {
        banded.insert(static_cast<std::int64_t>(id));
      }
    }
    Message flags{ group.ScatterFromFirst([&](int process) {
      std::vector<double> part;
      for (const std::int64_t id : table.HaloIds[static_cast<std::size_t>(process)])
      {
        part.push_back(banded.count(id) ? 1.0 : 0.0);
      }
      return part;
    }) };
    for (const std::size_t g : local.HaloNeighbors)
    {
      const bool ownersBand = flags.Next() != 0.0;
      inBand[g] = inBand[g] || ownersBand;
    }
  }

  // 4. The band's rows, to the first process; its components solved on every process.
  Message rows;
  std::vector<std::size_t> bandFaces;
  for (const std::size_t f : local.OwnFaces)
  {
    if (inBand[f])
    {
      PutBandRow(local, f, labels, inBand, rows);
      bandFaces.push_back(f);
    }
  }
  std::vector<std::vector<double>> gatheredRows = group.GatherOnFirst(rows.Values);
  rows = Message();
  BandSolution solution = SolveBand(std::move(gatheredRows), table, k, group, options, progress, parallelFor);
  result.Moves += solution.Moves;
  const double moves = static_cast<double>(result.Moves);
  Message solved{ group.ScatterFromFirst([&](int process) {
    std::vector<double> part{ solution.Aborted ? 1.0 : 0.0, moves };
    const std::vector<double>& labelsOf = solution.Parts[static_cast<std::size_t>(process)];
    part.insert(part.end(), labelsOf.begin(), labelsOf.end());
    return part;
  }) };
  if (solved.Next() != 0.0)
  {
    result.Aborted = true;
    return result;
  }
  result.Moves = static_cast<int>(solved.Next());
  for (const std::size_t f : bandFaces)
  {
    labels[f] = static_cast<int>(solved.Next());
  }
  for (const std::size_t g : local.HaloNeighbors)
  {
    const int label = static_cast<int>(solved.Next());
    if (label >= 0)
    {
      labels[g] = label;
    }
  }
  result.Labels = std::move(labels);
  if (first && progress)
  {
    progress(1.0);
  }
  return result;
}

} // namespace shapediameter
