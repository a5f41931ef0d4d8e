// SPDX-License-Identifier: BSD-3-Clause
// Google Benchmark of the whole pipeline through the VTK filters, per stage, with ratios
// measured in the same run.
//
// Usage
//   BenchPipeline [Google Benchmark flags] [MESH.off ...]
//   BenchPipeline --chain-once MESH.off    read + the whole chain once, stage times on stdout
//                                          (for /usr/bin/time -v: peak RSS of the chain)
//   BenchPipeline --accuracy [--tolerance T] MESH...
//                                          the chain with the exact and the adaptive SDF once
//                                          per mesh: times, |dSDFNormalized| (mean, p99, max),
//                                          SDFCluster area agreement after the best label
//                                          matching, skeleton points; a Markdown table
// Meshes: the positional arguments, else SHAPEDIAMETER_BENCH_MESH (one path, or several
// separated by ':'), else Data/armadillo.off. Each benchmark is named <Stage>/<mesh file stem>.
// Environment: SHAPEDIAMETER_BENCH_REPEATS (default 5) timed repeats per benchmark,
// SHAPEDIAMETER_BENCH_THREADS (default 2) NumberOfThreads of every filter.
//
// Benchmarks (every one runs REPEATS iterations and reports min_ms and median_ms counters;
// on a shared machine the minimum is the most faithful estimate, other processes only add):
//   Read          vtkSDFOFFReader.
//   SDF, RawEmbree, Smooth, Partition, Skeleton   one stage alone, on the cached output of
//                 the previous stage (the filter re-executes every iteration).
//   Paired        per iteration: raw Embree (BVH build + cast), the SDF filter and the
//                 smoothing filter; raw and SDF alternate their order every iteration so both
//                 see the same machine load. Counters: sdf_over_raw_min (min SDF / min raw),
//                 sdf_over_raw_median (median of the per-iteration ratios), smooth_over_sdf_*
//                 likewise. Targets: SDF / raw <= 1.25, smooth / SDF <= 0.15 (208k faces).
//   Chain         reader output -> SDF -> Smooth -> Partition -> Skeleton, every stage
//                 re-executed; total and per-stage counters.
//   SDFBreakdown  the SDF filter's steps re-enacted with the same core calls as
//                 vtkShapeDiameterFilter::RequestData (triangulate, orient, BVH, origins,
//                 cast + statistics, face graph, fill), next to the filter itself: where the
//                 filter's time goes beyond the raw cast.
//   SmoothBreakdown the same for vtkSDFBilateralSmooth (face graph, geodesic
//                 neighbourhoods, iterations, normalisation).
//   PartitionBreakdown   vtkSDFGMMPartition's conversion and its one core call
//                 (PartitionBySDF), whose per-step timings are the counters: face graph, cluster
//                 model ("gmm"), posteriors, energy, alpha-expansion, segments, histogram.
//   AdaptivePaired raw Embree (the exact mode's rays), the exact and the adaptive SDF filter,
//                 order rotated every iteration: adaptive_over_raw_*, adaptive_over_exact_*.
//   AdaptiveChain the chain with the exact and with the adaptive SDF, alternating:
//                 chain_ratio_* (adaptive / exact).
//   SDFAbort      abort requested from a ProgressEvent observer at progress 0.5: the time until
//                 Update() returns (abort_latency_*), the largest gap between progress events.
// Every *_min_ms / *_median_ms counter is also in --benchmark_out JSON; Paired and Chain add
// *_cpu_* counters (process CPU time, all threads) that a loaded machine disturbs less.
//
// The raw baseline (RawEmbreeBaseline.h) casts exactly the filter's rays: the triangles come
// from the same triangulation and orientation as the filter's (adapter::Triangulate,
// OrientOutward), the origins and cone pattern from MakeFaceOrigins / MakeConePattern, and it
// runs on the same vtkSMPTools STDThread ParallelFor with the same thread count.
// It uses the module's private SurfaceConversion.h on purpose: the benchmark must see the
// surface exactly as the filters do.
#include "RawEmbreeBaseline.h"

#include "RayCasting/EmbreeRayCaster.h"
#include "Mesh/FaceGraph.h"
#include "LabelMatching.h"
#include "Mesh/Orientation.h"
#include "Partition/Partition.h"
#include "SDF/SDF.h"
#include "SDF/ShapeDiameter.h"
#include "Smoothing/SmoothAndNormalize.h"
#include "SurfaceConversion.h"

#include "vtkCallbackCommand.h"
#include "vtkCellData.h"
#include "vtkIdList.h"
#include "vtkDataArray.h"
#include "vtkNew.h"
#include "vtkSDFOFFReader.h"
#include "vtkPolyData.h"
#include "vtkSDFBilateralSmooth.h"
#include "vtkSDFGMMPartition.h"
#include "vtkSDFSkeleton.h"
#include "vtkShapeDiameterFilter.h"
#include "vtkSmartPointer.h"

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <functional>
#include <iterator>
#include <iostream>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace
{
using namespace shapediameter;
using Clock = std::chrono::steady_clock;

// ---------------------------------------------------------------------------------------
// Settings

int EnvInt(const char* name, int fallback, int lowest)
{
  const char* text = std::getenv(name);
  if (!text || !*text)
  {
    return fallback;
  }
  char* end = nullptr;
  const long value = std::strtol(text, &end, 10);
  if (*end != '\0' || value < lowest || value > 1000000)
  {
    throw std::runtime_error(std::string(name) + "='" + text + "' is not an integer >= " +
      std::to_string(lowest));
  }
  return static_cast<int>(value);
}

int Repeats()
{
  static const int repeats = EnvInt("SHAPEDIAMETER_BENCH_REPEATS", 5, 1);
  return repeats;
}

int Threads()
{
  static const int threads = EnvInt("SHAPEDIAMETER_BENCH_THREADS", 2, 1);
  return threads;
}

double Milliseconds(Clock::time_point begin, Clock::time_point end)
{
  return std::chrono::duration<double, std::milli>(end - begin).count();
}

/// CPU time of the whole process (all threads), ms: less disturbed than the wall clock when
/// other processes compete for the cores, but it also counts threads that spin while waiting.
double ProcessCpuMilliseconds()
{
  timespec now{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &now);
  return 1e3 * static_cast<double>(now.tv_sec) + 1e-6 * static_cast<double>(now.tv_nsec);
}

/// Timed samples of one quantity, in ms.
class Samples
{
public:
  void Add(double ms) { this->Values.push_back(ms); }
  double Min() const
  {
    return this->Values.empty() ? 0.0 : *std::min_element(this->Values.begin(), this->Values.end());
  }
  double Median() const
  {
    if (this->Values.empty())
    {
      return 0.0;
    }
    std::vector<double> sorted = this->Values;
    std::sort(sorted.begin(), sorted.end());
    const std::size_t n = sorted.size();
    return n % 2 == 1 ? sorted[n / 2] : 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]);
  }

private:
  std::vector<double> Values;
};

/// Sets <prefix>min_ms and <prefix>median_ms.
void SetCounters(benchmark::State& state, const std::string& prefix, const Samples& samples)
{
  state.counters[prefix + "min_ms"] = samples.Min();
  state.counters[prefix + "median_ms"] = samples.Median();
}

// ---------------------------------------------------------------------------------------
// Pipeline stages with checks: a filter that fails reports vtkErrorMacro and passes its
// input through quickly, which must never be mistaken for a fast run.

void RequireCellArray(vtkPolyData* data, const char* name, const char* stage)
{
  if (!data || !data->GetCellData()->GetArray(name))
  {
    throw std::runtime_error(std::string(stage) + " produced no cell array '" + name +
      "' (see the VTK error above)");
  }
}

vtkSmartPointer<vtkPolyData> ReadMesh(const std::string& path)
{
  vtkNew<vtkSDFOFFReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkSmartPointer<vtkPolyData> mesh = reader->GetOutput();
  if (mesh->GetNumberOfPolys() == 0)
  {
    throw std::runtime_error("vtkSDFOFFReader read no polygon from " + path);
  }
  return mesh;
}

/// The four filters connected in a pipeline on a given surface.
struct Chain
{
  vtkSmartPointer<vtkPolyData> Surface;
  int SDFMode;
  /// Tolerance of the adaptive SDF; 0 keeps the filter's default.
  double Tolerance = 0.0;
  // The outputs of the last Run (the filters themselves live only during Run).
  vtkSmartPointer<vtkPolyData> SmoothOutput, PartitionOutput, Skeleton;

  explicit Chain(vtkPolyData* surface, int sdfMode = vtkShapeDiameterFilter::EXACT)
    : Surface(surface)
    , SDFMode(sdfMode)
  {
  }

  /// Executes every stage in order in a new pipeline; per-stage wall-clock times in ms (and
  /// process CPU times in `cpuMs` when given). The filters are deleted at the end, so no
  /// face graph they kept (vtkSDFSurfaceAlgorithm::KeepFaceGraph) survives into the next run
  /// or another chain: each run builds it once, as a fresh pipeline does.
  std::vector<double> Run(std::vector<double>* cpuMs = nullptr)
  {
    vtkNew<vtkShapeDiameterFilter> sdf;
    vtkNew<vtkSDFBilateralSmooth> smooth;
    vtkNew<vtkSDFGMMPartition> partition;
    vtkNew<vtkSDFSkeleton> skeleton;
    sdf->SetInputData(this->Surface);
    sdf->SetMode(this->SDFMode);
    if (this->Tolerance > 0)
    {
      sdf->SetTolerance(this->Tolerance);
    }
    smooth->SetInputConnection(sdf->GetOutputPort());
    partition->SetInputConnection(smooth->GetOutputPort());
    skeleton->SetInputConnection(partition->GetOutputPort());
    sdf->SetNumberOfThreads(Threads());
    smooth->SetNumberOfThreads(Threads());
    partition->SetNumberOfThreads(Threads());
    skeleton->SetNumberOfThreads(Threads());
    std::vector<double> ms;
    const auto timed = [&](vtkAlgorithm* stage) {
      const double c0 = ProcessCpuMilliseconds();
      const auto t0 = Clock::now();
      stage->Update();
      ms.push_back(Milliseconds(t0, Clock::now()));
      if (cpuMs)
      {
        cpuMs->push_back(ProcessCpuMilliseconds() - c0);
      }
    };
    timed(sdf);
    RequireCellArray(sdf->GetOutput(), vtkShapeDiameterFilter::SDF_ARRAY_NAME, "vtkShapeDiameterFilter");
    timed(smooth);
    RequireCellArray(smooth->GetOutput(), vtkSDFBilateralSmooth::NORMALIZED_ARRAY_NAME, "vtkSDFBilateralSmooth");
    timed(partition);
    RequireCellArray(partition->GetOutput(), vtkSDFGMMPartition::CLUSTER_ARRAY_NAME, "vtkSDFGMMPartition");
    timed(skeleton);
    if (skeleton->GetSkeleton()->GetNumberOfPoints() == 0)
    {
      throw std::runtime_error("vtkSDFSkeleton produced an empty skeleton (see the VTK error above)");
    }
    this->SmoothOutput = smooth->GetOutput();
    this->PartitionOutput = partition->GetOutput();
    this->Skeleton = skeleton->GetSkeleton();
    return ms;
  }
};

// ---------------------------------------------------------------------------------------
// Per-mesh data, loaded lazily and kept for one mesh at a time (benchmarks of one mesh are
// registered together, so a mesh is read once unless random interleaving is asked for).

struct MeshData
{
  std::string Path;
  vtkSmartPointer<vtkPolyData> Surface;
  // Stage outputs (shallow copies), computed on first use.
  vtkSmartPointer<vtkPolyData> WithSDF, Smoothed, Partitioned;
  // The filter's triangles (triangulated and oriented as vtkShapeDiameterFilter does) and rays.
  std::unique_ptr<adapter::TriangulatedSurface> Triangulated;
  std::unique_ptr<bench::RawRays> Rays;
};

std::unique_ptr<MeshData> CurrentMesh;

MeshData& Mesh(const std::string& path)
{
  if (!CurrentMesh || CurrentMesh->Path != path)
  {
    CurrentMesh.reset(); // free the previous mesh first
    auto mesh = std::make_unique<MeshData>();
    mesh->Path = path;
    mesh->Surface = ReadMesh(path);
    std::clog << "mesh " << path << ": " << mesh->Surface->GetNumberOfPoints() << " points, "
              << mesh->Surface->GetNumberOfPolys() << " polygons" << std::endl;
    CurrentMesh = std::move(mesh);
  }
  return *CurrentMesh;
}

vtkPolyData* WithSDF(MeshData& mesh)
{
  if (!mesh.WithSDF)
  {
    vtkNew<vtkShapeDiameterFilter> sdf;
    sdf->SetInputData(mesh.Surface);
    sdf->SetNumberOfThreads(Threads());
    sdf->Update();
    RequireCellArray(sdf->GetOutput(), vtkShapeDiameterFilter::SDF_ARRAY_NAME, "vtkShapeDiameterFilter");
    mesh.WithSDF = vtkSmartPointer<vtkPolyData>::New();
    mesh.WithSDF->ShallowCopy(sdf->GetOutput());
  }
  return mesh.WithSDF;
}

vtkPolyData* Smoothed(MeshData& mesh)
{
  if (!mesh.Smoothed)
  {
    vtkNew<vtkSDFBilateralSmooth> smooth;
    smooth->SetInputData(WithSDF(mesh));
    smooth->SetNumberOfThreads(Threads());
    smooth->Update();
    RequireCellArray(smooth->GetOutput(), vtkSDFBilateralSmooth::NORMALIZED_ARRAY_NAME, "vtkSDFBilateralSmooth");
    mesh.Smoothed = vtkSmartPointer<vtkPolyData>::New();
    mesh.Smoothed->ShallowCopy(smooth->GetOutput());
  }
  return mesh.Smoothed;
}

vtkPolyData* Partitioned(MeshData& mesh)
{
  if (!mesh.Partitioned)
  {
    vtkNew<vtkSDFGMMPartition> partition;
    partition->SetInputData(Smoothed(mesh));
    partition->SetNumberOfThreads(Threads());
    partition->Update();
    RequireCellArray(partition->GetOutput(), vtkSDFGMMPartition::CLUSTER_ARRAY_NAME, "vtkSDFGMMPartition");
    mesh.Partitioned = vtkSmartPointer<vtkPolyData>::New();
    mesh.Partitioned->ShallowCopy(partition->GetOutput());
  }
  return mesh.Partitioned;
}

/// The triangles exactly as vtkShapeDiameterFilter casts from (AutoOrient on).
const adapter::TriangulatedSurface& Triangulated(MeshData& mesh)
{
  if (!mesh.Triangulated)
  {
    auto surface = std::make_unique<adapter::TriangulatedSurface>();
    const std::string reason = adapter::Triangulate(mesh.Surface, *surface);
    if (!reason.empty())
    {
      throw std::runtime_error("cannot triangulate " + mesh.Path + ": " + reason);
    }
    ApplyFlips(surface->Triangles, OrientOutward(surface->Points, surface->Triangles).Flip);
    mesh.Triangulated = std::move(surface);
  }
  return *mesh.Triangulated;
}

const bench::RawRays& Rays(MeshData& mesh)
{
  if (!mesh.Rays)
  {
    const adapter::TriangulatedSurface& surface = Triangulated(mesh);
    vtkNew<vtkShapeDiameterFilter> defaults;
    mesh.Rays = std::make_unique<bench::RawRays>(bench::MakeRawRays(
      surface.Points, surface.Triangles, defaults->GetNumberOfRays(), defaults->GetConeAngle()));
  }
  return *mesh.Rays;
}

/// Raw Embree: BVH build + cast; build and cast times in ms.
std::pair<double, double> RunRaw(MeshData& mesh, const ParallelFor& parallelFor)
{
  const adapter::TriangulatedSurface& surface = Triangulated(mesh);
  const bench::RawRays& rays = Rays(mesh);
  const auto t0 = Clock::now();
  const bench::RawScene scene(surface.Points, surface.Triangles);
  const auto t1 = Clock::now();
  benchmark::DoNotOptimize(bench::CastRaw(scene, rays, parallelFor));
  const auto t2 = Clock::now();
  return { Milliseconds(t0, t1), Milliseconds(t1, t2) };
}

/// Re-executes `filter` every iteration and reports min/median.
void TimeFilter(benchmark::State& state, vtkAlgorithm* filter, const std::function<void()>& check)
{
  Samples samples;
  for (auto _ : state)
  {
    filter->Modified();
    const auto t0 = Clock::now();
    filter->Update();
    const auto t1 = Clock::now();
    samples.Add(Milliseconds(t0, t1));
    state.SetIterationTime(Milliseconds(t0, t1) / 1000.0);
  }
  check();
  SetCounters(state, "", samples);
}

/// Executes a new `Filter` on `input` every iteration, so that nothing one execution keeps
/// (the face graph, vtkSDFSurfaceAlgorithm::KeepFaceGraph) speeds up the next; min/median.
/// Each output must carry the cell array `arrayName`.
template <typename Filter>
void TimeNewStage(benchmark::State& state, vtkPolyData* input, const char* arrayName, const char* label)
{
  Samples samples;
  for (auto _ : state)
  {
    vtkNew<Filter> filter;
    filter->SetInputData(input);
    filter->SetNumberOfThreads(Threads());
    const auto t0 = Clock::now();
    filter->Update();
    const auto t1 = Clock::now();
    RequireCellArray(filter->GetOutput(), arrayName, label);
    samples.Add(Milliseconds(t0, t1));
    state.SetIterationTime(Milliseconds(t0, t1) / 1000.0);
  }
  SetCounters(state, "", samples);
}

// ---------------------------------------------------------------------------------------
// Benchmarks

/// Set when a benchmark failed: the program then exits with status 1.
bool AnyBenchmarkFailed = false;

/// Runs `body`, turning exceptions into a skipped benchmark with the reason.
void Guarded(benchmark::State& state, const std::function<void()>& body)
{
  try
  {
    body();
  }
  catch (const std::exception& error)
  {
    AnyBenchmarkFailed = true;
    state.SkipWithError(error.what());
  }
}

void BM_Read(benchmark::State& state, const std::string& path)
{
  Guarded(state, [&] {
    vtkNew<vtkSDFOFFReader> reader;
    reader->SetFileName(path.c_str());
    TimeFilter(state, reader, [&] {
      if (reader->GetOutput()->GetNumberOfPolys() == 0)
      {
        throw std::runtime_error("vtkSDFOFFReader read no polygon from " + path);
      }
    });
    state.counters["faces"] = static_cast<double>(reader->GetOutput()->GetNumberOfPolys());
  });
}

void BM_SDF(benchmark::State& state, const std::string& path)
{
  Guarded(state, [&] {
    MeshData& mesh = Mesh(path);
    vtkNew<vtkShapeDiameterFilter> sdf;
    sdf->SetInputData(mesh.Surface);
    sdf->SetNumberOfThreads(Threads());
    TimeFilter(state, sdf, [&] {
      RequireCellArray(sdf->GetOutput(), vtkShapeDiameterFilter::SDF_ARRAY_NAME, "vtkShapeDiameterFilter");
    });
  });
}

void BM_RawEmbree(benchmark::State& state, const std::string& path)
{
  Guarded(state, [&] {
    MeshData& mesh = Mesh(path);
    const ParallelFor parallelFor = adapter::MakeSMPParallelFor(Threads());
    Samples build, cast, total;
    for (auto _ : state)
    {
      const auto [buildMs, castMs] = RunRaw(mesh, parallelFor);
      build.Add(buildMs);
      cast.Add(castMs);
      total.Add(buildMs + castMs);
      state.SetIterationTime((buildMs + castMs) / 1000.0);
    }
    SetCounters(state, "", total);
    SetCounters(state, "build_", build);
    SetCounters(state, "cast_", cast);
    state.counters["rays"] = static_cast<double>(Rays(mesh).NumberOfRays());
  });
}

void BM_Smooth(benchmark::State& state, const std::string& path)
{
  Guarded(state, [&] {
    MeshData& mesh = Mesh(path);
    TimeNewStage<vtkSDFBilateralSmooth>(
      state, WithSDF(mesh), vtkSDFBilateralSmooth::NORMALIZED_ARRAY_NAME, "vtkSDFBilateralSmooth");
  });
}

void BM_Partition(benchmark::State& state, const std::string& path)
{
  Guarded(state, [&] {
    MeshData& mesh = Mesh(path);
    TimeNewStage<vtkSDFGMMPartition>(
      state, Smoothed(mesh), vtkSDFGMMPartition::CLUSTER_ARRAY_NAME, "vtkSDFGMMPartition");
  });
}

void BM_Skeleton(benchmark::State& state, const std::string& path)
{
  Guarded(state, [&] {
    MeshData& mesh = Mesh(path);
    vtkNew<vtkSDFSkeleton> skeleton;
    skeleton->SetInputData(Partitioned(mesh));
    skeleton->SetNumberOfThreads(Threads());
    TimeFilter(state, skeleton, [&] {
      if (skeleton->GetSkeleton()->GetNumberOfPoints() == 0)
      {
        throw std::runtime_error("vtkSDFSkeleton produced an empty skeleton");
      }
    });
  });
}

void BM_Paired(benchmark::State& state, const std::string& path)
{
  Guarded(state, [&] {
    MeshData& mesh = Mesh(path);
    const ParallelFor parallelFor = adapter::MakeSMPParallelFor(Threads());
    vtkNew<vtkShapeDiameterFilter> sdf;
    sdf->SetInputData(mesh.Surface);
    sdf->SetNumberOfThreads(Threads());
    Rays(mesh); // precomputed outside the timing, like the raw baseline's scene inputs

    Samples rawBuild, rawCast, raw, sdfTimes, smoothTimes, sdfOverRaw, smoothOverSdf;
    Samples rawCpu, sdfCpu, smoothCpu;
    int iteration = 0;
    for (auto _ : state)
    {
      double sdfMs = 0, sdfCpuMs = 0, rawCpuMs = 0;
      std::pair<double, double> rawMs;
      const auto runSdf = [&] {
        sdf->Modified();
        const double c0 = ProcessCpuMilliseconds();
        const auto t0 = Clock::now();
        sdf->Update();
        sdfMs = Milliseconds(t0, Clock::now());
        sdfCpuMs = ProcessCpuMilliseconds() - c0;
      };
      const auto runRaw = [&] {
        const double c0 = ProcessCpuMilliseconds();
        rawMs = RunRaw(mesh, parallelFor);
        rawCpuMs = ProcessCpuMilliseconds() - c0;
      };
      if (iteration++ % 2 == 0)
      {
        runRaw();
        runSdf();
      }
      else
      {
        runSdf();
        runRaw();
      }
      RequireCellArray(sdf->GetOutput(), vtkShapeDiameterFilter::SDF_ARRAY_NAME, "vtkShapeDiameterFilter");
      // A new smoothing filter: one re-executed would reuse the face graph it kept.
      vtkNew<vtkSDFBilateralSmooth> smooth;
      smooth->SetInputConnection(sdf->GetOutputPort());
      smooth->SetNumberOfThreads(Threads());
      const double c0 = ProcessCpuMilliseconds();
      const auto t0 = Clock::now();
      smooth->Update();
      const double smoothMs = Milliseconds(t0, Clock::now());
      smoothCpu.Add(ProcessCpuMilliseconds() - c0);
      RequireCellArray(smooth->GetOutput(), vtkSDFBilateralSmooth::NORMALIZED_ARRAY_NAME, "vtkSDFBilateralSmooth");

      const double rawTotal = rawMs.first + rawMs.second;
      rawBuild.Add(rawMs.first);
      rawCast.Add(rawMs.second);
      raw.Add(rawTotal);
      rawCpu.Add(rawCpuMs);
      sdfTimes.Add(sdfMs);
      sdfCpu.Add(sdfCpuMs);
      smoothTimes.Add(smoothMs);
      sdfOverRaw.Add(sdfMs / rawTotal);
      smoothOverSdf.Add(smoothMs / sdfMs);
      state.SetIterationTime((rawTotal + sdfMs + smoothMs) / 1000.0);
    }
    SetCounters(state, "raw_build_", rawBuild);
    SetCounters(state, "raw_cast_", rawCast);
    SetCounters(state, "raw_", raw);
    SetCounters(state, "sdf_", sdfTimes);
    SetCounters(state, "smooth_", smoothTimes);
    SetCounters(state, "raw_cpu_", rawCpu);
    SetCounters(state, "sdf_cpu_", sdfCpu);
    SetCounters(state, "smooth_cpu_", smoothCpu);
    state.counters["sdf_over_raw_min"] = sdfTimes.Min() / raw.Min();
    state.counters["sdf_over_raw_median"] = sdfOverRaw.Median();
    state.counters["smooth_over_sdf_min"] = smoothTimes.Min() / sdfTimes.Min();
    state.counters["smooth_over_sdf_median"] = smoothOverSdf.Median();
    state.counters["sdf_over_raw_cpu"] = sdfCpu.Min() / rawCpu.Min();
    state.counters["smooth_over_sdf_cpu"] = smoothCpu.Min() / sdfCpu.Min();
    state.counters["faces"] = static_cast<double>(mesh.Surface->GetNumberOfPolys());
  });
}

void BM_Chain(benchmark::State& state, const std::string& path)
{
  Guarded(state, [&] {
    MeshData& mesh = Mesh(path);
    Chain chain(mesh.Surface);
    Samples total, totalCpu;
    std::vector<Samples> stages(4), stagesCpu(4);
    for (auto _ : state)
    {
      std::vector<double> cpuMs;
      const std::vector<double> ms = chain.Run(&cpuMs);
      double sum = 0, sumCpu = 0;
      for (std::size_t s = 0; s < ms.size(); ++s)
      {
        stages[s].Add(ms[s]);
        stagesCpu[s].Add(cpuMs[s]);
        sum += ms[s];
        sumCpu += cpuMs[s];
      }
      total.Add(sum);
      totalCpu.Add(sumCpu);
      state.SetIterationTime(sum / 1000.0);
    }
    SetCounters(state, "", total);
    SetCounters(state, "cpu_", totalCpu);
    const std::string names[] = { "sdf_", "smooth_", "partition_", "skeleton_" };
    for (std::size_t s = 0; s < stages.size(); ++s)
    {
      SetCounters(state, names[s], stages[s]);
      SetCounters(state, names[s] + "cpu_", stagesCpu[s]);
    }
    state.counters["faces"] = static_cast<double>(mesh.Surface->GetNumberOfPolys());
  });
}

/// Times `filter` (re-executed) after the steps of one iteration; returns its time in ms.
double TimeOnce(vtkAlgorithm* filter)
{
  filter->Modified();
  const auto t0 = Clock::now();
  filter->Update();
  return Milliseconds(t0, Clock::now());
}

/// Raw Embree (the exact mode's rays), the exact SDF filter and the adaptive one, in an order
/// that rotates every iteration so that all three see the same machine load.
void BM_AdaptivePaired(benchmark::State& state, const std::string& path)
{
  Guarded(state, [&] {
    MeshData& mesh = Mesh(path);
    const ParallelFor parallelFor = adapter::MakeSMPParallelFor(Threads());
    vtkNew<vtkShapeDiameterFilter> exact, adaptive;
    for (vtkShapeDiameterFilter* sdf : { exact.Get(), adaptive.Get() })
    {
      sdf->SetInputData(mesh.Surface);
      sdf->SetNumberOfThreads(Threads());
    }
    adaptive->SetModeToAdaptive();
    Rays(mesh);
    Samples raw, exactTimes, adaptiveTimes, overRaw, overExact;
    int iteration = 0;
    for (auto _ : state)
    {
      double rawMs = 0, exactMs = 0, adaptiveMs = 0;
      const std::function<void()> steps[3] = {
        [&] {
          const auto r = RunRaw(mesh, parallelFor);
          rawMs = r.first + r.second;
        },
        [&] { exactMs = TimeOnce(exact); },
        [&] { adaptiveMs = TimeOnce(adaptive); } };
      for (int k = 0; k < 3; ++k)
      {
        steps[(iteration + k) % 3]();
      }
      ++iteration;
      RequireCellArray(adaptive->GetOutput(), vtkShapeDiameterFilter::SDF_ARRAY_NAME, "vtkShapeDiameterFilter (adaptive)");
      raw.Add(rawMs);
      exactTimes.Add(exactMs);
      adaptiveTimes.Add(adaptiveMs);
      overRaw.Add(adaptiveMs / rawMs);
      overExact.Add(adaptiveMs / exactMs);
      state.SetIterationTime((rawMs + exactMs + adaptiveMs) / 1000.0);
    }
    SetCounters(state, "raw_", raw);
    SetCounters(state, "exact_", exactTimes);
    SetCounters(state, "adaptive_", adaptiveTimes);
    state.counters["adaptive_over_raw_min"] = adaptiveTimes.Min() / raw.Min();
    state.counters["adaptive_over_raw_median"] = overRaw.Median();
    state.counters["adaptive_over_exact_min"] = adaptiveTimes.Min() / exactTimes.Min();
    state.counters["adaptive_over_exact_median"] = overExact.Median();
    state.counters["faces"] = static_cast<double>(mesh.Surface->GetNumberOfPolys());
  });
}

/// The whole chain with the exact and with the adaptive SDF, alternating.
void BM_AdaptiveChain(benchmark::State& state, const std::string& path)
{
  Guarded(state, [&] {
    MeshData& mesh = Mesh(path);
    Chain exact(mesh.Surface), adaptive(mesh.Surface, vtkShapeDiameterFilter::ADAPTIVE);
    Samples exactTotal, adaptiveTotal, ratio;
    std::vector<Samples> stages(4);
    int iteration = 0;
    for (auto _ : state)
    {
      std::vector<double> exactMs, adaptiveMs;
      if (iteration++ % 2 == 0)
      {
        exactMs = exact.Run();
        adaptiveMs = adaptive.Run();
      }
      else
      {
        adaptiveMs = adaptive.Run();
        exactMs = exact.Run();
      }
      double e = 0, a = 0;
      for (std::size_t s = 0; s < 4; ++s)
      {
        e += exactMs[s];
        a += adaptiveMs[s];
        stages[s].Add(adaptiveMs[s]);
      }
      exactTotal.Add(e);
      adaptiveTotal.Add(a);
      ratio.Add(a / e);
      state.SetIterationTime((a + e) / 1000.0);
    }
    SetCounters(state, "exact_chain_", exactTotal);
    SetCounters(state, "adaptive_chain_", adaptiveTotal);
    const std::string names[] = { "sdf_", "smooth_", "partition_", "skeleton_" };
    for (std::size_t s = 0; s < stages.size(); ++s)
    {
      SetCounters(state, "adaptive_" + names[s], stages[s]);
    }
    state.counters["chain_ratio_min"] = adaptiveTotal.Min() / exactTotal.Min();
    state.counters["chain_ratio_median"] = ratio.Median();
    state.counters["faces"] = static_cast<double>(mesh.Surface->GetNumberOfPolys());
  });
}

/// Named steps timed one after the other within an iteration (fastest repeat per step).
class Laps
{
public:
  explicit Laps(std::vector<std::string> names)
    : Names(std::move(names))
    , Steps(this->Names.size())
  {
  }
  void Start()
  {
    this->Next = 0;
    this->Sum = 0;
    this->Last = Clock::now();
  }
  /// Ends the next step.
  void Lap()
  {
    const auto now = Clock::now();
    const double ms = Milliseconds(this->Last, now);
    this->Steps.at(this->Next++).Add(ms);
    this->Sum += ms;
    this->Last = now;
  }
  /// Ends the next steps with times measured elsewhere (ms), e.g. a core result's timings.
  void Record(const std::vector<double>& stepsMs)
  {
    for (const double ms : stepsMs)
    {
      this->Steps.at(this->Next++).Add(ms);
      this->Sum += ms;
    }
    this->Last = Clock::now();
  }
  /// Ends the iteration; returns the sum of its steps.
  double Finish()
  {
    if (this->Next != this->Steps.size())
    {
      throw std::logic_error("Laps: a step was not timed");
    }
    this->Sums.Add(this->Sum);
    return this->Sum;
  }
  void SetCounters(benchmark::State& state) const
  {
    ::SetCounters(state, "steps_", this->Sums);
    for (std::size_t s = 0; s < this->Steps.size(); ++s)
    {
      ::SetCounters(state, this->Names[s] + "_", this->Steps[s]);
    }
  }

private:
  std::vector<std::string> Names;
  std::vector<Samples> Steps;
  Samples Sums;
  std::size_t Next = 0;
  double Sum = 0;
  Clock::time_point Last;
};


/// vtkShapeDiameterFilter::RequestData's steps, each timed, next to the filter itself.
void BM_SDFBreakdown(benchmark::State& state, const std::string& path)
{
  Guarded(state, [&] {
    MeshData& mesh = Mesh(path);
    const ParallelFor parallelFor = adapter::MakeSMPParallelFor(Threads());
    vtkNew<vtkShapeDiameterFilter> sdf;
    sdf->SetInputData(mesh.Surface);
    sdf->SetNumberOfThreads(Threads());
    Laps laps({ "triangulate", "orient", "bvh", "origins", "cast", "facegraph", "fill" });
    Samples filterTimes;
    for (auto _ : state)
    {
      laps.Start();
      adapter::TriangulatedSurface surface;
      const std::string reason = adapter::Triangulate(mesh.Surface, surface);
      if (!reason.empty())
      {
        throw std::runtime_error(reason);
      }
      laps.Lap();
      ApplyFlips(surface.Triangles, OrientOutward(surface.Points, surface.Triangles).Flip);
      laps.Lap();
      const EmbreeRayCaster caster(surface.Points, surface.Triangles);
      laps.Lap();
      const RayOrigins origins = MakeFaceOrigins(surface.Points, surface.Triangles);
      laps.Lap();
      ShapeDiameterResult result =
        ComputeShapeDiameter(caster, origins, ShapeDiameterOptions(), parallelFor);
      laps.Lap();
      const FaceGraph graph = BuildFaceGraph(surface.Points, surface.Triangles, parallelFor);
      laps.Lap();
      FillFromNeighbors(result.Values, result.ValidRays, graph.Offsets, graph.Neighbors);
      laps.Lap();
      laps.Finish();
      benchmark::DoNotOptimize(result.Values.data());

      const double filterMs = TimeOnce(sdf);
      filterTimes.Add(filterMs);
      state.SetIterationTime(filterMs / 1000.0);
    }
    RequireCellArray(sdf->GetOutput(), vtkShapeDiameterFilter::SDF_ARRAY_NAME, "vtkShapeDiameterFilter");
    SetCounters(state, "", filterTimes);
    laps.SetCounters(state);
  });
}

/// vtkSDFBilateralSmooth's steps (default parameters), next to the filter: the filter's
/// conversion, then the core call it makes (SmoothAndNormalize), whose per-step timings are the
/// next laps. "neighborhoods" runs the geodesic neighbourhood searches alone (on a face graph
/// built once, before the iterations; SmoothBilateral repeats them), to show their share of
/// "smooth".
void BM_SmoothBreakdown(benchmark::State& state, const std::string& path)
{
  Guarded(state, [&] {
    MeshData& mesh = Mesh(path);
    vtkPolyData* input = WithSDF(mesh);
    const ParallelFor parallelFor = adapter::MakeSMPParallelFor(Threads());
    vtkNew<vtkSDFBilateralSmooth> smooth;
    smooth->SetInputData(input);
    smooth->SetNumberOfThreads(Threads());
    Laps laps({ "convert", "facegraph", "smooth", "normalize", "neighborhoods" });
    Samples filterTimes;
    const SmoothAndNormalizeOptions options;
    const FaceGraph neighborhoodGraph = [&] {
      std::vector<std::int64_t> offsets, connectivity;
      adapter::PolygonCells(input, offsets, connectivity);
      return BuildFaceGraph(adapter::PointsOf(input), offsets, connectivity, parallelFor);
    }();
    for (auto _ : state)
    {
      laps.Start();
      std::vector<double> values;
      std::string reason = adapter::ReadNamedCellScalars(input, values, vtkShapeDiameterFilter::SDF_ARRAY_NAME);
      std::vector<std::int64_t> offsets, connectivity;
      adapter::PolygonCells(input, offsets, connectivity);
      const auto [first, last] = adapter::PolygonCellRange(input);
      const PointMatrix points = adapter::PointsOf(input);
      if (!reason.empty())
      {
        throw std::runtime_error(reason);
      }
      laps.Lap();
      const SmoothAndNormalizeResult result = SmoothAndNormalize(
        SmoothAndNormalizeInput{ points, offsets, connectivity, values, static_cast<std::size_t>(first),
          static_cast<std::size_t>(last) },
        options, parallelFor);
      benchmark::DoNotOptimize(result.Normalized.data());
      const SmoothAndNormalizeTimings& t = result.Timings;
      laps.Record({ t.FaceGraphMs, t.SmoothingMs, t.NormalizationMs });
      const double radius =
        options.Smoothing.NeighborhoodRadius * options.Smoothing.SpatialSigma * neighborhoodGraph.MeanEdgeLength;
      std::vector<std::size_t> found(neighborhoodGraph.FaceCount());
      parallelFor(neighborhoodGraph.FaceCount(), [&](std::size_t begin, std::size_t end) {
        DualGeodesicSearch search(neighborhoodGraph);
        std::vector<GeodesicNeighbor> neighbors;
        for (std::size_t face = begin; face < end; ++face)
        {
          search.Run(static_cast<std::int64_t>(face), radius, options.Smoothing.MaxNeighbors, neighbors);
          found[face] = neighbors.size();
        }
      });
      benchmark::DoNotOptimize(found.data());
      laps.Lap();
      laps.Finish();

      const double filterMs = TimeOnce(smooth);
      filterTimes.Add(filterMs);
      state.SetIterationTime(filterMs / 1000.0);
    }
    RequireCellArray(smooth->GetOutput(), vtkSDFBilateralSmooth::NORMALIZED_ARRAY_NAME, "vtkSDFBilateralSmooth");
    SetCounters(state, "", filterTimes);
    laps.SetCounters(state);
  });
}

/// vtkSDFGMMPartition's steps (default parameters, no model input), next to the filter: the
/// filter's conversion, then the core call it makes (PartitionBySDF), whose per-step timings
/// are the other laps.
void BM_PartitionBreakdown(benchmark::State& state, const std::string& path)
{
  Guarded(state, [&] {
    MeshData& mesh = Mesh(path);
    vtkPolyData* input = Smoothed(mesh);
    const ParallelFor parallelFor = adapter::MakeSMPParallelFor(Threads());
    vtkNew<vtkSDFGMMPartition> partition;
    partition->SetInputData(input);
    partition->SetNumberOfThreads(Threads());
    Laps laps(
      { "convert", "facegraph", "gmm", "posteriors", "energy", "alphaexpansion", "segments", "histogram" });
    Samples filterTimes;
    for (auto _ : state)
    {
      laps.Start();
      std::vector<double> values;
      const std::string reason =
        adapter::ReadNamedCellScalars(input, values, vtkSDFBilateralSmooth::NORMALIZED_ARRAY_NAME);
      if (!reason.empty())
      {
        throw std::runtime_error(reason);
      }
      std::vector<std::int64_t> offsets, connectivity;
      const auto [first, last] = adapter::PolygonFaces(input, offsets, connectivity);
      const PointMatrix points = adapter::PointsOf(input);
      const Eigen::Map<const Eigen::VectorXd> faceValues(values.data() + first, last - first);
      laps.Lap();
      // The filter's defaults are the core's (the density modes; see PartitionOptions).
      const PartitionResult result =
        PartitionBySDF(PartitionInput{ points, offsets, connectivity, faceValues }, PartitionOptions(), parallelFor);
      benchmark::DoNotOptimize(result.Segments.Segment.data());
      const PartitionTimings& t = result.Timings;
      laps.Record({ t.FaceGraphMs, t.ClusterModelMs, t.PosteriorsMs, t.EnergyMs, t.CutMs, t.SegmentsMs, t.HistogramMs });
      laps.Finish();
      state.counters["alphaexpansion_moves"] = static_cast<double>(result.CutMoves);

      const double filterMs = TimeOnce(partition);
      filterTimes.Add(filterMs);
      state.SetIterationTime(filterMs / 1000.0);
    }
    RequireCellArray(partition->GetOutput(), vtkSDFGMMPartition::CLUSTER_ARRAY_NAME, "vtkSDFGMMPartition");
    SetCounters(state, "", filterTimes);
    laps.SetCounters(state);
  });
}

/// What the abort benchmark's progress observer saw.
struct AbortWatch
{
  vtkAlgorithm* Filter = nullptr;
  double AbortAt = 0.5;
  Clock::time_point Start, LastEvent, RequestedAt;
  bool Requested = false;
  int Events = 0;
  double LargestGapMs = 0.0;

  static void OnProgress(vtkObject*, unsigned long, void* clientData, void* callData)
  {
    auto* watch = static_cast<AbortWatch*>(clientData);
    const auto now = Clock::now();
    if (watch->Requested)
    {
      return;
    }
    ++watch->Events;
    watch->LargestGapMs = std::max(watch->LargestGapMs, Milliseconds(watch->LastEvent, now));
    watch->LastEvent = now;
    if (*static_cast<double*>(callData) >= watch->AbortAt)
    {
      watch->Requested = true;
      watch->RequestedAt = now;
      watch->Filter->SetAbortExecute(1);
    }
  }
};

/// A user pressing abort in the middle of the SDF: an observer of ProgressEvent sets
/// AbortExecute once the progress reaches 0.5 (inside the ray loop). Iteration time (and
/// abort_latency_*) = from that call to Update()'s return; progress_gap_max_ms = the largest
/// gap between two progress events before it (how steadily the bar moves), progress_events =
/// how many. The aborted output must be the documented pass-through (no SDF array).
void BM_SDFAbort(benchmark::State& state, const std::string& path)
{
  Guarded(state, [&] {
    MeshData& mesh = Mesh(path);
    Samples latency, gap;
    int events = 0;
    for (auto _ : state)
    {
      vtkNew<vtkShapeDiameterFilter> sdf;
      sdf->SetInputData(mesh.Surface);
      sdf->SetNumberOfThreads(Threads());
      AbortWatch watch;
      watch.Filter = sdf;
      vtkNew<vtkCallbackCommand> observer;
      observer->SetCallback(AbortWatch::OnProgress);
      observer->SetClientData(&watch);
      sdf->AddObserver(vtkCommand::ProgressEvent, observer);
      watch.Start = watch.LastEvent = Clock::now();
      sdf->Update();
      const auto end = Clock::now();
      if (!watch.Requested)
      {
        throw std::runtime_error("the SDF filter never reported progress 0.5");
      }
      if (sdf->GetOutput()->GetCellData()->GetArray(vtkShapeDiameterFilter::SDF_ARRAY_NAME))
      {
        throw std::runtime_error("the aborted SDF filter wrote its SDF array");
      }
      latency.Add(Milliseconds(watch.RequestedAt, end));
      gap.Add(watch.LargestGapMs);
      events = watch.Events;
      state.SetIterationTime(Milliseconds(watch.RequestedAt, end) / 1000.0);
    }
    SetCounters(state, "abort_latency_", latency);
    state.counters["progress_gap_max_ms"] = gap.Median();
    state.counters["progress_events"] = events;
  });
}

std::string Stem(const std::string& path)
{
  const std::size_t slash = path.find_last_of('/');
  std::string name = slash == std::string::npos ? path : path.substr(slash + 1);
  const std::size_t dot = name.rfind('.');
  return dot == std::string::npos || dot == 0 ? name : name.substr(0, dot);
}

void RegisterMesh(const std::string& path)
{
  using Function = void (*)(benchmark::State&, const std::string&);
  const std::pair<const char*, Function> stages[] = { { "Read", BM_Read }, { "SDF", BM_SDF },
    { "RawEmbree", BM_RawEmbree }, { "Smooth", BM_Smooth }, { "Partition", BM_Partition },
    { "Skeleton", BM_Skeleton }, { "Paired", BM_Paired }, { "Chain", BM_Chain },
    { "SDFBreakdown", BM_SDFBreakdown }, { "SmoothBreakdown", BM_SmoothBreakdown },
    { "PartitionBreakdown", BM_PartitionBreakdown }, { "SDFAbort", BM_SDFAbort },
    { "AdaptivePaired", BM_AdaptivePaired }, { "AdaptiveChain", BM_AdaptiveChain } };
  for (const auto& [stage, function] : stages)
  {
    const std::string name = std::string(stage) + "/" + Stem(path);
    benchmark::RegisterBenchmark(name.c_str(), function, path)
      ->Iterations(Repeats())
      ->UseManualTime()
      ->Unit(benchmark::kMillisecond);
  }
}

std::vector<std::string> SplitColon(const std::string& text)
{
  std::vector<std::string> parts;
  std::size_t begin = 0;
  while (begin <= text.size())
  {
    const std::size_t end = std::min(text.find(':', begin), text.size());
    if (end > begin)
    {
      parts.push_back(text.substr(begin, end - begin));
    }
    begin = end + 1;
  }
  return parts;
}

/// --chain-once: read + chain once, stage times in seconds on one line.
int RunChainOnce(const std::string& path)
{
  const auto t0 = Clock::now();
  vtkSmartPointer<vtkPolyData> surface = ReadMesh(path);
  const double readMs = Milliseconds(t0, Clock::now());
  Chain chain(surface);
  const std::vector<double> ms = chain.Run();
  double total = 0;
  for (const double m : ms)
  {
    total += m;
  }
  std::printf("chain-once %s faces=%lld read_s=%.3f sdf_s=%.3f smooth_s=%.3f partition_s=%.3f "
              "skeleton_s=%.3f chain_s=%.3f\n",
    path.c_str(), static_cast<long long>(surface->GetNumberOfPolys()), readMs / 1000, ms[0] / 1000,
    ms[1] / 1000, ms[2] / 1000, ms[3] / 1000, total / 1000);
  return 0;
}

/// Area of every cell (fan triangulation of polygons; 0 for vertices and lines).
std::vector<double> CellAreas(vtkPolyData* mesh)
{
  std::vector<double> areas(static_cast<std::size_t>(mesh->GetNumberOfCells()), 0.0);
  vtkNew<vtkIdList> ids;
  for (vtkIdType cell = 0; cell < mesh->GetNumberOfCells(); ++cell)
  {
    mesh->GetCellPoints(cell, ids);
    if (ids->GetNumberOfIds() < 3)
    {
      continue;
    }
    double a[3], b[3], c[3];
    mesh->GetPoint(ids->GetId(0), a);
    for (vtkIdType k = 1; k + 1 < ids->GetNumberOfIds(); ++k)
    {
      mesh->GetPoint(ids->GetId(k), b);
      mesh->GetPoint(ids->GetId(k + 1), c);
      const double u[3] = { b[0] - a[0], b[1] - a[1], b[2] - a[2] };
      const double v[3] = { c[0] - a[0], c[1] - a[1], c[2] - a[2] };
      const double x = u[1] * v[2] - u[2] * v[1], y = u[2] * v[0] - u[0] * v[2], z = u[0] * v[1] - u[1] * v[0];
      areas[static_cast<std::size_t>(cell)] += 0.5 * std::sqrt(x * x + y * y + z * z);
    }
  }
  return areas;
}

/// --accuracy: the chain with the exact and the adaptive SDF on each mesh; a Markdown row
/// per mesh with the times and the differences the adaptive mode's bar is about.
int RunAccuracy(std::vector<std::string> paths)
{
  double tolerance = -1; // the filter's default
  if (paths.size() >= 2 && paths[0] == "--tolerance")
  {
    tolerance = std::stod(paths[1]);
    paths.erase(paths.begin(), paths.begin() + 2);
  }
  std::printf("| mesh | faces | SDF exact | SDF adaptive | adaptive/exact | mean abs dSDFNormalized | "
              "p99 | max | SDFCluster same area | k exact/adaptive | skeleton points exact/adaptive | "
              "chain exact | chain adaptive |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n");
  for (const std::string& path : paths)
  {
    vtkSmartPointer<vtkPolyData> surface = ReadMesh(path);
    Chain exact(surface), adaptive(surface, vtkShapeDiameterFilter::ADAPTIVE);
    if (tolerance > 0)
    {
      adaptive.Tolerance = tolerance;
    }
    const std::vector<double> exactMs = exact.Run();
    const std::vector<double> adaptiveMs = adaptive.Run();
    auto* e = vtkDataArray::SafeDownCast(
      exact.SmoothOutput->GetCellData()->GetArray(vtkSDFBilateralSmooth::NORMALIZED_ARRAY_NAME));
    auto* a = vtkDataArray::SafeDownCast(
      adaptive.SmoothOutput->GetCellData()->GetArray(vtkSDFBilateralSmooth::NORMALIZED_ARRAY_NAME));
    std::vector<double> differences;
    double sum = 0;
    for (vtkIdType c = 0; c < e->GetNumberOfTuples(); ++c)
    {
      differences.push_back(std::abs(e->GetTuple1(c) - a->GetTuple1(c)));
      sum += differences.back();
    }
    std::sort(differences.begin(), differences.end());
    const double mean = differences.empty() ? 0 : sum / static_cast<double>(differences.size());
    const double p99 = differences.empty() ? 0 : differences[std::min(differences.size() - 1,
      static_cast<std::size_t>(std::ceil(0.99 * static_cast<double>(differences.size()))) - 1)];
    auto labels = [](vtkPolyData* data) {
      auto* array = data->GetCellData()->GetArray(vtkSDFGMMPartition::CLUSTER_ARRAY_NAME);
      std::vector<int> values(static_cast<std::size_t>(array->GetNumberOfTuples()));
      for (std::size_t c = 0; c < values.size(); ++c)
      {
        values[c] = static_cast<int>(array->GetTuple1(static_cast<vtkIdType>(c)));
      }
      return values;
    };
    const std::vector<int> exactLabels = labels(exact.PartitionOutput);
    const std::vector<int> adaptiveLabels = labels(adaptive.PartitionOutput);
    const LabelMatchingResult matching = CompareLabelings(exactLabels, adaptiveLabels);
    std::map<int, int> matched(matching.Matching.begin(), matching.Matching.end());
    const std::vector<double> areas = CellAreas(surface);
    double same = 0, total = 0;
    for (std::size_t c = 0; c < areas.size(); ++c)
    {
      total += areas[c];
      const auto it = matched.find(exactLabels[c]);
      if (it != matched.end() && it->second == adaptiveLabels[c])
      {
        same += areas[c];
      }
    }
    const auto clusters = [](const std::vector<int>& values) {
      return values.empty() ? 0 : *std::max_element(values.begin(), values.end()) + 1;
    };
    std::printf("| %s | %lld | %.3f s | %.3f s | %.3f | %.4f | %.4f | %.4f | %.2f %% | %d/%d | %lld/%lld | %.3f s | %.3f s |\n",
      Stem(path).c_str(), static_cast<long long>(surface->GetNumberOfPolys()), exactMs[0] / 1000,
      adaptiveMs[0] / 1000, adaptiveMs[0] / exactMs[0], mean, p99, differences.empty() ? 0 : differences.back(),
      total > 0 ? 100 * same / total : 100.0, clusters(exactLabels), clusters(adaptiveLabels),
      static_cast<long long>(exact.Skeleton->GetNumberOfPoints()),
      static_cast<long long>(adaptive.Skeleton->GetNumberOfPoints()),
      (exactMs[0] + exactMs[1] + exactMs[2] + exactMs[3]) / 1000,
      (adaptiveMs[0] + adaptiveMs[1] + adaptiveMs[2] + adaptiveMs[3]) / 1000);
    std::fflush(stdout);
  }
  return 0;
}

} // namespace

int main(int argc, char** argv)
{
  try
  {
    if (argc >= 2 && std::strcmp(argv[1], "--chain-once") == 0)
    {
      if (argc != 3)
      {
        std::cerr << "usage: " << argv[0] << " --chain-once MESH.off\n";
        return 2;
      }
      return RunChainOnce(argv[2]);
    }
    if (argc >= 2 && std::strcmp(argv[1], "--accuracy") == 0)
    {
      return RunAccuracy(std::vector<std::string>(argv + 2, argv + argc));
    }

    benchmark::Initialize(&argc, argv);
    std::vector<std::string> meshes;
    for (int i = 1; i < argc; ++i)
    {
      if (argv[i][0] == '-')
      {
        std::cerr << argv[0] << ": unrecognized option " << argv[i] << "\n";
        return 2;
      }
      meshes.emplace_back(argv[i]);
    }
    if (meshes.empty())
    {
      const char* fromEnvironment = std::getenv("SHAPEDIAMETER_BENCH_MESH");
      meshes = fromEnvironment && *fromEnvironment
        ? SplitColon(fromEnvironment)
        : std::vector<std::string>{ std::string(SHAPEDIAMETER_DATA_DIR) + "/armadillo.off" };
    }
    Repeats(); // report a bad setting before anything runs
    Threads();
    for (const std::string& mesh : meshes)
    {
      RegisterMesh(mesh);
    }
    std::clog << "BenchPipeline: " << Repeats() << " repeats, NumberOfThreads " << Threads()
              << std::endl;
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    CurrentMesh.reset();
    if (AnyBenchmarkFailed)
    {
      std::cerr << argv[0] << ": some benchmarks failed (ERROR OCCURRED above)\n";
      return 1;
    }
    return 0;
  }
  catch (const std::exception& error)
  {
    std::cerr << argv[0] << ": " << error.what() << "\n";
    return 1;
  }
}
