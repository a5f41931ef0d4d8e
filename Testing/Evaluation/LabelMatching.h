// SPDX-License-Identifier: BSD-3-Clause
// Pose consistency of a partitioning: the measure of Table 2.
//
// What it computes
//   Shapira, Shamir & Cohen-Or 2008, Section 4, Table 2: "percent of triangles assigned to a
//   different part between all pairs of poses". Two labelings of the same faces (identical
//   connectivity, e.g. `SDFCluster` of two poses) are compared after the best one-to-one
//   matching of their labels: the matching maximises the number of faces whose labels
//   correspond (a linear assignment problem on the label confusion matrix, solved exactly by
//   the Hungarian algorithm with potentials, O(m^3) for m distinct labels). The result is
//   100 (n - matched faces) / n.
//   Labels are any integers; only the labels that occur matter. When the two labelings have a
//   different number of labels, the extra labels stay unmatched and all their faces count as
//   different.
//
// Degenerate cases and errors (LabelMatchingError)
//   - sizes differ: error. Empty labelings: 0 % (nothing differs).
//   - more than 2000 distinct labels in one labeling: error (the O(m^3) matching is meant for
//     clusters and segments, not arbitrary ids).
//
// Deviation from the paper: the paper does not say how parts are matched between poses; the
//   best one-to-one matching is the smallest difference any matching can show.
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace shapediameter
{

class LabelMatchingError : public std::runtime_error
{
public:
  explicit LabelMatchingError(const std::string& reason)
    : std::runtime_error(reason)
  {
  }
};

struct LabelMatchingResult
{
  double PercentDifferent = 0.0; ///< in [0, 100]
  std::size_t DifferentCount = 0;  ///< faces not matched
  /// (label in first, label in second) pairs of the optimal matching, sorted by first label;
  /// only pairs sharing at least one face are listed.
  std::vector<std::pair<int, int>> Matching;
};

/// Table 2 measure between two labelings of the same faces.
LabelMatchingResult CompareLabelings(const std::vector<int>& first, const std::vector<int>& second);

/// Minimum-cost perfect assignment of a square cost matrix (row-major, size x size):
/// result[row] = column. Exposed for tests. Costs must be finite (LabelMatchingError).
std::vector<int> SolveAssignment(const std::vector<double>& cost, std::size_t size);

} // namespace shapediameter
