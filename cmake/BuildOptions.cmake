# Every build option of pheromesh, in one place, printed at configure time.
option(PHEROMESH_BUILD_TESTS "Build unit and integration tests" ON)
option(PHEROMESH_BUILD_BENCH "Build benchmarks" ON)
option(PHEROMESH_CORE_ONLY "Build without DDS and the web console: the core, `pheromesh` with validate, sim, experiment and sweep, the unit tests of the core and its benchmarks" OFF)
option(PHEROMESH_WERROR "Treat warnings as errors" OFF)
option(PHEROMESH_TEST_CORE_ONLY "Add the ctest CoreOnly.BuildsAndSimulatesWithoutDds: configure, build and run a core-only tree beside this one (minutes without a warm ccache; make test-core-only runs it alone)" OFF)
option(PHEROMESH_TEST_IMAGE_FROM_SOURCE "Make the container tests' image with its own compile (Container.ImageBuildsFromTheTree: the build stage of deploy/container/Containerfile, about 14 minutes cold on two cores) instead of from this build's programs" OFF)
option(PHEROMESH_FUZZ "Build the libFuzzer harnesses of fuzz/ (clang only; docs/fuzzing.md)" OFF)
set(PHEROMESH_SANITIZER "" CACHE STRING "Sanitizers to build with: '', 'address,undefined' or 'thread'")
set_property(CACHE PHEROMESH_SANITIZER PROPERTY STRINGS "" "address,undefined" "thread")
# Python (docs/python.md): the package `import pheromesh` (python/) and
# policies written in Python, which pheromesh, pheromesh-uav, pheromesh-place
# and pheromesh-ground run in an embedded interpreter (common/pypolicy). On by
# default when pybind11 and Python's headers and embedding library are found
# (Debian: python3-dev python3-pybind11 python3-numpy); off by default in a
# sanitized or fuzzing build (the interpreter would need the sanitizer runtime
# preloaded); never in a core-only build (there a scenario naming a Python
# policy is refused: "built without Python support"). ON without pybind11 and
# the headers is an error. The core never links Python.
set(pheromesh_python_default OFF)
set(pheromesh_python_possible OFF)
set(PHEROMESH_PYTHON_OFF_REASON "a core-only build has no Python package")
if(NOT PHEROMESH_CORE_ONLY)
  # Debian's Python (whose python3-numpy, -pandas, -pytest the package and its
  # tests use), not whichever python3 comes first on PATH (a pyenv shim, a
  # virtualenv); -DPython_EXECUTABLE=... chooses another.
  if(NOT DEFINED Python_EXECUTABLE AND EXISTS /usr/bin/python3)
    set(Python_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "The Python the package is built for")
  endif()
  set(PYBIND11_FINDPYTHON ON)
  find_package(Python 3 QUIET COMPONENTS Interpreter Development.Module Development.Embed)
  find_package(pybind11 2.6 CONFIG QUIET)
  if(Python_FOUND AND pybind11_FOUND)
    set(pheromesh_python_possible ON)
    if(PHEROMESH_SANITIZER OR PHEROMESH_FUZZ)
      set(PHEROMESH_PYTHON_OFF_REASON
        "a sanitized or fuzzing build leaves it off by default (python3 would need the sanitizer runtime preloaded); -DPHEROMESH_PYTHON=ON builds it")
    else()
      set(pheromesh_python_default ON)
    endif()
  else()
    set(PHEROMESH_PYTHON_OFF_REASON
      "pybind11 or Python's headers not found (apt install python3-dev python3-pybind11 python3-numpy)")
  endif()
endif()
option(PHEROMESH_PYTHON "Build the Python package pheromesh and Python policies (python/, common/pypolicy/, docs/python.md)" ${pheromesh_python_default})
if(PHEROMESH_PYTHON AND NOT pheromesh_python_possible)
  message(FATAL_ERROR "PHEROMESH_PYTHON=ON, but ${PHEROMESH_PYTHON_OFF_REASON}")
elseif(NOT PHEROMESH_PYTHON)
  if(pheromesh_python_default)
    message(STATUS "pheromesh: the Python package is off (PHEROMESH_PYTHON=OFF)")
  else()
    message(STATUS "pheromesh: the Python package is off: ${PHEROMESH_PYTHON_OFF_REASON}")
  endif()
endif()

foreach(opt PHEROMESH_BUILD_TESTS PHEROMESH_BUILD_BENCH PHEROMESH_CORE_ONLY PHEROMESH_WERROR PHEROMESH_SANITIZER PHEROMESH_FUZZ
    PHEROMESH_TEST_CORE_ONLY PHEROMESH_TEST_IMAGE_FROM_SOURCE PHEROMESH_PYTHON
    CMAKE_BUILD_TYPE)
  message(STATUS "pheromesh option ${opt} = ${${opt}}")
endforeach()

# Interface target carrying warnings and sanitizer flags; every pheromesh
# target links it instead of touching global flags.
add_library(pheromesh_build_options INTERFACE)
add_library(pheromesh::build_options ALIAS pheromesh_build_options)
target_compile_options(pheromesh_build_options INTERFACE
  $<$<COMPILE_LANGUAGE:CXX>:-Wall -Wextra -Wconversion -Wpedantic -Wnon-virtual-dtor -Woverloaded-virtual>
  $<$<BOOL:${PHEROMESH_WERROR}>:-Werror>)
if(PHEROMESH_SANITIZER)
  target_compile_options(pheromesh_build_options INTERFACE -fsanitize=${PHEROMESH_SANITIZER} -fno-omit-frame-pointer)
  target_link_options(pheromesh_build_options INTERFACE -fsanitize=${PHEROMESH_SANITIZER})
endif()

# Fuzzing: every pheromesh library gets libFuzzer's coverage instrumentation
# and ASan + UBSan, so the harnesses (fuzz/, linked with -fsanitize=fuzzer)
# see the edges of the code they feed; any undefined behaviour aborts, which
# the fuzzer reports as a crash instead of printing a line and going on.
if(PHEROMESH_FUZZ)
  if(NOT CMAKE_CXX_COMPILER_ID STREQUAL "Clang")
    message(FATAL_ERROR "PHEROMESH_FUZZ needs clang (libFuzzer): configure with -DCMAKE_CXX_COMPILER=clang++ "
                        "-DCMAKE_C_COMPILER=clang (fuzz/fuzz.sh does)")
  endif()
  set(PHEROMESH_FUZZ_FLAGS -fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined
    -fno-omit-frame-pointer)
  target_compile_options(pheromesh_build_options INTERFACE ${PHEROMESH_FUZZ_FLAGS})
  target_link_options(pheromesh_build_options INTERFACE -fsanitize=address,undefined)
endif()
