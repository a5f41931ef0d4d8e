// SPDX-License-Identifier: BSD-3-Clause
#include "WholeSurface.h"

#include "vtkAbstractArray.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkDataSetAttributes.h"
#include "vtkFieldData.h"
#include "vtkIdList.h"
#include "vtkIntArray.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"

#include <algorithm>
#include <cmath>
#include <array>
#include <cstdint>
#include <cstring>
#include <limits>
#include <tuple>
#include <unordered_map>

namespace shapediameter::distributed
{
namespace
{
/// (piece, local id) of each whole cell or point.
using Sources = std::vector<std::pair<int, vtkIdType>>;

/// A single-component array of global ids: the GlobalIds attribute, else `name`.
vtkDataArray* IdArray(vtkDataSetAttributes* data, const char* name, vtkIdType count)
{
  vtkDataArray* ids = data->GetGlobalIds();
  if (!ids && name)
  {
    ids = data->GetArray(name);
  }
  return ids && ids->GetNumberOfComponents() == 1 && ids->GetNumberOfTuples() == count ? ids : nullptr;
}

/// True when two cells have the same corners (coordinates), in the same order.
bool SameCorners(vtkPolyData* a, vtkIdType cellA, vtkPolyData* b, vtkIdType cellB)
{
  vtkIdType countA, countB;
  const vtkIdType* idsA;
  const vtkIdType* idsB;
  a->GetCellPoints(cellA, countA, idsA);
  b->GetCellPoints(cellB, countB, idsB);
  if (countA != countB)
  {
    return false;
  }
  for (vtkIdType k = 0; k < countA; ++k)
  {
    double pa[3], pb[3];
    a->GetPoint(idsA[k], pa);
    b->GetPoint(idsB[k], pb);
    if (pa[0] != pb[0] || pa[1] != pb[1] || pa[2] != pb[2])
    {
      return false;
    }
  }
  return true;
}

struct CellEntry
{
  CellGroup Group;
  std::int64_t Key;
  int Ghost; // 1 for a duplicate copy of a cell owned by another process
  int Piece;
  vtkIdType Cell;
};

struct PointKeyHash
{
  std::size_t operator()(const std::array<double, 3>& p) const
  {
    std::size_t hash = 1469598103934665603ull;
    for (const double v : p)
    {
      std::uint64_t bits;
      std::memcpy(&bits, &v, sizeof(bits));
      hash = (hash ^ bits) * 1099511628211ull;
    }
    return hash;
  }
};

/// Every cell of the non-empty pieces keyed by `order`, sorted by (group, key, copy).
std::vector<CellEntry> SortedCells(
  const std::vector<vtkPolyData*>& pieces, const std::vector<int>& nonEmpty, CellOrder order)
{
  std::vector<CellEntry> entries;
  std::int64_t running = 0;
  for (const int r : nonEmpty)
  {
    vtkPolyData* piece = pieces[r];
    const vtkIdType n = piece->GetNumberOfCells();
    vtkDataArray* ids = order == CellOrder::GlobalCellIds ? IdArray(piece->GetCellData(), "GlobalCellIds", n)
      : order == CellOrder::OriginalCellIds             ? piece->GetCellData()->GetArray("vtkOriginalCellIds")
                                                        : nullptr;
    vtkDataArray* ghosts = piece->GetCellData()->GetArray(vtkDataSetAttributes::GhostArrayName());
    for (vtkIdType c = 0; c < n; ++c)
    {
      const int ghost =
        ghosts && (static_cast<int>(ghosts->GetComponent(c, 0)) & vtkDataSetAttributes::DUPLICATECELL) ? 1 : 0;
      entries.push_back({ CellGroupOf(piece->GetCellType(c)),
        ids ? static_cast<std::int64_t>(ids->GetComponent(c, 0)) : running++, ghost, r, c });
    }
  }
  std::sort(entries.begin(), entries.end(), [](const CellEntry& a, const CellEntry& b) {
    return std::tie(a.Group, a.Key, a.Ghost, a.Piece, a.Cell) < std::tie(b.Group, b.Key, b.Ghost, b.Piece, b.Cell);
  });
  return entries;
}

/// The cell order the pieces support (CellOrder's preference; `vtkOriginalCellIds` only
/// when equal ids always mean the same corners) and the cells sorted by it.
std::vector<CellEntry> OrderCells(
  const std::vector<vtkPolyData*>& pieces, const std::vector<int>& nonEmpty, CellOrder& order)
{
  bool globalCellIds = true, originalCellIds = true;
  for (const int r : nonEmpty)
  {
    const vtkIdType n = pieces[r]->GetNumberOfCells();
    globalCellIds = globalCellIds && IdArray(pieces[r]->GetCellData(), "GlobalCellIds", n);
    vtkDataArray* original = pieces[r]->GetCellData()->GetArray("vtkOriginalCellIds");
    originalCellIds =
      originalCellIds && original && original->GetNumberOfComponents() == 1 && original->GetNumberOfTuples() == n;
  }
  if (globalCellIds)
  {
    order = CellOrder::GlobalCellIds;
    return SortedCells(pieces, nonEmpty, order);
  }
  if (originalCellIds)
  {
    // RedistributeDataSet's ids of the cells in the piece they came from: global when one
    // process held the whole input (a reader that reads on piece 0 only); check they are distinct.
    std::vector<CellEntry> entries = SortedCells(pieces, nonEmpty, CellOrder::OriginalCellIds);
    bool distinct = true;
    for (std::size_t i = 1; i < entries.size() && distinct; ++i)
    {
      // Equal ids are fine for copies of one boundary cell (same corners), not otherwise.
      distinct = !(entries[i].Key == entries[i - 1].Key && entries[i].Group == entries[i - 1].Group &&
        !SameCorners(pieces[entries[i].Piece], entries[i].Cell, pieces[entries[i - 1].Piece], entries[i - 1].Cell));
    }
    if (distinct)
    {
      order = CellOrder::OriginalCellIds;
      return entries;
    }
  }
  order = CellOrder::ProcessOrder;
  return SortedCells(pieces, nonEmpty, order);
}

/// Sorted cells → the whole surface's cells (each key once) and every piece's cell map.
Sources KeepCellsOnce(const std::vector<CellEntry>& entries, std::vector<std::vector<vtkIdType>>& cellToWhole)
{
  Sources cellSource;
  cellSource.reserve(entries.size());
  for (std::size_t i = 0; i < entries.size(); ++i)
  {
    const CellEntry& e = entries[i];
    if (i == 0 || e.Group != entries[i - 1].Group || e.Key != entries[i - 1].Key)
    {
      cellSource.emplace_back(e.Piece, e.Cell);
    }
    cellToWhole[e.Piece][static_cast<std::size_t>(e.Cell)] = static_cast<vtkIdType>(cellSource.size()) - 1;
  }
  return cellSource;
}

/// The whole surface's points: by global id, else by identical coordinates in order of
/// first use by `cellSource`; fills every piece's point map.
Sources MergePoints(const std::vector<vtkPolyData*>& pieces, const std::vector<int>& nonEmpty,
  const Sources& cellSource, WholeSurface& whole)
{
  bool globalPointIds = true;
  for (const int r : nonEmpty)
  {
    globalPointIds = globalPointIds && IdArray(pieces[r]->GetPointData(), "GlobalPointIds", pieces[r]->GetNumberOfPoints());
  }
  Sources pointSource;
  if (globalPointIds)
  {
    whole.Points = PointOrder::GlobalPointIds;
    std::vector<std::tuple<std::int64_t, int, vtkIdType>> points;
    for (const int r : nonEmpty)
    {
      const vtkIdType n = pieces[r]->GetNumberOfPoints();
      vtkDataArray* ids = IdArray(pieces[r]->GetPointData(), "GlobalPointIds", n);
      for (vtkIdType p = 0; p < n; ++p)
      {
        points.emplace_back(static_cast<std::int64_t>(ids->GetComponent(p, 0)), r, p);
      }
    }
    std::sort(points.begin(), points.end());
    for (std::size_t i = 0; i < points.size(); ++i)
    {
      const auto& [key, r, p] = points[i];
      if (i == 0 || key != std::get<0>(points[i - 1]))
      {
        pointSource.emplace_back(r, p);
      }
      whole.PointToWhole[r][static_cast<std::size_t>(p)] = static_cast<vtkIdType>(pointSource.size()) - 1;
    }
    return pointSource;
  }
  whole.Points = PointOrder::Coordinates;
  std::unordered_map<std::array<double, 3>, vtkIdType, PointKeyHash> index;
  auto assign = [&](int r, vtkIdType p) {
    if (whole.PointToWhole[r][static_cast<std::size_t>(p)] >= 0)
    {
      return;
    }
    std::array<double, 3> x;
    pieces[r]->GetPoint(p, x.data());
    const auto [it, inserted] = index.emplace(x, static_cast<vtkIdType>(pointSource.size()));
    if (inserted)
    {
      pointSource.emplace_back(r, p);
    }
    whole.PointToWhole[r][static_cast<std::size_t>(p)] = it->second;
  };
  for (const auto& [r, c] : cellSource)
  {
    vtkIdType count;
    const vtkIdType* ids;
    pieces[r]->GetCellPoints(c, count, ids);
    for (vtkIdType k = 0; k < count; ++k)
    {
      assign(r, ids[k]);
    }
  }
  // Duplicated cells on other pieces and unused points.
  for (const int r : nonEmpty)
  {
    for (vtkIdType p = 0; p < pieces[r]->GetNumberOfPoints(); ++p)
    {
      assign(r, p);
    }
  }
  return pointSource;
}

/// Points and cells of the whole mesh from their sources.
void BuildGeometry(const std::vector<vtkPolyData*>& pieces, const std::vector<int>& nonEmpty,
  const Sources& cellSource, const Sources& pointSource, WholeSurface& whole)
{
  vtkPolyData* mesh = whole.Mesh;
  vtkNew<vtkPoints> points;
  for (const int r : nonEmpty)
  {
    if (pieces[r]->GetPoints())
    {
      points->SetDataType(pieces[r]->GetPoints()->GetDataType());
      break;
    }
  }
  points->SetNumberOfPoints(static_cast<vtkIdType>(pointSource.size()));
  for (std::size_t w = 0; w < pointSource.size(); ++w)
  {
    points->SetPoint(static_cast<vtkIdType>(w), pieces[pointSource[w].first]->GetPoint(pointSource[w].second));
  }
  mesh->SetPoints(points);

  vtkNew<vtkCellArray> verts, lines, polys, strips;
  vtkCellArray* groups[4] = { verts, lines, polys, strips };
  std::vector<vtkIdType> mapped;
  for (const auto& [r, c] : cellSource)
  {
    vtkIdType count;
    const vtkIdType* ids;
    pieces[r]->GetCellPoints(c, count, ids);
    mapped.resize(static_cast<std::size_t>(count));
    for (vtkIdType k = 0; k < count; ++k)
    {
      mapped[static_cast<std::size_t>(k)] = whole.PointToWhole[r][static_cast<std::size_t>(ids[k])];
    }
    groups[static_cast<int>(CellGroupOf(pieces[r]->GetCellType(c)))]->InsertNextCell(count, mapped.data());
  }
  if (verts->GetNumberOfCells() > 0)
  {
    mesh->SetVerts(verts);
  }
  if (lines->GetNumberOfCells() > 0)
  {
    mesh->SetLines(lines);
  }
  if (polys->GetNumberOfCells() > 0)
  {
    mesh->SetPolys(polys);
  }
  if (strips->GetNumberOfCells() > 0)
  {
    mesh->SetStrips(strips);
  }
}

/// The arrays common to every non-empty piece, taken from each whole element's source,
/// without the ghost-type array.
template <typename GetAttributes>
void CopyCommonArrays(const std::vector<vtkPolyData*>& pieces, const std::vector<int>& nonEmpty,
  GetAttributes getAttributes, const Sources& source, vtkDataSetAttributes* target)
{
  vtkDataSetAttributes::FieldList list(static_cast<int>(nonEmpty.size()));
  std::vector<int> listIndex(pieces.size(), -1);
  for (std::size_t k = 0; k < nonEmpty.size(); ++k)
  {
    listIndex[static_cast<std::size_t>(nonEmpty[k])] = static_cast<int>(k);
    if (k == 0)
    {
      list.InitializeFieldList(getAttributes(pieces[nonEmpty[k]]));
    }
    else
    {
      list.IntersectFieldList(getAttributes(pieces[nonEmpty[k]]));
    }
  }
  target->CopyAllocate(list, static_cast<vtkIdType>(source.size()));
  // Runs of whole elements that come from consecutive elements of one piece are copied at once
  // (a tuple at a time through the field list cost most of the assembly).
  for (std::size_t begin = 0; begin < source.size();)
  {
    const auto& [r, id] = source[begin];
    std::size_t end = begin + 1;
    while (end < source.size() && source[end].first == r &&
      source[end].second == id + static_cast<vtkIdType>(end - begin))
    {
      ++end;
    }
    target->CopyData(list, getAttributes(pieces[r]), listIndex[static_cast<std::size_t>(r)],
      static_cast<vtkIdType>(begin), static_cast<vtkIdType>(end - begin), id);
    begin = end;
  }
  target->RemoveArray(vtkDataSetAttributes::GhostArrayName());
}

/// True when `array` is one of the arrays of `attributes` (the same object, not a copy).
bool Holds(vtkFieldData* attributes, vtkAbstractArray* array)
{
  for (int a = 0; a < attributes->GetNumberOfArrays(); ++a)
  {
    if (attributes->GetAbstractArray(a) == array)
    {
      return true;
    }
  }
  return false;
}

/// Adds to `target` every array of `source` that the filter made (not passed through from
/// `passed`), taken at `indices`, with its attribute role.
void AddMapped(vtkDataSetAttributes* source, vtkDataSetAttributes* passed, const std::vector<vtkIdType>& indices,
  vtkDataSetAttributes* target)
{
  vtkNew<vtkIdList> ids;
  ids->SetNumberOfIds(static_cast<vtkIdType>(indices.size()));
  std::copy(indices.begin(), indices.end(), ids->GetPointer(0));
  for (int a = 0; a < source->GetNumberOfArrays(); ++a)
  {
    vtkAbstractArray* array = source->GetAbstractArray(a);
    if (Holds(passed, array))
    {
      continue;
    }
    auto copy = vtkSmartPointer<vtkAbstractArray>::Take(array->NewInstance());
    copy->SetName(array->GetName());
    copy->SetNumberOfComponents(array->GetNumberOfComponents());
    copy->CopyComponentNames(array);
    copy->SetNumberOfTuples(ids->GetNumberOfIds());
    if (ids->GetNumberOfIds() > 0)
    {
      array->GetTuples(ids, copy);
    }
    target->AddArray(copy);
  }
  for (int attribute = 0; attribute < vtkDataSetAttributes::NUM_ATTRIBUTES; ++attribute)
  {
    vtkAbstractArray* active = source->GetAbstractAttribute(attribute);
    if (active && active->GetName() && target->GetAbstractArray(active->GetName()))
    {
      target->SetActiveAttribute(active->GetName(), attribute);
    }
  }
}

/// Adds every array of `source` to `target` (replacing same names), with its attribute role.
void AddAll(vtkDataSetAttributes* source, vtkDataSetAttributes* target)
{
  for (int a = 0; a < source->GetNumberOfArrays(); ++a)
  {
    target->AddArray(source->GetAbstractArray(a));
  }
  for (int attribute = 0; attribute < vtkDataSetAttributes::NUM_ATTRIBUTES; ++attribute)
  {
    vtkAbstractArray* active = source->GetAbstractAttribute(attribute);
    if (active && active->GetName())
    {
      target->SetActiveAttribute(active->GetName(), attribute);
    }
  }
}

/// The piece's polygons with the winding of the whole output (the SDF filter's AutoOrient).
vtkSmartPointer<vtkCellArray> RewoundPolygons(
  vtkPolyData* piece, vtkPolyData* wholeOutput, const std::vector<vtkIdType>& cellToWhole,
  const std::vector<vtkIdType>& pointToWhole)
{
  auto polygons = vtkSmartPointer<vtkCellArray>::New();
  const vtkIdType first = piece->GetNumberOfVerts() + piece->GetNumberOfLines();
  std::vector<vtkIdType> local;
  for (vtkIdType c = first; c < first + piece->GetNumberOfPolys(); ++c)
  {
    vtkIdType count, wholeCount;
    const vtkIdType* ids;
    const vtkIdType* wholeIds;
    piece->GetCellPoints(c, count, ids);
    wholeOutput->GetCellPoints(cellToWhole[static_cast<std::size_t>(c)], wholeCount, wholeIds);
    local.assign(ids, ids + count);
    if (wholeCount == count)
    {
      for (vtkIdType k = 0; k < count; ++k)
      {
        for (vtkIdType j = 0; j < count; ++j)
        {
          if (pointToWhole[static_cast<std::size_t>(ids[j])] == wholeIds[k])
          {
            local[static_cast<std::size_t>(k)] = ids[j];
            break;
          }
        }
      }
    }
    polygons->InsertNextCell(count, local.data());
  }
  return polygons;
}

/// Field array marking a result whose polygons carry the whole output's winding.
constexpr const char* REWOUND_MARKER = "__ShapeDiameterDistributedRewound";

} // namespace

CellGroup CellGroupOf(int cellType)
{
  switch (cellType)
  {
    case VTK_VERTEX:
    case VTK_POLY_VERTEX:
      return CellGroup::Vertices;
    case VTK_LINE:
    case VTK_POLY_LINE:
      return CellGroup::Lines;
    case VTK_TRIANGLE_STRIP:
      return CellGroup::Strips;
    default:
      return CellGroup::Polygons;
  }
}

const char* ToString(CellOrder order)
{
  switch (order)
  {
    case CellOrder::GlobalCellIds:
      return "global cell ids";
    case CellOrder::OriginalCellIds:
      return "vtkOriginalCellIds";
    case CellOrder::ProcessOrder:
      break;
  }
  return "process order (no global cell ids)";
}

const char* ToString(PointOrder order)
{
  return order == PointOrder::GlobalPointIds ? "global point ids" : "coordinates (no global point ids)";
}

WholeSurface AssembleWholeSurface(const std::vector<vtkPolyData*>& pieces)
{
  WholeSurface whole;
  whole.CellToWhole.resize(pieces.size());
  whole.PointToWhole.resize(pieces.size());
  std::vector<int> nonEmpty;
  for (int r = 0; r < static_cast<int>(pieces.size()); ++r)
  {
    whole.CellToWhole[r].assign(static_cast<std::size_t>(pieces[r]->GetNumberOfCells()), -1);
    whole.PointToWhole[r].assign(static_cast<std::size_t>(pieces[r]->GetNumberOfPoints()), -1);
    if (pieces[r]->GetNumberOfCells() > 0 || pieces[r]->GetNumberOfPoints() > 0)
    {
      nonEmpty.push_back(r);
    }
  }
  if (nonEmpty.empty())
  {
    return whole;
  }
  const Sources cellSource = KeepCellsOnce(OrderCells(pieces, nonEmpty, whole.Cells), whole.CellToWhole);
  const Sources pointSource = MergePoints(pieces, nonEmpty, cellSource, whole);
  BuildGeometry(pieces, nonEmpty, cellSource, pointSource, whole);
  CopyCommonArrays(pieces, nonEmpty, [](vtkPolyData* p) -> vtkDataSetAttributes* { return p->GetPointData(); },
    pointSource, whole.Mesh->GetPointData());
  CopyCommonArrays(pieces, nonEmpty, [](vtkPolyData* p) -> vtkDataSetAttributes* { return p->GetCellData(); },
    cellSource, whole.Mesh->GetCellData());
  whole.Mesh->GetFieldData()->ShallowCopy(pieces[nonEmpty.front()]->GetFieldData());
  return whole;
}

std::vector<int> LowestHolders(const WholeSurface& whole, const std::vector<int>& pieceProcess)
{
  std::vector<int> holder(static_cast<std::size_t>(whole.Mesh->GetNumberOfCells()), -1);
  for (std::size_t k = 0; k < whole.CellToWhole.size(); ++k)
  {
    for (const vtkIdType cell : whole.CellToWhole[k])
    {
      if (cell < 0)
      {
        continue;
      }
      int& lowest = holder[static_cast<std::size_t>(cell)];
      lowest = lowest < 0 ? pieceProcess[k] : std::min(lowest, pieceProcess[k]);
    }
  }
  return holder;
}

vtkSmartPointer<vtkPolyData> LocalResult(vtkPolyData* piece, vtkPolyData* wholeInput, vtkPolyData* wholeOutput,
  const std::vector<vtkIdType>& cellToWhole, const std::vector<vtkIdType>& pointToWhole)
{
  auto result = vtkSmartPointer<vtkPolyData>::New();
  result->CopyStructure(piece);
  AddMapped(wholeOutput->GetCellData(), wholeInput->GetCellData(), cellToWhole, result->GetCellData());
  AddMapped(wholeOutput->GetPointData(), wholeInput->GetPointData(), pointToWhole, result->GetPointData());
  vtkNew<vtkFieldData> field;
  field->ShallowCopy(wholeOutput->GetFieldData());
  if (wholeOutput->GetPolys() != wholeInput->GetPolys() && piece->GetNumberOfPolys() > 0 &&
    wholeOutput->GetNumberOfPolys() > 0 && wholeOutput->GetNumberOfCells() == wholeInput->GetNumberOfCells())
  {
    result->SetPolys(RewoundPolygons(piece, wholeOutput, cellToWhole, pointToWhole));
    vtkNew<vtkIntArray> marker;
    marker->SetName(REWOUND_MARKER);
    marker->InsertNextValue(1);
    field->AddArray(marker);
  }
  result->SetFieldData(field);
  return result;
}

bool HasGlobalIds(vtkPolyData* piece)
{
  return IdArray(piece->GetCellData(), "GlobalCellIds", piece->GetNumberOfCells()) &&
    IdArray(piece->GetPointData(), "GlobalPointIds", piece->GetNumberOfPoints());
}

namespace
{
/// Per element of the whole surface: the id in `name` (the GlobalIds attribute first) of the
/// piece elements mapped to it (`toWhole`, per piece), -1 where none is.
std::vector<std::int64_t> WholeIds(vtkIdType wholeCount, const std::vector<vtkPolyData*>& pieces,
  const std::vector<std::vector<vtkIdType>>& toWhole, bool cells)
{
  std::vector<std::int64_t> ids(static_cast<std::size_t>(wholeCount), -1);
  for (std::size_t r = 0; r < pieces.size() && r < toWhole.size(); ++r)
  {
    vtkDataArray* pieceIds = cells
      ? IdArray(pieces[r]->GetCellData(), "GlobalCellIds", pieces[r]->GetNumberOfCells())
      : IdArray(pieces[r]->GetPointData(), "GlobalPointIds", pieces[r]->GetNumberOfPoints());
    for (std::size_t i = 0; pieceIds && i < toWhole[r].size(); ++i)
    {
      if (toWhole[r][i] >= 0)
      {
        ids[static_cast<std::size_t>(toWhole[r][i])] =
          static_cast<std::int64_t>(pieceIds->GetComponent(static_cast<vtkIdType>(i), 0));
      }
    }
  }
  return ids;
}
} // namespace

std::vector<std::int64_t> WholeGlobalCellIds(const WholeSurface& whole, const std::vector<vtkPolyData*>& pieces)
{
  return WholeIds(whole.Mesh->GetNumberOfCells(), pieces, whole.CellToWhole, true);
}

std::vector<std::int64_t> WholeGlobalPointIds(const WholeSurface& whole, const std::vector<vtkPolyData*>& pieces)
{
  return WholeIds(whole.Mesh->GetNumberOfPoints(), pieces, whole.PointToWhole, false);
}

std::vector<double> CellCenters(vtkPolyData* piece)
{
  std::vector<double> centers(3 * static_cast<std::size_t>(piece->GetNumberOfCells()), 0.0);
  for (vtkIdType cell = 0; cell < piece->GetNumberOfCells(); ++cell)
  {
    vtkIdType count = 0;
    const vtkIdType* corners = nullptr;
    piece->GetCellPoints(cell, count, corners);
    double* center = &centers[3 * static_cast<std::size_t>(cell)];
    for (vtkIdType k = 0; k < count; ++k)
    {
      double point[3];
      piece->GetPoint(corners[k], point);
      for (int axis = 0; axis < 3; ++axis)
      {
        center[axis] += point[axis];
      }
    }
    for (int axis = 0; count > 0 && axis < 3; ++axis)
    {
      center[axis] /= static_cast<double>(count);
    }
  }
  return centers;
}

std::vector<double> CenterBounds(const std::vector<double>& centers)
{
  const double infinity = std::numeric_limits<double>::infinity();
  std::vector<double> bounds{ infinity, -infinity, infinity, -infinity, infinity, -infinity };
  for (std::size_t i = 0; i < centers.size(); ++i)
  {
    const std::size_t axis = i % 3;
    bounds[2 * axis] = std::min(bounds[2 * axis], centers[i]);
    bounds[2 * axis + 1] = std::max(bounds[2 * axis + 1], centers[i]);
  }
  return bounds;
}

VoxelGrid VoxelGrid::Around(const std::vector<double>& bounds, double distance)
{
  VoxelGrid grid;
  double longest = 0.0;
  for (int axis = 0; axis < 3; ++axis)
  {
    const bool valid = bounds[2 * axis] <= bounds[2 * axis + 1];
    grid.Origin[axis] = valid ? bounds[2 * axis] : 0.0;
    longest = valid ? std::max(longest, bounds[2 * axis + 1] - bounds[2 * axis]) : longest;
  }
  // At most 512 voxels along the longest side: a surface then occupies a few million voxels at
  // most, few enough keys to send every process, and the halo stays thin against a piece.
  grid.Size = std::max({ distance, longest / 512.0, std::numeric_limits<double>::min() });
  return grid;
}

namespace
{
constexpr int VoxelBits = 21;
constexpr std::int64_t VoxelMask = (std::int64_t{ 1 } << VoxelBits) - 1;

/// Index (i, j, k) >= 0 packed into one key; the neighbours' keys differ by +-1 in a field.
std::int64_t VoxelKey(std::int64_t i, std::int64_t j, std::int64_t k)
{
  return (i << (2 * VoxelBits)) | (j << VoxelBits) | k;
}
} // namespace

std::vector<std::int64_t> CellVoxels(const std::vector<double>& centers, const VoxelGrid& grid)
{
  std::vector<std::int64_t> keys(centers.size() / 3);
  for (std::size_t cell = 0; cell < keys.size(); ++cell)
  {
    std::int64_t index[3];
    for (int axis = 0; axis < 3; ++axis)
    {
      // +1: the neighbours of the first voxel keep non-negative indices.
      const double position = std::floor((centers[3 * cell + axis] - grid.Origin[axis]) / grid.Size) + 1.0;
      index[axis] = static_cast<std::int64_t>(std::clamp(position, 1.0, static_cast<double>(VoxelMask - 1)));
    }
    keys[cell] = VoxelKey(index[0], index[1], index[2]);
  }
  return keys;
}

std::vector<double> PointCoordinates(vtkPolyData* piece)
{
  std::vector<double> coordinates(3 * static_cast<std::size_t>(piece->GetNumberOfPoints()));
  for (vtkIdType p = 0; p < piece->GetNumberOfPoints(); ++p)
  {
    piece->GetPoint(p, &coordinates[3 * static_cast<std::size_t>(p)]);
  }
  return coordinates;
}

std::vector<vtkIdType> CellsWithCornerInVoxels(
  vtkPolyData* piece, const std::vector<std::int64_t>& pointVoxels, const std::vector<std::int64_t>& voxels)
{
  std::vector<char> inVoxels(pointVoxels.size(), 0);
  for (std::size_t p = 0; p < pointVoxels.size(); ++p)
  {
    inVoxels[p] = std::binary_search(voxels.begin(), voxels.end(), pointVoxels[p]) ? 1 : 0;
  }
  std::vector<vtkIdType> cells;
  for (vtkIdType cell = 0; cell < piece->GetNumberOfCells(); ++cell)
  {
    vtkIdType count = 0;
    const vtkIdType* corners = nullptr;
    piece->GetCellPoints(cell, count, corners);
    if (std::any_of(corners, corners + count, [&](vtkIdType p) { return inVoxels[static_cast<std::size_t>(p)] != 0; }))
    {
      cells.push_back(cell);
    }
  }
  return cells;
}

std::vector<vtkIdType> CellsNearVoxels(const std::vector<std::int64_t>& cellVoxels, const std::vector<std::int64_t>& voxels)
{
  std::vector<std::int64_t> own(cellVoxels);
  std::sort(own.begin(), own.end());
  own.erase(std::unique(own.begin(), own.end()), own.end());
  std::vector<std::int64_t> near;
  for (const std::int64_t key : own)
  {
    const std::int64_t i = key >> (2 * VoxelBits), j = (key >> VoxelBits) & VoxelMask, k = key & VoxelMask;
    bool touches = false;
    for (int di = -1; di <= 1 && !touches; ++di)
    {
      for (int dj = -1; dj <= 1 && !touches; ++dj)
      {
        for (int dk = -1; dk <= 1 && !touches; ++dk)
        {
          touches = std::binary_search(voxels.begin(), voxels.end(), VoxelKey(i + di, j + dj, k + dk));
        }
      }
    }
    if (touches)
    {
      near.push_back(key);
    }
  }
  std::vector<vtkIdType> cells;
  for (std::size_t cell = 0; cell < cellVoxels.size(); ++cell)
  {
    if (std::binary_search(near.begin(), near.end(), cellVoxels[cell]))
    {
      cells.push_back(static_cast<vtkIdType>(cell));
    }
  }
  return cells;
}

vtkSmartPointer<vtkPolyData> ExtractPolygons(vtkPolyData* piece, const std::vector<vtkIdType>& cells)
{
  auto extracted = vtkSmartPointer<vtkPolyData>::New();
  // CopyCells makes float points unless the output has points of the input's type already.
  vtkNew<vtkPoints> points;
  points->SetDataType(piece->GetPoints() ? piece->GetPoints()->GetDataType() : VTK_DOUBLE);
  extracted->SetPoints(points);
  extracted->AllocateEstimate(static_cast<vtkIdType>(cells.size()), 3);
  extracted->GetCellData()->CopyGlobalIdsOn(); // ids are labels: VTK does not copy them unless asked
  extracted->GetCellData()->CopyAllocate(piece->GetCellData(), static_cast<vtkIdType>(cells.size()));
  extracted->GetPointData()->CopyGlobalIdsOn();
  extracted->GetPointData()->CopyAllocate(piece->GetPointData());
  vtkNew<vtkIdList> ids;
  ids->SetNumberOfIds(static_cast<vtkIdType>(cells.size()));
  std::copy(cells.begin(), cells.end(), ids->GetPointer(0));
  // The points each cell uses, once, in order of first use.
  extracted->CopyCells(piece, ids);
  return extracted;
}

void ApplyResult(vtkPolyData* input, vtkPolyData* result, vtkDataObject* outputObject)
{
  vtkPolyData* output = vtkPolyData::SafeDownCast(outputObject);
  if (!output)
  {
    return;
  }
  if (input)
  {
    output->ShallowCopy(input);
  }
  else
  {
    output->Initialize();
  }
  if (!result || result->GetNumberOfCells() != output->GetNumberOfCells() ||
    result->GetNumberOfPoints() != output->GetNumberOfPoints())
  {
    return; // nothing usable came back (the piece was empty)
  }
  AddAll(result->GetCellData(), output->GetCellData());
  AddAll(result->GetPointData(), output->GetPointData());
  vtkNew<vtkFieldData> field;
  field->ShallowCopy(result->GetFieldData());
  if (field->GetAbstractArray(REWOUND_MARKER))
  {
    field->RemoveArray(REWOUND_MARKER);
    output->SetPolys(result->GetPolys());
  }
  output->SetFieldData(field);
}

} // namespace shapediameter::distributed
