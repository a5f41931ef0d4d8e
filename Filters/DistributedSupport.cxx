// SPDX-License-Identifier: BSD-3-Clause
#include "DistributedSupport.h"

#include "Errors.h"
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
#include "vtkPolyData.h"
#include "vtkSmartPointer.h"
#include "vtkStreamingDemandDrivenPipeline.h"

#ifdef SHAPEDIAMETER_HAVE_MPI
#include "vtkMPICommunicator.h"
#endif

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <exception>
#include <functional>
#include <iostream>
#include <string>
#include <thread>

namespace shapediameter::distributed
{
namespace
{
constexpr int RESULT_TAG = 592008;
constexpr int STATUS_TAG = 592007;
constexpr int GATHER_TAG = 592006;
constexpr int REPLICA_TAG = 592010; // and the next one
constexpr int BARRIER_TAG = 592012;
constexpr int FAILURE_TAG = 592013; // and the next one

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

/// Process 0 to process r: the elements of `items` (ids, a text), their count first.
template <typename Container>
void SendSized(vtkMultiProcessController* controller, const Container& items, int r, int tag)
{
  vtkIdType count = static_cast<vtkIdType>(items.size());
  controller->Send(&count, 1, r, tag);
  if (count > 0)
  {
    controller->Send(items.data(), count, r, tag + 1);
  }
}

/// On process r: what SendSized sent it.
template <typename Container>
Container ReceiveSized(vtkMultiProcessController* controller, int tag)
{
  vtkIdType count = 0;
  controller->Receive(&count, 1, 0, tag);
  Container items(static_cast<std::size_t>(std::max<vtkIdType>(count, 0)), typename Container::value_type{});
  if (count > 0)
  {
    controller->Receive(items.data(), count, 0, tag + 1);
  }
  return items;
}

/// A barrier whose waiting processes sleep (SleepingReceive), before a collective that would
/// otherwise spin while the slowest process is still computing.
void SleepingBarrier(vtkMultiProcessController* controller)
{
  int token = 1;
  if (controller->GetLocalProcessId() == 0)
  {
    for (int r = 1; r < controller->GetNumberOfProcesses(); ++r)
    {
      SleepingReceive(controller, r, BARRIER_TAG);
    }
    for (int r = 1; r < controller->GetNumberOfProcesses(); ++r)
    {
      controller->Send(&token, 1, r, BARRIER_TAG);
    }
  }
  else
  {
    controller->Send(&token, 1, 0, BARRIER_TAG);
    SleepingReceive(controller, 0, BARRIER_TAG);
  }
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
      gathered[static_cast<std::size_t>(r)] = vtkSmartPointer<vtkPolyData>::New();
      controller->Receive(gathered[static_cast<std::size_t>(r)], r, GATHER_TAG);
    }
  }
  else
  {
    controller->Send(local, 0, GATHER_TAG);
  }
  return gathered;
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
        controller->Send(result, r, RESULT_TAG + port);
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
  const auto failure = ReceiveSized<std::string>(controller, FAILURE_TAG);
  if (!failure.empty())
  {
    vtkErrorWithObjectMacro(algorithm, << failure << " (process 0, which ran the filter on the whole surface; this process keeps its input)");
  }
  for (int port = 0; port < outputVector->GetNumberOfInformationObjects(); ++port)
  {
    vtkDataObject* real = outputVector->GetInformationObject(port)->Get(vtkDataObject::DATA_OBJECT());
    if (IsScattered(scatteredPorts, port))
    {
      vtkNew<vtkPolyData> result;
      controller->Receive(result, 0, RESULT_TAG + port);
      ApplyResult(input, result, real);
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
  const char* timing = std::getenv("SHAPEDIAMETER_DISTRIBUTED_TIMING");
  if (timing && std::string(timing) != "0")
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

  // 1. The whole surface and the owners on process 0; the others sleep until it is ready.
  WholeSurface whole;
  std::vector<int> owner;
  int ready = 1;
  if (rank == 0)
  {
    const std::vector<vtkSmartPointer<vtkPolyData>> gathered = GatherPieces(controller, local);
    std::vector<vtkPolyData*> pieces;
    for (const auto& piece : gathered)
    {
      pieces.push_back(piece.GetPointer());
    }
    try
    {
      whole = AssembleWholeSurface(pieces);
      owner.assign(static_cast<std::size_t>(whole.Mesh->GetNumberOfCells()), -1);
      for (int r = 0; r < processes; ++r)
      {
        for (const vtkIdType cell : whole.CellToWhole[static_cast<std::size_t>(r)])
        {
          if (cell >= 0 && owner[static_cast<std::size_t>(cell)] < 0)
          {
            owner[static_cast<std::size_t>(cell)] = r;
          }
        }
      }
    }
    catch (const std::exception& error)
    {
      vtkErrorWithObjectMacro(algorithm, "Distributed run failed on process 0: " << error.what());
      ready = 0;
    }
    for (int r = 1; r < processes; ++r)
    {
      controller->Send(&ready, 1, r, STATUS_TAG);
    }
  }
  else
  {
    GatherPieces(controller, local);
    ready = WaitForStatus(controller);
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

  // 2. Every process: the whole surface, the owners, its own cells' and points' places.
  controller->Broadcast(whole.Mesh, 0);
  owner.resize(static_cast<std::size_t>(whole.Mesh->GetNumberOfCells()));
  if (!owner.empty())
  {
    controller->Broadcast(owner.data(), static_cast<vtkIdType>(owner.size()), 0);
  }
  if (rank == 0)
  {
    for (int r = 1; r < processes; ++r)
    {
      SendSized(controller, whole.CellToWhole[static_cast<std::size_t>(r)], r, REPLICA_TAG);
      SendSized(controller, whole.PointToWhole[static_cast<std::size_t>(r)], r, REPLICA_TAG);
    }
    cellToWhole = whole.CellToWhole[0];
    pointToWhole = whole.PointToWhole[0];
  }
  else
  {
    cellToWhole = ReceiveSized<std::vector<vtkIdType>>(controller, REPLICA_TAG);
    pointToWhole = ReceiveSized<std::vector<vtkIdType>>(controller, REPLICA_TAG);
  }
  const double shareSeconds = Seconds(start) - assembleSeconds;

  // 3. The body on the whole surface, every process its own cells.
  ReplicatedShare share;
  share.Owned.resize(owner.size());
  for (std::size_t c = 0; c < owner.size(); ++c)
  {
    share.Owned[c] = owner[c] == rank ? 1 : 0;
  }
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
  const double bodySeconds = Seconds(start) - assembleSeconds - shareSeconds;

  // 4. Each process's own cells.
  keepOwnCells(outputs);
  int lowest = status;
  controller->AllReduce(&status, &lowest, 1, vtkCommunicator::MIN_OP);
  const char* timing = std::getenv("SHAPEDIAMETER_DISTRIBUTED_TIMING");
  if (rank == 0 && timing && std::string(timing) != "0")
  {
    std::cerr << "[ShapeDiameter distributed] " << algorithm->GetClassName() << " replicated on " << processes
              << " processes: " << whole.Mesh->GetNumberOfCells() << " cells (by " << ToString(whole.Cells)
              << ", points by " << ToString(whole.Points) << "); gather and build " << assembleSeconds
              << " s, share " << shareSeconds << " s, body " << bodySeconds << " s, local results "
              << Seconds(start) - assembleSeconds - shareSeconds - bodySeconds << " s" << std::endl;
  }
  return lowest;
}

} // namespace shapediameter::distributed
