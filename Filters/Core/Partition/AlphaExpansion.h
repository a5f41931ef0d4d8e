// SPDX-License-Identifier: BSD-3-Clause
// k-way graph cut of the SDF partitioning: alpha-expansion on a max-flow backend.
//
// What it computes
//   Section 4 of Shapira, Shamir & Cohen-Or 2008, second step of the partitioning: "an alpha
//   expansion graph-cut algorithm [Boykov, Veksler & Zabih 2001] ... assigns a single
//   partition for each face" minimising E of PartitionEnergy.h.
//   Starting from a labelling (by default the most probable GMM cluster of each face), each
//   move picks a label alpha and lets any set of faces switch to alpha, choosing the set with
//   the lowest energy exactly by a minimum s-t cut (Kolmogorov & Zabih 2004 construction: the
//   Potts pair term with one weight per edge is submodular for an expansion, so no auxiliary
//   nodes are needed). Labels are tried in cycles 0, 1, ..., k-1, 0, ... until k consecutive
//   moves bring no decrease, or `MaxCycles` cycles have run.
//   Guarantees: E never increases (a move is applied only if the directly evaluated E
//   decreases by more than `RelativeTolerance` max(1, |E|)); for k = 2 the result is a global
//   minimum; for k > 2 it is within E_data(x*) + 2 E_smooth(x*) of the optimum x*.
//
// Backend
//   MaxFlowGraph (MaxFlow.h, Boykov-Kolmogorov) on a graph whose topology (every face, one arc
//   pair per adjacent face pair) is built once per call; each move only refills the
//   capacities (double precision), with the pair terms split evenly between the two faces so
//   that equal-label pairs add no terminal capacity. Faces and arcs are limited to 2^31 - 2
//   (std::invalid_argument beyond). Why our own max-flow rather than Boost.Graph's: see
//   MaxFlow.h (measurements: docs/performance.md); the even split and the
//   skipped moves below cut the work itself (fewer augmentations, fewer solves).
//   A move whose result is known (no other move changed the labels since the last move of
//   the same alpha) is counted as tried without solving it.
//
// Parameters (AlphaExpansionOptions)
//   MaxCycles          20     [1, 1e6]   full passes over the labels (typically 2-4 are used).
//   RelativeTolerance  1e-12  [0, 1]     minimum relative decrease for a move to be applied.
//
// Progress and abort
//   progress(fraction) is called after every move with (moves done) / (MaxCycles k), and 1 at
//   the end; returning false stops after the current move: the result holds the best labelling
//   so far, with Aborted = true.
//
// Degenerate cases
//   FaceCount 0: empty result, Energy 0, Converged. k = 1: all zeros. Initial labels of the
//   wrong size or out of range: Error.
#pragma once

#include "Parallel.h"
#include "Partition/PartitionEnergy.h"

#include <functional>
#include <vector>

namespace shapediameter
{

class MaxFlowGraph;

struct AlphaExpansionOptions
{
  int MaxCycles = 20;
  double RelativeTolerance = 1e-12;
  /// Not a parameter of the method: called with the s-t graph of every move just before it is
  /// solved (capacities set), so a benchmark can record the graphs of a real run and time
  /// max-flow implementations on them alone. Called on the thread that solves the move.
  std::function<void(const MaxFlowGraph&)> BeforeEachCut;
};

struct AlphaExpansionResult
{
  std::vector<int> Labels;
  double InitialEnergy = 0.0;
  double Energy = 0.0; ///< E(labels), the paper's final graph-cut energy (`SDFEnergy`)
  /// E after every move tried, applied or not (non-increasing, for tests and diagnostics).
  std::vector<double> EnergyTrace;
  int Moves = 0;        ///< moves tried
  int AppliedMoves = 0; ///< moves that lowered E
  bool Converged = false;
  bool Aborted = false;
};

/// Alpha-expansion from the most probable labels (MostProbableLabels).
AlphaExpansionResult MinimizeByAlphaExpansion(const PartitionEnergy& energy,
  const AlphaExpansionOptions& options = {}, const ProgressCallback& progress = nullptr);

/// Alpha-expansion from the given labelling.
AlphaExpansionResult MinimizeByAlphaExpansion(const PartitionEnergy& energy,
  const std::vector<int>& initialLabels, const AlphaExpansionOptions& options = {},
  const ProgressCallback& progress = nullptr);

/// Throws Error unless the energy's sizes, pair indices, data costs and weights
/// are consistent (finite, weights >= 0).
void ValidateEnergyForCut(const PartitionEnergy& energy);

/// One expansion move: the labelling of lowest energy among those where every face keeps its
/// label or takes `alpha` (ties may go either way). For tests and custom schedules.
std::vector<int> OptimalExpansionMove(
  const PartitionEnergy& energy, const std::vector<int>& labels, int alpha);

} // namespace shapediameter
