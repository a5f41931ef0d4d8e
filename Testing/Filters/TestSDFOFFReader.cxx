// SPDX-License-Identifier: BSD-3-Clause
#include "FilterTestUtilities.h"
#include "vtkSDFOFFReader.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <vector>

using shapediameter::testing::DataFile;
using shapediameter::testing::MessageRecorder;

namespace
{
std::string WriteTemporary(const std::string& name, const std::string& text)
{
  const std::string path = ::testing::TempDir() + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}
} // namespace

TEST(SDFOFFReader, ReadsBundledCamel)
{
  vtkNew<vtkSDFOFFReader> reader;
  reader->SetFileName(DataFile("camel.off").c_str());
  reader->Update();
  vtkPolyData* mesh = reader->GetOutput();
  EXPECT_EQ(mesh->GetNumberOfPoints(), 9770);
  EXPECT_EQ(mesh->GetNumberOfPolys(), 19536);
  EXPECT_EQ(mesh->GetPolys()->GetMaxCellSize(), 3);
}

TEST(SDFOFFReader, KeepsNGonsAndColours)
{
  const std::string path = WriteTemporary("quad_colours.off",
    "COFF\n# a unit square and a triangle\n5 2 0\n"
    "0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n1 1 0 0 0 255 255\n0 1 0 10 20 30 255\n"
    "0.5 0.5 1 1 1 1 255\n\n4 0 1 2 3 200 100 50\n3 0 1 4\n");
  vtkNew<vtkSDFOFFReader> reader;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkPolyData* mesh = reader->GetOutput();
  ASSERT_EQ(mesh->GetNumberOfCells(), 2);
  EXPECT_EQ(mesh->GetCell(0)->GetNumberOfPoints(), 4);
  EXPECT_EQ(mesh->GetCell(1)->GetNumberOfPoints(), 3);
  vtkDataArray* colours = mesh->GetPointData()->GetArray("Colors");
  ASSERT_NE(colours, nullptr);
  EXPECT_EQ(colours->GetComponent(3, 2), 30);
  vtkDataArray* faceColours = mesh->GetCellData()->GetArray("Colors");
  ASSERT_NE(faceColours, nullptr);
  EXPECT_EQ(faceColours->GetComponent(0, 0), 200);
  EXPECT_DOUBLE_EQ(mesh->GetPoint(4)[2], 1.0);
}

TEST(SDFOFFReader, MalformedFileIsAnErrorWithEmptyOutput)
{
  const std::string path = WriteTemporary("bad_index.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
  vtkNew<vtkSDFOFFReader> reader;
  vtkNew<MessageRecorder> recorder;
  recorder->Observe(reader);
  reader->SetFileName(path.c_str());
  reader->Update();
  EXPECT_EQ(recorder->Errors, 1);
  EXPECT_NE(recorder->LastError.find("line 6"), std::string::npos) << recorder->LastError;
  EXPECT_EQ(reader->GetOutput()->GetNumberOfCells(), 0);
}

TEST(SDFOFFReader, MissingFileIsAnError)
{
  vtkNew<vtkSDFOFFReader> reader;
  vtkNew<MessageRecorder> recorder;
  recorder->Observe(reader);
  reader->SetFileName("/nonexistent/mesh.off");
  reader->Update();
  EXPECT_EQ(recorder->Errors, 1);
  EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 0);
  EXPECT_EQ(vtkSDFOFFReader::CanReadFile("/nonexistent/mesh.off"), 0);
  EXPECT_EQ(vtkSDFOFFReader::CanReadFile(DataFile("camel.off").c_str()), 1);
}

TEST(SDFOFFReader, PiecesShareTheFacesAndCarryGlobalIds)
{
  vtkNew<vtkSDFOFFReader> serial;
  serial->SetFileName(DataFile("camel.off").c_str());
  serial->Update();
  vtkPolyData* whole = serial->GetOutput();
  EXPECT_EQ(whole->GetPointData()->GetGlobalIds(), nullptr) << "serial runs carry no global ids";
  const vtkIdType faces = whole->GetNumberOfCells();
  constexpr int pieces = 3;
  std::vector<int> seen(static_cast<std::size_t>(faces), 0);
  for (int piece = 0; piece < pieces; ++piece)
  {
    vtkNew<vtkSDFOFFReader> reader;
    reader->SetFileName(DataFile("camel.off").c_str());
    reader->UpdatePiece(piece, pieces, 0);
    vtkPolyData* part = reader->GetOutput();
    EXPECT_NEAR(part->GetNumberOfCells(), faces / pieces, 1) << "piece " << piece;
    vtkDataArray* cellIds = part->GetCellData()->GetGlobalIds();
    vtkDataArray* pointIds = part->GetPointData()->GetGlobalIds();
    ASSERT_NE(cellIds, nullptr);
    ASSERT_NE(pointIds, nullptr);
    EXPECT_STREQ(cellIds->GetName(), "GlobalCellIds");
    EXPECT_STREQ(pointIds->GetName(), "GlobalPointIds");
    ASSERT_EQ(pointIds->GetNumberOfTuples(), part->GetNumberOfPoints());
    for (vtkIdType c = 0; c < part->GetNumberOfCells(); ++c)
    {
      const auto global = static_cast<vtkIdType>(cellIds->GetComponent(c, 0));
      ++seen[static_cast<std::size_t>(global)];
      vtkIdType count = 0;
      const vtkIdType* ids = nullptr;
      vtkIdType wholeCount = 0;
      const vtkIdType* wholeIds = nullptr;
      part->GetCellPoints(c, count, ids);
      whole->GetCellPoints(global, wholeCount, wholeIds);
      ASSERT_EQ(count, wholeCount);
      for (vtkIdType i = 0; i < count; ++i)
      {
        EXPECT_EQ(static_cast<vtkIdType>(pointIds->GetComponent(ids[i], 0)), wholeIds[i]);
      }
    }
  }
  EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), faces) << "every face in exactly one piece";
}
