// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkSDFGMMPartition
 * @brief   Consistent partitioning by the SDF: a 1-D Gaussian mixture fitted by EM (soft
 *          clustering) followed by a k-way alpha-expansion graph cut.
 *
 * Shapira, Shamir, Cohen-Or 2008, section 4. The steps below are one core call,
 * PartitionBySDF (Filters/Core/Partition/Partition.h); this filter converts, calls it and writes.
 *
 * 1. A 1-D mixture of at most k Gaussians models the normalised SDF of the faces (input
 *    array, default `SDFNormalized`). By default (ClusterModel 1) its components are the
 *    modes of the area-weighted density of the values, each a basin between two valleys
 *    (see ClusterModel below). ClusterModel 0 is the paper's EM fit of exactly k: k-means++
 *    initialisation with a fixed seed, Restarts restarts, the best likelihood kept, sigmas
 *    floored at 1e-3 of the value range (no collapse), fitted on a 512-bin histogram of
 *    exact per-bin moments (Filters/Core/Partition/GaussianMixture.h). Each face gets its posterior
 *    probability vector `SDFProbabilities`.
 * 2. A k-way graph cut by alpha-expansion (our Boykov-Kolmogorov max-flow,
 *    Filters/Core/Partition/MaxFlow.h) minimises
 *    E = Σ_f w_f·(−log(P(x_f|f) + ε)) + λ Σ_{f~g, x_f≠x_g} w_fg·e2(f, g), where P(x_f|f) is
 *    the posterior of cluster x_f at face f (`SDFProbabilities`),
 *    e2 = −log(max(φ'/π, 1e-5)), φ the angle between the two face normals, taken as is on
 *    concave edges and times ConvexityFactor on convex ones: cutting along a concave
 *    crease is cheap, across a flat or convex region expensive. w_f = face area / mean
 *    face area, w_fg = edge length · F / √(total area): E is then F times an integral
 *    over the surface, so λ means the same at every resolution and in every unit
 *    (Filters/Core/Partition/PartitionEnergy.h). It starts from the per-face most probable cluster
 *    and never increases E. Above 60,000 faces the cut is multilevel
 *    (Filters/Core/Partition/MultilevelCut.h): alpha-expansion on clusters of faces (connected,
 *    one most probable cluster, inside a cube of about 8 faces: decided by where a face lies,
 *    not by the face order), then on an 8-ring band around the boundaries at full resolution, because with this energy the
 *    plain alpha-expansion's cost grows as faces^1.5 (docs/performance.md).
 * 3. Clusters are numbered by GMM mean, largest first (`SDFCluster` 0 = thickest parts);
 *    the hierarchy `SDFLevel1` … `SDFLevel{k−1}` has level L = min(SDFCluster, L) (the
 *    paper's "sorting the means of the GMM from large to small"); connected parts of
 *    equal cluster are `SDFSegment`, 0 = the largest area.
 * 4. Optional fine level (RefineParts, default off; Filters/Core/Partition/PartRefinement.h):
 *    each part of a band covering at least RefinementMinimumArea (default 0.02, [0, 1]) of
 *    the area is cut again by the density modes of its own values, with the same energy;
 *    `SDFCluster` is then a (band, level) label and `SDFBand` keeps the band (without it
 *    `SDFBand` equals `SDFCluster`). The hierarchy levels follow the bands.
 *
 * Family consistency (the paper's title): the optional second input port "Model" takes
 * the output of another vtkSDFGMMPartition; its fitted mixture (field data
 * `SDFGMMMeans`, `SDFGMMSigmas`, `SDFGMMWeights`) is reused instead of fitting, so
 * cluster i means the same kind of part on every mesh of a family. A family shares two
 * things: one normalisation (every member's vtkSDFBilateralSmooth::NormalizationRange set
 * to the widest of the members' `SDFNormalizationRange`) and one model (partition the
 * appended members once and feed that output as Model); the pipeline command's `--family`
 * does both. Fewer faces then change cluster between poses than with each pose
 * partitioned alone (docs/partition.md).

 * Parameters (default, range; the ParaView proxy `SDFGMMPartition` mirrors them):
 * - NumberOfClusters k 5, [0, 16]: with ClusterModel 1 the most clusters (the density's
 *   modes decide how many, usually fewer); with ClusterModel 0 exactly k, and 0 = automatic:
 *   the k in [2, MaximumClusters] with the lowest BIC. The fit may use fewer clusters than asked when the data has fewer
 *   distinct values (e.g. a constant field gives one cluster), and the graph cut may
 *   leave a cluster without faces (a thickness level with no part large enough to pay
 *   for its boundary). `SDFClusterCount` is the k fitted.
 * - MaximumClusters 8, [2, 16]: the upper end of the automatic range.
 * - Lambda λ 0.12, [0, 1000] (the paper gives no value): a cut as long as √(area)
 *   across a flat region costs 1.4 × the mean data cost of all faces. Larger = fewer,
 *   smoother parts: short parts whose base has no crease (the fingers of a coarse hand)
 *   merge into their neighbour, and a thin band that comes and goes with the pose is
 *   dropped in every pose; 0 = no smoothing (argmax). With ClusterModel 0 (EM) use 0.03:
 *   EM's overlapping Gaussians lose clusters at 0.12 (docs/partition.md).
 * - Epsilon ε 1e-8, [1e-300, 1].
 * - ConvexityFactor 0.08, [0, 1]: 1 treats convex creases like concave ones.
 * - Restarts 5, [1, 100]; MaximumIterations 500, [1, 100000] (EM); Seed 0x5DF2008.
 * - NumberOfThreads 0 = all cores (vtkSDFSurfaceAlgorithm).
 * - ClusterModel 1 (default) = clusters from the modes of the area-weighted density of the
 *   input values (Filters/Core/Partition/DensityModes.h): the at most k modes rising ModeProminence
 *   (default 0.01, [0, 1]) of the highest peak and ModeValleyDepth (default 0, [0, 1])
 *   of their own height above their saddle, in a Gaussian kernel estimate of bandwidth
 *   ModeBandwidth (default 0.015 of the value range, [0.001, 0.5]). A valley depth keeps
 *   shoulders of a larger mode, which come and go with the pose, from becoming clusters;
 *   each cluster is the basin between two valleys, modelled by one Gaussian of its weighted
 *   moments. Boundaries then lie where few faces are, so a small pose-dependent shift moves
 *   few faces: fewer faces change cluster between poses than with EM (docs/partition.md). 0 = the paper's EM fit above: exactly k clusters, whose boundaries may
 *   fall inside a dense part of the histogram. A shape with fewer thickness levels than k
 *   gets fewer clusters with the modes (docs/partition.md).
 *
 * Output: the input with every cell and array plus cell arrays `SDFProbabilities`
 * (double, k components), `SDFCluster`, `SDFBand`, `SDFLevel1`…`SDFLevel{k−1}`, `SDFSegment`
 * (int), and field arrays `SDFGMMMeans`, `SDFGMMSigmas`, `SDFGMMWeights` (double, k),
 * `SDFClusterCount` (int), `SDFEnergy` (double). Only polygons are partitioned: other
 * cells get cluster, level and segment −1 and probabilities 0.
 *
 * Output port 1 ("Histogram", a vtkTable, the paper's Fig. 7 as data): HistogramBins bins
 * (default 64, [4, 4096]) over the input values extended by 4 of the largest sigma on each
 * side, with columns `BinCenter`, `Count` (faces per bin; the counts sum to the number of
 * polygons), `Density` (Count / (faces · bin width)), `Component0` … `Component{k−1}` (weight
 * × the mean normal density of each Gaussian over the bin) and `Mixture` (their sum), so
 * every curve integrates to its weight, even for a Gaussian narrower than a bin. ParaView opens it in a line chart beside the mesh.
 *
 * Bad input: no polygon, a missing, non-numeric or multi-component input array, a
 * non-finite value, or an invalid Model → vtkErrorMacro and a pass-through copy.
 *
 * Deviations: by default the mixture comes from the modes of the SDF density, not from EM
 * with a user-given k (the paper's consistency claim fails with EM at k = 5: a boundary
 * inside a dense part of the histogram moves whole limbs between poses; measurements:
 * docs/partition.md); the multilevel cut above 60,000 faces (a local minimum of the
 * coarse problem refined near the boundaries, not of every fine expansion move); e2 has a
 * floor (finite cost on flat edges) and a convexity factor; both terms carry the geometric
 * weights w_f, w_fg (the paper's plain sums make the balance depend on the resolution: fine
 * meshes fall into hundreds of segments; docs/partition.md); λ and the EM
 * settings are ours (the paper gives none); EM fits a fine histogram as the paper does, with
 * exact per-bin moments.
 */
#ifndef vtkSDFGMMPartition_h
#define vtkSDFGMMPartition_h

#include "ShapeDiameterFiltersModule.h" // for export macro
#include "vtkSDFSurfaceAlgorithm.h"

class vtkTable;

class SHAPEDIAMETERFILTERS_EXPORT vtkSDFGMMPartition : public vtkSDFSurfaceAlgorithm
{
public:
  static vtkSDFGMMPartition* New();
  vtkTypeMacro(vtkSDFGMMPartition, vtkSDFSurfaceAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Output array names.
  static constexpr const char* PROBABILITIES_ARRAY_NAME = "SDFProbabilities";
  static constexpr const char* CLUSTER_ARRAY_NAME = "SDFCluster";
  /// The thickness band of each face (the coarse cut), 0 = the thickest.
  static constexpr const char* BAND_ARRAY_NAME = "SDFBand";
  static constexpr const char* LEVEL_ARRAY_PREFIX = "SDFLevel";
  static constexpr const char* SEGMENT_ARRAY_NAME = "SDFSegment";
  static constexpr const char* MEANS_ARRAY_NAME = "SDFGMMMeans";
  static constexpr const char* SIGMAS_ARRAY_NAME = "SDFGMMSigmas";
  static constexpr const char* WEIGHTS_ARRAY_NAME = "SDFGMMWeights";
  static constexpr const char* CLUSTER_COUNT_ARRAY_NAME = "SDFClusterCount";
  static constexpr const char* ENERGY_ARRAY_NAME = "SDFEnergy";
  ///@}

  /// Connects the optional family model (port 1): another vtkSDFGMMPartition's output.
  void SetModelConnection(vtkAlgorithmOutput* model) { this->SetInputConnection(1, model); }
  /// Sets the optional family model (port 1) as data: another vtkSDFGMMPartition's output.
  void SetModelData(vtkDataObject* model) { this->SetInputData(1, model); }

  ///@{
  /// Number of clusters k (default 5, range [0, 16]): with ClusterModel 1 the most clusters,
  /// with 0 exactly k; 0 = automatic (up to MaximumClusters; with EM the k of lowest BIC).
  vtkSetClampMacro(NumberOfClusters, int, 0, 16);
  vtkGetMacro(NumberOfClusters, int);
  ///@}

  ///@{
  /// Upper end of the automatic range of k when NumberOfClusters is 0 (default 8, range
  /// [2, 16]).
  vtkSetClampMacro(MaximumClusters, int, 2, 16);
  vtkGetMacro(MaximumClusters, int);
  ///@}

  ///@{
  /// Smoothness weight λ of the graph cut, independent of resolution and units (default 0.12,
  /// range [0, 1000]); larger = fewer, smoother parts, 0 = per-face most probable cluster.
  vtkSetClampMacro(Lambda, double, 0.0, 1000.0);
  vtkGetMacro(Lambda, double);
  ///@}

  ///@{
  /// ε of the data term −log(P + ε) (default 1e-8, range [1e-300, 1]).
  vtkSetClampMacro(Epsilon, double, 1e-300, 1.0);
  vtkGetMacro(Epsilon, double);
  ///@}

  ///@{
  /// Scale of the normal angle on convex edges, 1 = convex creases cost like concave ones
  /// (default 0.08, range [0, 1]).
  vtkSetClampMacro(ConvexityFactor, double, 0.0, 1.0);
  vtkGetMacro(ConvexityFactor, double);
  ///@}

  ///@{
  /// EM (ClusterModel 0): k-means++ restarts, the best likelihood kept (default 5, range
  /// [1, 100]).
  vtkSetClampMacro(Restarts, int, 1, 100);
  vtkGetMacro(Restarts, int);
  ///@}

  ///@{
  /// EM (ClusterModel 0): iterations at most (default 500, range [1, 100000]).
  vtkSetClampMacro(MaximumIterations, int, 1, 100000);
  vtkGetMacro(MaximumIterations, int);
  ///@}

  ///@{
  /// EM (ClusterModel 0): seed of the initialisation (default 0x5DF2008 = 98508808; fixed, so
  /// the same input gives the same parts).
  vtkSetMacro(Seed, int);
  vtkGetMacro(Seed, int);
  ///@}

  ///@{
  /// Bins of the histogram table on output port 1 (default 64, range [4, 4096]).
  vtkSetClampMacro(HistogramBins, int, 4, 4096);
  vtkGetMacro(HistogramBins, int);
  ///@}

  /// Values of ClusterModel.
  enum ClusterModelType
  {
    EM = 0,
    DENSITY_MODES = 1
  };

  ///@{
  /// How the clusters are found: 1 = DENSITY_MODES (default) the at most k modes of the
  /// area-weighted SDF density (Filters/Core/Partition/DensityModes.h); 0 = EM the paper's EM
  /// fit of k Gaussians (range [0, 1]).
  vtkSetClampMacro(ClusterModel, int, EM, DENSITY_MODES);
  vtkGetMacro(ClusterModel, int);
  void SetClusterModelToEM() { this->SetClusterModel(EM); }
  void SetClusterModelToDensityModes() { this->SetClusterModel(DENSITY_MODES); }
  ///@}

  ///@{
  /// ClusterModel 1: kernel bandwidth of the density estimate, relative to the value range
  /// (default 0.015, range [0.001, 0.5]).
  vtkSetClampMacro(ModeBandwidth, double, 0.001, 0.5);
  vtkGetMacro(ModeBandwidth, double);
  ///@}

  ///@{
  /// ClusterModel 1: smallest height of a mode above its saddle, relative to the highest peak
  /// (default 0.01, range [0, 1]).
  vtkSetClampMacro(ModeProminence, double, 0.0, 1.0);
  vtkGetMacro(ModeProminence, double);
  ///@}

  ///@{
  /// ClusterModel 1: smallest height of a mode above its saddle, relative to the mode's own
  /// height (default 0 = prominence alone, range [0, 1]).
  vtkSetClampMacro(ModeValleyDepth, double, 0.0, 1.0);
  vtkGetMacro(ModeValleyDepth, double);
  ///@}

  ///@{
  /// The fine level: each part of a band covering at least RefinementMinimumArea of the area
  /// is cut again by the modes of its own values (Filters/Core/Partition/PartRefinement.h).
  /// RefineParts default on; off = `SDFCluster` is the band.
  vtkSetMacro(RefineParts, bool);
  vtkGetMacro(RefineParts, bool);
  vtkBooleanMacro(RefineParts, bool);
  ///@}

  ///@{
  /// Parts below this share of the area are not refined (default 0.02, range [0, 1]).
  vtkSetClampMacro(RefinementMinimumArea, double, 0.0, 1.0);
  vtkGetMacro(RefinementMinimumArea, double);
  ///@}

  /// The histogram and fitted densities (output port 1).
  vtkTable* GetHistogram();

protected:
  vtkSDFGMMPartition();
  ~vtkSDFGMMPartition() override;

  int FillInputPortInformation(int port, vtkInformation* info) override;
  int FillOutputPortInformation(int port, vtkInformation* info) override;
  bool ExecuteSurface(const shapediameter::adapter::SurfaceRequest& request) override;
  /// The selected normalised SDF array and its default, SDFNormalized.
  std::vector<std::string> CellArraysRead() override;
  /// Distributed runs build each process's own rows of the dual graph with a halo of its
  /// neighbours' faces; above 60,000 faces the graph cut runs on every process's faces
  /// (Partition/DistributedCut.h), below it process 0 partitions the gathered graph
  /// (Partition/DistributedPartition.h).
  bool CanRunWithHalo() const override { return true; }
  /// The halo: the faces sharing a corner with an own face (the dual graph's rows need one ring).
  bool HaloOfSharedCorners() const override { return true; }
  /// The corner voxels' size: twice the whole surface's mean edge length.
  double HaloRadius(vtkPolyData* piece, const shapediameter::ProcessGroup& group) override;

  int NumberOfClusters;
  int MaximumClusters;
  double Lambda;
  double Epsilon;
  double ConvexityFactor;
  int Restarts;
  int MaximumIterations;
  int Seed;
  int HistogramBins;
  int ClusterModel;
  double ModeBandwidth;
  double ModeProminence;
  double ModeValleyDepth;
  bool RefineParts;
  double RefinementMinimumArea;

private:
  vtkSDFGMMPartition(const vtkSDFGMMPartition&) = delete;
  void operator=(const vtkSDFGMMPartition&) = delete;
};

#endif
