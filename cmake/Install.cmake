# `cmake --install`: what goes where (cmake/InstallDirs.cmake has the layout)
# and the exported targets pheromesh::core and pheromesh::bus
# (docs/install.md). Two components, which are also the two Debian packages
# (cmake/Package.cmake):
#   runtime      the programs, scenarios, DDS profiles, schemas and docs
#   development  headers, static libraries and the CMake package
include(CMakePackageConfigHelpers)

# --- runtime ------------------------------------------------------------------
if(NOT PHEROMESH_CORE_ONLY)
  # The per-process programs go beside `pheromesh` in bin/: the launcher runs
  # its siblings from its own folder, and they are programs of their own that
  # are started by hand on other hosts (README, "Running swarms"). The test
  # probe is a test program and stays out.
  install(TARGETS pheromesh pheromesh-uav pheromesh-place pheromesh-ground
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT runtime)
  # pheromesh-uav runs a Python policy in this sibling (agent/python_sibling.hpp).
  if(PHEROMESH_PYTHON)
    install(TARGETS pheromesh-uav-python RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT runtime)
  endif()
  # The DDS modules: each program loads its vendor's from lib/pheromesh, found
  # relative to bin/ (common/bus/src/vendors.hpp), so a moved prefix works.
  install(TARGETS pheromesh_dds_cyclone pheromesh_dds_fastdds
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/pheromesh COMPONENT runtime)
  # Compiled into the bus as well; installed to read, copy and edit
  # (--dds-profile FILE[,FILE]).
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/deploy/dds/ DESTINATION ${PHEROMESH_INSTALL_DATADIR}/dds
    COMPONENT runtime FILES_MATCHING PATTERN "*.xml")
  # The DDS types, for programs of other languages or vendors that join a swarm.
  install(FILES ${PROJECT_SOURCE_DIR}/idl/pheromesh.idl DESTINATION ${PHEROMESH_INSTALL_DATADIR}/idl COMPONENT runtime)
else()
  # Core-only: `pheromesh` with validate, sim, experiment and sweep (cli/CMakeLists.txt).
  install(TARGETS pheromesh RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT runtime)
endif()
install(DIRECTORY ${PROJECT_SOURCE_DIR}/scenarios/ DESTINATION ${PHEROMESH_INSTALL_DATADIR}/scenarios
  COMPONENT runtime FILES_MATCHING PATTERN "*.textproto")
# The scenario and recording schemas (docs/scenario-format.md, docs/recording.md).
install(FILES ${PROJECT_SOURCE_DIR}/common/proto/scenario.proto ${PROJECT_SOURCE_DIR}/common/proto/recording.proto
  DESTINATION ${PHEROMESH_INSTALL_DATADIR}/proto COMPONENT runtime)
# README keeps its links: docs/ goes below it.
install(FILES ${PROJECT_SOURCE_DIR}/README.md DESTINATION ${CMAKE_INSTALL_DOCDIR} COMPONENT runtime)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR}/docs COMPONENT runtime)

# --- development: pheromesh::core and pheromesh::bus ---------------------------
# Static libraries, so every library they link privately is exported too (a
# consumer links it): pheromesh_proto carries the generated scenario code,
# pheromesh_idl_fastdds the Fast DDS types (the Cyclone types are inside
# pheromesh_bus_cyclone), pheromesh_build_options the sanitizer link flags of
# a sanitized build. Only core and bus are the API; the rest are link-only.
set(pheromesh_exported pheromesh_core pheromesh_proto pheromesh_build_options)
set_target_properties(pheromesh_core PROPERTIES EXPORT_NAME core)
set_target_properties(pheromesh_proto PROPERTIES EXPORT_NAME detail_scenario_proto)
set_target_properties(pheromesh_build_options PROPERTIES EXPORT_NAME detail_build_options)
if(NOT PHEROMESH_CORE_ONLY)
  list(APPEND pheromesh_exported pheromesh_bus pheromesh_bus_common pheromesh_bus_cyclone pheromesh_bus_fastdds
    pheromesh_idl_fastdds)
  set_target_properties(pheromesh_bus PROPERTIES EXPORT_NAME bus)
  foreach(t bus_common bus_cyclone bus_fastdds idl_fastdds)
    set_target_properties(pheromesh_${t} PROPERTIES EXPORT_NAME detail_${t})
  endforeach()
endif()
install(TARGETS ${pheromesh_exported} EXPORT pheromeshTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT development)
# `cmake --install --strip` and the Debian package strip the programs; CMake
# leaves static libraries alone, so drop their debug sections here (as Debian
# does for -dev packages): the -dev package shrank from 21.5 MB to 1.2 MB.
set(pheromesh_archives)
foreach(t IN LISTS pheromesh_exported)
  get_target_property(type ${t} TYPE)
  if(type STREQUAL "STATIC_LIBRARY")
    list(APPEND pheromesh_archives "$<TARGET_FILE_NAME:${t}>")
  endif()
endforeach()
install(CODE "
  if(CMAKE_INSTALL_DO_STRIP)
    foreach(archive ${pheromesh_archives})
      execute_process(COMMAND \"${CMAKE_STRIP}\" --strip-debug
        \"\$ENV{DESTDIR}\${CMAKE_INSTALL_PREFIX}/${CMAKE_INSTALL_LIBDIR}/\${archive}\" COMMAND_ERROR_IS_FATAL ANY)
    endforeach()
  endif()" COMPONENT development)

# The public headers: the shared core, every paper's room, the bus. They
# include nothing generated (no .pb.h, no IDL header) and nothing of a vendor.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/common/core/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
  COMPONENT development FILES_MATCHING PATTERN "*.hpp")
file(GLOB pheromesh_room_includes LIST_DIRECTORIES true ${PROJECT_SOURCE_DIR}/common/core/papers/*/include)
foreach(dir IN LISTS pheromesh_room_includes)
  install(DIRECTORY ${dir}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT development FILES_MATCHING PATTERN "*.hpp")
endforeach()
if(NOT PHEROMESH_CORE_ONLY)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/common/bus/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
    COMPONENT development FILES_MATCHING PATTERN "*.hpp")
endif()

install(EXPORT pheromeshTargets NAMESPACE pheromesh:: DESTINATION ${PHEROMESH_INSTALL_CMAKEDIR}
  COMPONENT development)
if(PHEROMESH_CORE_ONLY)
  set(PHEROMESH_CONFIG_WITH_BUS OFF)
else()
  set(PHEROMESH_CONFIG_WITH_BUS ON)
endif()
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/pheromeshConfig.cmake.in
  ${PROJECT_BINARY_DIR}/pheromeshConfig.cmake INSTALL_DESTINATION ${PHEROMESH_INSTALL_CMAKEDIR})
# 0.x: a minor version may change the API.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/pheromeshConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/pheromeshConfig.cmake ${PROJECT_BINARY_DIR}/pheromeshConfigVersion.cmake
  DESTINATION ${PHEROMESH_INSTALL_CMAKEDIR} COMPONENT development)
