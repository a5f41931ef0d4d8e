// SPDX-License-Identifier: BSD-3-Clause
// Clusters that follow the modes of the SDF distribution: an alternative to the paper's EM fit
// (GaussianMixture.h) for pose-consistent partitions.
//
// Why
//   The paper fits k Gaussians to the histogram of the normalised SDF by EM (section 4). With
//   k above the number of thickness levels a shape really has, EM puts a component boundary
//   inside a dense part of the histogram, where a small pose-dependent shift of the values
//   moves a whole limb to another cluster, so the EM argmax can disagree between poses,
//   while the area-weighted density of the values keeps its modes (measurements:
//   docs/partition.md). Clusters bounded by the density's valleys move
//   little when the values shift a little, because few faces lie near a valley.
//
// What it computes
//   1. The area-weighted histogram (BinCount bins over [min, max]) smoothed by a Gaussian
//      kernel of standard deviation Bandwidth x (max - min), evaluated on GridSize points over
//      [min - 3h, max + 3h]: a kernel density estimate f.
//   2. Its local maxima and how far each rises above its key saddle (topographic: the highest
//      saddle that separates it from a higher peak, or the lowest point towards the end of the
//      range when no higher peak lies that way): its prominence, relative to the highest peak,
//      and its valley depth, relative to its own height.
//   3. The modes with prominence >= MinimumProminence and valley depth >= MinimumValleyDepth,
//      the MaximumModes most prominent of them (ties: the lower value first). Between two
//      neighbouring kept modes, the valley is the lowest grid point (the first of equals).
//   4. One Gaussian per basin between valleys: the weighted mean and standard deviation
//      (floored at MinSigmaRelative x (max - min)) of the values in the basin, weight = the
//      basin's share of the total weight. Sorted by mean, largest first, like the EM fit, so the
//      result feeds the same posteriors, graph cut and hierarchy.
//
// Parameters (DensityModesOptions; none of them is in the paper)
//   Bandwidth          0.015  (0, 1]   kernel sigma, relative to the value range: fine enough
//                                      for the thickness levels people cut on the segmentation
//                                      benchmark (docs/partition.md).
//   MinimumProminence  0.01   [0, 1]   relative to the highest peak: drops bumps of a few faces.
//   MinimumValleyDepth 0      [0, 1]   relative to the mode's own height: > 0 asks a mode to be
//                                      separated from its higher neighbour by a valley that deep,
//                                      so that a shoulder on the flank of a larger mode, which
//                                      comes and goes with the pose, is not a cluster. Off by
//                                      default: the graph cut's λ (PartitionEnergy.h) removes
//                                      the small parts such a mode gives, and the valley depth
//                                      cost the benchmark (docs/partition.md).
//   MaximumModes       5      [1, 64]  at most this many clusters (the filter's k).
//   BinCount 2048, GridSize 1201; MinSigmaRelative 1e-3.
//
// Degenerate cases: constant values -> one component (sigma = the floor relative to
// max(|value|, 1)); zero total weight -> every value weighs 1. Throws Error on
// empty input, sizes that differ, non-finite values or a negative or non-finite weight.
//
// Why a valley depth: at the partition's earlier λ 0.03, with the prominence relative to the
// highest peak alone, weak modes of unseen pose families straddled the threshold from pose to
// pose (the lion got 3, 4 or 5 clusters by pose). Shoulders and real modes overlap in
// prominence but not in valley depth; the figures and the margins, which are narrow:
// docs/partition.md. At today's λ 0.12 the graph cut drops such a mode's small parts, so the
// partition's default is 0.
//
// Deviation from the paper: the number of clusters and their boundaries come from the density
// rather than from k; k only caps the count. A shape with fewer thickness levels than k gets
// fewer clusters (hand.off: 4 modes at the defaults, of which the cut keeps 2).
#pragma once

#include "Errors.h"
#include "Partition/GaussianMixture.h"

#include <stdexcept>
#include <string>
#include <vector>

namespace shapediameter
{

// The user-facing ranges of the options vtkSDFGMMPartition exposes (ModeBandwidth,
// ModeProminence, ModeValleyDepth; the filter's clamps and the XML repeat them), checked by
// ValidatePartitionOptions on PartitionOptions::Modes. FitDensityModes itself keeps the wider
// ranges of the table above ((0, 1], [0, inf), [0, 1]): the fine level (PartRefinement.cpp)
// widens a part's bandwidth up to 1.
inline constexpr Range<double> ModeBandwidthRange{ 0.001, 0.5 };
inline constexpr Range<double> ModeProminenceRange{ 0.0, 1.0 };
inline constexpr Range<double> ModeValleyDepthRange{ 0.0, 1.0 };

struct DensityModesOptions
{
  double Bandwidth = 0.015;         ///< (0, 1]; as a partition option ModeBandwidthRange [0.001, 0.5]
  double MinimumProminence = 0.01;  ///< [0, inf); as a partition option ModeProminenceRange [0, 1]
  double MinimumValleyDepth = 0.0;  ///< [0, 1] = ModeValleyDepthRange
  int MaximumModes = 5;
  int BinCount = 2048;
  int GridSize = 1201;
  double MinSigmaRelative = 1e-3;
};

struct DensityModesResult
{
  GaussianMixtureModel Model;    ///< one Gaussian per kept mode's basin, largest mean first
  std::vector<double> Modes;      ///< positions of the kept modes, increasing
  std::vector<double> Prominences; ///< of the kept modes, relative to the highest peak
  std::vector<double> ValleyDepths; ///< of the kept modes, relative to their own height
  std::vector<double> Valleys;    ///< between neighbouring kept modes, increasing
};

/// Fits the modes of the weighted density of `values` (see the header comment).
DensityModesResult FitDensityModes(ValuesView values, ValuesView weights, const DensityModesOptions& options = {});

} // namespace shapediameter
