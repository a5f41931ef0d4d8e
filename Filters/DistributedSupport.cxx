// SPDX-License-Identifier: BSD-3-Clause
#include "DistributedSupport.h"

#include "Errors.h"
#include "PolyDataTransfer.h"
#include "WholeSurface.h"

#include "vtkAlgorithm.h"
#include "vtkCellData.h"
#include "vtkCommunicator.h"
#include "vtkDataArray.h"
#include "vtkDataObject.h"
#include "vtkDataSetAttributes.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkMultiProcessController.h"
#include "vtkSetGet.h"
#include "vtkNew.h"
#include "vtkPointData.h"
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#ifdef SHAPEDIAMETER_HAVE_MPI
#include "vtkMPICommunicator.h"
#endif

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <functional>
#include <iostream>
#include <limits>
#include <numeric>
#include <string>
#include <thread>
#include <utility>

namespace shapediameter::distributed
{

bool TimingReportsRequested()
{
  const char* timing = std::getenv("SHAPEDIAMETER_DISTRIBUTED_TIMING");
  return timing && std::string(timing) != "0";
}
namespace
{
constexpr int RESULT_TAG = 592008;
constexpr int STATUS_TAG = 592007;
constexpr int GATHER_TAG = 592006;
constexpr int BARRIER_TAG = 592012;
constexpr int FAILURE_TAG = 592013; // and the next one
constexpr int EXCHANGE_TAG = 592020;
constexpr int STATE_TAG = 592021;
constexpr int GATHER_ON_FIRST_TAG = 592022;    // and the next one
constexpr int SCATTER_FROM_FIRST_TAG = 592024; // and the next one

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

/**
 * One int from `source`. MPI's blocking receive spins on a core; processes sharing a node with
 * the busy ones would take those cores from their threads. So, with MPI, wait by polling a
 * non-blocking receive with short sleeps (at most 2 ms of added latency).
 */
int SleepingReceive(vtkMultiProcessController* controller, int source, int tag)
{
  int value = 0;
#ifdef SHAPEDIAMETER_HAVE_MPI
  if (auto* mpi = vtkMPICommunicator::SafeDownCast(controller->GetCommunicator()))
  {
    vtkMPICommunicator::Request request;
    if (mpi->NoBlockReceive(&value, 1, source, tag, request))
    {
      auto pause = std::chrono::microseconds(50);
      while (!request.Test())
      {
        std::this_thread::sleep_for(pause);
        pause = std::min(pause * 2, std::chrono::microseconds(2000));
      }
      return value;
    }
  }
#endif
  controller->Receive(&value, 1, source, tag);
  return value;
}

/// The status process 0 sends when its serial run is done.
int WaitForStatus(vtkMultiProcessController* controller)
{
  return SleepingReceive(controller, 0, STATUS_TAG);
}

/// Drops the cell arrays not named in `keep` (nothing when it is empty), except the global ids
/// attribute and the arrays AssembleWholeSurface orders and matches cells by.
void KeepCellArrays(vtkCellData* cells, const std::vector<std::string>& keep)
{
  if (keep.empty())
  {
    return;
  }
  vtkDataArray* globalIds = cells->GetGlobalIds();
  for (int i = cells->GetNumberOfArrays() - 1; i >= 0; --i)
  {
    vtkAbstractArray* array = cells->GetAbstractArray(i);
    const std::string name = array->GetName() ? array->GetName() : "";
    const bool assembly = array == globalIds || name == "GlobalCellIds" || name == "vtkOriginalCellIds" ||
      name == vtkDataSetAttributes::GhostArrayName();
    if (!assembly && std::find(keep.begin(), keep.end(), name) == keep.end())
    {
      cells->RemoveArray(i);
    }
  }
}

/// To process `to`: the elements of `items` (ids, a text, values), their count first
/// (vtkCommunicator splits sends above 2^31 bytes).
template <typename Container>
void SendSized(vtkMultiProcessController* controller, const Container& items, int to, int tag)
{
  vtkIdType count = static_cast<vtkIdType>(items.size());
  controller->Send(&count, 1, to, tag);
  if (count > 0)
  {
    controller->Send(items.data(), count, to, tag + 1);
  }
}

/// What SendSized sent this process from process `from`.
template <typename Container>
Container ReceiveSized(vtkMultiProcessController* controller, int from, int tag)
{
  vtkIdType count = 0;
  controller->Receive(&count, 1, from, tag);
  Container items(static_cast<std::size_t>(std::max<vtkIdType>(count, 0)), typename Container::value_type{});
  if (count > 0)
  {
    controller->Receive(items.data(), count, from, tag + 1);
  }
  return items;
}

/// Every process's `value` to process 0, which combines them (`combine` gets them in process
/// order) and sends the result back: a collective whose waiting processes sleep
/// (SleepingReceive) instead of spinning while the slowest process is still computing.
int SleepingCombine(vtkMultiProcessController* controller, int value, int tag,
  const std::function<int(const std::vector<int>&)>& combine)
{
  int combined = 0;
  if (controller->GetLocalProcessId() == 0)
  {
    std::vector<int> values{ value };
    for (int r = 1; r < controller->GetNumberOfProcesses(); ++r)
    {
      values.push_back(SleepingReceive(controller, r, tag));
    }
    combined = combine(values);
    for (int r = 1; r < controller->GetNumberOfProcesses(); ++r)
    {
      controller->Send(&combined, 1, r, tag);
    }
  }
  else
  {
    controller->Send(&value, 1, 0, tag);
    combined = SleepingReceive(controller, 0, tag);
  }
  return combined;
}

/// A barrier whose waiting processes sleep, before a collective that would otherwise spin.
void SleepingBarrier(vtkMultiProcessController* controller)
{
  SleepingCombine(controller, 1, BARRIER_TAG, [](const std::vector<int>&) { return 1; });
}

double Seconds(std::chrono::steady_clock::time_point start)
{
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

bool IsScattered(const std::vector<int>& scatteredPorts, int port)
{
  return std::find(scatteredPorts.begin(), scatteredPorts.end(), port) != scatteredPorts.end();
}

/// Every process's piece on process 0 (piece 0 = local), nothing elsewhere. Point-to-point
/// rather than Gather: vtkCommunicator splits sends larger than 2^31 bytes, while a gather's MPI
/// counts and displacements are ints (whole surfaces above ~2 GiB).
std::vector<vtkSmartPointer<vtkPolyData>> GatherPieces(vtkMultiProcessController* controller, vtkPolyData* local)
{
  const int processes = controller->GetNumberOfProcesses();
  std::vector<vtkSmartPointer<vtkPolyData>> gathered(static_cast<std::size_t>(processes));
  if (controller->GetLocalProcessId() == 0)
  {
    gathered[0] = local;
    for (int r = 1; r < processes; ++r)
    {
      gathered[static_cast<std::size_t>(r)] = ReceivePolyData(controller, r, GATHER_TAG);
    }
  }
  else
  {
    SendPolyData(controller, local, 0, GATHER_TAG);
  }
  return gathered;
}

/// Every other process's polydata, `outgoing(r)` sent to each process r: point to point, in
/// one global order of the pairs (deadlock-free with blocking sends: the lowest unfinished
/// pair always has both its processes waiting for it). Indexed by process; this process's
/// own entry is null.
std::vector<vtkSmartPointer<vtkPolyData>> ExchangeWithEveryProcess(
  vtkMultiProcessController* controller, const std::function<vtkSmartPointer<vtkPolyData>(int)>& outgoing)
{
  const int rank = controller->GetLocalProcessId();
  const int processes = controller->GetNumberOfProcesses();
  std::vector<vtkSmartPointer<vtkPolyData>> received(static_cast<std::size_t>(processes));
  const auto send = [&](int other) { SendPolyData(controller, outgoing(other), other, EXCHANGE_TAG); };
  const auto receive = [&](int other) {
    received[static_cast<std::size_t>(other)] = ReceivePolyData(controller, other, EXCHANGE_TAG);
  };
  for (int a = 0; a < processes; ++a)
  {
    for (int b = a + 1; b < processes; ++b)
    {
      if (rank == a)
      {
        send(b);
        receive(b);
      }
      else if (rank == b)
      {
        receive(a);
        send(a);
      }
    }
  }
  return received;
}

/// What process 0's serial run produced: one output per port (empty unless Ran).
struct WholeRun
{
  WholeSurface Whole;
  std::vector<vtkSmartPointer<vtkDataObject>> Outputs;
  bool Ran = false;
  int Status = 1;
  /// What the filter reported as its failure on process 0 (empty: none).
  std::string Failure;
  double BuildSeconds = 0.0;
  double SerialSeconds = 0.0;
};

/// Runs `run` (a filter's RequestData) on `mesh` through substitute information vectors: the
/// other input ports as they are, one fresh output object per port in `outputs`.
template <typename Run>
int RunOnMesh(vtkAlgorithm* algorithm, vtkInformationVector** inputVector, vtkInformationVector* outputVector,
  vtkPolyData* mesh, std::vector<vtkSmartPointer<vtkDataObject>>& outputs, const Run& run)
{
  const int inputPorts = algorithm->GetNumberOfInputPorts();
  std::vector<vtkInformationVector*> inputs(inputVector, inputVector + inputPorts);
  vtkNew<vtkInformationVector> wholeInputVector;
  vtkNew<vtkInformation> wholeInputInfo;
  wholeInputInfo->Set(vtkDataObject::DATA_OBJECT(), mesh);
  wholeInputVector->Append(wholeInputInfo);
  inputs[0] = wholeInputVector;
  vtkNew<vtkInformationVector> wholeOutputVector;
  outputs.clear();
  for (int port = 0; port < outputVector->GetNumberOfInformationObjects(); ++port)
  {
    vtkDataObject* real = outputVector->GetInformationObject(port)->Get(vtkDataObject::DATA_OBJECT());
    outputs.push_back(vtkSmartPointer<vtkDataObject>::Take(real->NewInstance()));
    vtkNew<vtkInformation> info;
    info->Set(vtkDataObject::DATA_OBJECT(), outputs.back());
    wholeOutputVector->Append(info);
  }
  return run(inputs.data(), wholeOutputVector.GetPointer());
}

/// Assembles the whole surface from the pieces and runs the serial algorithm on it. A failure
/// is reported and leaves Ran false, so that the other processes are never left waiting (they
/// get their input back unchanged).
WholeRun RunSerialOnWhole(vtkAlgorithm* algorithm, vtkInformationVector** inputVector,
  vtkInformationVector* outputVector, const std::vector<vtkPolyData*>& pieces, const SerialBody& serial,
  const std::function<std::string()>& failure)
{
  WholeRun run;
  try
  {
    auto start = std::chrono::steady_clock::now();
    run.Whole = AssembleWholeSurface(pieces);
    run.BuildSeconds = Seconds(start);
    // Their arrays are in the whole surface now; only their cells and points are read again
    // (LocalResult), so the filter runs without a second copy of the arrays.
    for (vtkPolyData* piece : pieces)
    {
      piece->GetCellData()->Initialize();
      piece->GetPointData()->Initialize();
    }

    start = std::chrono::steady_clock::now();
    run.Status = RunOnMesh(algorithm, inputVector, outputVector, run.Whole.Mesh, run.Outputs, serial);
    run.SerialSeconds = Seconds(start);
    run.Ran = true;
    if (failure)
    {
      run.Failure = failure();
    }
  }
  catch (const std::exception& error)
  {
    run.Failure = std::string("Distributed run failed on process 0: ") + error.what();
    vtkErrorWithObjectMacro(algorithm, << run.Failure);
    run.Status = 0;
  }
  return run;
}

/// On process 0: the whole outputs on its unscattered ports, the status to every process, then
/// each process's share of every scattered port (process 0's own applied last).
void ScatterResults(vtkMultiProcessController* controller, vtkPolyData* input, vtkInformationVector* outputVector,
  const std::vector<int>& scatteredPorts, const std::vector<vtkPolyData*>& pieces, const WholeRun& run)
{
  const int processes = controller->GetNumberOfProcesses();
  for (int port = 0; port < outputVector->GetNumberOfInformationObjects(); ++port)
  {
    vtkDataObject* real = outputVector->GetInformationObject(port)->Get(vtkDataObject::DATA_OBJECT());
    if (!IsScattered(scatteredPorts, port))
    {
      if (run.Ran)
      {
        real->ShallowCopy(run.Outputs[static_cast<std::size_t>(port)]);
      }
      else
      {
        real->Initialize();
      }
    }
  }
  for (int r = 1; r < processes; ++r)
  {
    int status = run.Status;
    controller->Send(&status, 1, r, STATUS_TAG);
    SendSized(controller, run.Failure, r, FAILURE_TAG);
  }
  const WholeSurface& whole = run.Whole;
  for (const int port : scatteredPorts)
  {
    auto* wholeOutput = run.Ran ? vtkPolyData::SafeDownCast(run.Outputs[static_cast<std::size_t>(port)]) : nullptr;
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
        SendPolyData(controller, result, r, RESULT_TAG + port);
      }
    }
  }
}

/// On the other processes: the status, then this process's share of every scattered port (the
/// other ports are complete on process 0 only).
int ReceiveResults(vtkAlgorithm* algorithm, vtkMultiProcessController* controller, vtkPolyData* input,
  vtkInformationVector* outputVector, const std::vector<int>& scatteredPorts)
{
  const int status = WaitForStatus(controller);
  const auto failure = ReceiveSized<std::string>(controller, 0, FAILURE_TAG);
  if (!failure.empty())
  {
    vtkErrorWithObjectMacro(algorithm, << failure << " (process 0, which ran the filter on the whole surface; this process keeps its input)");
  }
  for (int port = 0; port < outputVector->GetNumberOfInformationObjects(); ++port)
  {
    vtkDataObject* real = outputVector->GetInformationObject(port)->Get(vtkDataObject::DATA_OBJECT());
    if (IsScattered(scatteredPorts, port))
    {
      ApplyResult(input, ReceivePolyData(controller, 0, RESULT_TAG + port), real);
    }
    else
    {
      real->Initialize();
    }
  }
  return status;
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
  vtkInformationVector* outputVector, const std::vector<int>& scatteredPorts, const SerialBody& serial,
  const std::function<std::string()>& failure, const std::vector<std::string>& cellArrays)
{
  vtkMultiProcessController* controller = Controller();
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0]);
  vtkNew<vtkPolyData> local;
  if (input)
  {
    local->ShallowCopy(input);
    KeepCellArrays(local->GetCellData(), cellArrays);
  }
  if (controller->GetLocalProcessId() != 0)
  {
    GatherPieces(controller, local);
    return ReceiveResults(algorithm, controller, input, outputVector, scatteredPorts);
  }

  auto start = std::chrono::steady_clock::now();
  const std::vector<vtkSmartPointer<vtkPolyData>> gathered = GatherPieces(controller, local);
  const double gatherSeconds = Seconds(start);
  std::vector<vtkPolyData*> pieces;
  for (const auto& piece : gathered)
  {
    pieces.push_back(piece.GetPointer());
  }
  const WholeRun run = RunSerialOnWhole(algorithm, inputVector, outputVector, pieces, serial, failure);
  start = std::chrono::steady_clock::now();
  ScatterResults(controller, input, outputVector, scatteredPorts, pieces, run);
  if (TimingReportsRequested())
  {
    const WholeSurface& whole = run.Whole;
    std::cerr << "[ShapeDiameter distributed] " << algorithm->GetClassName() << " on "
              << controller->GetNumberOfProcesses() << " processes: " << whole.Mesh->GetNumberOfCells()
              << " cells, " << whole.Mesh->GetNumberOfPoints() << " points, "
              << whole.Mesh->GetActualMemorySize() / 1024.0 << " MiB (cells by " << ToString(whole.Cells)
              << ", points by " << ToString(whole.Points) << "); gather " << gatherSeconds << " s, build "
              << run.BuildSeconds << " s, serial algorithm " << run.SerialSeconds << " s, scatter "
              << Seconds(start) << " s" << std::endl;
  }
  return run.Status;
}

namespace
{
/// What a process brings to ReplicatedShare::Combine.
enum class Arrival : long long
{
  Done = 0,
  Aborted = 1,
  Stopped = 2
};

/// The collective behind ReplicatedShare::Combine (see there); `arrival` Stopped = this
/// process joins only so that the others do not wait (its values are not used).
void CombineAcrossProcesses(vtkMultiProcessController* controller, Arrival arrival, std::vector<double>& values,
  std::vector<int>& counts, bool& aborted)
{
  const auto n = static_cast<long long>(values.size());
  const long long mine[4] = { static_cast<long long>(arrival), n, -n,
    static_cast<long long>(counts.size()) == n ? 0 : 1 };
  long long all[4] = { 0, 0, 0, 0 };
  SleepingBarrier(controller); // the processes finish their shares at different times
  controller->AllReduce(mine, all, 4, vtkCommunicator::MAX_OP);
  if (all[0] == static_cast<long long>(Arrival::Stopped))
  {
    if (arrival != Arrival::Stopped)
    {
      throw Error("another process of the distributed run stopped before its share was done (its own "
                  "error says why)");
    }
    return;
  }
  if (all[0] == static_cast<long long>(Arrival::Aborted))
  {
    aborted = true;
    return;
  }
  if (all[1] != -all[2] || all[3] != 0)
  {
    throw Error("the processes of the distributed run disagree on the size of the whole surface");
  }
  if (n == 0)
  {
    return;
  }
  std::vector<double> valueSums(values.size());
  controller->AllReduce(values.data(), valueSums.data(), n, vtkCommunicator::SUM_OP);
  values.swap(valueSums);
  std::vector<int> countSums(counts.size());
  controller->AllReduce(counts.data(), countSums.data(), n, vtkCommunicator::SUM_OP);
  counts.swap(countSums);
}
} // namespace

int RunOnReplicatedSurface(vtkAlgorithm* algorithm, vtkInformationVector** inputVector,
  vtkInformationVector* outputVector, const std::vector<int>& scatteredPorts, const ReplicatedBody& body)
{
  vtkMultiProcessController* controller = Controller();
  const int rank = controller->GetLocalProcessId();
  const int processes = controller->GetNumberOfProcesses();
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0]);
  vtkNew<vtkPolyData> local;
  if (input)
  {
    local->ShallowCopy(input);
  }
  const auto start = std::chrono::steady_clock::now();

  // 1. and 2. Every piece to every process; each assembles the whole surface and its owners.
  WholeSurface whole;
  std::vector<int> owner;
  int ready = 1;
  {
    std::vector<vtkSmartPointer<vtkPolyData>> exchanged = ExchangeWithEveryProcess(controller,
      [&](int) { return vtkSmartPointer<vtkPolyData>(local.GetPointer()); });
    exchanged[static_cast<std::size_t>(rank)] = local.GetPointer();
    std::vector<vtkPolyData*> pieces;
    for (const auto& piece : exchanged)
    {
      pieces.push_back(piece.GetPointer());
    }
    try
    {
      whole = AssembleWholeSurface(pieces);
      std::vector<int> processOfPiece(static_cast<std::size_t>(processes));
      std::iota(processOfPiece.begin(), processOfPiece.end(), 0);
      owner = LowestHolders(whole, processOfPiece);
    }
    catch (const std::exception& error)
    {
      vtkErrorWithObjectMacro(algorithm, "Distributed run failed on process " << rank << ": " << error.what());
      ready = 0;
    }
    int everyone = ready;
    controller->AllReduce(&ready, &everyone, 1, vtkCommunicator::MIN_OP);
    ready = everyone;
  }
  // Each process's own cells of the body's `outputs` (none: the process keeps its input), no
  // exchange; outputs other than the scattered ports stay on process 0.
  std::vector<vtkIdType> cellToWhole, pointToWhole;
  const auto keepOwnCells = [&](const std::vector<vtkSmartPointer<vtkDataObject>>& outputs) {
    for (int port = 0; port < outputVector->GetNumberOfInformationObjects(); ++port)
    {
      vtkDataObject* real = outputVector->GetInformationObject(port)->Get(vtkDataObject::DATA_OBJECT());
      vtkDataObject* wholeOutput = outputs.empty() ? nullptr : outputs[static_cast<std::size_t>(port)].GetPointer();
      if (IsScattered(scatteredPorts, port))
      {
        auto* wholeSurface = vtkPolyData::SafeDownCast(wholeOutput);
        ApplyResult(input,
          wholeSurface ? LocalResult(local.GetPointer(), whole.Mesh, wholeSurface, cellToWhole, pointToWhole)
                       : vtkSmartPointer<vtkPolyData>::New(),
          real);
      }
      else if (real)
      {
        if (rank == 0 && wholeOutput)
        {
          real->ShallowCopy(wholeOutput);
        }
        else
        {
          real->Initialize();
        }
      }
    }
  };
  if (!ready)
  {
    keepOwnCells({});
    return 0;
  }
  const double assembleSeconds = Seconds(start);

  cellToWhole = whole.CellToWhole[static_cast<std::size_t>(rank)];
  pointToWhole = whole.PointToWhole[static_cast<std::size_t>(rank)];
  whole.CellToWhole.clear();
  whole.PointToWhole.clear();

  // 3. The body on the whole surface, every process its own cells.
  ReplicatedShare share;
  share.Owned.resize(owner.size());
  for (std::size_t c = 0; c < owner.size(); ++c)
  {
    share.Owned[c] = owner[c] == rank ? 1 : 0;
  }
  share.ReleaseGeometry = [&whole](vtkPolyData* output) {
    vtkPolyData* input = whole.Mesh;
    if (!output || output->GetPolys() != input->GetPolys())
    {
      return;
    }
    for (vtkPolyData* data : { input, output })
    {
      data->SetPoints(nullptr);
      data->SetVerts(nullptr);
      data->SetLines(nullptr);
      data->SetPolys(nullptr);
      data->SetStrips(nullptr);
    }
  };
  const vtkIdType wholeCells = whole.Mesh->GetNumberOfCells();
  bool combined = false;
  share.Combine = [controller, &combined](std::vector<double>& values, std::vector<int>& counts, bool& aborted) {
    combined = true;
    CombineAcrossProcesses(controller, aborted ? Arrival::Aborted : Arrival::Done, values, counts, aborted);
  };
  std::vector<vtkSmartPointer<vtkDataObject>> outputs;
  int status = 0;
  try
  {
    status = RunOnMesh(algorithm, inputVector, outputVector, whole.Mesh, outputs,
      [&](vtkInformationVector** in, vtkInformationVector* out) { return body(in, out, share); });
  }
  catch (const std::exception& error)
  {
    vtkErrorWithObjectMacro(algorithm, "Distributed run failed on process " << rank << ": " << error.what());
    outputs.clear();
  }
  if (!combined)
  {
    std::vector<double> noValues;
    std::vector<int> noCounts;
    bool aborted = algorithm->GetAbortExecute() != 0;
    CombineAcrossProcesses(controller, aborted ? Arrival::Aborted : Arrival::Stopped, noValues, noCounts, aborted);
  }
  const double bodySeconds = Seconds(start) - assembleSeconds;

  // 4. Each process's own cells.
  keepOwnCells(outputs);
  int lowest = status;
  controller->AllReduce(&status, &lowest, 1, vtkCommunicator::MIN_OP);
  if (rank == 0 && TimingReportsRequested())
  {
    std::cerr << "[ShapeDiameter distributed] " << algorithm->GetClassName() << " replicated on " << processes
              << " processes: " << wholeCells << " cells (by " << ToString(whole.Cells)
              << ", points by " << ToString(whole.Points) << "); exchange and build " << assembleSeconds
              << " s, body " << bodySeconds << " s, local results "
              << Seconds(start) - assembleSeconds - bodySeconds << " s" << std::endl;
  }
  return lowest;
}

namespace
{
/// How a process of a halo run ends its part.
enum Outcome : int
{
  Succeeded = 0,
  Aborted = 1,
  Failed = 2,
  /// The halo was narrower than the body's neighbourhood (HaloTooNarrowError): run on the
  /// whole surface instead.
  HaloTooNarrow = 3
};

/// The processes' states, combined.
struct GroupState
{
  int HighestOutcome = Succeeded;
  bool AllEnded = false;
  bool AnyEnded = false;
};

/// Every process's values on every process, concatenated in process order, and each
/// process's count and offset in them.
template <typename T>
struct Gathered
{
  std::vector<T> All;
  std::vector<vtkIdType> Counts, Offsets;
};

/// Gathered `values` of every process (any count each, none included). Collective.
template <typename T>
Gathered<T> AllGatherVariable(vtkMultiProcessController* controller, std::vector<T> values)
{
  const auto processes = static_cast<std::size_t>(controller->GetNumberOfProcesses());
  Gathered<T> gathered;
  gathered.Counts.resize(processes);
  gathered.Offsets.assign(processes, 0);
  vtkIdType mine = static_cast<vtkIdType>(values.size());
  controller->AllGather(&mine, gathered.Counts.data(), 1);
  for (std::size_t r = 1; r < processes; ++r)
  {
    gathered.Offsets[r] = gathered.Offsets[r - 1] + gathered.Counts[r - 1];
  }
  const auto total = static_cast<std::size_t>(gathered.Offsets.back() + gathered.Counts.back());
  values.resize(std::max<std::size_t>(values.size(), 1)); // valid buffers even when empty
  gathered.All.resize(std::max<std::size_t>(total, 1));
  controller->AllGatherV(values.data(), gathered.All.data(), mine, gathered.Counts.data(), gathered.Offsets.data());
  gathered.All.resize(total);
  return gathered;
}

/// Every process's outcome and whether it has ended, combined on every process through
/// process 0; the waiting processes sleep.
GroupState ExchangeStates(vtkMultiProcessController* controller, int outcome, bool ended)
{
  const int combined = SleepingCombine(controller, outcome * 2 + (ended ? 1 : 0), STATE_TAG,
    [](const std::vector<int>& codes) {
      int highest = Succeeded;
      bool all = true, any = false;
      for (const int code : codes)
      {
        highest = std::max(highest, code / 2);
        all = all && code % 2 == 1;
        any = any || code % 2 == 1;
      }
      return highest * 4 + (all ? 2 : 0) + (any ? 1 : 0);
    });
  return GroupState{ combined / 4, (combined / 2) % 2 == 1, combined % 2 == 1 };
}

/**
 * The core's ProcessGroup over the controller. Before each collective the processes exchange
 * their states: when one has failed (it calls Finish instead of the collective), the others'
 * collective throws, and they call Finish too; Finish repeats the exchange until every
 * process has ended, so no process waits for one that left.
 */
class ControllerGroup final : public ProcessGroup
{
public:
  explicit ControllerGroup(vtkMultiProcessController* controller)
    : Controller(controller)
  {
  }

  std::vector<double> AllGather(const std::vector<double>& values) const override
  {
    this->Proceed();
    return AllGatherVariable(this->Controller, values).All;
  }

  void SumInPlace(std::vector<std::int64_t>& values) const override
  {
    this->Proceed();
    if (values.empty())
    {
      return;
    }
    std::vector<long long> mine(values.begin(), values.end()), sums(values.size());
    this->Controller->AllReduce(mine.data(), sums.data(), static_cast<vtkIdType>(mine.size()), vtkCommunicator::SUM_OP);
    std::copy(sums.begin(), sums.end(), values.begin());
  }

  void MaxInPlace(std::vector<double>& values) const override
  {
    this->Proceed();
    if (values.empty())
    {
      return;
    }
    std::vector<double> maxima(values.size());
    this->Controller->AllReduce(values.data(), maxima.data(), static_cast<vtkIdType>(values.size()), vtkCommunicator::MAX_OP);
    values.swap(maxima);
  }

  int Rank() const override { return this->Controller->GetLocalProcessId(); }

  std::vector<std::vector<double>> GatherOnFirst(const std::vector<double>& values) const override
  {
    this->Proceed();
    const int processes = this->Controller->GetNumberOfProcesses();
    if (this->Rank() != 0)
    {
      SendSized(this->Controller, values, 0, GATHER_ON_FIRST_TAG);
      return {};
    }
    std::vector<std::vector<double>> all{ values };
    for (int r = 1; r < processes; ++r)
    {
      all.push_back(ReceiveSized<std::vector<double>>(this->Controller, r, GATHER_ON_FIRST_TAG));
    }
    return all;
  }

  std::vector<double> ScatterFromFirst(const std::function<std::vector<double>(int)>& part) const override
  {
    this->Proceed();
    if (this->Rank() != 0)
    {
      return ReceiveSized<std::vector<double>>(this->Controller, 0, SCATTER_FROM_FIRST_TAG);
    }
    for (int r = 1; r < this->Controller->GetNumberOfProcesses(); ++r)
    {
      SendSized(this->Controller, part(r), r, SCATTER_FROM_FIRST_TAG);
    }
    return part(0);
  }

  /// This process's part is over with `outcome`; returns the highest outcome of all, once
  /// every process has ended. Collective.
  int Finish(int outcome) const
  {
    for (;;)
    {
      const GroupState state = ExchangeStates(this->Controller, outcome, true);
      if (state.AllEnded)
      {
        return state.HighestOutcome;
      }
    }
  }

private:
  void Proceed() const
  {
    const GroupState state = ExchangeStates(this->Controller, Succeeded, false);
    if (state.HighestOutcome == Failed)
    {
      throw Error("another process of the distributed run stopped (its own error says why)");
    }
    if (state.AnyEnded)
    {
      throw Error("the processes of the distributed run went out of step");
    }
  }

  vtkMultiProcessController* Controller;
};

/// What each process sent (indexed by process; this process's entry is null), and the
/// distance around each own cell centre within which every cell centre arrived.
struct Halo
{
  std::vector<vtkSmartPointer<vtkPolyData>> Received;
  double Width = 0.0;
};

/// Each process's piece's own cells near every other process's cells, exchanged with every
/// process: those within `radius` of one of their centres (HaloKind::CentresWithin), or those
/// sharing a corner with one of them (HaloKind::SharedCorners; `radius` is then the voxel size),
/// found through a voxel grid whose occupied voxels every process sends every other.
Halo ExchangeHalos(vtkMultiProcessController* controller, vtkPolyData* local, double radius, HaloKind kind)
{
  const int processes = controller->GetNumberOfProcesses();
  const bool corners = kind == HaloKind::SharedCorners;
  // The cells' centres, or with SharedCorners the points: what the voxels hold.
  const std::vector<double> positions = corners ? PointCoordinates(local) : CellCenters(local);
  std::vector<double> bounds = CenterBounds(positions);
  std::vector<double> allBounds(6 * static_cast<std::size_t>(processes));
  controller->AllGather(bounds.data(), allBounds.data(), 6);
  const double infinity = std::numeric_limits<double>::infinity();
  std::vector<double> whole{ infinity, -infinity, infinity, -infinity, infinity, -infinity };
  double largest = 0.0;
  for (int r = 0; r < processes; ++r)
  {
    for (int axis = 0; axis < 3; ++axis)
    {
      const double low = allBounds[6 * r + 2 * axis], high = allBounds[6 * r + 2 * axis + 1];
      if (low <= high)
      {
        whole[2 * axis] = std::min(whole[2 * axis], low);
        whole[2 * axis + 1] = std::max(whole[2 * axis + 1], high);
        largest = std::max({ largest, std::abs(low), std::abs(high) });
      }
    }
  }
  // The centres here and the face graph's may differ in the last bits.
  const double rounding = 1e-9 * radius + 1e-12 * largest;
  const VoxelGrid grid = VoxelGrid::Around(whole, radius + rounding);
  const std::vector<std::int64_t> positionVoxels = CellVoxels(positions, grid);
  std::vector<vtkIdType> occupied(positionVoxels.begin(), positionVoxels.end());
  std::sort(occupied.begin(), occupied.end());
  occupied.erase(std::unique(occupied.begin(), occupied.end()), occupied.end());
  const Gathered<vtkIdType> allOccupied = AllGatherVariable(controller, std::move(occupied));
  Halo halo;
  halo.Received = ExchangeWithEveryProcess(controller, [&](int other) {
    const auto first = allOccupied.All.begin() + allOccupied.Offsets[static_cast<std::size_t>(other)];
    const std::vector<std::int64_t> voxels(first, first + allOccupied.Counts[static_cast<std::size_t>(other)]);
    return ExtractPolygons(local,
      corners ? CellsWithCornerInVoxels(local, positionVoxels, voxels) : CellsNearVoxels(positionVoxels, voxels));
  });
  // Two centres within the voxel size lie in the same or neighbouring voxels.
  halo.Width = corners ? 0.0 : grid.Size - rounding;
  return halo;
}
} // namespace

std::optional<int> RunOnHaloSurface(vtkAlgorithm* algorithm, vtkInformationVector** inputVector,
  vtkInformationVector* outputVector, const std::vector<int>& scatteredPorts, HaloKind kind,
  const HaloRadiusFunction& radius, const HaloBody& body, const std::function<std::string()>& failure,
  const std::vector<std::string>& cellArrays)
{
  vtkMultiProcessController* controller = Controller();
  const int rank = controller->GetLocalProcessId();
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0]);
  vtkNew<vtkPolyData> local;
  if (input)
  {
    local->ShallowCopy(input);
    KeepCellArrays(local->GetCellData(), cellArrays);
  }
  auto start = std::chrono::steady_clock::now();

  // 1. Can every process run with a halo, and how wide?
  double haloRadius = -1.0;
  {
    const ControllerGroup group(controller);
    int outcome = Failed;
    try
    {
      if (input && local->GetNumberOfCells() > 0 && local->GetNumberOfCells() == local->GetNumberOfPolys() &&
        HasGlobalIds(local))
      {
        haloRadius = radius(local, group);
        outcome = std::isfinite(haloRadius) && haloRadius >= 0.0 ? Succeeded : Failed;
      }
    }
    catch (const std::exception&)
    {
      outcome = Failed; // RunOnWholeSurface, which the caller runs instead, reports it
    }
    if (group.Finish(outcome) != Succeeded)
    {
      return std::nullopt;
    }
  }
  const double radiusSeconds = Seconds(start);

  // 2. and 3. The halo, and this process's cells with it in the whole surface's order.
  start = std::chrono::steady_clock::now();
  // 10 % wider than the radius: a cell that several processes hold (RedistributeDataSet's
  // "assign to all regions") counted once per process in the radius's mean edge length.
  Halo halo = kind == HaloKind::None ? Halo() : ExchangeHalos(controller, local, 1.1 * haloRadius, kind);
  std::vector<vtkSmartPointer<vtkPolyData>>& received = halo.Received;
  std::vector<vtkPolyData*> pieces{ local.GetPointer() };
  std::vector<int> pieceProcess{ rank };
  for (int r = 0; r < static_cast<int>(received.size()); ++r)
  {
    if (received[static_cast<std::size_t>(r)] && received[static_cast<std::size_t>(r)]->GetNumberOfCells() > 0)
    {
      pieces.push_back(received[static_cast<std::size_t>(r)].GetPointer());
      pieceProcess.push_back(r);
    }
  }
  const ControllerGroup group(controller);
  int outcome = Succeeded;
  int status = 1;
  WholeSurface surface;
  std::vector<vtkSmartPointer<vtkDataObject>> outputs;
  double exchangeSeconds = 0.0, bodySeconds = 0.0;
  try
  {
    surface = AssembleWholeSurface(pieces);
    HaloShare share;
    share.GlobalIds = WholeGlobalCellIds(surface, pieces);
    share.GlobalPointIds = WholeGlobalPointIds(surface, pieces);
    received.clear();
    share.Group = &group;
    share.Width = halo.Width;
    share.Own.assign(static_cast<std::size_t>(surface.Mesh->GetNumberOfCells()), 0);
    for (const vtkIdType cell : surface.CellToWhole[0])
    {
      share.Own[static_cast<std::size_t>(cell)] = 1;
    }
    // A cell a lower process also holds is counted there (it reaches this process in that
    // process's halo: it lies within the radius of itself).
    const std::vector<int> holders = LowestHolders(surface, pieceProcess);
    share.Counted.resize(share.Own.size());
    for (std::size_t c = 0; c < share.Own.size(); ++c)
    {
      share.Counted[c] = share.Own[c] && holders[c] == rank ? 1 : 0;
    }
    exchangeSeconds = Seconds(start);
    start = std::chrono::steady_clock::now();
    status = RunOnMesh(algorithm, inputVector, outputVector, surface.Mesh, outputs,
      [&](vtkInformationVector** in, vtkInformationVector* out) { return body(in, out, share); });
    bodySeconds = Seconds(start);
    if (failure && !failure().empty())
    {
      outcome = Failed;
    }
    else if (algorithm->GetAbortExecute())
    {
      outcome = Aborted;
    }
  }
  catch (const HaloTooNarrowError&)
  {
    outcome = HaloTooNarrow;
  }
  catch (const std::exception& error)
  {
    vtkErrorWithObjectMacro(algorithm, "Distributed run failed on process " << rank << ": " << error.what());
    outcome = Failed;
  }
  const int highest = group.Finish(outcome);
  if (highest == HaloTooNarrow)
  {
    return std::nullopt; // every process: the caller runs on the whole surface
  }
  if (highest == Failed && outcome != Failed)
  {
    vtkErrorWithObjectMacro(algorithm, "Another process of the distributed run failed (its own error says "
                                       "why); this process keeps its input.");
  }

  // 4. Each process's own cells.
  for (int port = 0; port < outputVector->GetNumberOfInformationObjects(); ++port)
  {
    vtkDataObject* real = outputVector->GetInformationObject(port)->Get(vtkDataObject::DATA_OBJECT());
    auto* result = highest == Succeeded && !outputs.empty()
      ? vtkPolyData::SafeDownCast(outputs[static_cast<std::size_t>(port)])
      : nullptr;
    if (IsScattered(scatteredPorts, port))
    {
      ApplyResult(input,
        result ? LocalResult(local, surface.Mesh, result, surface.CellToWhole[0], surface.PointToWhole[0])
               : vtkSmartPointer<vtkPolyData>::New(),
        real);
    }
    else if (real && rank == 0 && highest == Succeeded && !outputs.empty())
    {
      real->ShallowCopy(outputs[static_cast<std::size_t>(port)]); // whole-surface outputs (a histogram)
    }
    else if (real)
    {
      real->Initialize();
    }
  }
  if (rank == 0 && TimingReportsRequested())
  {
    std::cerr << "[ShapeDiameter distributed] " << algorithm->GetClassName()
              << (kind == HaloKind::None ? " on its own cells (no halo) on " : " with a halo on ")
              << controller->GetNumberOfProcesses() << " processes: radius " << haloRadius << " ("
              << radiusSeconds << " s), process 0: " << local->GetNumberOfCells() << " own cells, "
              << surface.Mesh->GetNumberOfCells() - local->GetNumberOfCells() << " halo cells; halo exchange "
              << exchangeSeconds << " s, body " << bodySeconds << " s" << std::endl;
  }
  return highest == Succeeded ? status : 1;
}

} // namespace shapediameter::distributed
