// SPDX-License-Identifier: BSD-3-Clause
#include "ArticulatedFigure.h"
#include "FilterTestUtilities.h"
#include "vtkSDFBilateralSmooth.h"
#include "vtkShapeDiameterFilter.h"

#include "vtkAppendPolyData.h"
#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkLineSource.h"
#include "vtkNew.h"
#include "vtkSmartPointer.h"
#include "vtkPolyData.h"
#include "vtkSphereSource.h"
#include "vtkStringArray.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

using shapediameter::testing::MessageRecorder;
using shapediameter::testing::ToPolyData;
namespace figure = shapediameter::testing;

namespace
{
vtkSmartPointer<vtkPolyData> SphereWithField(const char* name, double (*field)(vtkIdType))
{
  vtkNew<vtkSphereSource> source;
  source->SetThetaResolution(32);
  source->SetPhiResolution(32);
  source->Update();
  auto mesh = vtkSmartPointer<vtkPolyData>::New();
  mesh->DeepCopy(source->GetOutput());
  vtkNew<vtkDoubleArray> array;
  array->SetName(name);
  array->SetNumberOfTuples(mesh->GetNumberOfCells());
  for (vtkIdType c = 0; c < mesh->GetNumberOfCells(); ++c)
  {
    array->SetValue(c, field(c));
  }
  mesh->GetCellData()->AddArray(array);
  return mesh;
}

std::vector<double> Values(vtkPolyData* mesh, const char* name)
{
  std::vector<double> values;
  if (vtkDataArray* array = mesh->GetCellData()->GetArray(name))
  {
    for (vtkIdType i = 0; i < array->GetNumberOfTuples(); ++i)
    {
      values.push_back(array->GetComponent(i, 0));
    }
  }
  return values;
}

struct SmoothRun
{
  vtkSmartPointer<vtkPolyData> Output;
  int Errors = 0;
};

SmoothRun Smooth(vtkPolyData* input, int iterations = 3, int threads = 0, const char* array = nullptr)
{
  vtkNew<vtkSDFBilateralSmooth> filter;
  vtkNew<MessageRecorder> recorder;
  recorder->Observe(filter);
  filter->SetInputData(input);
  filter->SetNumberOfIterations(iterations);
  filter->SetNumberOfThreads(threads);
  if (array)
  {
    filter->SetInputArrayToProcess(0, 0, 0, vtkDataObject::FIELD_ASSOCIATION_CELLS, array);
  }
  filter->Update();
  return { filter->GetOutput(), recorder->Errors };
}
} // namespace

TEST(SDFBilateralSmooth, ConstantFieldStaysConstantAndNormalisesToZero)
{
  const SmoothRun run = Smooth(SphereWithField("SDF", [](vtkIdType) { return 0.7; }));
  EXPECT_EQ(run.Errors, 0);
  for (double v : Values(run.Output, "SDFSmoothed"))
  {
    ASSERT_EQ(v, 0.7);
  }
  for (double v : Values(run.Output, "SDFNormalized"))
  {
    ASSERT_EQ(v, 0.0);
  }
}

TEST(SDFBilateralSmooth, NormalisedRangeIsZeroToOneAndOtherArraysSurvive)
{
  vtkSmartPointer<vtkPolyData> mesh = SphereWithField("MyField", [](vtkIdType c) { return 1.0 + (c % 97) * 0.01; });
  const SmoothRun run = Smooth(mesh, 3, 0, "MyField");
  EXPECT_EQ(run.Errors, 0);
  const std::vector<double> nsdf = Values(run.Output, "SDFNormalized");
  ASSERT_EQ(nsdf.size(), static_cast<std::size_t>(mesh->GetNumberOfCells()));
  EXPECT_DOUBLE_EQ(*std::min_element(nsdf.begin(), nsdf.end()), 0.0);
  EXPECT_DOUBLE_EQ(*std::max_element(nsdf.begin(), nsdf.end()), 1.0);
  EXPECT_NE(run.Output->GetCellData()->GetArray("MyField"), nullptr);
}

TEST(SDFBilateralSmooth, LinesKeepTheirValueAndGetZero)
{
  vtkNew<vtkLineSource> line;
  line->SetPoint1(3, 3, 3);
  line->Update();
  vtkNew<vtkPolyData> lineData;
  lineData->DeepCopy(line->GetOutput());
  vtkNew<vtkDoubleArray> lineField;
  lineField->SetName("SDF");
  lineField->SetNumberOfTuples(1);
  lineField->SetValue(0, -50.0); // must not become the normalisation minimum
  lineData->GetCellData()->AddArray(lineField);
  vtkNew<vtkAppendPolyData> append;
  append->AddInputData(lineData);
  append->AddInputData(SphereWithField("SDF", [](vtkIdType c) { return 1.0 + (c % 5); }));
  append->Update();
  const SmoothRun run = Smooth(append->GetOutput());
  const std::vector<double> smoothed = Values(run.Output, "SDFSmoothed");
  const std::vector<double> nsdf = Values(run.Output, "SDFNormalized");
  EXPECT_EQ(smoothed[0], -50.0);
  EXPECT_EQ(nsdf[0], 0.0);
  EXPECT_DOUBLE_EQ(*std::max_element(nsdf.begin() + 1, nsdf.end()), 1.0);
  EXPECT_GE(*std::min_element(nsdf.begin() + 1, nsdf.end()), 0.0);
}

TEST(SDFBilateralSmooth, BadArraysAreErrorsWithPassThrough)
{
  vtkSmartPointer<vtkPolyData> mesh = SphereWithField("Other", [](vtkIdType) { return 1.0; });
  SmoothRun missing = Smooth(mesh);
  EXPECT_EQ(missing.Errors, 1);
  EXPECT_EQ(missing.Output->GetCellData()->GetArray("SDFSmoothed"), nullptr);
  EXPECT_EQ(missing.Output->GetNumberOfCells(), mesh->GetNumberOfCells());

  vtkNew<vtkStringArray> text;
  text->SetName("SDF");
  text->SetNumberOfValues(mesh->GetNumberOfCells());
  mesh->GetCellData()->AddArray(text);
  EXPECT_EQ(Smooth(mesh).Errors, 1);

  vtkNew<vtkDoubleArray> vectors;
  vectors->SetName("Vec");
  vectors->SetNumberOfComponents(3);
  vectors->SetNumberOfTuples(mesh->GetNumberOfCells());
  vectors->FillValue(1.0);
  mesh->GetCellData()->AddArray(vectors);
  EXPECT_EQ(Smooth(mesh, 3, 0, "Vec").Errors, 1);

  vtkSmartPointer<vtkPolyData> nan = SphereWithField("SDF", [](vtkIdType c) { return c == 7 ? std::nan("") : 1.0; });
  const SmoothRun bad = Smooth(nan);
  EXPECT_EQ(bad.Errors, 1);
  EXPECT_EQ(bad.Output->GetCellData()->GetArray("SDFNormalized"), nullptr);
}

TEST(SDFBilateralSmooth, AGivenNormalizationRangeIsUsedAndReported)
{
  // Values 1..2 over the faces; own range [1, 2], reported as field data.
  vtkSmartPointer<vtkPolyData> mesh =
    SphereWithField("SDF", [](vtkIdType c) { return 1.0 + static_cast<double>(c % 11) / 10.0; });
  auto run = [&](double low, double high, int& errors) {
    vtkNew<vtkSDFBilateralSmooth> filter;
    vtkNew<MessageRecorder> recorder;
    recorder->Observe(filter);
    filter->SetInputData(mesh);
    filter->SetNumberOfIterations(0);
    filter->SetNormalizationRange(low, high);
    filter->Update();
    errors = recorder->Errors;
    return vtkSmartPointer<vtkPolyData>(filter->GetOutput());
  };
  int errors = -1;
  vtkSmartPointer<vtkPolyData> own = run(0.0, 0.0, errors);
  EXPECT_EQ(errors, 0);
  vtkDataArray* ownRange = own->GetFieldData()->GetArray("SDFNormalizationRange");
  ASSERT_NE(ownRange, nullptr);
  EXPECT_EQ(ownRange->GetNumberOfTuples(), 2);
  EXPECT_EQ(ownRange->GetComponent(0, 0), 1.0);
  EXPECT_EQ(ownRange->GetComponent(1, 0), 2.0);
  // A family range [0, 4]: the value 2 maps to the fraction 1/2, not to 1.
  vtkSmartPointer<vtkPolyData> family = run(0.0, 4.0, errors);
  EXPECT_EQ(errors, 0);
  EXPECT_EQ(family->GetFieldData()->GetArray("SDFNormalizationRange")->GetComponent(1, 0), 4.0);
  const std::vector<double> sdf = Values(family, "SDF");
  const std::vector<double> nsdf = Values(family, "SDFNormalized");
  for (std::size_t f = 0; f < sdf.size(); ++f)
  {
    ASSERT_NEAR(nsdf[f], std::log1p(4.0 * sdf[f] / 4.0) / std::log1p(4.0), 1e-12);
  }
  // max <= min: automatic, the same as the default.
  EXPECT_EQ(Values(run(3.0, 1.0, errors), "SDFNormalized"), Values(own, "SDFNormalized"));
  EXPECT_EQ(errors, 0);
  // A NaN or infinite bound: an error and a pass-through copy.
  for (const auto& [low, high] : { std::make_pair(std::nan(""), 1.0), std::make_pair(0.0, std::numeric_limits<double>::infinity()) })
  {
    vtkSmartPointer<vtkPolyData> bad = run(low, high, errors);
    EXPECT_EQ(errors, 1);
    EXPECT_EQ(bad->GetCellData()->GetArray("SDFNormalized"), nullptr);
    EXPECT_EQ(bad->GetNumberOfCells(), mesh->GetNumberOfCells());
  }
}

TEST(SDFBilateralSmooth, ThreadCountDoesNotChangeTheResult)
{
  vtkSmartPointer<vtkPolyData> mesh = SphereWithField("SDF", [](vtkIdType c) { return std::sin(0.37 * c) + 2; });
  EXPECT_TRUE(Values(Smooth(mesh, 3, 1).Output, "SDFSmoothed") == Values(Smooth(mesh, 3, 2).Output, "SDFSmoothed"));
}

TEST(SDFBilateralSmooth, SmoothingMakesTheFigureMorePoseInvariant)
{
  // The non-rigid pose (joints bent over four radii and stretched): the SDF of the two poses
  // differs where the geometry does and wherever rays see moved parts.
  const figure::ArticulatedFigureTemplate figureTemplate;
  const figure::ArticulatedFigure rest = figureTemplate.Rest();
  const figure::ArticulatedFigure posed = figureTemplate.NonRigidPose(figure::FigurePose{ 0.9, -0.6, 0.5, -0.4 });

  // Faces away from the joints: every edge keeps its length (the torso that stays still and
  // the limbs beyond the joint, which move rigidly).
  std::vector<char> rigid(static_cast<std::size_t>(rest.Triangles.rows()), 1);
  for (Eigen::Index t = 0; t < rest.Triangles.rows(); ++t)
  {
    for (int corner = 0; corner < 3; ++corner)
    {
      const Eigen::Index a = rest.Triangles(t, corner);
      const Eigen::Index b = rest.Triangles(t, (corner + 1) % 3);
      const double restLength = (rest.Points.row(a) - rest.Points.row(b)).norm();
      if (std::abs((posed.Points.row(a) - posed.Points.row(b)).norm() - restLength) > 1e-9 * restLength)
      {
        rigid[static_cast<std::size_t>(t)] = 0;
      }
    }
  }
  const auto rigidCount = static_cast<std::size_t>(std::count(rigid.begin(), rigid.end(), 1));
  EXPECT_GT(rigidCount, rigid.size() / 2);
  EXPECT_LT(rigidCount, rigid.size());

  // Both poses are normalised over one range, the family's (the widest of their own ranges):
  // with each pose's own min and max, a single face's extreme would decide the comparison
  // (measured on the rigid Pose() with HitRule 0: the smoothed maximum moves 2.8 %, its p99
  // 0.04 %, and the mean |delta nsdf| below is then 0.0135 smoothed vs 0.0031 raw).
  auto nsdfPair = [](const figure::ArticulatedFigure& a, const figure::ArticulatedFigure& b, int iterations) {
    std::vector<vtkSmartPointer<vtkSDFBilateralSmooth>> smooths;
    double family[2] = { std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity() };
    for (const figure::ArticulatedFigure* shape : { &a, &b })
    {
      vtkNew<vtkShapeDiameterFilter> sdf;
      sdf->SetInputData(ToPolyData(shape->Points, shape->Triangles));
      auto smooth = vtkSmartPointer<vtkSDFBilateralSmooth>::New();
      smooth->SetInputConnection(sdf->GetOutputPort());
      smooth->SetNumberOfIterations(iterations);
      smooth->Update();
      vtkDataArray* own = smooth->GetOutput()->GetFieldData()->GetArray("SDFNormalizationRange");
      family[0] = std::min(family[0], own->GetComponent(0, 0));
      family[1] = std::max(family[1], own->GetComponent(1, 0));
      smooths.push_back(smooth);
    }
    std::vector<std::vector<double>> values;
    for (const auto& smooth : smooths)
    {
      smooth->SetNormalizationRange(family);
      smooth->Update();
      values.push_back(Values(smooth->GetOutput(), "SDFNormalized"));
    }
    return values;
  };
  auto meanDifference = [&](const std::vector<double>& a, const std::vector<double>& b) {
    double sum = 0.0;
    std::size_t count = 0;
    for (std::size_t f = 0; f < a.size(); ++f)
    {
      if (rigid[f])
      {
        sum += std::abs(a[f] - b[f]);
        ++count;
      }
    }
    return sum / static_cast<double>(count);
  };
  const auto raw = nsdfPair(rest, posed, 0);
  const auto smoothed = nsdfPair(rest, posed, 3);
  const double before = meanDifference(raw[0], raw[1]);
  const double after = meanDifference(smoothed[0], smoothed[1]);
  std::printf("mean |delta nsdf| away from joints: raw %.5f, smoothed %.5f\n", before, after);
  // Measured on the non-rigid pose: raw 0.00258, smoothed 0.00187 (equal, and red, with the
  // smoothing's weights set to 0).
  EXPECT_LT(after, before);
}
