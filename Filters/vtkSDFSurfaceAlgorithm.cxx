// SPDX-License-Identifier: BSD-3-Clause
#include "vtkSDFSurfaceAlgorithm.h"

#include "DistributedSupport.h"
#include "Mesh/FaceGraph.h"
#include "ProcessGroup.h"
#include "SurfaceConversion.h"
#include "SurfaceRequest.h"

#include "vtkDataObject.h"
#include "vtkInformation.h"
#include "vtkInformationVector.h"
#include "vtkPolyData.h"

#include <optional>

vtkSDFSurfaceAlgorithm::vtkSDFSurfaceAlgorithm(
  const char* task, const char* emptyNote, int surfacePort, bool acceptStrips)
  : Task(task)
  , EmptyNote(emptyNote)
  , SurfacePort(surfacePort)
  , AcceptStrips(acceptStrips)
{
}

vtkSDFSurfaceAlgorithm::~vtkSDFSurfaceAlgorithm() = default;

void vtkSDFSurfaceAlgorithm::KeepFaceGraph(std::shared_ptr<const shapediameter::FaceGraph> graph)
{
  // ReleaseDataFlag asks the pipeline to trade speed for memory: nothing is kept then.
  this->KeptFaceGraph = this->GetReleaseDataFlag() ? nullptr : std::move(graph);
}

namespace
{
/// Points `slot` at `share` for the lifetime of this object (a distributed run's body).
template <typename Share>
class ActiveDuring
{
public:
  ActiveDuring(const Share*& slot, const Share& share)
    : Slot(slot)
  {
    slot = &share;
  }
  ~ActiveDuring() { this->Slot = nullptr; }
  ActiveDuring(const ActiveDuring&) = delete;
  ActiveDuring& operator=(const ActiveDuring&) = delete;

private:
  const Share*& Slot;
};
} // namespace

int vtkSDFSurfaceAlgorithm::RequestData(
  vtkInformation*, vtkInformationVector** inputVector, vtkInformationVector* outputVector)
{
  using namespace shapediameter;
  if (!this->ActiveShare && !this->ActiveHalo && distributed::IsDistributedRequest(inputVector, outputVector))
  {
    if (this->CanRunReplicated())
    {
      return distributed::RunOnReplicatedSurface(this, inputVector, outputVector, { this->SurfacePort },
        [this](vtkInformationVector** in, vtkInformationVector* out, const distributed::ReplicatedShare& share) {
          const ActiveDuring<distributed::ReplicatedShare> active(this->ActiveShare, share);
          return this->RequestData(nullptr, in, out);
        });
    }
    if (this->CanRunWithHalo())
    {
      const std::optional<int> status = distributed::RunOnHaloSurface(this, inputVector, outputVector,
        { this->SurfacePort },
        this->NeedsNoHalo()           ? distributed::HaloKind::None
          : this->HaloOfSharedCorners() ? distributed::HaloKind::SharedCorners
                                        : distributed::HaloKind::CentresWithin,
        [this](vtkPolyData* piece, const ProcessGroup& group) { return this->HaloRadius(piece, group); },
        [this](vtkInformationVector** in, vtkInformationVector* out, const distributed::HaloShare& share) {
          const ActiveDuring<distributed::HaloShare> active(this->ActiveHalo, share);
          return this->RequestData(nullptr, in, out);
        },
        [this] { return this->LastFailure; }, this->CellArraysRead());
      if (status)
      {
        return *status;
      }
    }
    return distributed::RunOnWholeSurface(this, inputVector, outputVector, { this->SurfacePort },
      [this](vtkInformationVector** in, vtkInformationVector* out) { return this->RequestData(nullptr, in, out); },
      [this] { return this->LastFailure; }, this->CellArraysRead());
  }
  this->LastFailure.clear();

  vtkPolyData* input = vtkPolyData::GetData(inputVector[0]);
  vtkPolyData* output = vtkPolyData::GetData(outputVector, this->SurfacePort);
  output->ShallowCopy(input);
  if (input->GetNumberOfCells() == 0)
  {
    vtkWarningMacro("The input is empty: " << this->EmptyNote << ".");
    return 1;
  }
  if (input->GetNumberOfPolys() == 0 && !(this->AcceptStrips && input->GetNumberOfStrips() > 0))
  {
    this->LastFailure = std::string("Cannot ") + this->Task + ": the input has no polygons" +
      (this->AcceptStrips ? " or triangle strips" : "") + ".";
    vtkErrorMacro(<< this->LastFailure);
    return 1;
  }

  try
  {
    const adapter::SurfaceRequest request{ input, output, inputVector, outputVector,
      adapter::MakeSMPParallelFor(this->NumberOfThreads), this->ActiveShare, this->ActiveHalo };
    if (!this->ExecuteSurface(request))
    {
      this->PassThrough(input, outputVector);
      return 1;
    }
  }
  // Not bad input: a halo run's request to run on the whole surface (DistributedSupport.h).
  catch (const HaloTooNarrowError&)
  {
    throw;
  }
  // Bad input found by a filter's body and by the core alike (shapediameter::Error, Errors.h);
  // what() is the reason as the user reads it after "Cannot <task>: ".
  catch (const std::exception& error)
  {
    this->LastFailure = std::string("Cannot ") + this->Task + ": " + error.what();
    vtkErrorMacro(<< this->LastFailure);
    this->PassThrough(input, outputVector);
    return 1;
  }
  this->UpdateProgress(1.0);
  return 1;
}

double vtkSDFSurfaceAlgorithm::MeanEdgeLengthOverPieces(vtkPolyData* piece, const shapediameter::ProcessGroup& group)
{
  using namespace shapediameter;
  std::vector<std::int64_t> offsets, connectivity;
  adapter::PolygonCells(piece, offsets, connectivity);
  const std::vector<std::uint8_t> own(offsets.empty() ? 0 : offsets.size() - 1, 1);
  return MeanEdgeLengthOverProcesses(adapter::PointsOf(piece), offsets, connectivity, own, group);
}

double vtkSDFSurfaceAlgorithm::HaloRadius(vtkPolyData*, const shapediameter::ProcessGroup&)
{
  return -1.0; // never asked: CanRunWithHalo() is false
}

std::vector<std::string> vtkSDFSurfaceAlgorithm::WithSelectedArray(std::vector<std::string> names)
{
  std::string selected = shapediameter::adapter::SelectedArrayName(this);
  if (!selected.empty())
  {
    names.push_back(std::move(selected));
  }
  return names;
}

void vtkSDFSurfaceAlgorithm::PassThrough(vtkPolyData* input, vtkInformationVector* outputVector)
{
  for (int port = 0; port < outputVector->GetNumberOfInformationObjects(); ++port)
  {
    vtkDataObject* output = outputVector->GetInformationObject(port)->Get(vtkDataObject::DATA_OBJECT());
    if (port == this->SurfacePort)
    {
      vtkPolyData::SafeDownCast(output)->ShallowCopy(input);
    }
    else if (output)
    {
      output->Initialize();
    }
  }
}

void vtkSDFSurfaceAlgorithm::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "NumberOfThreads: " << this->NumberOfThreads << "\n";
}
