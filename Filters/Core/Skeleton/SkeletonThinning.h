// SPDX-License-Identifier: BSD-3-Clause
// SDF-guided skeleton, step 2 of 4: moving-least-squares (MLS) thinning of the cloud P.
//
// What it computes
//   For every point p of P: the principal component analysis (PCA) of the points of P within
//   h(p) = NeighborhoodScale * radius(p) of p, the projection of p onto the regression line
//   (the line through the neighbourhood centroid along the first principal axis), and
//       confidence(p) = max(e1, e2, e3) / (e1 + e2 + e3)
//   from the three eigenvalues. The projection is repeated NumberOfIterations times, each
//   time with the neighbourhood re-queried around the moved point. Points with confidence >=
//   ConfidenceThreshold are then thinned to a minimal spacing: in order of decreasing
//   confidence, a point is kept unless an already kept point lies within
//   epsilon = SpacingFactor * radius of it. The kept points form T (paper, Fig. 12b).
//   Given the surface (`volume`), a point is eligible for T only if its medial ball fits: no
//   surface within MinimumClearance * radius of its projected position, along the three axes
//   and the four diagonals, both ways (14 short rays; a plane at distance d is seen when d is
//   at most the reach times the cosine of its normal's angle to the nearest ray, >= 0.8 of it).
//
// Reference
//   Shapira, Shamir, Cohen-Or 2008, section 5, third and fourth paragraphs; the MLS curve
//   projection follows Lee 2000 ("Curve reconstruction from unorganized points") and Levin
//   1998 (refs [15], [17] of the paper).
//
// Parameters (SkeletonThinningOptions), all lengths relative to the local radius(p)
//   NumberOfIterations   "2 to 4" in the paper; default 3; valid [1, 100].
//   NeighborhoodScale   h = scale * radius(p); paper: radius(p), i.e. 1; default 1; (0, 10].
//   ConfidenceThreshold  keep points with confidence >= threshold; the paper gives no value.
//                        Default 0.8: a straight tube whose cloud scatters by sigma across
//                        the axis has confidence (h^2/3) / (h^2/3 + 2 sigma^2), so 0.8 keeps
//                        tubes with sigma < 0.2 h (typical SDF noise) and drops junctions of
//                        three branches (about 0.5) and blobs. Valid [0, 1] (confidence is
//                        always >= 1/3, so a threshold <= 1/3 keeps every defined point).
//   MinimumConfidentShare  the threshold is lowered, if needed, to the confidence of the
//                        point at this share of the defined points counted from the most
//                        confident, so that at least this share of them is eligible for T.
//                        Default 0.2; valid [0, 1] (0: ConfidenceThreshold alone). Why: a
//                        character with short, stubby limbs has few tube-like neighbourhoods,
//                        so with the threshold alone only its longest limbs get a branch
//                        (deviation: the paper says only "high confidence"; evidence:
//                        docs/skeleton.md). Never below 0.6: a junction of three branches has
//                        about 0.5, a blob at most that (a sphere stays one node). Meshes
//                        where this share already reaches ConfidenceThreshold are unchanged.
//   SpacingFactor        epsilon = factor * radius(p); default 0.25 (about 8 nodes along a
//                        tube twice as long as its radius); valid [0, 10]. The paper uses one
//                        constant epsilon; a radius-relative one keeps thin parts (fingers)
//                        as finely sampled as thick ones (torso).
//   MinimumNeighbors    a neighbourhood with fewer points (the point included) has no
//                        defined regression line: confidence 0 and the point does not move.
//                        Default 5; valid [2, 1000].
//   MinimumClearance     0.25; valid [0, 1]; 0 (or no volume given): no test. Deviation (the
//                        paper has no such test): where two faces meet at a convex edge (a box,
//                        a machined part) the faces beside the edge have a short SDF, so their
//                        projected points line up along the edge, inside the medial ball of the
//                        edge's neighbour, and MLS finds them confident: poly-segments then
//                        trace the box's edges and the skeleton wanders round it instead of
//                        reaching its bosses. Their clearance is about 0.15 of their radius
//                        (median of the confident points of a cube with a boss), against 0.8 on
//                        limbs (camel, armadillo: 5 % of their confident points below 0.52).
//                        Measured from 0.2 to 0.35 on the segmentation benchmark: limbs reached
//                        92.4-92.7 % (91.8 % without), the mechanical parts 88-91 % (77 %);
//                        with other sampling seeds +0.2 / -0.1 points overall, the mechanical
//                        parts +4 / +2 (docs/skeleton.md).
//   ContractCloud        false (default): the regression line is always fitted to the
//                        original cloud P, only the query point moves (the MLS projection of
//                        Levin and Lee). true: each iteration fits to the cloud moved by the
//                        previous one. Deviation note: on a curved tube of centre-line radius
//                        R the linear fit sits h^2 / (6 R) inside the curve; refitting the moved
//                        cloud adds that bias up at every iteration, the fixed-data projection
//                        does not.
//
// Degenerate cases
//   Empty cloud -> empty result. Zero radius, or all neighbours coincident (e.g. a sphere whose
//   exact SDF sends every sample to the centre) -> confidence 0, point not moved, not in T.
//   Confidence and positions are always finite.
//
// Threading
//   The per-point loop runs under the given ParallelFor; each point only reads the fixed data
//   and writes its own outputs, so the result is bit-identical for any split.
#pragma once

#include "Errors.h"
#include "Mesh/MeshTypes.h"
#include "Parallel.h"
#include "RayCasting/RayCaster.h"
#include "Skeleton/SkeletonSampling.h"

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

namespace shapediameter
{

class SkeletonPointTree;

struct SkeletonThinningOptions
{
  /// Projection iterations (paper: "2 to 4"). SkeletonIterationsRange [1, 100].
  int NumberOfIterations = 3;
  /// Neighbourhood radius h = NeighborhoodScale * radius(p) (paper: radius(p)).
  /// NeighborhoodScaleRange (0, 10].
  double NeighborhoodScale = 1.0;
  /// Points of T have confidence >= ConfidenceThreshold (lowered by MinimumConfidentShare).
  /// ConfidenceThresholdRange [0, 1].
  double ConfidenceThreshold = 0.8;
  /// At least this share of the defined points is eligible for T (see header).
  /// MinimumConfidentShareRange [0, 1].
  double MinimumConfidentShare = 0.2;
  /// Minimal spacing epsilon = SpacingFactor * radius(p) between points of T.
  /// ThinningSpacingFactorRange [0, 10].
  double SpacingFactor = 0.25;
  /// Smallest neighbourhood (point included) with a defined regression line.
  /// MinimumNeighborsRange [2, 1000].
  int MinimumNeighbors = 5;
  /// Fit each iteration to the moved cloud instead of the original P (see header). Off.
  bool ContractCloud = false;
  /// Points of T need this clearance, as a share of their radius, to the surface (see
  /// header; read only when ThinProjectedCloud is given the volume). MinimumClearanceRange
  /// [0, 1], 0 = off.
  double MinimumClearance = 0.25;
};

// The ranges, checked by ValidateThinningOptions; vtkSDFSkeleton's vtkSetClampMacro repeats those
// of its properties (NumberOfIterations, ConfidenceThreshold, MinimumConfidentShare,
// SpacingFactor; Testing/Filters/TestParameterRanges.cxx).
inline constexpr Range<int> SkeletonIterationsRange{ 1, 100 };
/// Not a filter property.
inline constexpr Range<double> NeighborhoodScaleRange{ 0.0, 10.0, true };
inline constexpr Range<double> ConfidenceThresholdRange{ 0.0, 1.0 };
inline constexpr Range<double> MinimumConfidentShareRange{ 0.0, 1.0 };
inline constexpr Range<double> ThinningSpacingFactorRange{ 0.0, 10.0 };
inline constexpr Range<double> MinimumClearanceRange{ 0.0, 1.0 };
/// Not a filter property.
inline constexpr Range<int> MinimumNeighborsRange{ 2, 1000 };

struct ThinnedCloud
{
  /// MLS-projected position of every point of P (n x 3).
  PointMatrix Positions;
  /// Unit direction of the last regression line of every point; zero where undefined.
  PointMatrix Axis;
  /// confidence(p) in [1/3, 1], or 0 where undefined.
  std::vector<double> Confidence;
  /// The principal variances of P within h of each point's own position (the first
  /// iteration's neighbourhood), increasing, and the axis of the smallest; zero rows where
  /// undefined. Step 4 (SkeletonConnection.h) finds sheets with them.
  PointMatrix LocalSpread;
  PointMatrix LocalNormal;
  /// The threshold that was applied: min(ConfidenceThreshold, the MinimumConfidentShare one).
  double AppliedConfidenceThreshold = 0.0;
  /// T: indices into P of the kept points, by decreasing confidence (ties: lower index).
  std::vector<std::int64_t> Thinned;
  /// True if the progress callback asked to stop; the other members are then empty.
  bool Aborted = false;
};

/// Throws Error if an option is outside its documented range.
void ValidateThinningOptions(const SkeletonThinningOptions& options);

/// One MLS iteration's answers for some points, row by row: the projection onto the regression
/// line (the point itself where the line is undefined), its unit axis and confidence (zero
/// where undefined), and the principal variances and smallest axis (ThinnedCloud's LocalSpread
/// and LocalNormal; zero where undefined).
struct RegressionProjections
{
  /// `rows` rows of zeros.
  static RegressionProjections Zero(Eigen::Index rows)
  {
    return { PointMatrix::Zero(rows, 3), PointMatrix::Zero(rows, 3), std::vector<double>(static_cast<std::size_t>(rows), 0.0),
      PointMatrix::Zero(rows, 3), PointMatrix::Zero(rows, 3) };
  }

  PointMatrix Positions;
  PointMatrix Axis;
  std::vector<double> Confidence;
  PointMatrix Spread;
  PointMatrix Normal;
};

/// One MLS iteration for the rows [first, end) of `positions`, with neighbourhood radius
/// `radii[row]` over the points of `cloud` (the tree of P, or of P's moved points under
/// ContractCloud), written into the same rows of `out` (RegressionProjections::Zero of as many
/// rows; undefined spreads and normals are left as they are). Rows are independent: any split
/// of them gives the same answers.
void ProjectOntoRegressionLines(const SkeletonPointTree& cloud, const PointMatrix& positions,
  const std::vector<double>& radii, double minimumNeighbors, std::size_t first, std::size_t end,
  RegressionProjections& out, const ParallelFor& parallelFor);

/// Runs the MLS iterations elsewhere: the distributed skeleton splits the rows over processes
/// (DistributedSkeleton.cpp). Must answer as ProjectOntoRegressionLines over a tree of `cloud`.
class RegressionProjector
{
public:
  virtual ~RegressionProjector() = default;
  /// `cloudChanged`: false when `cloud` holds the same points as in the previous call.
  virtual RegressionProjections Project(const PointMatrix& cloud, bool cloudChanged, const PointMatrix& positions,
    const std::vector<double>& radii, double minimumNeighbors) const = 0;
};

/// Step 2: MLS projection, confidence and epsilon-thinning of P; with `volume` (the surface),
/// only points whose medial ball fits are eligible for T (MinimumClearance). With `projector`,
/// each iteration's projections come from it (one call per iteration, progress after each)
/// instead of from this process's loop (progress after each of 16 blocks of points).
/// progress receives fractions in [0, 1] of this step; returning false aborts.
ThinnedCloud ThinProjectedCloud(const ProjectedCloud& cloud,
  const SkeletonThinningOptions& options, const ParallelFor& parallelFor,
  const ProgressCallback& progress = {}, const RayCaster* volume = nullptr,
  const RegressionProjector* projector = nullptr);

} // namespace shapediameter
