// SPDX-License-Identifier: BSD-3-Clause
#include "DistributedSupport.h"

#include "vtkAlgorithm.h"
#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkCellType.h"
#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkDataSetAttributes.h"
#include "vtkFieldData.h"
#include "vtkIdList.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkIntArray.h"
#include "vtkMultiProcessController.h"
#include "vtkObject.h"
#include "vtkSetGet.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#ifdef SHAPEDIAMETER_HAVE_MPI
#include "vtkMPICommunicator.h"
#endif

#include <algorithm>
#include <array>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <iostream>
#include <string>
#include <thread>
#include <tuple>
#include <unordered_map>

namespace shapediameter::distributed
{
namespace
{
constexpr int RESULT_TAG = 592008;
constexpr int STATUS_TAG = 592007;
constexpr int GATHER_TAG = 592006;

vtkMultiProcessController* Controller()
{
  vtkMultiProcessController* controller = vtkMultiProcessController::GetGlobalController();
  return controller && controller->GetNumberOfProcesses() > 1 ? controller : nullptr;
}

int RequestedPieces(vtkInformation* info)
{
  return info && info->Has(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES())
    ? info->Get(vtkStreamingDemandDrivenPipeline::UPDATE_NUMBER_OF_PIECES())
    : 0;
}

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

/// vtkPolyData numbers verts, then lines, then polygons, then strips.
int CellGroup(int cellType)
{
  switch (cellType)
  {
    case VTK_VERTEX:
    case VTK_POLY_VERTEX:
      return 0;
    case VTK_LINE:
    case VTK_POLY_LINE:
      return 1;
    case VTK_TRIANGLE_STRIP:
      return 3;
    default:
      return 2;
  }
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
  int Group;
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

/// The whole surface on process 0 and where each piece's cells and points went.
struct WholeSurface
{
  vtkSmartPointer<vtkPolyData> Mesh = vtkSmartPointer<vtkPolyData>::New();
  std::vector<std::vector<vtkIdType>> CellToWhole, PointToWhole;
  const char* CellOrder = "none";
  const char* PointOrder = "none";
};

WholeSurface BuildWholeSurface(const std::vector<vtkPolyData*>& pieces)
{
  WholeSurface whole;
  const int pieceCount = static_cast<int>(pieces.size());
  whole.CellToWhole.resize(pieces.size());
  whole.PointToWhole.resize(pieces.size());
  std::vector<int> nonEmpty;
  for (int r = 0; r < pieceCount; ++r)
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

  // Cells: by global id (original order), each kept once.
  bool globalCellIds = true, originalCellIds = true;
  for (const int r : nonEmpty)
  {
    const vtkIdType n = pieces[r]->GetNumberOfCells();
    globalCellIds = globalCellIds && IdArray(pieces[r]->GetCellData(), "GlobalCellIds", n);
    vtkDataArray* original = pieces[r]->GetCellData()->GetArray("vtkOriginalCellIds");
    originalCellIds = originalCellIds && original && original->GetNumberOfComponents() == 1 &&
      original->GetNumberOfTuples() == n;
  }
  std::vector<CellEntry> entries;
  auto collect = [&](int mode) {
    entries.clear();
    std::int64_t running = 0;
    for (const int r : nonEmpty)
    {
      vtkPolyData* piece = pieces[r];
      const vtkIdType n = piece->GetNumberOfCells();
      vtkDataArray* ids = mode == 0 ? IdArray(piece->GetCellData(), "GlobalCellIds", n)
        : mode == 1                 ? piece->GetCellData()->GetArray("vtkOriginalCellIds")
                                    : nullptr;
      vtkDataArray* ghosts = piece->GetCellData()->GetArray(vtkDataSetAttributes::GhostArrayName());
      for (vtkIdType c = 0; c < n; ++c)
      {
        const int ghost = ghosts && (static_cast<int>(ghosts->GetComponent(c, 0)) &
                                      vtkDataSetAttributes::DUPLICATECELL)
          ? 1
          : 0;
        entries.push_back({ CellGroup(piece->GetCellType(c)),
          ids ? static_cast<std::int64_t>(ids->GetComponent(c, 0)) : running++, ghost, r, c });
      }
    }
    std::sort(entries.begin(), entries.end(), [](const CellEntry& a, const CellEntry& b) {
      return std::tie(a.Group, a.Key, a.Ghost, a.Piece, a.Cell) <
        std::tie(b.Group, b.Key, b.Ghost, b.Piece, b.Cell);
    });
  };
  if (globalCellIds)
  {
    collect(0);
    whole.CellOrder = "global cell ids";
  }
  else if (originalCellIds)
  {
    // RedistributeDataSet's ids of the cells in the piece they came from: global when one
    // process held the whole input (a reader that reads on piece 0 only); check they are distinct.
    collect(1);
    whole.CellOrder = "vtkOriginalCellIds";
    for (std::size_t i = 1; i < entries.size(); ++i)
    {
      // Equal ids are fine for copies of one boundary cell (same corners), not otherwise.
      if (entries[i].Key == entries[i - 1].Key && entries[i].Group == entries[i - 1].Group &&
        !SameCorners(pieces[entries[i].Piece], entries[i].Cell, pieces[entries[i - 1].Piece], entries[i - 1].Cell))
      {
        collect(2);
        whole.CellOrder = "process order (no global cell ids)";
        break;
      }
    }
  }
  else
  {
    collect(2);
    whole.CellOrder = "process order (no global cell ids)";
  }
  std::vector<std::pair<int, vtkIdType>> cellSource; // (piece, cell) of each whole cell
  cellSource.reserve(entries.size());
  for (std::size_t i = 0; i < entries.size(); ++i)
  {
    const CellEntry& e = entries[i];
    if (i == 0 || e.Group != entries[i - 1].Group || e.Key != entries[i - 1].Key)
    {
      cellSource.emplace_back(e.Piece, e.Cell);
    }
    whole.CellToWhole[e.Piece][static_cast<std::size_t>(e.Cell)] = static_cast<vtkIdType>(cellSource.size()) - 1;
  }
  entries = std::vector<CellEntry>();

  // Points: by global id, else by identical coordinates in order of first use.
  bool globalPointIds = true;
  for (const int r : nonEmpty)
  {
    globalPointIds = globalPointIds && IdArray(pieces[r]->GetPointData(), "GlobalPointIds", pieces[r]->GetNumberOfPoints());
  }
  std::vector<std::pair<int, vtkIdType>> pointSource;
  if (globalPointIds)
  {
    whole.PointOrder = "global point ids";
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
  }
  else
  {
    whole.PointOrder = "coordinates (no global point ids)";
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
  }

  // The mesh.
  vtkPolyData* mesh = whole.Mesh;
  vtkNew<vtkPoints> points;
  vtkPoints* firstPoints = nullptr;
  for (const int r : nonEmpty)
  {
    if (!firstPoints && pieces[r]->GetPoints())
    {
      firstPoints = pieces[r]->GetPoints();
    }
  }
  if (firstPoints)
  {
    points->SetDataType(firstPoints->GetDataType());
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
    groups[CellGroup(pieces[r]->GetCellType(c))]->InsertNextCell(count, mapped.data());
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

  // Arrays common to every non-empty piece.
  auto copyAttributes = [&](auto getAttributes, const std::vector<std::pair<int, vtkIdType>>& source,
                          vtkDataSetAttributes* target) {
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
    for (std::size_t w = 0; w < source.size(); ++w)
    {
      const auto& [r, id] = source[w];
      target->CopyData(list, getAttributes(pieces[r]), listIndex[static_cast<std::size_t>(r)], id,
        static_cast<vtkIdType>(w));
    }
    target->RemoveArray(vtkDataSetAttributes::GhostArrayName());
  };
  copyAttributes([](vtkPolyData* p) -> vtkDataSetAttributes* { return p->GetPointData(); }, pointSource,
    mesh->GetPointData());
  copyAttributes([](vtkPolyData* p) -> vtkDataSetAttributes* { return p->GetCellData(); }, cellSource,
    mesh->GetCellData());
  mesh->GetFieldData()->ShallowCopy(pieces[nonEmpty.front()]->GetFieldData());
  return whole;
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

/**
 * What one process gets back: its piece's geometry (needed by the data-object transport),
 * the arrays the filter made on the piece's cells and points, the whole output's field
 * data, and the polygons with the whole output's winding when the filter changed it.
 */
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
    wholeOutput->GetNumberOfCells() == wholeInput->GetNumberOfCells())
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

/// This process's output: its own input plus the result's arrays (and winding).
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

/**
 * The status process 0 sends when its serial run is done. MPI's blocking receive spins on a
 * core; processes sharing a node with process 0 would take those cores from its threads for
 * the whole run. So, with MPI, wait by polling a non-blocking receive with short sleeps
 * (at most 2 ms of added latency).
 */
int WaitForStatus(vtkMultiProcessController* controller)
{
  int status = 0;
#ifdef SHAPEDIAMETER_HAVE_MPI
  if (auto* mpi = vtkMPICommunicator::SafeDownCast(controller->GetCommunicator()))
  {
    vtkMPICommunicator::Request request;
    if (mpi->NoBlockReceive(&status, 1, 0, STATUS_TAG, request))
    {
      auto pause = std::chrono::microseconds(50);
      while (!request.Test())
      {
        std::this_thread::sleep_for(pause);
        pause = std::min(pause * 2, std::chrono::microseconds(2000));
      }
      return status;
    }
  }
#endif
  controller->Receive(&status, 1, 0, STATUS_TAG);
  return status;
}

double Seconds(std::chrono::steady_clock::time_point start)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}
} // namespace

bool IsDistributedRequest(vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  vtkMultiProcessController* controller = Controller();
  if (!controller)
  {
    return false;
  }
  int pieces = 0;
  for (int port = 0; outputVector && port < outputVector->GetNumberOfInformationObjects(); ++port)
  {
    pieces = std::max(pieces, RequestedPieces(outputVector->GetInformationObject(port)));
  }
  if (pieces == 0 && inputVector && inputVector[0] && inputVector[0]->GetNumberOfInformationObjects() > 0)
  {
    pieces = RequestedPieces(inputVector[0]->GetInformationObject(0));
  }
  return pieces > 1 && pieces == controller->GetNumberOfProcesses();
}

int RunOnWholeSurface(vtkAlgorithm* algorithm, vtkInformationVector** inputVector,
  vtkInformationVector* outputVector, const std::vector<int>& scatteredPorts, const SerialBody& serial)
{
  vtkMultiProcessController* controller = Controller();
  const int rank = controller->GetLocalProcessId();
  const int processes = controller->GetNumberOfProcesses();
  const bool timing = rank == 0 && std::getenv("SHAPEDIAMETER_DISTRIBUTED_TIMING") &&
    std::string(std::getenv("SHAPEDIAMETER_DISTRIBUTED_TIMING")) != "0";
  auto start = std::chrono::steady_clock::now();

  vtkPolyData* input = vtkPolyData::GetData(inputVector[0]);
  vtkNew<vtkPolyData> local;
  if (input)
  {
    local->ShallowCopy(input);
  }
  // Point-to-point rather than Gather: vtkCommunicator splits sends larger than 2^31 bytes,
  // while a gather's MPI counts and displacements are ints (whole surfaces above ~2 GiB).
  std::vector<vtkSmartPointer<vtkPolyData>> gathered(static_cast<std::size_t>(processes));
  if (rank == 0)
  {
    for (int r = 1; r < processes; ++r)
    {
      gathered[static_cast<std::size_t>(r)] = vtkSmartPointer<vtkPolyData>::New();
      controller->Receive(gathered[static_cast<std::size_t>(r)], r, GATHER_TAG);
    }
  }
  else
  {
    controller->Send(local, 0, GATHER_TAG);
  }
  const double gatherSeconds = Seconds(start);

  int status = 1;
  const int outputPorts = outputVector->GetNumberOfInformationObjects();
  auto isScattered = [&](int port) {
    return std::find(scatteredPorts.begin(), scatteredPorts.end(), port) != scatteredPorts.end();
  };
  double buildSeconds = 0.0, serialSeconds = 0.0;
  if (rank == 0)
  {
    start = std::chrono::steady_clock::now();
    std::vector<vtkPolyData*> pieces;
    for (int r = 0; r < processes; ++r)
    {
      pieces.push_back(r == 0 ? local.GetPointer() : gathered[static_cast<std::size_t>(r)].GetPointer());
    }
    WholeSurface whole;
    std::vector<vtkSmartPointer<vtkDataObject>> wholeOutputs;
    bool ran = false;
    try
    {
      whole = BuildWholeSurface(pieces);
      buildSeconds = Seconds(start);

      // The serial algorithm on substitute information vectors.
      start = std::chrono::steady_clock::now();
      const int inputPorts = algorithm->GetNumberOfInputPorts();
      std::vector<vtkInformationVector*> inputs(inputVector, inputVector + inputPorts);
      vtkNew<vtkInformationVector> wholeInputVector;
      vtkNew<vtkInformation> wholeInputInfo;
      wholeInputInfo->Set(vtkDataObject::DATA_OBJECT(), whole.Mesh);
      wholeInputVector->Append(wholeInputInfo);
      inputs[0] = wholeInputVector;
      vtkNew<vtkInformationVector> wholeOutputVector;
      for (int port = 0; port < outputPorts; ++port)
      {
        vtkDataObject* real = outputVector->GetInformationObject(port)->Get(vtkDataObject::DATA_OBJECT());
        wholeOutputs.push_back(vtkSmartPointer<vtkDataObject>::Take(real->NewInstance()));
        vtkNew<vtkInformation> info;
        info->Set(vtkDataObject::DATA_OBJECT(), wholeOutputs.back());
        wholeOutputVector->Append(info);
      }
      status = serial(inputs.data(), wholeOutputVector);
      serialSeconds = Seconds(start);
      ran = true;
    }
    catch (const std::exception& error)
    {
      // Never leave the other processes waiting: they get their input back unchanged.
      vtkErrorWithObjectMacro(algorithm, "Distributed run failed on process 0: " << error.what());
      status = 0;
    }

    start = std::chrono::steady_clock::now();
    for (int port = 0; port < outputPorts; ++port)
    {
      vtkDataObject* real = outputVector->GetInformationObject(port)->Get(vtkDataObject::DATA_OBJECT());
      if (!isScattered(port))
      {
        if (ran)
        {
          real->ShallowCopy(wholeOutputs[static_cast<std::size_t>(port)]);
        }
        else
        {
          real->Initialize();
        }
      }
    }
    for (int r = 1; r < processes; ++r)
    {
      controller->Send(&status, 1, r, STATUS_TAG);
    }
    for (const int port : scatteredPorts)
    {
      auto* wholeOutput = ran ? vtkPolyData::SafeDownCast(wholeOutputs[static_cast<std::size_t>(port)]) : nullptr;
      for (int r = processes - 1; r >= 0; --r)
      {
        vtkSmartPointer<vtkPolyData> result = wholeOutput
          ? LocalResult(pieces[static_cast<std::size_t>(r)], whole.Mesh, wholeOutput,
              whole.CellToWhole[static_cast<std::size_t>(r)], whole.PointToWhole[static_cast<std::size_t>(r)])
          : vtkSmartPointer<vtkPolyData>::New(); // nothing usable: the process keeps its input
        if (r == 0)
        {
          ApplyResult(input, result, outputVector->GetInformationObject(port)->Get(vtkDataObject::DATA_OBJECT()));
        }
        else
        {
          controller->Send(result, r, RESULT_TAG + port);
        }
      }
    }
    if (timing)
    {
      std::cerr << "[ShapeDiameter distributed] " << algorithm->GetClassName() << " on " << processes
                << " processes: " << whole.Mesh->GetNumberOfCells() << " cells, "
                << whole.Mesh->GetNumberOfPoints() << " points, "
                << whole.Mesh->GetActualMemorySize() / 1024.0 << " MiB (cells by " << whole.CellOrder
                << ", points by " << whole.PointOrder << "); gather " << gatherSeconds << " s, build "
                << buildSeconds << " s, serial algorithm " << serialSeconds << " s, scatter "
                << Seconds(start) << " s" << std::endl;
    }
  }
  else
  {
    status = WaitForStatus(controller);
    for (int port = 0; port < outputPorts; ++port)
    {
      vtkDataObject* real = outputVector->GetInformationObject(port)->Get(vtkDataObject::DATA_OBJECT());
      if (isScattered(port))
      {
        vtkNew<vtkPolyData> result;
        controller->Receive(result, 0, RESULT_TAG + port);
        ApplyResult(input, result, real);
      }
      else
      {
        real->Initialize(); // complete on process 0 only
      }
    }
  }
  return status;
}

} // namespace shapediameter::distributed
