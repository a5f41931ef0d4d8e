// SPDX-License-Identifier: BSD-3-Clause
// Conversion between vtkPolyData and the VTK-free core, shared by the filters.
// Private to the module: not installed, not wrapped.
#pragma once

#include "Mesh/MeshTypes.h"
#include "Parallel.h"

#include "vtkSmartPointer.h"
#include "vtkType.h"

#include <algorithm>

#include <string>
#include <utility>
#include <vector>

class vtkAlgorithm;
class vtkPolyData;

namespace shapediameter::adapter
{

/**
 * The surface part of a vtkPolyData as the core sees it: every polygon and
 * triangle-strip cell split into triangles (polygons by a fan from their first
 * point, strips with alternating winding so every triangle keeps the strip's
 * orientation). Vertices and lines own no triangle. Cell ids are the input's:
 * verts, then lines, then polys, then strips (vtkPolyData's numbering).
 */
struct TriangulatedSurface
{
  PointMatrix Points;
  TriangleMatrix Triangles;
  /// Input cell id of each triangle.
  std::vector<vtkIdType> TriangleCell;
  /// Size NumberOfCells + 1: the triangles of cell c are [CellFirstTriangle[c], CellFirstTriangle[c+1]).
  std::vector<std::int64_t> CellFirstTriangle;

  vtkIdType NumberOfCells() const { return static_cast<vtkIdType>(this->CellFirstTriangle.size()) - 1; }
};

/**
 * Fills `surface` from `input`. Returns an empty string on success, otherwise the
 * one-line reason the input cannot be processed (no polygon or strip, or a
 * non-finite coordinate used by one). Points that no polygon uses are copied as
 * (0, 0, 0) when their coordinates are not finite.
 */
std::string Triangulate(vtkPolyData* input, TriangulatedSurface& surface);

/// The input's points as an n x 3 double matrix (empty without points).
PointMatrix PointsOf(vtkPolyData* input);

/**
 * Every cell as a polygon in CSR form, in cell-id order: polygons with their points,
 * every other cell (vertex, line, strip) empty, so it has no neighbour in a FaceGraph
 * and keeps its id. Returns the number of polygon cells.
 */
vtkIdType PolygonCells(
  vtkPolyData* input, std::vector<std::int64_t>& offsets, std::vector<std::int64_t>& connectivity);

/// Id range [first, last) of the polygon cells (after verts and lines, before strips).
std::pair<vtkIdType, vtkIdType> PolygonCellRange(vtkPolyData* input);

/**
 * The polygon cells alone in CSR form (the first offset 0): face i is cell first + i.
 * Returns the id range [first, last) of the polygon cells (PolygonCellRange).
 */
std::pair<vtkIdType, vtkIdType> PolygonFaces(
  vtkPolyData* input, std::vector<std::int64_t>& offsets, std::vector<std::int64_t>& connectivity);

/// The name of the array `algorithm` was told to process (SetInputArrayToProcess index 0);
/// empty when nothing is selected.
std::string SelectedArrayName(vtkAlgorithm* algorithm);

/**
 * Reads the cell array `algorithm` was told to process (SetInputArrayToProcess index 0;
 * `defaultName` when that selection is empty) into `values` and its name into
 * `arrayName`. Returns an empty string on success, otherwise the one-line reason: a
 * point array selected, no such cell array, not numeric, several components, not one
 * value per cell, or a non-finite value.
 */
std::string ReadCellScalars(vtkAlgorithm* algorithm, vtkPolyData* input, const char* defaultName,
  std::vector<double>& values, std::string& arrayName);

/// ReadCellScalars for a given array name.
std::string ReadNamedCellScalars(vtkPolyData* input, std::vector<double>& values, const std::string& arrayName);

/// A named VTK array holding `values` as tuples of `components` (array types with
/// SetNumberOfComponents/SetNumberOfTuples/GetPointer, e.g. vtkDoubleArray, vtkIdTypeArray).
template <typename ArrayT, typename ValueT>
vtkSmartPointer<ArrayT> MakeArray(const char* name, const std::vector<ValueT>& values, int components = 1)
{
  auto array = vtkSmartPointer<ArrayT>::New();
  if (name)
  {
    array->SetName(name);
  }
  array->SetNumberOfComponents(components);
  array->SetNumberOfTuples(static_cast<vtkIdType>(values.size() / static_cast<std::size_t>(components)));
  std::copy(values.begin(), values.end(), array->GetPointer(0));
  return array;
}

/// A core ParallelFor running on vtkSMPTools' STDThread backend with `threads`
/// workers (0 = all cores), whatever backend the application selected globally. While the
/// loop runs (on a helper thread), the calling thread reports the progress that workers
/// gave to callbacks made by MakeProgress on it, every 50 ms.
ParallelFor MakeSMPParallelFor(int threads);

/// A core ProgressCallback that maps [0, 1] into [begin, end] of the algorithm's
/// progress and returns false once the algorithm's AbortExecute flag is set. Any thread may
/// call it; the progress events are raised on the creating thread only (directly, or from
/// a MakeSMPParallelFor loop it waits for), never going backwards.
ProgressCallback MakeProgress(vtkAlgorithm* algorithm, double begin, double end);

} // namespace shapediameter::adapter
