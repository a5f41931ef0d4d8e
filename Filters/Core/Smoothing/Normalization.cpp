// SPDX-License-Identifier: BSD-3-Clause
#include "Smoothing/Normalization.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace shapediameter
{

std::pair<double, double> NormalizationRange(const std::vector<double>& values, const NormalizationOptions& options)
{
  if (options.UseGivenRange)
  {
    if (!std::isfinite(options.RangeMinimum) || !std::isfinite(options.RangeMaximum) ||
      !(options.RangeMaximum > options.RangeMinimum))
    {
      throw Error("the given range must be finite with its maximum above its minimum");
    }
    return { options.RangeMinimum, options.RangeMaximum };
  }
  if (values.empty())
  {
    return { 0.0, 0.0 };
  }
  const auto [minimumIt, maximumIt] = std::minmax_element(values.begin(), values.end());
  return { *minimumIt, *maximumIt };
}

std::vector<double> NormalizeLogarithmic(const std::vector<double>& values, const NormalizationOptions& options)
{
  const double alpha = options.Alpha;
  CheckRange(alpha, NormalizeLogarithmicAlphaRange, "normalization: Alpha");
  for (std::size_t i = 0; i < values.size(); ++i)
  {
    if (!std::isfinite(values[i]))
    {
      throw Error("non-finite value at index " + std::to_string(i));
    }
  }
  const auto [minimum, maximum] = NormalizationRange(values, options);
  std::vector<double> normalized(values.size(), 0.0);
  if (values.empty() || !(maximum > minimum))
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
