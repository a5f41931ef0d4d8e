// SPDX-License-Identifier: BSD-3-Clause
// ConeSampling: the deterministic ray pattern of the shape diameter function.
//
// Paper (Shapira, Shamir & Cohen-Or 2008, Sect. 3): "we use a cone centered around its
// inward-normal direction ... and send several rays inside this cone"; default opening angle
// 120 degrees, 30 rays; "the weights used are the inverse of the angle between the ray to the
// center of the cone".
//
// Pattern (the paper does not specify one): a golden-angle (Vogel) spiral that is uniform in
// solid angle over the cap of half-angle alpha = coneAngle / 2. Ray i of N (i = 0..N-1) has
//     cos(theta_i) = 1 - (1 - cos(alpha)) * (i + 1/2) / N,   phi_i = i * pi * (3 - sqrt(5)),
// i.e. each ray sits in the middle (in solid angle) of one of N equal-area annuli, so no ray
// lies on the axis or on the rim; at the defaults theta runs from 7.4 to 59.5 degrees. For
// N = 1 the single ray is the cone axis itself (the paper's "single ray to the antipodal
// point").
//
// Weights: w_i = 1 / max(theta_i, thetaFloor), thetaFloor = rho / 2, where rho is the
// angular radius of a cap of solid angle Omega / N (Omega = the cone's solid angle), i.e. half
// the angular size of one ray's share of the cone. A ray ON the axis (only for N = 1) thus
// gets weight 1 / thetaFloor, never infinity. For N >= 2 every theta_i exceeds thetaFloor
// (theta_0 ~ rho / sqrt(2)), so the floor changes nothing and w_i = 1 / theta_i exactly.
//
// Frames: the pattern lives in a local frame (X, Y, A) with A the cone axis (inward normal).
//   - Face origins: X = the face's first edge (v1 - v0) projected onto the plane normal to A,
//     so a rigid motion of the mesh moves the rays with it.
//   - Vertex origins (no edge given): X from A alone with the branchless orthonormal basis of
//     Duff et al., "Building an Orthonormal Basis, Revisited", JCGT 6(1), 2017. Deterministic
//     but tied to the world axes, so vertex SDF is invariant to rigid motion only up to the
//     pattern's rotation about the normal.
//   Y = A x X, so (X, Y, A) is right-handed.
#pragma once

#include "Errors.h"
#include <stdexcept>
#include <vector>

namespace shapediameter
{

/// Valid ranges, checked by MakeConePattern.
constexpr int kMaxConeRays = 4096;
/// N, rays per cone: vtkShapeDiameterFilter::NumberOfRays and the XML use the same [1, 4096].
inline constexpr Range<int> NumberOfRaysRange{ 1, kMaxConeRays };

struct ConePattern
{
  /// N x 3 unit directions in the local frame, z = cone axis.
  std::vector<double> LocalDirections;
  /// N angles between each ray and the axis, radians.
  std::vector<double> AnglesToAxis;
  /// N weights 1 / max(angle, AxisAngleFloor).
  std::vector<double> Weights;
  /// The smallest angle used in a weight (see header).
  double AxisAngleFloor = 0;

  int GetNumberOfRays() const { return static_cast<int>(this->AnglesToAxis.size()); }
};

/// numberOfRays in NumberOfRaysRange; coneAngleDegrees (full opening angle) in (0, 180).
/// Throws Error otherwise.
ConePattern MakeConePattern(int numberOfRays, double coneAngleDegrees);

/// Right-handed orthonormal frame around the unit axis: firstAxis is `preferredFirstAxis`
/// projected onto the plane normal to the axis and normalised; when that projection is
/// (nearly) zero or not finite (or preferredFirstAxis is null), the Duff et al. frame of the
/// axis is used. secondAxis = axis x firstAxis.
void MakeConeFrame(const double axis[3], const double* preferredFirstAxis, double firstAxis[3],
  double secondAxis[3]);

/// World directions (N x 3) of the pattern in the frame (firstAxis, secondAxis, axis).
void OrientConePattern(const ConePattern& pattern, const double axis[3], const double firstAxis[3],
  const double secondAxis[3], double* outDirections);

} // namespace shapediameter
