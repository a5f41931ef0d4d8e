// SPDX-License-Identifier: BSD-3-Clause
// Log normalisation of the SDF to [0, 1].
//
// Paper: Shapira, Shamir, Cohen-Or 2008, section 4:
//
//   nsdf(f) = log( (sdf(f) - min(sdf)) / (max(sdf) - min(sdf)) * alpha + 1 ) / log(alpha + 1)
//
// Maps min -> 0 and max -> 1, monotone increasing, concave: the log stretches the low
// values, "enhancing the importance of delicate parts (which tend to have low SDF values)".
// Evaluated with log1p, which is the same function, accurate for small arguments.
//
// Parameters: alpha, default 4 (the paper's value in all its examples), valid range
// AlphaRange [0.001, 1000] (the filter's, vtkSDFBilateralSmooth; SmoothAndNormalize checks it).
// alpha -> 0 tends to the linear map; larger alpha stretches more.
// A documented wider check: NormalizeLogarithmic alone accepts any positive finite alpha,
// NormalizeLogarithmicAlphaRange (0, DBL_MAX] (the core's range before AlphaRange), because the
// function is well defined there and its tests use alpha = 1e-9 to check the linear limit to
// 1e-9 (which the log1p evaluation is for); only the user-facing chain is held to AlphaRange.
//
// Family range: min and max may be given instead of taken from the values (a family of
// meshes normalised with one range, so that one nsdf means one thickness on every member);
// values outside the range then map to 0 or 1.
//
// Degenerate cases: empty input -> empty output; a constant field (max == min) -> 0
// everywhere. Outputs are clamped to [0, 1] against rounding, never NaN.
// Bad input (throws Error): a non-finite value, alpha outside its range, a
// given range that is not finite or whose maximum is not above its minimum.
// No deviation from the paper (the given range is an extension for families).
#pragma once

#include "Errors.h"
#include <limits>
#include <stdexcept>
#include <utility>
#include <vector>

namespace shapediameter
{

struct NormalizationOptions
{
  /// alpha of the paper, AlphaRange [0.001, 1000] (NormalizeLogarithmic alone: (0, DBL_MAX]).
  double Alpha = 4.0;
  /// When true, RangeMinimum and RangeMaximum replace the values' own min and max.
  bool UseGivenRange = false;
  double RangeMinimum = 0.0;
  double RangeMaximum = 1.0;
};

/// Alpha, the user-facing range: vtkSDFBilateralSmooth's vtkSetClampMacro repeats it
/// (Testing/Filters/TestParameterRanges.cxx) and SmoothAndNormalize checks it. Was (0, inf) for
/// the options before.
inline constexpr Range<double> AlphaRange{ 0.001, 1000.0 };
/// Alpha as NormalizeLogarithmic alone checks it (see the header comment): positive and finite.
inline constexpr Range<double> NormalizeLogarithmicAlphaRange{ 0.0, std::numeric_limits<double>::max(), true };

/// The [min, max] NormalizeLogarithmic maps to [0, 1]: the given range or the values' own
/// (0, 0 for empty input).
std::pair<double, double> NormalizationRange(const std::vector<double>& values, const NormalizationOptions& options = {});

/// nsdf of every value (see the header comment).
std::vector<double> NormalizeLogarithmic(const std::vector<double>& values, const NormalizationOptions& options = {});

} // namespace shapediameter
