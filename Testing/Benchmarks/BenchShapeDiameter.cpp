// SPDX-License-Identifier: BSD-3-Clause
// Google Benchmark of the shape diameter function against raw Embree.
//
// BM_RawEmbree casts exactly the rays of the SDF (same origins, same cone pattern and frames,
// 30 rays, 120 degrees) with plain rtcIntersect1 and the same intersection filter (reject the
// source triangle and hits whose geometric normal Ng has a non-negative dot product with the
// origin normal), keeping the first valid hit only: no statistics, no double-precision
// refinement, no virtual calls. It includes Embree directly on purpose: it is the independent
// baseline, not product code (RawEmbreeBaseline.h, shared with BenchPipeline).
// BM_ShapeDiameter runs the full core (EmbreeRayCaster + ComputeShapeDiameter). The /2
// variants use ThreadedFor(2); the *WithBuild variants include building the BVH (and, for
// the SDF, the face origins). The /1 variants run on one thread and measure
// CPU time, which is far less noisy on a shared machine. Each benchmark is repeated 5 times;
// after the runs the program prints the ratios SDF / raw of the fastest repetitions (add
// --benchmark_enable_random_interleaving=true to interleave them); the target is <= 1.25.
// BM_PairedRatio alternates the two within each iteration and reports their ratio as a
// counter: the number to trust when other processes share the machine.
//
// Mesh: the OFF file named by the environment variable SHAPEDIAMETER_BENCH_MESH (n-gons are
// fan-triangulated by the tiny reader below), else a generated icosphere of 52020 faces.
#include "RayCasting/ConeSampling.h"
#include "RayCasting/EmbreeRayCaster.h"
#include "TestShapes.h"
#include "RawEmbreeBaseline.h"
#include "SDF/SDF.h"
#include "SDF/ShapeDiameter.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{
using namespace shapediameter;


/// Minimal ASCII OFF reader (the product's parser is OFFParser): "OFF", counts, vertices,
/// faces; '#' comments; polygons fan-triangulated.
testshapes::TestMesh ReadOFF(const std::string& path)
{
  std::ifstream file(path);
  if (!file)
  {
    throw std::runtime_error("cannot open " + path);
  }
  std::stringstream text;
  for (std::string line; std::getline(file, line);)
  {
    text << line.substr(0, line.find('#')) << '\n';
  }
  std::string keyword;
  text >> keyword;
  if (keyword.find("OFF") == std::string::npos)
  {
    throw std::runtime_error(path + ": not an OFF file");
  }
  long vertexCount = 0, faceCount = 0, edgeCount = 0;
  text >> vertexCount >> faceCount >> edgeCount;
  testshapes::TestMesh mesh;
  mesh.Points.resize(vertexCount, 3);
  for (long v = 0; v < vertexCount; ++v)
  {
    text >> mesh.Points(v, 0) >> mesh.Points(v, 1) >> mesh.Points(v, 2);
  }
  std::vector<std::int64_t> triangles;
  for (long f = 0; f < faceCount; ++f)
  {
    int n = 0;
    text >> n;
    std::vector<std::int64_t> polygon(static_cast<std::size_t>(n));
    for (auto& index : polygon)
    {
      text >> index;
    }
    std::string colour;
    std::getline(text, colour);
    for (int k = 1; k + 1 < n; ++k)
    {
      triangles.insert(triangles.end(), { polygon[0], polygon[static_cast<std::size_t>(k)],
                                          polygon[static_cast<std::size_t>(k + 1)] });
    }
  }
  if (!text)
  {
    throw std::runtime_error(path + ": truncated OFF file");
  }
  mesh.Triangles = Eigen::Map<TriangleMatrix>(
    triangles.data(), static_cast<Eigen::Index>(triangles.size() / 3), 3);
  return mesh;
}

const testshapes::TestMesh& BenchMesh()
{
  static const testshapes::TestMesh mesh = [] {
    const char* path = std::getenv("SHAPEDIAMETER_BENCH_MESH");
    testshapes::TestMesh m =
      path && *path ? ReadOFF(path) : testshapes::MakeIcosphere(51, 1.0);
    std::cout << "mesh: " << (path && *path ? path : "icosphere") << ", " << m.Points.rows()
              << " points, " << m.Triangles.rows() << " triangles" << std::endl;
    return m;
  }();
  return mesh;
}

// ---------------------------------------------------------------------------------------
// Raw Embree baseline (shared with BenchPipeline: RawEmbreeBaseline.h)

using bench::CastRaw;
using bench::RawRays;
using bench::RawScene;

/// The SDF's rays, precomputed in float: 30 directions per face.
const RawRays& BenchRays()
{
  static const RawRays rays = bench::MakeRawRays(BenchMesh().Points, BenchMesh().Triangles);
  return rays;
}

/// SerialFor for 1 thread, else ThreadedFor.
ParallelFor MakeParallelFor(benchmark::State& state)
{
  const auto threads = static_cast<unsigned>(state.range(0));
  return threads <= 1 ? ParallelFor(SerialFor) : ThreadedFor(threads);
}

void BM_RawEmbree(benchmark::State& state)
{
  const RawScene scene(BenchMesh().Points, BenchMesh().Triangles);
  const RawRays& rays = BenchRays();
  const ParallelFor parallelFor = MakeParallelFor(state);
  for (auto _ : state)
  {
    benchmark::DoNotOptimize(CastRaw(scene, rays, parallelFor));
  }
  state.counters["rays/s"] = benchmark::Counter(
    static_cast<double>(rays.Directions.size() / 3), benchmark::Counter::kIsIterationInvariantRate);
}

void BM_RawEmbreeWithBuild(benchmark::State& state)
{
  const RawRays& rays = BenchRays();
  const ParallelFor parallelFor = MakeParallelFor(state);
  for (auto _ : state)
  {
    const RawScene scene(BenchMesh().Points, BenchMesh().Triangles);
    benchmark::DoNotOptimize(CastRaw(scene, rays, parallelFor));
  }
}

// ---------------------------------------------------------------------------------------
// The product

void BM_ShapeDiameter(benchmark::State& state)
{
  const testshapes::TestMesh& mesh = BenchMesh();
  const EmbreeRayCaster caster(mesh.Points, mesh.Triangles);
  const RayOrigins origins = MakeFaceOrigins(mesh.Points, mesh.Triangles);
  const ParallelFor parallelFor = MakeParallelFor(state);
  for (auto _ : state)
  {
    const ShapeDiameterResult result =
      ComputeShapeDiameter(caster, origins, ShapeDiameterOptions(), parallelFor);
    benchmark::DoNotOptimize(result.Values.data());
  }
  state.counters["rays/s"] = benchmark::Counter(static_cast<double>(mesh.Triangles.rows()) * 30,
    benchmark::Counter::kIsIterationInvariantRate);
}

void BM_ShapeDiameterWithBuild(benchmark::State& state)
{
  const testshapes::TestMesh& mesh = BenchMesh();
  const ParallelFor parallelFor = MakeParallelFor(state);
  for (auto _ : state)
  {
    const ShapeDiameterResult result =
      ComputeFaceShapeDiameter(mesh.Points, mesh.Triangles, ShapeDiameterOptions(), parallelFor);
    benchmark::DoNotOptimize(result.Values.data());
  }
}

/// Raw and SDF casts alternated within each iteration, so that both see the same machine load;
/// counters: the fastest time of each (ms) and their ratio. The most robust ratio on a shared
/// machine.
void BM_PairedRatio(benchmark::State& state)
{
  const testshapes::TestMesh& mesh = BenchMesh();
  const RawScene scene(mesh.Points, mesh.Triangles);
  const RawRays& rays = BenchRays();
  const EmbreeRayCaster caster(mesh.Points, mesh.Triangles);
  const RayOrigins origins = MakeFaceOrigins(mesh.Points, mesh.Triangles);
  const ParallelFor parallelFor = MakeParallelFor(state);
  using Clock = std::chrono::steady_clock;
  double fastestRaw = std::numeric_limits<double>::infinity();
  double fastestSDF = std::numeric_limits<double>::infinity();
  for (auto _ : state)
  {
    const auto t0 = Clock::now();
    benchmark::DoNotOptimize(CastRaw(scene, rays, parallelFor));
    const auto t1 = Clock::now();
    const ShapeDiameterResult result =
      ComputeShapeDiameter(caster, origins, ShapeDiameterOptions(), parallelFor);
    benchmark::DoNotOptimize(result.Values.data());
    const auto t2 = Clock::now();
    fastestRaw = std::min(fastestRaw, std::chrono::duration<double, std::milli>(t1 - t0).count());
    fastestSDF = std::min(fastestSDF, std::chrono::duration<double, std::milli>(t2 - t1).count());
  }
  state.counters["raw_ms"] = fastestRaw;
  state.counters["sdf_ms"] = fastestSDF;
  state.counters["sdf/raw"] = fastestSDF / fastestRaw;
}

/// Fastest repetition: on a shared machine the other processes only ever add time, so the
/// minimum is the most faithful estimate and gives stable ratios.
double Fastest(const std::vector<double>& times)
{
  return *std::min_element(times.begin(), times.end());
}

void Configure(benchmark::internal::Benchmark* benchmark)
{
  benchmark->Unit(benchmark::kMillisecond)
    ->MinTime(1.0)
    ->Repetitions(5)
    ->ReportAggregatesOnly(true)
    ->ComputeStatistics("min", Fastest);
}

// Argument = threads. With 2 threads the wall-clock time is measured; the single-thread runs
// measure the main thread's CPU time, which a busy machine disturbs much less.
BENCHMARK(BM_RawEmbree)->Arg(2)->UseRealTime()->Apply(Configure);
BENCHMARK(BM_ShapeDiameter)->Arg(2)->UseRealTime()->Apply(Configure);
BENCHMARK(BM_RawEmbreeWithBuild)->Arg(2)->UseRealTime()->Apply(Configure);
BENCHMARK(BM_ShapeDiameterWithBuild)->Arg(2)->UseRealTime()->Apply(Configure);
BENCHMARK(BM_RawEmbree)->Arg(1)->Apply(Configure);
BENCHMARK(BM_ShapeDiameter)->Arg(1)->Apply(Configure);
BENCHMARK(BM_PairedRatio)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(6);

/// Console output, plus the time per iteration of every run for the ratios: real time for the
/// multi-threaded runs, CPU time for the single-thread ones (the fastest repetition).
class RatioReporter : public benchmark::ConsoleReporter
{
public:
  void ReportRuns(const std::vector<Run>& runs) override
  {
    for (const Run& run : runs)
    {
      if (run.run_type == Run::RT_Iteration || run.aggregate_name == "min")
      {
        const bool realTime = run.run_name.time_type.find("real") != std::string::npos;
        this->Times[run.run_name.function_name + "/" + run.run_name.args] =
          realTime ? run.GetAdjustedRealTime() : run.GetAdjustedCPUTime();
      }
    }
    ConsoleReporter::ReportRuns(runs);
  }

  void PrintRatio(const std::string& product, const std::string& baseline) const
  {
    const auto p = this->Times.find(product), b = this->Times.find(baseline);
    if (p != this->Times.end() && b != this->Times.end() && b->second > 0)
    {
      std::printf("ratio %s / %s = %.3f (target <= 1.25)\n", product.c_str(), baseline.c_str(),
        p->second / b->second);
    }
  }

private:
  std::map<std::string, double> Times;
};

} // namespace

int main(int argc, char** argv)
{
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv))
  {
    return 1;
  }
  RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  reporter.PrintRatio("BM_ShapeDiameter/2", "BM_RawEmbree/2");
  reporter.PrintRatio("BM_ShapeDiameterWithBuild/2", "BM_RawEmbreeWithBuild/2");
  reporter.PrintRatio("BM_ShapeDiameter/1", "BM_RawEmbree/1");
  benchmark::Shutdown();
  return 0;
}
