// SPDX-License-Identifier: BSD-3-Clause
// The cells the multilevel cut coarsens by: their size, their degenerate cases, and the reason
// they exist (the cut's labels do not depend on the order of the faces).
#include "Partition/CoarseningCells.h"
#include "Partition/MultilevelCut.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <random>
#include <set>
#include <vector>

namespace
{

using shapediameter::AlphaExpansionResult;
using shapediameter::CoarseningCells;
using shapediameter::DualGraphView;
using shapediameter::MinimizeMultilevel;
using shapediameter::MultilevelOptions;
using shapediameter::ParentCell;
using shapediameter::PartitionEnergy;

/// A side x side lattice of faces (centres at integer points of the plane z = 0, 4-neighbour
/// pairs) in the face order `order` (order[lattice index] = face index), with three vertical
/// bands with wavy borders as the truth and 30 % of the faces given a random label. Data costs
/// and weights are small integers, so every sum the cut forms is exact in any order.
struct Lattice
{
  PartitionEnergy Energy;
  std::vector<double> Centers;
  std::vector<std::int64_t> Offsets, Neighbors;

  Lattice(int side, const std::vector<std::size_t>& order)
  {
    const std::size_t n = static_cast<std::size_t>(side) * static_cast<std::size_t>(side);
    std::mt19937_64 generator(2008);
    std::uniform_real_distribution<double> uniform(0.0, 1.0);
    Energy.FaceCount = n;
    Energy.LabelCount = 3;
    Energy.DataCosts.resize(n * 3);
    Centers.resize(n * 3);
    std::vector<std::vector<std::int64_t>> adjacent(n);
    for (int y = 0; y < side; ++y)
    {
      for (int x = 0; x < side; ++x)
      {
        const std::size_t cell = static_cast<std::size_t>(y) * static_cast<std::size_t>(side) + static_cast<std::size_t>(x);
        const std::size_t f = order[cell];
        const double wave = 0.05 * side * std::sin(0.1 * y);
        int truth = x + wave < side / 3.0 ? 0 : (x + wave < 2.0 * side / 3.0 ? 1 : 2);
        if (uniform(generator) < 0.3)
        {
          truth = static_cast<int>(uniform(generator) * 3.0) % 3;
        }
        for (int l = 0; l < 3; ++l)
        {
          Energy.DataCosts[f * 3 + static_cast<std::size_t>(l)] = l == truth ? 1.0 : 2.0;
        }
        Centers[3 * f] = x;
        Centers[3 * f + 1] = y;
        for (const auto& [dx, dy] : { std::pair{ 1, 0 }, std::pair{ 0, 1 } })
        {
          if (x + dx < side && y + dy < side)
          {
            const std::size_t g = order[cell + static_cast<std::size_t>(dx + dy * side)];
            adjacent[f].push_back(static_cast<std::int64_t>(g));
            adjacent[g].push_back(static_cast<std::int64_t>(f));
          }
        }
      }
    }
    Offsets.push_back(0);
    for (std::size_t f = 0; f < n; ++f)
    {
      std::sort(adjacent[f].begin(), adjacent[f].end());
      for (const std::int64_t g : adjacent[f])
      {
        Neighbors.push_back(g);
        if (static_cast<std::size_t>(g) > f)
        {
          Energy.PairFirst.push_back(static_cast<std::int64_t>(f));
          Energy.PairSecond.push_back(g);
          Energy.PairWeight.push_back(2.0);
        }
      }
      Offsets.push_back(static_cast<std::int64_t>(Neighbors.size()));
    }
  }

  DualGraphView View() const
  {
    DualGraphView view;
    view.Offsets = Offsets.data();
    view.Neighbors = Neighbors.data();
    view.FaceCount = Energy.FaceCount;
    view.FaceCenter = Centers.data();
    return view;
  }
};

std::vector<std::size_t> Identity(std::size_t n)
{
  std::vector<std::size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  return order;
}

std::uint64_t Axis(std::uint64_t cell, int axis)
{
  return (cell >> (21 * axis)) & ((std::uint64_t{ 1 } << 21) - 1);
}

TEST(CoarseningCells, CubesOfSqrtClusterSizeMeanSpacings)
{
  const Lattice lattice(40, Identity(1600));
  const std::vector<std::uint64_t> cells = CoarseningCells(lattice.View(), 8);
  ASSERT_EQ(cells.size(), 1600u);
  // Spacing 1, side sqrt(8) = 2.83: x = 0..2 in cube 0, 3..5 in cube 1, 6..8 in cube 2, ...
  for (const int x : { 0, 2, 3, 5, 6, 39 })
  {
    EXPECT_EQ(Axis(cells[static_cast<std::size_t>(x)], 0), static_cast<std::uint64_t>(std::floor(x / std::sqrt(8.0))))
      << "x = " << x;
  }
  EXPECT_EQ(Axis(cells[40 * 39], 1), 13u);
  EXPECT_EQ(Axis(cells[40 * 39], 2), 0u);
  EXPECT_EQ(std::set<std::uint64_t>(cells.begin(), cells.end()).size(), 14u * 14u); // 39 / 2.83 = 13.8
  // The parent: the cube of twice the side, sharing the origin.
  const std::uint64_t parent = ParentCell(cells[40 * 39 + 39]);
  EXPECT_EQ(Axis(parent, 0), 6u);
  EXPECT_EQ(Axis(parent, 1), 6u);
  std::set<std::uint64_t> parents;
  for (const std::uint64_t cell : cells)
  {
    parents.insert(ParentCell(cell));
  }
  EXPECT_EQ(parents.size(), 7u * 7u);
}

TEST(CoarseningCells, NoCellsWithoutCentresPairsOrFiniteValues)
{
  Lattice lattice(4, Identity(16));
  DualGraphView view = lattice.View();
  EXPECT_EQ(CoarseningCells(view, 8).size(), 16u);
  view.FaceCenter = nullptr;
  EXPECT_TRUE(CoarseningCells(view, 8).empty());
  lattice.Centers[5] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(CoarseningCells(lattice.View(), 8).empty());
  lattice.Centers[5] = 0.0;
  std::fill(lattice.Centers.begin(), lattice.Centers.end(), 1.0); // every centre the same point
  EXPECT_TRUE(CoarseningCells(lattice.View(), 8).empty());
  Lattice isolated(4, Identity(16));
  std::fill(isolated.Offsets.begin(), isolated.Offsets.end(), 0);
  EXPECT_TRUE(CoarseningCells(isolated.View(), 8).empty());
}

TEST(CoarseningCells, AFarAwayFaceStretchesTheGridWithinItsBits)
{
  // Face 99 moved 1e12 spacings away, with no neighbours (a separate piece): more cubes than 21
  // bits hold at sqrt(8) spacings.
  Lattice lattice(10, Identity(100));
  lattice.Centers[3 * 99] = 1e12;
  std::vector<std::int64_t> offsets{ 0 }, neighbors;
  for (std::size_t f = 0; f < 100; ++f)
  {
    for (std::int64_t e = lattice.Offsets[f]; e < lattice.Offsets[f + 1]; ++e)
    {
      if (f != 99 && lattice.Neighbors[static_cast<std::size_t>(e)] != 99)
      {
        neighbors.push_back(lattice.Neighbors[static_cast<std::size_t>(e)]);
      }
    }
    offsets.push_back(static_cast<std::int64_t>(neighbors.size()));
  }
  lattice.Offsets = offsets;
  lattice.Neighbors = neighbors;
  const std::vector<std::uint64_t> cells = CoarseningCells(lattice.View(), 8);
  ASSERT_EQ(cells.size(), 100u);
  EXPECT_EQ(Axis(cells[99], 0), (std::uint64_t{ 1 } << 21) - 1) << "the far face in the last cube";
  EXPECT_EQ(Axis(cells[0], 0), 0u);
  EXPECT_EQ(Axis(cells[98], 0), 0u) << "the rest share the first cube along x";
}

/// The labels of the cut on the lattice in a shuffled face order, in lattice order.
std::vector<int> LabelsInLatticeOrder(const std::vector<std::size_t>& order, bool byCells)
{
  const Lattice lattice(120, order);
  MultilevelOptions coarsen;
  coarsen.DirectBelowFaces = 500; // 14400 faces coarsened twice
  const std::vector<std::uint64_t> cells = byCells ? CoarseningCells(lattice.View(), coarsen.ClusterSize)
                                                   : std::vector<std::uint64_t>();
  const AlphaExpansionResult cut = MinimizeMultilevel(lattice.Energy, coarsen, {}, nullptr, shapediameter::SerialFor, cells);
  EXPECT_FALSE(cut.Aborted);
  EXPECT_LT(cut.Energy, 0.9 * cut.InitialEnergy);
  std::vector<int> labels(order.size());
  for (std::size_t i = 0; i < order.size(); ++i)
  {
    labels[i] = cut.Labels[order[i]];
  }
  return labels;
}

/// Per lattice index, the lowest lattice index in its first-level cluster: the clusters as sets
/// of places, whatever their numbering.
std::vector<std::size_t> ClustersInLatticeOrder(const std::vector<std::size_t>& order, bool byCells)
{
  const Lattice lattice(120, order);
  const std::vector<std::uint64_t> cells = byCells ? CoarseningCells(lattice.View(), 8) : std::vector<std::uint64_t>();
  const auto [cluster, count] = shapediameter::FirstLevelClusters(lattice.Energy, cells, 8);
  constexpr std::size_t none = static_cast<std::size_t>(-1);
  std::vector<std::size_t> lowest(count, none);
  for (std::size_t i = 0; i < order.size(); ++i)
  {
    lowest[cluster[order[i]]] = std::min(lowest[cluster[order[i]]], i);
  }
  std::vector<std::size_t> representative(order.size());
  for (std::size_t i = 0; i < order.size(); ++i)
  {
    representative[i] = lowest[cluster[order[i]]];
  }
  return representative;
}

TEST(MultilevelCut, ByCellsTheClustersAndLabelsDoNotDependOnTheFaceOrder)
{
  std::vector<std::size_t> shuffled = Identity(14400);
  std::shuffle(shuffled.begin(), shuffled.end(), std::mt19937_64(7));
  const std::vector<std::size_t> clusters = ClustersInLatticeOrder(Identity(14400), true);
  EXPECT_EQ(ClustersInLatticeOrder(shuffled, true), clusters);
  EXPECT_GT(std::set<std::size_t>(clusters.begin(), clusters.end()).size(), 14400u / 8)
    << "cubes of about 8 faces, split by labels";
  EXPECT_LT(std::set<std::size_t>(clusters.begin(), clusters.end()).size(), 14400u / 2);
  // Breadth-first in face order: another order, other clusters.
  EXPECT_NE(ClustersInLatticeOrder(shuffled, false), ClustersInLatticeOrder(Identity(14400), false));
  // The same clusters make the same cut (the sums here are exact in any order).
  EXPECT_EQ(LabelsInLatticeOrder(shuffled, true), LabelsInLatticeOrder(Identity(14400), true));
}

TEST(MultilevelCut, CellsOfTheWrongCountAreAnError)
{
  const Lattice lattice(30, Identity(900));
  MultilevelOptions coarsen;
  coarsen.DirectBelowFaces = 100;
  EXPECT_THROW(MinimizeMultilevel(lattice.Energy, coarsen, {}, nullptr, shapediameter::SerialFor,
                 std::vector<std::uint64_t>(899, 0)),
    shapediameter::Error);
}

} // namespace
