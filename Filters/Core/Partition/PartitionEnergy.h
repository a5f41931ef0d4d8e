// SPDX-License-Identifier: BSD-3-Clause
// The graph-cut energy of the SDF partitioning, and what is read off a labelling of faces.
//
// What it computes
//   Section 4 of Shapira, Shamir & Cohen-Or 2008: the energy minimised by the k-way graph cut
//     E(x) = sum_f w_f e1(f, x_f) + lambda sum_{f,g adjacent} w_fg e2(x_f, x_g)
//     e1(f, l)   = -log(P(l | f) + epsilon)                     (data term: the posterior of label l given face f)
//     e2(f, g)   = -log(max(phi'/pi, MinAngleRatio)) if x_f != x_g, 0 otherwise
//   with phi in [0, pi] the angle between the two face normals (0 = flat, pi = folded back),
//   phi' = phi on concave edges and phi' = ConvexityFactor * phi on convex edges. Cutting along
//   a concave crease is cheap, along a flat or convex region expensive (the paper: "concavity
//   as the positive dihedral angle ... normalized to [0, 1]"). Each unordered adjacent pair is
//   counted once. The pairwise term depends on the labels only through x_f != x_g (a Potts
//   model with one weight per edge), so every alpha-expansion move is submodular.
//   Geometric weights (GeometricWeights, default on): w_f = area_f / mean face area and
//   w_fg = shared edge length * F / sqrt(A), F faces of total area A. Then
//     E / F = (1/A) integral of e1 dA  +  lambda (1/sqrt(A)) integral over the cuts of e2 ds,
//   a property of the surface, not of its triangulation: the same lambda gives the same parts
//   at any resolution, in any unit, on irregular meshes. Without them (the paper's sums) the
//   smoothness weight falls as 1/sqrt(F) relative to the data term: fine meshes fragment,
//   coarse ones collapse. Measurements of both: docs/partition.md.
//   Also here: the functions of a final labelling over the same graph -- the hierarchy levels
//   (paper: "by sorting the means of the GMM from large to small ... the first level separates
//   the largest value from all other values") and connected segments.
//
// Input graph (DualGraphView): face adjacency in CSR form. For face f the entries
//   offsets[f] .. offsets[f+1]-1 hold a neighbour face, the normal angle phi, a concave flag
//   and the shared edge length; per face its area. It must be symmetric (g listed by f <=> f
//   listed by g); the values of the entry with f < g are used for the pair. A pair listed
//   twice (two faces sharing two edges) counts twice.
//
// Parameters (PartitionEnergyOptions)
//   Lambda              0.12   [0, 1e3]   smoothness weight (paper's lambda; the paper gives no
//                                         value). A cut of length sqrt(A) across a flat region
//                                         costs 0.12 * 11.5 = 1.4 times the mean data cost of
//                                         all faces; along a 90-degree concave crease 0.08.
//                                         Chosen on the segmentation benchmark (flat from 0.08 to
//                                         0.15) and the elephant's poses (steady from 0.12 to
//                                         0.15); a part shorter than about lambda * sqrt(A) /
//                                         (its data-cost gain per face) whose base has no crease
//                                         merges into its neighbour (docs/partition.md).
//   Epsilon             1e-8   [1e-300, 1] epsilon of e1: a zero posterior costs 18.4.
//   ConvexityFactor     0.08   [0, 1]     phi scale on convex edges (convex creases are not
//                                         part boundaries; 1 = ignore convexity).
//   MinAngleRatio       1e-5   [1e-300, 1] floor of phi'/pi: a flat edge costs -log(1e-5) = 11.5,
//                                         large but finite.
//   GeometricWeights    true              the weights w_f, w_fg above. Fallback when the total
//                                         area is 0: w_f = 1, w_fg = edge length / mean edge
//                                         length (1 when that is 0 too). Zero-area faces have
//                                         no data cost: their neighbours decide their label.
//
// Degenerate cases and errors (Error, one-line reason)
//   - posteriors: must be FaceCount x k, k >= 1, finite; values are clamped to [0, 1].
//   - graph: null arrays, offsets not starting at 0 or decreasing, neighbour out of range,
//     a face listed as its own neighbour, asymmetric adjacency, NaN/Inf angle; with geometric
//     weights also missing, negative or NaN/Inf edge lengths or face areas -> error. Angles
//     are clamped to [0, pi] (rounding of acos). Faces with no neighbours (isolated, or
//     lines) are simply data-term only.
//   - Evaluate / segments / levels: labels of the wrong size or out of range -> error.
//
// Deviations from the paper
//   The paper's e2 is -log(theta/pi) with no floor (infinite on flat edges), no convexity
//   factor and no weights; the floor keeps energies finite, the convexity factor implements
//   the paper's "concave areas" intent, the geometric weights make lambda independent of the
//   mesh resolution (above).
#pragma once

#include "Errors.h"
#include "Mesh/FaceGraph.h"
#include "Partition/GaussianMixture.h"

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace shapediameter
{

/// Face adjacency (dual graph) in CSR form; see the header for the conventions.
struct DualGraphView
{
  const std::int64_t* Offsets = nullptr;    ///< FaceCount + 1 entries, offsets[0] = 0 (may be
                                            ///< null when FaceCount = 0)
  const std::int64_t* Neighbors = nullptr; ///< offsets[FaceCount] entries
  const double* NormalAngle = nullptr;      ///< per entry, angle between normals in [0, pi]
  const std::uint8_t* Concave = nullptr;    ///< per entry, nonzero = concave edge
  const double* EdgeLength = nullptr;       ///< per entry; may be null without geometric weights
  const double* FaceArea = nullptr;         ///< per face; may be null without geometric weights
  std::size_t FaceCount = 0;
  /// Optional, per face: its centre (x, y, z). With it the multilevel cut groups faces by cells
  /// of space (CoarseningCells.h), independently of the face order; without, in face order.
  const double* FaceCenter = nullptr;
};

/// The view of a FaceGraph (which must outlive it), with every array set.
DualGraphView MakeDualGraphView(const FaceGraph& graph);

/// Lambda, the paper's λ (vtkSDFGMMPartition::Lambda and the XML repeat the range).
inline constexpr Range<double> LambdaRange{ 0.0, 1000.0 };
/// Epsilon, the paper's ε (vtkSDFGMMPartition::Epsilon).
inline constexpr Range<double> EpsilonRange{ 1e-300, 1.0 };
/// ConvexityFactor (vtkSDFGMMPartition::ConvexityFactor).
inline constexpr Range<double> ConvexityFactorRange{ 0.0, 1.0 };
/// MinAngleRatio (not a filter property).
inline constexpr Range<double> MinAngleRatioRange{ 1e-300, 1.0 };

struct PartitionEnergyOptions
{
  double Lambda = 0.12;          ///< LambdaRange [0, 1000]
  double Epsilon = 1e-8;         ///< EpsilonRange [1e-300, 1]
  double ConvexityFactor = 0.08; ///< ConvexityFactorRange [0, 1]
  double MinAngleRatio = 1e-5;   ///< MinAngleRatioRange [1e-300, 1]
  bool GeometricWeights = true;
};

/// The energy of one problem: data costs and weighted pairs, ready for AlphaExpansion.
struct PartitionEnergy
{
  std::size_t FaceCount = 0;
  int LabelCount = 0;
  /// e1(f, l) at [f * LabelCount + l].
  std::vector<double> DataCosts;
  /// Adjacent pairs, first < second, and what the pair pays when its labels differ
  /// (lambda e2, times the length factor). All weights are finite and >= 0.
  std::vector<std::int64_t> PairFirst;
  std::vector<std::int64_t> PairSecond;
  std::vector<double> PairWeight;

  double DataCost(std::size_t face, int label) const
  {
    return DataCosts[face * static_cast<std::size_t>(LabelCount) + static_cast<std::size_t>(label)];
  }
  /// E(labels). Throws Error on a wrong size or a label outside [0, LabelCount).
  double Evaluate(const std::vector<int>& labels) const;
  /// E(labels) as an exact sum of its terms, correctly rounded (ExactSum.h): the same for any
  /// order of the faces and pairs, so processes holding parts of the surface can form it
  /// together (the partition reports this one). Throws as Evaluate.
  double EvaluateExactly(const std::vector<int>& labels) const;
};

/// e2 of one edge for unequal labels (without lambda and length factor). A NaN/Inf angle
/// counts as flat (the most expensive cut).
double SmoothnessTerm(double normalAngle, bool concave, const PartitionEnergyOptions& options = {});

/// The geometric weights' factors of a surface of `faceCount` faces and total area
/// `totalArea` (> 0, finite): a face's data cost is weighted by its area / MeanArea, a pair's
/// weight by the shared edge length x PerUnitLength. The builders of the whole surface's energy
/// and of a process's share (Partition/DistributedPartition.cpp) both use these and the two
/// functions below, so that their terms are the same bits.
struct AreaScale
{
  double MeanArea = 0.0;
  double PerUnitLength = 0.0;
};
AreaScale AreaScaleOf(double totalArea, std::size_t faceCount);

/// e1 of a label with the face's weight: faceWeight x -log(clamp(posterior, 0, 1) + Epsilon).
double WeightedDataCost(double faceWeight, double posterior, const PartitionEnergyOptions& options);

/// What a pair pays when its labels differ: Lambda x e2, times edgeLength x perUnitLength when
/// perUnitLength > 0 (no geometric factor otherwise).
double PairWeight(double normalAngle, bool concave, double edgeLength, double perUnitLength,
  const PartitionEnergyOptions& options);

/// Throws Error when the graph breaks a rule of the header.
/// requireGeometry: edge lengths and face areas must be present and finite >= 0. The
/// neighbour lists are checked through parallelFor; the error names the lowest failing face
/// whatever the thread split.
void ValidateDualGraph(const DualGraphView& graph, bool requireGeometry, const ParallelFor& parallelFor = SerialFor);

/// Builds E from the GMM posteriors (FaceCount x k) and the adjacency. Pairs are listed in the
/// order of their lower face, then of its adjacency; the result is the same for any parallelFor.
PartitionEnergy BuildPartitionEnergy(Eigen::Ref<const PosteriorMatrix> posteriors,
  const DualGraphView& graph, const PartitionEnergyOptions& options = {}, const ParallelFor& parallelFor = SerialFor);

/// BuildPartitionEnergy on a graph that has passed ValidateDualGraph(graph,
/// options.GeometricWeights): the same result without checking the graph again (PartitionBySDF
/// validates it once for the energy and the segments).
PartitionEnergy BuildPartitionEnergyOnValidGraph(Eigen::Ref<const PosteriorMatrix> posteriors,
  const DualGraphView& graph, const PartitionEnergyOptions& options = {}, const ParallelFor& parallelFor = SerialFor);

/// argmin_l e1(f, l) per face (= argmax posterior; lowest label on ties).
std::vector<int> MostProbableLabels(const PartitionEnergy& energy);
/// The same of `faceCount` faces' data costs laid out as PartitionEnergy::DataCosts.
std::vector<int> MostProbableLabels(const double* dataCosts, std::size_t faceCount, int labelCount);

/// Hierarchy level L (1 <= L): min(cluster, L). With clusters sorted by mean descending,
/// level L keeps the L largest-mean clusters apart and merges all others into label L.
std::vector<int> HierarchyLevel(const std::vector<int>& clusters, int level);

struct ConnectedSegments
{
  std::vector<int> Segment;       ///< per face, 0 = the segment of largest total area
  std::vector<double> Area;       ///< per segment, total face area (non-increasing)
  std::vector<int> Label;         ///< per segment, the label of its faces
  int SegmentCount() const { return static_cast<int>(Area.size()); }
};

/// Connected components of equal label over the adjacency, numbered by decreasing total area
/// (ties: the segment containing the lower face index first). faceAreas: finite, >= 0.
ConnectedSegments FindConnectedSegments(const DualGraphView& graph, const std::vector<int>& labels,
  const std::vector<double>& faceAreas, const ParallelFor& parallelFor = SerialFor);

/// FindConnectedSegments on a graph that has passed ValidateDualGraph: the same result without
/// checking its topology again (labels and areas are still checked).
ConnectedSegments FindConnectedSegmentsOnValidGraph(const DualGraphView& graph, const std::vector<int>& labels,
  const std::vector<double>& faceAreas);

} // namespace shapediameter
