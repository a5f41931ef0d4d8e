// SPDX-License-Identifier: BSD-3-Clause
// PartitionEnergy + AlphaExpansion: energy terms, exactness on tiny graphs against exhaustive
// search, monotone energy, crease-following cuts, hierarchy levels and connected segments.
#include "Partition/AlphaExpansion.h"
#include "Partition/PartitionEnergy.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <tuple>
#include <vector>

namespace
{
using namespace shapediameter;

constexpr double kPi = 3.14159265358979323846;

double Uniform(std::mt19937_64& generator)
{
  return static_cast<double>(generator() >> 11) * (1.0 / 9007199254740992.0);
}

/// A dual graph in CSR form built from undirected edges (a, b, angle, concave, length); every
/// face has area 1.
struct TestGraph
{
  std::vector<std::int64_t> offsets, neighbours;
  std::vector<double> angle, length, area;
  std::vector<std::uint8_t> concave;
  std::size_t faceCount = 0;

  using Edge = std::tuple<int, int, double, bool, double>;
  TestGraph(std::size_t faces, const std::vector<Edge>& edges)
    : area(faces, 1.0)
    , faceCount(faces)
  {
    std::vector<std::vector<std::tuple<int, double, bool, double>>> adjacency(faces);
    for (const auto& [a, b, phi, isConcave, len] : edges)
    {
      adjacency[static_cast<std::size_t>(a)].emplace_back(b, phi, isConcave, len);
      adjacency[static_cast<std::size_t>(b)].emplace_back(a, phi, isConcave, len);
    }
    offsets.push_back(0);
    for (const auto& list : adjacency)
    {
      for (const auto& [g, phi, isConcave, len] : list)
      {
        neighbours.push_back(g);
        angle.push_back(phi);
        concave.push_back(isConcave ? 1 : 0);
        length.push_back(len);
      }
      offsets.push_back(static_cast<std::int64_t>(neighbours.size()));
    }
  }

  DualGraphView View() const
  {
    return { offsets.data(), neighbours.data(), angle.data(), concave.data(), length.data(), area.data(), faceCount };
  }
};

/// A random energy on <= 10 faces: data costs in [0, 4), pair weights in [0, 2).
PartitionEnergy RandomEnergy(std::mt19937_64& generator, std::size_t faces, int labels)
{
  PartitionEnergy energy;
  energy.FaceCount = faces;
  energy.LabelCount = labels;
  for (std::size_t i = 0; i < faces * static_cast<std::size_t>(labels); ++i)
  {
    energy.DataCosts.push_back(4.0 * Uniform(generator));
  }
  for (std::size_t a = 0; a < faces; ++a)
  {
    for (std::size_t b = a + 1; b < faces; ++b)
    {
      if (Uniform(generator) < 0.4)
      {
        energy.PairFirst.push_back(static_cast<std::int64_t>(a));
        energy.PairSecond.push_back(static_cast<std::int64_t>(b));
        energy.PairWeight.push_back(2.0 * Uniform(generator));
      }
    }
  }
  return energy;
}

double SmoothnessOf(const PartitionEnergy& energy, const std::vector<int>& labels)
{
  double sum = 0.0;
  for (std::size_t p = 0; p < energy.PairWeight.size(); ++p)
  {
    if (labels[static_cast<std::size_t>(energy.PairFirst[p])] != labels[static_cast<std::size_t>(energy.PairSecond[p])])
    {
      sum += energy.PairWeight[p];
    }
  }
  return sum;
}

/// Exhaustive minimum over all k^n labelings.
std::vector<int> ExhaustiveMinimum(const PartitionEnergy& energy)
{
  const std::size_t n = energy.FaceCount;
  std::vector<int> labels(n, 0), best(n, 0);
  double bestEnergy = energy.Evaluate(labels);
  while (true)
  {
    std::size_t digit = 0;
    while (digit < n && ++labels[digit] == energy.LabelCount)
    {
      labels[digit++] = 0;
    }
    if (digit == n)
    {
      return best;
    }
    const double e = energy.Evaluate(labels);
    if (e < bestEnergy)
    {
      bestEnergy = e;
      best = labels;
    }
  }
}

TEST(PartitionEnergy, SmoothnessTermMatchesTheFormula)
{
  const PartitionEnergyOptions options;
  EXPECT_NEAR(SmoothnessTerm(0.0, true, options), -std::log(1e-5), 1e-12); // flat: floor
  EXPECT_NEAR(SmoothnessTerm(kPi / 2, true, options), std::log(2.0), 1e-12);
  EXPECT_NEAR(SmoothnessTerm(kPi, true, options), 0.0, 1e-12);
  EXPECT_NEAR(SmoothnessTerm(kPi / 2, false, options), -std::log(0.08 * 0.5), 1e-12);
  EXPECT_NEAR(SmoothnessTerm(4.0, true, options), 0.0, 1e-12); // clamped to pi
  EXPECT_GT(SmoothnessTerm(0.1, false, options), SmoothnessTerm(0.1, true, options));
}

TEST(PartitionEnergy, BuildAndEvaluateHandComputedCase)
{
  // Three faces in a row; edges 0-1 (concave, pi/2, length 1) and 1-2 (convex, pi/2, length 3).
  const TestGraph graph(3, { { 0, 1, kPi / 2, true, 1.0 }, { 1, 2, kPi / 2, false, 3.0 } });
  PosteriorMatrix posteriors(3, 2);
  posteriors << 0.9, 0.1, 0.5, 0.5, 0.0, 1.0;
  PartitionEnergyOptions options;
  options.Lambda = 0.5;
  const PartitionEnergy energy = BuildPartitionEnergy(posteriors, graph.View(), options);
  ASSERT_EQ(energy.FaceCount, 3u);
  ASSERT_EQ(energy.LabelCount, 2);
  ASSERT_EQ(energy.PairWeight.size(), 2u);
  EXPECT_NEAR(energy.DataCost(0, 0), -std::log(0.9 + 1e-8), 1e-12);
  EXPECT_NEAR(energy.DataCost(2, 0), -std::log(1e-8), 1e-9);
  // Areas 1: data factors 1; pair factor = length * faceCount / sqrt(total area) = length * sqrt(3).
  EXPECT_NEAR(energy.PairWeight[0], 0.5 * std::log(2.0) * 1.0 * std::sqrt(3.0), 1e-12);
  EXPECT_NEAR(energy.PairWeight[1], 0.5 * -std::log(0.04) * 3.0 * std::sqrt(3.0), 1e-12);
  const double expected = -std::log(0.9 + 1e-8) - std::log(0.5 + 1e-8) - std::log(1.0 + 1e-8) +
    energy.PairWeight[1];
  EXPECT_NEAR(energy.Evaluate({ 0, 0, 1 }), expected, 1e-12);
  EXPECT_EQ(MostProbableLabels(energy), std::vector<int>({ 0, 0, 1 }));

  // Unequal areas weight the data term by area / mean area (mean 2 here).
  TestGraph uneven = graph;
  uneven.area = { 1.0, 1.0, 4.0 };
  const PartitionEnergy weighted = BuildPartitionEnergy(posteriors, uneven.View(), options);
  EXPECT_NEAR(weighted.DataCost(0, 0), 0.5 * -std::log(0.9 + 1e-8), 1e-12);
  EXPECT_NEAR(weighted.DataCost(2, 0), 2.0 * -std::log(1e-8), 1e-9);
  EXPECT_NEAR(weighted.PairWeight[0], 0.5 * std::log(2.0) * 1.0 * 3.0 / std::sqrt(6.0), 1e-12);

  // Zero total area: data factors 1, pair factors length / mean length (mean 2).
  TestGraph flat = graph;
  flat.area = { 0.0, 0.0, 0.0 };
  const PartitionEnergy fallback = BuildPartitionEnergy(posteriors, flat.View(), options);
  EXPECT_NEAR(fallback.DataCost(2, 0), -std::log(1e-8), 1e-9);
  EXPECT_NEAR(fallback.PairWeight[1], 0.5 * -std::log(0.04) * 1.5, 1e-12);

  options.GeometricWeights = false;
  const PartitionEnergy unweighted = BuildPartitionEnergy(posteriors, graph.View(), options);
  EXPECT_NEAR(unweighted.PairWeight[0], 0.5 * std::log(2.0), 1e-12);

  EXPECT_THROW(energy.Evaluate({ 0, 0 }), Error);
  EXPECT_THROW(energy.Evaluate({ 0, 2, 0 }), Error);
}

TEST(PartitionEnergy, TheSameForAnyThreadSplit)
{
  // A random graph of 500 faces (each with up to 4 higher neighbours) and random posteriors:
  // serial and threaded builds list the same pairs in the same order with the same weights.
  std::mt19937_64 generator(17);
  std::vector<TestGraph::Edge> edges;
  for (int f = 0; f < 500; ++f)
  {
    for (int g = f + 1; g < std::min(500, f + 5); ++g)
    {
      if (Uniform(generator) < 0.7)
      {
        edges.emplace_back(f, g, kPi * Uniform(generator), Uniform(generator) < 0.5, 0.1 + Uniform(generator));
      }
    }
  }
  const TestGraph graph(500, edges);
  PosteriorMatrix posteriors(500, 3);
  for (Eigen::Index f = 0; f < 500; ++f)
  {
    const double a = Uniform(generator), b = Uniform(generator);
    posteriors.row(f) << a, b * (1 - a), (1 - b) * (1 - a);
  }
  const PartitionEnergy serial = BuildPartitionEnergy(posteriors, graph.View());
  ASSERT_EQ(serial.PairWeight.size(), edges.size());
  for (const unsigned threads : { 2u, 3u, 7u })
  {
    const PartitionEnergy threaded = BuildPartitionEnergy(posteriors, graph.View(), {}, ThreadedFor(threads));
    EXPECT_EQ(threaded.DataCosts, serial.DataCosts) << threads << " threads";
    EXPECT_EQ(threaded.PairFirst, serial.PairFirst) << threads << " threads";
    EXPECT_EQ(threaded.PairSecond, serial.PairSecond) << threads << " threads";
    EXPECT_EQ(threaded.PairWeight, serial.PairWeight) << threads << " threads";
  }
  // A broken graph: the error names the same (lowest) failing face whatever the split.
  TestGraph broken = graph;
  const auto entry = static_cast<std::size_t>(broken.offsets[400]);
  broken.neighbours[entry] = broken.neighbours[entry] == 0 ? 1 : 0;
  auto messageOf = [&](const ParallelFor& parallelFor) {
    try
    {
      BuildPartitionEnergy(posteriors, broken.View(), {}, parallelFor);
    }
    catch (const Error& error)
    {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  const std::string serialMessage = messageOf(SerialFor);
  EXPECT_NE(serialMessage.find("not symmetric"), std::string::npos) << serialMessage;
  EXPECT_EQ(messageOf(ThreadedFor(3)), serialMessage);
  EXPECT_EQ(messageOf(ThreadedFor(7)), serialMessage);
  const std::vector<int> labels(500, 0);
  EXPECT_EQ(FindConnectedSegments(graph.View(), labels, graph.area, ThreadedFor(3)).SegmentCount(),
    FindConnectedSegments(graph.View(), labels, graph.area).SegmentCount());
  EXPECT_THROW(FindConnectedSegments(broken.View(), labels, broken.area, ThreadedFor(3)), Error);
  PosteriorMatrix withNaN = posteriors;
  withNaN(321, 1) = std::nan("");
  try
  {
    BuildPartitionEnergy(withNaN, graph.View(), {}, ThreadedFor(3));
    ADD_FAILURE() << "a NaN posterior must throw";
  }
  catch (const Error& error)
  {
    EXPECT_NE(std::string(error.what()).find("face 321"), std::string::npos) << error.what();
  }
}

TEST(PartitionEnergy, BadGraphsAndPosteriorsThrow)
{
  const TestGraph good(2, { { 0, 1, 0.3, true, 1.0 } });
  PosteriorMatrix posteriors(2, 2);
  posteriors << 0.5, 0.5, 0.5, 0.5;
  EXPECT_NO_THROW(BuildPartitionEnergy(posteriors, good.View()));

  TestGraph asymmetric = good;
  asymmetric.neighbours = { 1, 1 }; // face 1 lists itself instead of 0
  EXPECT_THROW(BuildPartitionEnergy(posteriors, asymmetric.View()), Error);
  TestGraph outOfRange = good;
  outOfRange.neighbours = { 5, 0 };
  EXPECT_THROW(BuildPartitionEnergy(posteriors, outOfRange.View()), Error);
  TestGraph nanAngle = good;
  nanAngle.angle[0] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(BuildPartitionEnergy(posteriors, nanAngle.View()), Error);
  TestGraph negativeLength = good;
  negativeLength.length[1] = -1.0;
  EXPECT_THROW(BuildPartitionEnergy(posteriors, negativeLength.View()), Error);
  TestGraph negativeArea = good;
  negativeArea.area[0] = -1.0;
  EXPECT_THROW(BuildPartitionEnergy(posteriors, negativeArea.View()), Error);
  TestGraph nanArea = good;
  nanArea.area[1] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(BuildPartitionEnergy(posteriors, nanArea.View()), Error);
  DualGraphView noAreas = good.View();
  noAreas.FaceArea = nullptr;
  EXPECT_THROW(BuildPartitionEnergy(posteriors, noAreas), Error);
  DualGraphView noLengths = good.View();
  noLengths.EdgeLength = nullptr;
  EXPECT_THROW(BuildPartitionEnergy(posteriors, noLengths), Error);
  PartitionEnergyOptions unweighted;
  unweighted.GeometricWeights = false;
  EXPECT_NO_THROW(BuildPartitionEnergy(posteriors, noLengths, unweighted));
  TestGraph decreasing = good;
  decreasing.offsets = { 0, 2, 1 };
  EXPECT_THROW(BuildPartitionEnergy(posteriors, decreasing.View()), Error);

  PosteriorMatrix wrongRows(3, 2);
  wrongRows.setConstant(0.5);
  EXPECT_THROW(BuildPartitionEnergy(wrongRows, good.View()), Error);
  PosteriorMatrix withNaN = posteriors;
  withNaN(1, 0) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(BuildPartitionEnergy(withNaN, good.View()), Error);
  PartitionEnergyOptions badLambda;
  badLambda.Lambda = -1.0;
  EXPECT_THROW(BuildPartitionEnergy(posteriors, good.View(), badLambda), Error);
}

TEST(AlphaExpansion, SingleMoveIsTheOptimalExpansion)
{
  std::mt19937_64 generator(1234);
  for (int instance = 0; instance < 100; ++instance)
  {
    const std::size_t n = 1 + static_cast<std::size_t>(generator() % 10);
    const PartitionEnergy energy = RandomEnergy(generator, n, 3);
    std::vector<int> labels(n);
    for (int& l : labels)
    {
      l = static_cast<int>(generator() % 3);
    }
    for (int alpha = 0; alpha < 3; ++alpha)
    {
      const std::vector<int> move = OptimalExpansionMove(energy, labels, alpha);
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t mask = 0; mask < (std::size_t(1) << n); ++mask)
      {
        std::vector<int> candidate = labels;
        for (std::size_t f = 0; f < n; ++f)
        {
          if (mask & (std::size_t(1) << f))
          {
            candidate[f] = alpha;
          }
        }
        best = std::min(best, energy.Evaluate(candidate));
      }
      for (std::size_t f = 0; f < n; ++f)
      {
        ASSERT_TRUE(move[f] == labels[f] || move[f] == alpha);
      }
      ASSERT_NEAR(energy.Evaluate(move), best, 1e-9) << "instance " << instance << " alpha " << alpha;
    }
  }
}

TEST(AlphaExpansion, TwoLabelsReachTheExhaustiveOptimum)
{
  std::mt19937_64 generator(2008);
  for (int instance = 0; instance < 200; ++instance)
  {
    const std::size_t n = 1 + static_cast<std::size_t>(generator() % 10);
    const PartitionEnergy energy = RandomEnergy(generator, n, 2);
    const AlphaExpansionResult result = MinimizeByAlphaExpansion(energy);
    const double optimum = energy.Evaluate(ExhaustiveMinimum(energy));
    ASSERT_TRUE(result.Converged);
    ASSERT_NEAR(result.Energy, optimum, 1e-9) << "instance " << instance;
    ASSERT_NEAR(result.Energy, energy.Evaluate(result.Labels), 1e-12);
    ASSERT_LE(result.Energy, energy.Evaluate(MostProbableLabels(energy)) + 1e-12);
  }
}

TEST(AlphaExpansion, ThreeLabelsStayWithinTheFactorTwoBound)
{
  std::mt19937_64 generator(2009);
  int exact = 0;
  for (int instance = 0; instance < 200; ++instance)
  {
    const std::size_t n = 1 + static_cast<std::size_t>(generator() % 9);
    const PartitionEnergy energy = RandomEnergy(generator, n, 3);
    const AlphaExpansionResult result = MinimizeByAlphaExpansion(energy);
    const std::vector<int> optimal = ExhaustiveMinimum(energy);
    const double optimum = energy.Evaluate(optimal);
    const double smoothness = SmoothnessOf(energy, optimal);
    ASSERT_TRUE(result.Converged);
    ASSERT_GE(result.Energy, optimum - 1e-9);
    // Boykov-Veksler-Zabih: E(x) <= E_data(x*) + 2 E_smooth(x*) for a Potts local minimum.
    ASSERT_LE(result.Energy, optimum + smoothness + 1e-9) << "instance " << instance;
    ASSERT_LE(result.Energy, 2.0 * optimum + 1e-9);
    exact += std::abs(result.Energy - optimum) < 1e-9 ? 1 : 0;
  }
  EXPECT_GT(exact, 150); // in practice nearly always optimal on such graphs
}

TEST(AlphaExpansion, EnergyNeverIncreases)
{
  std::mt19937_64 generator(77);
  for (int instance = 0; instance < 50; ++instance)
  {
    const PartitionEnergy energy = RandomEnergy(generator, 10, 4);
    std::vector<int> start(10);
    for (int& l : start)
    {
      l = static_cast<int>(generator() % 4);
    }
    const AlphaExpansionResult result = MinimizeByAlphaExpansion(energy, start);
    ASSERT_EQ(result.EnergyTrace.size(), static_cast<std::size_t>(result.Moves));
    double previous = result.InitialEnergy;
    for (double e : result.EnergyTrace)
    {
      ASSERT_LE(e, previous);
      previous = e;
    }
    ASSERT_EQ(result.Energy, result.EnergyTrace.back());
    ASSERT_NEAR(result.InitialEnergy, energy.Evaluate(start), 1e-12);
  }
}

/// A chain of 10 faces: 0-3 clearly cluster 0, 6-9 clearly cluster 1, 4-5 undecided. The cut
/// must follow the one concave crease, wherever it is.
TEST(AlphaExpansion, CutFollowsTheConcaveCrease)
{
  for (int crease : { 3, 4, 5 })
  {
    std::vector<TestGraph::Edge> edges;
    for (int f = 0; f + 1 < 10; ++f)
    {
      const bool isCrease = f == crease;
      edges.emplace_back(f, f + 1, isCrease ? 1.2 : 0.02, isCrease, 1.0);
    }
    const TestGraph graph(10, edges);
    PosteriorMatrix posteriors(10, 2);
    for (int f = 0; f < 10; ++f)
    {
      const double p = f < 4 ? 0.95 : (f < 6 ? 0.5 : 0.05);
      posteriors(f, 0) = p;
      posteriors(f, 1) = 1.0 - p;
    }
    const PartitionEnergy energy = BuildPartitionEnergy(posteriors, graph.View());
    const AlphaExpansionResult result = MinimizeByAlphaExpansion(energy);
    for (int f = 0; f < 10; ++f)
    {
      EXPECT_EQ(result.Labels[static_cast<std::size_t>(f)], f <= crease ? 0 : 1) << "crease " << crease << " face " << f;
    }
    EXPECT_NEAR(result.Energy, energy.Evaluate(ExhaustiveMinimum(energy)), 1e-9);
  }
}

/// A noisy two-region grid: the cut removes the isolated noise (BK on a larger graph).
TEST(AlphaExpansion, DenoisesAGridAndHandlesThreeLabels)
{
  const int side = 60;
  const std::size_t n = static_cast<std::size_t>(side * side);
  std::vector<TestGraph::Edge> edges;
  for (int y = 0; y < side; ++y)
  {
    for (int x = 0; x < side; ++x)
    {
      const int f = y * side + x;
      if (x + 1 < side)
      {
        edges.emplace_back(f, f + 1, 0.05, false, 1.0);
      }
      if (y + 1 < side)
      {
        edges.emplace_back(f, f + side, 0.05, false, 1.0);
      }
    }
  }
  const TestGraph graph(n, edges);
  std::mt19937_64 generator(5);
  PosteriorMatrix posteriors(static_cast<Eigen::Index>(n), 3);
  std::vector<int> truth(n);
  int noisy = 0;
  for (std::size_t f = 0; f < n; ++f)
  {
    const int x = static_cast<int>(f) % side;
    truth[f] = x < 20 ? 0 : (x < 40 ? 1 : 2);
    int observed = truth[f];
    if (Uniform(generator) < 0.15)
    {
      observed = (observed + 1 + static_cast<int>(generator() % 2)) % 3;
      ++noisy;
    }
    for (int l = 0; l < 3; ++l)
    {
      posteriors(static_cast<Eigen::Index>(f), l) = l == observed ? 0.7 : 0.15;
    }
  }
  ASSERT_GT(noisy, 400);
  // λ 0.03, not the partition's default: at 0.12 the two 60-face cuts cost more than the
  // bands' 0.7-against-0.15 posteriors gain, and the whole grid takes one label.
  PartitionEnergyOptions options;
  options.Lambda = 0.03;
  const PartitionEnergy energy = BuildPartitionEnergy(posteriors, graph.View(), options);
  const AlphaExpansionResult result = MinimizeByAlphaExpansion(energy);
  EXPECT_TRUE(result.Converged);
  EXPECT_LT(result.Energy, result.InitialEnergy);
  int wrong = 0;
  for (std::size_t f = 0; f < n; ++f)
  {
    wrong += result.Labels[f] != truth[f] ? 1 : 0;
  }
  EXPECT_EQ(wrong, 0);
  EXPECT_NEAR(result.Energy, energy.Evaluate(truth), 1e-9);
}

TEST(AlphaExpansion, DegenerateInputsAndAbort)
{
  // An empty mesh may come with no arrays at all.
  const DualGraphView nothing;
  const PartitionEnergy emptyEnergy = BuildPartitionEnergy(PosteriorMatrix(0, 2), nothing);
  EXPECT_EQ(emptyEnergy.FaceCount, 0u);
  EXPECT_TRUE(MinimizeByAlphaExpansion(emptyEnergy).Labels.empty());
  EXPECT_EQ(FindConnectedSegments(nothing, {}, {}).SegmentCount(), 0);

  PartitionEnergy empty;
  empty.LabelCount = 3;
  const AlphaExpansionResult none = MinimizeByAlphaExpansion(empty);
  EXPECT_TRUE(none.Labels.empty());
  EXPECT_EQ(none.Energy, 0.0);
  EXPECT_TRUE(none.Converged);

  std::mt19937_64 generator(9);
  PartitionEnergy single = RandomEnergy(generator, 5, 1);
  const AlphaExpansionResult one = MinimizeByAlphaExpansion(single);
  EXPECT_EQ(one.Labels, std::vector<int>(5, 0));

  // Isolated faces (no pairs): the data argmin is optimal.
  PartitionEnergy isolated = RandomEnergy(generator, 6, 3);
  isolated.PairFirst.clear();
  isolated.PairSecond.clear();
  isolated.PairWeight.clear();
  EXPECT_EQ(MinimizeByAlphaExpansion(isolated).Labels, MostProbableLabels(isolated));

  const PartitionEnergy energy = RandomEnergy(generator, 8, 3);
  EXPECT_THROW(MinimizeByAlphaExpansion(energy, std::vector<int>(7, 0)), Error);
  EXPECT_THROW(MinimizeByAlphaExpansion(energy, std::vector<int>(8, 3)), Error);
  EXPECT_THROW(OptimalExpansionMove(energy, std::vector<int>(8, 0), 3), Error);
  PartitionEnergy badWeight = energy;
  if (!badWeight.PairWeight.empty())
  {
    badWeight.PairWeight[0] = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW(MinimizeByAlphaExpansion(badWeight), Error);
  }

  int calls = 0;
  const AlphaExpansionResult aborted = MinimizeByAlphaExpansion(
    energy, std::vector<int>(8, 0), {}, [&calls](double) { return ++calls < 2; });
  EXPECT_TRUE(aborted.Aborted);
  EXPECT_EQ(aborted.Moves, 2);
  EXPECT_NEAR(aborted.Energy, energy.Evaluate(aborted.Labels), 1e-12);
}

TEST(PartitionEnergy, HierarchyLevels)
{
  const std::vector<int> clusters = { 0, 1, 2, 3, 2, 0 };
  EXPECT_EQ(HierarchyLevel(clusters, 1), std::vector<int>({ 0, 1, 1, 1, 1, 0 }));
  EXPECT_EQ(HierarchyLevel(clusters, 2), std::vector<int>({ 0, 1, 2, 2, 2, 0 }));
  EXPECT_EQ(HierarchyLevel(clusters, 3), clusters);
  EXPECT_THROW(HierarchyLevel(clusters, 0), Error);
  EXPECT_THROW(HierarchyLevel({ -1 }, 1), Error);
}

TEST(PartitionEnergy, ConnectedSegmentsAreNumberedByArea)
{
  // Chain 0-1-2-3-4-5 plus a separate pair 6-7.
  const TestGraph graph(8, { { 0, 1, 0.1, true, 1.0 }, { 1, 2, 0.1, true, 1.0 }, { 2, 3, 0.1, true, 1.0 },
                             { 3, 4, 0.1, true, 1.0 }, { 4, 5, 0.1, true, 1.0 }, { 6, 7, 0.1, true, 1.0 } });
  const std::vector<int> labels = { 0, 0, 1, 1, 0, 2, 0, 0 };
  const std::vector<double> areas = { 1, 1, 3, 3, 0.5, 0.5, 1, 1 };
  const ConnectedSegments segments = FindConnectedSegments(graph.View(), labels, areas);
  // Components: {0,1} area 2, {2,3} area 6, {4} 0.5, {5} 0.5, {6,7} area 2 (label 0 again,
  // but not connected to {0,1}). Ties keep the order of the lowest face.
  EXPECT_EQ(segments.SegmentCount(), 5);
  EXPECT_EQ(segments.Segment, std::vector<int>({ 1, 1, 0, 0, 3, 4, 2, 2 }));
  EXPECT_EQ(segments.Area, std::vector<double>({ 6, 2, 2, 0.5, 0.5 }));
  EXPECT_EQ(segments.Label, std::vector<int>({ 1, 0, 0, 0, 2 }));

  EXPECT_THROW(FindConnectedSegments(graph.View(), { 0, 0 }, areas), Error);
  std::vector<double> badAreas = areas;
  badAreas[3] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(FindConnectedSegments(graph.View(), labels, badAreas), Error);
}

} // namespace
