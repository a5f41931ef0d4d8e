// SPDX-License-Identifier: BSD-3-Clause
// Small helpers shared by the filter tests.
#pragma once

#include "vtkCommand.h"
#include "vtkObject.h"
#include "vtkSmartPointer.h"

#include <cstdlib>
#include <string>

namespace shapediameter::testing
{

/// Counts ErrorEvent/WarningEvent invocations of one VTK object and keeps the last text,
/// so tests can assert that bad input is reported (and not printed to the console).
class MessageRecorder : public vtkCommand
{
public:
  static MessageRecorder* New() { return new MessageRecorder; }

  void Execute(vtkObject*, unsigned long event, void* callData) override
  {
    const std::string text = callData ? static_cast<const char*>(callData) : "";
    if (event == vtkCommand::ErrorEvent)
    {
      ++this->Errors;
      this->LastError = text;
    }
    else if (event == vtkCommand::WarningEvent)
    {
      ++this->Warnings;
      this->LastWarning = text;
    }
  }

  void Observe(vtkObject* object)
  {
    object->AddObserver(vtkCommand::ErrorEvent, this);
    object->AddObserver(vtkCommand::WarningEvent, this);
  }

  int Errors = 0;
  int Warnings = 0;
  std::string LastError;
  std::string LastWarning;
};

/// Directory holding the bundled meshes (Data/), set by ctest.
inline std::string DataFile(const std::string& name)
{
  const char* directory = std::getenv("SHAPEDIAMETER_DATA_DIR");
  return std::string(directory ? directory : "Data") + "/" + name;
}

} // namespace shapediameter::testing
