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

# The classes' public headers are handed to VTK as copies in this module's binary directory,
# next to the generated ShapeDiameterFiltersModule.h. VTK >= 9.3 (ParaView 5.13) checks that
# every public header passed as an absolute path lies under CMAKE_CURRENT_BINARY_DIR and
# emits an AUTHOR_WARNING ("source appears to be outside of the module's source or binary
# directory") for each one that does not, which Filters/ never is: this directory's source
# dir is generated in the build tree (see the top-level CMakeLists.txt) and its binary dir is
# elsewhere again. The copies change nothing that is installed or wrapped (same names, same
# contents, same flat include/ShapeDiameter/ destination; VTK 9.2 installs and wraps them the
# same way). configure_file makes each header a configure dependency: editing one in Filters/
# re-runs CMake at the next build, which refreshes the copy before anything is compiled or
# wrapped from it. The .cxx files and the private headers stay where they are (VTK does not
# check them), so `CLASSES` is spelled out as SOURCES + HEADERS, in the same order.
set(_class_sources)
set(_class_headers)
foreach (_class IN LISTS _classes)
  list(APPEND _class_sources "${_filters_dir}/${_class}.cxx")
  configure_file("${_filters_dir}/${_class}.h" "${CMAKE_CURRENT_BINARY_DIR}/${_class}.h" COPYONLY)
  list(APPEND _class_headers "${CMAKE_CURRENT_BINARY_DIR}/${_class}.h")
endforeach ()

vtk_module_add_module(ShapeDiameter::Filters
  SOURCES "${_filters_dir}/SurfaceConversion.cxx" "${_filters_dir}/DistributedSupport.cxx"
    "${_filters_dir}/PolyDataTransfer.cxx"
    "${_filters_dir}/WholeSurface.cxx"
    $<TARGET_OBJECTS:ShapeDiameterCore>
    ${_class_sources}
  HEADERS ${_class_headers}
  PRIVATE_HEADERS "${_filters_dir}/SurfaceConversion.h" "${_filters_dir}/SurfaceRequest.h"
    "${_filters_dir}/DistributedSupport.h" "${_filters_dir}/PolyDataTransfer.h"
    "${_filters_dir}/WholeSurface.h")
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
