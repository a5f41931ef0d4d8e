// SPDX-License-Identifier: BSD-3-Clause
#include "RayCasting/ConeSampling.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace shapediameter
{

namespace
{
constexpr double kPi = 3.14159265358979323846;
}

ConePattern MakeConePattern(int numberOfRays, double coneAngleDegrees)
{
  CheckRange(numberOfRays, NumberOfRaysRange, "cone sampling: the number of rays");
  // Open at both ends (Range has an inclusive High), so not CheckRange.
  if (!(coneAngleDegrees > 0 && coneAngleDegrees < 180))
  {
    throw Error(
      "cone sampling: the cone angle must be in (0, 180) degrees, got " +
      std::to_string(coneAngleDegrees));
  }
  const double halfAngle = 0.5 * coneAngleDegrees * kPi / 180.0;
  const double capHeight = 1.0 - std::cos(halfAngle); // solid angle / (2 pi)
  const double n = numberOfRays;
  const double goldenAngle = kPi * (3.0 - std::sqrt(5.0));

  ConePattern pattern;
  pattern.AxisAngleFloor = 0.5 * std::acos(1.0 - capHeight / n);
  pattern.LocalDirections.resize(3 * static_cast<std::size_t>(numberOfRays));
  pattern.AnglesToAxis.resize(static_cast<std::size_t>(numberOfRays));
  pattern.Weights.resize(static_cast<std::size_t>(numberOfRays));
  for (int i = 0; i < numberOfRays; ++i)
  {
    const double cosTheta = numberOfRays == 1 ? 1.0 : 1.0 - capHeight * (i + 0.5) / n;
    const double theta = std::acos(cosTheta);
    const double sinTheta = std::sin(theta);
    const double phi = goldenAngle * i;
    const auto k = static_cast<std::size_t>(i);
    pattern.LocalDirections[3 * k + 0] = sinTheta * std::cos(phi);
    pattern.LocalDirections[3 * k + 1] = sinTheta * std::sin(phi);
    pattern.LocalDirections[3 * k + 2] = cosTheta;
    pattern.AnglesToAxis[k] = theta;
    pattern.Weights[k] = 1.0 / std::max(theta, pattern.AxisAngleFloor);
  }
  return pattern;
}

void MakeConeFrame(const double axis[3], const double* preferredFirstAxis, double firstAxis[3],
  double secondAxis[3])
{
  bool haveFirstAxis = false;
  if (preferredFirstAxis)
  {
    const double* e = preferredFirstAxis;
    const double along = e[0] * axis[0] + e[1] * axis[1] + e[2] * axis[2];
    const double p[3] = { e[0] - along * axis[0], e[1] - along * axis[1], e[2] - along * axis[2] };
    const double length2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
    const double edgeLength2 = e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
    // Reject an edge (nearly) parallel to the axis: its projection's direction is noise.
    if (std::isfinite(length2) && length2 > 1e-12 * edgeLength2 && length2 > 0)
    {
      const double inverseLength = 1.0 / std::sqrt(length2);
      for (int c = 0; c < 3; ++c)
      {
        firstAxis[c] = p[c] * inverseLength;
      }
      haveFirstAxis = true;
    }
  }
  if (!haveFirstAxis)
  {
    // Duff et al. 2017, listing 3 (first basis vector).
    const double sign = std::copysign(1.0, axis[2]);
    const double a = -1.0 / (sign + axis[2]);
    const double b = axis[0] * axis[1] * a;
    firstAxis[0] = 1.0 + sign * axis[0] * axis[0] * a;
    firstAxis[1] = sign * b;
    firstAxis[2] = -sign * axis[0];
  }
  secondAxis[0] = axis[1] * firstAxis[2] - axis[2] * firstAxis[1];
  secondAxis[1] = axis[2] * firstAxis[0] - axis[0] * firstAxis[2];
  secondAxis[2] = axis[0] * firstAxis[1] - axis[1] * firstAxis[0];
}

void OrientConePattern(const ConePattern& pattern, const double axis[3], const double firstAxis[3],
  const double secondAxis[3], double* outDirections)
{
  const std::size_t count = pattern.AnglesToAxis.size();
  const double* local = pattern.LocalDirections.data();
  for (std::size_t i = 0; i < count; ++i)
  {
    const double x = local[3 * i], y = local[3 * i + 1], z = local[3 * i + 2];
    for (int c = 0; c < 3; ++c)
    {
      outDirections[3 * i + c] = x * firstAxis[c] + y * secondAxis[c] + z * axis[c];
    }
  }
}

} // namespace shapediameter
