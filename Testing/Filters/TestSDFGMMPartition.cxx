// SPDX-License-Identifier: BSD-3-Clause
#include "ArticulatedFigure.h"
#include "Mesh/FaceGraph.h"
#include "FilterTestUtilities.h"
#include "LabelMatching.h"
#include "SurfaceConversion.h"
#include "vtkSDFBilateralSmooth.h"
#include "vtkSDFGMMPartition.h"
#include "vtkShapeDiameterFilter.h"

#include "vtkAppendPolyData.h"
#include "vtkLinearSubdivisionFilter.h"
#include "vtkLoopSubdivisionFilter.h"
#include "vtkSDFOFFReader.h"
#include "vtkTriangleFilter.h"
#include "vtkCellData.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPolyData.h"
#include "vtkSphereSource.h"
#include "vtkStaticPointLocator.h"
#include "vtkTable.h"

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <map>
#include <memory>
#include <vector>

using shapediameter::testing::MessageRecorder;
using shapediameter::testing::ToPolyData;
namespace figure = shapediameter::testing;

namespace
{
std::vector<int> IntValues(vtkPolyData* mesh, const char* name)
{
  std::vector<int> values;
  if (vtkDataArray* array = mesh->GetCellData()->GetArray(name))
  {
    for (vtkIdType i = 0; i < array->GetNumberOfTuples(); ++i)
    {
      values.push_back(static_cast<int>(array->GetComponent(i, 0)));
    }
  }
  return values;
}

/// SDF -> smoothing of a triangle mesh, ready to partition; normalised over `range` when
/// given (a family's shared range), else over its own.
vtkSmartPointer<vtkPolyData> Normalized(const figure::ArticulatedFigure& shape, const double* range = nullptr)
{
  vtkNew<vtkShapeDiameterFilter> sdf;
  sdf->SetInputData(ToPolyData(shape.Points, shape.Triangles));
  vtkNew<vtkSDFBilateralSmooth> smooth;
  smooth->SetInputConnection(sdf->GetOutputPort());
  if (range)
  {
    smooth->SetNormalizationRange(range[0], range[1]);
  }
  smooth->Update();
  return smooth->GetOutput();
}

/// The [min, max] a smoothing output was normalised over.
std::array<double, 2> NormalizationRangeOf(vtkPolyData* smoothed)
{
  vtkDataArray* range = smoothed->GetFieldData()->GetArray("SDFNormalizationRange");
  return { range->GetComponent(0, 0), range->GetComponent(1, 0) };
}

vtkSmartPointer<vtkPolyData> Partition(vtkPolyData* input, vtkDataObject* model = nullptr, int k = 5,
  int clusterModel = 0)
{
  vtkNew<vtkSDFGMMPartition> partition;
  partition->SetClusterModel(clusterModel);
  partition->SetInputData(input);
  if (model)
  {
    partition->SetModelData(model);
  }
  partition->SetNumberOfClusters(k);
  partition->Update();
  return partition->GetOutput();
}

/// The most frequent cluster of the faces of one part.
int MajorityCluster(const std::vector<int>& clusters, const std::vector<int>& parts, int part)
{
  std::map<int, int> votes;
  for (std::size_t f = 0; f < clusters.size(); ++f)
  {
    if (parts[f] == part)
    {
      ++votes[clusters[f]];
    }
  }
  return std::max_element(votes.begin(), votes.end(), [](auto& a, auto& b) { return a.second < b.second; })->first;
}

class FigurePartition : public ::testing::Test
{
protected:
  static void SetUpTestSuite()
  {
    const figure::ArticulatedFigureTemplate figureTemplate;
    figure::FigurePose bent;
    bent.LeftArm = 0.9;
    bent.RightArm = -0.6;
    bent.LeftLeg = 0.5;
    bent.RightLeg = -0.4;
    Rest = new figure::ArticulatedFigure(figureTemplate.Rest());
    Bent = new figure::ArticulatedFigure(figureTemplate.Pose(bent));
    RestNormalized = Normalized(*Rest);
    BentNormalized = Normalized(*Bent);
  }
  static void TearDownTestSuite()
  {
    delete Rest;
    delete Bent;
    RestNormalized = nullptr;
    BentNormalized = nullptr;
  }
  static figure::ArticulatedFigure* Rest;
  static figure::ArticulatedFigure* Bent;
  static vtkSmartPointer<vtkPolyData> RestNormalized;
  static vtkSmartPointer<vtkPolyData> BentNormalized;
};
figure::ArticulatedFigure* FigurePartition::Rest = nullptr;
figure::ArticulatedFigure* FigurePartition::Bent = nullptr;
vtkSmartPointer<vtkPolyData> FigurePartition::RestNormalized;
vtkSmartPointer<vtkPolyData> FigurePartition::BentNormalized;
} // namespace

TEST_F(FigurePartition, LimbsAndTorsoGetDifferentClusters)
{
  vtkSmartPointer<vtkPolyData> parts = Partition(RestNormalized, nullptr, 3);
  const std::vector<int> clusters = IntValues(parts, "SDFCluster");
  const int torso = MajorityCluster(clusters, Rest->FaceParts, figure::Torso);
  EXPECT_EQ(torso, 0) << "the torso is the thickest part";
  for (int limb : { figure::LeftArm, figure::RightArm, figure::LeftLeg, figure::RightLeg })
  {
    EXPECT_NE(MajorityCluster(clusters, Rest->FaceParts, limb), torso) << "limb " << limb;
  }
  vtkFieldData* field = parts->GetFieldData();
  const int k = static_cast<int>(field->GetArray("SDFClusterCount")->GetComponent(0, 0));
  EXPECT_EQ(k, 3);
  EXPECT_EQ(field->GetArray("SDFGMMMeans")->GetNumberOfTuples(), k);
  EXPECT_TRUE(std::isfinite(field->GetArray("SDFEnergy")->GetComponent(0, 0)));
  EXPECT_EQ(parts->GetCellData()->GetArray("SDFProbabilities")->GetNumberOfComponents(), k);
  EXPECT_NE(parts->GetCellData()->GetArray("SDFLevel2"), nullptr);
  EXPECT_EQ(parts->GetCellData()->GetArray("SDFLevel3"), nullptr);
  const std::vector<int> level1 = IntValues(parts, "SDFLevel1");
  for (std::size_t f = 0; f < clusters.size(); ++f)
  {
    ASSERT_EQ(level1[f], std::min(clusters[f], 1));
  }
}

TEST_F(FigurePartition, TwoPosesAgreeAndTheSharedModelDoesNotHurt)
{
  // EM at k = 3: thick (torso), middle (head, legs), thin (arms); with k above the number of
  // thickness levels the per-mesh fits split a level differently in each pose, which is what
  // the shared model was first for (EM at k = 5 with the first energy: 7.8 % per mesh, 3.9 %
  // shared). Density modes (the default) at k = 5 find the levels themselves.
  // The family way (docs/partition.md, "Consistency"): one normalisation range, the widest of the two,
  // and one model fitted on both poses together.
  const std::array<double, 2> restRange = NormalizationRangeOf(RestNormalized);
  const std::array<double, 2> bentRange = NormalizationRangeOf(BentNormalized);
  EXPECT_NE(restRange, bentRange) << "the smoothed extremes move with the pose";
  const double familyRange[2] = { std::min(restRange[0], bentRange[0]), std::max(restRange[1], bentRange[1]) };
  vtkSmartPointer<vtkPolyData> restFamily = Normalized(*Rest, familyRange);
  vtkSmartPointer<vtkPolyData> bentFamily = Normalized(*Bent, familyRange);
  EXPECT_EQ(NormalizationRangeOf(bentFamily)[1], familyRange[1]);
  vtkNew<vtkAppendPolyData> family;
  family->AddInputData(restFamily);
  family->AddInputData(bentFamily);
  family->Update();
  for (const auto& [k, clusterModel] : { std::make_pair(3, 0), std::make_pair(5, 1) })
  {
    const std::vector<int> rest = IntValues(Partition(RestNormalized, nullptr, k, clusterModel), "SDFCluster");
    const std::vector<int> bent = IntValues(Partition(BentNormalized, nullptr, k, clusterModel), "SDFCluster");
    const double perMesh = shapediameter::CompareLabelings(rest, bent).PercentDifferent;
    vtkSmartPointer<vtkPolyData> model = Partition(family->GetOutput(), nullptr, k, clusterModel);
    const std::vector<int> restShared = IntValues(Partition(restFamily, model, k, clusterModel), "SDFCluster");
    const std::vector<int> bentShared = IntValues(Partition(bentFamily, model, k, clusterModel), "SDFCluster");
    const double shared = shapediameter::CompareLabelings(restShared, bentShared).PercentDifferent;
    std::printf("Table 2 measure on the figure, ClusterModel %d, k = %d: per-mesh %.3f %%, family %.3f %%\n",
      clusterModel, k, perMesh, shared);
    EXPECT_LE(perMesh, 3.0);
    // The default (density modes) must gain from the family; EM at k = 3 must not lose more
    // than a tenth of a point (measured with HitRule 0: +0.024, 6 faces in 25k: the mixture
    // fitted on both poses sets its boundaries between the two per-pose fits).
    EXPECT_LE(shared, perMesh + (clusterModel == 1 ? 1e-9 : 0.1));
  }
}

TEST_F(FigurePartition, DensityModesFollowTheThicknessLevelsInBothPoses)
{
  // ClusterModel 1 at the default k = 5: the figure has three thickness levels (torso; head
  // and legs; arms), so at most k and at least the torso/limb split; the two poses agree within
  // the same 3 % as EM at the right k (threshold stated before measuring).
  vtkSmartPointer<vtkPolyData> restParts = Partition(RestNormalized, nullptr, 5, 1);
  const std::vector<int> rest = IntValues(restParts, "SDFCluster");
  const std::vector<int> bent = IntValues(Partition(BentNormalized, nullptr, 5, 1), "SDFCluster");
  const int k = static_cast<int>(restParts->GetFieldData()->GetArray("SDFClusterCount")->GetComponent(0, 0));
  EXPECT_GE(k, 2);
  EXPECT_LE(k, 5);
  const int torso = MajorityCluster(rest, Rest->FaceParts, figure::Torso);
  EXPECT_EQ(torso, 0);
  for (int limb : { figure::LeftArm, figure::RightArm, figure::LeftLeg, figure::RightLeg })
  {
    EXPECT_NE(MajorityCluster(rest, Rest->FaceParts, limb), torso) << "limb " << limb;
  }
  const double percent = shapediameter::CompareLabelings(rest, bent).PercentDifferent;
  std::printf("density modes: k = %d, Table 2 measure on the figure %.3f %%\n", k, percent);
  EXPECT_LE(percent, 3.0);
}

TEST(SDFGMMPartition, ClusterModelHasNamedSettersAndIsClamped)
{
  vtkNew<vtkSDFGMMPartition> partition;
  partition->SetClusterModelToEM();
  EXPECT_EQ(partition->GetClusterModel(), 0);
  partition->SetClusterModelToDensityModes();
  EXPECT_EQ(partition->GetClusterModel(), 1);
  partition->SetClusterModel(-3);
  EXPECT_EQ(partition->GetClusterModel(), vtkSDFGMMPartition::EM);
}

TEST(SDFGMMPartition, DegenerateInputsAreDefined)
{
  vtkNew<vtkSphereSource> sphere;
  sphere->Update();
  vtkNew<vtkPolyData> mesh;
  mesh->DeepCopy(sphere->GetOutput());
  vtkNew<vtkDoubleArray> constant;
  constant->SetName("SDFNormalized");
  constant->SetNumberOfTuples(mesh->GetNumberOfCells());
  constant->FillValue(0.0);
  mesh->GetCellData()->AddArray(constant);

  // Constant field: one cluster, everything in it.
  vtkSmartPointer<vtkPolyData> parts = Partition(mesh);
  const std::vector<int> clusters = IntValues(parts, "SDFCluster");
  ASSERT_EQ(clusters.size(), static_cast<std::size_t>(mesh->GetNumberOfCells()));
  EXPECT_EQ(*std::max_element(clusters.begin(), clusters.end()), 0);
  EXPECT_EQ(parts->GetFieldData()->GetArray("SDFClusterCount")->GetComponent(0, 0), 1);

  // A single face and k larger than the number of faces.
  vtkNew<vtkPolyData> single;
  single->SetPoints(mesh->GetPoints());
  vtkNew<vtkCellArray> one;
  const vtkIdType ids[3] = { 0, 2, 3 };
  one->InsertNextCell(3, ids);
  single->SetPolys(one);
  vtkNew<vtkDoubleArray> value;
  value->SetName("SDFNormalized");
  value->InsertNextValue(0.5);
  single->GetCellData()->AddArray(value);
  vtkSmartPointer<vtkPolyData> singleParts = Partition(single, nullptr, 16);
  EXPECT_EQ(IntValues(singleParts, "SDFCluster"), std::vector<int>{ 0 });
  EXPECT_EQ(IntValues(singleParts, "SDFSegment"), std::vector<int>{ 0 });

  // Missing array and a bad model: error, pass-through.
  vtkNew<vtkSDFGMMPartition> partition;
  vtkNew<MessageRecorder> recorder;
  recorder->Observe(partition);
  partition->SetInputData(sphere->GetOutput());
  partition->Update();
  EXPECT_EQ(recorder->Errors, 1);
  EXPECT_EQ(partition->GetOutput()->GetCellData()->GetArray("SDFCluster"), nullptr);
  partition->SetInputData(mesh);
  partition->SetModelData(sphere->GetOutput());
  partition->Update();
  EXPECT_EQ(recorder->Errors, 2);
  EXPECT_EQ(partition->GetOutput()->GetCellData()->GetArray("SDFCluster"), nullptr);

  // Empty input: a warning, empty output.
  vtkNew<vtkPolyData> empty;
  vtkNew<vtkSDFGMMPartition> emptyPartition;
  vtkNew<MessageRecorder> emptyRecorder;
  emptyRecorder->Observe(emptyPartition);
  emptyPartition->SetInputData(empty);
  emptyPartition->Update();
  EXPECT_EQ(emptyRecorder->Errors, 0);
  EXPECT_EQ(emptyRecorder->Warnings, 1);
}

TEST_F(FigurePartition, HistogramTableMatchesTheFacesAndTheMixture)
{
  vtkNew<vtkSDFGMMPartition> partition;
  partition->SetInputData(RestNormalized);
  partition->SetNumberOfClusters(3);
  partition->Update();
  vtkTable* table = partition->GetHistogram();
  ASSERT_NE(table, nullptr);
  ASSERT_EQ(table->GetNumberOfRows(), 64);
  vtkDataArray* centers = vtkDataArray::SafeDownCast(table->GetColumnByName("BinCenter"));
  vtkDataArray* counts = vtkDataArray::SafeDownCast(table->GetColumnByName("Count"));
  ASSERT_TRUE(centers && counts && table->GetColumnByName("Density") && table->GetColumnByName("Mixture"));
  double total = 0.0;
  for (vtkIdType b = 0; b < counts->GetNumberOfTuples(); ++b)
  {
    total += counts->GetComponent(b, 0);
  }
  EXPECT_EQ(total, RestNormalized->GetNumberOfCells());
  const double width = centers->GetComponent(1, 0) - centers->GetComponent(0, 0);
  vtkDataArray* weights = partition->GetOutput()->GetFieldData()->GetArray("SDFGMMWeights");
  for (int c = 0; c < 3; ++c)
  {
    vtkDataArray* curve = vtkDataArray::SafeDownCast(table->GetColumnByName(("Component" + std::to_string(c)).c_str()));
    ASSERT_NE(curve, nullptr);
    double integral = 0.0;
    for (vtkIdType b = 0; b < curve->GetNumberOfTuples(); ++b)
    {
      integral += curve->GetComponent(b, 0) * width;
    }
    EXPECT_NEAR(integral, weights->GetComponent(c, 0), 0.02 * weights->GetComponent(c, 0)) << "component " << c;
  }
}

TEST(SDFGMMPartition, ASubdivisionKeepsTheParts)
{
  // A mesh and its one-level subdivision (faces 4i...4i+3 lie in face i) must get the same
  // clusters: linear subdivision is the same surface with four times the faces, Loop a
  // slightly smoothed one. The camel subdivided has 78k faces, so this also runs the
  // multilevel cut, which lost a whole cluster of the linear one (16 % of the area) before
  // regions off their most probable label joined its refinement band
  // (Filters/Core/Partition/MultilevelCut.h). Measured after: linear 0.50 %, Loop 0.91 % of the faces.
  vtkNew<vtkSDFOFFReader> reader;
  reader->SetFileName(shapediameter::testing::DataFile("camel.off").c_str());
  vtkNew<vtkTriangleFilter> triangles;
  triangles->SetInputConnection(reader->GetOutputPort());
  vtkNew<vtkLinearSubdivisionFilter> linear;
  linear->SetNumberOfSubdivisions(1);
  linear->SetInputConnection(triangles->GetOutputPort());
  vtkNew<vtkLoopSubdivisionFilter> loop;
  loop->SetNumberOfSubdivisions(1);
  loop->SetInputConnection(triangles->GetOutputPort());
  std::vector<std::vector<int>> labels;
  for (vtkAlgorithm* source : { static_cast<vtkAlgorithm*>(triangles), static_cast<vtkAlgorithm*>(linear),
         static_cast<vtkAlgorithm*>(loop) })
  {
    vtkNew<vtkShapeDiameterFilter> sdf;
    sdf->SetInputConnection(source->GetOutputPort());
    vtkNew<vtkSDFBilateralSmooth> smooth;
    smooth->SetInputConnection(sdf->GetOutputPort());
    vtkNew<vtkSDFGMMPartition> partition;
    partition->SetInputConnection(smooth->GetOutputPort());
    partition->Update();
    labels.push_back(IntValues(partition->GetOutput(), "SDFCluster"));
  }
  ASSERT_EQ(labels[0].size(), 19536u);
  std::vector<int> parent(4 * labels[0].size());
  for (std::size_t f = 0; f < parent.size(); ++f)
  {
    parent[f] = labels[0][f / 4];
  }
  for (const std::size_t fine : { 1, 2 })
  {
    ASSERT_EQ(labels[fine].size(), parent.size());
    const double changed = shapediameter::CompareLabelings(parent, labels[fine]).PercentDifferent;
    std::printf("camel vs its %s subdivision: %.2f %% of the faces change cluster\n", fine == 1 ? "linear" : "Loop", changed);
    EXPECT_LT(changed, 2.0);
  }
}

// ---------------------------------------------------------------------------------------------
// Consistency of the whole chain at its defaults (README "Parameters") on inputs where it is
// not given by construction: a non-rigid pose and another tessellation of the figure.

namespace
{
std::vector<double> FaceAreas(const figure::ArticulatedFigure& shape)
{
  std::vector<double> areas(static_cast<std::size_t>(shape.Triangles.rows()));
  for (Eigen::Index t = 0; t < shape.Triangles.rows(); ++t)
  {
    const Eigen::Vector3d a = shape.Points.row(shape.Triangles(t, 0)).transpose();
    const Eigen::Vector3d b = shape.Points.row(shape.Triangles(t, 1)).transpose();
    const Eigen::Vector3d c = shape.Points.row(shape.Triangles(t, 2)).transpose();
    areas[static_cast<std::size_t>(t)] = 0.5 * (b - a).cross(c - a).norm();
  }
  return areas;
}

/// The Table 2 measure with faces weighted by area: percent of the area whose labels differ
/// after the one-to-one matching of labels that maximises the matched area.
double PercentOfAreaDifferent(const std::vector<int>& first, const std::vector<int>& second, const std::vector<double>& areas)
{
  std::map<int, std::size_t> firstIndex, secondIndex;
  for (std::size_t f = 0; f < first.size(); ++f)
  {
    firstIndex.emplace(first[f], firstIndex.size());
    secondIndex.emplace(second[f], secondIndex.size());
  }
  const std::size_t size = std::max(firstIndex.size(), secondIndex.size());
  std::vector<double> sharedArea(size * size, 0.0);
  double total = 0.0;
  for (std::size_t f = 0; f < first.size(); ++f)
  {
    sharedArea[firstIndex[first[f]] * size + secondIndex[second[f]]] += areas[f];
    total += areas[f];
  }
  std::vector<double> cost(sharedArea.size());
  std::transform(sharedArea.begin(), sharedArea.end(), cost.begin(), [](double area) { return -area; });
  const std::vector<int> matching = shapediameter::SolveAssignment(cost, size);
  double matched = 0.0;
  for (std::size_t row = 0; row < size; ++row)
  {
    matched += sharedArea[row * size + static_cast<std::size_t>(matching[row])];
  }
  return 100.0 * (total - matched) / total;
}

std::vector<Eigen::Vector3d> FaceCenters(const figure::ArticulatedFigure& shape)
{
  std::vector<Eigen::Vector3d> centers(static_cast<std::size_t>(shape.Triangles.rows()));
  for (Eigen::Index t = 0; t < shape.Triangles.rows(); ++t)
  {
    centers[static_cast<std::size_t>(t)] = (shape.Points.row(shape.Triangles(t, 0)) +
      shape.Points.row(shape.Triangles(t, 1)) + shape.Points.row(shape.Triangles(t, 2))).transpose() / 3.0;
  }
  return centers;
}

/// Labels of `source`'s faces carried to `reference`'s: each reference face takes the label of
/// the source face whose centre is nearest to its own.
std::vector<int> TransferByNearestFaceCenter(
  const figure::ArticulatedFigure& source, const std::vector<int>& sourceLabels, const figure::ArticulatedFigure& reference)
{
  vtkNew<vtkPoints> sourceCenters;
  sourceCenters->SetDataTypeToDouble();
  for (const Eigen::Vector3d& center : FaceCenters(source))
  {
    sourceCenters->InsertNextPoint(center.data());
  }
  vtkNew<vtkPolyData> cloud;
  cloud->SetPoints(sourceCenters);
  vtkNew<vtkStaticPointLocator> locator;
  locator->SetDataSet(cloud);
  locator->BuildLocator();
  std::vector<int> labels;
  for (Eigen::Vector3d center : FaceCenters(reference))
  {
    labels.push_back(sourceLabels[static_cast<std::size_t>(locator->FindClosestPoint(center.data()))]);
  }
  return labels;
}

/// SDF -> smoothing -> partition, every filter at its defaults; SDFCluster per face.
std::vector<int> ClustersAtDefaults(const figure::ArticulatedFigure& shape)
{
  vtkNew<vtkShapeDiameterFilter> sdf;
  sdf->SetInputData(ToPolyData(shape.Points, shape.Triangles));
  vtkNew<vtkSDFBilateralSmooth> smooth;
  smooth->SetInputConnection(sdf->GetOutputPort());
  vtkNew<vtkSDFGMMPartition> partition;
  partition->SetInputConnection(smooth->GetOutputPort());
  // The defaults this test is about (README "Parameters"): if one changes, the thresholds below
  // were stated for other settings and must be looked at again.
  EXPECT_EQ(sdf->GetHitRule(), 0);
  EXPECT_EQ(sdf->GetNumberOfRays(), 30);
  EXPECT_EQ(smooth->GetNumberOfIterations(), 3);
  EXPECT_EQ(partition->GetClusterModel(), vtkSDFGMMPartition::DENSITY_MODES);
  EXPECT_EQ(partition->GetNumberOfClusters(), 5);
  EXPECT_EQ(partition->GetLambda(), 0.12);
  partition->Update();
  return IntValues(partition->GetOutput(), "SDFCluster");
}

class FigureConsistencyAtDefaults : public ::testing::Test
{
protected:
  static void SetUpTestSuite()
  {
    const figure::ArticulatedFigureTemplate figureTemplate;
    Rest = new figure::ArticulatedFigure(figureTemplate.Rest());
    // Not the pose the other figure tests use, and bent over a joint four radii long with the
    // joint stretched (ArticulatedFigure.h, step 5): no limb moves rigidly near the torso.
    NonRigid = new figure::ArticulatedFigure(figureTemplate.NonRigidPose(figure::FigurePose{ 0.7, -0.5, 0.6, -0.3 }));
    figure::FigureOptions otherTessellation;
    otherTessellation.CellSize = 0.042;
    otherTessellation.GridAngle = 0.6;
    Retriangulated = new figure::ArticulatedFigure(figure::ArticulatedFigureTemplate(otherTessellation).Rest());
    RestClusters = new std::vector<int>(ClustersAtDefaults(*Rest));
  }
  static void TearDownTestSuite()
  {
    delete Rest;
    delete NonRigid;
    delete Retriangulated;
    delete RestClusters;
  }
  static figure::ArticulatedFigure* Rest;
  static figure::ArticulatedFigure* NonRigid;
  static figure::ArticulatedFigure* Retriangulated;
  static std::vector<int>* RestClusters;
};
figure::ArticulatedFigure* FigureConsistencyAtDefaults::Rest = nullptr;
figure::ArticulatedFigure* FigureConsistencyAtDefaults::NonRigid = nullptr;
figure::ArticulatedFigure* FigureConsistencyAtDefaults::Retriangulated = nullptr;
std::vector<int>* FigureConsistencyAtDefaults::RestClusters = nullptr;

int ClustersCoveringOnePercent(const std::vector<int>& clusters, const std::vector<double>& areas)
{
  std::map<int, double> clusterArea;
  double total = 0.0;
  for (std::size_t f = 0; f < clusters.size(); ++f)
  {
    clusterArea[clusters[f]] += areas[f];
    total += areas[f];
  }
  return static_cast<int>(std::count_if(clusterArea.begin(), clusterArea.end(),
    [total](const auto& entry) { return entry.second >= 0.01 * total; }));
}
} // namespace

TEST_F(FigureConsistencyAtDefaults, NonRigidPoseKeepsThePartsOfTheRestPose)
{
  // Threshold stated before measuring (commit message): at most 5.5 % of the area, the bound
  // the elephant's real poses meet at these defaults (docs/partition.md, "Consistency").
  // Measured 0.70 % of the area (0.70 % of the faces), 4 clusters in both. An SDF scaled by
  // (1 + height) gives 8.2 % and fails; by (1 + height / 2) it gives 1.2 % and passes.
  const std::vector<int> nonRigid = ClustersAtDefaults(*NonRigid);
  ASSERT_EQ(nonRigid.size(), RestClusters->size());
  const std::vector<double> areas = FaceAreas(*Rest);
  const double areaPercent = PercentOfAreaDifferent(*RestClusters, nonRigid, areas);
  const double facePercent = shapediameter::CompareLabelings(*RestClusters, nonRigid).PercentDifferent;
  std::printf("rest vs non-rigid pose at the defaults: %.3f %% of the area (%.3f %% of the faces) change cluster; "
              "clusters >= 1 %% of the area: %d / %d\n",
    areaPercent, facePercent, ClustersCoveringOnePercent(*RestClusters, areas), ClustersCoveringOnePercent(nonRigid, areas));
  EXPECT_LE(areaPercent, 5.5);
}

TEST_F(FigureConsistencyAtDefaults, AnotherTessellationKeepsTheParts)
{
  // Threshold stated before measuring (commit message): at most 5.5 % of the reference's
  // area after nearest-centre transfer, as for the poses (docs/partition.md, "Consistency": a subdivision
  // changes 0.6-4.7 % on six of seven meshes). Measured 0.92 %, 4 clusters in both; an SDF
  // that depends on the face numbering (x 1.3 on alternate blocks of 500 faces) gives 49 %.
  const std::vector<int> copyClusters = ClustersAtDefaults(*Retriangulated);
  ASSERT_EQ(copyClusters.size(), static_cast<std::size_t>(Retriangulated->Triangles.rows()));
  const std::vector<int> transferred = TransferByNearestFaceCenter(*Retriangulated, copyClusters, *Rest);
  const std::vector<double> areas = FaceAreas(*Rest);
  const double areaPercent = PercentOfAreaDifferent(*RestClusters, transferred, areas);
  std::printf("figure (%td faces) vs another tessellation (%td faces) at the defaults: %.3f %% of the area changes "
              "cluster; clusters >= 1 %% of the area: %d / %d\n",
    Rest->Triangles.rows(), Retriangulated->Triangles.rows(), areaPercent, ClustersCoveringOnePercent(*RestClusters, areas),
    ClustersCoveringOnePercent(copyClusters, FaceAreas(*Retriangulated)));
  EXPECT_LE(areaPercent, 5.5);
}

TEST(SDFGMMPartition, TheChainBuildsOneFaceGraphKeptWhileItsFiltersLive)
{
  vtkNew<vtkSphereSource> sphere;
  sphere->SetThetaResolution(24);
  sphere->SetPhiResolution(16);
  auto sdf = vtkSmartPointer<vtkShapeDiameterFilter>::New();
  sdf->SetInputConnection(sphere->GetOutputPort());
  auto smooth = vtkSmartPointer<vtkSDFBilateralSmooth>::New();
  smooth->SetInputConnection(sdf->GetOutputPort());
  auto partition = vtkSmartPointer<vtkSDFGMMPartition>::New();
  partition->SetInputConnection(smooth->GetOutputPort());
  partition->Update();
  vtkSmartPointer<vtkPolyData> parts = partition->GetOutput();
  ASSERT_NE(parts->GetCellData()->GetArray("SDFCluster"), nullptr);

  std::vector<std::int64_t> offsets, connectivity;
  shapediameter::adapter::PolygonFaces(parts, offsets, connectivity);
  const shapediameter::PointMatrix points = shapediameter::adapter::PointsOf(parts);
  std::shared_ptr<const shapediameter::FaceGraph> graph =
    shapediameter::SharedFaceGraph(points, offsets, connectivity);
  // One graph, held by the smoothing, the partition and this test: the partition reused the
  // smoothing's instead of building its own.
  EXPECT_EQ(graph.use_count(), 3);
  EXPECT_EQ(graph->FaceCount(), static_cast<std::size_t>(parts->GetNumberOfPolys()));

  // Re-executed on the same surface (another lambda), the partition keeps the same graph.
  partition->SetLambda(partition->GetLambda() * 2);
  partition->Update();
  EXPECT_EQ(graph.use_count(), 3);

  // With ReleaseDataFlag on, the smoothing keeps nothing: only the partition and this test hold it.
  smooth->ReleaseDataFlagOn();
  smooth->Modified();
  partition->Update();
  EXPECT_EQ(graph.use_count(), 2);
  smooth->ReleaseDataFlagOff();

  // Deleting the filters releases it: nothing else keeps a graph alive.
  partition = nullptr;
  smooth = nullptr;
  sdf = nullptr;
  EXPECT_EQ(graph.use_count(), 1);
}
