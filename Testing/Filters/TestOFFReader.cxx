// SPDX-License-Identifier: BSD-3-Clause
#include "FilterTestUtilities.h"
#include "vtkOFFReader.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

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

TEST(OFFReader, ReadsBundledCamel)
{
  vtkNew<vtkOFFReader> reader;
  reader->SetFileName(DataFile("camel.off").c_str());
  reader->Update();
  vtkPolyData* mesh = reader->GetOutput();
  EXPECT_EQ(mesh->GetNumberOfPoints(), 9770);
  EXPECT_EQ(mesh->GetNumberOfPolys(), 19536);
  EXPECT_EQ(mesh->GetPolys()->GetMaxCellSize(), 3);
}

TEST(OFFReader, KeepsNGonsAndColours)
{
  const std::string path = WriteTemporary("quad_colours.off",
    "COFF\n# a unit square and a triangle\n5 2 0\n"
    "0 0 0 255 0 0 255\n1 0 0 0 255 0 255\n1 1 0 0 0 255 255\n0 1 0 10 20 30 255\n"
    "0.5 0.5 1 1 1 1 255\n\n4 0 1 2 3 200 100 50\n3 0 1 4\n");
  vtkNew<vtkOFFReader> reader;
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

TEST(OFFReader, MalformedFileIsAnErrorWithEmptyOutput)
{
  const std::string path = WriteTemporary("bad_index.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 7\n");
  vtkNew<vtkOFFReader> reader;
  vtkNew<MessageRecorder> recorder;
  recorder->Observe(reader);
  reader->SetFileName(path.c_str());
  reader->Update();
  EXPECT_EQ(recorder->Errors, 1);
  EXPECT_NE(recorder->LastError.find("line 6"), std::string::npos) << recorder->LastError;
  EXPECT_EQ(reader->GetOutput()->GetNumberOfCells(), 0);
}

TEST(OFFReader, MissingFileIsAnError)
{
  vtkNew<vtkOFFReader> reader;
  vtkNew<MessageRecorder> recorder;
  recorder->Observe(reader);
  reader->SetFileName("/nonexistent/mesh.off");
  reader->Update();
  EXPECT_EQ(recorder->Errors, 1);
  EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 0);
  EXPECT_EQ(vtkOFFReader::CanReadFile("/nonexistent/mesh.off"), 0);
  EXPECT_EQ(vtkOFFReader::CanReadFile(DataFile("camel.off").c_str()), 1);
}
