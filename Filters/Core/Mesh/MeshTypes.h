// SPDX-License-Identifier: BSD-3-Clause
// Plain data types shared by the VTK-free algorithm core.
//
// The core never includes VTK. Adapters build these views over VTK arrays
// (Eigen::Map, no copy where the memory layout allows) and call the core.
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <functional>

namespace shapediameter
{

/// n x 3 vertex coordinates, one row per point.
using PointMatrix = Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>;
/// m x 3 triangle vertex indices (counter-clockwise seen from outside = outward normal).
using TriangleMatrix = Eigen::Matrix<std::int64_t, Eigen::Dynamic, 3, Eigen::RowMajor>;

/// Read-only views accepted by core functions (bind to matrices or Eigen::Map).
using PointsView = Eigen::Ref<const PointMatrix>;
using TrianglesView = Eigen::Ref<const TriangleMatrix>;

} // namespace shapediameter
