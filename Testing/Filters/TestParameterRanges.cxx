// SPDX-License-Identifier: BSD-3-Clause
// Every clamped parameter of the filters clamps to the range the core checks: the filter's
// vtkSetClampMacro repeats the core's Range constant as literal numbers (VTK's wrapping needs
// them, and the public filter headers do not include the core), so this test keeps the two
// equal. Testing/Python/test_xml_matches_cpp.py does the same for the ParaView XML.
#include "Partition/Partition.h"
#include "RayCasting/ConeSampling.h"
#include "SDF/ShapeDiameter.h"
#include "Skeleton/Skeleton.h"
#include "Smoothing/BilateralSmoothing.h"
#include "Smoothing/Normalization.h"
#include "vtkSDFBilateralSmooth.h"
#include "vtkSDFGMMPartition.h"
#include "vtkSDFSkeleton.h"
#include "vtkShapeDiameterFilter.h"

#include "vtkNew.h"

#include <gtest/gtest.h>

#include <cmath>

namespace
{

using shapediameter::Range;

#define EXPECT_CLAMP_EQ(filter, Name, range)                                                        \
  do                                                                                              \
  {                                                                                               \
    EXPECT_EQ(filter->Get##Name##MinValue(), (range).Low) << #Name " minimum";                    \
    EXPECT_EQ(filter->Get##Name##MaxValue(), (range).High) << #Name " maximum";                   \
  } while (false)

TEST(ParameterRanges, ShapeDiameterFilterClampsToTheCoreRanges)
{
  vtkNew<vtkShapeDiameterFilter> filter;
  EXPECT_CLAMP_EQ(filter, NumberOfRays, shapediameter::NumberOfRaysRange);
  EXPECT_CLAMP_EQ(filter, ConeAngle, shapediameter::ConeAngleRange);
  EXPECT_CLAMP_EQ(filter, Tolerance, shapediameter::ToleranceRange);
  // The enumerations clamp to their first and last value.
  EXPECT_EQ(filter->GetHitRuleMinValue(), vtkShapeDiameterFilter::FIRST_HIT_LEAVING);
  EXPECT_EQ(filter->GetHitRuleMaxValue(), vtkShapeDiameterFilter::SKIP_SAME_FACING);
  EXPECT_EQ(filter->GetModeMinValue(), vtkShapeDiameterFilter::EXACT);
  EXPECT_EQ(filter->GetModeMaxValue(), vtkShapeDiameterFilter::ADAPTIVE);
  // Closed ranges in the core, so the clamp's ends are valid core values.
  EXPECT_FALSE(shapediameter::ConeAngleRange.LowExclusive);
  EXPECT_FALSE(shapediameter::ToleranceRange.LowExclusive);
}

TEST(ParameterRanges, GMMPartitionClampsToTheCoreRanges)
{
  vtkNew<vtkSDFGMMPartition> filter;
  EXPECT_CLAMP_EQ(filter, NumberOfClusters, shapediameter::NumberOfClustersRange);
  EXPECT_CLAMP_EQ(filter, MaximumClusters, shapediameter::MaximumClustersRange);
  EXPECT_CLAMP_EQ(filter, Lambda, shapediameter::LambdaRange);
  EXPECT_CLAMP_EQ(filter, Epsilon, shapediameter::EpsilonRange);
  EXPECT_CLAMP_EQ(filter, ConvexityFactor, shapediameter::ConvexityFactorRange);
  EXPECT_CLAMP_EQ(filter, Restarts, shapediameter::RestartsRange);
  EXPECT_CLAMP_EQ(filter, MaximumIterations, shapediameter::MaximumIterationsRange);
  EXPECT_CLAMP_EQ(filter, HistogramBins, shapediameter::HistogramBinsRange);
  EXPECT_CLAMP_EQ(filter, ModeBandwidth, shapediameter::ModeBandwidthRange);
  EXPECT_CLAMP_EQ(filter, ModeProminence, shapediameter::ModeProminenceRange);
  EXPECT_CLAMP_EQ(filter, ModeValleyDepth, shapediameter::ModeValleyDepthRange);
  EXPECT_CLAMP_EQ(filter, RefinementMinimumArea, shapediameter::RefinementMinimumAreaRange);
  EXPECT_EQ(filter->GetClusterModelMinValue(), vtkSDFGMMPartition::EM);
  EXPECT_EQ(filter->GetClusterModelMaxValue(), vtkSDFGMMPartition::DENSITY_MODES);
}

TEST(ParameterRanges, BilateralSmoothClampsToTheCoreRanges)
{
  vtkNew<vtkSDFBilateralSmooth> filter;
  EXPECT_CLAMP_EQ(filter, NumberOfIterations, shapediameter::SmoothingIterationsRange);
  EXPECT_CLAMP_EQ(filter, SpatialSigma, shapediameter::SpatialSigmaRange);
  EXPECT_CLAMP_EQ(filter, NeighborhoodRadius, shapediameter::NeighborhoodRadiusRange);
  EXPECT_CLAMP_EQ(filter, RangeThreshold, shapediameter::RangeThresholdRange);
  EXPECT_CLAMP_EQ(filter, Alpha, shapediameter::AlphaRange);
  EXPECT_FALSE(shapediameter::SpatialSigmaRange.LowExclusive);
  EXPECT_FALSE(shapediameter::AlphaRange.LowExclusive);
}

TEST(ParameterRanges, SkeletonClampsToTheCoreRanges)
{
  vtkNew<vtkSDFSkeleton> filter;
  EXPECT_CLAMP_EQ(filter, NumberOfSamples, shapediameter::NumberOfSamplesRange);
  EXPECT_CLAMP_EQ(filter, NumberOfIterations, shapediameter::SkeletonIterationsRange);
  EXPECT_CLAMP_EQ(filter, ConfidenceThreshold, shapediameter::ConfidenceThresholdRange);
  EXPECT_CLAMP_EQ(filter, MinimumConfidentShare, shapediameter::MinimumConfidentShareRange);
  EXPECT_CLAMP_EQ(filter, SpacingFactor, shapediameter::ThinningSpacingFactorRange);
  EXPECT_CLAMP_EQ(filter, MaximumExitAngle, shapediameter::MaximumExitAngleRange);
  EXPECT_CLAMP_EQ(filter, TipReach, shapediameter::TipReachRange);
  EXPECT_CLAMP_EQ(filter, UncoveredFactor, shapediameter::UncoveredFactorRange);
  EXPECT_CLAMP_EQ(filter, ThinLimbFactor, shapediameter::ThinLimbFactorRange);
  EXPECT_CLAMP_EQ(filter, OwnBoneShare, shapediameter::OwnBoneShareRange);
  EXPECT_CLAMP_EQ(filter, PartUncoveredFactor, shapediameter::PartUncoveredFactorRange);
  EXPECT_CLAMP_EQ(filter, BoneSmoothing, shapediameter::BoneSmoothingRange);
}

/// The ends of every clamp are accepted by the core: a filter at its clamp limits runs.
TEST(ParameterRanges, TheClampEndsAreValidCoreOptions)
{
  for (const bool high : { false, true })
  {
    shapediameter::ShapeDiameterOptions sdf;
    sdf.NumberOfRays = high ? shapediameter::NumberOfRaysRange.High : shapediameter::NumberOfRaysRange.Low;
    sdf.ConeAngle = high ? shapediameter::ConeAngleRange.High : shapediameter::ConeAngleRange.Low;
    sdf.Tolerance = high ? shapediameter::ToleranceRange.High : shapediameter::ToleranceRange.Low;
    EXPECT_NO_THROW(shapediameter::CheckShapeDiameterOptions(sdf)) << high;
    EXPECT_NO_THROW(shapediameter::MakeConePattern(sdf.NumberOfRays, sdf.ConeAngle)) << high;

    shapediameter::PartitionOptions partition;
    const auto end = [high](const auto& range) { return high ? range.High : range.Low; };
    partition.NumberOfClusters = end(shapediameter::NumberOfClustersRange);
    partition.MaximumClusters = end(shapediameter::MaximumClustersRange);
    partition.HistogramBins = end(shapediameter::HistogramBinsRange);
    partition.Mixture.Restarts = end(shapediameter::RestartsRange);
    partition.Mixture.MaximumIterations = end(shapediameter::MaximumIterationsRange);
    partition.Modes.Bandwidth = end(shapediameter::ModeBandwidthRange);
    partition.Modes.MinimumProminence = end(shapediameter::ModeProminenceRange);
    partition.Modes.MinimumValleyDepth = end(shapediameter::ModeValleyDepthRange);
    partition.Energy.Lambda = end(shapediameter::LambdaRange);
    partition.Energy.Epsilon = end(shapediameter::EpsilonRange);
    partition.Energy.ConvexityFactor = end(shapediameter::ConvexityFactorRange);
    partition.Refinement.MinimumAreaShare = end(shapediameter::RefinementMinimumAreaRange);
    EXPECT_NO_THROW(shapediameter::ValidatePartitionOptions(partition)) << high;

    // The smoothing's options are checked by SmoothBilateral (no separate validator): an empty
    // mesh runs the checks and nothing else.
    shapediameter::BilateralSmoothingOptions smoothing;
    smoothing.NumberOfIterations = end(shapediameter::SmoothingIterationsRange);
    smoothing.SpatialSigma = end(shapediameter::SpatialSigmaRange);
    smoothing.NeighborhoodRadius = end(shapediameter::NeighborhoodRadiusRange);
    smoothing.RangeThreshold = end(shapediameter::RangeThresholdRange);
    const shapediameter::FaceGraph empty =
      shapediameter::BuildFaceGraph(shapediameter::PointMatrix(0, 3), shapediameter::TriangleMatrix(0, 3));
    EXPECT_NO_THROW(shapediameter::SmoothBilateral(empty, {}, smoothing)) << high;
    shapediameter::NormalizationOptions normalization;
    normalization.Alpha = end(shapediameter::AlphaRange);
    EXPECT_NO_THROW(shapediameter::NormalizeLogarithmic({ 1.0, 2.0 }, normalization)) << high;
    EXPECT_TRUE(shapediameter::NormalizeLogarithmicAlphaRange.Contains(normalization.Alpha)) << high;

    shapediameter::SkeletonOptions skeleton;
    skeleton.Sampling.NumberOfSamples = static_cast<std::size_t>(end(shapediameter::NumberOfSamplesRange));
    skeleton.Thinning.NumberOfIterations = end(shapediameter::SkeletonIterationsRange);
    skeleton.Thinning.ConfidenceThreshold = end(shapediameter::ConfidenceThresholdRange);
    skeleton.Thinning.MinimumConfidentShare = end(shapediameter::MinimumConfidentShareRange);
    skeleton.Thinning.SpacingFactor = end(shapediameter::ThinningSpacingFactorRange);
    skeleton.LeafExtension.MaximumExitAngle = end(shapediameter::MaximumExitAngleRange);
    skeleton.LeafExtension.TipReach = end(shapediameter::TipReachRange);
    skeleton.Coverage.UncoveredFactor = end(shapediameter::UncoveredFactorRange);
    skeleton.Coverage.ThinLimbFactor = end(shapediameter::ThinLimbFactorRange);
    skeleton.Coverage.ThinLimbLinearity = end(shapediameter::ThinLimbLinearityRange);
    skeleton.Coverage.ThinLimbMinimumShare = end(shapediameter::ThinLimbMinimumShareRange);
    skeleton.OwnBoneShare = end(shapediameter::OwnBoneShareRange);
    skeleton.Coverage.PartUncoveredFactor = end(shapediameter::PartUncoveredFactorRange);
    skeleton.Smoothing.Bandwidth = end(shapediameter::BoneSmoothingRange);
    EXPECT_NO_THROW(shapediameter::ValidateSkeletonOptions(skeleton)) << high;
  }
}

TEST(ParameterRanges, CheckRangeNamesTheValueAndTheRange)
{
  try
  {
    shapediameter::CheckRange(0.0005, shapediameter::ToleranceRange, "shape diameter: Tolerance");
    FAIL() << "no error";
  }
  catch (const shapediameter::Error& error)
  {
    EXPECT_STREQ(error.what(), "shape diameter: Tolerance = 0.0005 is outside [0.001, 1]");
  }
  constexpr Range<double> positive{ 0.0, 1.0, true };
  EXPECT_THROW(shapediameter::CheckRange(0.0, positive, "x"), shapediameter::Error);
  EXPECT_NO_THROW(shapediameter::CheckRange(1.0, positive, "x"));
  EXPECT_THROW(shapediameter::CheckRange(std::nan(""), positive, "x"), shapediameter::Error);
}

} // namespace
