# Where `cmake --install` puts things (GNUInstallDirs), and what the programs
# need to know of it at run time. Included before the targets are defined;
# the install rules themselves are in cmake/Install.cmake.
#   bin/                       pheromesh and the per-process programs
#   share/pheromesh/scenarios  the shipped scenarios (`pheromesh run NAME`)
#   share/pheromesh/dds        the DDS profiles (also compiled in)
#   share/pheromesh/{idl,proto} the message and scenario schemas
#   share/doc/pheromesh        README and docs/
#   include/, lib/, lib/cmake/pheromesh   pheromesh::core and pheromesh::bus
include(GNUInstallDirs)

set(PHEROMESH_INSTALL_DATADIR ${CMAKE_INSTALL_DATADIR}/pheromesh)
set(PHEROMESH_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/pheromesh)

# The shipped scenarios as seen from the installed `pheromesh`, so that a
# prefix moved elsewhere as a whole still works (common/cliutil/include/pheromesh/cliutil/scenario_paths.hpp).
file(RELATIVE_PATH PHEROMESH_INSTALLED_SCENARIOS_REL
  ${CMAKE_INSTALL_FULL_BINDIR} ${CMAKE_INSTALL_FULL_DATADIR}/pheromesh/scenarios)

# For pheromesh::cliutil, which compiles scenario_paths.cpp.
set(PHEROMESH_SCENARIO_SEARCH_DEFINITIONS
  PHEROMESH_INSTALLED_SCENARIOS_REL="${PHEROMESH_INSTALLED_SCENARIOS_REL}"
  PHEROMESH_BUILD_BIN_DIR="${PROJECT_BINARY_DIR}/bin"
  PHEROMESH_SOURCE_SCENARIOS_DIR="${PROJECT_SOURCE_DIR}/scenarios")
