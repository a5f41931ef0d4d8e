// SPDX-License-Identifier: BSD-3-Clause
#include "ExactSum.h"

#include <cmath>
#include <cstddef>

namespace shapediameter
{

void ExactSum::Add(double term)
{
  // Each partial is folded into the running term with an error-free addition (hi + lo equals
  // x + y exactly); the non-zero errors stay as partials, the last hi becomes the largest.
  std::size_t kept = 0;
  double x = term;
  for (double y : this->Parts)
  {
    if (std::abs(x) < std::abs(y))
    {
      const double swap = x;
      x = y;
      y = swap;
    }
    const double hi = x + y;
    const double lo = y - (hi - x);
    if (lo != 0.0)
    {
      this->Parts[kept++] = lo;
    }
    x = hi;
  }
  this->Parts.resize(kept);
  this->Parts.push_back(x);
}

void ExactSum::Add(const std::vector<double>& terms)
{
  for (const double term : terms)
  {
    this->Add(term);
  }
}

double ExactSum::Rounded() const
{
  // From the largest partial down, until the first addition that is not exact; then the
  // half-way case is settled by the sign of the next smaller partial (round half to even
  // would otherwise be decided on an incomplete sum).
  std::size_t n = this->Parts.size();
  if (n == 0)
  {
    return 0.0;
  }
  double hi = this->Parts[--n];
  double lo = 0.0;
  while (n > 0)
  {
    const double x = hi;
    const double y = this->Parts[--n];
    hi = x + y;
    const double rounded = hi - x;
    lo = y - rounded;
    if (lo != 0.0)
    {
      break;
    }
  }
  if (n > 0 && ((lo < 0.0 && this->Parts[n - 1] < 0.0) || (lo > 0.0 && this->Parts[n - 1] > 0.0)))
  {
    const double y = lo * 2.0;
    const double x = hi + y;
    if (y == x - hi)
    {
      hi = x;
    }
  }
  return hi;
}

} // namespace shapediameter
