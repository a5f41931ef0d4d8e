# SPDX-License-Identifier: BSD-3-Clause
# Works around Debian 13's paraview-dev (5.13.2+dfsg-2 and later).
#
# ParaView's exports of its Python modules, vtk/VTKPython-targets(-debug).cmake and
# ParaViewPython-targets(-debug).cmake, name the extension modules
# lib/python3/dist-packages/{vtkmodules,paraview/modules}/vtk<Module>.so, but since 5.13.2+dfsg-2 ("drop
# --no-ext-rename option from dh_python3", debian/changelog) the package installs them renamed to
# vtk<Module>.cpython-<ver>-<multiarch>.so. CMake's existence check at the end of the export then
# stops find_package(VTK) and find_package(ParaView):
#   The imported target "VTK::vtkCommonCorePython" references the file
#   "/usr/lib/python3/dist-packages/vtkmodules/vtkCommonCore.so" but this file does not exist.
# No Debian 13 package ships the old names (python3-paraview and python3-vtk9 both ship the
# renamed files; checked in trixie's Contents-amd64), and VTK's and ParaView's configs force
# their Python wrapping ON, so no cache setting skips these exports.
#
# shapediameter_fix_python_export(<export file>) loads a copy of such an export whose file names
# are the installed ones. All its targets are then defined with correct
# locations, and the original export, included later by find_package, returns at once (a
# CMake export skips itself when every target it defines already exists).
# It does nothing when the export's files exist (Debian 12, ParaView 5.11) or the targets
# exist already. It must run before find_package(ParaView) / find_package(VTK).
function (shapediameter_fix_python_export main)
  set(_main "${main}")
  if (NOT EXISTS "${_main}")
    return ()
  endif ()
  file(READ "${_main}" _main_text)
  if (_main_text MATCHES "_cmake_expected_target IN ITEMS ([^ )]+)")
    if (TARGET "${CMAKE_MATCH_1}")
      return () # loaded already
    endif ()
  endif ()
  get_filename_component(_export_dir "${_main}" DIRECTORY)
  get_filename_component(_export_name "${_main}" NAME_WE)
  # The export computes its prefix by stripping one path component per line from its own dir.
  string(REGEX MATCHALL "get_filename_component\\(_IMPORT_PREFIX \"\\\${_IMPORT_PREFIX}\" PATH\\)"
    _strips "${_main_text}")
  list(LENGTH _strips _strip_count)
  get_filename_component(_prefix "${_main}" DIRECTORY)
  foreach (_i RANGE 1 ${_strip_count})
    get_filename_component(_prefix "${_prefix}" DIRECTORY)
  endforeach ()

  set(_copy_dir "${CMAKE_BINARY_DIR}/CMakeFiles/ShapeDiameterPythonExports/${_export_name}")
  file(GLOB _config_files "${_export_dir}/${_export_name}-*.cmake")
  set(_patched FALSE)
  set(_unresolved)
  set(_copies)
  foreach (_config IN LISTS _config_files)
    file(READ "${_config}" _text)
    string(REGEX MATCHALL "\\\${_IMPORT_PREFIX}/[^\"]+\\.so\"" _references "${_text}")
    list(REMOVE_DUPLICATES _references)
    foreach (_reference IN LISTS _references)
      string(REGEX REPLACE "^\\\${_IMPORT_PREFIX}/(.*)\"$" "\\1" _relative "${_reference}")
      if (EXISTS "${_prefix}/${_relative}")
        continue ()
      endif ()
      string(REGEX REPLACE "\\.so$" "" _stem "${_relative}")
      file(GLOB _renamed RELATIVE "${_prefix}" "${_prefix}/${_stem}.cpython-*.so")
      list(LENGTH _renamed _renamed_count)
      if (_renamed_count EQUAL 1)
        string(REPLACE "\${_IMPORT_PREFIX}/${_relative}\"" "\${_IMPORT_PREFIX}/${_renamed}\""
          _text "${_text}")
        set(_patched TRUE)
      else ()
        list(APPEND _unresolved "${_prefix}/${_relative}")
      endif ()
    endforeach ()
    get_filename_component(_name "${_config}" NAME)
    list(APPEND _copies "${_copy_dir}/${_name}")
    file(WRITE "${_copy_dir}/${_name}.tmp" "${_text}")
  endforeach ()
  if (NOT _patched)
    file(REMOVE_RECURSE "${_copy_dir}")
    return () # Nothing renamed: the export is right (or broken in a way we do not know).
  endif ()
  if (_unresolved)
    list(JOIN _unresolved "\n  " _unresolved_text)
    message(WARNING "${_main} references files that are missing under "
      "both their own and their renamed name:\n  ${_unresolved_text}")
  endif ()
  foreach (_copy IN LISTS _copies)
    file(RENAME "${_copy}.tmp" "${_copy}")
  endforeach ()
  # The copy finds its per-configuration files next to itself but computes the prefix from the
  # original's location.
  string(REPLACE "get_filename_component(_IMPORT_PREFIX \"\${CMAKE_CURRENT_LIST_FILE}\" PATH)"
    "get_filename_component(_IMPORT_PREFIX \"${_main}\" PATH)" _main_text "${_main_text}")
  file(WRITE "${_copy_dir}/${_export_name}.cmake" "${_main_text}")
  include("${_copy_dir}/${_export_name}.cmake")
  message(STATUS "${_export_name}: Debian renamed the Python modules it names "
    "(*.cpython-*.so); loaded a corrected copy from ${_copy_dir}")
endfunction ()

# The Python exports of the ParaView whose VTK lives in vtk_dir (<ParaView config dir>/vtk):
# on Debian 13 VTKPython, ParaViewPython and ParaViewPythonIncubator.
function (shapediameter_fix_vtk_python_targets vtk_dir)
  get_filename_component(_paraview_dir "${vtk_dir}" DIRECTORY)
  # VTK's first: ParaView's refer to its targets.
  file(GLOB _vtk_exports "${vtk_dir}/*Python*-targets.cmake")
  file(GLOB _paraview_exports "${_paraview_dir}/*Python*-targets.cmake")
  foreach (_export IN LISTS _vtk_exports _paraview_exports)
    shapediameter_fix_python_export("${_export}")
  endforeach ()
endfunction ()

# The VTK config directories of the ParaViews CMake may find: ParaView_DIR or VTK_DIR when given,
# else <prefix>/lib[/<multiarch>]/cmake/paraview-*/vtk under the usual prefixes.
function (shapediameter_fix_paraview_vtk_python_targets)
  set(_dirs)
  if (VTK_DIR)
    list(APPEND _dirs "${VTK_DIR}")
  endif ()
  if (ParaView_DIR)
    list(APPEND _dirs "${ParaView_DIR}/vtk")
  endif ()
  if (NOT _dirs)
    foreach (_prefix IN LISTS CMAKE_PREFIX_PATH CMAKE_SYSTEM_PREFIX_PATH)
      file(GLOB _found LIST_DIRECTORIES TRUE
        "${_prefix}/lib/${CMAKE_LIBRARY_ARCHITECTURE}/cmake/paraview-*/vtk"
        "${_prefix}/lib/cmake/paraview-*/vtk")
      list(APPEND _dirs ${_found})
    endforeach ()
  endif ()
  set(_real_dirs)
  foreach (_dir IN LISTS _dirs)
    get_filename_component(_real "${_dir}" REALPATH) # /lib and /usr/lib on merged-/usr systems
    list(APPEND _real_dirs "${_real}")
  endforeach ()
  list(REMOVE_DUPLICATES _real_dirs)
  foreach (_dir IN LISTS _real_dirs)
    shapediameter_fix_vtk_python_targets("${_dir}")
  endforeach ()
endfunction ()
