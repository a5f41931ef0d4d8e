// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkShapeDiameterFilter
 * @brief   The shape diameter function (SDF) of a surface, per face (or per point).
 *
 * Shapira, Shamir, Cohen-Or, "Consistent mesh partitioning and skeletonisation using
 * the shape diameter function", The Visual Computer 24(4), 2008, section 3.
 *
 * For every face the filter casts a cone of rays around the inward normal from the face
 * centre, keeps for each ray its first hit when the ray leaves the volume there (HitRule 0,
 * the default; a first hit on a surface turned towards the ray is no measurement and the
 * ray is dropped), drops rays that hit nothing, keeps the lengths within one standard
 * deviation of their median and averages
 * them with weights 1/(angle to the cone axis). The result is a local measure of the
 * object's diameter: about twice the distance to the medial axis, invariant to rigid
 * motions and nearly invariant to articulated pose changes. Details of the statistics
 * and of the ray pattern: Filters/Core/SDF/ShapeDiameter.h and
 * Filters/Core/RayCasting/ConeSampling.h; defaults and their evidence: docs/sdf.md.
 *
 * Parameters (the ParaView proxy `ShapeDiameter` mirrors them):
 * - NumberOfRays, default 30 (paper), range [1, 4096].
 * - ConeAngle, full opening angle in degrees, default 120 (paper), range [1, 179].
 * - HitRule, default 0 = the ray's first hit, kept when the ray leaves the volume through
 *   it, else the ray is dropped; 1 = hits on faces turned the same way as the origin's face
 *   are skipped and the ray goes on (see Deviations).
 * - PerPoint, default off: compute at the points (cone around the area-weighted vertex
 *   normal) and write point arrays instead of cell arrays.
 * - AutoOrient, default on: make the polygon winding consistent and outward per
 *   connected component before casting (inward or mixed winding would send the cones out
 *   of the object). The output polygons carry the repaired winding and a warning says
 *   how many were flipped. Triangle strips are cast correctly but keep their winding.
 * - IgnoreBuriedFaces, default on (ours): a face lying inside another part of a
 *   self-intersecting mesh (a paw pushed into the torso) gets no value of its own and is filled
 *   from its neighbours like a face without a valid ray; its rays would measure the distance to
 *   the enclosing part's surface, which changes with the pose. Found by one ray along the
 *   outward normal whose first hit is left, not entered (Filters/Core/SDF/ShapeDiameter.h, "Buried
 *   origins"). Off = the paper's value for every face.
 * - Mode, default 0 = Exact: every face casts its cone (the paper). 1 = Adaptive: cones are
 *   cast from a subset of faces spaced at half the local SDF, refined where neighbouring cast
 *   values differ by more than Tolerance, and the other faces are interpolated over the
 *   surface (not across concave creases); the cost follows the shape, not the face count
 *   (Filters/Core/SDF/AdaptiveShapeDiameter.h; accuracy and speed: docs/adaptive-sdf.md).
 *   Cast faces get exactly the Exact value; SDFValidRays of an interpolated face is that of
 *   the cast face its value comes from.
 * - Tolerance, default 0.15, range [0.001, 1]: Adaptive only, relative SDF difference between
 *   neighbouring cast faces above which more faces are cast.
 * - NumberOfThreads, default 0 = all cores (vtkSMPTools' STDThread backend is used
 *   whatever backend the application selected, because ParaView defaults to Sequential).
 *   The output does not depend on the thread count.
 *
 * Output: the input with every cell (in order) and every array, plus
 * - `SDF` (double): the shape diameter in the mesh's length units;
 * - `SDFValidRays` (int): rays kept after filtering; 0 marks a value filled in from the
 *   neighbouring faces across manifold edges (no valid ray, e.g. a face looking out
 *   through a hole, a degenerate face, or a buried face). A component with no valid face at all gets the median SDF of the
 *   whole mesh (0 if no face has a value). Vertices and lines get SDF 0 and 0 rays.
 * Polygons of any size and triangle strips are split into triangles internally; a
 * cell's SDF is the area-weighted mean of its triangles' values and SDFValidRays their
 * sum (for triangle meshes this is exactly the per-face SDF).
 *
 * Bad input: no polygons, or a non-finite coordinate used by a polygon → vtkErrorMacro
 * and a pass-through copy of the input without new arrays. Empty input → a warning and
 * an empty output. Abort is honoured between the steps before the ray loop (triangulation,
 * adjacency, orientation, BVH) and between chunks of faces in it (the output is then the
 * pass-through copy). No NaN is ever written.
 *
 * Deviations from the paper: the paper ignores "intersections where the normal at the
 * intersection points in the same direction as the point-of-origin (angle difference less
 * than 90 degrees)". Read as "skip and continue" (HitRule 1), a ray that meets such a face —
 * a neighbouring part touching or crossing in front of the limb — goes on into that part,
 * so the value depends on the pose. Read as "such a first hit is no measurement" (HitRule 0,
 * the default, as CGAL does), the ray is dropped. HitRule 0 is the default because the
 * normalised SDF then changes less between poses (measurements: docs/sdf.md). HitRule 0
 * keeps the wide rays of the cone (HitRule 1 loses every ray more than 45 degrees off the
 * normal on a sphere), so its values on round bodies are smaller. HitRule 0 tests the
 * ray against the hit's normal (leaving the volume), which also drops rays that start inside
 * a fold. The paper leaves the ray pattern, the weight of the axial
 * ray and the exact "standard deviation" open; our choices are documented in the core.
 * The paper uses an octree; we use Embree's BVH.
 */
#ifndef vtkShapeDiameterFilter_h
#define vtkShapeDiameterFilter_h

#include "ShapeDiameterFiltersModule.h" // for export macro
#include "vtkSDFSurfaceAlgorithm.h"

class SHAPEDIAMETERFILTERS_EXPORT vtkShapeDiameterFilter : public vtkSDFSurfaceAlgorithm
{
public:
  static vtkShapeDiameterFilter* New();
  vtkTypeMacro(vtkShapeDiameterFilter, vtkSDFSurfaceAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  /// Output array names.
  static constexpr const char* SDF_ARRAY_NAME = "SDF";
  static constexpr const char* VALID_RAYS_ARRAY_NAME = "SDFValidRays";

  ///@{
  /// Rays per cone (default 30, range [1, 4096]).
  vtkSetClampMacro(NumberOfRays, int, 1, 4096);
  vtkGetMacro(NumberOfRays, int);
  ///@}

  ///@{
  /// Full opening angle of the cone in degrees (default 120, range [1, 179]).
  vtkSetClampMacro(ConeAngle, double, 1.0, 179.0);
  vtkGetMacro(ConeAngle, double);
  ///@}

  /// Values of HitRule.
  enum HitRuleType
  {
    FIRST_HIT_LEAVING = 0,
    SKIP_SAME_FACING = 1
  };

  ///@{
  /// Which hit a ray measures: 0 = FIRST_HIT_LEAVING (default) its first hit, dropped unless
  /// the ray leaves the volume there; 1 = SKIP_SAME_FACING the first hit on a face turned
  /// against the origin's, skipping others (range [0, 1]).
  vtkSetClampMacro(HitRule, int, FIRST_HIT_LEAVING, SKIP_SAME_FACING);
  vtkGetMacro(HitRule, int);
  void SetHitRuleToFirstHitLeaving() { this->SetHitRule(FIRST_HIT_LEAVING); }
  void SetHitRuleToSkipSameFacing() { this->SetHitRule(SKIP_SAME_FACING); }
  ///@}

  ///@{
  /// Compute at points instead of faces (default off).
  vtkSetMacro(PerPoint, vtkTypeBool);
  vtkGetMacro(PerPoint, vtkTypeBool);
  vtkBooleanMacro(PerPoint, vtkTypeBool);
  ///@}

  ///@{
  /// Orient polygons consistently and outward per component first (default on).
  vtkSetMacro(AutoOrient, vtkTypeBool);
  vtkGetMacro(AutoOrient, vtkTypeBool);
  vtkBooleanMacro(AutoOrient, vtkTypeBool);
  ///@}

  ///@{
  /// Give faces inside another part of a self-intersecting mesh their neighbours' value
  /// instead of their own (default on).
  vtkSetMacro(IgnoreBuriedFaces, vtkTypeBool);
  vtkGetMacro(IgnoreBuriedFaces, vtkTypeBool);
  vtkBooleanMacro(IgnoreBuriedFaces, vtkTypeBool);
  ///@}

  /// Values of Mode.
  enum ModeType
  {
    EXACT = 0,
    ADAPTIVE = 1
  };

  ///@{
  /// Evaluation mode: 0 = Exact (default, every face casts), 1 = Adaptive (a subset casts,
  /// the rest is interpolated; cost follows the shape).
  vtkSetClampMacro(Mode, int, EXACT, ADAPTIVE);
  vtkGetMacro(Mode, int);
  void SetModeToExact() { this->SetMode(EXACT); }
  void SetModeToAdaptive() { this->SetMode(ADAPTIVE); }
  ///@}

  ///@{
  /// Adaptive mode: relative SDF difference between neighbouring cast faces above which more
  /// faces are cast (default 0.15, range [0.001, 1]).
  vtkSetClampMacro(Tolerance, double, 0.001, 1.0);
  vtkGetMacro(Tolerance, double);
  ///@}

protected:
  vtkShapeDiameterFilter();
  ~vtkShapeDiameterFilter() override;

  bool ExecuteSurface(const shapediameter::adapter::SurfaceRequest& request) override;
  /// Under MPI the exact per-face SDF runs on every process, each casting from its own faces
  /// (the adaptive mode and PerPoint run once on process 0; docs/distributed.md).
  bool CanRunReplicated() const override { return this->Mode == EXACT && !this->PerPoint; }

  int NumberOfRays;
  double ConeAngle;
  vtkTypeBool PerPoint = false;
  int HitRule;
  vtkTypeBool AutoOrient = true;
  vtkTypeBool IgnoreBuriedFaces = true;
  int Mode;
  double Tolerance;

private:
  vtkShapeDiameterFilter(const vtkShapeDiameterFilter&) = delete;
  void operator=(const vtkShapeDiameterFilter&) = delete;
};

#endif
