// SPDX-License-Identifier: BSD-3-Clause
// Cost of the face graph, the bilateral smoothing and the log normalisation.
//
// Product budget: smoothing + normalisation on ~208k faces <= 15 % of the SDF time
// (about 1.3 s with Embree on 2 threads), i.e. well under 0.2 s on 2 threads.
// Meshes: a torus of 2 * 520 * 200 = 208,000 triangles (and 4x that, 832,000, for the
// face graph), with a synthetic noisy two-level field as SDF.
// Ratios are printed as counters of BM_SmoothingStep208k: fraction_of_sdf (face graph +
// smoothing + normalisation, wall clock / 1.3 s), smooth_norm_fraction (smoothing +
// normalisation only) and cpu_fraction_of_sdf (process CPU time / threads / 1.3 s, the
// figure an otherwise idle machine would give).
#include "Smoothing/BilateralSmoothing.h"
#include "Mesh/FaceGraph.h"
#include "Smoothing/Normalization.h"
#include "Smoothing/SmoothAndNormalize.h"
#include "TestShapes.h"

#include <benchmark/benchmark.h>

#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace
{

using namespace shapediameter;

constexpr double SdfSecondsOnTwoThreads = 1.3; // measured Embree SDF time on 208k faces

// Two plateaus (0.2 and 0.6, like a limb and a torso) plus 5 % uniform noise.
std::vector<double> SyntheticSdf(const FaceGraph& graph)
{
  std::mt19937_64 random(12345);
  std::vector<double> values(graph.FaceCount());
  for (std::size_t f = 0; f < values.size(); ++f)
  {
    const double base = graph.Centers(static_cast<Eigen::Index>(f), 0) > 0.0 ? 0.6 : 0.2;
    const double unit = static_cast<double>(random() >> 11) * 0x1.0p-53;
    values[f] = base * (1.0 + 0.05 * (2.0 * unit - 1.0));
  }
  return values;
}

const testshapes::TestMesh& Torus208k()
{
  static const testshapes::TestMesh torus = testshapes::MakeTorus(1.0, 0.3, 520, 200);
  return torus;
}

void BM_BuildFaceGraph208k(benchmark::State& state)
{
  const testshapes::TestMesh& torus = Torus208k();
  const ParallelFor parallelFor = ThreadedFor(static_cast<unsigned>(state.range(0)));
  for (auto _ : state)
  {
    benchmark::DoNotOptimize(BuildFaceGraph(torus.Points, torus.Triangles, parallelFor));
  }
  state.counters["faces"] = static_cast<double>(torus.Triangles.rows());
}
BENCHMARK(BM_BuildFaceGraph208k)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_BuildFaceGraph832k(benchmark::State& state)
{
  static const testshapes::TestMesh torus = testshapes::MakeTorus(1.0, 0.3, 1040, 400);
  const ParallelFor parallelFor = ThreadedFor(static_cast<unsigned>(state.range(0)));
  for (auto _ : state)
  {
    benchmark::DoNotOptimize(BuildFaceGraph(torus.Points, torus.Triangles, parallelFor));
  }
  state.counters["faces"] = static_cast<double>(torus.Triangles.rows());
}
BENCHMARK(BM_BuildFaceGraph832k)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_SmoothBilateral208k(benchmark::State& state)
{
  const testshapes::TestMesh& torus = Torus208k();
  const ParallelFor parallelFor = ThreadedFor(static_cast<unsigned>(state.range(0)));
  const FaceGraph graph = BuildFaceGraph(torus.Points, torus.Triangles, parallelFor);
  const std::vector<double> sdf = SyntheticSdf(graph);
  for (auto _ : state)
  {
    benchmark::DoNotOptimize(SmoothBilateral(graph, sdf, {}, parallelFor));
  }
}
BENCHMARK(BM_SmoothBilateral208k)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

void BM_NormalizeLogarithmic208k(benchmark::State& state)
{
  const testshapes::TestMesh& torus = Torus208k();
  const FaceGraph graph = BuildFaceGraph(torus.Points, torus.Triangles);
  const std::vector<double> sdf = SyntheticSdf(graph);
  for (auto _ : state)
  {
    benchmark::DoNotOptimize(NormalizeLogarithmic(sdf));
  }
}
BENCHMARK(BM_NormalizeLogarithmic208k)->Unit(benchmark::kMillisecond)->UseRealTime();

// The whole step as the adapter runs it (SmoothAndNormalize): face graph, smoothing,
// normalisation.
void BM_SmoothingStep208k(benchmark::State& state)
{
  const testshapes::TestMesh& torus = Torus208k();
  const ParallelFor parallelFor = ThreadedFor(static_cast<unsigned>(state.range(0)));
  const std::vector<double> sdf = SyntheticSdf(BuildFaceGraph(torus.Points, torus.Triangles));
  double seconds = 0.0;
  double smoothingSeconds = 0.0;
  double cpuSeconds = 0.0;
  for (auto _ : state)
  {
    const std::clock_t cpuStart = std::clock();
    const auto start = std::chrono::steady_clock::now();
    const SmoothAndNormalizeResult result = SmoothAndNormalize(torus.Points, torus.Triangles, sdf, {}, parallelFor);
    benchmark::DoNotOptimize(result.Normalized.data());
    const auto end = std::chrono::steady_clock::now();
    cpuSeconds += static_cast<double>(std::clock() - cpuStart) / CLOCKS_PER_SEC;
    seconds += std::chrono::duration<double>(end - start).count();
    smoothingSeconds += (result.Timings.SmoothingMs + result.Timings.NormalizationMs) / 1000.0;
  }
  const auto iterations = static_cast<double>(state.iterations());
  // Wall-clock ratios (inflated when other processes share the cores) ...
  state.counters["fraction_of_sdf"] = seconds / iterations / SdfSecondsOnTwoThreads;
  state.counters["smooth_norm_fraction"] = smoothingSeconds / iterations / SdfSecondsOnTwoThreads;
  // ... and the same from CPU time spread over the threads (what an idle machine gives).
  state.counters["cpu_fraction_of_sdf"] =
    cpuSeconds / iterations / static_cast<double>(state.range(0)) / SdfSecondsOnTwoThreads;
}
BENCHMARK(BM_SmoothingStep208k)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

} // namespace
// No main(): link with benchmark_main (like gtest_main for the tests).
