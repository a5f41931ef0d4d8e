// SPDX-License-Identifier: BSD-3-Clause
// Conversion between vtkPolyData and the VTK-free core, shared by the filters.
// Private to the module: not installed, not wrapped.
#pragma once

#include "MeshTypes.h"
#include "Parallel.h"

#include "vtkType.h"

#include <string>
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
 * non-finite coordinate used by one).
 */
std::string Triangulate(vtkPolyData* input, TriangulatedSurface& surface);

/// A core ParallelFor running on vtkSMPTools' STDThread backend with `threads`
/// workers (0 = all cores), whatever backend the application selected globally.
ParallelFor MakeSMPParallelFor(int threads);

/// A core ProgressCallback that maps [0, 1] into [begin, end] of the algorithm's
/// progress (reported from the creating thread only) and returns false once the
/// algorithm's AbortExecute flag is set.
ProgressCallback MakeProgress(vtkAlgorithm* algorithm, double begin, double end);

} // namespace shapediameter::adapter
