// SPDX-License-Identifier: BSD-3-Clause
// Benchmark of the SDF-guided skeleton core (paper section 5) on a generated articulated
// figure (a star-shaped union of capsules: torso, head, two arms, two legs) at about 52k and
// 208k faces, with the analytic SDF. The baseline is CGAL's mean-curvature-flow skeleton on a
// 52k-face mesh, measured at 2.8 s on the project machine (CGAL is not a dependency, so the
// number is a constant here): the counter `speedup_vs_cgal_mcf` must stay above 5.
//
// BM_Skeleton/<faces level>/<threads>: the whole ComputeSkeleton (validation, components,
// sampling, thinning, segments, connection, face link). BM_SkeletonStep/<level>/<step> times
// each step alone on a prepared input, to show that only the per-face parts scale with the
// face count.
#include "Skeleton/Skeleton.h"
#include "Skeleton/SkeletonPointTree.h"
#include "TestShapes.h"

#include <benchmark/benchmark.h>

#include <map>

namespace
{

using namespace shapediameter;
using namespace shapediameter::testshapes;

constexpr double CgalMeanCurvatureFlowSeconds = 2.8;

/// Level 0: 256 x 102 UV grid, 51,712 faces; level 1: 512 x 204, 208,384 faces.
const TestMesh& Figure(int level)
{
  static std::map<int, TestMesh> cache;
  const auto found = cache.find(level);
  if (found != cache.end())
  {
    return found->second;
  }
  const std::vector<Arm> arms{
    { Eigen::Vector3d(0, 0, 1), 3.5, 1.5 },                          // torso
    { Eigen::Vector3d(0, 0, 1), 5.5, 0.8 },                          // neck and head
    { Eigen::Vector3d(1, 0, 0.3).normalized(), 5.0, 0.5 },           // arms
    { Eigen::Vector3d(-1, 0, 0.3).normalized(), 5.0, 0.5 },
    { Eigen::Vector3d(0.35, 0, -1).normalized(), 6.0, 0.7 },         // legs
    { Eigen::Vector3d(-0.35, 0, -1).normalized(), 6.0, 0.7 },
  };
  const int around = level == 0 ? 256 : 512;
  const int rings = level == 0 ? 102 : 204;
  return cache.emplace(level, MakeCapsuleStar(arms, around, rings, Eigen::Vector3d(0, 1, 0)))
    .first->second;
}

void BM_Skeleton(benchmark::State& state)
{
  const TestMesh& mesh = Figure(static_cast<int>(state.range(0)));
  const auto threads = static_cast<unsigned>(state.range(1));
  const ParallelFor parallelFor = threads <= 1 ? ParallelFor(SerialFor) : ThreadedFor(threads);
  SkeletonResult result;
  for (auto _ : state)
  {
    result = ComputeSkeleton(mesh.Points, mesh.Triangles, mesh.Sdf, {}, parallelFor);
    benchmark::DoNotOptimize(result.NodePositions.data());
  }
  state.counters["faces"] = static_cast<double>(mesh.Faces());
  state.counters["nodes"] = static_cast<double>(result.NodePositions.rows());
  state.counters["bones"] = static_cast<double>(result.BoneLength.size());
  state.counters["speedup_vs_cgal_mcf"] = benchmark::Counter(
    CgalMeanCurvatureFlowSeconds * static_cast<double>(state.iterations()),
    benchmark::Counter::kIsRate);
}
BENCHMARK(BM_Skeleton)
  ->ArgsProduct({ { 0, 1 }, { 1, 2 } })
  ->ArgNames({ "level", "threads" })
  ->Unit(benchmark::kMillisecond)
  ->UseRealTime();

enum Step
{
  Sampling,
  Thinning,
  Segments,
  Connection,
  FaceLink
};

void BM_SkeletonStep(benchmark::State& state)
{
  const TestMesh& mesh = Figure(static_cast<int>(state.range(0)));
  const auto step = static_cast<Step>(state.range(1));
  const SkeletonOptions options;
  const ProjectedCloud cloud =
    SampleProjectedCloud(mesh.Points, mesh.Triangles, mesh.Sdf, PointMatrix(), options.Sampling);
  const ThinnedCloud thinned = ThinProjectedCloud(cloud, options.Thinning, SerialFor);
  const std::vector<std::int64_t> component(cloud.Size(), 0);
  const std::vector<PolySegment> segments =
    GrowPolySegments(cloud, thinned, component, options.Segments);
  bool aborted = false;
  const SkeletonGraph graph = ConnectPolySegments(
    cloud, thinned, segments, component, options.Connection, SerialFor, {}, aborted);
  for (auto _ : state)
  {
    switch (step)
    {
      case Sampling:
        benchmark::DoNotOptimize(SampleProjectedCloud(
          mesh.Points, mesh.Triangles, mesh.Sdf, PointMatrix(), options.Sampling));
        break;
      case Thinning:
        benchmark::DoNotOptimize(ThinProjectedCloud(cloud, options.Thinning, SerialFor));
        break;
      case Segments:
        benchmark::DoNotOptimize(GrowPolySegments(cloud, thinned, component, options.Segments));
        break;
      case Connection:
        benchmark::DoNotOptimize(ConnectPolySegments(
          cloud, thinned, segments, component, options.Connection, SerialFor, {}, aborted));
        break;
      case FaceLink:
      {
        // What ComputeSkeleton adds per face: components, normals, projected centres and
        // the nearest-node search.
        const std::vector<std::int64_t> faceComponents =
          LabelFaceComponents(mesh.Triangles, static_cast<std::size_t>(mesh.Points.rows()));
        const SkeletonPointTree nodes(graph.NodePositions);
        std::int64_t sum = 0;
        for (Eigen::Index f = 0; f < mesh.Faces(); ++f)
        {
          const Eigen::Vector3d normal =
            EffectiveFaceNormal(mesh.Points, mesh.Triangles, PointMatrix(), f);
          const Eigen::Vector3d centre = (mesh.Points.row(mesh.Triangles(f, 0)) +
                                           mesh.Points.row(mesh.Triangles(f, 1)) +
                                           mesh.Points.row(mesh.Triangles(f, 2)))
                                           .transpose() /
              3.0 -
            0.5 * mesh.Sdf[f] * normal;
          sum += nodes.NearestAccepted(centre, [&](std::int64_t) { return faceComponents[f] >= 0; });
        }
        benchmark::DoNotOptimize(sum);
        break;
      }
    }
  }
  state.counters["faces"] = static_cast<double>(mesh.Faces());
}
BENCHMARK(BM_SkeletonStep)
  ->ArgsProduct({ { 0, 1 }, { Sampling, Thinning, Segments, Connection, FaceLink } })
  ->ArgNames({ "level", "step" })
  ->Unit(benchmark::kMillisecond)
  ->UseRealTime();

} // namespace

BENCHMARK_MAIN();
