// SPDX-License-Identifier: BSD-3-Clause
// The raw form in which distributed runs send polydata (Filters/PolyDataTransfer.h), on one
// process: a message described and rebuilt with its payloads copied in order, as MPI delivers
// them. The transport itself runs in every `ctest -R MPI` test.
#include "PolyDataTransfer.h"

#include "vtkBitArray.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataSetAttributes.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkFloatArray.h"
#include "vtkIdTypeArray.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkStringArray.h"
#include "vtkUnsignedCharArray.h"

#include <gtest/gtest.h>

#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

using namespace shapediameter::distributed;

namespace
{
/// What the receiving process gets: the message rebuilt, its payloads read in order.
vtkSmartPointer<vtkPolyData> RoundTrip(vtkPolyData* data, std::size_t* payloads = nullptr)
{
  const PolyDataMessage message = DescribePolyData(data);
  std::vector<std::vector<char>> sent;
  for (vtkDataArray* array : message.Payloads)
  {
    const auto* bytes = static_cast<const char*>(array->GetVoidPointer(0));
    sent.emplace_back(bytes, bytes + array->GetNumberOfValues() * array->GetDataTypeSize());
  }
  if (payloads)
  {
    *payloads = sent.size();
  }
  std::size_t next = 0;
  return RebuildPolyData(message.Header, message.Names, message.Marshalled, [&](char* destination, long long bytes) {
    while (next < sent.size() && sent[next].empty())
    {
      ++next; // empty arrays are not sent
    }
    ASSERT_LT(next, sent.size());
    ASSERT_EQ(static_cast<long long>(sent[next].size()), bytes);
    std::memcpy(destination, sent[next].data(), static_cast<std::size_t>(bytes));
    ++next;
  });
}

/// Points in double, verts and polygons (one a quad) in 64-bit storage, lines in 32-bit, no
/// strips; point and cell arrays of several types, an active attribute, a null-named array,
/// component names; field data.
vtkSmartPointer<vtkPolyData> Piece()
{
  auto piece = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  for (int i = 0; i < 6; ++i)
  {
    points->InsertNextPoint(0.1 * i, 1.0 / (i + 1), -2.5 * i);
  }
  piece->SetPoints(points);
  vtkNew<vtkCellArray> verts, polys;
  vtkNew<vtkCellArray> lines;
  lines->Use32BitStorage();
  const vtkIdType vertex[1] = { 5 };
  verts->InsertNextCell(1, vertex);
  const vtkIdType line[2] = { 4, 5 };
  lines->InsertNextCell(2, line);
  const vtkIdType triangle[3] = { 0, 1, 2 };
  const vtkIdType quad[4] = { 1, 3, 4, 2 };
  polys->InsertNextCell(3, triangle);
  polys->InsertNextCell(4, quad);
  piece->SetVerts(verts);
  piece->SetLines(lines);
  piece->SetPolys(polys);

  vtkNew<vtkIdTypeArray> globalPoints;
  globalPoints->SetName("GlobalPointIds");
  for (vtkIdType i = 0; i < 6; ++i)
  {
    globalPoints->InsertNextValue(100 + 7 * i);
  }
  piece->GetPointData()->SetGlobalIds(globalPoints);
  vtkNew<vtkFloatArray> normals;
  normals->SetName("Normals");
  normals->SetNumberOfComponents(3);
  normals->SetComponentName(0, "nx");
  normals->SetComponentName(2, "nz");
  for (int i = 0; i < 6; ++i)
  {
    normals->InsertNextTuple3(i, -i, 0.5f * i);
  }
  piece->GetPointData()->SetNormals(normals);

  vtkNew<vtkDoubleArray> sdf;
  sdf->SetName("SDF");
  vtkNew<vtkUnsignedCharArray> ghosts;
  ghosts->SetName(vtkDataSetAttributes::GhostArrayName());
  vtkNew<vtkIntArray> unnamed;
  for (int c = 0; c < 4; ++c)
  {
    sdf->InsertNextValue(c == 2 ? 1e-300 : 0.25 * c);
    ghosts->InsertNextValue(c == 3 ? vtkDataSetAttributes::DUPLICATECELL : 0);
    unnamed->InsertNextValue(-c);
  }
  piece->GetCellData()->AddArray(sdf);
  piece->GetCellData()->SetActiveScalars("SDF");
  piece->GetCellData()->AddArray(ghosts);
  piece->GetCellData()->AddArray(unnamed);

  vtkNew<vtkIntArray> marker;
  marker->SetName("Marker");
  marker->InsertNextValue(42);
  piece->GetFieldData()->AddArray(marker);
  return piece;
}

void ExpectSameValues(vtkDataArray* expected, vtkDataArray* actual)
{
  ASSERT_NE(actual, nullptr);
  EXPECT_EQ(expected->GetDataType(), actual->GetDataType());
  ASSERT_EQ(expected->GetNumberOfComponents(), actual->GetNumberOfComponents());
  ASSERT_EQ(expected->GetNumberOfTuples(), actual->GetNumberOfTuples());
  for (vtkIdType v = 0; v < expected->GetNumberOfValues(); ++v)
  {
    EXPECT_EQ(expected->GetVariantValue(v), actual->GetVariantValue(v)) << expected->GetName() << " value " << v;
  }
}

void ExpectSameCells(vtkCellArray* expected, vtkCellArray* actual)
{
  ASSERT_NE(actual, nullptr);
  EXPECT_EQ(expected->IsStorage64Bit(), actual->IsStorage64Bit());
  ExpectSameValues(expected->GetOffsetsArray(), actual->GetOffsetsArray());
  ExpectSameValues(expected->GetConnectivityArray(), actual->GetConnectivityArray());
}
} // namespace

TEST(PolyDataTransfer, RawFormKeepsGeometryCellsArraysRolesAndNames)
{
  vtkSmartPointer<vtkPolyData> piece = Piece();
  std::size_t payloads = 0;
  vtkSmartPointer<vtkPolyData> received = RoundTrip(piece, &payloads);
  // Points, 3 cell arrays x 2, 2 point arrays, 3 cell arrays: the raw form, not the legacy one.
  EXPECT_EQ(payloads, 1u + 6u + 2u + 3u);

  ExpectSameValues(piece->GetPoints()->GetData(), received->GetPoints()->GetData());
  ExpectSameCells(piece->GetVerts(), received->GetVerts());
  ExpectSameCells(piece->GetLines(), received->GetLines());
  ExpectSameCells(piece->GetPolys(), received->GetPolys());
  EXPECT_EQ(received->GetNumberOfStrips(), 0);
  EXPECT_EQ(received->GetNumberOfCells(), 4);

  ExpectSameValues(piece->GetPointData()->GetArray("GlobalPointIds"), received->GetPointData()->GetGlobalIds());
  EXPECT_STREQ(received->GetPointData()->GetGlobalIds()->GetClassName(), "vtkIdTypeArray");
  vtkDataArray* normals = received->GetPointData()->GetNormals();
  ExpectSameValues(piece->GetPointData()->GetNormals(), normals);
  EXPECT_STREQ(normals->GetComponentName(0), "nx");
  EXPECT_EQ(normals->GetComponentName(1), nullptr);
  EXPECT_STREQ(normals->GetComponentName(2), "nz");

  ASSERT_EQ(received->GetCellData()->GetNumberOfArrays(), 3);
  ExpectSameValues(piece->GetCellData()->GetArray("SDF"), received->GetCellData()->GetScalars());
  ExpectSameValues(piece->GetCellData()->GetArray(vtkDataSetAttributes::GhostArrayName()),
    received->GetCellData()->GetArray(vtkDataSetAttributes::GhostArrayName()));
  EXPECT_EQ(received->GetCellData()->GetArray(2)->GetName(), nullptr);
  ExpectSameValues(piece->GetCellData()->GetArray(2), received->GetCellData()->GetArray(2));

  ASSERT_NE(received->GetFieldData()->GetArray("Marker"), nullptr);
  EXPECT_EQ(received->GetFieldData()->GetArray("Marker")->GetTuple1(0), 42);
}

TEST(PolyDataTransfer, EmptyPolyDataStaysEmpty)
{
  vtkNew<vtkPolyData> empty;
  vtkSmartPointer<vtkPolyData> received = RoundTrip(empty);
  EXPECT_EQ(received->GetPoints(), nullptr);
  EXPECT_EQ(received->GetNumberOfCells(), 0);
  EXPECT_EQ(received->GetPointData()->GetNumberOfArrays(), 0);

  vtkNew<vtkPolyData> pointsOnly;
  vtkNew<vtkPoints> none;
  pointsOnly->SetPoints(none);
  received = RoundTrip(pointsOnly);
  ASSERT_NE(received->GetPoints(), nullptr);
  EXPECT_EQ(received->GetNumberOfPoints(), 0);
  EXPECT_EQ(received->GetPoints()->GetDataType(), VTK_FLOAT);
}

TEST(PolyDataTransfer, ArraysTheRawFormCannotCarryTravelWhole)
{
  // A string array and a bit array on the cells: the polydata goes through vtkCommunicator's
  // marshalling, as before, and nothing is lost.
  vtkSmartPointer<vtkPolyData> piece = Piece();
  vtkNew<vtkStringArray> labels;
  labels->SetName("Labels");
  vtkNew<vtkBitArray> bits;
  bits->SetName("Bits");
  for (int c = 0; c < 4; ++c)
  {
    labels->InsertNextValue("cell " + std::to_string(c));
    bits->InsertNextValue(c % 2);
  }
  piece->GetCellData()->AddArray(labels);
  piece->GetCellData()->AddArray(bits);
  std::size_t payloads = 0;
  vtkSmartPointer<vtkPolyData> received = RoundTrip(piece, &payloads);
  EXPECT_EQ(payloads, 0u);
  EXPECT_EQ(received->GetCellData()->GetAbstractArray("Labels"), labels.GetPointer()); // the same object here
  EXPECT_EQ(received->GetNumberOfCells(), 4);
}

TEST(PolyDataTransfer, DamagedHeaderIsAnError)
{
  vtkSmartPointer<vtkPolyData> piece = Piece();
  PolyDataMessage message = DescribePolyData(piece);
  const auto ignore = [](char*, long long) {};
  std::vector<long long> cut(message.Header.begin(), message.Header.begin() + 5);
  EXPECT_THROW(RebuildPolyData(cut, message.Names, nullptr, ignore), std::exception);
  std::vector<long long> unknown = message.Header;
  unknown[0] = 7;
  EXPECT_THROW(RebuildPolyData(unknown, message.Names, nullptr, ignore), std::exception);
  EXPECT_THROW(RebuildPolyData(message.Header, "", nullptr, ignore), std::exception); // names missing
}
