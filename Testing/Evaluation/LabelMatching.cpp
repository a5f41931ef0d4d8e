// SPDX-License-Identifier: BSD-3-Clause
#include "LabelMatching.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace shapediameter
{
namespace
{

constexpr std::size_t kMaxDistinctLabels = 2000;

/// Sorted distinct labels and each value's index among them.
std::vector<int> Compact(const std::vector<int>& labels, std::vector<std::size_t>& index)
{
  std::vector<int> distinct(labels);
  std::sort(distinct.begin(), distinct.end());
  distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
  if (distinct.size() > kMaxDistinctLabels)
  {
    throw LabelMatchingError("label matching: more than 2000 distinct labels");
  }
  index.resize(labels.size());
  for (std::size_t f = 0; f < labels.size(); ++f)
  {
    index[f] = static_cast<std::size_t>(
      std::lower_bound(distinct.begin(), distinct.end(), labels[f]) - distinct.begin());
  }
  return distinct;
}

} // namespace

std::vector<int> SolveAssignment(const std::vector<double>& cost, std::size_t size)
{
  if (cost.size() != size * size)
  {
    throw LabelMatchingError("assignment: the cost matrix must be size x size");
  }
  for (double c : cost)
  {
    if (!std::isfinite(c))
    {
      throw LabelMatchingError("assignment: a cost is NaN or infinite");
    }
  }
  // Shortest augmenting paths with row/column potentials (Kuhn-Munkres). Rows are added one
  // by one; column 0 is a virtual column holding the row being inserted. 1-based inside.
  const double infinity = std::numeric_limits<double>::infinity();
  std::vector<double> rowPotential(size + 1, 0.0), columnPotential(size + 1, 0.0);
  std::vector<std::size_t> rowOfColumn(size + 1, 0), previousColumn(size + 1, 0);
  for (std::size_t row = 1; row <= size; ++row)
  {
    rowOfColumn[0] = row;
    std::size_t column = 0;
    std::vector<double> slack(size + 1, infinity);
    std::vector<char> visited(size + 1, 0);
    do
    {
      visited[column] = 1;
      const std::size_t currentRow = rowOfColumn[column];
      double delta = infinity;
      std::size_t nextColumn = 0;
      for (std::size_t j = 1; j <= size; ++j)
      {
        if (visited[j])
        {
          continue;
        }
        const double reduced =
          cost[(currentRow - 1) * size + (j - 1)] - rowPotential[currentRow] - columnPotential[j];
        if (reduced < slack[j])
        {
          slack[j] = reduced;
          previousColumn[j] = column;
        }
        if (slack[j] < delta)
        {
          delta = slack[j];
          nextColumn = j;
        }
      }
      for (std::size_t j = 0; j <= size; ++j)
      {
        if (visited[j])
        {
          rowPotential[rowOfColumn[j]] += delta;
          columnPotential[j] -= delta;
        }
        else
        {
          slack[j] -= delta;
        }
      }
      column = nextColumn;
    } while (rowOfColumn[column] != 0);
    // Flip the augmenting path back to the virtual column.
    while (column != 0)
    {
      const std::size_t previous = previousColumn[column];
      rowOfColumn[column] = rowOfColumn[previous];
      column = previous;
    }
  }
  std::vector<int> assignment(size, -1);
  for (std::size_t j = 1; j <= size; ++j)
  {
    assignment[rowOfColumn[j] - 1] = static_cast<int>(j - 1);
  }
  return assignment;
}

LabelMatchingResult CompareLabelings(const std::vector<int>& first, const std::vector<int>& second)
{
  if (first.size() != second.size())
  {
    throw LabelMatchingError("label matching: the labelings have " + std::to_string(first.size()) +
      " and " + std::to_string(second.size()) + " faces");
  }
  LabelMatchingResult result;
  if (first.empty())
  {
    return result;
  }
  std::vector<std::size_t> firstIndex, secondIndex;
  const std::vector<int> firstLabels = Compact(first, firstIndex);
  const std::vector<int> secondLabels = Compact(second, secondIndex);
  const std::size_t size = std::max(firstLabels.size(), secondLabels.size());
  std::vector<double> overlap(size * size, 0.0);
  for (std::size_t f = 0; f < first.size(); ++f)
  {
    overlap[firstIndex[f] * size + secondIndex[f]] += 1.0;
  }
  std::vector<double> cost(overlap.size());
  std::transform(overlap.begin(), overlap.end(), cost.begin(), [](double c) { return -c; });
  const std::vector<int> assignment = SolveAssignment(cost, size);
  double matched = 0.0;
  for (std::size_t i = 0; i < firstLabels.size(); ++i)
  {
    const auto j = static_cast<std::size_t>(assignment[i]);
    const double shared = overlap[i * size + j];
    if (shared > 0.0)
    {
      matched += shared;
      result.Matching.emplace_back(firstLabels[i], secondLabels[j]);
    }
  }
  result.DifferentCount = first.size() - static_cast<std::size_t>(matched);
  result.PercentDifferent = 100.0 * static_cast<double>(result.DifferentCount) / static_cast<double>(first.size());
  return result;
}

} // namespace shapediameter
