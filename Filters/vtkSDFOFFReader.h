// SPDX-License-Identifier: BSD-3-Clause
/**
 * @class   vtkSDFOFFReader
 * @brief   Reads Object File Format (OFF) polygon meshes into vtkPolyData.
 *
 * OFF is the format of CGAL's, the Princeton Segmentation Benchmark's and most
 * research meshes; VTK 9.2 and ParaView 5.11 have no reader for it. VTK >= 9.3 (ParaView
 * 5.13) has `vtkOFFReader` (IOGeometry, plain ASCII OFF only): this class was called that
 * too and is renamed so that the two do not collide (one class name in two libraries: the
 * client-server and Python wrappers and the dynamic linker then pick one of them).
 *
 * Supported: `OFF`, `COFF` (per-vertex colours), `NOFF` (per-vertex normals),
 * `CNOFF`, `STOFF` (texture coordinates are read and dropped), `#` comments,
 * blank lines, the header counts on the keyword line or the next one, polygons
 * of any size (n-gons are kept as polygons, not triangulated) and optional
 * per-face colours (integers 0-255 or floats in [0, 1]).
 *
 * Output arrays:
 * - point array `Colors` (unsigned char, 4 components) for COFF files;
 * - point array `Normals` (double, 3 components) for NOFF files;
 * - cell array `Colors` (unsigned char, 4 components) when face lines carry colours.
 *
 * Parsing happens in the VTK-free core (`shapediameter::ReadOFFFile`, `ReadOFFPiece`), which
 * validates the declared counts against the file size before allocating
 * anything. A missing, truncated or malformed file is reported with
 * vtkErrorMacro (with the line number) and produces an empty output; the
 * reader never crashes or allocates from an unchecked count. Binary OFF and
 * 4-D OFF are rejected with an error.
 *
 * Parallel pieces: when N > 1 pieces are requested (MPI: pvbatch, pvserver), piece p keeps
 * the p-th of N equal ranges of the faces along a Morton (Z-order) curve through the face
 * centroids (`SpatialPieces` on, the default), so every piece is a compact region of space,
 * or the faces [F·p/N, F·(p+1)/N) in file order (`SpatialPieces` off; file order is rarely
 * compact). Each piece lists its faces in file order, with the vertices they use (border
 * vertices appear in each piece that uses them; vertices no face uses stay on piece 0).
 *
 * Memory per rank: a piece reads the file a few MB at a time (`shapediameter::ReadOFFPiece`)
 * and holds, besides its own piece, every point (3 doubles per vertex, for the face
 * centroids), one byte per vertex and, while it chooses its faces, two 8-byte Morton keys per
 * face; never the file's text or the whole mesh's faces. It reads the file 2 times (3 for
 * NOFF/COFF; the same with `SpatialPieces` off), where one piece (a serial run) reads and parses
 * the whole file once (`ReadOFFFile`). The pieces, global ids and errors are exactly those of
 * splitting the whole parsed mesh. The output then also
 * carries the GlobalIds attributes `GlobalPointIds` (point data) and `GlobalCellIds` (cell
 * data), vtkIdType, numbering points and faces in file order: the module's filters use them
 * to rebuild the original mesh from the pieces, however they were redistributed afterwards
 * (Filters/DistributedSupport.h). Serial runs (one piece) get neither array.
 *
 * The spatial split replaces ParaView's Redistribute DataSet after this reader: with Debian
 * 12's current libexpat (2.5.0-1+deb12u5) ParaView 5.11's own data exchange loses cells (see
 * docs/distributed.md).
 */
#ifndef vtkSDFOFFReader_h
#define vtkSDFOFFReader_h

#include "ShapeDiameterFiltersModule.h" // for export macro
#include "vtkPolyDataAlgorithm.h"

#include <string>

class SHAPEDIAMETERFILTERS_EXPORT vtkSDFOFFReader : public vtkPolyDataAlgorithm
{
public:
  static vtkSDFOFFReader* New();
  vtkTypeMacro(vtkSDFOFFReader, vtkPolyDataAlgorithm);
  void PrintSelf(ostream& os, vtkIndent indent) override;

  ///@{
  /// The OFF file to read.
  vtkSetStdStringFromCharMacro(FileName);
  vtkGetCharFromStdStringMacro(FileName);
  ///@}

  ///@{
  /// Under MPI, deal faces out to the pieces in compact spatial regions (Morton order of the
  /// face centroids) rather than contiguous ranges of the file. Default on. No effect on a
  /// serial run.
  vtkSetMacro(SpatialPieces, bool);
  vtkGetMacro(SpatialPieces, bool);
  vtkBooleanMacro(SpatialPieces, bool);
  ///@}

  /// Returns 1 when the file starts with an OFF header keyword (cheap check, for reader factories).
  static int CanReadFile(const char* fileName);

protected:
  vtkSDFOFFReader();
  ~vtkSDFOFFReader() override;

  int RequestInformation(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;
  int RequestData(vtkInformation*, vtkInformationVector**, vtkInformationVector*) override;

private:
  vtkSDFOFFReader(const vtkSDFOFFReader&) = delete;
  void operator=(const vtkSDFOFFReader&) = delete;

  std::string FileName;
  bool SpatialPieces = true;
};

#endif
