// SPDX-License-Identifier: BSD-3-Clause
// Consistent partitioning by the SDF: the steps of the paper's section 4, in order, as one call.
//
// What it computes
//   A partition of a polygon surface into parts of similar thickness, from the normalised SDF
//   of its faces (Shapira, Shamir, Cohen-Or 2008, section 4):
//     1. SharedFaceGraph         - the dual graph: adjacency, areas, normal angles (FaceGraph.h;
//                                  reused when a graph of the same surface is still held)
//     2. the cluster model       - a 1-D mixture of at most k Gaussians: the modes of the
//                                  area-weighted density (DensityModes.h, the default), the
//                                  paper's EM fit (GaussianMixture.h), or a given family model
//     3. ComputePosteriors       - P(cluster | f) of every face, the soft partition
//     4. BuildPartitionEnergy    - E = data term from the posteriors + lambda x weighted
//                                  concave-crease term (PartitionEnergy.h)
//     5. MinimizeMultilevel      - the k-way alpha-expansion graph cut, multilevel on large
//                                  meshes, plain below MultilevelOptions::DirectBelowFaces
//                                  (MultilevelCut.h, AlphaExpansion.h)
//     6. the hierarchy levels of the bands and their connected segments (PartitionEnergy.h)
//     7. RefineParts             - the fine level: each large segment of a band cut again by
//                                  the modes of its own values (PartRefinement.h); the
//                                  connected segments of the fine labels
//     8. MixtureHistogram        - the histogram of the values with the fitted densities
//                                  (the paper's Fig. 7 as data)
//   Bands (the cut's labels) are numbered by mixture mean, largest first (band 0 = the thickest
//   parts); the fine labels (`SDFCluster`) by band, then by mean. Without the refinement the
//   fine labels are the bands.
//   Each step's own header documents its method, parameters and deviations from the paper;
//   this file only chains them, maps the options and times the steps.
//
// Reference
//   Shapira, Shamir, Cohen-Or 2008, "Consistent mesh partitioning and skeletonisation using
//   the shape diameter function", The Visual Computer 24(4), section 4.
//
// Input (PartitionInput; views of the caller's arrays, which must outlive the call)
//   Points, FaceOffsets, FaceConnectivity  the polygons in CSR form, as BuildFaceGraph takes
//                                          them (any polygon size; counter-clockwise seen from
//                                          outside, for the concavity test).
//   FaceValues     one value per face, finite: the normalised SDF (VTK: `SDFNormalized`).
//   FamilyModel    optional: a mixture fitted on a family of meshes (another partition's
//                  Model). When given, it is used as is instead of fitting, so cluster i means
//                  the same kind of part on every member; ClusterModel and k are then not read.
//
// Parameters: PartitionOptions below; the options of each step are documented in its header.
//   The VTK adapter (vtkSDFGMMPartition) exposes the ones a user needs, with the same defaults.
//
// Degenerate input and errors
//   No faces, values of another size than the face count, an option outside its range (k
//   outside [0, 16], MaximumClusters outside [2, 16], HistogramBins outside [4, 4096]) -> Error. Every step throws Error (Errors.h) on what it cannot
//   process, with a one-line reason naming the step. The dual graph is
//   validated once (ValidateDualGraph, before the energy) and not again by the segments.
//   Constant values give one cluster; the cut may leave a cluster without faces.
//
// Threading and determinism
//   parallelFor runs the face graph, the posteriors, the energy, the cut's bands and the
//   segments; the result is bit-identical for any ParallelFor. progress receives [0, 1]
//   (0.1 after the face graph, 0.2 after the posteriors, the cut in [0.2, 0.95], 1 at the
//   end); returning false between the steps or during the cut aborts: the result is then
//   empty with Aborted = true. The cut may call progress from worker threads, one call at a
//   time (MultilevelCut.h).
#pragma once

#include "Errors.h"
#include "Partition/AlphaExpansion.h"
#include "Partition/DensityModes.h"
#include "Mesh/FaceGraph.h"
#include "Partition/GaussianMixture.h"
#include "Mesh/MeshTypes.h"
#include "Partition/MultilevelCut.h"
#include "Partition/PartRefinement.h"
#include "Parallel.h"
#include "Partition/PartitionEnergy.h"

#include <cstdint>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace shapediameter
{

/// Where the mixture of the clusters comes from (the family model, when given, overrides both).
enum class PartitionClusterModel
{
  /// The paper's EM fit of exactly k Gaussians (GaussianMixture.h); k = 0 picks the k in
  /// [2, MaximumClusters] with the lowest BIC.
  ExpectationMaximization = 0,
  /// The modes of the area-weighted density of the values, at most k of them (DensityModes.h).
  DensityModes = 1
};

struct PartitionOptions
{
  /// How the clusters are found; default DensityModes.
  PartitionClusterModel ClusterModel = PartitionClusterModel::DensityModes;
  /// k, default 5, NumberOfClustersRange [0, 16]: with DensityModes the most clusters; with EM exactly k, and 0 =
  /// automatic (lowest BIC in [2, MaximumClusters]).
  int NumberOfClusters = 5;
  /// Default 8, MaximumClustersRange [2, 16]: the most clusters when k = 0.
  int MaximumClusters = 8;
  /// The EM fit (Restarts, MaximumIterations, Seed, ...; GaussianMixture.h).
  GaussianMixtureOptions Mixture;
  /// The density modes (Bandwidth, MinimumProminence, ...; DensityModes.h). MaximumModes is not
  /// read: it is k, or MaximumClusters when k = 0.
  DensityModesOptions Modes;
  /// The energy: Lambda (the paper's λ), Epsilon (ε), ConvexityFactor, ...
  /// (PartitionEnergy.h).
  PartitionEnergyOptions Energy;
  /// When and how the cut is multilevel (MultilevelCut.h).
  MultilevelOptions Multilevel;
  /// The alpha-expansion moves (AlphaExpansion.h).
  AlphaExpansionOptions AlphaExpansion;
  /// The fine level (PartRefinement.h): Enabled, MinimumAreaShare, the modes inside a part.
  /// Its Energy, Multilevel and AlphaExpansion are not read: the partition's own are used.
  PartRefinementOptions Refinement;
  /// Bins of the histogram (MixtureHistogram), default 64, HistogramBinsRange [4, 4096].
  int HistogramBins = 64;
};

// The ranges of the options vtkSDFGMMPartition exposes, checked by ValidatePartitionOptions and
// by the steps' validators; the filter's vtkSetClampMacro and Plugin/ShapeDiameter.xml repeat
// these numbers (Testing/Filters/TestParameterRanges.cxx). Where the core was wider before, the
// filter's range won: NumberOfClusters was [0, inf), MaximumClusters [1, inf), HistogramBins
// [1, inf). The others: RestartsRange, MaximumIterationsRange (GaussianMixture.h), LambdaRange,
// EpsilonRange, ConvexityFactorRange (PartitionEnergy.h), ModeBandwidthRange,
// ModeProminenceRange, ModeValleyDepthRange (DensityModes.h), RefinementMinimumAreaRange
// (PartRefinement.h).
/// NumberOfClusters, k: 0 = automatic.
inline constexpr Range<int> NumberOfClustersRange{ 0, 16 };
/// MaximumClusters: the BIC search starts at 2.
inline constexpr Range<int> MaximumClustersRange{ 2, 16 };
/// HistogramBins.
inline constexpr Range<int> HistogramBinsRange{ 4, 4096 };

struct PartitionShare; // Partition/DistributedPartition.h

/// What is partitioned; see the header comment.
struct PartitionInput
{
  PointsView Points;
  const std::vector<std::int64_t>& FaceOffsets;
  const std::vector<std::int64_t>& FaceConnectivity;
  ValuesView FaceValues;
  const GaussianMixtureModel* FamilyModel = nullptr;
  /// Distributed runs: the faces are this process's share of a surface split over processes
  /// (its own faces and a halo around them); the result is the partition of the whole
  /// surface, on the own faces (Partition/DistributedPartition.h). nullptr: the faces are the
  /// whole surface.
  const PartitionShare* Share = nullptr;
};

/// The histogram of the values and the mixture's densities over the same bins (the paper's
/// Fig. 7 as data). Bins are equal, over [min - 4 sigma_max, max + 4 sigma_max] of the values.
struct PartitionHistogram
{
  std::vector<double> BinCenters;
  /// Values per bin; the counts sum to the number of values.
  std::vector<double> Counts;
  /// Counts / (values x bin width): integrates to 1.
  std::vector<double> Density;
  /// Per component, per bin: weight x the mean normal density over the bin (exact, so each
  /// curve integrates to its weight, even for a Gaussian narrower than a bin).
  std::vector<std::vector<double>> Components;
  /// Sum of the components per bin.
  std::vector<double> Mixture;
};

/// Wall-clock time of each step in ms (for benchmarks; not part of the partition).
struct PartitionTimings
{
  double FaceGraphMs = 0.0;
  /// EM or density modes (a copy of the family model when given).
  double ClusterModelMs = 0.0;
  double PosteriorsMs = 0.0;
  /// The dual graph's validation and the energy.
  double EnergyMs = 0.0;
  /// The multilevel or plain alpha-expansion.
  double CutMs = 0.0;
  /// The connected segments and the hierarchy levels.
  double SegmentsMs = 0.0;
  /// The fine level and its segments.
  double RefinementMs = 0.0;
  double HistogramMs = 0.0;
};

struct PartitionResult
{
  /// The mixture used: fitted, or the family model. Its ComponentCount() is the k fitted.
  GaussianMixtureModel Model;
  /// P(cluster | f), faces x k, rows sum to 1.
  PosteriorMatrix Probabilities;
  /// The band of each face after the cut, in [0, k) (`SDFBand`).
  std::vector<int> Bands;
  /// The fine label of each face (`SDFCluster`): the bands refined (PartRefinement.h), or the
  /// bands themselves when the refinement is off.
  std::vector<int> Labels;
  /// Per fine label, its band.
  std::vector<int> LabelBands;
  /// Levels[L - 1] = hierarchy level L = min(band, L), L = 1 .. k - 1 (`SDFLevel{L}`).
  std::vector<std::vector<int>> Levels;
  /// Connected parts of equal fine label, 0 = the largest area (`SDFSegment`).
  ConnectedSegments Segments;
  /// E of the labels (`SDFEnergy`).
  double Energy = 0.0;
  /// Alpha-expansion moves tried (diagnostics).
  int CutMoves = 0;
  PartitionHistogram Histogram;
  PartitionTimings Timings;
  /// The face graph used (SharedFaceGraph; see SmoothAndNormalizeResult::Graph).
  std::shared_ptr<const FaceGraph> Graph;
  /// True if the progress callback aborted the computation (the other members are then empty).
  /// Under processes: the graph cut ran on every process's faces (Partition/DistributedCut.h)
  /// rather than on the first process's gathered graph.
  bool CutOverProcesses = false;
  bool Aborted = false;
};

/// Throws Error if an option of the partition itself is outside its documented range
/// (the steps check their own options when they run).
void ValidatePartitionOptions(const PartitionOptions& options);

/// Step 2: the mixture of the clusters, fitted to the values weighted by the face areas as the
/// options say (a family model replaces it).
GaussianMixtureModel FitClusterModel(ValuesView values, const std::vector<double>& faceAreas, const PartitionOptions& options);

/// The SDF partition of section 4. See the header comment for inputs and guarantees.
PartitionResult PartitionBySDF(const PartitionInput& input, const PartitionOptions& options = {},
  const ParallelFor& parallelFor = SerialFor, const ProgressCallback& progress = {});

/**
 * Steps 2 to 8 on a dual graph that is already built (step 1 of PartitionBySDF): the
 * partition of the faces of `graph`, one value each, with `faceAreas` as their areas (the
 * graph's FaceArea is not read). PartitionBySDF builds the graph from polygons; a distributed
 * run assembles it from the rows every process computed for its own faces
 * (Partition/DistributedPartition.h). Validates the graph (ValidateDualGraph). The result has
 * no Graph and no FaceGraphMs; progress as PartitionBySDF's, from 0.1.
 *
 * releaseEdgeGeometry, if given, is called once the energy is built when nothing after it reads
 * the graph's normal angles, concave flags, edge lengths or face centres (the refinement, step 7,
 * does: not called when it is enabled); the caller may free them then. Why: a distributed run's
 * process 0 owns the assembled graph, whose angles, flags, lengths and centres (about 75 bytes
 * per face) would otherwise stay resident through the cut, the step's peak.
 */
PartitionResult PartitionOnDualGraph(DualGraphView graph, const std::vector<double>& faceAreas,
  ValuesView faceValues, const GaussianMixtureModel* familyModel, const PartitionOptions& options = {},
  const ParallelFor& parallelFor = SerialFor, const ProgressCallback& progress = {},
  const std::function<void()>& releaseEdgeGeometry = {});

/// Convenience: a triangle mesh.
PartitionResult PartitionBySDF(PointsView points, TrianglesView triangles, ValuesView faceValues,
  const PartitionOptions& options = {}, const ParallelFor& parallelFor = SerialFor,
  const ProgressCallback& progress = {});

/// The histogram of `values` in `bins` bins and the densities of `model` over them (see
/// PartitionHistogram). Throws Error on empty values, bins < 1 or an empty model.
PartitionHistogram MixtureHistogram(const GaussianMixtureModel& model, ValuesView values, int bins);

} // namespace shapediameter
