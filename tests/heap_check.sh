#!/usr/bin/env bash
# The heap each swarm program runs on (cmake/Allocator.cmake): with
# PHEROMESH_ALLOCATOR=tcmalloc the dynamic linker binds libc's own calls of
# malloc to tcmalloc in pheromesh-place and pheromesh-ground, and to glibc in
# pheromesh-uav; with `system`, to glibc in all three. Read from the loader
# (LD_DEBUG=bindings) while each program prints its --help, so a library
# linked but dropped, or loaded after libc, fails here.
#
#   tests/heap_check.sh BIN_DIR tcmalloc|system
set -euo pipefail
bin=${1:?BIN_DIR}
allocator=${2:?tcmalloc or system}
case "$allocator" in
  tcmalloc) heap_of_place=libtcmalloc_minimal.so ;;
  system) heap_of_place=libc.so ;;
  *) echo "heap_check: unknown allocator '$allocator' (tcmalloc or system)" >&2; exit 2 ;;
esac
failed=0
for program in pheromesh-place pheromesh-ground pheromesh-uav; do
  want=$heap_of_place
  [ "$program" = pheromesh-uav ] && want=libc.so
  # libc's malloc binds where the program's heap is: the first object of the
  # search order that defines it.
  binding=$(LD_DEBUG=bindings "$bin/$program" --help 2>&1 >/dev/null |
    grep -E "binding file [^ ]*/libc\.so\.6 .* normal symbol \`malloc'" | head -1 || true)
  if [ -z "$binding" ]; then
    echo "FAIL $program: the loader reported no binding of libc's malloc (LD_DEBUG=bindings $bin/$program --help)"
    failed=1
    continue
  fi
  target=$(sed -E 's/.* to ([^ ]+) \[.*/\1/' <<< "$binding")
  if [[ "$(basename "$target")" == "$want"* ]]; then
    echo "ok   $program: malloc from $target"
  else
    echo "FAIL $program: malloc from $target, expected ${want}* (PHEROMESH_ALLOCATOR=$allocator)"
    failed=1
  fi
done
exit $failed
