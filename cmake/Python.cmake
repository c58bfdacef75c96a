# PHEROMESH_PYTHON: policies written in Python (docs/python.md, "Python
# policies"). ON by default when pybind11 and the Python 3 development files
# (the embedding library) are found; ON without them is an error, OFF builds
# programs that refuse a scenario naming a Python policy. The core never links
# Python: the library pheromesh_pypolicy (common/pypolicy) does, and the
# programs that may run a Python policy link it.
#
# Debian's interpreter (/usr/bin/python3) unless Python3_EXECUTABLE says
# otherwise: the one Debian's pybind11 and python3-* packages belong to, even
# when another python3 (pyenv, a virtualenv) comes first on PATH.
if(NOT DEFINED Python3_EXECUTABLE AND EXISTS /usr/bin/python3)
  set(Python3_EXECUTABLE /usr/bin/python3)
endif()
find_package(Python3 COMPONENTS Interpreter Development.Embed QUIET)
if(Python3_FOUND)
  find_package(pybind11 CONFIG QUIET)
endif()
if(Python3_FOUND AND pybind11_FOUND)
  set(PHEROMESH_PYTHON_DEFAULT ON)
else()
  set(PHEROMESH_PYTHON_DEFAULT OFF)
endif()
option(PHEROMESH_PYTHON "Python policies: pheromesh-uav, pheromesh-place, pheromesh-ground and pheromesh embed an interpreter when a scenario names one (needs pybind11 and the Python 3 development files)" ${PHEROMESH_PYTHON_DEFAULT})
if(PHEROMESH_PYTHON AND NOT (Python3_FOUND AND pybind11_FOUND))
  message(FATAL_ERROR "PHEROMESH_PYTHON=ON needs pybind11 (Debian: pybind11-dev) and the Python 3 development files "
                      "(python3-dev); found Python3: ${Python3_FOUND}, pybind11: ${pybind11_FOUND}")
endif()
if(PHEROMESH_PYTHON)
  message(STATUS "pheromesh option PHEROMESH_PYTHON = ON (Python ${Python3_VERSION} ${Python3_EXECUTABLE}, pybind11 ${pybind11_VERSION})")
else()
  message(STATUS "pheromesh option PHEROMESH_PYTHON = OFF")
endif()

# Links `target` with the Python policies when PHEROMESH_PYTHON is on: the
# program then registers them at start (pheromesh/pypolicy/pypolicy.hpp).
function(pheromesh_link_python_policies target)
  if(PHEROMESH_PYTHON)
    target_link_libraries(${target} PRIVATE pheromesh::pypolicy)
    target_compile_definitions(${target} PRIVATE PHEROMESH_WITH_PYTHON=1)
  endif()
endfunction()
