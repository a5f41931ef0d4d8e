// SPDX-License-Identifier: BSD-3-Clause
#include "Partition/MultilevelCut.h"

#include "ExactSum.h"
#include "Partition/CoarseningCells.h"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace shapediameter
{
namespace
{

/// Pairs by face (CSR): the neighbour and the pair (whose weight is the energy's), 32 bits
/// each: half the memory of a neighbour and a weight, on the first process of a distributed
/// run the largest array of the cut (MaxFlowGraph limits faces and pairs to 2^31 - 2 anyway).
struct Adjacency
{
  std::vector<std::size_t> start;
  std::vector<std::uint32_t> neighbor;
  std::vector<std::uint32_t> pair;
  const std::vector<double>& weight;

  explicit Adjacency(const PartitionEnergy& energy)
    : start(energy.FaceCount + 1, 0)
    , weight(energy.PairWeight)
  {
    constexpr std::size_t limit = std::numeric_limits<std::uint32_t>::max();
    if (energy.FaceCount > limit || energy.PairWeight.size() > limit)
    {
      throw Error("multilevel cut: more than 2^32 - 1 faces or pairs");
    }
    for (std::size_t p = 0; p < energy.PairWeight.size(); ++p)
    {
      ++start[static_cast<std::size_t>(energy.PairFirst[p]) + 1];
      ++start[static_cast<std::size_t>(energy.PairSecond[p]) + 1];
    }
    for (std::size_t f = 0; f < energy.FaceCount; ++f)
    {
      start[f + 1] += start[f];
    }
    std::vector<std::size_t> fill(start.begin(), start.end() - 1);
    neighbor.resize(start.back());
    pair.resize(start.back());
    for (std::size_t p = 0; p < energy.PairWeight.size(); ++p)
    {
      const auto a = static_cast<std::size_t>(energy.PairFirst[p]);
      const auto b = static_cast<std::size_t>(energy.PairSecond[p]);
      neighbor[fill[a]] = static_cast<std::uint32_t>(b);
      pair[fill[a]++] = static_cast<std::uint32_t>(p);
      neighbor[fill[b]] = static_cast<std::uint32_t>(a);
      pair[fill[b]++] = static_cast<std::uint32_t>(p);
    }
  }

  double Weight(std::size_t entry) const { return weight[pair[entry]]; }
};

/// The energy of labellings constant on clusters.
PartitionEnergy CoarseEnergy(const PartitionEnergy& energy, const Adjacency& adjacency,
  const std::vector<std::size_t>& cluster, std::size_t clusterCount)
{
  const auto k = static_cast<std::size_t>(energy.LabelCount);
  PartitionEnergy coarse;
  coarse.FaceCount = clusterCount;
  coarse.LabelCount = energy.LabelCount;
  coarse.DataCosts.assign(clusterCount * k, 0.0);
  std::vector<std::size_t> memberStart(clusterCount + 1, 0);
  for (std::size_t f = 0; f < energy.FaceCount; ++f)
  {
    ++memberStart[cluster[f] + 1];
  }
  for (std::size_t c = 0; c < clusterCount; ++c)
  {
    memberStart[c + 1] += memberStart[c];
  }
  std::vector<std::uint32_t> members(energy.FaceCount);
  {
    std::vector<std::size_t> fill(memberStart.begin(), memberStart.end() - 1);
    for (std::size_t f = 0; f < energy.FaceCount; ++f)
    {
      members[fill[cluster[f]]++] = static_cast<std::uint32_t>(f);
    }
  }
  // Exact sums (ExactSum.h): they do not depend on the order of the faces or of the pairs, so
  // processes that each hold some of a cluster's faces can form them together. Cluster by
  // cluster (a), the pairs to higher clusters (b) sorted by b: built per cluster rather than
  // for every pair at once (24 bytes per pair: 30 MB at 832k faces).
  std::vector<std::pair<std::size_t, double>> links;
  for (std::size_t a = 0; a < clusterCount; ++a)
  {
    for (std::size_t l = 0; l < k; ++l)
    {
      ExactSum cost;
      for (std::size_t m = memberStart[a]; m < memberStart[a + 1]; ++m)
      {
        cost.Add(energy.DataCosts[members[m] * k + l]);
      }
      coarse.DataCosts[a * k + l] = cost.Rounded();
    }
    links.clear();
    for (std::size_t m = memberStart[a]; m < memberStart[a + 1]; ++m)
    {
      const std::size_t f = members[m];
      for (std::size_t e = adjacency.start[f]; e < adjacency.start[f + 1]; ++e)
      {
        const std::size_t b = cluster[adjacency.neighbor[e]];
        if (b > a)
        {
          links.emplace_back(b, adjacency.Weight(e));
        }
      }
    }
    std::sort(links.begin(), links.end());
    for (std::size_t i = 0; i < links.size();)
    {
      const std::size_t b = links[i].first;
      ExactSum sum;
      for (; i < links.size() && links[i].first == b; ++i)
      {
        sum.Add(links[i].second);
      }
      coarse.PairFirst.push_back(static_cast<std::int64_t>(a));
      coarse.PairSecond.push_back(static_cast<std::int64_t>(b));
      coarse.PairWeight.push_back(sum.Rounded());
    }
  }
  return coarse;
}

/// Per node, 1 when it lies in a region of nodes off their most probable label, connected
/// through nodes of the same most probable label, whose size (the sum of `sizes` over its
/// nodes; 1 each when empty) reaches `minimumRegion`.
std::vector<std::uint8_t> LostRegionNodes(const Adjacency& adjacency, const std::vector<int>& labels,
  const std::vector<int>& mostProbable, const std::vector<double>& sizes, std::size_t minimumRegion)
{
  const std::size_t n = labels.size();
  std::vector<std::uint8_t> lost(n, 0), visited(n, 0);
  std::vector<std::size_t> region;
  for (std::size_t seed = 0; seed < n; ++seed)
  {
    if (visited[seed] || labels[seed] == mostProbable[seed])
    {
      continue;
    }
    region.assign(1, seed);
    visited[seed] = 1;
    double size = 0.0;
    for (std::size_t i = 0; i < region.size(); ++i)
    {
      const std::size_t f = region[i];
      size += sizes.empty() ? 1.0 : sizes[f];
      for (std::size_t e = adjacency.start[f]; e < adjacency.start[f + 1]; ++e)
      {
        const std::size_t g = adjacency.neighbor[e];
        if (!visited[g] && labels[g] != mostProbable[g] && mostProbable[g] == mostProbable[seed])
        {
          visited[g] = 1;
          region.push_back(g);
        }
      }
    }
    if (size >= static_cast<double>(minimumRegion))
    {
      for (const std::size_t f : region)
      {
        lost[f] = 1;
      }
    }
  }
  return lost;
}

/// Faces within `rings` rings of a face that has a neighbour with another label, or that lies
/// in a connected region of at least `minimumRegion` faces whose label is not their most
/// probable one (a part the coarse solve lost: it has no boundary left to refine from).
std::vector<std::uint8_t> BoundaryBand(const Adjacency& adjacency, const std::vector<int>& labels,
  const std::vector<int>& mostProbable, int rings, std::size_t minimumRegion)
{
  const std::size_t n = labels.size();
  std::vector<std::uint8_t> inBand(n, 0);
  std::vector<std::size_t> frontier;
  for (std::size_t f = 0; f < n; ++f)
  {
    for (std::size_t e = adjacency.start[f]; e < adjacency.start[f + 1]; ++e)
    {
      if (labels[adjacency.neighbor[e]] != labels[f])
      {
        inBand[f] = 1;
        frontier.push_back(f);
        break;
      }
    }
  }
  // Regions of faces off their most probable label (a part the coarse solve lost); large
  // ones join the band.
  const std::vector<std::uint8_t> lost = LostRegionNodes(adjacency, labels, mostProbable, {}, minimumRegion);
  for (std::size_t f = 0; f < n; ++f)
  {
    if (lost[f] && !inBand[f])
    {
      inBand[f] = 1;
      frontier.push_back(f);
    }
  }
  std::vector<std::size_t> next;
  for (int ring = 1; ring < rings && !frontier.empty(); ++ring)
  {
    next.clear();
    for (const std::size_t f : frontier)
    {
      for (std::size_t e = adjacency.start[f]; e < adjacency.start[f + 1]; ++e)
      {
        const std::size_t g = adjacency.neighbor[e];
        if (!inBand[g])
        {
          inBand[g] = 1;
          next.push_back(g);
        }
      }
    }
    frontier.swap(next);
  }
  return inBand;
}

/// The connected components of the band (through pairs of band faces), each as its faces in
/// increasing order; components ordered by their lowest face.
std::vector<std::vector<std::size_t>> BandComponents(const Adjacency& adjacency, const std::vector<std::uint8_t>& inBand,
  const std::vector<std::size_t>& bandFaces, const std::vector<std::size_t>& bandIndex)
{
  constexpr std::size_t none = static_cast<std::size_t>(-1);
  std::vector<std::size_t> component(bandFaces.size(), none);
  std::vector<std::vector<std::size_t>> components;
  for (std::size_t seed = 0; seed < bandFaces.size(); ++seed)
  {
    if (component[seed] != none)
    {
      continue;
    }
    std::vector<std::size_t> faces(1, bandFaces[seed]);
    component[seed] = components.size();
    for (std::size_t i = 0; i < faces.size(); ++i)
    {
      const std::size_t f = faces[i];
      for (std::size_t e = adjacency.start[f]; e < adjacency.start[f + 1]; ++e)
      {
        const std::size_t g = adjacency.neighbor[e];
        if (inBand[g] && component[bandIndex[g]] == none)
        {
          component[bandIndex[g]] = components.size();
          faces.push_back(g);
        }
      }
    }
    std::sort(faces.begin(), faces.end());
    components.push_back(std::move(faces));
  }
  return components;
}

/// The energy of `faces` (a band component, increasing) with every other face fixed at
/// `labels`: pairs with fixed faces become data costs.
PartitionEnergy BandEnergy(const PartitionEnergy& energy, const Adjacency& adjacency, const std::vector<std::uint8_t>& inBand,
  const std::vector<std::size_t>& faces, const std::vector<int>& labels)
{
  const auto k = static_cast<std::size_t>(energy.LabelCount);
  PartitionEnergy part;
  part.FaceCount = faces.size();
  part.LabelCount = energy.LabelCount;
  part.DataCosts.resize(faces.size() * k);
  for (std::size_t b = 0; b < faces.size(); ++b)
  {
    const std::size_t f = faces[b];
    for (std::size_t l = 0; l < k; ++l)
    {
      part.DataCosts[b * k + l] = energy.DataCosts[f * k + l];
    }
    for (std::size_t e = adjacency.start[f]; e < adjacency.start[f + 1]; ++e)
    {
      const std::size_t g = adjacency.neighbor[e];
      const double w = adjacency.Weight(e);
      if (!inBand[g])
      {
        for (std::size_t l = 0; l < k; ++l)
        {
          part.DataCosts[b * k + l] += static_cast<int>(l) != labels[g] ? w : 0.0;
        }
      }
      else if (g > f)
      {
        // Pairs in the order of their lower face, then of the adjacency: the sub-energy does
        // not depend on how the band is split among threads.
        part.PairFirst.push_back(static_cast<std::int64_t>(b));
        part.PairSecond.push_back(static_cast<std::int64_t>(
          std::lower_bound(faces.begin(), faces.end(), g) - faces.begin()));
        part.PairWeight.push_back(w);
      }
    }
  }
  return part;
}

void CheckCellCount(const PartitionEnergy& energy, const std::vector<std::uint64_t>& faceCells)
{
  if (!faceCells.empty() && faceCells.size() != energy.FaceCount)
  {
    throw Error("multilevel cut: " + std::to_string(faceCells.size()) + " cells for " +
      std::to_string(energy.FaceCount) + " faces");
  }
}

ProgressCallback SubRange(const ProgressCallback& progress, double from, double to)
{
  if (!progress)
  {
    return nullptr;
  }
  return [progress, from, to](double fraction) { return progress(from + (to - from) * fraction); };
}

} // namespace

std::pair<std::vector<std::size_t>, std::size_t> GrowClusters(const std::size_t* start, const std::uint32_t* neighbor,
  const std::vector<int>& seedLabels, const std::vector<std::uint64_t>& cells, int size, const std::uint8_t* include)
{
  const std::size_t n = seedLabels.size();
  const std::size_t limit = cells.empty() ? static_cast<std::size_t>(size) : n;
  std::vector<std::size_t> cluster(n, NoCluster);
  std::vector<std::size_t> queue;
  std::size_t count = 0;
  for (std::size_t seed = 0; seed < n; ++seed)
  {
    if (cluster[seed] != NoCluster || (include && !include[seed]))
    {
      continue;
    }
    queue.assign(1, seed);
    cluster[seed] = count;
    for (std::size_t head = 0; head < queue.size() && queue.size() < limit; ++head)
    {
      const std::size_t f = queue[head];
      for (std::size_t e = start[f]; e < start[f + 1] && queue.size() < limit; ++e)
      {
        const std::size_t g = neighbor[e];
        if (cluster[g] == NoCluster && (!include || include[g]) && seedLabels[g] == seedLabels[seed] &&
          (cells.empty() || cells[g] == cells[seed]))
        {
          cluster[g] = count;
          queue.push_back(g);
        }
      }
    }
    ++count;
  }
  return { std::move(cluster), count };
}

std::vector<std::uint8_t> LostRegions(const PartitionEnergy& energy, const std::vector<int>& labels,
  const std::vector<int>& mostProbable, const std::vector<double>& sizes, std::size_t minimumRegion)
{
  return LostRegionNodes(Adjacency(energy), labels, mostProbable, sizes, minimumRegion);
}

std::pair<std::vector<std::size_t>, std::size_t> FirstLevelClusters(
  const PartitionEnergy& energy, const std::vector<std::uint64_t>& faceCells, int clusterSize)
{
  ValidateEnergyForCut(energy);
  CheckCellCount(energy, faceCells);
  const Adjacency adjacency(energy);
  const std::vector<int> mostProbable = MostProbableLabels(energy);
  return GrowClusters(adjacency.start.data(), adjacency.neighbor.data(), mostProbable, faceCells, clusterSize);
}

AlphaExpansionResult MinimizeMultilevel(const PartitionEnergy& energy, const MultilevelOptions& multilevel,
  const AlphaExpansionOptions& options, const ProgressCallback& progress, const ParallelFor& parallelFor,
  const std::vector<std::uint64_t>& faceCells)
{
  if (multilevel.DirectBelowFaces < 16 || multilevel.ClusterSize < 2 || multilevel.ClusterSize > 1024 ||
    multilevel.BandRings < 1 || multilevel.BandRings > 64 || multilevel.LostRegionFaces < 1)
  {
    throw Error("multilevel cut: options out of range");
  }
  if (energy.FaceCount <= multilevel.DirectBelowFaces || energy.LabelCount < 2)
  {
    return MinimizeByAlphaExpansion(energy, options, progress);
  }
  ValidateEnergyForCut(energy);
  const std::vector<int> mostProbable = MostProbableLabels(energy);
  const Adjacency adjacency(energy);
  CheckCellCount(energy, faceCells);
  std::vector<std::uint64_t> cells(faceCells);
  std::vector<std::size_t> cluster;
  std::size_t clusterCount = 0;
  // Where the faces are large against the cells (a coarse region, or a far-away face that
  // stretched the grid), larger cells.
  for (int doubling = 0;; ++doubling)
  {
    std::tie(cluster, clusterCount) = GrowClusters(adjacency.start.data(), adjacency.neighbor.data(), mostProbable, cells, multilevel.ClusterSize);
    if (cells.empty() || 2 * clusterCount <= energy.FaceCount || doubling == MaximumCellDoublings)
    {
      break;
    }
    std::transform(cells.begin(), cells.end(), cells.begin(), ParentCell);
  }
  if (2 * clusterCount > energy.FaceCount)
  {
    return MinimizeByAlphaExpansion(energy, options, progress); // too fragmented to coarsen
  }

  // Coarse solve, projected onto the faces.
  const PartitionEnergy coarse = CoarseEnergy(energy, adjacency, cluster, clusterCount);
  std::vector<std::uint64_t> coarseCells;
  if (!cells.empty())
  {
    coarseCells.resize(clusterCount);
    for (std::size_t f = 0; f < energy.FaceCount; ++f)
    {
      coarseCells[cluster[f]] = ParentCell(cells[f]);
    }
    cells = std::vector<std::uint64_t>();
  }
  const AlphaExpansionResult coarseResult =
    MinimizeMultilevel(coarse, multilevel, options, SubRange(progress, 0.0, 0.5), parallelFor, coarseCells);
  AlphaExpansionResult result;
  result.InitialEnergy = energy.Evaluate(mostProbable);
  result.Labels.resize(energy.FaceCount);
  for (std::size_t f = 0; f < energy.FaceCount; ++f)
  {
    result.Labels[f] = coarseResult.Labels[cluster[f]];
  }
  result.Moves = coarseResult.Moves;
  result.AppliedMoves = coarseResult.AppliedMoves;
  if (coarseResult.Aborted)
  {
    result.Aborted = true;
    result.Energy = energy.Evaluate(result.Labels);
    return result;
  }

  // The band at full resolution, the rest fixed.
  const std::vector<std::uint8_t> inBand =
    BoundaryBand(adjacency, result.Labels, mostProbable, multilevel.BandRings, multilevel.LostRegionFaces);
  std::vector<std::size_t> bandIndex(energy.FaceCount, 0);
  std::vector<std::size_t> bandFaces;
  for (std::size_t f = 0; f < energy.FaceCount; ++f)
  {
    if (inBand[f])
    {
      bandIndex[f] = bandFaces.size();
      bandFaces.push_back(f);
    }
  }
  // The band's connected components are independent problems (everything around them is
  // fixed): each is solved on its own, in parallel. An expansion move's cut of a union of
  // components is the union of their cuts (the source side is the set reachable from s), so
  // this is the joint alpha-expansion up to moves that change nothing or below the tolerance.
  const std::vector<std::vector<std::size_t>> components = BandComponents(adjacency, inBand, bandFaces, bandIndex);
  std::vector<AlphaExpansionResult> solved(components.size());
  SharedProgress bandProgress(SubRange(progress, 0.5, 1.0), bandFaces.size());
  parallelFor(components.size(), [&](std::size_t begin, std::size_t end) {
    for (std::size_t c = begin; c < end; ++c)
    {
      const std::vector<std::size_t>& faces = components[c];
      const PartitionEnergy part = BandEnergy(energy, adjacency, inBand, faces, result.Labels);
      std::vector<int> partLabels(faces.size());
      for (std::size_t i = 0; i < faces.size(); ++i)
      {
        partLabels[i] = result.Labels[faces[i]];
      }
      solved[c] = MinimizeByAlphaExpansion(part, partLabels, options, bandProgress.ForPart(faces.size()));
    }
  });
  result.Converged = true;
  for (std::size_t c = 0; c < components.size(); ++c)
  {
    for (std::size_t i = 0; i < components[c].size(); ++i)
    {
      result.Labels[components[c][i]] = solved[c].Labels[i];
    }
    result.Moves += solved[c].Moves;
    result.AppliedMoves += solved[c].AppliedMoves;
    result.Converged = result.Converged && solved[c].Converged;
    result.Aborted = result.Aborted || solved[c].Aborted;
  }
  result.Energy = energy.Evaluate(result.Labels);
  result.EnergyTrace.push_back(result.Energy);
  if (progress)
  {
    progress(1.0);
  }
  return result;
}

} // namespace shapediameter
