# pheromesh_link_python_policies(target): links a program with the Python
# policies when PHEROMESH_PYTHON is on (cmake/BuildOptions.cmake finds Python
# and pybind11). The program then registers them at start
# (pheromesh/pypolicy/enable.hpp) and embeds an interpreter when a scenario
# names a Python policy. The Python package's extension links
# pheromesh::pypolicy without the embedding library: it runs inside python3.
function(pheromesh_link_python_policies target)
  if(PHEROMESH_PYTHON)
    target_link_libraries(${target} PRIVATE pheromesh::pypolicy pybind11::embed)
    target_compile_definitions(${target} PRIVATE PHEROMESH_WITH_PYTHON=1)
  endif()
endfunction()
