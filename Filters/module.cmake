# SPDX-License-Identifier: BSD-3-Clause
# Sources of the VTK module ShapeDiameter::Filters (included from the generated
# module directory, see the top-level CMakeLists.txt).
set(_filters_dir "${CMAKE_CURRENT_LIST_DIR}")
set(_classes
  vtkSDFOFFReader
  vtkSDFSurfaceAlgorithm
  vtkShapeDiameterFilter
  vtkSDFBilateralSmooth
  vtkSDFGMMPartition
  vtkSDFSkeleton)

set(_classes_abs)
foreach (_class IN LISTS _classes)
  list(APPEND _classes_abs "${_filters_dir}/${_class}")
endforeach ()

vtk_module_add_module(ShapeDiameter::Filters
  CLASSES ${_classes_abs}
  SOURCES "${_filters_dir}/SurfaceConversion.cxx" "${_filters_dir}/DistributedSupport.cxx"
    "${_filters_dir}/WholeSurface.cxx"
    $<TARGET_OBJECTS:ShapeDiameterCore>
  PRIVATE_HEADERS "${_filters_dir}/SurfaceConversion.h" "${_filters_dir}/SurfaceRequest.h"
    "${_filters_dir}/DistributedSupport.h" "${_filters_dir}/WholeSurface.h")
vtk_module_include(ShapeDiameter::Filters
  PUBLIC "$<BUILD_INTERFACE:${_filters_dir}>"
  PRIVATE "${_filters_dir}/Core")
vtk_module_link(ShapeDiameter::Filters PRIVATE embree Eigen3::Eigen Threads::Threads)
vtk_module_compile_options(ShapeDiameter::Filters PRIVATE -Wall -Wextra)
# Distributed runs: with ParaView's MPI module, processes waiting for process 0 sleep instead
# of spinning in MPI (Filters/DistributedSupport.cxx). Linked by file, not as a target nor a
# module dependency: the installed package must not make its C++ consumers find
# MPI (VTK::ParallelMPI -> VTK::mpi -> MPI::MPI_C, which needs the C language).
if (TARGET VTK::ParallelMPI)
  vtk_module_link(ShapeDiameter::Filters PRIVATE "$<TARGET_FILE:VTK::ParallelMPI>")
  vtk_module_definitions(ShapeDiameter::Filters PRIVATE SHAPEDIAMETER_HAVE_MPI)
  # ParaView 5.13's vtkMPICommunicator.h includes <mpi.h> (5.11's did not): its directory, from
  # the MPI that ParaView's config found, privately (not exported to consumers).
  if (TARGET MPI::MPI_C)
    vtk_module_include(ShapeDiameter::Filters
      PRIVATE "$<TARGET_PROPERTY:MPI::MPI_C,INTERFACE_INCLUDE_DIRECTORIES>")
  endif ()
endif ()
