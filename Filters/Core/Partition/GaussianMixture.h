// SPDX-License-Identifier: BSD-3-Clause
// Soft clustering of the normalised SDF: a 1-D Gaussian mixture fitted by EM.
//
// What it computes
//   Section 4 of Shapira, Shamir & Cohen-Or 2008, "Consistent mesh partitioning and
//   skeletonisation using the shape diameter function", first step of the partitioning:
//   "a Gaussian mixture model (GMM) fitting k Gaussians to the histogram of SDF values of the
//   faces ... using the expectation-maximization (EM) algorithm". The result for each face is
//   the vector of posterior probabilities P(cluster | f) of the clusters given the face's value
//   (the paper's soft partitioning), used by the data term of the graph cut (PartitionEnergy.h).
//   Components are sorted by mean DESCENDING: component 0 has the largest mean (interface.md,
//   `SDFCluster` 0 = largest GMM mean), so hierarchy level L separates the L largest means.
//
// How
//   - The values are binned into `BinCount` equal bins over [min, max]. Each occupied bin is
//     one weighted point holding the count, the mean and the sum of squared deviations of its
//     values (exact first and second moments). EM then runs on the occupied bins with the
//     responsibilities shared by all values of a bin: this is block-constrained EM, which
//     increases a lower bound of the exact log-likelihood, the M-step uses the exact moments,
//     and the result equals unbinned EM up to the variation of the responsibilities inside one
//     bin (the tests check the means agree within 1e-3 of the range). One iteration costs
//     O(BinCount k) instead of O(n k). BinCount = 0 selects exact EM on the distinct values
//     (sorted, with multiplicities), for tests and small data.
//   - Initialisation: k-means++ seeding (first centre with probability proportional to the
//     count, the next ones proportional to count x squared distance to the nearest centre),
//     then weights and variances from the nearest-centre assignment. Random numbers: one
//     std::mt19937_64 seeded with `Seed`, mapped to [0, 1) by (r >> 11) * 2^-53 (bit-identical
//     on every platform). `Restarts` seedings are drawn one after another from that generator;
//     each runs `ScreeningIterations` EM iterations, and only the one with the largest
//     log-likelihood then (the first on ties) runs on to convergence. Screening keeps the cost
//     of restarts low: EM crawls for hundreds of iterations when k exceeds the modes present.
//   - Convergence: stop when the log-likelihood per value increases by less than `Tolerance`,
//     or after `MaximumIterations` iterations in all (the model's `Converged` says which).
//   - Posteriors (ComputePosteriors) are evaluated per value, exactly, from the fitted
//     parameters with a log-sum-exp: every row sums to 1 (to rounding) and is finite.
//
// Parameters (GaussianMixtureOptions; the paper gives none of these)
//   Restarts        5       [1, 100]    k-means++ seedings; the most likely is kept.
//   MaximumIterations 500   [1, 1e5]    EM iterations of the kept seeding, screening included.
//   ScreeningIterations 20  [1, 1e6]    EM iterations given to every seeding before choosing.
//   Tolerance       1e-8    [0, 1]      stop when the log-likelihood per value gains less.
//   BinCount        512     [0, 1e7]    histogram bins; 0 = exact EM on distinct values.
//                                       Cost per iteration O(BinCount k), independent of n.
//   MinSigmaRelative 1e-3   [1e-12, 1]  sigma floor, relative to the data range max - min
//                                       (relative to max(|value|, 1) for constant data).
//                                       Stops a component collapsing onto one value.
//   Seed            0x5DF2008
//   BIC k range (FitGaussianMixtureBic): 2..8 by default; BIC = -2 logL + (3k - 1) ln n with
//   the (binned) log-likelihood above; lowest wins, the smaller k on ties.
//
// Degenerate cases
//   - empty data, NaN or Inf values, k < 1: Error.
//   - constant data: one component (mean = the value, sigma = the floor, weight 1), whatever k.
//   - k larger than the number of distinct values (occupied bins when binned): k is reduced to
//     that number; the model's ComponentCount() is the k actually used.
//   - a component that loses all responsibility keeps its previous mean and sigma, and its
//     weight is floored at 1e-12 (then the weights are renormalised), so no log(0) occurs.
//
// Deviations from the paper
//   The paper fits "the histogram"; we fit the per-bin exact moments (better than bin centres)
//   and evaluate the posteriors per face. k-means++ restarts and the sigma floor are ours:
//   EM needs some initialisation and guard, the paper does not say which.
#pragma once

#include "Errors.h"
#include "Parallel.h"

#include <Eigen/Core>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace shapediameter
{

/// Read-only view of the values (bind a std::vector or a VTK array through Eigen::Map).
using ValuesView = Eigen::Ref<const Eigen::VectorXd>;
/// n x k posterior probabilities, one row per value, component order of the model.
using PosteriorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

/// Restarts (vtkSDFGMMPartition::Restarts and the XML repeat it). Was [1, 1000] in the core.
inline constexpr Range<int> RestartsRange{ 1, 100 };
/// MaximumIterations (vtkSDFGMMPartition::MaximumIterations and the XML). Was [1, 1e6].
inline constexpr Range<int> MaximumIterationsRange{ 1, 100000 };

struct GaussianMixtureOptions
{
  int Restarts = 5;           ///< RestartsRange [1, 100]
  int MaximumIterations = 500; ///< MaximumIterationsRange [1, 1e5]
  int ScreeningIterations = 20;
  double Tolerance = 1e-8;
  int BinCount = 512;
  double MinSigmaRelative = 1e-3;
  std::uint64_t Seed = 0x5DF2008;
};

/// A fitted 1-D mixture; components sorted by mean, largest first.
struct GaussianMixtureModel
{
  std::vector<double> Means;
  std::vector<double> Sigmas;
  std::vector<double> Weights; ///< sum to 1
  /// Log-likelihood of the data (a tight lower bound when binned, see header), finite.
  double LogLikelihood = 0.0;
  std::size_t SampleCount = 0;
  int Iterations = 0;     ///< EM iterations of the kept restart
  bool Converged = false; ///< the kept restart met the tolerance before MaximumIterations

  int ComponentCount() const { return static_cast<int>(Means.size()); }
  /// Bayesian information criterion -2 logL + (3k - 1) ln n (lower is better).
  double Bic() const;
};

/// Fits `componentCount` Gaussians (fewer if the data has fewer distinct values, see header).
/// Throws Error on empty or non-finite data or componentCount < 1.
GaussianMixtureModel FitGaussianMixture(
  ValuesView values, int componentCount, const GaussianMixtureOptions& options = {});

struct GaussianMixtureBicResult
{
  GaussianMixtureModel Model;     ///< the fit with the lowest BIC
  std::vector<int> ComponentCounts; ///< k tried, in order (duplicates after reduction removed)
  std::vector<double> Bics;       ///< BIC of each k tried
};

/// Fits k = minComponents..maxComponents and keeps the lowest BIC (the smallest k on ties).
/// Throws Error on bad data or 1 > minComponents or minComponents > maxComponents.
GaussianMixtureBicResult FitGaussianMixtureBic(ValuesView values, int minComponents = 2,
  int maxComponents = 8, const GaussianMixtureOptions& options = {});

/// Posterior probability of each component for each value (n x k, rows sum to 1, finite).
/// Per-value work only: bit-identical whatever the ParallelFor split.
/// Throws Error on non-finite values or an empty/invalid model.
PosteriorMatrix ComputePosteriors(
  const GaussianMixtureModel& model, ValuesView values, const ParallelFor& parallelFor = SerialFor);

} // namespace shapediameter
