// SPDX-License-Identifier: BSD-3-Clause
// Segmentation comparison metrics of the Princeton Segmentation Benchmark, and .seg files.
//
// What it computes
//   Chen, Golovinskiy & Funkhouser 2009, "A Benchmark for 3D Mesh Segmentation" (SIGGRAPH),
//   Section 4: four ways to compare a segmentation A (computed, the paper's S1) with a
//   segmentation B (reference, S2) of the same mesh, given as one integer label per face.
//   Every value is 0 for identical segmentations and grows with disagreement (lower is better).
//   - Cut Discrepancy (CD): how far the segment boundaries ("cuts") of one segmentation lie
//     from the cuts of the other, along the surface, relative to the mesh size.
//   - Hamming distance: Rm (missing rate), Rf (false alarm rate) and H = (Rm + Rf) / 2, from
//     the best-overlapping segment of the other segmentation (Huang & Dom 1995).
//   - Rand Index, reported as 1 - RI: the fraction of pairs of surface points that one
//     segmentation puts in one segment and the other in two (Rand 1971).
//   - Global and Local Consistency Error (GCE, LCE): refinement errors, which forgive a
//     segmentation for being a refinement of the other (Martin et al. 2001, ICCV).
//   Labels are arbitrary integers (not necessarily 0..k-1); a segment is the set of faces with
//   one label, connected or not. Relabelling either segmentation changes no value at all
//   (the result is bit-identical).
//
// Weighting (SegmentationMetricsOptions::weighting)
//   FaceArea (default, the PSB convention of measuring a face set by its area): every face
//   counts with its area, so the values measure the surface and barely depend on the
//   triangulation; splitting a face into pieces with its label changes no value except by
//   rounding. 1 - RI is then the probability that two independent, area-uniform random points
//   of the surface are grouped inconsistently:
//     1 - RI = (sum_i a_i^2 + sum_j b_j^2 - 2 sum_ij n_ij^2) / W^2,
//   with a_i, b_j the segment areas, n_ij the area of A-segment i intersected with B-segment j
//   and W the total area. Cut points are weighted by length along the cut.
//   Uniform: every face counts 1 and every cut vertex counts 1 (the counting of common
//   re-implementations of the benchmark). 1 - RI is then the classical Rand index over pairs
//   of distinct faces:
//     1 - RI = (sum C(a_i,2) + sum C(b_j,2) - 2 sum C(n_ij,2)) / C(n,2).
//   A mesh whose faces all have zero area (or explicit weights summing to 0) is measured with
//   Uniform weights: there is no area to weigh by.
//
// Definitions (A = S1, B = S2; |X| the weight of the face set X; W = total weight)
//   Rm = sum over B-segments B_j of |B_j \ A_best(j)| / W, A_best(j) the A-segment with the
//        largest overlap with B_j (on a tie any, the value is the same). Rf = the same with A
//        and B swapped. The paper's convention,
//        literally: A = one segment, B = two halves gives Rm = 0, Rf = 0.5.
//   GCE = min(sum_f w_f E(A,B,f), sum_f w_f E(B,A,f)) / W, LCE = sum_f w_f min(E(A,B,f),
//        E(B,A,f)) / W, with E(X,Y,f) = |X(f) \ Y(f)| / |X(f)| the refinement error at face f
//        (X(f) the segment holding f; 0 for a segment of zero weight). GCE = LCE = 0 whenever
//        one segmentation refines the other.
//   CD   The cuts of a segmentation are the mesh edges whose incident faces do not all have
//        the same label (boundary edges of open meshes are never cuts). For a point p on the
//        cuts C_A of A, d(p, C_B) is the geodesic distance to the nearest cut of B.
//        DCD(A=>B) = mean of d(p, C_B) over p in C_A; CD is the mean of d over the points of
//        both cuts (pooled: (integral over C_A + integral over C_B) / (|C_A| + |C_B|)),
//        divided by avgRadius, the mean Euclidean distance from the surface to its area
//        centroid (a surface integral, FaceArea or not). The directional values
//        DCD(A=>B)/avgRadius and DCD(B=>A)/avgRadius are reported too.
//
// Approximations and deviations from the paper (documented, deliberate)
//   - Geodesic distances are shortest paths over the mesh edge graph (multi-source Dijkstra
//     from the vertices of the other segmentation's cut edges). This over-estimates the
//     surface geodesic by the zig-zag along edges: exact along edges, a few percent on
//     irregular triangulations, up to 41 % across the diagonals of a regular right-triangle
//     grid. Re-implementations report the benchmark's code to use edge-graph distances too.
//     The mean along a cut edge is the mean of its two end distances (trapezoid rule).
//   - A cut point from which no cut of the other segmentation is reachable (another connected
//     component) is given the Euclidean distance to the nearest vertex of the other cut, so
//     that CD stays finite and still counts the disagreement; the count of such points is
//     reported (CutPointsWithEuclideanDistance).
//   - Combination of the two directions: the paper writes CD = (DCD(A=>B) + DCD(B=>A)) /
//     avgRadius; the benchmark's released code, which produced the published numbers, pools
//     the points of both cuts into one mean (reported by re-implementations). We return the
//     pooled mean as CutDiscrepancy (comparable with published CD values, within the geodesic
//     approximation); the paper's sum is DirectionalCutDiscrepancyAB + ...BA.
//   - CD is undefined when exactly one segmentation has no cut (a single segment): then
//     CutDiscrepancyDefined = false and every CD value is 0. No cuts on either side: CD = 0,
//     defined (identical partitions of the cut-free kind).
//   - avgRadius is integrated with the 7-point degree-5 quadrature of each triangle (Strang &
//     Fix); the benchmark's code is not specific about it. Zero total area: mean vertex distance
//     from the vertex centroid. avgRadius = 0 (all points coincide): CD = 0.
//   - 1 - RI under FaceArea counts pairs of points, including pairs within one face; this keeps
//     the value independent of how a segment is triangulated (see Weighting).
//
// Input, degenerate cases and errors (SegmentationMetricsError, one-line reason)
//   Points n x 3; faces as triangles or as polygons in CSR form (faceOffsets with faceCount + 1
//   entries starting at 0, non-decreasing, ending at faceConnectivity.size()). Polygons are
//   fan-triangulated for areas and the edge graph; labels stay per polygon, and fan diagonals
//   are never cuts (both sides carry the polygon's label). Polygons with fewer than 3 vertices
//   have zero area and no edges but keep their label.
//   Errors: label vectors whose size differs from the face count, or from each other; a point
//   index out of range; malformed offsets; a non-finite coordinate of a point used by a face;
//   negative or non-finite explicit weights. No faces: every value is 0 (nothing differs).
//   Never NaN or Inf in a result: every value is finite, and those in [0, 1] are clamped there.
//
// Cost: O(n + kA + kB + E log E) for n faces, k segments, E edges (labels are
//   compacted with a hash map; the contingency table is sparse, built by a two-pass counting
//   sort, so many segments cost no quadratic memory). Single-threaded and deterministic.
#pragma once

#include "Mesh/MeshTypes.h"

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace shapediameter
{

/// Bad input to a metric (sizes, indices, non-finite values).
class SegmentationMetricsError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

/// Malformed or unreadable .seg file, or a write failure.
/// what() is "[source: ]line N: reason" ("[source: ]reason" when no line applies).
class SegFileError : public std::runtime_error
{
public:
  /// line: 1-based line, 0 when the error is not tied to a line (open / write failure).
  SegFileError(std::int64_t line, const std::string& reason, const std::string& source = {});
  std::int64_t Line() const noexcept { return this->LineNumber; }

private:
  std::int64_t LineNumber;
};

enum class SegmentationWeighting
{
  FaceArea, ///< faces weighted by area, cut points by length (PSB convention; default)
  Uniform   ///< every face and every cut vertex counts 1
};

struct SegmentationMetricsOptions
{
  /// How faces and cut points are counted (see the header comment). Default FaceArea.
  SegmentationWeighting Weighting = SegmentationWeighting::FaceArea;
};

/// The metrics that only need labels and face weights. All in [0, 1], 0 = identical.
struct PartitionComparison
{
  double MissingRate = 0.0;            ///< Rm(A, B)
  double FalseAlarmRate = 0.0;         ///< Rf(A, B)
  double HammingDistance = 0.0;        ///< H = (Rm + Rf) / 2
  double RandIndexError = 0.0;         ///< 1 - RI
  double GlobalConsistencyError = 0.0; ///< GCE
  double LocalConsistencyError = 0.0;  ///< LCE
  std::size_t SegmentCountA = 0;       ///< distinct labels in A
  std::size_t SegmentCountB = 0;       ///< distinct labels in B
  bool UsedUniformWeights = false;     ///< true when faces were counted, not weighted
};

struct CutDiscrepancyResult
{
  /// CD: pooled mean distance over the cut points of both segmentations / avgRadius. >= 0.
  double CutDiscrepancy = 0.0;
  /// DCD(A=>B) / avgRadius: from the cuts of A to the nearest cut of B.
  double DirectionalCutDiscrepancyAB = 0.0;
  /// DCD(B=>A) / avgRadius.
  double DirectionalCutDiscrepancyBA = 0.0;
  /// false when exactly one segmentation has no cut (then the three values above are 0).
  bool CutDiscrepancyDefined = true;
  /// Mean Euclidean distance of the surface from its area centroid (length units).
  double AverageRadius = 0.0;
  std::size_t CutEdgeCountA = 0;
  std::size_t CutEdgeCountB = 0;
  /// Total length of the cut edges (length units).
  double CutLengthA = 0.0;
  double CutLengthB = 0.0;
  /// Cut vertices that reach no cut of the other segmentation along edges (see header).
  std::size_t CutPointsWithEuclideanDistance = 0;
};

struct SegmentationComparison
{
  CutDiscrepancyResult Cut;
  PartitionComparison Partition;
};

/// Hamming, Rand, GCE and LCE between two labelings of the same faces.
/// faceWeights: one finite value >= 0 per face (e.g. areas), or empty to count faces (Uniform,
/// classical Rand index over distinct pairs). With weights, 1 - RI is the point-pair form.
PartitionComparison ComparePartitions(const std::vector<int>& labelsA, const std::vector<int>& labelsB,
  const std::vector<double>& faceWeights = {});

/// Cut Discrepancy of two per-triangle labelings.
CutDiscrepancyResult ComputeCutDiscrepancy(const PointsView& points, const TrianglesView& triangles,
  const std::vector<int>& labelsA, const std::vector<int>& labelsB,
  const SegmentationMetricsOptions& options = {});

/// All metrics, triangles.
SegmentationComparison CompareSegmentations(const PointsView& points, const TrianglesView& triangles,
  const std::vector<int>& labelsA, const std::vector<int>& labelsB,
  const SegmentationMetricsOptions& options = {});

/// All metrics, polygons in CSR form (one label per polygon; see the header comment).
SegmentationComparison CompareSegmentations(const PointsView& points,
  const std::vector<std::int64_t>& faceOffsets, const std::vector<std::int64_t>& faceConnectivity,
  const std::vector<int>& labelsA, const std::vector<int>& labelsB,
  const SegmentationMetricsOptions& options = {});

/// Area of each polygon (sum of its fan triangles; 0 below 3 vertices). Validates the input
/// like CompareSegmentations.
std::vector<double> ComputeFaceAreas(const PointsView& points,
  const std::vector<std::int64_t>& faceOffsets, const std::vector<std::int64_t>& faceConnectivity);

/// Segments (distinct labels) whose weight is at least minimumShare of the total weight, e.g.
/// 0.005 = the segments covering >= 0.5 % of the area. faceWeights: one finite value >= 0 per
/// face (e.g. ComputeFaceAreas), or empty to count faces; a total weight of 0 counts faces too
/// (as the metrics do). Throws SegmentationMetricsError on a size mismatch or a bad weight.
std::size_t CountSegmentsCovering(
  const std::vector<int>& labels, const std::vector<double>& faceWeights, double minimumShare);

// ---- .seg files: one integer label per line, line f = face f (the PSB format).

/// Parses .seg text. Accepted: spaces and tabs around the number, CRLF, a leading '+' or '-',
/// blank lines (skipped), a UTF-8 byte-order mark, no newline at the end. Rejected with the
/// 1-based line number: anything else on a line (garbage, two numbers, a fraction), a value
/// outside int. Empty input gives no labels. source prefixes messages (e.g. the path).
std::vector<int> ParseSeg(const char* data, std::size_t size, const std::string& source = {});

/// Reads a .seg file; messages are prefixed with the path. Throws SegFileError.
std::vector<int> ReadSegFile(const std::string& path);

/// Writes one label per line ('\n' endings). Throws SegFileError when the file cannot be
/// written.
void WriteSegFile(const std::string& path, const std::vector<int>& labels);

} // namespace shapediameter
