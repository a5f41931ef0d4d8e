// SPDX-License-Identifier: BSD-3-Clause
// The one error type of the core, and the parameter ranges it checks.
//
// Every core step signals input it cannot process (bad options, inconsistent sizes, non-finite
// values, malformed files) by throwing shapediameter::Error; what() is a one-line reason, prefixed
// by the step ("partition: ...", "skeleton: ..."). The VTK filters catch it once and report
// "Cannot <task>: <reason>" (vtkSDFSurfaceAlgorithm). Subclasses: OFFParseError, which also
// carries the input line, and HaloTooNarrowError (ProcessGroup.h), which is not bad input but a
// request to a distributed run to fall back to the whole surface.
//
// A parameter's valid range is stated once, as a Range constant next to its option in the step's
// options header; the step's Validate*Options checks it with CheckRange, and the filter's
// vtkSetClampMacro and the ParaView XML repeat its numbers (Testing/Filters/TestParameterRanges.cxx
// and Testing/Python/test_xml_matches_cpp.py keep the three equal).
#ifndef shapediameter_Errors_h
#define shapediameter_Errors_h

#include <cmath>
#include <cstdlib>
#include <sstream>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace shapediameter
{

/// Input a core step cannot process; what() is a one-line reason.
class Error : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

/// Closed interval [Low, High] of a parameter's valid values. With LowExclusive the interval is
/// (Low, High]: for values that must be strictly positive (a sigma, a factor that divides), where
/// the user-facing clamp (vtkSetClampMacro) still uses Low as its minimum because VTK has no open
/// bound; such a value is then rejected by the core, not silently used.
template <typename T>
struct Range
{
  T Low;
  T High;
  bool LowExclusive = false;

  /// False for NaN, tested first: an ordered comparison on NaN raises FE_INVALID, which the
  /// debug test runs trap.
  bool Contains(T value) const noexcept
  {
    if constexpr (std::is_floating_point_v<T>)
    {
      if (std::isnan(value))
      {
        return false;
      }
    }
    return (this->LowExclusive ? value > this->Low : value >= this->Low) && value <= this->High;
  }
};

namespace detail
{
template <typename T>
std::string FormatRangeValue(T value)
{
  if constexpr (std::is_floating_point_v<T>)
  {
    // The shortest precision that reads back as the same value: 0.0005, not 0.00050000000000000001.
    for (int precision = 6;; ++precision)
    {
      std::ostringstream stream;
      stream.precision(precision);
      stream << static_cast<double>(value);
      if (precision >= 17 || std::isnan(value) || std::strtod(stream.str().c_str(), nullptr) == static_cast<double>(value))
      {
        return stream.str();
      }
    }
  }
  else
  {
    std::ostringstream stream;
    stream << value;
    return stream.str();
  }
}
} // namespace detail

/// "<what> = <value> is outside [Low, High]" (or "(Low, High]"), for a one-line Error message.
template <typename T>
std::string RangeMessage(T value, const Range<T>& range, const std::string& what)
{
  return what + " = " + detail::FormatRangeValue(value) + " is outside " + (range.LowExclusive ? "(" : "[") +
    detail::FormatRangeValue(range.Low) + ", " + detail::FormatRangeValue(range.High) + "]";
}

/// Throws Error unless range contains value. `what` names the parameter with its step prefix,
/// e.g. "partition: NumberOfClusters".
template <typename T, typename V>
void CheckRange(V value, const Range<T>& range, const std::string& what)
{
  static_assert(std::is_arithmetic_v<V>, "CheckRange takes a number");
  // An integer option wider than T (std::size_t against Range<int>) must not wrap into range.
  if constexpr (std::is_integral_v<V> && std::is_integral_v<T>)
  {
    if (static_cast<V>(static_cast<T>(value)) != value || (value < 0) != (static_cast<T>(value) < 0))
    {
      throw Error(what + " = " + detail::FormatRangeValue(value) + " is outside " +
        (range.LowExclusive ? "(" : "[") + detail::FormatRangeValue(range.Low) + ", " +
        detail::FormatRangeValue(range.High) + "]");
    }
  }
  const T converted = static_cast<T>(value);
  if (!range.Contains(converted))
  {
    throw Error(RangeMessage(converted, range, what));
  }
}

} // namespace shapediameter

#endif
