// SPDX-License-Identifier: BSD-3-Clause
// ExactSum, the ProcessGroup collectives' helpers, and SmoothAndNormalize on processes' shares
// of a surface: equal, bit for bit, to one process over the whole surface.
//
// The processes are threads here (ThreadGroup: a real implementation of the collectives with a
// barrier); tests under MPI (ctest -R MPI) run the same code through ParaView's controller.
#include "ExactSum.h"
#include "Mesh/FaceGraph.h"
#include "Partition/DistributedPartition.h"
#include "Partition/Partition.h"
#include "ProcessGroup.h"
#include "Smoothing/BilateralSmoothing.h"
#include "Smoothing/SmoothAndNormalize.h"
#include "Mesh/Orientation.h"
#include "Mesh/TrianglesOverProcesses.h"
#include "Skeleton/DistributedSkeleton.h"
#include "Skeleton/Skeleton.h"
#include "TestShapes.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <condition_variable>
#include <functional>
#include <limits>
#include <map>
#include <mutex>
#include <numeric>
#include <random>
#include <thread>
#include <tuple>
#include <vector>

namespace
{

using namespace shapediameter;

// ---- ExactSum

TEST(ExactSum, IsCorrectlyRoundedWhereNaiveSumsAreNot)
{
  ExactSum tenths;
  for (int i = 0; i < 10; ++i)
  {
    tenths.Add(0.1);
  }
  EXPECT_EQ(tenths.Rounded(), 1.0); // the naive sum gives 0.9999999999999999

  ExactSum cancelling;
  cancelling.Add(1e100);
  cancelling.Add(1.0);
  cancelling.Add(-1e100);
  EXPECT_EQ(cancelling.Rounded(), 1.0); // the naive sum gives 0

  // 1 + 2^-53 + 2^-106: above the half-way point, so it rounds up (round-half-even on the
  // first two terms alone would round down).
  ExactSum halfWay;
  halfWay.Add(1.0);
  halfWay.Add(0x1.0p-53);
  halfWay.Add(0x1.0p-106);
  EXPECT_EQ(halfWay.Rounded(), 1.0 + 0x1.0p-52);
  EXPECT_EQ(ExactSum().Rounded(), 0.0);
}

TEST(ExactSum, DoesNotDependOnTheOrderOrTheGroupingOfTheTerms)
{
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> length(1e-3, 2.0);
  std::vector<double> terms(20000);
  for (double& term : terms)
  {
    term = length(random);
  }
  ExactSum whole;
  whole.Add(terms);
  double naive = 0.0;
  for (int trial = 0; trial < 5; ++trial)
  {
    std::shuffle(terms.begin(), terms.end(), random);
    // Three groups summed apart, then merged through their partials.
    ExactSum merged;
    for (std::size_t begin : { std::size_t{ 0 }, std::size_t{ 7000 }, std::size_t{ 12345 } })
    {
      const std::size_t end = begin == 0 ? 7000 : (begin == 7000 ? 12345 : terms.size());
      ExactSum part;
      part.Add(std::vector<double>(terms.begin() + static_cast<std::ptrdiff_t>(begin),
        terms.begin() + static_cast<std::ptrdiff_t>(end)));
      merged.Add(part.Partials());
    }
    EXPECT_EQ(merged.Rounded(), whole.Rounded());
    naive = std::accumulate(terms.begin(), terms.end(), 0.0);
  }
  // The exact sum is within half an ulp of the naive one's neighbourhood (a sanity check of
  // the value itself, not of the order independence).
  EXPECT_NEAR(whole.Rounded(), naive, 1e-9 * naive);
}

// ---- A group of threads

/// The collectives for `size` threads, one ThreadGroup per thread (rank).
class ThreadHub
{
public:
  explicit ThreadHub(int size)
    : Size(size)
    , Slots(static_cast<std::size_t>(size))
  {
  }

  /// Each rank's `mine`, all of them in rank order, to every rank.
  std::vector<std::vector<double>> Exchange(int rank, std::vector<double> mine)
  {
    std::unique_lock<std::mutex> lock(this->Mutex);
    this->Slots[static_cast<std::size_t>(rank)] = std::move(mine);
    this->Wait(lock);
    std::vector<std::vector<double>> all = this->Slots;
    this->Wait(lock); // nobody overwrites a slot before every rank has read them
    return all;
  }

  const int Size;

private:
  void Wait(std::unique_lock<std::mutex>& lock)
  {
    const long long generation = this->Generation;
    if (++this->Arrived == this->Size)
    {
      this->Arrived = 0;
      ++this->Generation;
      this->Changed.notify_all();
      return;
    }
    this->Changed.wait(lock, [&] { return this->Generation != generation; });
  }

  std::mutex Mutex;
  std::condition_variable Changed;
  int Arrived = 0;
  long long Generation = 0;
  std::vector<std::vector<double>> Slots;
};

class ThreadGroup final : public ProcessGroup
{
public:
  ThreadGroup(ThreadHub& hub, int rank)
    : Hub(hub)
    , Index(rank)
  {
  }
  std::vector<double> AllGather(const std::vector<double>& values) const override
  {
    std::vector<double> all;
    for (const auto& part : this->Hub.Exchange(this->Index, values))
    {
      all.insert(all.end(), part.begin(), part.end());
    }
    return all;
  }
  void SumInPlace(std::vector<std::int64_t>& values) const override
  {
    const auto all = this->Hub.Exchange(this->Index, std::vector<double>(values.begin(), values.end()));
    for (std::size_t i = 0; i < values.size(); ++i)
    {
      values[i] = 0;
      for (const auto& part : all)
      {
        values[i] += static_cast<std::int64_t>(part[i]); // small counts: exact in a double
      }
    }
  }
  void MaxInPlace(std::vector<double>& values) const override
  {
    const auto all = this->Hub.Exchange(this->Index, values);
    for (const auto& part : all)
    {
      for (std::size_t i = 0; i < values.size(); ++i)
      {
        values[i] = std::max(values[i], part[i]);
      }
    }
  }

  int Rank() const override { return this->Index; }
  std::vector<std::vector<double>> GatherOnFirst(const std::vector<double>& values) const override
  {
    auto all = this->Hub.Exchange(this->Index, values);
    return this->Index == 0 ? all : std::vector<std::vector<double>>{};
  }
  std::vector<double> ScatterFromFirst(const std::function<std::vector<double>(int)>& part) const override
  {
    std::vector<double> flat; // on the first thread: each part's length, then the part
    if (this->Index == 0)
    {
      for (int r = 0; r < this->Hub.Size; ++r)
      {
        const std::vector<double> one = part(r);
        flat.push_back(static_cast<double>(one.size()));
        flat.insert(flat.end(), one.begin(), one.end());
      }
    }
    const std::vector<double> all = this->Hub.Exchange(this->Index, flat)[0];
    std::size_t at = 0;
    for (int r = 0;; ++r)
    {
      const auto length = static_cast<std::size_t>(all[at]);
      if (r == this->Index)
      {
        return std::vector<double>(all.begin() + static_cast<std::ptrdiff_t>(at + 1),
          all.begin() + static_cast<std::ptrdiff_t>(at + 1 + length));
      }
      at += 1 + length;
    }
  }

private:
  ThreadHub& Hub;
  const int Index;
};

/// Runs body(rank, group) on `size` threads at once.
void OnThreads(int size, const std::function<void(int, const ProcessGroup&)>& body)
{
  ThreadHub hub(size);
  std::vector<std::thread> threads;
  for (int rank = 0; rank < size; ++rank)
  {
    threads.emplace_back([&, rank] { body(rank, ThreadGroup(hub, rank)); });
  }
  for (std::thread& thread : threads)
  {
    thread.join();
  }
}

TEST(ProcessGroup, SingleProcessCollectivesAreTheIdentity)
{
  const ProcessGroup& single = SingleProcess();
  std::vector<std::int64_t> counts{ 3, -4 };
  single.SumInPlace(counts);
  EXPECT_EQ(counts, (std::vector<std::int64_t>{ 3, -4 }));
  std::vector<double> values{ 1.5, -2.0 };
  single.MaxInPlace(values);
  EXPECT_EQ(values, (std::vector<double>{ 1.5, -2.0 }));
  EXPECT_EQ(single.AllGather(values), values);
  EXPECT_EQ(OrderStatisticsOverProcesses({ 5.0, -1.0, 3.0, 3.0 }, { 0, 1, 2, 3 }, single),
    (std::vector<double>{ -1.0, 3.0, 3.0, 5.0 }));
}

TEST(ProcessGroup, GatherOnFirstAndScatterFromFirstKeepProcessOrder)
{
  EXPECT_EQ(SingleProcess().Rank(), 0);
  EXPECT_EQ(SingleProcess().GatherOnFirst({ 1.0, 2.0 }), (std::vector<std::vector<double>>{ { 1.0, 2.0 } }));
  EXPECT_EQ(SingleProcess().ScatterFromFirst([](int r) { return std::vector<double>{ 10.0 + r }; }),
    (std::vector<double>{ 10.0 }));
  std::vector<int> partsMade(3, 0);
  std::mutex madeMutex;
  OnThreads(3, [&](int rank, const ProcessGroup& group) {
    EXPECT_EQ(group.Rank(), rank);
    // Process 1 sends nothing: an empty entry keeps its place.
    std::vector<double> mine(rank == 1 ? 0 : static_cast<std::size_t>(rank) + 1, static_cast<double>(rank));
    const std::vector<std::vector<double>> gathered = group.GatherOnFirst(mine);
    if (rank == 0)
    {
      EXPECT_EQ(gathered, (std::vector<std::vector<double>>{ { 0.0 }, {}, { 2.0, 2.0, 2.0 } }));
    }
    else
    {
      EXPECT_TRUE(gathered.empty());
    }
    const std::vector<double> part = group.ScatterFromFirst([&](int r) {
      std::lock_guard<std::mutex> lock(madeMutex);
      ++partsMade[static_cast<std::size_t>(r)];
      EXPECT_EQ(rank, 0) << "parts are made on the first process only";
      return r == 1 ? std::vector<double>{} : std::vector<double>(static_cast<std::size_t>(r) + 2, 100.0 + r);
    });
    EXPECT_EQ(part, rank == 1 ? std::vector<double>{} : std::vector<double>(static_cast<std::size_t>(rank) + 2, 100.0 + rank));
  });
  EXPECT_EQ(partsMade, (std::vector<int>{ 1, 1, 1 }));
}

TEST(ProcessGroup, GatherOnFirstInTurnTakesOneProcessAtATimeInOrder)
{
  // Each process makes its values once, at its turn; the first takes them in process order.
  std::vector<int> made(3, 0);
  std::vector<std::size_t> taken;
  std::mutex mutex;
  OnThreads(3, [&](int rank, const ProcessGroup& group) {
    GatherOnFirstInTurn(
      [&]() {
        std::lock_guard<std::mutex> lock(mutex);
        ++made[static_cast<std::size_t>(rank)];
        return std::vector<double>(static_cast<std::size_t>(rank) + 1, 10.0 * rank);
      },
      [&](std::size_t process, std::vector<double>&& values) {
        std::lock_guard<std::mutex> lock(mutex);
        EXPECT_EQ(rank, 0) << "taken on the first process only";
        EXPECT_EQ(values, std::vector<double>(process + 1, 10.0 * static_cast<double>(process)));
        taken.push_back(process);
      },
      group);
  });
  EXPECT_EQ(made, (std::vector<int>{ 1, 1, 1 }));
  EXPECT_EQ(taken, (std::vector<std::size_t>{ 0, 1, 2 }));
}

TEST(ProcessGroup, OrderStatisticsCoverTheWholeRangeOfDoubles)
{
  const double largest = std::numeric_limits<double>::max();
  const std::vector<double> values{ largest, -largest, 1.0, -1e-300, 5e-324, 0.0, 1.0, -2.5, 1e300 };
  std::vector<double> sorted(values);
  std::sort(sorted.begin(), sorted.end());
  std::vector<std::int64_t> ranks(values.size());
  std::iota(ranks.begin(), ranks.end(), 0);
  OnThreads(3, [&](int rank, const ProcessGroup& group) {
    std::vector<double> mine;
    for (std::size_t i = static_cast<std::size_t>(rank); i < values.size(); i += 3)
    {
      mine.push_back(values[i]);
    }
    EXPECT_EQ(OrderStatisticsOverProcesses(mine, ranks, group), sorted);
  });
}

TEST(ProcessGroup, OrderStatisticsRangeAndSpreadEqualThoseOfAllTheValues)
{
  std::mt19937_64 random(5);
  std::lognormal_distribution<double> sdf(0.0, 0.7);
  std::vector<double> values(5003);
  for (double& value : values)
  {
    value = sdf(random);
  }
  values[17] = values[18]; // ties
  values[40] = -0.0;
  values[41] = 0.0;
  const std::vector<std::int64_t> ranks{ 0, 1, 100, 2500, 4902, 5002 };
  std::vector<double> expected;
  for (const std::int64_t rank : ranks)
  {
    std::vector<double> scratch(values);
    std::nth_element(scratch.begin(), scratch.begin() + rank, scratch.end());
    expected.push_back(scratch[static_cast<std::size_t>(rank)]);
  }
  const double expectedSpread = RobustSpread(values);
  const auto [low, high] = std::minmax_element(values.begin(), values.end());
  for (const int processes : { 1, 2, 3, 5 })
  {
    OnThreads(processes, [&](int rank, const ProcessGroup& group) {
      // Uneven shares, one of them empty when there are five.
      std::vector<double> mine;
      for (std::size_t i = 0; i < values.size(); ++i)
      {
        if (static_cast<int>((i * 7) % static_cast<std::size_t>(processes == 5 ? 4 : processes)) == rank)
        {
          mine.push_back(values[i]);
        }
      }
      const std::vector<double> found = OrderStatisticsOverProcesses(mine, ranks, group);
      const double spread = RobustSpreadOverProcesses(mine, group);
      const auto [minimum, maximum] = RangeOverProcesses(mine, group);
      for (std::size_t i = 0; i < ranks.size(); ++i)
      {
        EXPECT_EQ(found[i], expected[i]) << "rank " << ranks[i] << " on " << processes << " processes";
      }
      EXPECT_EQ(spread, expectedSpread);
      EXPECT_EQ(minimum, *low);
      EXPECT_EQ(maximum, *high);
    });
  }
}

// ---- SmoothAndNormalize on shares

/// One process's share of a surface: its faces and every face whose centre lies within
/// `radius` of one of them, in the whole surface's order, with the points they use.
struct Share
{
  PointMatrix Points;
  std::vector<std::int64_t> Offsets{ 0 }, Connectivity;
  std::vector<double> Values;
  std::vector<std::uint8_t> Own;
  std::vector<std::size_t> WholeFace; // per face of the share
  std::vector<std::int64_t> WholePoint; // per point of the share
};

Share MakeShare(const testshapes::TestMesh& mesh, const std::vector<double>& values, const FaceGraph& whole,
  const std::function<bool(std::size_t)>& owns, double radius);

Share MakeShare(const testshapes::TestMesh& mesh, const std::vector<double>& values, const FaceGraph& whole,
  const std::vector<int>& owner, int rank, double radius)
{
  return MakeShare(mesh, values, whole, [&](std::size_t f) { return owner[f] == rank; }, radius);
}

Share MakeShare(const testshapes::TestMesh& mesh, const std::vector<double>& values, const FaceGraph& whole,
  const std::function<bool(std::size_t)>& owns, double radius)
{
  std::vector<std::size_t> own;
  for (std::size_t f = 0; f < values.size(); ++f)
  {
    if (owns(f))
    {
      own.push_back(f);
    }
  }
  Share share;
  std::map<std::int64_t, std::int64_t> pointIndex; // whole -> share, in whole order
  for (std::size_t f = 0; f < values.size(); ++f)
  {
    bool near = owns(f);
    for (std::size_t k = 0; !near && k < own.size(); ++k)
    {
      near = (whole.Centers.row(static_cast<Eigen::Index>(f)) - whole.Centers.row(static_cast<Eigen::Index>(own[k])))
               .norm() <= radius;
    }
    if (!near)
    {
      continue;
    }
    share.WholeFace.push_back(f);
    share.Own.push_back(owns(f) ? 1 : 0);
    share.Values.push_back(values[f]);
    for (int corner = 0; corner < 3; ++corner)
    {
      pointIndex[mesh.Triangles(static_cast<Eigen::Index>(f), corner)] = 0;
    }
  }
  std::int64_t next = 0;
  share.Points.resize(static_cast<Eigen::Index>(pointIndex.size()), 3);
  for (auto& [wholePoint, sharePoint] : pointIndex)
  {
    share.WholePoint.push_back(wholePoint);
    sharePoint = next;
    share.Points.row(next++) = mesh.Points.row(wholePoint);
  }
  for (const std::size_t f : share.WholeFace)
  {
    for (int corner = 0; corner < 3; ++corner)
    {
      share.Connectivity.push_back(pointIndex[mesh.Triangles(static_cast<Eigen::Index>(f), corner)]);
    }
    share.Offsets.push_back(static_cast<std::int64_t>(share.Connectivity.size()));
  }
  return share;
}

TEST(SmoothAndNormalizeOnShares, OwnFacesGetTheSerialValuesBitForBit)
{
  const testshapes::TestMesh mesh = testshapes::MakeCapsule(0.5, 1.5, 24, 6, 10);
  std::vector<double> values;
  std::mt19937_64 random(3);
  for (Eigen::Index f = 0; f < mesh.Faces(); ++f)
  {
    const double unit = static_cast<double>(random() >> 11) * 0x1.0p-53;
    values.push_back((mesh.Points(mesh.Triangles(f, 0), 2) > 0.0 ? 1.0 : 0.6) * (1.0 + 0.1 * unit));
  }
  SmoothAndNormalizeOptions options;
  options.Smoothing.NumberOfIterations = 4;
  const SmoothAndNormalizeResult serial = SmoothAndNormalize(mesh.Points, mesh.Triangles, values, options);
  const FaceGraph& whole = *serial.Graph;
  const double radius = options.Smoothing.NeighborhoodRadius * options.Smoothing.SpatialSigma * whole.MeanEdgeLength;

  for (const int processes : { 2, 3 })
  {
    // Slabs along z by face centre: compact pieces, as the reader's spatial split gives.
    std::vector<int> owner(values.size());
    for (std::size_t f = 0; f < owner.size(); ++f)
    {
      const double z = whole.Centers(static_cast<Eigen::Index>(f), 2);
      owner[f] = std::min(processes - 1, static_cast<int>((z + 2.0) / 4.0 * processes));
    }
    std::vector<int> covered(values.size(), 0);
    std::mutex coveredMutex;
    OnThreads(processes, [&](int rank, const ProcessGroup& group) {
      const Share share = MakeShare(mesh, values, whole, owner, rank, radius * 1.001);
      const FaceShare faceShare{ share.Own, group };
      const SmoothAndNormalizeResult result = SmoothAndNormalize(
        SmoothAndNormalizeInput{ share.Points, share.Offsets, share.Connectivity, share.Values, 0,
          share.Values.size(), &faceShare },
        options);
      ASSERT_FALSE(result.Aborted);
      EXPECT_EQ(result.RangeMinimum, serial.RangeMinimum);
      EXPECT_EQ(result.RangeMaximum, serial.RangeMaximum);
      std::lock_guard<std::mutex> lock(coveredMutex);
      for (std::size_t f = 0; f < share.WholeFace.size(); ++f)
      {
        if (share.Own[f])
        {
          const std::size_t w = share.WholeFace[f];
          ++covered[w];
          EXPECT_EQ(result.Smoothed[f], serial.Smoothed[w]) << "face " << w << ", " << processes << " processes";
          EXPECT_EQ(result.Normalized[f], serial.Normalized[w]) << "face " << w;
        }
      }
    });
    EXPECT_TRUE(std::all_of(covered.begin(), covered.end(), [](int n) { return n == 1; }));
  }

  // The test can fail: without its halo a share's border faces lose neighbours and change.
  OnThreads(2, [&](int rank, const ProcessGroup& group) {
    std::vector<int> owner(values.size());
    for (std::size_t f = 0; f < owner.size(); ++f)
    {
      owner[f] = whole.Centers(static_cast<Eigen::Index>(f), 2) > 0.0 ? 1 : 0;
    }
    const Share share = MakeShare(mesh, values, whole, owner, rank, 0.0);
    const FaceShare faceShare{ share.Own, group };
    const SmoothAndNormalizeResult result = SmoothAndNormalize(
      SmoothAndNormalizeInput{ share.Points, share.Offsets, share.Connectivity, share.Values, 0, share.Values.size(),
        &faceShare },
      options);
    std::size_t differing = 0;
    for (std::size_t f = 0; f < share.WholeFace.size(); ++f)
    {
      differing += result.Smoothed[f] != serial.Smoothed[share.WholeFace[f]] ? 1 : 0;
    }
    EXPECT_GT(differing, 0u);
  });
}

TEST(SmoothAndNormalizeOnShares, FacesSeveralProcessesOwnAreCountedOnce)
{
  // RedistributeDataSet's "assign to all regions": faces near the cut belong to both processes;
  // both smooth them, only the lower one counts them in the whole surface's measures.
  const testshapes::TestMesh mesh = testshapes::MakeCapsule(0.5, 1.5, 24, 6, 10);
  std::vector<double> values;
  for (Eigen::Index f = 0; f < mesh.Faces(); ++f)
  {
    values.push_back(1.0 + 0.05 * static_cast<double>((f * 7919) % 13) + (mesh.Points(mesh.Triangles(f, 0), 2) > 0 ? 0.5 : 0.0));
  }
  SmoothAndNormalizeOptions options;
  const SmoothAndNormalizeResult serial = SmoothAndNormalize(mesh.Points, mesh.Triangles, values, options);
  const FaceGraph& whole = *serial.Graph;
  const double radius = options.Smoothing.NeighborhoodRadius * options.Smoothing.SpatialSigma * whole.MeanEdgeLength;
  const auto z = [&](std::size_t f) { return whole.Centers(static_cast<Eigen::Index>(f), 2); };
  for (const bool countOnce : { true, false })
  {
    std::vector<std::size_t> differing(2, 0);
    OnThreads(2, [&](int rank, const ProcessGroup& group) {
      const auto owns = [&](std::size_t f) { return rank == 0 ? z(f) <= 0.3 : z(f) >= -0.3; };
      const Share share = MakeShare(mesh, values, whole, owns, radius * 1.001);
      std::vector<std::uint8_t> counted(share.Own);
      for (std::size_t f = 0; f < counted.size(); ++f)
      {
        counted[f] = rank == 1 && countOnce && z(share.WholeFace[f]) <= 0.3 ? 0 : counted[f];
      }
      const FaceShare faceShare{ share.Own, group, &counted };
      const SmoothAndNormalizeResult result = SmoothAndNormalize(
        SmoothAndNormalizeInput{ share.Points, share.Offsets, share.Connectivity, share.Values, 0,
          share.Values.size(), &faceShare },
        options);
      for (std::size_t f = 0; f < share.WholeFace.size(); ++f)
      {
        if (share.Own[f])
        {
          differing[static_cast<std::size_t>(rank)] += result.Smoothed[f] != serial.Smoothed[share.WholeFace[f]] ||
              result.Normalized[f] != serial.Normalized[share.WholeFace[f]]
            ? 1
            : 0;
        }
      }
    });
    if (countOnce)
    {
      EXPECT_EQ(differing, (std::vector<std::size_t>{ 0, 0 }));
    }
    else
    {
      EXPECT_GT(differing[0] + differing[1], 0u); // counted twice, the measures change
    }
  }
}

TEST(SmoothAndNormalizeOnShares, AHaloNarrowerThanTheRadiusThrowsOnEveryProcess)
{
  const testshapes::TestMesh mesh = testshapes::MakeCapsule(0.5, 1.5, 24, 6, 10);
  const std::vector<double> values(static_cast<std::size_t>(mesh.Faces()), 1.0);
  const SmoothAndNormalizeOptions options;
  const FaceGraph whole = BuildFaceGraph(mesh.Points, mesh.Triangles);
  const double radius = options.Smoothing.NeighborhoodRadius * (options.Smoothing.SpatialSigma * whole.MeanEdgeLength);
  for (const double width : { 0.99 * radius, 1.01 * radius })
  {
    std::vector<int> threw(2, 0);
    OnThreads(2, [&](int rank, const ProcessGroup& group) {
      std::vector<int> owner(values.size());
      for (std::size_t f = 0; f < owner.size(); ++f)
      {
        owner[f] = whole.Centers(static_cast<Eigen::Index>(f), 2) > 0.0 ? 1 : 0;
      }
      const Share share = MakeShare(mesh, values, whole, owner, rank, width);
      FaceShare faceShare{ share.Own, group };
      faceShare.HaloWidth = width;
      try
      {
        SmoothAndNormalize(SmoothAndNormalizeInput{ share.Points, share.Offsets, share.Connectivity, share.Values, 0,
                             share.Values.size(), &faceShare },
          options);
      }
      catch (const HaloTooNarrowError&)
      {
        threw[static_cast<std::size_t>(rank)] = 1;
      }
    });
    EXPECT_EQ(threw, (std::vector<int>(2, width < radius ? 1 : 0))) << "halo width " << width << ", radius " << radius;
  }
}

TEST(SmoothAndNormalizeOnShares, AConstantFieldNormalizesToZeroAsInASerialRun)
{
  const testshapes::TestMesh mesh = testshapes::MakeCapsule(0.5, 1.5, 24, 6, 10);
  const std::vector<double> values(static_cast<std::size_t>(mesh.Faces()), 0.75);
  const SmoothAndNormalizeResult serial = SmoothAndNormalize(mesh.Points, mesh.Triangles, values);
  const FaceGraph& whole = *serial.Graph;
  const double radius = NeighborhoodRadiusOf(BilateralSmoothingOptions{}, whole.MeanEdgeLength);
  OnThreads(2, [&](int rank, const ProcessGroup& group) {
    std::vector<int> owner(values.size());
    for (std::size_t f = 0; f < owner.size(); ++f)
    {
      owner[f] = whole.Centers(static_cast<Eigen::Index>(f), 2) > 0.0 ? 1 : 0;
    }
    const Share share = MakeShare(mesh, values, whole, owner, rank, radius * 1.001);
    const FaceShare faceShare{ share.Own, group };
    const SmoothAndNormalizeResult result = SmoothAndNormalize(SmoothAndNormalizeInput{ share.Points, share.Offsets,
      share.Connectivity, share.Values, 0, share.Values.size(), &faceShare });
    EXPECT_EQ(result.RangeMinimum, serial.RangeMinimum);
    EXPECT_EQ(result.RangeMaximum, serial.RangeMaximum);
    EXPECT_EQ(result.RangeMinimum, 0.75);
    EXPECT_TRUE(std::all_of(result.Normalized.begin(), result.Normalized.end(), [](double v) { return v == 0.0; }));
  });
}

TEST(SmoothAndNormalizeOnShares, MeanEdgeLengthOverProcessesIsTheWholeSurfaces)
{
  const testshapes::TestMesh mesh = testshapes::MakeCapsule(0.5, 1.5, 24, 6, 10);
  std::vector<std::int64_t> offsets, connectivity;
  TriangleFaces(mesh.Triangles, offsets, connectivity);
  const double serial = BuildFaceGraph(mesh.Points, mesh.Triangles).MeanEdgeLength;
  OnThreads(3, [&](int rank, const ProcessGroup& group) {
    std::vector<std::uint8_t> mine(static_cast<std::size_t>(mesh.Faces()), 0);
    for (std::size_t f = static_cast<std::size_t>(rank); f < mine.size(); f += 3)
    {
      mine[f] = 1;
    }
    EXPECT_EQ(MeanEdgeLengthOverProcesses(mesh.Points, offsets, connectivity, mine, group), serial);
  });
}

TEST(SmoothAndNormalizeOnShares, AnAbortOnOneProcessAbortsEvery)
{
  const testshapes::TestMesh mesh = testshapes::MakeCapsule(0.5, 1.5, 24, 6, 10);
  std::vector<double> values;
  for (Eigen::Index f = 0; f < mesh.Faces(); ++f)
  {
    values.push_back(1.0 + 0.01 * static_cast<double>(f % 7));
  }
  std::vector<std::int64_t> offsets, connectivity;
  TriangleFaces(mesh.Triangles, offsets, connectivity);
  OnThreads(2, [&](int rank, const ProcessGroup& group) {
    // Both hold the whole surface and own half of it: the halo is all the rest.
    std::vector<std::uint8_t> own(values.size(), 0);
    for (std::size_t f = static_cast<std::size_t>(rank); f < own.size(); f += 2)
    {
      own[f] = 1;
    }
    const FaceShare share{ own, group };
    const ProgressCallback stopOnRankOne = [rank](double) { return rank != 1; };
    const SmoothAndNormalizeResult result = SmoothAndNormalize(
      SmoothAndNormalizeInput{ mesh.Points, offsets, connectivity, values, 0, values.size(), &share }, {}, SerialFor,
      stopOnRankOne);
    EXPECT_TRUE(result.Aborted) << "process " << rank;
  });
}


// ---- PartitionBySDF on shares

/// Values of two thicknesses (the capsule's upper and lower halves) with some noise.
std::vector<double> TwoThicknesses(const testshapes::TestMesh& mesh)
{
  std::vector<double> values;
  std::mt19937_64 random(5);
  for (Eigen::Index f = 0; f < mesh.Faces(); ++f)
  {
    const double unit = static_cast<double>(random() >> 11) * 0x1.0p-53;
    values.push_back((mesh.Points(mesh.Triangles(f, 0), 2) > 0.0 ? 0.8 : 0.3) + 0.05 * unit);
  }
  return values;
}

/// PartitionBySDF on `share` with the thread group; global ids = whole face index x idStep
/// (1: dense ids, as the reader's; larger: sparse ids, in the same order).
PartitionResult PartitionShareOf(const Share& share, const ProcessGroup& group, std::int64_t idStep = 1,
  bool pointIds = false, const PartitionOptions& options = {}, const ProgressCallback& progress = {})
{
  std::vector<std::int64_t> ids;
  for (const std::size_t f : share.WholeFace)
  {
    ids.push_back(static_cast<std::int64_t>(f) * idStep + 7);
  }
  const PartitionShare partitionShare{ ids, share.Own, group, pointIds ? &share.WholePoint : nullptr };
  const Eigen::Map<const Eigen::VectorXd> values(share.Values.data(), static_cast<Eigen::Index>(share.Values.size()));
  return PartitionBySDF(PartitionInput{ share.Points, share.Offsets, share.Connectivity, values, nullptr, &partitionShare },
    options, SerialFor, progress);
}

/// Every own face of `share` has the serial partition's results; returns how many faces it checked.
void ExpectSerialPartition(const PartitionResult& serial, const PartitionResult& result, const Share& share)
{
  ASSERT_FALSE(result.Aborted);
  EXPECT_EQ(result.Model.Means, serial.Model.Means);
  EXPECT_EQ(result.Model.Sigmas, serial.Model.Sigmas);
  EXPECT_EQ(result.Model.Weights, serial.Model.Weights);
  EXPECT_EQ(result.Energy, serial.Energy);
  EXPECT_EQ(result.LabelBands, serial.LabelBands);
  EXPECT_EQ(result.Segments.Area, serial.Segments.Area);
  ASSERT_EQ(result.Levels.size(), serial.Levels.size());
  for (std::size_t f = 0; f < share.WholeFace.size(); ++f)
  {
    if (!share.Own[f])
    {
      continue;
    }
    const std::size_t w = share.WholeFace[f];
    EXPECT_EQ(result.Labels[f], serial.Labels[w]) << "face " << w;
    EXPECT_EQ(result.Bands[f], serial.Bands[w]) << "face " << w;
    EXPECT_EQ(result.Segments.Segment[f], serial.Segments.Segment[w]) << "face " << w;
    for (std::size_t level = 0; level < serial.Levels.size(); ++level)
    {
      EXPECT_EQ(result.Levels[level][f], serial.Levels[level][w]) << "face " << w;
    }
    for (Eigen::Index c = 0; c < serial.Probabilities.cols(); ++c)
    {
      EXPECT_EQ(result.Probabilities(static_cast<Eigen::Index>(f), c),
        serial.Probabilities(static_cast<Eigen::Index>(w), c)) << "face " << w;
    }
  }
}

TEST(PartitionOnShares, OwnFacesGetTheSerialPartitionBitForBit)
{
  const testshapes::TestMesh mesh = testshapes::MakeCapsule(0.5, 1.5, 24, 6, 10);
  const std::vector<double> values = TwoThicknesses(mesh);
  const Eigen::Map<const Eigen::VectorXd> wholeValues(values.data(), static_cast<Eigen::Index>(values.size()));
  const PartitionResult serial = PartitionBySDF(mesh.Points, mesh.Triangles, wholeValues);
  ASSERT_GE(serial.Model.ComponentCount(), 2);
  ASSERT_GE(serial.Segments.SegmentCount(), 2); // the test can fail: there is a boundary to cut
  const FaceGraph& whole = *serial.Graph;
  // The farthest apart two adjacent faces' centres are: a halo that wide holds every neighbour.
  const double width = *std::max_element(whole.CenterDistances.begin(), whole.CenterDistances.end());

  for (const auto& [processes, idStep] : { std::pair{ 2, 1 }, std::pair{ 3, 1 }, std::pair{ 3, 1000 } })
  {
    std::vector<int> owner(values.size());
    for (std::size_t f = 0; f < owner.size(); ++f)
    {
      owner[f] = std::min(processes - 1, static_cast<int>((whole.Centers(static_cast<Eigen::Index>(f), 2) + 2.0) / 4.0 * processes));
    }
    std::vector<int> covered(values.size(), 0);
    std::mutex coveredMutex;
    OnThreads(processes, [&, processes = processes, idStep = idStep](int rank, const ProcessGroup& group) {
      const Share share = MakeShare(mesh, values, whole, owner, rank, width * 1.001);
      const PartitionResult result = PartitionShareOf(share, group, idStep);
      std::lock_guard<std::mutex> lock(coveredMutex);
      ExpectSerialPartition(serial, result, share);
      EXPECT_EQ(result.Histogram.Counts, rank == 0 ? serial.Histogram.Counts : std::vector<double>{});
      for (std::size_t f = 0; f < share.WholeFace.size(); ++f)
      {
        covered[share.WholeFace[f]] += share.Own[f];
      }
    });
    EXPECT_TRUE(std::all_of(covered.begin(), covered.end(), [](int n) { return n == 1; }));
  }

  // Faces both processes own (RedistributeDataSet's "assign to all regions"): the same results on both.
  OnThreads(2, [&](int rank, const ProcessGroup& group) {
    const auto owns = [&](std::size_t f) {
      const double z = whole.Centers(static_cast<Eigen::Index>(f), 2);
      return rank == 0 ? z < 0.2 : z > -0.2;
    };
    const Share share = MakeShare(mesh, values, whole, owns, width * 1.001);
    ExpectSerialPartition(serial, PartitionShareOf(share, group), share);
  });
}

// Above DirectBelowFaces the cut runs on every process's faces (Partition/DistributedCut.h):
// clusters joined across the pieces, the coarse graph and the bands on the first process.
TEST(PartitionOnShares, TheCutOnEveryProcessGivesTheSerialPartitionBitForBit)
{
  const testshapes::TestMesh mesh = testshapes::MakeCapsule(0.5, 1.5, 64, 16, 40);
  const std::vector<double> values = TwoThicknesses(mesh);
  const Eigen::Map<const Eigen::VectorXd> wholeValues(values.data(), static_cast<Eigen::Index>(values.size()));
  PartitionOptions options;
  options.Multilevel.DirectBelowFaces = 300;
  options.Multilevel.BandRings = 3; // bands that cross the pieces' borders and stop short of others
  const PartitionResult serial = PartitionBySDF(mesh.Points, mesh.Triangles, wholeValues, options);
  ASSERT_GT(static_cast<std::size_t>(mesh.Faces()), 4 * options.Multilevel.DirectBelowFaces); // coarsened twice
  ASSERT_GE(serial.Segments.SegmentCount(), 2);
  const FaceGraph& whole = *serial.Graph;
  const double width = *std::max_element(whole.CenterDistances.begin(), whole.CenterDistances.end());
  for (const auto& [processes, idStep] : { std::pair{ 2, 1 }, std::pair{ 3, 1000 }, std::pair{ 4, 1 } })
  {
    std::vector<int> owner(values.size());
    for (std::size_t f = 0; f < owner.size(); ++f)
    {
      // Pieces across the thickness boundary (z = 0) and around the axis: borders everywhere.
      const Eigen::RowVector3d c = whole.Centers.row(static_cast<Eigen::Index>(f));
      owner[f] = static_cast<int>(std::floor((std::atan2(c[1], c[0]) + M_PI) / (2.0 * M_PI) * processes)) % processes;
    }
    OnThreads(processes, [&, idStep = idStep](int rank, const ProcessGroup& group) {
      const Share share = MakeShare(mesh, values, whole, owner, rank, width * 1.001);
      const PartitionResult result = PartitionShareOf(share, group, idStep, false, options);
      EXPECT_TRUE(result.CutOverProcesses);
      ExpectSerialPartition(serial, result, share);
    });
  }
}

// Two separate capsules (two components, a cluster of each on several pieces), one process
// owning no face, small lost regions re-solved.
TEST(PartitionOnShares, TheCutOnEveryProcessCopesWithAnEmptyPieceAndTwoComponents)
{
  const testshapes::TestMesh capsule = testshapes::MakeCapsule(0.5, 1.5, 48, 12, 30);
  testshapes::TestMesh mesh;
  mesh.Points.resize(2 * capsule.Points.rows(), 3);
  mesh.Triangles.resize(2 * capsule.Faces(), 3);
  mesh.Points << capsule.Points, capsule.Points.rowwise() + Eigen::RowVector3d(3.0, 0.0, 0.0);
  mesh.Triangles << capsule.Triangles, capsule.Triangles.array() + capsule.Points.rows();
  const std::vector<double> values = TwoThicknesses(mesh);
  const Eigen::Map<const Eigen::VectorXd> wholeValues(values.data(), static_cast<Eigen::Index>(values.size()));
  PartitionOptions options;
  options.Multilevel.DirectBelowFaces = 500;
  options.Multilevel.LostRegionFaces = 8;
  const PartitionResult serial = PartitionBySDF(mesh.Points, mesh.Triangles, wholeValues, options);
  ASSERT_GE(serial.Segments.SegmentCount(), 4); // two halves on each capsule
  const FaceGraph& whole = *serial.Graph;
  const double width = *std::max_element(whole.CenterDistances.begin(), whole.CenterDistances.end());
  std::vector<int> owner(values.size());
  for (std::size_t f = 0; f < owner.size(); ++f)
  {
    // Slabs across both capsules along y; process 3 gets none.
    owner[f] = whole.Centers(static_cast<Eigen::Index>(f), 1) < -0.15 ? 0 : (whole.Centers(static_cast<Eigen::Index>(f), 1) < 0.15 ? 1 : 2);
  }
  OnThreads(4, [&](int rank, const ProcessGroup& group) {
    const Share share = MakeShare(mesh, values, whole, owner, rank, width * 1.001);
    const PartitionResult result = PartitionShareOf(share, group, 1, false, options);
    EXPECT_TRUE(result.CutOverProcesses);
    ExpectSerialPartition(serial, result, share);
  });
}

TEST(PartitionOnShares, AnAbortDuringTheCutOnEveryProcessAbortsEvery)
{
  const testshapes::TestMesh mesh = testshapes::MakeCapsule(0.5, 1.5, 64, 16, 40);
  const std::vector<double> values = TwoThicknesses(mesh);
  PartitionOptions options;
  options.Multilevel.DirectBelowFaces = 300;
  const FaceGraph whole = BuildFaceGraph(mesh.Points, mesh.Triangles);
  const double width = *std::max_element(whole.CenterDistances.begin(), whole.CenterDistances.end());
  std::vector<int> owner(values.size());
  for (std::size_t f = 0; f < owner.size(); ++f)
  {
    owner[f] = static_cast<int>(f % 3);
  }
  // At 0.1 once the model is fitted (rank 0's first report), then inside the coarse solve.
  for (const double abortAt : { 0.1, 0.3, 0.5 })
  {
    OnThreads(3, [&](int rank, const ProcessGroup& group) {
      const Share share = MakeShare(mesh, values, whole, owner, rank, width * 1.001);
      const PartitionResult result = PartitionShareOf(
        share, group, 1, false, options, [&](double fraction) { return fraction < abortAt; });
      EXPECT_TRUE(result.Aborted) << "process " << rank << ", abort at " << abortAt;
    });
  }
}

TEST(PartitionOnShares, AHaloThatMissesANeighbourThrowsOnEveryProcess)
{
  const testshapes::TestMesh mesh = testshapes::MakeCapsule(0.5, 1.5, 24, 6, 10);
  const std::vector<double> values = TwoThicknesses(mesh);
  const FaceGraph whole = BuildFaceGraph(mesh.Points, mesh.Triangles);
  PartitionOptions cutOnEveryProcess; // the same check on the path of Partition/DistributedCut.h
  cutOnEveryProcess.Multilevel.DirectBelowFaces = 100;
  for (const PartitionOptions& options : { PartitionOptions(), cutOnEveryProcess })
  {
    for (const bool oneSided : { false, true })
    {
      std::vector<int> thrown(2, 0);
      OnThreads(2, [&](int rank, const ProcessGroup& group) {
        const auto owns = [&](std::size_t f) { return (whole.Centers(static_cast<Eigen::Index>(f), 2) > 0.0) == (rank == 1); };
        // No halo at all, or (one-sided) a halo on process 1 only: both miss, or one misses, the other.
        const Share share = MakeShare(mesh, values, whole, owns, oneSided && rank == 1 ? 10.0 : 0.0);
        try
        {
          PartitionShareOf(share, group, 1, false, options);
        }
        catch (const HaloTooNarrowError&)
        {
          thrown[static_cast<std::size_t>(rank)] = 1;
        }
      });
      EXPECT_EQ(thrown, (std::vector<int>{ 1, 1 }))
        << (oneSided ? "one-sided" : "no halo") << ", direct below " << options.Multilevel.DirectBelowFaces;
    }
  }
}

TEST(PartitionOnShares, ASeamOfDuplicatedPointsIsNoMissedAdjacencyWithGlobalPointIds)
{
  // The upper half's faces use copies of their points: the halves meet at the equator along
  // sides with equal coordinates but distinct points, which the whole surface does not join.
  testshapes::TestMesh mesh = testshapes::MakeCapsule(0.5, 1.5, 24, 6, 10);
  const Eigen::Index n = mesh.Points.rows();
  mesh.Points.conservativeResize(2 * n, 3);
  mesh.Points.bottomRows(n) = mesh.Points.topRows(n);
  for (Eigen::Index f = 0; f < mesh.Faces(); ++f)
  {
    const double z = (mesh.Points(mesh.Triangles(f, 0), 2) + mesh.Points(mesh.Triangles(f, 1), 2) +
                       mesh.Points(mesh.Triangles(f, 2), 2)) / 3.0;
    if (z > 0.0)
    {
      mesh.Triangles.row(f).array() += static_cast<int>(n);
    }
  }
  const std::vector<double> values = TwoThicknesses(mesh);
  const Eigen::Map<const Eigen::VectorXd> wholeValues(values.data(), static_cast<Eigen::Index>(values.size()));
  const PartitionResult serial = PartitionBySDF(mesh.Points, mesh.Triangles, wholeValues);
  const FaceGraph& whole = *serial.Graph;
  ASSERT_GT(whole.BoundaryEdgeCount, 0u); // the seam is open
  const double width = *std::max_element(whole.CenterDistances.begin(), whole.CenterDistances.end());
  for (const bool pointIds : { true, false })
  {
    std::vector<int> thrown(2, 0);
    OnThreads(2, [&](int rank, const ProcessGroup& group) {
      const auto owns = [&](std::size_t f) { return (whole.Centers(static_cast<Eigen::Index>(f), 2) > 0.0) == (rank == 1); };
      const Share share = MakeShare(mesh, values, whole, owns, width * 1.001);
      try
      {
        const PartitionResult result = PartitionShareOf(share, group, 1, pointIds);
        ExpectSerialPartition(serial, result, share);
      }
      catch (const HaloTooNarrowError&)
      {
        thrown[static_cast<std::size_t>(rank)] = 1;
      }
    });
    // By coordinates the seam's sides look like an adjacency both halos missed: the documented
    // fallback to one process. By the corners' ids they are what they are: open sides.
    EXPECT_EQ(thrown, pointIds ? (std::vector<int>{ 0, 0 }) : (std::vector<int>{ 1, 1 }))
      << (pointIds ? "global point ids" : "coordinates");
  }
}

// ---- The skeleton on shares

/// The serial reference as the adapter computes it: the whole mesh oriented outward, then the
/// skeleton with part labels.
SkeletonResult OrientedSkeleton(testshapes::TestMesh mesh, const std::vector<std::int64_t>& parts,
  const SkeletonOptions& options)
{
  ApplyFlips(mesh.Triangles, OrientOutward(mesh.Points, mesh.Triangles).Flip);
  return ComputeSkeleton(mesh.Points, mesh.Triangles, mesh.Sdf, PointMatrix(0, 3), {}, options, SerialFor, {}, parts);
}

/// A tripod with some triangles wound inward (the first process orients the whole mesh), two
/// parts (the arm along +x and the rest) and a cloud label per face.
struct SkeletonCase
{
  testshapes::TestMesh Mesh;
  std::vector<std::int64_t> Parts;
  std::vector<double> Labels;
  SkeletonOptions Options;

  explicit SkeletonCase(testshapes::TestMesh mesh = testshapes::MakeTripod(5.0, 1.0, 60, 30))
    : Mesh(std::move(mesh))
  {
    for (Eigen::Index f = 0; f < Mesh.Faces(); f += 7)
    {
      std::swap(Mesh.Triangles(f, 1), Mesh.Triangles(f, 2));
    }
    for (Eigen::Index f = 0; f < Mesh.Faces(); ++f)
    {
      const double x = Mesh.Points.row(Mesh.Triangles(f, 0)).x();
      Parts.push_back(x > 1.5 ? 1 : 0);
      Labels.push_back(static_cast<double>(f % 5));
    }
    Options.Sampling.NumberOfSamples = 3000;
  }
};

/// The skeleton of process `rank`'s faces (owns), ids spread by idStep.
DistributedSkeletonResult SkeletonShareOf(const SkeletonCase& shape, const FaceGraph& graph,
  const std::function<bool(std::size_t)>& owns, const ProcessGroup& group, std::int64_t idStep,
  std::vector<std::size_t>& wholeFaces, const ProgressCallback& progress = {})
{
  const Share share = MakeShare(shape.Mesh, shape.Mesh.Sdf, graph, owns, 0.0);
  wholeFaces = share.WholeFace;
  const auto faces = static_cast<Eigen::Index>(share.WholeFace.size());
  TriangleMatrix triangles(faces, 3);
  std::vector<std::int64_t> cells, cellIds, parts;
  std::vector<double> labels;
  for (Eigen::Index f = 0; f < faces; ++f)
  {
    for (int corner = 0; corner < 3; ++corner)
    {
      triangles(f, corner) = share.Connectivity[static_cast<std::size_t>(3 * f + corner)];
    }
    const std::size_t w = share.WholeFace[static_cast<std::size_t>(f)];
    cells.push_back(f);
    cellIds.push_back(static_cast<std::int64_t>(w) * idStep);
    parts.push_back(shape.Parts[w]);
    labels.push_back(shape.Labels[w]);
  }
  std::vector<std::int64_t> pointIds(share.WholePoint.begin(), share.WholePoint.end());
  for (std::int64_t& id : pointIds)
  {
    id *= idStep;
  }
  return ComputeSkeletonOverProcesses(SkeletonShareInput{ share.Points, triangles, cells, share.Values, parts, labels },
    SkeletonShare{ cellIds, pointIds, group }, shape.Options, SerialFor, progress);
}

/// The skeleton on shares of `shape` (slabs along y; with `twice`, the faces near y = 0 belong
/// to both of 2 processes) against the serial one: every process's link, the first's skeleton.
void ExpectTheSerialSkeletonOnShares(const SkeletonCase& shape, const SkeletonResult& serial, int processes,
  std::int64_t idStep, bool twice)
{
  const FaceGraph graph = BuildFaceGraph(shape.Mesh.Points, shape.Mesh.Triangles);
  const auto faces = static_cast<std::size_t>(shape.Mesh.Faces());
  std::vector<int> covered(faces, 0);
  std::mutex coveredMutex;
  OnThreads(processes, [&](int rank, const ProcessGroup& group) {
    const auto owns = [&](std::size_t f) {
      const double y = graph.Centers(static_cast<Eigen::Index>(f), 1);
      if (twice)
      {
        return rank == 0 ? y < 0.5 : y > -0.5;
      }
      return std::min(processes - 1, static_cast<int>((y + 6.0) / 12.0 * processes)) == rank;
    };
    std::vector<std::size_t> wholeFaces;
    const DistributedSkeletonResult result = SkeletonShareOf(shape, graph, owns, group, idStep, wholeFaces);
    std::lock_guard<std::mutex> lock(coveredMutex);
    ASSERT_FALSE(result.Aborted);
    ASSERT_EQ(result.FaceNodeId.size(), wholeFaces.size());
    for (std::size_t f = 0; f < wholeFaces.size(); ++f)
    {
      EXPECT_EQ(result.FaceNodeId[f], serial.FaceNodeId[wholeFaces[f]]) << "face " << wholeFaces[f];
      EXPECT_EQ(result.FaceBoneId[f], serial.FaceBoneId[wholeFaces[f]]) << "face " << wholeFaces[f];
      covered[wholeFaces[f]] = 1;
    }
    if (rank != 0)
    {
      EXPECT_EQ(result.Whole.NodePositions.rows(), 0);
      return;
    }
    EXPECT_TRUE(result.Whole.NodePositions == serial.NodePositions);
    EXPECT_EQ(result.Whole.NodeRadius, serial.NodeRadius);
    EXPECT_EQ(result.Whole.Polylines, serial.Polylines);
    EXPECT_EQ(result.Whole.BoneId, serial.BoneId);
    EXPECT_EQ(result.Whole.NodeBoneId, serial.NodeBoneId);
    EXPECT_TRUE(result.Whole.CloudPositions == serial.CloudPositions);
    EXPECT_EQ(result.Whole.CloudSourceFace, serial.CloudSourceFace);
    ASSERT_EQ(result.CloudLabels.size(), serial.CloudSourceFace.size());
    for (std::size_t p = 0; p < serial.CloudSourceFace.size(); ++p)
    {
      const auto source = static_cast<std::size_t>(serial.CloudSourceFace[p]);
      EXPECT_EQ(result.CloudSourceCellId[p], static_cast<std::int64_t>(source) * idStep);
      EXPECT_EQ(result.CloudLabels[p], shape.Labels[source]);
    }
  });
  EXPECT_TRUE(std::all_of(covered.begin(), covered.end(), [](int n) { return n == 1; }));
}

TEST(SkeletonOnShares, EveryProcessGetsTheSerialLinkAndTheFirstTheSerialSkeleton)
{
  const SkeletonCase shape;
  const SkeletonResult serial = OrientedSkeleton(shape.Mesh, shape.Parts, shape.Options);
  ASSERT_GE(serial.BoneLength.size(), 3u); // the test can fail: three arms, bones to link
  for (const auto& [processes, idStep, twice] :
    { std::tuple{ 2, 1, false }, std::tuple{ 3, 1, false }, std::tuple{ 3, 1000, false }, std::tuple{ 2, 1, true } })
  {
    ExpectTheSerialSkeletonOnShares(shape, serial, processes, idStep, twice);
  }
}

TEST(SkeletonOnShares, ComponentsWithAndWithoutSamplesGetTheSerialLink)
{
  // Two tripods and two spheres too small for any sample, each of which gets the fallback node
  // at its largest face (their faces split over the processes): an icosahedron's faces of
  // equal area (the lowest face wins) and a latitude-longitude sphere's of unequal area, its
  // axis along y and its centre above the split, so that the first process holds only a cap
  // of small faces.
  using testshapes::Concatenate;
  const testshapes::TestMesh tripod = testshapes::MakeTripod(5.0, 1.0, 60, 30);
  const Eigen::Vector3d icosahedronAt(-20.0, 0.0, 0.0), sphereAt(-20.0, 0.6e-4, 10.0);
  Eigen::Matrix3d zToY;
  zToY << 1, 0, 0, 0, 0, 1, 0, -1, 0;
  testshapes::TestMesh specks = Concatenate(testshapes::MakeIcosphere(1, 1e-4, icosahedronAt),
    testshapes::Transformed(testshapes::MakeSphere(1e-4, 8, 6), zToY, sphereAt));
  specks.Sdf.assign(static_cast<std::size_t>(specks.Faces()), 2e-4);
  const SkeletonCase shape(Concatenate(Concatenate(tripod,
    testshapes::Transformed(tripod, Eigen::Matrix3d::Identity(), Eigen::Vector3d(20.0, 0.0, 0.0))), specks));
  const SkeletonResult serial = OrientedSkeleton(shape.Mesh, shape.Parts, shape.Options);
  for (const Eigen::Vector3d& speck : { icosahedronAt, sphereAt })
  {
    int nodes = 0; // the fallback node
    for (Eigen::Index n = 0; n < serial.NodePositions.rows(); ++n)
    {
      nodes += (serial.NodePositions.row(n).transpose() - speck).norm() < 1e-3 ? 1 : 0;
    }
    ASSERT_EQ(nodes, 1);
  }
  ASSERT_GE(serial.BoneLength.size(), 7u);
  for (const int processes : { 2, 3 })
  {
    ExpectTheSerialSkeletonOnShares(shape, serial, processes, 1, false);
  }
}

/// Two processes' triangles of a square split along its diagonal into cells 10 (two
/// triangles) and 20 (one): process 0 sends cell 10, process 1 cells 10 and 20 (a cell both
/// hold). `breakShare` lets a test corrupt process 1's share. With `lateColumns`, the columns
/// (the one above and its negative) are gathered again afterwards (GatherTriangleColumnsOnFirst)
/// into it.
std::pair<WholeTriangles, std::string> GatherSquare(
  const std::function<void(TriangleMatrix&, std::vector<std::int64_t>& triangleCell)>& breakShare,
  std::vector<std::vector<double>>* lateColumns = nullptr)
{
  WholeTriangles whole;
  std::string firstError, otherError;
  OnThreads(2, [&](int rank, const ProcessGroup& group) {
    PointMatrix points(4, 3);
    points << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0;
    std::vector<std::int64_t> pointIds{ 100, 101, 102, 103 };
    TriangleMatrix triangles(rank == 0 ? 2 : 3, 3);
    std::vector<std::int64_t> triangleCell, cellIds;
    std::vector<double> column;
    triangles.row(0) << 0, 1, 2;
    triangles.row(1) << 0, 2, 3;
    triangleCell = { 0, 0 };
    cellIds = { 10 };
    if (rank == 1)
    {
      triangles.row(2) << 1, 2, 3;
      triangleCell.push_back(1);
      cellIds.push_back(20);
      breakShare(triangles, triangleCell);
    }
    for (Eigen::Index t = 0; t < triangles.rows(); ++t)
    {
      column.push_back(10.0 * rank + static_cast<double>(t));
    }
    try
    {
      WholeTriangles mine =
        GatherTrianglesOnFirst(TriangleShare{ points, triangles, triangleCell, cellIds, pointIds, { &column } }, group);
      if (lateColumns)
      {
        std::vector<double> negative;
        for (const double value : column)
        {
          negative.push_back(-value);
        }
        std::vector<std::vector<double>> late = GatherTriangleColumnsOnFirst(
          { &column, &negative }, mine.ProcessTriangles, static_cast<std::size_t>(mine.Triangles.rows()), group);
        if (rank == 0)
        {
          *lateColumns = std::move(late);
        }
        else
        {
          EXPECT_TRUE(late.empty());
        }
      }
      if (rank == 0)
      {
        whole = std::move(mine);
      }
    }
    catch (const Error& error)
    {
      (rank == 0 ? firstError : otherError) = error.what();
    }
  });
  EXPECT_EQ(otherError, "") << "only the first process assembles";
  return { std::move(whole), firstError };
}

TEST(TrianglesOverProcesses, TheWholeMeshTakesEachCellOnceInIdOrder)
{
  const auto [whole, error] = GatherSquare([](TriangleMatrix&, std::vector<std::int64_t>&) {});
  ASSERT_EQ(error, "");
  ASSERT_EQ(whole.Triangles.rows(), 3);
  EXPECT_EQ(whole.Points.rows(), 4);
  EXPECT_EQ(whole.TriangleCellId, (std::vector<std::int64_t>{ 10, 10, 20 }));
  // Cell 10's triangles come from process 0 (the lowest that holds it), cell 20's from 1.
  EXPECT_EQ(whole.Columns[0], (std::vector<double>{ 0.0, 1.0, 12.0 }));
  EXPECT_EQ(whole.ProcessTriangles, (std::vector<std::vector<std::int64_t>>{ { 0, 1 }, { 0, 1, 2 } }));
  EXPECT_EQ(whole.Triangles(2, 0), 1);
}

TEST(TrianglesOverProcesses, ColumnsGatheredLaterAreLaidOutAsTheMeshsOwn)
{
  std::vector<std::vector<double>> late;
  const auto [whole, error] = GatherSquare([](TriangleMatrix&, std::vector<std::int64_t>&) {}, &late);
  ASSERT_EQ(error, "");
  ASSERT_EQ(late.size(), 2u);
  EXPECT_EQ(late[0], whole.Columns[0]) << "cell 10 from process 0, cell 20 from process 1";
  EXPECT_EQ(late[1], (std::vector<double>{ -0.0, -1.0, -12.0 }));
}

TEST(TrianglesOverProcesses, ACellTriangulatedDifferentlyThrowsOnTheFirstAfterEveryGather)
{
  // Process 1 gives cell 10 one triangle and cell 20 two: the cells' counts disagree.
  const auto [whole, error] = GatherSquare([](TriangleMatrix&, std::vector<std::int64_t>& triangleCell) {
    triangleCell = { 0, 1, 1 };
  });
  EXPECT_EQ(error, "triangles over processes: two processes triangulate cell 10 differently");
}

TEST(SkeletonOnShares, AnAbortOnTheFirstProcessAbortsEvery)
{
  const SkeletonCase shape;
  const FaceGraph graph = BuildFaceGraph(shape.Mesh.Points, shape.Mesh.Triangles);
  OnThreads(3, [&](int rank, const ProcessGroup& group) {
    const auto owns = [&](std::size_t f) { return static_cast<int>(f % 3) == rank; };
    std::vector<std::size_t> wholeFaces;
    const DistributedSkeletonResult result =
      SkeletonShareOf(shape, graph, owns, group, 1, wholeFaces, [](double progress) { return progress < 0.5; });
    EXPECT_TRUE(result.Aborted) << "process " << rank;
    EXPECT_TRUE(result.FaceNodeId.empty());
  });
}

} // namespace
