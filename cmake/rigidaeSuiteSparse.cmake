# SuiteSparseQR, KLU, CHOLMOD and SuiteSparse_config (Debian's libsuitesparse-dev,
# which ships no CMake package files) as imported targets rigidae::spqr, rigidae::klu,
# rigidae::cholmod and rigidae::suitesparseconfig. Included by the build and,
# installed beside rigidaeConfig.cmake, by projects that find_package(rigidae):
# the static rigidae_core links them.
foreach(_rigidae_lib spqr klu cholmod suitesparseconfig)
  if(NOT TARGET rigidae::${_rigidae_lib})
    find_library(RIGIDAE_${_rigidae_lib}_LIBRARY ${_rigidae_lib})
    if(NOT RIGIDAE_${_rigidae_lib}_LIBRARY)
      message(FATAL_ERROR "rigidae: lib${_rigidae_lib} not found (Debian: apt-get install libsuitesparse-dev)")
    endif()
    add_library(rigidae::${_rigidae_lib} UNKNOWN IMPORTED)
    set_target_properties(rigidae::${_rigidae_lib} PROPERTIES IMPORTED_LOCATION "${RIGIDAE_${_rigidae_lib}_LIBRARY}")
  endif()
endforeach()
unset(_rigidae_lib)
