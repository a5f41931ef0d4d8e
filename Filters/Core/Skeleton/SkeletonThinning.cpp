// SPDX-License-Identifier: BSD-3-Clause
#include "Skeleton/SkeletonThinning.h"

#include "Skeleton/SkeletonPointTree.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iterator>
#include <memory>
#include <string>

namespace shapediameter
{

namespace
{

/// MinimumConfidentShare never lowers the threshold below this: a junction of three branches
/// has confidence about 0.5, a blob at most that.
constexpr double kLowestConfidentShareThreshold = 0.6;

} // namespace

void ValidateThinningOptions(const SkeletonThinningOptions& options)
{
  CheckRange(options.NumberOfIterations, SkeletonIterationsRange, "skeleton: NumberOfIterations");
  CheckRange(options.NeighborhoodScale, NeighborhoodScaleRange, "skeleton: NeighborhoodScale");
  CheckRange(options.ConfidenceThreshold, ConfidenceThresholdRange, "skeleton: ConfidenceThreshold");
  CheckRange(options.MinimumConfidentShare, MinimumConfidentShareRange, "skeleton: MinimumConfidentShare");
  CheckRange(options.SpacingFactor, ThinningSpacingFactorRange, "skeleton: thinning SpacingFactor");
  CheckRange(options.MinimumNeighbors, MinimumNeighborsRange, "skeleton: MinimumNeighbors");
  CheckRange(options.MinimumClearance, MinimumClearanceRange, "skeleton: MinimumClearance");
}

namespace
{

struct Projection
{
  Eigen::Vector3d Position;
  Eigen::Vector3d Axis;
  double Confidence;
  Eigen::Vector3d Spread = Eigen::Vector3d::Zero(); ///< variances, increasing
  Eigen::Vector3d Normal = Eigen::Vector3d::Zero(); ///< the axis of the smallest
};

/// One MLS step for a point at `position` with neighbourhood radius h.
Projection ProjectOntoRegressionLine(const SkeletonPointTree& tree,
  const Eigen::Vector3d& position, double h, double minimumNeighbors)
{
  const Projection unchanged{ position, Eigen::Vector3d::Zero(), 0.0 };
  if (!(h > 0.0))
  {
    return unchanged;
  }
  const SkeletonPointTree::Moments moments = tree.BallMoments(position, h);
  if (moments.Count < minimumNeighbors)
  {
    return unchanged;
  }
  // Moments are about the query position, so the covariance has no cancellation beyond h^2.
  const Eigen::Vector3d mean = moments.Sum / moments.Count;
  Eigen::Matrix3d covariance = moments.SumOfSquares / moments.Count - mean * mean.transpose();
  covariance = 0.5 * (covariance + covariance.transpose()).eval();
  if (!covariance.allFinite())
  {
    return unchanged;
  }
  // The closed-form 3 x 3 solver is several times faster than the iterative one; its
  // eigenvalue error is ~1e-15 of the largest, far below any confidence threshold.
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  solver.computeDirect(covariance);
  if (solver.info() != Eigen::Success)
  {
    return unchanged;
  }
  const Eigen::Vector3d eigenvalues = solver.eigenvalues().cwiseMax(0.0);
  const double sum = eigenvalues.sum();
  // Coincident neighbours (sum at rounding level of h^2) have no direction.
  if (!(sum > 1e-14 * h * h))
  {
    return unchanged;
  }
  const Eigen::Vector3d axis = solver.eigenvectors().col(2).normalized();
  // The query position is the origin of the local frame: the regression line passes through
  // `mean`, and the projection of the origin onto it is mean - (mean . axis) axis.
  const Eigen::Vector3d moved = position + mean - mean.dot(axis) * axis;
  const double confidence = eigenvalues(2) / sum;
  if (!moved.allFinite() || !axis.allFinite() || !std::isfinite(confidence))
  {
    return unchanged;
  }
  return { moved, axis, std::clamp(confidence, 0.0, 1.0), eigenvalues, solver.eigenvectors().col(0).normalized() };
}

/// Per centre, whether no surface lies within its reach along the axes and the diagonals: the
/// 14 rays of every centre in one batch (a volume over processes answers it in one exchange;
/// serially one parallel loop, where a loop per direction cost more in starting the loops
/// than the rays a centre that fails early saves).
std::vector<char> BallsFit(const RayCaster& volume, const std::vector<Eigen::Vector3d>& centres,
  const std::vector<double>& reaches, const ParallelFor& parallelFor)
{
  constexpr double d = 0.57735026918962576; // 1 / sqrt(3)
  static const Eigen::Vector3d directions[14] = { { 1, 0, 0 }, { -1, 0, 0 }, { 0, 1, 0 }, { 0, -1, 0 }, { 0, 0, 1 },
    { 0, 0, -1 }, { d, d, d }, { d, d, -d }, { d, -d, d }, { d, -d, -d }, { -d, d, d }, { -d, d, -d }, { -d, -d, d },
    { -d, -d, -d } };
  constexpr std::size_t perCentre = std::size(directions);
  std::vector<Ray> rays;
  rays.reserve(perCentre * centres.size());
  for (std::size_t c = 0; c < centres.size(); ++c)
  {
    for (const Eigen::Vector3d& direction : directions)
    {
      rays.push_back(ExitRay(centres[c], direction, reaches[c]));
    }
  }
  std::vector<double> exits;
  volume.CastRays(rays, exits, parallelFor);
  std::vector<char> fits(centres.size(), 1);
  for (std::size_t r = 0; r < rays.size(); ++r)
  {
    if (std::isfinite(exits[r]))
    {
      fits[r / perCentre] = 0;
    }
  }
  return fits;
}

} // namespace

void ProjectOntoRegressionLines(const SkeletonPointTree& cloud, const PointMatrix& positions,
  const std::vector<double>& radii, double minimumNeighbors, std::size_t first, std::size_t end,
  RegressionProjections& out, const ParallelFor& parallelFor)
{
  parallelFor(end - first, [&](std::size_t begin, std::size_t stop) {
    for (std::size_t k = first + begin; k < first + stop; ++k)
    {
      const auto i = static_cast<Eigen::Index>(k);
      const Projection projection =
        ProjectOntoRegressionLine(cloud, positions.row(i).transpose(), radii[k], minimumNeighbors);
      out.Positions.row(i) = projection.Position.transpose();
      out.Axis.row(i) = projection.Axis.transpose();
      out.Confidence[k] = projection.Confidence;
      if (projection.Normal.allFinite())
      {
        out.Spread.row(i) = projection.Spread.transpose();
        out.Normal.row(i) = projection.Normal.transpose();
      }
    }
  });
}

ThinnedCloud ThinProjectedCloud(const ProjectedCloud& cloud,
  const SkeletonThinningOptions& options, const ParallelFor& parallelFor,
  const ProgressCallback& progress, const RayCaster* volume, const RegressionProjector* projector)
{
  ValidateThinningOptions(options);
  ThinnedCloud result;
  const std::size_t count = cloud.Size();
  const auto rows = static_cast<Eigen::Index>(count);
  result.Positions = cloud.Positions;
  result.Axis = PointMatrix::Zero(rows, 3);
  result.Confidence.assign(count, 0.0);
  result.LocalSpread = PointMatrix::Zero(rows, 3);
  result.LocalNormal = PointMatrix::Zero(rows, 3);
  if (count == 0)
  {
    return result;
  }

  const auto abortedResult = [&result]() {
    result = ThinnedCloud();
    result.Aborted = true;
    return result;
  };

  std::vector<double> radii(count);
  for (std::size_t k = 0; k < count; ++k)
  {
    radii[k] = options.NeighborhoodScale * cloud.Radius[k];
  }
  const auto minimumNeighbors = static_cast<double>(options.MinimumNeighbors);
  const double steps = options.NumberOfIterations + 1.0;
  std::unique_ptr<SkeletonPointTree> tree;
  for (int iteration = 0; iteration < options.NumberOfIterations; ++iteration)
  {
    const bool cloudChanged = iteration == 0 || options.ContractCloud;
    RegressionProjections step;
    if (projector)
    {
      step = projector->Project(result.Positions, cloudChanged, result.Positions, radii, minimumNeighbors);
      if (step.Positions.rows() != rows || step.Axis.rows() != rows || step.Confidence.size() != count ||
        step.Spread.rows() != rows || step.Normal.rows() != rows)
      {
        throw Error("skeleton: the MLS step answered " + std::to_string(step.Positions.rows()) + " of " +
          std::to_string(rows) + " points");
      }
      if (progress && !progress((iteration + 1.0) / steps))
      {
        return abortedResult();
      }
    }
    else
    {
      if (cloudChanged)
      {
        tree = std::make_unique<SkeletonPointTree>(result.Positions);
      }
      step = RegressionProjections::Zero(rows);
      // In blocks, for progress and abort between them.
      const std::size_t blocks = std::min<std::size_t>(16, count);
      const std::size_t blockSize = (count + blocks - 1) / blocks;
      for (std::size_t blockBegin = 0; blockBegin < count; blockBegin += blockSize)
      {
        const std::size_t blockEnd = std::min(count, blockBegin + blockSize);
        ProjectOntoRegressionLines(
          *tree, result.Positions, radii, minimumNeighbors, blockBegin, blockEnd, step, parallelFor);
        const double done = (iteration + static_cast<double>(blockEnd) / static_cast<double>(count)) / steps;
        if (progress && !progress(done))
        {
          return abortedResult();
        }
      }
    }
    result.Positions = std::move(step.Positions);
    result.Axis = std::move(step.Axis);
    result.Confidence = std::move(step.Confidence);
    if (iteration == 0)
    {
      result.LocalSpread = std::move(step.Spread);
      result.LocalNormal = std::move(step.Normal);
    }
  }

  // The threshold, lowered so that at least MinimumConfidentShare of the defined points pass.
  double threshold = options.ConfidenceThreshold;
  {
    std::vector<double> defined;
    for (const double confidence : result.Confidence)
    {
      if (confidence > 0.0)
      {
        defined.push_back(confidence);
      }
    }
    const auto wanted = static_cast<std::size_t>(std::ceil(options.MinimumConfidentShare * static_cast<double>(defined.size())));
    if (wanted > 0)
    {
      std::nth_element(defined.begin(), defined.begin() + static_cast<std::ptrdiff_t>(wanted - 1), defined.end(), std::greater<double>());
      threshold = std::min(threshold, std::max(kLowestConfidentShareThreshold, defined[wanted - 1]));
    }
  }
  result.AppliedConfidenceThreshold = threshold;
  // Epsilon-thinning: most confident first, each kept point suppresses its epsilon-ball.
  std::vector<std::int64_t> candidates;
  for (std::size_t k = 0; k < count; ++k)
  {
    if (result.Confidence[k] > 0.0 && result.Confidence[k] >= threshold)
    {
      candidates.push_back(static_cast<std::int64_t>(k));
    }
  }
  if (volume && options.MinimumClearance > 0.0)
  {
    std::vector<Eigen::Vector3d> centres;
    std::vector<double> reaches;
    centres.reserve(candidates.size());
    reaches.reserve(candidates.size());
    for (const std::int64_t k : candidates)
    {
      centres.emplace_back(cloud.Positions.row(static_cast<Eigen::Index>(k)).transpose());
      reaches.push_back(options.MinimumClearance * cloud.Radius[static_cast<std::size_t>(k)]);
    }
    const std::vector<char> fits = BallsFit(*volume, centres, reaches, parallelFor);
    std::size_t kept = 0;
    for (std::size_t c = 0; c < candidates.size(); ++c)
    {
      if (fits[c])
      {
        candidates[kept++] = candidates[c];
      }
    }
    candidates.resize(kept);
  }
  std::sort(candidates.begin(), candidates.end(), [&result](std::int64_t a, std::int64_t b) {
    return result.Confidence[a] > result.Confidence[b] ||
      (result.Confidence[a] == result.Confidence[b] && a < b);
  });
  PointMatrix candidatePositions(static_cast<Eigen::Index>(candidates.size()), 3);
  for (std::size_t c = 0; c < candidates.size(); ++c)
  {
    candidatePositions.row(static_cast<Eigen::Index>(c)) = result.Positions.row(candidates[c]);
  }
  const SkeletonPointTree candidateTree(candidatePositions);
  std::vector<char> suppressed(candidates.size(), 0);
  std::vector<std::int64_t> nearby;
  for (std::size_t c = 0; c < candidates.size(); ++c)
  {
    if (suppressed[c])
    {
      continue;
    }
    result.Thinned.push_back(candidates[c]);
    candidateTree.RadiusSearch(candidatePositions.row(static_cast<Eigen::Index>(c)).transpose(),
      options.SpacingFactor * cloud.Radius[candidates[c]], nearby);
    for (const std::int64_t other : nearby)
    {
      suppressed[other] = 1;
    }
  }
  if (progress && !progress(1.0))
  {
    return abortedResult();
  }
  return result;
}

} // namespace shapediameter
