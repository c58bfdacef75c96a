# CPack: `cpack -G DEB` in the build folder (`make package`) makes two Debian
# packages from the two install components (cmake/Install.cmake):
#   pheromesh_<version>_<arch>.deb      the programs, scenarios, profiles, docs
#   pheromesh-dev_<version>_<arch>.deb  headers, static libraries, CMake package
#   python3-pheromesh_<version>_<arch>.deb  `import pheromesh` (PHEROMESH_PYTHON)
# The programs' Depends come from dpkg-shlibdeps (dpkg-dev), so they name
# exactly the shared libraries this build linked. tests/package checks the
# package on a clean Debian bookworm (docs/install.md).
set(CPACK_PACKAGE_NAME pheromesh)
set(CPACK_PACKAGE_VENDOR "pheromesh")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
# No CPACK_PACKAGE_DESCRIPTION_SUMMARY: CPack would put it before both
# packages' descriptions; the first line of each description is its summary.
set(PHEROMESH_PACKAGE_MAINTAINER "pheromesh maintainers <maintainers@users.noreply.h-seed-e68ae258.example>"
  CACHE STRING "Maintainer field of the Debian packages")
set(CPACK_PACKAGE_CONTACT ${PHEROMESH_PACKAGE_MAINTAINER})
set(CPACK_STRIP_FILES ON)  # as Debian ships programs; the build tree keeps the debug info
set(CPACK_PACKAGE_FILE_NAME "${CPACK_PACKAGE_NAME}-${PROJECT_VERSION}")  # only non-DEB generators use it

set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_COMPONENTS_ALL runtime development)
if(PHEROMESH_PYTHON)
  list(APPEND CPACK_COMPONENTS_ALL python)
endif()
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)  # <name>_<version>_<arch>.deb
set(CPACK_DEBIAN_PACKAGE_MAINTAINER ${PHEROMESH_PACKAGE_MAINTAINER})
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)

set(CPACK_DEBIAN_RUNTIME_PACKAGE_NAME pheromesh)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_SHLIBDEPS ON)
# `pheromesh run` with partition or loss faults drives ip and nft; with
# --discovery-server it starts fast-discovery-server (docs/faults.md, README).
set(CPACK_DEBIAN_RUNTIME_PACKAGE_RECOMMENDS "iproute2, nftables")
set(CPACK_DEBIAN_RUNTIME_PACKAGE_SUGGESTS "fastdds-tools")
set(CPACK_COMPONENT_RUNTIME_DESCRIPTION
  "UAV swarm coordinating through digital pheromones over DDS
Every UAV is its own process; every map region is a place agent process that
owns the pheromone tiles of its region, aggregating, evaporating and diffusing
the deposits the UAVs make. Processes talk over DDS (Cyclone DDS or Fast DDS,
or both mixed) and a ground station watches, with a web console.
.
`pheromesh run small-test` starts a swarm of a shipped scenario on this host;
`pheromesh sim` runs the same deterministically in one process; `pheromesh
experiment` reproduces the experiments of the papers implemented (Shao 2020,
Liu 2022, Duan 2009, Shostak 2024, Ravankar 2016).")

set(CPACK_DEBIAN_DEVELOPMENT_PACKAGE_NAME pheromesh-dev)
set(CPACK_DEBIAN_DEVELOPMENT_PACKAGE_SECTION libdevel)
# Static libraries: what find_package(pheromesh) finds again (pheromeshConfig.cmake).
set(CPACK_DEBIAN_DEVELOPMENT_PACKAGE_DEPENDS
  "libeigen3-dev, libprotobuf-dev, libssl-dev, libspdlog-dev, cyclonedds-dev, libfastrtps-dev, libfastcdr-dev")
set(CPACK_COMPONENT_DEVELOPMENT_DESCRIPTION
  "UAV swarm coordinating through digital pheromones over DDS - development files
Headers, static libraries and the CMake package of pheromesh:
find_package(pheromesh CONFIG) gives pheromesh::core (scenarios, pheromone
layers, the papers' policies, the simulator; no DDS) and pheromesh::bus (the
vendor-neutral bus over Cyclone DDS and Fast DDS).")

# The Python package (python/, docs/python.md): the extension links the core
# statically, so it depends on the shared libraries dpkg-shlibdeps finds, on
# the pheromesh package of the same version (the shipped scenarios, and the
# `pheromesh` program that run() and replay() start) and on NumPy.
set(CPACK_DEBIAN_PYTHON_PACKAGE_NAME python3-pheromesh)
set(CPACK_DEBIAN_PYTHON_PACKAGE_SECTION python)
set(CPACK_DEBIAN_PYTHON_PACKAGE_SHLIBDEPS ON)
if(PHEROMESH_PYTHON)
  # The extension is built for this Python's ABI (…cpython-311-…so).
  math(EXPR pheromesh_python_minor_next "${Python_VERSION_MINOR} + 1")
  set(CPACK_DEBIAN_PYTHON_PACKAGE_DEPENDS
    "pheromesh (= ${PROJECT_VERSION}), python3 (>= ${Python_VERSION_MAJOR}.${Python_VERSION_MINOR}), python3 (<< ${Python_VERSION_MAJOR}.${pheromesh_python_minor_next}), python3-numpy")
endif()
set(CPACK_DEBIAN_PYTHON_PACKAGE_RECOMMENDS "python3-pandas")
set(CPACK_DEBIAN_PYTHON_PACKAGE_SUGGESTS "python3-matplotlib, jupyter-notebook")
set(CPACK_COMPONENT_PYTHON_DESCRIPTION
  "UAV swarm coordinating through digital pheromones - Python package
`import pheromesh`: load a scenario, set its fields, run the in-process
simulator and get the metrics, the time series and the pheromone fields as
NumPy arrays; sweep parameters into a pandas table; fly the scenario as real
processes over DDS with the pheromesh program and read the same result back.")

include(CPack)
