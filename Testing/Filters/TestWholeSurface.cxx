// SPDX-License-Identifier: BSD-3-Clause
// The whole-surface assembly and scatter mapping of distributed runs (Filters/WholeSurface.h)
// on one process: pieces are cut from a small mesh by hand, no MPI involved.
#include "WholeSurface.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkDataSetAttributes.h"
#include "vtkDoubleArray.h"
#include "vtkFieldData.h"
#include "vtkIdTypeArray.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkUnsignedCharArray.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <vector>

using namespace shapediameter::distributed;

namespace
{
/// The point ids of one cell.
std::vector<vtkIdType> CellPoints(vtkPolyData* mesh, vtkIdType cell)
{
  vtkIdType count;
  const vtkIdType* ids;
  mesh->GetCellPoints(cell, count, ids);
  return std::vector<vtkIdType>(ids, ids + count);
}

/// Points 0..6 in the plane; cells: vertex 0, line 1-2, then four triangles (ids 2..5).
vtkSmartPointer<vtkPolyData> Mesh()
{
  auto mesh = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  const double xy[7][2] = { { 0, 0 }, { 1, 0 }, { 2, 0 }, { 0, 1 }, { 1, 1 }, { 2, 1 }, { 5, 5 } };
  for (const auto& p : xy)
  {
    points->InsertNextPoint(p[0], p[1], 0.0);
  }
  mesh->SetPoints(points);
  vtkNew<vtkCellArray> verts, lines, polys;
  const vtkIdType vertex[1] = { 6 };
  verts->InsertNextCell(1, vertex);
  const vtkIdType line[2] = { 1, 2 };
  lines->InsertNextCell(2, line);
  const vtkIdType triangles[4][3] = { { 0, 1, 4 }, { 0, 4, 3 }, { 1, 2, 5 }, { 1, 5, 4 } };
  for (const auto& t : triangles)
  {
    polys->InsertNextCell(3, t);
  }
  mesh->SetVerts(verts);
  mesh->SetLines(lines);
  mesh->SetPolys(polys);
  vtkNew<vtkDoubleArray> value;
  value->SetName("Value");
  for (vtkIdType c = 0; c < mesh->GetNumberOfCells(); ++c)
  {
    value->InsertNextValue(10.0 * static_cast<double>(c));
  }
  mesh->GetCellData()->AddArray(value);
  return mesh;
}

/// The cells `cells` (ascending, so in vtkPolyData's group order) of `mesh` with the points
/// they use, in the order `pointOrder` gives (ascending point ids when empty); with the
/// reader's GlobalCellIds/GlobalPointIds when `ids`.
vtkSmartPointer<vtkPolyData> Piece(vtkPolyData* mesh, const std::vector<vtkIdType>& cells, bool ids,
  std::vector<vtkIdType> pointOrder = {})
{
  if (pointOrder.empty())
  {
    std::map<vtkIdType, bool> used;
    for (const vtkIdType c : cells)
    {
      for (const vtkIdType p : CellPoints(mesh, c))
      {
        used[p] = true;
      }
    }
    for (const auto& entry : used)
    {
      pointOrder.push_back(entry.first);
    }
  }
  std::map<vtkIdType, vtkIdType> local;
  auto piece = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> points;
  vtkNew<vtkIdTypeArray> pointIds;
  pointIds->SetName("GlobalPointIds");
  for (const vtkIdType p : pointOrder)
  {
    local[p] = points->InsertNextPoint(mesh->GetPoint(p));
    pointIds->InsertNextValue(p);
  }
  piece->SetPoints(points);
  vtkNew<vtkCellArray> verts, lines, polys;
  vtkNew<vtkIdTypeArray> cellIds;
  cellIds->SetName("GlobalCellIds");
  vtkNew<vtkDoubleArray> value;
  value->SetName("Value");
  for (const vtkIdType c : cells)
  {
    std::vector<vtkIdType> mapped = CellPoints(mesh, c);
    for (vtkIdType& p : mapped)
    {
      p = local.at(p);
    }
    const int group = static_cast<int>(CellGroupOf(mesh->GetCellType(c)));
    (group == 0 ? verts : group == 1 ? lines : polys)->InsertNextCell(static_cast<vtkIdType>(mapped.size()), mapped.data());
    cellIds->InsertNextValue(c);
    value->InsertNextValue(mesh->GetCellData()->GetArray("Value")->GetComponent(c, 0));
  }
  piece->SetVerts(verts);
  piece->SetLines(lines);
  piece->SetPolys(polys);
  piece->GetCellData()->AddArray(value);
  if (ids)
  {
    piece->GetCellData()->AddArray(cellIds);
    piece->GetPointData()->AddArray(pointIds);
  }
  return piece;
}

void ExpectSameGeometry(vtkPolyData* expected, vtkPolyData* actual)
{
  ASSERT_EQ(actual->GetNumberOfPoints(), expected->GetNumberOfPoints());
  ASSERT_EQ(actual->GetNumberOfCells(), expected->GetNumberOfCells());
  for (vtkIdType p = 0; p < expected->GetNumberOfPoints(); ++p)
  {
    double a[3], b[3];
    expected->GetPoint(p, a);
    actual->GetPoint(p, b);
    EXPECT_EQ(a[0], b[0]);
    EXPECT_EQ(a[1], b[1]);
    EXPECT_EQ(a[2], b[2]);
  }
  for (vtkIdType c = 0; c < expected->GetNumberOfCells(); ++c)
  {
    EXPECT_EQ(actual->GetCellType(c), expected->GetCellType(c)) << "cell " << c;
    EXPECT_EQ(CellPoints(actual, c), CellPoints(expected, c)) << "cell " << c;
  }
}
} // namespace

TEST(WholeSurface, CellGroupsFollowPolyDataNumbering)
{
  EXPECT_EQ(CellGroupOf(VTK_VERTEX), CellGroup::Vertices);
  EXPECT_EQ(CellGroupOf(VTK_POLY_VERTEX), CellGroup::Vertices);
  EXPECT_EQ(CellGroupOf(VTK_LINE), CellGroup::Lines);
  EXPECT_EQ(CellGroupOf(VTK_POLY_LINE), CellGroup::Lines);
  EXPECT_EQ(CellGroupOf(VTK_TRIANGLE), CellGroup::Polygons);
  EXPECT_EQ(CellGroupOf(VTK_QUAD), CellGroup::Polygons);
  EXPECT_EQ(CellGroupOf(VTK_POLYGON), CellGroup::Polygons);
  EXPECT_EQ(CellGroupOf(VTK_TRIANGLE_STRIP), CellGroup::Strips);
}

TEST(WholeSurface, GlobalIdsRestoreTheOriginalOrder)
{
  const auto mesh = Mesh();
  // Interleaved cells, points in a scrambled order, an empty piece in between.
  const auto a = Piece(mesh, { 1, 3, 5 }, true, { 5, 2, 1, 4, 0, 3 });
  const auto empty = vtkSmartPointer<vtkPolyData>::New();
  const auto b = Piece(mesh, { 0, 2, 4 }, true);
  const WholeSurface whole = AssembleWholeSurface({ a, empty, b });
  EXPECT_EQ(whole.Cells, CellOrder::GlobalCellIds);
  EXPECT_EQ(whole.Points, PointOrder::GlobalPointIds);
  ExpectSameGeometry(mesh, whole.Mesh);
  vtkDataArray* value = whole.Mesh->GetCellData()->GetArray("Value");
  ASSERT_NE(value, nullptr);
  for (vtkIdType c = 0; c < mesh->GetNumberOfCells(); ++c)
  {
    EXPECT_EQ(value->GetComponent(c, 0), 10.0 * static_cast<double>(c));
  }
  EXPECT_EQ(whole.CellToWhole[0], (std::vector<vtkIdType>{ 1, 3, 5 }));
  EXPECT_TRUE(whole.CellToWhole[1].empty());
  EXPECT_EQ(whole.CellToWhole[2], (std::vector<vtkIdType>{ 0, 2, 4 }));
  EXPECT_EQ(whole.PointToWhole[0], (std::vector<vtkIdType>{ 5, 2, 1, 4, 0, 3 }));
}

TEST(WholeSurface, DuplicatedBoundaryCellKeptOnce)
{
  const auto mesh = Mesh();
  const auto a = Piece(mesh, { 2, 3, 5 }, true);
  const auto b = Piece(mesh, { 0, 1, 4, 5 }, true);
  // b's copy of cell 5 is the duplicate ("Assign to all regions").
  vtkNew<vtkUnsignedCharArray> ghosts;
  ghosts->SetName(vtkDataSetAttributes::GhostArrayName());
  for (const unsigned char g : { 0, 0, 0, static_cast<int>(vtkDataSetAttributes::DUPLICATECELL) })
  {
    ghosts->InsertNextValue(g);
  }
  b->GetCellData()->AddArray(ghosts);
  const WholeSurface whole = AssembleWholeSurface({ a, b });
  ExpectSameGeometry(mesh, whole.Mesh);
  EXPECT_EQ(whole.CellToWhole[0], (std::vector<vtkIdType>{ 2, 3, 5 }));
  EXPECT_EQ(whole.CellToWhole[1], (std::vector<vtkIdType>{ 0, 1, 4, 5 }));
  EXPECT_EQ(whole.Mesh->GetCellData()->GetArray(vtkDataSetAttributes::GhostArrayName()), nullptr);
}

TEST(WholeSurface, WithoutIdsProcessOrderAndMergedCoordinates)
{
  const auto mesh = Mesh();
  const auto a = Piece(mesh, { 0, 2, 3 }, false);
  const auto b = Piece(mesh, { 1, 4, 5 }, false);
  const WholeSurface whole = AssembleWholeSurface({ a, b });
  EXPECT_EQ(whole.Cells, CellOrder::ProcessOrder);
  EXPECT_EQ(whole.Points, PointOrder::Coordinates);
  // Group order first (vertex, line, polygons), then process by process.
  EXPECT_EQ(whole.CellToWhole[0], (std::vector<vtkIdType>{ 0, 2, 3 }));
  EXPECT_EQ(whole.CellToWhole[1], (std::vector<vtkIdType>{ 1, 4, 5 }));
  // Shared coordinates are one point: the original 7.
  EXPECT_EQ(whole.Mesh->GetNumberOfPoints(), 7);
  EXPECT_EQ(whole.Mesh->GetNumberOfPolys(), 4);
}

TEST(WholeSurface, OriginalCellIdsOnlyWhenConsistent)
{
  const auto mesh = Mesh();
  auto originalIds = [](vtkPolyData* piece, const std::vector<vtkIdType>& ids) {
    vtkNew<vtkIdTypeArray> array;
    array->SetName("vtkOriginalCellIds");
    for (const vtkIdType id : ids)
    {
      array->InsertNextValue(id);
    }
    piece->GetCellData()->AddArray(array);
  };
  auto a = Piece(mesh, { 1, 3, 5 }, false);
  auto b = Piece(mesh, { 0, 2, 4 }, false);
  originalIds(a, { 1, 3, 5 });
  originalIds(b, { 0, 2, 4 });
  WholeSurface whole = AssembleWholeSurface({ a, b });
  EXPECT_EQ(whole.Cells, CellOrder::OriginalCellIds);
  EXPECT_EQ(whole.CellToWhole[0], (std::vector<vtkIdType>{ 1, 3, 5 }));

  // Per-piece ids (0, 1, 2 on both): equal ids with different corners → process order.
  a = Piece(mesh, { 1, 3, 5 }, false);
  b = Piece(mesh, { 0, 2, 4 }, false);
  originalIds(a, { 0, 1, 2 });
  originalIds(b, { 0, 1, 2 });
  whole = AssembleWholeSurface({ a, b });
  EXPECT_EQ(whole.Cells, CellOrder::ProcessOrder);
  EXPECT_EQ(whole.Mesh->GetNumberOfCells(), 6);
}

TEST(WholeSurface, KeepsOnlyArraysEveryPieceHas)
{
  const auto mesh = Mesh();
  const auto a = Piece(mesh, { 0, 1, 2 }, true);
  const auto b = Piece(mesh, { 3, 4, 5 }, true);
  vtkNew<vtkIntArray> onlyA;
  onlyA->SetName("OnlyA");
  onlyA->SetNumberOfTuples(a->GetNumberOfCells());
  onlyA->FillValue(1);
  a->GetCellData()->AddArray(onlyA);
  vtkNew<vtkIntArray> field;
  field->SetName("Field");
  field->InsertNextValue(7);
  a->GetFieldData()->AddArray(field);
  const WholeSurface whole = AssembleWholeSurface({ a, b });
  EXPECT_NE(whole.Mesh->GetCellData()->GetArray("Value"), nullptr);
  EXPECT_EQ(whole.Mesh->GetCellData()->GetArray("OnlyA"), nullptr);
  EXPECT_NE(whole.Mesh->GetFieldData()->GetArray("Field"), nullptr);
}

TEST(WholeSurface, EmptyPiecesGiveAnEmptyMesh)
{
  const auto a = vtkSmartPointer<vtkPolyData>::New();
  const auto b = vtkSmartPointer<vtkPolyData>::New();
  const WholeSurface whole = AssembleWholeSurface({ a, b });
  EXPECT_EQ(whole.Mesh->GetNumberOfCells(), 0);
  EXPECT_EQ(whole.Mesh->GetNumberOfPoints(), 0);
  EXPECT_EQ(whole.CellToWhole.size(), 2u);
}

TEST(WholeSurface, ScatterGivesEachPieceItsNewArraysAndWinding)
{
  const auto mesh = Mesh();
  const auto a = Piece(mesh, { 1, 3, 5 }, true, { 5, 2, 1, 4, 0, 3 });
  const auto b = Piece(mesh, { 0, 2, 4 }, true);
  const WholeSurface whole = AssembleWholeSurface({ a, b });

  // A filter's output on the whole surface: everything passed through, one new cell array,
  // one new point array, a field array, and the winding of the last triangle reversed.
  vtkNew<vtkPolyData> output;
  output->ShallowCopy(whole.Mesh);
  vtkNew<vtkDoubleArray> cellNew, pointNew, fieldNew;
  cellNew->SetName("CellNew");
  for (vtkIdType c = 0; c < output->GetNumberOfCells(); ++c)
  {
    cellNew->InsertNextValue(static_cast<double>(c));
  }
  pointNew->SetName("PointNew");
  for (vtkIdType p = 0; p < output->GetNumberOfPoints(); ++p)
  {
    pointNew->InsertNextValue(static_cast<double>(100 + p));
  }
  fieldNew->SetName("FieldNew");
  fieldNew->InsertNextValue(3.0);
  output->GetCellData()->AddArray(cellNew);
  output->GetPointData()->AddArray(pointNew);
  output->GetFieldData()->AddArray(fieldNew);
  vtkNew<vtkCellArray> polys;
  const vtkIdType triangles[4][3] = { { 0, 1, 4 }, { 0, 4, 3 }, { 1, 2, 5 }, { 1, 4, 5 } };
  for (const auto& t : triangles)
  {
    polys->InsertNextCell(3, t);
  }
  output->SetPolys(polys);

  const vtkSmartPointer<vtkPolyData> pieces[2] = { a, b };
  for (int r = 0; r < 2; ++r)
  {
    vtkPolyData* piece = pieces[r];
    const auto result = LocalResult(piece, whole.Mesh, output, whole.CellToWhole[r], whole.PointToWhole[r]);
    EXPECT_EQ(result->GetCellData()->GetArray("Value"), nullptr) << "passed through: not sent back";
    vtkNew<vtkPolyData> local;
    ApplyResult(piece, result, local);
    ASSERT_EQ(local->GetNumberOfCells(), piece->GetNumberOfCells());
    vtkDataArray* cells = local->GetCellData()->GetArray("CellNew");
    vtkDataArray* points = local->GetPointData()->GetArray("PointNew");
    ASSERT_NE(cells, nullptr);
    ASSERT_NE(points, nullptr);
    EXPECT_NE(local->GetCellData()->GetArray("Value"), nullptr) << "the process's own arrays stay";
    EXPECT_NE(local->GetFieldData()->GetArray("FieldNew"), nullptr);
    vtkDataArray* globalCells = piece->GetCellData()->GetArray("GlobalCellIds");
    vtkDataArray* globalPoints = piece->GetPointData()->GetArray("GlobalPointIds");
    for (vtkIdType c = 0; c < local->GetNumberOfCells(); ++c)
    {
      EXPECT_EQ(cells->GetComponent(c, 0), globalCells->GetComponent(c, 0));
    }
    for (vtkIdType p = 0; p < local->GetNumberOfPoints(); ++p)
    {
      EXPECT_EQ(points->GetComponent(p, 0), 100.0 + globalPoints->GetComponent(p, 0));
    }
    // Winding in global point ids, as in the whole output.
    for (vtkIdType c = 0; c < local->GetNumberOfCells(); ++c)
    {
      const vtkIdType wholeCell = static_cast<vtkIdType>(globalCells->GetComponent(c, 0));
      std::vector<vtkIdType> ids = CellPoints(local, c);
      for (vtkIdType& p : ids)
      {
        p = static_cast<vtkIdType>(globalPoints->GetComponent(p, 0));
      }
      EXPECT_EQ(ids, CellPoints(output, wholeCell)) << "cell " << wholeCell;
    }
  }
}

TEST(WholeSurface, ApplyResultKeepsTheInputWhenNothingCameBack)
{
  const auto mesh = Mesh();
  vtkNew<vtkPolyData> nothing, local;
  ApplyResult(mesh, nothing, local);
  EXPECT_EQ(local->GetNumberOfCells(), mesh->GetNumberOfCells());
  EXPECT_NE(local->GetCellData()->GetArray("Value"), nullptr);
}

TEST(WholeSurface, LowestHolderOwnsACellSeveralPiecesHold)
{
  const auto mesh = Mesh();
  // Triangle 3 is in pieces of processes 2 and 1; an empty piece of process 0.
  const WholeSurface whole = AssembleWholeSurface(
    { Piece(mesh, { 2, 3 }, true), Piece(mesh, { 3, 4, 5 }, true), vtkSmartPointer<vtkPolyData>::New() });
  EXPECT_EQ(LowestHolders(whole, { 2, 1, 0 }), (std::vector<int>{ 2, 1, 1, 1 }));
  EXPECT_EQ(LowestHolders(whole, { 0, 1, 2 }), (std::vector<int>{ 0, 0, 1, 1 }));
}

TEST(WholeSurface, HaloSelectionAndExtractionKeepIdsAndArrays)
{
  const auto mesh = Mesh();
  // Triangles 2..5, centres (2/3, 1/3), (1/3, 2/3), (5/3, 1/3), (4/3, 2/3).
  const auto piece = Piece(mesh, { 2, 3, 4, 5 }, true);
  EXPECT_TRUE(HasGlobalIds(piece));
  EXPECT_FALSE(HasGlobalIds(Piece(mesh, { 2, 3 }, false)));
  const std::vector<double> centers = CellCenters(piece);
  ASSERT_EQ(centers.size(), 12u);
  EXPECT_NEAR(centers[0], 2.0 / 3.0, 1e-15);
  EXPECT_NEAR(centers[1], 1.0 / 3.0, 1e-15);
  const std::vector<double> bounds = CenterBounds(centers);
  EXPECT_NEAR(bounds[0], 1.0 / 3.0, 1e-15);
  EXPECT_NEAR(bounds[1], 5.0 / 3.0, 1e-15);
  EXPECT_EQ(bounds[4], 0.0);
  const std::vector<double> none = CenterBounds(CellCenters(vtkNew<vtkPolyData>()));
  EXPECT_GT(none[0], none[1]);

  // Voxels of 0.5 from the box's corner: the centres at x 1/3 and 2/3 (y 2/3 and 1/3) lie in
  // voxels (0, 1) and (1, 0), the ones at x 4/3 and 5/3 in (2, 1) and (3, 0).
  const VoxelGrid grid = VoxelGrid::Around({ 0.0, 2.0, 0.0, 1.0, 0.0, 0.0 }, 0.5);
  EXPECT_EQ(grid.Size, 0.5);
  EXPECT_EQ(VoxelGrid::Around({ 0.0, 1024.0, 0.0, 1.0, 0.0, 0.0 }, 0.5).Size, 2.0); // at most 512 along
  const std::vector<std::int64_t> voxels = CellVoxels(centers, grid);
  ASSERT_EQ(voxels.size(), 4u);
  EXPECT_EQ(std::set<std::int64_t>(voxels.begin(), voxels.end()).size(), 4u);
  // Near the first centre's voxel: itself and the second (a neighbour), not the two far ones.
  EXPECT_EQ(CellsNearVoxels(voxels, { voxels[1] }), (std::vector<vtkIdType>{ 0, 1 }));
  EXPECT_EQ(CellsNearVoxels(voxels, { voxels[2] }), (std::vector<vtkIdType>{ 2, 3 }));
  EXPECT_TRUE(CellsNearVoxels(voxels, {}).empty());
  // Every pair of centres within the voxel size is found, whatever the voxel boundaries.
  for (const double size : { 0.35, 0.5, 0.9 })
  {
    const VoxelGrid fine = VoxelGrid::Around({ -0.1, 2.0, 0.0, 1.0, 0.0, 0.0 }, size);
    const std::vector<std::int64_t> keys = CellVoxels(centers, fine);
    for (std::size_t a = 0; a < keys.size(); ++a)
    {
      const std::vector<vtkIdType> near = CellsNearVoxels(keys, { keys[a] });
      const double centers[4][2] = { { 2 / 3.0, 1 / 3.0 }, { 1 / 3.0, 2 / 3.0 }, { 5 / 3.0, 1 / 3.0 }, { 4 / 3.0, 2 / 3.0 } };
      for (std::size_t b = 0; b < keys.size(); ++b)
      {
        const double distance = std::hypot(centers[a][0] - centers[b][0], centers[a][1] - centers[b][1]);
        if (distance <= size)
        {
          EXPECT_TRUE(std::find(near.begin(), near.end(), static_cast<vtkIdType>(b)) != near.end())
            << "centres " << a << " and " << b << " at " << distance << ", voxels of " << size;
        }
      }
    }
  }

  // Shared corners: triangle 3 (0-4-3) shares only point 4 with the second piece's triangles
  // 4 (1-2-5) and 5 (1-5-4): fine voxels find triangle 5 alone, coarse ones a superset.
  const auto left = Piece(mesh, { 3 }, true);
  const auto right = Piece(mesh, { 4, 5 }, true);
  EXPECT_EQ(PointCoordinates(left).size(), 3 * static_cast<std::size_t>(left->GetNumberOfPoints()));
  for (const auto& [size, expected] :
    { std::pair{ 0.1, std::vector<vtkIdType>{ 1 } }, std::pair{ 5.0, std::vector<vtkIdType>{ 0, 1 } } })
  {
    const VoxelGrid cornerGrid = VoxelGrid::Around({ 0.0, 2.0, 0.0, 1.0, 0.0, 0.0 }, size);
    std::vector<std::int64_t> leftVoxels = CellVoxels(PointCoordinates(left), cornerGrid);
    std::sort(leftVoxels.begin(), leftVoxels.end());
    EXPECT_EQ(CellsWithCornerInVoxels(right, CellVoxels(PointCoordinates(right), cornerGrid), leftVoxels), expected)
      << "voxels of " << size;
    EXPECT_TRUE(CellsWithCornerInVoxels(right, CellVoxels(PointCoordinates(right), cornerGrid), {}).empty());
  }

  const auto extracted = ExtractPolygons(piece, { 1, 3 });
  ASSERT_EQ(extracted->GetNumberOfCells(), 2);
  ASSERT_EQ(extracted->GetNumberOfPoints(), 5); // triangles 0-4-3 and 1-5-4 share point 4
  // Its ids and arrays let AssembleWholeSurface put it back in place beside the other cells.
  const WholeSurface whole = AssembleWholeSurface({ extracted, ExtractPolygons(piece, { 0, 2 }) });
  EXPECT_EQ(whole.Cells, CellOrder::GlobalCellIds);
  EXPECT_EQ(whole.Points, PointOrder::GlobalPointIds);
  EXPECT_EQ(whole.CellToWhole[0], (std::vector<vtkIdType>{ 1, 3 }));
  vtkDataArray* value = whole.Mesh->GetCellData()->GetArray("Value");
  ASSERT_NE(value, nullptr);
  for (vtkIdType c = 0; c < 4; ++c)
  {
    EXPECT_EQ(value->GetComponent(c, 0), 10.0 * static_cast<double>(c + 2));
    EXPECT_EQ(CellPoints(whole.Mesh, c).size(), 3u);
  }
}
