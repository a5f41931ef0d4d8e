// SPDX-License-Identifier: BSD-3-Clause
#include "DistributedSupport.h"

#include "WholeSurface.h"

#include "vtkAlgorithm.h"
#include "vtkDataObject.h"
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
  double BuildSeconds = 0.0;
  double SerialSeconds = 0.0;
};

/// Assembles the whole surface from the pieces and runs the serial algorithm on it through
/// substitute information vectors. A failure is reported and leaves Ran false, so that the
/// other processes are never left waiting (they get their input back unchanged).
WholeRun RunSerialOnWhole(vtkAlgorithm* algorithm, vtkInformationVector** inputVector,
  vtkInformationVector* outputVector, const std::vector<vtkPolyData*>& pieces, const SerialBody& serial)
{
  WholeRun run;
  try
  {
    auto start = std::chrono::steady_clock::now();
    run.Whole = AssembleWholeSurface(pieces);
    run.BuildSeconds = Seconds(start);

    start = std::chrono::steady_clock::now();
    const int inputPorts = algorithm->GetNumberOfInputPorts();
    std::vector<vtkInformationVector*> inputs(inputVector, inputVector + inputPorts);
    vtkNew<vtkInformationVector> wholeInputVector;
    vtkNew<vtkInformation> wholeInputInfo;
    wholeInputInfo->Set(vtkDataObject::DATA_OBJECT(), run.Whole.Mesh);
    wholeInputVector->Append(wholeInputInfo);
    inputs[0] = wholeInputVector;
    vtkNew<vtkInformationVector> wholeOutputVector;
    for (int port = 0; port < outputVector->GetNumberOfInformationObjects(); ++port)
    {
      vtkDataObject* real = outputVector->GetInformationObject(port)->Get(vtkDataObject::DATA_OBJECT());
      run.Outputs.push_back(vtkSmartPointer<vtkDataObject>::Take(real->NewInstance()));
      vtkNew<vtkInformation> info;
      info->Set(vtkDataObject::DATA_OBJECT(), run.Outputs.back());
      wholeOutputVector->Append(info);
    }
    run.Status = serial(inputs.data(), wholeOutputVector);
    run.SerialSeconds = Seconds(start);
    run.Ran = true;
  }
  catch (const std::exception& error)
  {
    vtkErrorWithObjectMacro(algorithm, "Distributed run failed on process 0: " << error.what());
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
int ReceiveResults(vtkMultiProcessController* controller, vtkPolyData* input, vtkInformationVector* outputVector,
  const std::vector<int>& scatteredPorts)
{
  const int status = WaitForStatus(controller);
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
  vtkInformationVector* outputVector, const std::vector<int>& scatteredPorts, const SerialBody& serial)
{
  vtkMultiProcessController* controller = Controller();
  vtkPolyData* input = vtkPolyData::GetData(inputVector[0]);
  vtkNew<vtkPolyData> local;
  if (input)
  {
    local->ShallowCopy(input);
  }
  if (controller->GetLocalProcessId() != 0)
  {
    GatherPieces(controller, local);
    return ReceiveResults(controller, input, outputVector, scatteredPorts);
  }

  auto start = std::chrono::steady_clock::now();
  const std::vector<vtkSmartPointer<vtkPolyData>> gathered = GatherPieces(controller, local);
  const double gatherSeconds = Seconds(start);
  std::vector<vtkPolyData*> pieces;
  for (const auto& piece : gathered)
  {
    pieces.push_back(piece.GetPointer());
  }
  const WholeRun run = RunSerialOnWhole(algorithm, inputVector, outputVector, pieces, serial);
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

} // namespace shapediameter::distributed
