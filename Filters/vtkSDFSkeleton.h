// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkSDFSkeleton
 * @brief   SDF-guided curve skeleton that keeps its link to the surface.
 *
 * Shapira, Shamir, Cohen-Or 2008, section 5. The SDF approximates twice the distance to
 * the medial axis, so:
 * 1. NumberOfSamples random surface points (area-weighted, fixed Seed) are pushed inward
 *    along the inward normal by half the SDF of their face: a cloud P near the medial
 *    axis; each point keeps radius(p) = SDF/2 and its source face.
 * 2. MLS thinning, NumberOfIterations times: PCA of each point's neighbours within
 *    radius(p) (k-d tree), projection onto the regression line, confidence =
 *    max(e)/(e1+e2+e3); points with confidence ≥ ConfidenceThreshold are kept and thinned
 *    to a minimal spacing SpacingFactor·radius(p) → T. (ours) Only points whose medial ball
 *    fits are kept: no surface within a quarter of radius(p) along the axes and diagonals
 *    (14 short rays; the core's SkeletonThinningOptions::MinimumClearance 0.25, 0 = off; not
 *    a filter property). Deviation: beside a box's convex edges the faces' short SDF lines
 *    their points up along the edge, inside the ball of the face across it, and MLS finds
 *    them confident: without the test the skeleton of a machined part traced its edges and
 *    left its bosses without a leaf (Filters/Core/Skeleton/SkeletonThinning.h).
 * 3. Poly-segments grow from the most confident unused point of T along its regression
 *    line in both directions.
 * 4. k-terminal shortest paths through P (a priority-queue growth from all segments at
 *    once) join the segments: one connected tree per connected surface component.
 *    (ours) Where P spreads in a plane (a palm, a flat torso), a path pays less per unit
 *    length the deeper the point lies inside that sheet (its in-plane distance to the
 *    surface over its radius), so it follows the sheet's middle rather than its rim; in tubes
 *    and blobs lengths are the paper's (deviation: libigl hand rig recall 90.0 -> 94.5 %;
 *    Filters/Core/Skeleton/SkeletonConnection.h, evidence in docs/skeleton.md).
 *    (ours) A leaf whose branch points head-on at its part's end gets one more node where a
 *    ball of its radius touches that end (exit normal within MaximumExitAngle of the
 *    branch); then short leaf stubs are pruned.
 * 5. (ours) Every large group of projected points far from that tree (UncoveredFactor),
 *    and every thin or small limb among the smaller ones (ThinLimbFactor), gets a branch
 *    through P to the centre of its far end; a large group that is several limbs (a head with
 *    its snout and ears) gets one more to each other far end that leaves the group near where
 *    the group meets the tree (segmentation benchmark, Armadillo: limbs reached 83.5 -> 92.9 %); a
 *    node behind the surface covers no point (FourLeg: a tail against a hind leg kept its
 *    leaf, 91.4 -> 93.2 %);
 *    junctions it creates closer than one radius to another are merged (its leaves are not
 *    pruned).
 * 6. (ours, with the segment link below) A large segment left without a bone of its own whose
 *    farthest projected point is far from the skeleton (PartUncoveredFactor) gets a branch.
 * 7. (ours) Every bone is made a smooth curve through the volume (BoneSmoothing): its nodes
 *    move onto a local quadratic fit along the bone, held back where a smoothed edge would
 *    leave the volume; the bones are numbered again by their smoothed lengths and every
 *    face, keeping its bone, is linked again to the nearest node of it.
 *    (ours, 7b) A leaf whose smoothed bone meets its part's end head-on (MaximumExitAngle)
 *    is carried on TipReach of the way to the surface, so a limb's bone spans the limb.
 * Every face is linked to the node nearest to its projected centre (face centre pushed
 * inward by SDF/2). When the input has `SDFSegment` (the partition's connected parts; the
 * product chain puts vtkSDFGMMPartition before this filter) and LinkBySegment is on, every
 * segment is then linked to one bone (one of its own where a bone holds OwnBoneShare of it,
 * else the bone holding most of its area under the nearest-node link), and each of its faces
 * to the nearest node of that bone. This follows the paper's Fig. 15 (the projected points
 * keep their face's part) and is what makes
 * `SkeletonBoneId` consistent across poses: the skeleton's junctions move with the pose,
 * the partition's boundaries much less (measurements: docs/skeleton.md).
 * Algorithm details, the remaining (advanced) defaults and the deviations:
 * Filters/Core/Skeleton/Skeleton*.h.
 *
 * Input: a polygonal surface with a per-cell SDF: the selected array (default
 * `SDFSmoothed`; when the input has no such array, `SDF`). Polygons are triangulated
 * internally and oriented consistently outward (as vtkShapeDiameterFilter does).
 *
 * Parameters (default, range; the ParaView proxy `SDFSkeleton` mirrors them):
 * - NumberOfSamples N 10000, [1, 1000000] (paper: at most 10000).
 * - NumberOfIterations 3, [1, 100] (paper: 2 to 4).
 * - ConfidenceThreshold 0.8, [0, 1].
 * - MinimumConfidentShare 0.2, [0, 1]: the threshold is lowered where needed so that at
 *   least this share of the projected points is eligible (deviation: the paper says only
 *   "high confidence"; with 0.8 alone a character with short, stubby limbs keeps few of
 *   its points and only its longest limbs get a branch; 0 = the threshold alone;
 *   Filters/Core/Skeleton/SkeletonThinning.h, evidence in docs/skeleton.md).
 * - SpacingFactor ε 0.25, [0, 10], in units of the local radius SDF/2.
 * - MaximumExitAngle 40 degrees, [0, 90]: a leaf is carried on to its part's end when its
 *   branch leaves the volume within this angle of the exit surface's normal (deviation: the
 *   paper's branches stop where the confident points stop, short of a hand or a head, by an
 *   amount that changes with the pose; 0 = the paper's; Filters/Core/Skeleton/SkeletonLeafExtension.h).
 * - TipReach 1, [0, 1]: step 7b (ours): such a leaf gets one more node this share of the way
 *   from it to the surface ahead; 1 = at the surface, where a rig puts the end joint of a
 *   limb (the medial axis ends one radius inside: the branch would stop short of a fingertip,
 *   a head top or a sole by that radius); 0 = off (the leaf stays at the ball's centre). The
 *   node's Radius is its leaf's (SDF/2 of the part's end), not that of an inscribed ball.
 * - UncoveredFactor 3, [0, 1e6]: after step 4, every large group of projected points farther
 *   than this many radii from the skeleton gets a branch (deviation: the paper's skeleton
 *   only joins confident segments, so a bent or stubby limb or an ear gets a branch in some
 *   poses and not in others; 0 = the paper's; Filters/Core/Skeleton/SkeletonCoverage.h).
 * - ThinLimbFactor 6, [0, 1e6]: in step 5, a group of far points holding less than 1 % of
 *   them still gets a branch when its tip lies at least this many radii from the skeleton and
 *   it is a thin limb (its points along a line, linearity 0.95) or a small one (at least 0.5 %
 *   of the points, any shape: a hand, a fin) (deviation: area-weighted sampling gives a tail or
 *   a finger so few points that it never forms a confident segment nor a large group: the
 *   camel's tail had no branch; 0 = off; Filters/Core/Skeleton/SkeletonCoverage.h).
 * - LinkBySegment on: the segment link above (deviation: the paper draws the parts on the
 *   projected points but does not say how faces are assigned to bones).
 * - OwnBoneShare 0.15, [0, 1]: with the segment link, segments first get bones of their own,
 *   largest overlaps first, among the bones holding at least this share of their area; a
 *   segment left without one takes the bone holding most of it (a bone running through two
 *   parts, such as an ear's across the head, no longer joins them in some poses only; above
 *   0.5 = each segment the bone holding most of it).
 * - PartUncoveredFactor 2, [0, 1e6]: with the segment link, step 6 (ours): a segment holding
 *   at least 3 % of the projected points that got no bone of its own, and whose farthest
 *   projected point lies more than this many radii from the skeleton, gets a branch into it
 *   (an elephant's lowered head whose only bones were its ears'; a teddy's stubby arm that the
 *   spine's path crosses at its base); 0 = off.
 * - BoneSmoothing 1, [0, 100]: step 7's Gaussian weights along a bone, standard deviation in
 *   node radii (deviation: the paper's nodes as connected zig-zag about the medial axis by
 *   the SDF's noise, 90th percentile of the turning angle 24–30° on the camel, man and
 *   armadillo against 8–14°, rig recall unchanged; 0 = the paper's; Filters/Core/Skeleton/SkeletonSmoothing.h).
 * - Seed 0x5DF5EED; NumberOfThreads 0 = all cores (the output does not depend on it;
 *   vtkSDFSurfaceAlgorithm).
 *
 * Outputs:
 * - port 0 "Skeleton": nodes as points with point arrays `Radius`, `Confidence`; polylines
 *   (a component whose shape has no curve-like part gets a single-node vertex) with cell
 *   arrays `BoneId` and `IsConnection` (1 = connecting path, 0 = fitted poly-segment). A
 *   bone is a branch of the skeleton tree (a maximal path between ends and junctions),
 *   numbered by decreasing length; polylines are cut at junctions so each lies in one bone;
 *   a junction belongs to the longest bone meeting there;
 * - port 1 "Surface": the input with every cell and array plus cell arrays
 *   `SkeletonNodeId`, `SkeletonBoneId` (−1 for vertices and lines);
 * - port 2 "Projected Points": the cloud P as vertices with point arrays `SourceFaceId`
 *   (input cell id; under MPI the cell's global id), `Radius`, `Confidence`, and `SDFCluster`
 *   when the input has it.
 * Active scalars (what ParaView colours by): `BoneId`, `SkeletonBoneId`, `Confidence`.
 *
 * Under MPI (pieces with global ids, polygons only) every process triangulates its own cells
 * and sends process 0 only what the skeleton reads: triangles by global point ids, the SDF
 * and `SDFSegment` per triangle, and its points (about 70 bytes per triangle;
 * Filters/Core/Skeleton/DistributedSkeleton.h). Process 0 builds the whole triangle mesh in
 * the global ids' order, orients it and computes the skeleton (ports 0 and 2, on process 0
 * only), every process casting the skeleton's rays that may meet its own triangles and
 * projecting its share of the thinning's MLS points; every process links its own cells to it
 * (port 1), process 0 completing the link's
 * sums; process 0 asks the owners of the projected points' source cells for their ids and
 * `SDFCluster`: the serial result bit for bit. Other
 * pieces are collected on process 0 whole (Filters/DistributedSupport.h).
 *
 * Bad input: no polygon (of three or more points), no usable SDF array (missing,
 * non-numeric, several components, non-finite or negative values), non-finite coordinates →
 * vtkErrorMacro; ports 0 and 2 empty and port 1 a pass-through copy. Empty input → a
 * warning and empty outputs. A surface without area (all points coincident, or lengths
 * whose squares underflow) → a warning, one node per component and no projected points.
 */
#ifndef vtkSDFSkeleton_h
#define vtkSDFSkeleton_h

#include "ShapeDiameterFiltersModule.h" // for export macro
#include "vtkSDFSurfaceAlgorithm.h"

class SHAPEDIAMETERFILTERS_EXPORT vtkSDFSkeleton : public vtkSDFSurfaceAlgorithm
{
public:
  static vtkSDFSkeleton* New();
  vtkTypeMacro(vtkSDFSkeleton, vtkSDFSurfaceAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// Array names.
  static constexpr const char* RADIUS_ARRAY_NAME = "Radius";
  static constexpr const char* CONFIDENCE_ARRAY_NAME = "Confidence";
  static constexpr const char* BONE_ID_ARRAY_NAME = "BoneId";
  static constexpr const char* IS_CONNECTION_ARRAY_NAME = "IsConnection";
  static constexpr const char* NODE_ID_ARRAY_NAME = "SkeletonNodeId";
  static constexpr const char* SURFACE_BONE_ID_ARRAY_NAME = "SkeletonBoneId";
  static constexpr const char* SOURCE_FACE_ARRAY_NAME = "SourceFaceId";
  ///@}

  ///@{
  /// Surface samples N, area-weighted (default 10000, range [1, 1000000]; paper: at most
  /// 10000).
  vtkSetClampMacro(NumberOfSamples, int, 1, 1000000);
  vtkGetMacro(NumberOfSamples, int);
  ///@}

  ///@{
  /// MLS projection iterations (default 3, range [1, 100]; paper: 2 to 4).
  vtkSetClampMacro(NumberOfIterations, int, 1, 100);
  vtkGetMacro(NumberOfIterations, int);
  ///@}

  ///@{
  /// Points with MLS confidence at least this form the thinned set T (default 0.8, range
  /// [0, 1]).
  vtkSetClampMacro(ConfidenceThreshold, double, 0.0, 1.0);
  vtkGetMacro(ConfidenceThreshold, double);
  ///@}

  ///@{
  /// The confidence threshold is lowered where needed so that at least this share of the
  /// projected points is eligible for T; 0 = the threshold alone (default 0.2, range [0, 1]).
  vtkSetClampMacro(MinimumConfidentShare, double, 0.0, 1.0);
  vtkGetMacro(MinimumConfidentShare, double);
  ///@}

  ///@{
  /// Minimal spacing ε between thinned points, in units of the local radius SDF/2 (default
  /// 0.25, range [0, 10]).
  vtkSetClampMacro(SpacingFactor, double, 0.0, 10.0);
  vtkGetMacro(SpacingFactor, double);
  ///@}

  ///@{
  /// A leaf whose branch leaves the volume within this angle (degrees) of the exit surface's
  /// normal gets a node where a ball of its radius touches the part's end (default 40, range
  /// [0, 90]; 0 = off; not in the paper, see Filters/Core/Skeleton/SkeletonLeafExtension.h).
  vtkSetClampMacro(MaximumExitAngle, double, 0.0, 90.0);
  vtkGetMacro(MaximumExitAngle, double);
  ///@}

  ///@{
  /// Step 7b (ours): a leaf whose smoothed bone leaves the volume within MaximumExitAngle of
  /// the exit surface's normal gets one more node this share of the way to that surface, in
  /// its bone (default 1 = at the surface, range [0, 1]; 0 = off; the node's Radius is its
  /// leaf's; Filters/Core/Skeleton/SkeletonLeafExtension.h).
  vtkSetClampMacro(TipReach, double, 0.0, 1.0);
  vtkGetMacro(TipReach, double);
  ///@}

  ///@{
  /// Projected points farther than this many radii from the skeleton are uncovered, and every
  /// group of them holding 1 % of the points gets a branch (default 3, range [0, 1e6]; 0 = off;
  /// not in the paper, see Filters/Core/Skeleton/SkeletonCoverage.h).
  vtkSetClampMacro(UncoveredFactor, double, 0.0, 1e6);
  vtkGetMacro(UncoveredFactor, double);
  ///@}

  ///@{
  /// A group of uncovered points holding less than 1 % of the points still gets a branch when
  /// its points lie along a line (a tail, a finger) and its tip lies at least this many of its
  /// radii from the skeleton (default 6, range [0, 1e6]; 0 = off; not in the paper, see
  /// Filters/Core/Skeleton/SkeletonCoverage.h).
  vtkSetClampMacro(ThinLimbFactor, double, 0.0, 1e6);
  vtkGetMacro(ThinLimbFactor, double);
  ///@}

  ///@{
  /// Link every segment of the input's `SDFSegment` (vtkSDFGMMPartition) to one bone (default
  /// on); off, or without that array, each face is linked to its nearest node alone.
  vtkSetMacro(LinkBySegment, vtkTypeBool);
  vtkGetMacro(LinkBySegment, vtkTypeBool);
  vtkBooleanMacro(LinkBySegment, vtkTypeBool);
  ///@}

  ///@{
  /// With LinkBySegment: a segment takes a bone no other segment has taken when that bone holds
  /// at least this share of its area under the nearest-node link (larger overlaps first), else
  /// the bone holding most of it (default 0.15, range [0, 1]; above 0.5 every segment takes the
  /// bone holding most of it; see Filters/Core/Skeleton/Skeleton.h).
  vtkSetClampMacro(OwnBoneShare, double, 0.0, 1.0);
  vtkGetMacro(OwnBoneShare, double);
  ///@}

  ///@{
  /// With LinkBySegment: a segment holding 3 % of the projected points that got no bone of its
  /// own, and whose farthest projected point lies more than this many radii from the skeleton,
  /// gets a branch into it (step 6; default 2, range [0, 1e6]; 0 = off; not in the paper, see
  /// Filters/Core/Skeleton/Skeleton.h).
  vtkSetClampMacro(PartUncoveredFactor, double, 0.0, 1e6);
  vtkGetMacro(PartUncoveredFactor, double);
  ///@}

  ///@{
  /// Step 7 (ours): every bone's nodes (leaves and junctions too) are moved onto a local
  /// quadratic fit (linear at the ends) along the bone whose Gaussian weights have this standard deviation, in node radii, held back where
  /// a smoothed edge would leave the volume (default 1, range [0, 100]; 0 = off, the paper's
  /// nodes; Filters/Core/Skeleton/SkeletonSmoothing.h).
  vtkSetClampMacro(BoneSmoothing, double, 0.0, 100.0);
  vtkGetMacro(BoneSmoothing, double);
  ///@}

  ///@{
  /// Seed of the surface sampling (default 0x5DF5EED = 98524909; fixed, so the same input
  /// gives the same skeleton).
  vtkSetMacro(Seed, int);
  vtkGetMacro(Seed, int);
  ///@}

  /// The skeleton (output port 0).
  vtkPolyData* GetSkeleton() { return this->GetOutput(0); }
  /// The input surface with SkeletonNodeId and SkeletonBoneId (output port 1).
  vtkPolyData* GetSurface() { return this->GetOutput(1); }
  /// The projected point cloud P (output port 2).
  vtkPolyData* GetProjectedPoints() { return this->GetOutput(2); }

protected:
  vtkSDFSkeleton();
  ~vtkSDFSkeleton() override;

  bool ExecuteSurface(const shapediameter::adapter::SurfaceRequest& request) override;
  /// The selected SDF array, its fallbacks SDFSmoothed and SDF, SDFSegment and SDFCluster.
  std::vector<std::string> CellArraysRead() override;
  /// Distributed runs: every process triangulates its own cells and sends process 0 only
  /// what the skeleton reads (Filters/Core/Skeleton/DistributedSkeleton.h); no halo.
  bool CanRunWithHalo() const override { return true; }
  bool NeedsNoHalo() const override { return true; }
  double HaloRadius(vtkPolyData*, const shapediameter::ProcessGroup&) override { return 0.0; }


  int NumberOfSamples;
  int NumberOfIterations;
  double ConfidenceThreshold;
  double MinimumConfidentShare;
  double SpacingFactor;
  double MaximumExitAngle;
  double TipReach;
  double UncoveredFactor;
  double ThinLimbFactor;
  vtkTypeBool LinkBySegment = 1;
  double OwnBoneShare;
  double PartUncoveredFactor;
  double BoneSmoothing;
  int Seed;

private:
  vtkSDFSkeleton(const vtkSDFSkeleton&) = delete;
  void operator=(const vtkSDFSkeleton&) = delete;
};

#endif
