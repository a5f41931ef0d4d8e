// SPDX-License-Identifier: BSD-3-Clause
// The fine level of the hierarchy: every large part of a thickness band is cut again by the
// modes of its own SDF values.
//
// What it computes
//   The coarse partition (density modes over the whole mesh, then the graph cut) gives thickness
//   bands that hold across poses, but a band holds every part of about that thickness: the
//   fingers, the tail and the ears of one figure fall into one band, and a limb and the hand at
//   its end often do too. The paper's hierarchy answers this with more iso-values of the SDF
//   ("one iso-value may separate the arms, legs and head ... the second and third values might
//   separate the hands and the fingers", section 4). Here the further values are found per
//   part, where they are visible:
//     1. the coarse segments (connected parts of one band) covering at least MinimumAreaShare
//        of the area are refined, smaller ones are kept whole;
//     2. the area-weighted density of the part's own values is fitted with the density-mode
//        rules (DensityModes.h): the kernel keeps its width in nsdf units (Modes.Bandwidth
//        relative to the whole mesh's value range, not the part's), the prominence and valley
//        depth are relative to the part's own highest peak, so a mode that the global density
//        hid under a larger part's peak becomes visible, while noise on a part of nearly
//        constant thickness stays below the kernel's width;
//     3. a part with two or more modes is cut by the same energy as the coarse level
//        (PartitionEnergy.h) restricted to its faces and edges, with lambda scaled by
//        sqrt(whole area / part area) so that the smoothness weighs against the data as it
//        does on the whole surface (the energy normalises by the area it is given);
//     4. a fine label is a (band, level) pair: level 0 is a part's thickest fine label (a part
//        kept whole is level 0 of its band), so the fine labels of a band are the same kind
//        of region in every part; numbered by band (0 = the thickest), then level. Levels the
//        cut left without faces are dropped.
//   A part is never merged with another one: the fine labels refine the bands.
//
// Input
//   graph      the validated dual graph (ValidateDualGraph) of the whole surface;
//   values     one finite value per face (the nsdf);
//   bands      the coarse labels, one per face, in [0, bandCount);
//   segments   the connected segments of `bands` on `graph`.
//
// Parameters (PartRefinementOptions)
//   Enabled            false           true: refine; false: the fine labels are the bands.
//   MinimumAreaShare   0.02   [0, 1]   parts below this share of the area are not refined.
//   Modes                              the density-mode rules inside a part (DensityModes.h
//                                      defaults; MaximumModes 3: at most three fine labels
//                                      per part).
//   Energy, Multilevel, AlphaExpansion the cut's options (the partition's own).
//
// Deviation from the paper: the paper chooses k iso-values for the whole mesh; here a part gets
// further values only where its own density has valleys, so the count of parts follows the
// shape and not a global k.
//
// Why it is off by default: on the development data it made the benchmark parts barely finer,
// while a large part refined in some poses and not in others made the labels less consistent
// between poses (measurements: docs/partition.md).
//
// Threading and determinism: the parts are independent; parallelFor runs over them and the
// result is the same for any ParallelFor. Cost: one density fit per large part and one cut on
// its faces: about one more coarse cut in total.
#pragma once

#include "Parallel.h"
#include "Partition/AlphaExpansion.h"
#include "Partition/DensityModes.h"
#include "Partition/MultilevelCut.h"
#include "Partition/PartitionEnergy.h"

#include <vector>

namespace shapediameter
{

/// MinimumAreaShare (vtkSDFGMMPartition::RefinementMinimumArea and the XML repeat the range).
inline constexpr Range<double> RefinementMinimumAreaRange{ 0.0, 1.0 };

struct PartRefinementOptions
{
  bool Enabled = false;
  double MinimumAreaShare = 0.02; ///< RefinementMinimumAreaRange [0, 1]
  DensityModesOptions Modes = [] {
    DensityModesOptions modes;
    modes.MaximumModes = 3;
    return modes;
  }();
  PartitionEnergyOptions Energy;
  MultilevelOptions Multilevel;
  AlphaExpansionOptions AlphaExpansion;
};

struct PartRefinementResult
{
  /// Per face, the fine label (`SDFCluster`), numbered by band, then by mean (see header).
  std::vector<int> Labels;
  /// Per fine label, its band and the weighted mean of its faces' values.
  std::vector<int> LabelBand;
  std::vector<double> LabelMean;
  /// Parts that were cut into more than one fine label.
  int RefinedParts = 0;
  bool Aborted = false;
};

/// Throws Error on options outside their ranges.
void ValidatePartRefinementOptions(const PartRefinementOptions& options);

/// See the header comment.
PartRefinementResult RefineParts(const DualGraphView& graph, ValuesView values, const std::vector<int>& bands,
  const ConnectedSegments& segments, const PartRefinementOptions& options = {},
  const ParallelFor& parallelFor = SerialFor, const ProgressCallback& progress = {});

} // namespace shapediameter
