// SPDX-License-Identifier: BSD-3-Clause
#include "Skeleton/SkeletonPointTree.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>

namespace shapediameter
{

namespace
{

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

} // namespace shapediameter
