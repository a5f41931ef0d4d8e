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
      whole = AssembleWholeSurface(pieces);
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
                << whole.Mesh->GetActualMemorySize() / 1024.0 << " MiB (cells by " << ToString(whole.Cells)
                << ", points by " << ToString(whole.Points) << "); gather " << gatherSeconds << " s, build "
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
