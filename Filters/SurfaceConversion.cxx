// SPDX-License-Identifier: BSD-3-Clause
#include "SurfaceConversion.h"

#include "vtkAlgorithm.h"
#include "vtkCellArray.h"
#include "vtkCellArrayIterator.h"
#include "vtkCellData.h"
#include "vtkDataArray.h"
#include "vtkDoubleArray.h"
#include "vtkFloatArray.h"
#include "vtkInformation.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkSMPTools.h"
#include "vtkSmartPointer.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <future>
#include <memory>
#include <numeric>
#include <sstream>
#include <thread>
#include <vector>

namespace shapediameter::adapter
{
namespace
{
// Appends the triangles of one polygon (fan) or one strip; returns how many.
std::int64_t AppendTriangles(
  const vtkIdType* ids, vtkIdType count, bool isStrip, std::vector<std::int64_t>& triangles)
{
  std::int64_t added = 0;
  for (vtkIdType i = 0; i + 2 < count; ++i, ++added)
  {
    if (isStrip)
    {
      const bool flip = (i % 2) == 1;
      triangles.insert(triangles.end(),
        { ids[i], flip ? ids[i + 2] : ids[i + 1], flip ? ids[i + 1] : ids[i + 2] });
    }
    else
    {
      triangles.insert(triangles.end(), { ids[0], ids[i + 1], ids[i + 2] });
    }
  }
  return added;
}
} // namespace

std::string Triangulate(vtkPolyData* input, TriangulatedSurface& surface)
{
  const vtkIdType cellCount = input->GetNumberOfCells();
  const vtkIdType firstPolygon = input->GetNumberOfVerts() + input->GetNumberOfLines();
  if (input->GetNumberOfPolys() + input->GetNumberOfStrips() == 0 || !input->GetPoints())
  {
    return "the input has no polygons or triangle strips";
  }

  const vtkIdType pointCount = input->GetNumberOfPoints();
  surface.Points = PointsOf(input);
  surface.TriangleCell.clear();
  surface.CellFirstTriangle.assign(static_cast<std::size_t>(cellCount) + 1, 0);
  std::int64_t triangleCount = 0;
  vtkIdType cellId = firstPolygon; // then one past the last polygon or strip cell
  vtkCellArray* polys = input->GetPolys();
  if (input->GetNumberOfStrips() == 0 && polys->IsHomogeneous() == 3)
  {
    // Triangles only (the common case): the connectivity is the triangle matrix; no iterator,
    // no per-cell vector growth (832k triangles: 0.155 s -> 0.028 s with the points' copy below,
    // docs/performance.md).
    triangleCount = polys->GetNumberOfCells();
    surface.Triangles.resize(triangleCount, 3);
    const auto copyIds = [&](const auto* ids) {
      std::copy(ids, ids + 3 * triangleCount, surface.Triangles.data());
    };
    if (polys->IsStorage64Bit())
    {
      copyIds(polys->GetConnectivityArray64()->GetPointer(0));
    }
    else
    {
      copyIds(polys->GetConnectivityArray32()->GetPointer(0));
    }
    surface.TriangleCell.resize(static_cast<std::size_t>(triangleCount));
    std::iota(surface.TriangleCell.begin(), surface.TriangleCell.end(), firstPolygon);
    for (std::int64_t t = 0; t < triangleCount; ++t)
    {
      surface.CellFirstTriangle[static_cast<std::size_t>(firstPolygon + t) + 1] = t + 1;
    }
    cellId = firstPolygon + triangleCount;
  }
  else
  {
    std::vector<std::int64_t> triangles;
    triangles.reserve(static_cast<std::size_t>(input->GetNumberOfPolys()) * 3);
    for (vtkCellArray* cells : { polys, input->GetStrips() })
    {
      const bool isStrip = cells == input->GetStrips();
      auto iterator = vtk::TakeSmartPointer(cells->NewIterator());
      for (iterator->GoToFirstCell(); !iterator->IsDoneWithTraversal(); iterator->GoToNextCell(), ++cellId)
      {
        vtkIdType count;
        const vtkIdType* ids;
        iterator->GetCurrentCell(count, ids);
        const std::int64_t added = AppendTriangles(ids, count, isStrip, triangles);
        surface.TriangleCell.insert(surface.TriangleCell.end(), static_cast<std::size_t>(added), cellId);
        triangleCount += added;
        surface.CellFirstTriangle[static_cast<std::size_t>(cellId) + 1] = triangleCount;
      }
    }
    surface.Triangles = Eigen::Map<const TriangleMatrix>(triangles.data(), triangleCount, 3);
  }
  // Cells after the last polygon (none) and before the first (verts, lines) own no triangle.
  for (std::size_t c = static_cast<std::size_t>(cellId) + 1; c < surface.CellFirstTriangle.size(); ++c)
  {
    surface.CellFirstTriangle[c] = triangleCount;
  }

  std::vector<char> finite(static_cast<std::size_t>(pointCount));
  for (vtkIdType p = 0; p < pointCount; ++p)
  {
    finite[static_cast<std::size_t>(p)] = surface.Points.row(p).allFinite() ? 1 : 0;
  }
  std::vector<char> used(static_cast<std::size_t>(pointCount), 0);
  const std::int64_t* ids = surface.Triangles.data();
  for (std::int64_t k = 0; k < 3 * triangleCount; ++k)
  {
    const std::int64_t id = ids[k];
    if (id < 0 || id >= pointCount)
    {
      std::ostringstream reason;
      reason << "a polygon references point " << id << " but the input has " << pointCount << " points";
      return reason.str();
    }
    if (!finite[static_cast<std::size_t>(id)])
    {
      std::ostringstream reason;
      reason << "point " << id << " used by a polygon has a non-finite coordinate";
      return reason.str();
    }
    used[static_cast<std::size_t>(id)] = 1;
  }
  // Points no polygon uses play no part; a non-finite one must not reach the ray caster.
  for (vtkIdType p = 0; p < pointCount; ++p)
  {
    if (!used[static_cast<std::size_t>(p)] && !finite[static_cast<std::size_t>(p)])
    {
      surface.Points.row(p).setZero();
    }
  }
  return {};
}

PointMatrix PointsOf(vtkPolyData* input)
{
  const vtkIdType pointCount = input->GetPoints() ? input->GetNumberOfPoints() : 0;
  PointMatrix points(pointCount, 3);
  if (pointCount == 0)
  {
    return points;
  }
  // vtkPoints hold 3-component AOS arrays: float and double (nearly every reader's output)
  // are copied straight, anything else through the virtual per-point accessor.
  vtkDataArray* data = input->GetPoints()->GetData();
  const auto copyFrom = [&](auto* array) {
    std::copy(array->GetPointer(0), array->GetPointer(0) + 3 * pointCount, points.data());
  };
  if (auto* doubles = vtkDoubleArray::FastDownCast(data))
  {
    copyFrom(doubles);
  }
  else if (auto* floats = vtkFloatArray::FastDownCast(data))
  {
    copyFrom(floats);
  }
  else
  {
    for (vtkIdType p = 0; p < pointCount; ++p)
    {
      input->GetPoints()->GetPoint(p, points.row(p).data());
    }
  }
  return points;
}

vtkIdType PolygonCells(
  vtkPolyData* input, std::vector<std::int64_t>& offsets, std::vector<std::int64_t>& connectivity)
{
  const auto [first, last] = PolygonCellRange(input);
  offsets.assign(static_cast<std::size_t>(first) + 1, 0);
  offsets.reserve(static_cast<std::size_t>(input->GetNumberOfCells()) + 1);
  connectivity.clear();
  connectivity.reserve(static_cast<std::size_t>(input->GetPolys()->GetNumberOfConnectivityIds()));
  auto iterator = vtk::TakeSmartPointer(input->GetPolys()->NewIterator());
  for (iterator->GoToFirstCell(); !iterator->IsDoneWithTraversal(); iterator->GoToNextCell())
  {
    vtkIdType count;
    const vtkIdType* ids;
    iterator->GetCurrentCell(count, ids);
    connectivity.insert(connectivity.end(), ids, ids + count);
    offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
  }
  offsets.resize(static_cast<std::size_t>(input->GetNumberOfCells()) + 1, offsets.back());
  return last - first;
}

std::pair<vtkIdType, vtkIdType> PolygonCellRange(vtkPolyData* input)
{
  const vtkIdType first = input->GetNumberOfVerts() + input->GetNumberOfLines();
  return { first, first + input->GetNumberOfPolys() };
}

std::pair<vtkIdType, vtkIdType> PolygonFaces(
  vtkPolyData* input, std::vector<std::int64_t>& offsets, std::vector<std::int64_t>& connectivity)
{
  // Verts and lines come first and have empty entries: the polygons' offsets start at 0.
  PolygonCells(input, offsets, connectivity);
  const auto [first, last] = PolygonCellRange(input);
  offsets.erase(offsets.begin() + last + 1, offsets.end());
  offsets.erase(offsets.begin(), offsets.begin() + first);
  return { first, last };
}

std::string SelectedArrayName(vtkAlgorithm* algorithm)
{
  vtkInformation* selection = algorithm->GetInputArrayInformation(0);
  return selection && selection->Has(vtkDataObject::FIELD_NAME()) ? selection->Get(vtkDataObject::FIELD_NAME())
                                                                 : "";
}

std::string ReadCellScalars(vtkAlgorithm* algorithm, vtkPolyData* input, const char* defaultName,
  std::vector<double>& values, std::string& arrayName)
{
  vtkInformation* selection = algorithm->GetInputArrayInformation(0);
  arrayName = SelectedArrayName(algorithm);
  if (arrayName.empty())
  {
    // ParaView sends an empty selection when the proxy was created before its input had
    // arrays (pvpython chains): the documented default applies.
    arrayName = defaultName;
    return ReadNamedCellScalars(input, values, arrayName);
  }
  if (selection && selection->Has(vtkDataObject::FIELD_ASSOCIATION()) &&
    selection->Get(vtkDataObject::FIELD_ASSOCIATION()) != vtkDataObject::FIELD_ASSOCIATION_CELLS)
  {
    return "the input array must be a cell array";
  }
  return ReadNamedCellScalars(input, values, arrayName);
}

std::string ReadNamedCellScalars(vtkPolyData* input, std::vector<double>& values, const std::string& arrayName)
{
  vtkAbstractArray* abstractArray = input->GetCellData()->GetAbstractArray(arrayName.c_str());
  if (!abstractArray)
  {
    return "the input has no cell array '" + arrayName + "'";
  }
  vtkDataArray* array = vtkDataArray::SafeDownCast(abstractArray);
  if (!array)
  {
    return "the cell array '" + arrayName + "' is not numeric";
  }
  if (array->GetNumberOfComponents() != 1)
  {
    return "the cell array '" + arrayName + "' has " + std::to_string(array->GetNumberOfComponents()) +
      " components, 1 expected";
  }
  const vtkIdType count = array->GetNumberOfTuples();
  if (count != input->GetNumberOfCells())
  {
    return "the cell array '" + arrayName + "' has " + std::to_string(count) + " values for " +
      std::to_string(input->GetNumberOfCells()) + " cells";
  }
  values.resize(static_cast<std::size_t>(count));
  for (vtkIdType i = 0; i < count; ++i)
  {
    values[static_cast<std::size_t>(i)] = array->GetComponent(i, 0);
    if (!std::isfinite(values[static_cast<std::size_t>(i)]))
    {
      return "the cell array '" + arrayName + "' has a non-finite value at cell " + std::to_string(i);
    }
  }
  return {};
}

namespace
{
/// What a worker thread reported last for one algorithm, waiting for its creating thread to
/// pass it on (VTK's progress observers, Python's included, are not thread-safe).
struct PendingProgress
{
  vtkAlgorithm* Algorithm = nullptr;
  double Begin = 0.0;
  double End = 1.0;
  std::atomic<double> Latest{ -1.0 };
  double Reported = -1.0;

  void Report()
  {
    const double fraction = this->Latest.load(std::memory_order_relaxed);
    if (fraction > this->Reported)
    {
      this->Reported = fraction;
      this->Algorithm->UpdateProgress(this->Begin + (this->End - this->Begin) * fraction);
    }
  }
};

/// The progress callbacks created on this thread and still alive.
thread_local std::vector<std::weak_ptr<PendingProgress>> PendingOnThisThread;

void ReportPendingProgress()
{
  auto& pending = PendingOnThisThread;
  pending.erase(std::remove_if(pending.begin(), pending.end(),
                  [](const std::weak_ptr<PendingProgress>& entry) { return entry.expired(); }),
    pending.end());
  for (const auto& entry : pending)
  {
    if (const auto state = entry.lock())
    {
      state->Report();
    }
  }
}
} // namespace

ParallelFor MakeSMPParallelFor(int threads)
{
  return [threads](std::size_t count, const RangeBody& body) {
    // The loop runs on a helper thread while this thread passes the workers' progress on to
    // the algorithm every 50 ms: vtkSMPTools' STDThread backend does the work in its pool,
    // so this thread would otherwise report nothing until the loop ends.
    std::exception_ptr failure;
    std::promise<void> done;
    std::future<void> finished = done.get_future();
    std::thread loop([&]() {
      try
      {
        vtkSMPTools::LocalScope(vtkSMPTools::Config{ threads, "STDThread", false }, [&]() {
          vtkSMPTools::For(0, static_cast<vtkIdType>(count), [&](vtkIdType begin, vtkIdType end) {
            body(static_cast<std::size_t>(begin), static_cast<std::size_t>(end));
          });
        });
      }
      catch (...)
      {
        failure = std::current_exception();
      }
      done.set_value();
    });
    while (finished.wait_for(std::chrono::milliseconds(50)) != std::future_status::ready)
    {
      ReportPendingProgress();
    }
    loop.join();
    ReportPendingProgress();
    if (failure)
    {
      std::rethrow_exception(failure);
    }
  };
}

ProgressCallback MakeProgress(vtkAlgorithm* algorithm, double begin, double end)
{
  // Any thread may call it: the fraction is stored, and the creating thread reports it (here,
  // or while it waits for a parallel loop). Every thread may read the abort flag.
  auto state = std::make_shared<PendingProgress>();
  state->Algorithm = algorithm;
  state->Begin = begin;
  state->End = end;
  PendingOnThisThread.push_back(state);
  return [state, owner = std::this_thread::get_id()](double fraction) {
    const double clamped = std::min(1.0, std::max(0.0, fraction));
    double previous = state->Latest.load(std::memory_order_relaxed);
    while (clamped > previous && !state->Latest.compare_exchange_weak(previous, clamped, std::memory_order_relaxed))
    {
    }
    if (std::this_thread::get_id() == owner)
    {
      state->Report();
    }
    return !state->Algorithm->GetAbortExecute();
  };
}

} // namespace shapediameter::adapter
