// SPDX-License-Identifier: BSD-3-Clause
#include "SkeletonThinning.h"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <numeric>

namespace shapediameter
{

namespace
{

/// MinimumConfidentShare never lowers the threshold below this: a junction of three branches
/// has confidence about 0.5, a blob at most that.
constexpr double kLowestConfidentShareThreshold = 0.6;

constexpr std::uint32_t LeafSize = 12;
constexpr std::size_t MaximumDepth = 128;

/// Adds moments about `from` to `total`, re-expressed about `to`. With o = from - to:
/// S1' = S1 + n o, S2' = S2 + o S1^T + S1 o^T + n o o^T. The shift terms are of the size of
/// the node, not of the coordinates, so nothing cancels.
inline void AddShifted(double* total, const double* moments, const double* from, const double* to)
{
  const double n = moments[0];
  const double ox = from[0] - to[0];
  const double oy = from[1] - to[1];
  const double oz = from[2] - to[2];
  const double sx = moments[1];
  const double sy = moments[2];
  const double sz = moments[3];
  total[0] += n;
  total[1] += sx + n * ox;
  total[2] += sy + n * oy;
  total[3] += sz + n * oz;
  total[4] += moments[4] + 2.0 * ox * sx + n * ox * ox;
  total[5] += moments[5] + ox * sy + sx * oy + n * ox * oy;
  total[6] += moments[6] + ox * sz + sx * oz + n * ox * oz;
  total[7] += moments[7] + 2.0 * oy * sy + n * oy * oy;
  total[8] += moments[8] + oy * sz + sy * oz + n * oy * oz;
  total[9] += moments[9] + 2.0 * oz * sz + n * oz * oz;
}

inline void AddPoint(double* total, double dx, double dy, double dz)
{
  total[0] += 1.0;
  total[1] += dx;
  total[2] += dy;
  total[3] += dz;
  total[4] += dx * dx;
  total[5] += dx * dy;
  total[6] += dx * dz;
  total[7] += dy * dy;
  total[8] += dy * dz;
  total[9] += dz * dz;
}

template <typename NodeType>
inline double MinSquaredDistance(const NodeType& node, const double* centre)
{
  double sum = 0.0;
  for (int d = 0; d < 3; ++d)
  {
    const double below = node.Lower[d] - centre[d];
    const double above = centre[d] - node.Upper[d];
    const double gap = below > 0.0 ? below : (above > 0.0 ? above : 0.0);
    sum += gap * gap;
  }
  return sum;
}

template <typename NodeType>
inline double MaxSquaredDistance(const NodeType& node, const double* centre)
{
  double sum = 0.0;
  for (int d = 0; d < 3; ++d)
  {
    const double reach = std::max(std::abs(centre[d] - node.Lower[d]), std::abs(node.Upper[d] - centre[d]));
    sum += reach * reach;
  }
  return sum;
}

/// True if no point below the node can beat `worst` in the (squared distance, index) order.
template <typename NodeType>
inline bool CannotImprove(
  const NodeType& node, double minSquaredDistance, const std::pair<double, std::int64_t>& worst)
{
  return minSquaredDistance > worst.first ||
    (minSquaredDistance == worst.first && node.MinIndex > worst.second);
}

inline double SquaredDistance(const double* point, const double* centre)
{
  const double dx = point[0] - centre[0];
  const double dy = point[1] - centre[1];
  const double dz = point[2] - centre[2];
  return dx * dx + dy * dy + dz * dz;
}

/// Keeps the k best (squared distance, index) pairs in ascending order.
void InsertCandidate(std::vector<std::pair<double, std::int64_t>>& best, std::size_t k,
  double squaredDistance, std::int64_t index)
{
  const std::pair<double, std::int64_t> candidate(squaredDistance, index);
  if (best.size() == k && !(candidate < best.back()))
  {
    return;
  }
  best.insert(std::upper_bound(best.begin(), best.end(), candidate), candidate);
  if (best.size() > k)
  {
    best.pop_back();
  }
}

} // namespace

// --------------------------------------------------------------------------------------------
// SkeletonPointTree

SkeletonPointTree::SkeletonPointTree(PointsView points)
{
  const auto count = static_cast<std::size_t>(points.rows());
  Index.resize(count);
  std::iota(Index.begin(), Index.end(), std::int64_t{ 0 });
  if (count == 0)
  {
    return;
  }
  // Build on the input order (Index permutes), then store the coordinates in tree order so
  // that every leaf is contiguous in memory.
  Coordinates.resize(3 * count);
  for (std::size_t i = 0; i < count; ++i)
  {
    for (int d = 0; d < 3; ++d)
    {
      Coordinates[3 * i + d] = points(static_cast<Eigen::Index>(i), d);
    }
  }
  Nodes.reserve(2 * (count / LeafSize + 1));
  Build(0, static_cast<std::uint32_t>(count));
  std::vector<double> ordered(3 * count);
  for (std::size_t i = 0; i < count; ++i)
  {
    for (int d = 0; d < 3; ++d)
    {
      ordered[3 * i + d] = Coordinates[3 * Index[i] + d];
    }
  }
  Coordinates.swap(ordered);
}

std::int32_t SkeletonPointTree::Build(std::uint32_t begin, std::uint32_t end)
{
  const auto nodeId = static_cast<std::int32_t>(Nodes.size());
  Nodes.emplace_back();
  Node node;
  for (int d = 0; d < 3; ++d)
  {
    node.Lower[d] = node.Upper[d] = Coordinates[3 * Index[begin] + d];
  }
  for (std::uint32_t i = begin + 1; i < end; ++i)
  {
    for (int d = 0; d < 3; ++d)
    {
      node.Lower[d] = std::min(node.Lower[d], Coordinates[3 * Index[i] + d]);
      node.Upper[d] = std::max(node.Upper[d], Coordinates[3 * Index[i] + d]);
    }
  }
  for (int d = 0; d < 3; ++d)
  {
    node.Centre[d] = 0.5 * (node.Lower[d] + node.Upper[d]);
  }
  node.Begin = begin;
  node.End = end;
  node.MinIndex = *std::min_element(Index.begin() + begin, Index.begin() + end);
  if (end - begin <= LeafSize)
  {
    for (std::uint32_t i = begin; i < end; ++i)
    {
      const double* p = &Coordinates[3 * Index[i]];
      AddPoint(node.Sums.Values, p[0] - node.Centre[0], p[1] - node.Centre[1], p[2] - node.Centre[2]);
    }
  }
  else
  {
    int axis = 0;
    for (int d = 1; d < 3; ++d)
    {
      if (node.Upper[d] - node.Lower[d] > node.Upper[axis] - node.Lower[axis])
      {
        axis = d;
      }
    }
    const std::uint32_t middle = begin + (end - begin) / 2;
    // Ties ordered by index: the split, hence every query's summation order, is reproducible.
    std::nth_element(Index.begin() + begin, Index.begin() + middle, Index.begin() + end,
      [this, axis](std::int64_t a, std::int64_t b) {
        const double ca = Coordinates[3 * a + axis];
        const double cb = Coordinates[3 * b + axis];
        return ca < cb || (ca == cb && a < b);
      });
    node.Left = Build(begin, middle);
    node.Right = Build(middle, end);
    for (const std::int32_t child : { node.Left, node.Right })
    {
      AddShifted(node.Sums.Values, Nodes[child].Sums.Values, Nodes[child].Centre, node.Centre);
    }
  }
  Nodes[nodeId] = node;
  return nodeId;
}

SkeletonPointTree::Moments SkeletonPointTree::BallMoments(
  const Eigen::Vector3d& centre, double radius) const
{
  Moments result;
  if (Nodes.empty() || !(radius >= 0.0))
  {
    return result;
  }
  const double c[3] = { centre.x(), centre.y(), centre.z() };
  const double squaredRadius = radius * radius;
  double total[10] = {};
  std::array<std::int32_t, MaximumDepth> stack{};
  std::size_t top = 0;
  stack[top++] = 0;
  while (top > 0)
  {
    const Node& node = Nodes[stack[--top]];
    if (MinSquaredDistance(node, c) > squaredRadius)
    {
      continue;
    }
    if (MaxSquaredDistance(node, c) <= squaredRadius)
    {
      AddShifted(total, node.Sums.Values, node.Centre, c);
      continue;
    }
    if (node.Left < 0)
    {
      for (std::uint32_t i = node.Begin; i < node.End; ++i)
      {
        const double* p = &Coordinates[3 * i];
        if (SquaredDistance(p, c) <= squaredRadius)
        {
          AddPoint(total, p[0] - c[0], p[1] - c[1], p[2] - c[2]);
        }
      }
      continue;
    }
    stack[top++] = node.Right;
    stack[top++] = node.Left;
  }
  result.Count = total[0];
  result.Sum << total[1], total[2], total[3];
  result.SumOfSquares << total[4], total[5], total[6], total[5], total[7], total[8], total[6],
    total[8], total[9];
  return result;
}

void SkeletonPointTree::RadiusSearch(
  const Eigen::Vector3d& centre, double radius, std::vector<std::int64_t>& indices) const
{
  indices.clear();
  if (Nodes.empty() || !(radius >= 0.0))
  {
    return;
  }
  const double c[3] = { centre.x(), centre.y(), centre.z() };
  const double squaredRadius = radius * radius;
  std::array<std::int32_t, MaximumDepth> stack{};
  std::size_t top = 0;
  stack[top++] = 0;
  while (top > 0)
  {
    const Node& node = Nodes[stack[--top]];
    if (MinSquaredDistance(node, c) > squaredRadius)
    {
      continue;
    }
    const bool inside = MaxSquaredDistance(node, c) <= squaredRadius;
    if (node.Left < 0 || inside)
    {
      for (std::uint32_t i = node.Begin; i < node.End; ++i)
      {
        if (inside || SquaredDistance(&Coordinates[3 * i], c) <= squaredRadius)
        {
          indices.push_back(Index[i]);
        }
      }
      continue;
    }
    stack[top++] = node.Right;
    stack[top++] = node.Left;
  }
  std::sort(indices.begin(), indices.end());
}

void SkeletonPointTree::NearestNeighbors(const Eigen::Vector3d& centre, std::size_t k,
  std::vector<std::int64_t>& indices, std::vector<double>& squaredDistances) const
{
  indices.clear();
  squaredDistances.clear();
  if (Nodes.empty() || k == 0)
  {
    return;
  }
  const double c[3] = { centre.x(), centre.y(), centre.z() };
  std::vector<std::pair<double, std::int64_t>> best;
  best.reserve(k + 1);
  std::array<std::int32_t, MaximumDepth> stack{};
  std::size_t top = 0;
  stack[top++] = 0;
  while (top > 0)
  {
    const Node& node = Nodes[stack[--top]];
    if (best.size() == k && CannotImprove(node, MinSquaredDistance(node, c), best.back()))
    {
      continue;
    }
    if (node.Left < 0)
    {
      for (std::uint32_t i = node.Begin; i < node.End; ++i)
      {
        InsertCandidate(best, k, SquaredDistance(&Coordinates[3 * i], c), Index[i]);
      }
      continue;
    }
    // Visit the nearer child first so that the bound tightens early.
    const bool leftFirst =
      MinSquaredDistance(Nodes[node.Left], c) <= MinSquaredDistance(Nodes[node.Right], c);
    stack[top++] = leftFirst ? node.Right : node.Left;
    stack[top++] = leftFirst ? node.Left : node.Right;
  }
  for (const auto& [squaredDistance, index] : best)
  {
    indices.push_back(index);
    squaredDistances.push_back(squaredDistance);
  }
}

std::vector<std::int64_t> SkeletonPointTree::NodeLabels(
  const std::vector<std::int64_t>& pointLabels) const
{
  std::vector<std::int64_t> labels(Nodes.size(), -1);
  // Children are created after their parent, so a reverse sweep sees children first.
  for (std::size_t n = Nodes.size(); n-- > 0;)
  {
    const Node& node = Nodes[n];
    if (node.Left < 0)
    {
      std::int64_t label = pointLabels[Index[node.Begin]];
      for (std::uint32_t i = node.Begin + 1; i < node.End && label >= 0; ++i)
      {
        if (pointLabels[Index[i]] != label)
        {
          label = -1;
        }
      }
      labels[n] = label;
    }
    else
    {
      labels[n] = labels[node.Left] == labels[node.Right] ? labels[node.Left] : -1;
    }
  }
  return labels;
}

std::int64_t SkeletonPointTree::NearestAccepted(const Eigen::Vector3d& centre,
  const std::function<bool(std::int64_t)>& accept, const std::vector<std::int64_t>* nodeLabels,
  std::int64_t skipLabel) const
{
  if (Nodes.empty())
  {
    return -1;
  }
  const double c[3] = { centre.x(), centre.y(), centre.z() };
  double bestDistance = std::numeric_limits<double>::infinity();
  std::int64_t bestIndex = -1;
  std::array<std::int32_t, MaximumDepth> stack{};
  std::size_t top = 0;
  stack[top++] = 0;
  while (top > 0)
  {
    const std::int32_t nodeId = stack[--top];
    const Node& node = Nodes[nodeId];
    if (nodeLabels && skipLabel >= 0 && (*nodeLabels)[nodeId] == skipLabel)
    {
      continue;
    }
    if (bestIndex >= 0 &&
      CannotImprove(node, MinSquaredDistance(node, c), { bestDistance, bestIndex }))
    {
      continue;
    }
    if (node.Left < 0)
    {
      for (std::uint32_t i = node.Begin; i < node.End; ++i)
      {
        const double squaredDistance = SquaredDistance(&Coordinates[3 * i], c);
        const std::int64_t index = Index[i];
        if ((squaredDistance < bestDistance ||
              (squaredDistance == bestDistance && index < bestIndex)) &&
          (!accept || accept(index)))
        {
          bestDistance = squaredDistance;
          bestIndex = index;
        }
      }
      continue;
    }
    const bool leftFirst =
      MinSquaredDistance(Nodes[node.Left], c) <= MinSquaredDistance(Nodes[node.Right], c);
    stack[top++] = leftFirst ? node.Right : node.Left;
    stack[top++] = leftFirst ? node.Left : node.Right;
  }
  return bestIndex;
}

// --------------------------------------------------------------------------------------------
// MLS thinning

void ValidateThinningOptions(const SkeletonThinningOptions& options)
{
  if (options.NumberOfIterations < 1 || options.NumberOfIterations > 100)
  {
    throw SkeletonError("skeleton: NumberOfIterations must be in [1, 100]");
  }
  if (!(options.NeighborhoodScale > 0.0 && options.NeighborhoodScale <= 10.0))
  {
    throw SkeletonError("skeleton: NeighborhoodScale must be in (0, 10]");
  }
  if (!(options.ConfidenceThreshold >= 0.0 && options.ConfidenceThreshold <= 1.0))
  {
    throw SkeletonError("skeleton: ConfidenceThreshold must be in [0, 1]");
  }
  if (!(options.MinimumConfidentShare >= 0.0 && options.MinimumConfidentShare <= 1.0))
  {
    throw SkeletonError("skeleton: MinimumConfidentShare must be in [0, 1]");
  }
  if (!(options.SpacingFactor >= 0.0 && options.SpacingFactor <= 10.0))
  {
    throw SkeletonError("skeleton: thinning SpacingFactor must be in [0, 10]");
  }
  if (options.MinimumNeighbors < 2 || options.MinimumNeighbors > 1000)
  {
    throw SkeletonError("skeleton: MinimumNeighbors must be in [2, 1000]");
  }
}

namespace
{

struct Projection
{
  Eigen::Vector3d Position;
  Eigen::Vector3d Axis;
  double Confidence;
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
  return { moved, axis, std::clamp(confidence, 0.0, 1.0) };
}

} // namespace

ThinnedCloud ThinProjectedCloud(const ProjectedCloud& cloud,
  const SkeletonThinningOptions& options, const ParallelFor& parallelFor,
  const ProgressCallback& progress)
{
  ValidateThinningOptions(options);
  ThinnedCloud result;
  const std::size_t count = cloud.Size();
  const auto rows = static_cast<Eigen::Index>(count);
  result.Positions = cloud.Positions;
  result.Axis = PointMatrix::Zero(rows, 3);
  result.Confidence.assign(count, 0.0);
  if (count == 0)
  {
    return result;
  }

  const auto abortedResult = [&result]() {
    result = ThinnedCloud();
    result.Aborted = true;
    return result;
  };

  std::unique_ptr<SkeletonPointTree> tree = std::make_unique<SkeletonPointTree>(cloud.Positions);
  PointMatrix nextPositions(rows, 3);
  const std::size_t blocks = std::min<std::size_t>(16, count);
  const std::size_t blockSize = (count + blocks - 1) / blocks;
  const auto minimumNeighbors = static_cast<double>(options.MinimumNeighbors);
  for (int iteration = 0; iteration < options.NumberOfIterations; ++iteration)
  {
    if (options.ContractCloud && iteration > 0)
    {
      tree = std::make_unique<SkeletonPointTree>(result.Positions);
    }
    for (std::size_t blockBegin = 0; blockBegin < count; blockBegin += blockSize)
    {
      const std::size_t blockEnd = std::min(count, blockBegin + blockSize);
      parallelFor(blockEnd - blockBegin, [&](std::size_t begin, std::size_t end) {
        for (std::size_t k = blockBegin + begin; k < blockBegin + end; ++k)
        {
          const auto i = static_cast<Eigen::Index>(k);
          const Projection projection = ProjectOntoRegressionLine(*tree,
            result.Positions.row(i).transpose(), options.NeighborhoodScale * cloud.Radius[k],
            minimumNeighbors);
          nextPositions.row(i) = projection.Position.transpose();
          result.Axis.row(i) = projection.Axis.transpose();
          result.Confidence[k] = projection.Confidence;
        }
      });
      const double done = (static_cast<double>(iteration) +
                            static_cast<double>(blockEnd) / static_cast<double>(count)) /
        (options.NumberOfIterations + 1.0);
      if (progress && !progress(done))
      {
        return abortedResult();
      }
    }
    result.Positions.swap(nextPositions);
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
