// SPDX-License-Identifier: BSD-3-Clause
// Polydata between the processes of a distributed run, as raw array bytes.
//
// Why
//   vtkCommunicator's own Send(vtkDataObject*) marshals through the legacy VTK writer and
//   reader (a text header, big-endian swaps, cells converted to the legacy layout and back):
//   0.16-0.19 s for each rank's piece of the 208k armadillo on 2 ranks, about a tenth of the
//   SDF stage there, and every stage of a distributed run sends pieces (the replicated SDF's
//   exchange, the halos, the gathers and scatters). A piece's points, cells and data arrays are
//   contiguous arrays: they travel as their bytes, one message each.
//
// What travels
//   A header (array types, sizes, attribute roles), the names (arrays' and components'), and
//   per array its bytes: the points, the offsets and connectivity of the verts, lines, polys
//   and strips (32- or 64-bit storage as sent), and every point and cell data array. Field
//   data, usually a few values, goes through vtkCommunicator's marshalling. A polydata with an
//   array the raw form cannot carry (a point or cell array that is not a data array with the
//   standard memory layout, e.g. strings or bits; points of another layout) travels whole
//   through vtkCommunicator as before. Not kept either way: arrays' information keys.
//
// Private to the module: not installed, not wrapped.
#pragma once

#include "vtkSmartPointer.h"

#include <functional>
#include <string>
#include <vector>

class vtkDataArray;
class vtkDataObject;
class vtkMultiProcessController;
class vtkPolyData;

namespace shapediameter::distributed
{

/// A polydata as it travels: the header and names describe it, Payloads are its arrays (the
/// polydata's own, not copies) in the order their bytes are sent, Marshalled is what goes
/// through vtkCommunicator (the field data, or the whole polydata; null: nothing).
struct PolyDataMessage
{
  std::vector<long long> Header;
  std::string Names;
  std::vector<vtkDataArray*> Payloads;
  vtkSmartPointer<vtkDataObject> Marshalled;
};

/// The message of `data` (see the header comment); `data` must outlive it.
PolyDataMessage DescribePolyData(vtkPolyData* data);

/// The polydata a message describes: `readPayload(destination, bytes)` fills each array's bytes
/// in the order of Payloads. Throws shapediameter::Error on a header it cannot read.
vtkSmartPointer<vtkPolyData> RebuildPolyData(const std::vector<long long>& header, const std::string& names,
  vtkDataObject* marshalled, const std::function<void(char*, long long)>& readPayload);

/// DescribePolyData's message to process `to`, every part on `tag` (MPI keeps their order).
void SendPolyData(vtkMultiProcessController* controller, vtkPolyData* data, int to, int tag);

/// What SendPolyData sent this process from process `from` on `tag`.
vtkSmartPointer<vtkPolyData> ReceivePolyData(vtkMultiProcessController* controller, int from, int tag);

} // namespace shapediameter::distributed
