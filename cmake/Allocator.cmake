# The heap of the place agents and the ground station (pheromesh-place,
# pheromesh-ground): PHEROMESH_ALLOCATOR=tcmalloc links gperftools'
# tcmalloc_minimal (Debian: libgoogle-perftools-dev to build,
# libtcmalloc-minimal4 to run), `system` keeps glibc's malloc. Every DDS
# sample allocates and frees in the vendor's receive path and in ours, and a
# place agent takes and writes several samples per UAV tick; glibc's malloc
# and free were a tenth of a lockstep swarm's CPU (docs/benchmarks.md, "A
# faster heap"). The UAVs keep glibc's: tcmalloc gained them nothing
# measurable and cost each 4 MiB more PSS, which 2000 of them would pay 2000
# times. Default: tcmalloc when found, except in a sanitized or fuzzing build
# (the sanitizers bring their own allocator); tcmalloc asked for and not found
# is an error.
set(pheromesh_allocator_default system)
set(PHEROMESH_ALLOCATOR_REASON "")
if(NOT PHEROMESH_CORE_ONLY)
  find_library(PHEROMESH_TCMALLOC_LIBRARY NAMES tcmalloc_minimal
    DOC "gperftools' tcmalloc_minimal (Debian: libgoogle-perftools-dev)")
  if(PHEROMESH_SANITIZER OR PHEROMESH_FUZZ)
    set(PHEROMESH_ALLOCATOR_REASON " (a sanitized or fuzzing build keeps the system's)")
  elseif(PHEROMESH_TCMALLOC_LIBRARY)
    set(pheromesh_allocator_default tcmalloc)
  else()
    set(PHEROMESH_ALLOCATOR_REASON " (tcmalloc_minimal not found: apt install libgoogle-perftools-dev)")
  endif()
endif()
set(PHEROMESH_ALLOCATOR ${pheromesh_allocator_default} CACHE STRING
  "Heap of pheromesh-place and pheromesh-ground: 'tcmalloc' (gperftools' tcmalloc_minimal) or 'system' (glibc)")
set_property(CACHE PHEROMESH_ALLOCATOR PROPERTY STRINGS tcmalloc system)
if(NOT PHEROMESH_ALLOCATOR MATCHES "^(tcmalloc|system)$")
  message(FATAL_ERROR "PHEROMESH_ALLOCATOR='${PHEROMESH_ALLOCATOR}': use 'tcmalloc' or 'system'")
endif()
if(PHEROMESH_ALLOCATOR STREQUAL "tcmalloc")
  if(PHEROMESH_CORE_ONLY)
    message(FATAL_ERROR "PHEROMESH_ALLOCATOR=tcmalloc: a core-only build has no swarm processes; use 'system'")
  endif()
  if(NOT PHEROMESH_TCMALLOC_LIBRARY)
    message(FATAL_ERROR "PHEROMESH_ALLOCATOR=tcmalloc, but tcmalloc_minimal was not found "
                        "(apt install libgoogle-perftools-dev), or configure with -DPHEROMESH_ALLOCATOR=system")
  endif()
  if(PHEROMESH_SANITIZER OR PHEROMESH_FUZZ)
    message(FATAL_ERROR "PHEROMESH_ALLOCATOR=tcmalloc cannot be combined with sanitizers or fuzzing; use 'system'")
  endif()
endif()
message(STATUS "pheromesh option PHEROMESH_ALLOCATOR = ${PHEROMESH_ALLOCATOR}${PHEROMESH_ALLOCATOR_REASON}")

# Links the chosen heap into a program. tcmalloc replaces malloc by
# being loaded, not by a symbol the program names, so it is linked with
# --no-as-needed (a linker that drops unreferenced libraries would drop it).
function(pheromesh_link_allocator target)
  if(PHEROMESH_ALLOCATOR STREQUAL "tcmalloc")
    target_link_libraries(${target} PRIVATE "-Wl,--push-state,--no-as-needed" ${PHEROMESH_TCMALLOC_LIBRARY}
      "-Wl,--pop-state")
  endif()
endfunction()
