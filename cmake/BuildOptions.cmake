# Every build option of pheromesh, in one place, printed at configure time.
option(PHEROMESH_BUILD_TESTS "Build unit and integration tests" ON)
option(PHEROMESH_BUILD_BENCH "Build benchmarks" ON)
option(PHEROMESH_CORE_ONLY "Build only the DDS-free core, its unit tests and benchmarks" OFF)
option(PHEROMESH_WERROR "Treat warnings as errors" OFF)
set(PHEROMESH_SANITIZER "" CACHE STRING "Sanitizers to build with: '', 'address,undefined' or 'thread'")
set_property(CACHE PHEROMESH_SANITIZER PROPERTY STRINGS "" "address,undefined" "thread")

foreach(opt PHEROMESH_BUILD_TESTS PHEROMESH_BUILD_BENCH PHEROMESH_CORE_ONLY PHEROMESH_WERROR PHEROMESH_SANITIZER CMAKE_BUILD_TYPE)
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
