// SPDX-License-Identifier: BSD-3-Clause
#include "Skeleton/SkeletonSmoothing.h"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <set>
#include <utility>
#include <vector>

namespace shapediameter
{

void ValidateSmoothingOptions(const SkeletonSmoothingOptions& options)
{
  CheckRange(options.Bandwidth, BoneSmoothingRange, "skeleton: BoneSmoothing");
}

namespace
{

/// The bones as node paths from one end (degree != 2) to the other, in the order of their
/// first node and its neighbours; loops of degree-2 nodes are left out (the tree has none).
std::vector<std::vector<std::int64_t>> BonePaths(const SkeletonGraph& graph)
{
  const std::size_t n = graph.NodeRadius.size();
  std::vector<std::set<std::int64_t>> neighbours(n);
  for (const auto& polyline : graph.Polylines)
  {
    for (std::size_t i = 1; i < polyline.size(); ++i)
    {
      if (polyline[i - 1] != polyline[i])
      {
        neighbours[static_cast<std::size_t>(polyline[i - 1])].insert(polyline[i]);
        neighbours[static_cast<std::size_t>(polyline[i])].insert(polyline[i - 1]);
      }
    }
  }
  std::set<std::pair<std::int64_t, std::int64_t>> walked;
  const auto edge = [](std::int64_t a, std::int64_t b) { return std::make_pair(std::min(a, b), std::max(a, b)); };
  std::vector<std::vector<std::int64_t>> paths;
  for (std::size_t start = 0; start < n; ++start)
  {
    if (neighbours[start].size() == 2)
    {
      continue;
    }
    for (const std::int64_t first : neighbours[start])
    {
      if (walked.count(edge(static_cast<std::int64_t>(start), first)))
      {
        continue;
      }
      std::vector<std::int64_t> path{ static_cast<std::int64_t>(start) };
      std::int64_t previous = static_cast<std::int64_t>(start), current = first;
      walked.insert(edge(previous, current));
      while (neighbours[static_cast<std::size_t>(current)].size() == 2)
      {
        path.push_back(current);
        const auto& around = neighbours[static_cast<std::size_t>(current)];
        const std::int64_t next = *around.begin() == previous ? *around.rbegin() : *around.begin();
        previous = current;
        current = next;
        walked.insert(edge(previous, current));
      }
      path.push_back(current);
      paths.push_back(std::move(path));
    }
  }
  return paths;
}

/// Local polynomial fit at every node of `path` (see the header comment, step 2): fitted
/// positions and radii, in path order; at the ends the fit is one-sided and linear.
void FitAlongPath(const SkeletonGraph& graph, const std::vector<std::int64_t>& path, double bandwidth,
  std::vector<Eigen::Vector3d>& positions, std::vector<double>& radii)
{
  const std::size_t m = path.size();
  std::vector<double> arc(m, 0.0);
  std::vector<Eigen::Vector3d> original(m);
  std::vector<double> originalRadii(m);
  for (std::size_t i = 0; i < m; ++i)
  {
    original[i] = graph.NodePositions.row(path[i]).transpose();
    originalRadii[i] = graph.NodeRadius[static_cast<std::size_t>(path[i])];
    if (i > 0)
    {
      arc[i] = arc[i - 1] + (original[i] - original[i - 1]).norm();
    }
  }
  positions = original;
  radii = originalRadii;
  for (std::size_t i = 0; i < m; ++i)
  {
    const double sigma = bandwidth * originalRadii[i];
    if (!(sigma > 0.0))
    {
      continue;
    }
    // Weighted least squares in (1, d, d^2), d = arc length from the node; the intercept is
    // the fit at the node.
    Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
    Eigen::Matrix<double, 3, 4> moments = Eigen::Matrix<double, 3, 4>::Zero();
    int before = 0, after = 0;
    const auto add = [&](std::size_t j) {
      const double d = arc[j] - arc[i];
      const double w = std::exp(-0.5 * d * d / (sigma * sigma));
      const Eigen::Vector3d basis(1.0, d, d * d);
      normal += w * basis * basis.transpose();
      Eigen::Vector4d value;
      value << original[j], originalRadii[j];
      moments += w * basis * value.transpose();
      before += d < 0.0 ? 1 : 0;
      after += d > 0.0 ? 1 : 0;
    };
    for (std::size_t j = i + 1; j-- > 0 && arc[i] - arc[j] <= 3.0 * sigma;)
    {
      add(j);
    }
    for (std::size_t j = i + 1; j < m && arc[j] - arc[i] <= 3.0 * sigma; ++j)
    {
      add(j);
    }
    // Quadratic where the window reaches two nodes on either side, linear at and near the ends
    // (a one-sided quadratic extrapolates); a lower degree where the fit is ill-conditioned.
    int degree = (before >= 2 && after >= 2) ? 2 : 1;
    Eigen::Vector4d fit = moments.row(0).transpose() / normal(0, 0);
    for (; degree >= 1; --degree)
    {
      const Eigen::Index size = degree + 1;
      const Eigen::MatrixXd block = normal.topLeftCorner(size, size);
      const Eigen::LDLT<Eigen::MatrixXd> solver(block);
      if (solver.info() != Eigen::Success || !(solver.rcond() > 1e-9))
      {
        continue;
      }
      const Eigen::MatrixXd coefficients = solver.solve(moments.topRows(size));
      fit = coefficients.row(0).transpose();
      break;
    }
    const Eigen::Vector3d position = fit.head<3>();
    const double radius = fit[3];
    if (radius > 0.0 && std::isfinite(radius) && position.allFinite())
    {
      positions[i] = position;
      radii[i] = radius;
    }
  }
}

} // namespace

BoneSmoothingResult SmoothBones(
  SkeletonGraph& graph, const RayCaster* volume, const SkeletonSmoothingOptions& options)
{
  ValidateSmoothingOptions(options);
  BoneSmoothingResult result;
  if (!(options.Bandwidth > 0.0))
  {
    return result;
  }
  const std::size_t n = graph.NodeRadius.size();
  const std::vector<std::vector<std::int64_t>> paths = BonePaths(graph);
  // Targets: an interior node's fit; an end's fit from every bone it ends, averaged (a
  // junction moves to where its bones' fits meet, a leaf along its bone's line).
  std::vector<Eigen::Vector3d> target(n, Eigen::Vector3d::Zero());
  std::vector<double> targetRadius(n, 0.0);
  std::vector<int> fits(n, 0);
  for (const std::vector<std::int64_t>& path : paths)
  {
    std::vector<Eigen::Vector3d> fitted;
    std::vector<double> fittedRadii;
    FitAlongPath(graph, path, options.Bandwidth, fitted, fittedRadii);
    for (std::size_t i = 0; i < path.size(); ++i)
    {
      const auto node = static_cast<std::size_t>(path[i]);
      target[node] += fitted[i];
      targetRadius[node] += fittedRadii[i];
      ++fits[node];
    }
  }
  std::vector<Eigen::Vector3d> original(n);
  std::vector<double> share(n, 0.0);
  for (std::size_t node = 0; node < n; ++node)
  {
    original[node] = graph.NodePositions.row(static_cast<Eigen::Index>(node)).transpose();
    if (fits[node] > 0)
    {
      target[node] /= fits[node];
      targetRadius[node] /= fits[node];
      share[node] = 1.0;
    }
  }
  const auto at = [&](std::size_t node) {
    return Eigen::Vector3d(original[node] + share[node] * (target[node] - original[node]));
  };

  // Through the volume: the edges of all bones, each tested as it is and as smoothed.
  std::vector<std::pair<std::size_t, std::size_t>> edges;
  for (const std::vector<std::int64_t>& path : paths)
  {
    for (std::size_t i = 1; i < path.size(); ++i)
    {
      edges.emplace_back(static_cast<std::size_t>(path[i - 1]), static_cast<std::size_t>(path[i]));
    }
  }
  if (volume)
  {
    std::vector<Segment> asTheyAre;
    for (const auto& [a, b] : edges)
    {
      asTheyAre.push_back(Segment{ original[a], original[b] });
    }
    const std::vector<char> crossing = SegmentsCrossSurface(*volume, asTheyAre, SerialFor);
    std::size_t kept = 0;
    for (std::size_t e = 0; e < edges.size(); ++e)
    {
      if (!crossing[e])
      {
        edges[kept++] = edges[e];
      }
    }
    edges.resize(kept);
  }
  constexpr int halvings = 4;
  std::vector<char> held(n, 0);
  for (int round = 0; volume; ++round)
  {
    // Every edge tested at the round's positions in one batch (a volume over processes answers
    // it in one exchange); an edge with an end already held back in this round is tested
    // again, at its end's new position, as the edges are taken in order.
    std::vector<std::size_t> tested;
    std::vector<Segment> atRoundStart;
    for (std::size_t e = 0; e < edges.size(); ++e)
    {
      const auto [a, b] = edges[e];
      if (share[a] > 0.0 || share[b] > 0.0) // both ends at rest stay so: the edge is skipped
      {
        tested.push_back(e);
        atRoundStart.push_back(Segment{ at(a), at(b) });
      }
    }
    const std::vector<char> crossingOfTested = SegmentsCrossSurface(*volume, atRoundStart, SerialFor);
    std::vector<char> crossingAtStart(edges.size(), 0);
    for (std::size_t t = 0; t < tested.size(); ++t)
    {
      crossingAtStart[tested[t]] = crossingOfTested[t];
    }
    std::vector<char> heldThisRound(n, 0);
    bool changed = false;
    for (std::size_t e = 0; e < edges.size(); ++e)
    {
      const auto [a, b] = edges[e];
      if (share[a] == 0.0 && share[b] == 0.0)
      {
        continue;
      }
      const bool crossing =
        heldThisRound[a] || heldThisRound[b] ? SegmentCrossesSurface(*volume, at(a), at(b)) : crossingAtStart[e] != 0;
      if (!crossing)
      {
        continue;
      }
      for (const std::size_t node : { a, b })
      {
        if (share[node] > 0.0)
        {
          share[node] = round < halvings ? 0.5 * share[node] : 0.0;
          held[node] = 1;
          heldThisRound[node] = 1;
          changed = true;
        }
      }
    }
    if (!changed)
    {
      break;
    }
  }
  for (std::size_t node = 0; node < n; ++node)
  {
    const Eigen::Vector3d position = at(node);
    if (position != original[node])
    {
      ++result.MovedNodes;
    }
    result.HeldNodes += held[node] ? 1 : 0;
    graph.NodePositions.row(static_cast<Eigen::Index>(node)) = position.transpose();
    graph.NodeRadius[node] += share[node] * (targetRadius[node] - graph.NodeRadius[node]);
  }
  return result;
}

} // namespace shapediameter
