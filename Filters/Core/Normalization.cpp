// SPDX-License-Identifier: BSD-3-Clause
#include "Normalization.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace shapediameter
{

std::vector<double> NormalizeLogarithmic(const std::vector<double>& values, const NormalizationOptions& options)
{
  const double alpha = options.Alpha;
  if (!(alpha > 0.0) || !std::isfinite(alpha))
  {
    throw NormalizationError("alpha must be positive and finite");
  }
  for (std::size_t i = 0; i < values.size(); ++i)
  {
    if (!std::isfinite(values[i]))
    {
      throw NormalizationError("non-finite value at index " + std::to_string(i));
    }
  }
  std::vector<double> normalized(values.size(), 0.0);
  if (values.empty())
  {
    return normalized;
  }
  const auto [minimumIt, maximumIt] = std::minmax_element(values.begin(), values.end());
  const double minimum = *minimumIt;
  const double maximum = *maximumIt;
  if (!(maximum > minimum))
  {
    return normalized;
  }
  // Halving both sides keeps (x - min) / (max - min) finite when max - min overflows.
  const bool halve = !std::isfinite(maximum - minimum);
  const double scale = halve ? 0.5 : 1.0;
  const double range = scale * maximum - scale * minimum;
  const double logNormalizer = std::log1p(alpha);
  for (std::size_t i = 0; i < values.size(); ++i)
  {
    const double fraction = std::clamp((scale * values[i] - scale * minimum) / range, 0.0, 1.0);
    normalized[i] = std::clamp(std::log1p(fraction * alpha) / logNormalizer, 0.0, 1.0);
  }
  return normalized;
}

} // namespace shapediameter
