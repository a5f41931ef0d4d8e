// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkSDFBilateralSmooth
 * @brief   Bilateral smoothing of the SDF on small geodesic neighbourhoods, then the
 *          paper's log normalisation to [0, 1].
 *
 * Shapira, Shamir, Cohen-Or 2008, section 3 (smoothing) and section 4 (normalisation).
 *
 * Smoothing, exactly as the paper writes it (Filters/Core/Smoothing/BilateralSmoothing.h):
 *   f^{i+1}(x) = (f^i(x) + Σ_y c(|f^i(x) − f(y)|) w_x(y) f(y)) / (1 + Σ_y c(·) w_x(y)),
 * the centre keeps weight 1, neighbours contribute their original values f(y);
 * w_x(y) = exp(−d²/2σ²) with d the geodesic distance between face centres, approximated
 * by shortest paths over the face-adjacency (dual) graph; c(x) = 1 for x ≤ t, 0 above, so
 * jumps larger than t (boundaries between parts) stay sharp while noise within a part is
 * averaged out. This is what makes the SDF robust to pose changes (paper, Fig. 4).
 *
 * Normalisation: nsdf = log(((sdf − min)/(max − min))·α + 1) / log(α + 1) over the
 * surface cells; a constant field gives 0 everywhere.
 *
 * Parameters (default, range; the ParaView proxy `SDFBilateralSmooth` mirrors them):
 * - input array: cell array, default `SDF` (SetInputArrayToProcess(0, ...)).
 * - NumberOfIterations 3, [0, 100] (paper: "a small number").
 * - SpatialSigma σ 1.0, [0.01, 100], in units of the mesh's mean edge length.
 * - NeighborhoodRadius 2.0, [0, 10], in units of σ (about 20-30 faces; at most
 *   MaxNeighbors = 24 nearest).
 * - RangeThreshold t 0.1, [0, 10], a fraction of the field's robust spread
 *   Q(0.98) − Q(0.02).
 * - Alpha α 4, [0.001, 1000] (paper: 4).
 * - NormalizationRange [min, max], default [0, 0] = this mesh's own minimum and maximum of
 *   SDFSmoothed (the paper). A family of meshes (poses of one object) shares one range so
 *   that one nsdf means one thickness on every member: set every member's range to the
 *   smallest minimum and the largest maximum of the members' `SDFNormalizationRange` (what
 *   the pipeline command's `--family` does). Values outside a given range map to 0 or 1.
 *   Any range with max <= min means automatic; a NaN or infinite bound is an error.
 * - NumberOfThreads 0 = all cores; the output does not depend on it (vtkSDFSurfaceAlgorithm).
 *
 * Output: the input with all its cells and arrays plus cell arrays `SDFSmoothed` (length
 * units) and `SDFNormalized` ([0, 1]), and the field array `SDFNormalizationRange` (double,
 * 2: the [min, max] of SDFSmoothed that was mapped to [0, 1]). Only polygons take part; strips, vertices and lines
 * keep their input value in SDFSmoothed and get SDFNormalized 0, and are ignored by
 * min/max.
 *
 * Bad input: no polygon, a missing, non-numeric or multi-component input array, or a
 * non-finite input value → vtkErrorMacro and a pass-through copy without new arrays.
 * Faces without neighbours keep their value; several components, non-manifold edges and
 * open boundaries are handled by the face graph.
 *
 * Distributed runs (pvbatch / pvserver under MPI): each process smooths its own faces with
 * a halo of the other processes' faces within the neighbourhood radius, and the mean edge
 * length, the robust spread and the normalisation range are those of the whole surface
 * (combined over the processes); the results equal a serial run's bit for bit. Pieces without
 * global ids (the SDF OFF Reader provides them) or with cells other than polygons are smoothed
 * once on process 0 instead (docs/distributed.md).
 *
 * Deviations: the paper gives no values for the neighbourhood, σ and t; ours are relative
 * to mesh resolution and SDF spread so they transfer to unseen meshes.
 */
#ifndef vtkSDFBilateralSmooth_h
#define vtkSDFBilateralSmooth_h

#include "ShapeDiameterFiltersModule.h" // for export macro
#include "vtkSDFSurfaceAlgorithm.h"

class SHAPEDIAMETERFILTERS_EXPORT vtkSDFBilateralSmooth : public vtkSDFSurfaceAlgorithm
{
public:
  static vtkSDFBilateralSmooth* New();
  vtkTypeMacro(vtkSDFBilateralSmooth, vtkSDFSurfaceAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Output array names.
  static constexpr const char* SMOOTHED_ARRAY_NAME = "SDFSmoothed";
  static constexpr const char* NORMALIZED_ARRAY_NAME = "SDFNormalized";
  static constexpr const char* NORMALIZATION_RANGE_ARRAY_NAME = "SDFNormalizationRange";

  ///@{
  /// Bilateral iterations (default 3, range [0, 100]; paper: "a small number"); 0 only
  /// normalises.
  vtkSetClampMacro(NumberOfIterations, int, 0, 100);
  vtkGetMacro(NumberOfIterations, int);
  ///@}

  ///@{
  /// Spatial Gaussian sigma σ in mean edge lengths of the mesh (default 1, range [0.01, 100]).
  vtkSetClampMacro(SpatialSigma, double, 0.01, 100.0);
  vtkGetMacro(SpatialSigma, double);
  ///@}

  ///@{
  /// Geodesic neighbourhood radius in units of σ, at most 24 nearest faces (default 2, range
  /// [0, 10]).
  vtkSetClampMacro(NeighborhoodRadius, double, 0.0, 10.0);
  vtkGetMacro(NeighborhoodRadius, double);
  ///@}

  ///@{
  /// Range threshold t as a fraction of the field's robust spread Q(0.98) − Q(0.02): larger
  /// differences stay sharp (default 0.1, range [0, 10]).
  vtkSetClampMacro(RangeThreshold, double, 0.0, 10.0);
  vtkGetMacro(RangeThreshold, double);
  ///@}

  ///@{
  /// α of the log normalisation (default 4, range [0.001, 1000]; paper: 4).
  vtkSetClampMacro(Alpha, double, 0.001, 1000.0);
  vtkGetMacro(Alpha, double);
  ///@}

  ///@{
  /// Shared [min, max] of SDFSmoothed mapped to [0, 1] for a family (default [0, 0]; any
  /// max <= min = automatic, this mesh's own range; see the class documentation).
  vtkSetVector2Macro(NormalizationRange, double);
  vtkGetVector2Macro(NormalizationRange, double);
  ///@}

protected:
  vtkSDFBilateralSmooth();
  ~vtkSDFBilateralSmooth() override;

  bool ExecuteSurface(const shapediameter::adapter::SurfaceRequest& request) override;
  /// The selected SDF array and its default, SDF.
  std::vector<std::string> CellArraysRead() override;
  /// Distributed runs smooth each process's own faces with a halo of its neighbours'.
  bool CanRunWithHalo() const override { return true; }
  /// NeighborhoodRadius x SpatialSigma x the whole surface's mean edge length.
  double HaloRadius(vtkPolyData* piece, const shapediameter::ProcessGroup& group) override;

  int NumberOfIterations;
  double SpatialSigma;
  double NeighborhoodRadius;
  double RangeThreshold;
  double Alpha;
  double NormalizationRange[2] = { 0.0, 0.0 };

private:
  vtkSDFBilateralSmooth(const vtkSDFBilateralSmooth&) = delete;
  void operator=(const vtkSDFBilateralSmooth&) = delete;
};

#endif
