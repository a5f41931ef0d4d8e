// SPDX-License-Identifier: BSD-3-Clause
// The whole-surface assembly and scatter mapping of distributed runs, as pure functions of
// VTK data: no controller, no MPI. DistributedSupport.cxx moves the pieces between the
// processes and calls these; Testing/Filters/TestWholeSurface.cxx tests them on one process.
//
// Private to the module: not installed, not wrapped.
#pragma once

#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkType.h"

#include <cstdint>
#include <utility>
#include <vector>

class vtkDataObject;

namespace shapediameter::distributed
{

/// vtkPolyData numbers its cells by group: verts, then lines, then polygons, then strips.
enum class CellGroup : int
{
  Vertices = 0,
  Lines = 1,
  Polygons = 2,
  Strips = 3
};

/// The group of a VTK cell type (every type that is no vertex, line or strip is a polygon).
CellGroup CellGroupOf(int cellType);

/// What orders the cells of the whole surface, in order of preference.
enum class CellOrder : int
{
  GlobalCellIds,     ///< the cell GlobalIds attribute, else the reader's `GlobalCellIds`
  OriginalCellIds,   ///< RedistributeDataSet's `vtkOriginalCellIds` (see AssembleWholeSurface)
  ProcessOrder       ///< no ids: process by process, each in its own order
};

/// How the points of the whole surface were merged.
enum class PointOrder : int
{
  GlobalPointIds,    ///< the point GlobalIds attribute, else the reader's `GlobalPointIds`
  Coordinates        ///< identical coordinates, in order of first use by the ordered cells
};

const char* ToString(CellOrder order);
const char* ToString(PointOrder order);

/// The whole surface and where each piece's cells and points went.
struct WholeSurface
{
  vtkSmartPointer<vtkPolyData> Mesh = vtkSmartPointer<vtkPolyData>::New();
  /// Per piece, per local cell / point: its id in Mesh.
  std::vector<std::vector<vtkIdType>> CellToWhole, PointToWhole;
  CellOrder Cells = CellOrder::ProcessOrder;
  PointOrder Points = PointOrder::Coordinates;
};

/**
 * The pieces of a distributed surface (one per process, empty ones allowed) as one mesh:
 * cells sorted by global id (CellOrder; `vtkOriginalCellIds` only when equal ids always
 * mean the same corners), a cell present on several pieces kept once (the copy not marked
 * DUPLICATECELL first); points merged by global id (PointOrder) and sorted by it, else by
 * identical coordinates; the cell and point arrays that every non-empty piece has, without
 * ghost-type arrays; the field data of the first non-empty piece.
 */
WholeSurface AssembleWholeSurface(const std::vector<vtkPolyData*>& pieces);

/**
 * Per cell of `whole`: the lowest process among those whose piece holds it (the cell's owner
 * when several pieces hold it, e.g. RedistributeDataSet's "assign to all regions"); -1 for
 * none. `pieceProcess` gives the process of each piece AssembleWholeSurface got.
 */
std::vector<int> LowestHolders(const WholeSurface& whole, const std::vector<int>& pieceProcess);

/**
 * What one process gets back from the filter's output on the whole surface: the piece's
 * geometry, the arrays the filter made (those of `wholeOutput` not passed through from
 * `wholeInput`) on the piece's cells and points, the whole output's field data, and the
 * polygons with the whole output's winding when the filter changed it.
 */
vtkSmartPointer<vtkPolyData> LocalResult(vtkPolyData* piece, vtkPolyData* wholeInput, vtkPolyData* wholeOutput,
  const std::vector<vtkIdType>& cellToWhole, const std::vector<vtkIdType>& pointToWhole);

/// A process's output: its own `input` plus the arrays (and winding) of its LocalResult;
/// just the input when `result` does not match it (nothing usable came back).
void ApplyResult(vtkPolyData* input, vtkPolyData* result, vtkDataObject* output);

/// True when the piece has global ids for its cells and its points (the GlobalIds attributes,
/// else the reader's `GlobalCellIds` and `GlobalPointIds`): AssembleWholeSurface then orders
/// any set of pieces' cells and points as the whole surface orders them.
bool HasGlobalIds(vtkPolyData* piece);

/// Per cell of `whole`, assembled from `pieces` that all have global ids (HasGlobalIds): its
/// global cell id.
std::vector<std::int64_t> WholeGlobalCellIds(const WholeSurface& whole, const std::vector<vtkPolyData*>& pieces);

/// Per point of `whole`, assembled from `pieces` that all have global ids: its global point id.
std::vector<std::int64_t> WholeGlobalPointIds(const WholeSurface& whole, const std::vector<vtkPolyData*>& pieces);

/// The centre (mean of the corners; the origin without corners) of each of the piece's cells,
/// x y z per cell.
std::vector<double> CellCenters(vtkPolyData* piece);

/// The bounding box (xmin, xmax, ymin, ymax, zmin, zmax) of CellCenters; inverted (min > max)
/// when there are none.
std::vector<double> CenterBounds(const std::vector<double>& centers);

/// Cubic voxels over space, the same on every process, for finding the cells near another
/// process's cells without sending all of them: two centres within Size of each other lie in
/// the same or neighbouring voxels.
struct VoxelGrid
{
  double Origin[3] = { 0.0, 0.0, 0.0 };
  double Size = 1.0;
  /// A grid over `bounds` (CenterBounds of every process, combined) whose voxels are at
  /// least `distance` wide, and at most 512 along the bounds' longest side.
  static VoxelGrid Around(const std::vector<double>& bounds, double distance);
};

/// Per position (x y z each: CellCenters, PointCoordinates): the key of the voxel holding it.
std::vector<std::int64_t> CellVoxels(const std::vector<double>& centers, const VoxelGrid& grid);

/// The piece's cells (given their CellVoxels) whose voxel is, or touches, one of `voxels`
/// (sorted keys, e.g. another process's occupied voxels): a superset of the cells whose centre
/// lies within grid.Size of a centre in those voxels.
std::vector<vtkIdType> CellsNearVoxels(const std::vector<std::int64_t>& cellVoxels, const std::vector<std::int64_t>& voxels);

/// The coordinates of the piece's points, x y z per point.
std::vector<double> PointCoordinates(vtkPolyData* piece);

/// The piece's cells one of whose corners lies in one of `voxels` (sorted keys, e.g. the
/// voxels holding another process's points), given the voxel of each of the piece's points
/// (CellVoxels of PointCoordinates): every cell sharing a corner with one of that process's
/// cells, since a shared corner has the same coordinates, hence the same voxel, on both.
std::vector<vtkIdType> CellsWithCornerInVoxels(
  vtkPolyData* piece, const std::vector<std::int64_t>& pointVoxels, const std::vector<std::int64_t>& voxels);

/// The piece's polygons `cells` with the points they use, as a polydata with the piece's cell
/// and point arrays on them.
vtkSmartPointer<vtkPolyData> ExtractPolygons(vtkPolyData* piece, const std::vector<vtkIdType>& cells);

} // namespace shapediameter::distributed
