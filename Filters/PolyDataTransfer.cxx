// SPDX-License-Identifier: BSD-3-Clause
#include "PolyDataTransfer.h"

#include "Errors.h"

#include "vtkCellArray.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDataSetAttributes.h"
#include "vtkFieldData.h"
#include "vtkNew.h"
#include "vtkMultiProcessController.h"
#include "vtkPointData.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkTypeInt32Array.h"
#include "vtkTypeInt64Array.h"

#include <algorithm>
#include <array>
#include <cstddef>
#include <utility>

namespace shapediameter::distributed
{

namespace
{
/// The header's first value: the raw form follows, or the polydata travels whole (Marshalled).
constexpr long long RawForm = 1;
constexpr long long WholeForm = 2;
/// A name that was null (not the empty name).
constexpr long long NullName = -1;

/// Whether the message has a part that goes through vtkCommunicator's marshalling: the whole
/// polydata, or the raw form's field data (its header's last value).
bool HasMarshalledPart(const std::vector<long long>& header)
{
  return !header.empty() && (header.front() == WholeForm || (header.front() == RawForm && header.back() != 0));
}

bool IsRawArray(vtkAbstractArray* array)
{
  auto* data = vtkDataArray::SafeDownCast(array);
  return data && data->HasStandardMemoryLayout() && data->GetDataType() != VTK_BIT;
}

bool CanTravelRaw(vtkPolyData* data)
{
  if (data->GetPoints() && !IsRawArray(data->GetPoints()->GetData()))
  {
    return false;
  }
  for (vtkDataSetAttributes* attributes : { static_cast<vtkDataSetAttributes*>(data->GetPointData()),
         static_cast<vtkDataSetAttributes*>(data->GetCellData()) })
  {
    for (int a = 0; a < attributes->GetNumberOfArrays(); ++a)
    {
      if (!IsRawArray(attributes->GetAbstractArray(a)))
      {
        return false;
      }
    }
  }
  return true;
}

void PutName(const char* name, PolyDataMessage& message)
{
  if (!name)
  {
    message.Header.push_back(NullName);
    return;
  }
  const std::string text(name);
  message.Header.push_back(static_cast<long long>(text.size()));
  message.Names += text;
}

/// Reads the header and the names in the order DescribePolyData wrote them.
class MessageReader
{
public:
  MessageReader(const std::vector<long long>& header, const std::string& names)
    : Header(header)
    , Names(names)
  {
  }

  long long Next()
  {
    if (this->At >= this->Header.size())
    {
      throw Error("a polydata from another process ended early (" + std::to_string(this->Header.size()) +
        " header values)");
    }
    return this->Header[this->At++];
  }

  /// A count or size: non-negative.
  vtkIdType NextSize()
  {
    const long long value = this->Next();
    if (value < 0)
    {
      throw Error("a polydata from another process has a negative size");
    }
    return static_cast<vtkIdType>(value);
  }

  /// False for a null name.
  bool NextName(std::string& name)
  {
    const long long length = this->Next();
    if (length == NullName)
    {
      return false;
    }
    if (length < 0 || static_cast<std::size_t>(length) > this->Names.size() - this->NameAt)
    {
      throw Error("a polydata from another process has a name out of range");
    }
    name = this->Names.substr(this->NameAt, static_cast<std::size_t>(length));
    this->NameAt += static_cast<std::size_t>(length);
    return true;
  }

private:
  const std::vector<long long>& Header;
  const std::string& Names;
  std::size_t At = 0;
  std::size_t NameAt = 0;
};

/// `array` sized and its bytes read.
void ReadInto(vtkDataArray* array, int components, vtkIdType tuples,
  const std::function<void(char*, long long)>& readPayload)
{
  array->SetNumberOfComponents(components);
  array->SetNumberOfTuples(tuples);
  const long long bytes = static_cast<long long>(tuples) * components * array->GetDataTypeSize();
  if (bytes > 0)
  {
    readPayload(static_cast<char*>(array->GetVoidPointer(0)), bytes);
  }
}

/// A new array of `type` (one the raw form carries) with its bytes read.
vtkSmartPointer<vtkDataArray> ReadArray(int type, int components, vtkIdType tuples,
  const std::function<void(char*, long long)>& readPayload)
{
  auto array = vtkSmartPointer<vtkDataArray>::Take(vtkDataArray::CreateDataArray(type));
  if (!array || !array->HasStandardMemoryLayout() || components < 1)
  {
    throw Error("a polydata from another process has an array of type " + std::to_string(type) + " and " +
      std::to_string(components) + " components");
  }
  ReadInto(array, components, tuples, readPayload);
  return array;
}

/// Offsets and connectivity of the storage the sender had.
template <typename Storage>
void ReadCells(vtkCellArray* cells, vtkIdType offsets, vtkIdType connectivity,
  const std::function<void(char*, long long)>& readPayload)
{
  vtkNew<Storage> offsetValues;
  vtkNew<Storage> connectivityValues;
  ReadInto(offsetValues, 1, offsets, readPayload);
  ReadInto(connectivityValues, 1, connectivity, readPayload);
  cells->SetData(offsetValues, connectivityValues);
}

std::array<vtkCellArray*, 4> CellArraysOf(vtkPolyData* data)
{
  return { data->GetVerts(), data->GetLines(), data->GetPolys(), data->GetStrips() };
}

void DescribeAttributes(vtkDataSetAttributes* attributes, PolyDataMessage& message)
{
  message.Header.push_back(attributes->GetNumberOfArrays());
  for (int a = 0; a < attributes->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* array = attributes->GetArray(a);
    long long roles = 0;
    for (int attribute = 0; attribute < vtkDataSetAttributes::NUM_ATTRIBUTES; ++attribute)
    {
      if (attributes->GetAbstractAttribute(attribute) == array)
      {
        roles |= 1LL << attribute;
      }
    }
    message.Header.insert(message.Header.end(),
      { array->GetDataType(), array->GetNumberOfComponents(), array->GetNumberOfTuples(), roles });
    PutName(array->GetName(), message);
    message.Header.push_back(array->HasAComponentName() ? 1 : 0);
    if (array->HasAComponentName())
    {
      for (int c = 0; c < array->GetNumberOfComponents(); ++c)
      {
        PutName(array->GetComponentName(c), message);
      }
    }
    message.Payloads.push_back(array);
  }
}

void RebuildAttributes(MessageReader& reader, const std::function<void(char*, long long)>& readPayload,
  vtkDataSetAttributes* attributes)
{
  const vtkIdType count = reader.NextSize();
  std::vector<std::pair<int, long long>> roles;
  for (vtkIdType a = 0; a < count; ++a)
  {
    const auto type = static_cast<int>(reader.Next());
    const auto components = static_cast<int>(reader.Next());
    const vtkIdType tuples = reader.NextSize();
    const long long arrayRoles = reader.Next();
    std::string name;
    const bool named = reader.NextName(name);
    const bool componentNames = reader.Next() != 0;
    std::vector<std::pair<int, std::string>> namesOfComponents;
    for (int c = 0; componentNames && c < components; ++c)
    {
      std::string componentName;
      if (reader.NextName(componentName))
      {
        namesOfComponents.emplace_back(c, componentName);
      }
    }
    vtkSmartPointer<vtkDataArray> array = ReadArray(type, components, tuples, readPayload);
    if (named)
    {
      array->SetName(name.c_str());
    }
    for (const auto& [c, componentName] : namesOfComponents)
    {
      array->SetComponentName(c, componentName.c_str());
    }
    roles.emplace_back(attributes->AddArray(array), arrayRoles);
  }
  for (const auto& [index, arrayRoles] : roles)
  {
    for (int attribute = 0; attribute < vtkDataSetAttributes::NUM_ATTRIBUTES; ++attribute)
    {
      if (arrayRoles & (1LL << attribute))
      {
        attributes->SetActiveAttribute(index, attribute);
      }
    }
  }
}
} // namespace

PolyDataMessage DescribePolyData(vtkPolyData* data)
{
  PolyDataMessage message;
  if (!CanTravelRaw(data))
  {
    message.Header.push_back(WholeForm);
    message.Marshalled = data;
    return message;
  }
  message.Header.push_back(RawForm);
  vtkPoints* points = data->GetPoints();
  if (points)
  {
    message.Header.insert(message.Header.end(), { points->GetData()->GetDataType(), points->GetNumberOfPoints() });
    message.Payloads.push_back(points->GetData());
  }
  else
  {
    message.Header.insert(message.Header.end(), { -1, 0 });
  }
  for (vtkCellArray* cells : CellArraysOf(data))
  {
    const bool any = cells && cells->GetNumberOfCells() > 0;
    message.Header.insert(message.Header.end(), { any ? 1 : 0, any && cells->IsStorage64Bit() ? 1 : 0,
                                                  any ? cells->GetOffsetsArray()->GetNumberOfValues() : 0,
                                                  any ? cells->GetConnectivityArray()->GetNumberOfValues() : 0 });
    if (any)
    {
      message.Payloads.push_back(cells->GetOffsetsArray());
      message.Payloads.push_back(cells->GetConnectivityArray());
    }
  }
  DescribeAttributes(data->GetPointData(), message);
  DescribeAttributes(data->GetCellData(), message);
  const bool fields = data->GetFieldData() && data->GetFieldData()->GetNumberOfArrays() > 0;
  message.Header.push_back(fields ? 1 : 0);
  if (fields)
  {
    auto carrier = vtkSmartPointer<vtkPolyData>::New();
    carrier->GetFieldData()->ShallowCopy(data->GetFieldData());
    message.Marshalled = carrier;
  }
  return message;
}

vtkSmartPointer<vtkPolyData> RebuildPolyData(const std::vector<long long>& header, const std::string& names,
  vtkDataObject* marshalled, const std::function<void(char*, long long)>& readPayload)
{
  MessageReader reader(header, names);
  const long long form = reader.Next();
  if (form == WholeForm)
  {
    auto whole = vtkSmartPointer<vtkPolyData>::New();
    if (auto* sent = vtkPolyData::SafeDownCast(marshalled))
    {
      whole->ShallowCopy(sent);
    }
    return whole;
  }
  if (form != RawForm)
  {
    throw Error("a polydata from another process is in an unknown form (" + std::to_string(form) + ")");
  }
  auto data = vtkSmartPointer<vtkPolyData>::New();
  const auto pointType = static_cast<int>(reader.Next());
  const vtkIdType pointCount = reader.NextSize();
  if (pointType >= 0)
  {
    vtkNew<vtkPoints> points;
    points->SetData(ReadArray(pointType, 3, pointCount, readPayload));
    data->SetPoints(points);
  }
  std::array<vtkSmartPointer<vtkCellArray>, 4> cellArrays;
  for (vtkSmartPointer<vtkCellArray>& cells : cellArrays)
  {
    const bool any = reader.Next() != 0;
    const bool storage64 = reader.Next() != 0;
    const vtkIdType offsets = reader.NextSize();
    const vtkIdType connectivity = reader.NextSize();
    if (!any)
    {
      continue;
    }
    cells = vtkSmartPointer<vtkCellArray>::New();
    if (storage64)
    {
      ReadCells<vtkTypeInt64Array>(cells, offsets, connectivity, readPayload);
    }
    else
    {
      ReadCells<vtkTypeInt32Array>(cells, offsets, connectivity, readPayload);
    }
  }
  data->SetVerts(cellArrays[0]);
  data->SetLines(cellArrays[1]);
  data->SetPolys(cellArrays[2]);
  data->SetStrips(cellArrays[3]);
  RebuildAttributes(reader, readPayload, data->GetPointData());
  RebuildAttributes(reader, readPayload, data->GetCellData());
  if (reader.Next() != 0)
  {
    if (auto* carrier = vtkPolyData::SafeDownCast(marshalled))
    {
      data->GetFieldData()->ShallowCopy(carrier->GetFieldData());
    }
  }
  return data;
}

void SendPolyData(vtkMultiProcessController* controller, vtkPolyData* data, int to, int tag)
{
  const PolyDataMessage message = DescribePolyData(data);
  const auto headerSize = static_cast<vtkIdType>(message.Header.size());
  controller->Send(&headerSize, 1, to, tag);
  controller->Send(message.Header.data(), headerSize, to, tag);
  const auto namesSize = static_cast<vtkIdType>(message.Names.size());
  controller->Send(&namesSize, 1, to, tag);
  if (namesSize > 0)
  {
    controller->Send(message.Names.data(), namesSize, to, tag);
  }
  if (message.Marshalled)
  {
    controller->Send(message.Marshalled, to, tag);
  }
  for (vtkDataArray* array : message.Payloads)
  {
    const auto bytes = static_cast<vtkIdType>(array->GetNumberOfValues() * array->GetDataTypeSize());
    if (bytes > 0)
    {
      controller->Send(static_cast<const char*>(array->GetVoidPointer(0)), bytes, to, tag);
    }
  }
}

vtkSmartPointer<vtkPolyData> ReceivePolyData(vtkMultiProcessController* controller, int from, int tag)
{
  vtkIdType headerSize = 0;
  controller->Receive(&headerSize, 1, from, tag);
  std::vector<long long> header(static_cast<std::size_t>(std::max<vtkIdType>(headerSize, 0)));
  controller->Receive(header.data(), headerSize, from, tag);
  vtkIdType namesSize = 0;
  controller->Receive(&namesSize, 1, from, tag);
  std::string names(static_cast<std::size_t>(std::max<vtkIdType>(namesSize, 0)), '\0');
  if (namesSize > 0)
  {
    controller->Receive(names.data(), namesSize, from, tag);
  }
  // The marshalled part comes before the payloads: its presence is in the header.
  vtkSmartPointer<vtkPolyData> marshalled;
  if (HasMarshalledPart(header))
  {
    marshalled = vtkSmartPointer<vtkPolyData>::New();
    controller->Receive(marshalled, from, tag);
  }
  return RebuildPolyData(header, names, marshalled,
    [&](char* destination, long long bytes) { controller->Receive(destination, static_cast<vtkIdType>(bytes), from, tag); });
}

} // namespace shapediameter::distributed
