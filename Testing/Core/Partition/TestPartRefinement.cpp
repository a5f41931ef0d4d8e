// SPDX-License-Identifier: BSD-3-Clause
// The fine level (PartRefinement.h): a part with two thickness levels of its own is cut in two
// along the level change, a part of one thickness stays whole, small parts are not refined,
// the numbering follows band then mean, and threads do not change the result.
#include "Partition/PartRefinement.h"

#include "Partition/Partition.h"
#include "TestShapes.h"

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <vector>

namespace
{

using namespace shapediameter;

Eigen::Vector3d Centre(const testshapes::TestMesh& mesh, Eigen::Index face)
{
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  for (int corner = 0; corner < 3; ++corner)
  {
    centre += mesh.Points.row(mesh.Triangles(face, corner)).transpose() / 3.0;
  }
  return centre;
}

/// The refinement switched on (it is off by default).
PartRefinementOptions Enabled()
{
  PartRefinementOptions options;
  options.Enabled = true;
  return options;
}

/// A capsule along z (half-length 1, radius 0.3) with values given by the face centre's z.
struct Capsule
{
  testshapes::TestMesh Mesh = testshapes::MakeCapsule(0.3, 1.0, 24, 6, 16);
  FaceGraph Graph;
  Eigen::VectorXd Values;

  template <typename ValueOfZ>
  explicit Capsule(ValueOfZ valueOfZ)
    : Graph(BuildFaceGraph(Mesh.Points, Mesh.Triangles))
  {
    Values.resize(Mesh.Triangles.rows());
    for (Eigen::Index f = 0; f < Values.size(); ++f)
    {
      Values[f] = valueOfZ(Centre(Mesh, f).z());
    }
  }

  /// One band and one segment over the whole capsule.
  PartRefinementResult RefineAsOnePart(const PartRefinementOptions& options = Enabled(),
    const ParallelFor& parallelFor = SerialFor) const
  {
    const DualGraphView view = MakeDualGraphView(Graph);
    const std::vector<int> bands(Graph.FaceCount(), 0);
    const ConnectedSegments segments = FindConnectedSegments(view, bands, Graph.Areas);
    return RefineParts(view, Values, bands, segments, options, parallelFor);
  }
};

double Ripple(double z)
{
  return 0.01 * std::sin(9.0 * z);
}

TEST(PartRefinement, APartWithTwoLevelsOfItsOwnIsCutAtTheLevelChange)
{
  // Thin tip below z = -0.2, thicker above; the whole value range is [0, 1] (two far faces
  // stretch it), so the part's own range is a fifth of it.
  const Capsule shape([](double z) { return (z < -0.2 ? 0.30 : 0.45) + Ripple(z); });
  Capsule wide = shape;
  wide.Values[0] = 0.0;
  wide.Values[1] = 1.0;
  const PartRefinementResult result = wide.RefineAsOnePart();
  ASSERT_EQ(result.LabelBand.size(), 2u);
  EXPECT_EQ(result.RefinedParts, 1);
  EXPECT_GT(result.LabelMean[0], result.LabelMean[1]); // thicker first within the band
  std::size_t wrong = 0, counted = 0;
  for (Eigen::Index f = 2; f < shape.Values.size(); ++f)
  {
    const double z = Centre(shape.Mesh, f).z();
    if (std::abs(z + 0.2) < 0.1)
    {
      continue; // the cut may run anywhere along the step's ring of faces
    }
    ++counted;
    wrong += result.Labels[static_cast<std::size_t>(f)] != (z < -0.2 ? 1 : 0);
  }
  EXPECT_LT(static_cast<double>(wrong) / static_cast<double>(counted), 0.01);
}

TEST(PartRefinement, APartOfOneThicknessStaysWhole)
{
  // The same ripple as above, but one level: the ripple is narrower than the kernel, which
  // keeps its width in units of the whole range.
  Capsule shape([](double z) { return 0.45 + Ripple(z); });
  shape.Values[0] = 0.0;
  shape.Values[1] = 1.0;
  const PartRefinementResult result = shape.RefineAsOnePart();
  EXPECT_EQ(result.RefinedParts, 0);
  EXPECT_EQ(result.LabelBand.size(), 1u);
  EXPECT_EQ(std::set<int>(result.Labels.begin(), result.Labels.end()), std::set<int>{ 0 });
}

TEST(PartRefinement, SmallPartsAndTheSwitchOffKeepTheBands)
{
  Capsule shape([](double z) { return (z < -0.2 ? 0.30 : 0.45) + Ripple(z); });
  shape.Values[0] = 0.0;
  shape.Values[1] = 1.0;
  PartRefinementOptions options = Enabled();
  options.MinimumAreaShare = 1.0; // only a part covering everything qualifies
  EXPECT_EQ(shape.RefineAsOnePart(options).RefinedParts, 1);
  std::vector<int> halves(shape.Graph.FaceCount());
  for (std::size_t f = 0; f < halves.size(); ++f)
  {
    halves[f] = Centre(shape.Mesh, static_cast<Eigen::Index>(f)).z() > 0.5 ? 0 : 1;
  }
  const DualGraphView view = MakeDualGraphView(shape.Graph);
  const ConnectedSegments segments = FindConnectedSegments(view, halves, shape.Graph.Areas);
  options.MinimumAreaShare = 0.9; // neither part
  const PartRefinementResult kept = RefineParts(view, shape.Values, halves, segments, options);
  EXPECT_EQ(kept.RefinedParts, 0);
  EXPECT_EQ(kept.Labels, halves);
  options = Enabled();
  options.Enabled = false;
  EXPECT_EQ(shape.RefineAsOnePart(options).LabelBand.size(), 1u);
}

TEST(PartRefinement, ThreadsDoNotChangeTheLabels)
{
  Capsule shape([](double z) { return (z < -0.2 ? 0.30 : 0.45) + Ripple(z); });
  shape.Values[0] = 0.0;
  shape.Values[1] = 1.0;
  EXPECT_EQ(shape.RefineAsOnePart(Enabled(), SerialFor).Labels, shape.RefineAsOnePart(Enabled(), ThreadedFor(3)).Labels);
}

TEST(PartRefinement, FineLabelsRefineTheBandsInBandOrder)
{
  // Through the entry point: two bands (thick top, thin bottom), the thin band with a step
  // of its own; every fine label lies in one band and the labels are numbered by band.
  const Capsule shape([](double z) { return z > 0.0 ? 0.85 : (z < -0.6 ? 0.10 : 0.22) + Ripple(z); });
  PartitionOptions options;
  options.Refinement.Enabled = true;
  const PartitionResult result = PartitionBySDF(shape.Mesh.Points, shape.Mesh.Triangles, shape.Values, options);
  ASSERT_EQ(result.Labels.size(), result.Bands.size());
  for (std::size_t f = 0; f < result.Labels.size(); ++f)
  {
    ASSERT_EQ(result.LabelBands[static_cast<std::size_t>(result.Labels[f])], result.Bands[f]);
  }
  for (std::size_t label = 1; label < result.LabelBands.size(); ++label)
  {
    EXPECT_LE(result.LabelBands[label - 1], result.LabelBands[label]);
  }
  EXPECT_GE(result.LabelBands.size(), static_cast<std::size_t>(result.Model.ComponentCount()));
}

TEST(PartRefinement, BadOptionsThrow)
{
  PartRefinementOptions options;
  options.MinimumAreaShare = -0.1;
  EXPECT_THROW(ValidatePartRefinementOptions(options), Error);
  options = {};
  options.Modes.MaximumModes = 0;
  EXPECT_THROW(ValidatePartRefinementOptions(options), Error);
}

} // namespace
