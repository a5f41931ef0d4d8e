// SPDX-License-Identifier: BSD-3-Clause
// A sum of doubles that does not depend on the order of its terms.
//
// What it computes
//   The exact sum of the terms added, kept as a short list of non-overlapping partial sums
//   (Shewchuk's adaptive-precision expansion, 1997; the method behind Python's math.fsum), and
//   that sum correctly rounded to a double on request. Because the rounded value is a function
//   of the exact sum alone, it is the same for any order and any grouping of the terms: two
//   sums merged (Add of the other's Partials) round to the same double as one sum of all their
//   terms. That is what makes a whole-surface mean computed by several processes, each over
//   its own faces, equal bit for bit to the serial one (FaceGraph::MeanEdgeLength).
//
// Limits: the terms must be finite and their partial sums must not overflow (no term above
//   about 1e307 in magnitude): the sum is then exact. Finite terms of a mesh (lengths) are far
//   from that.
// Cost: each Add walks the partials; for terms of one sign and similar magnitudes there are
//   one to three of them (a few nanoseconds per term).
#pragma once

#include <vector>

namespace shapediameter
{

class ExactSum
{
public:
  /// Adds one finite term.
  void Add(double term);
  /// Adds every term (for instance another sum's Partials()).
  void Add(const std::vector<double>& terms);
  /// The non-overlapping partial sums, increasing in magnitude: their exact total is the sum.
  const std::vector<double>& Partials() const { return this->Parts; }
  /// The sum correctly rounded to the nearest double (ties to even); 0 for no terms.
  double Rounded() const;

private:
  std::vector<double> Parts;
};

} // namespace shapediameter
