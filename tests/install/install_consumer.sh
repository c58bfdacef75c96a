#!/usr/bin/env bash
# Install.*: `cmake --install` into a temporary prefix, move the prefix
# elsewhere (a relocated install must still work), then
#   - the layout of docs/install.md is there (and no test program);
#   - the installed `pheromesh` finds a shipped scenario by name from another
#     directory, and an unknown name lists the shipped ones;
#   - tests/install/consumer, a project of its own, finds the package with
#     find_package(pheromesh CONFIG), builds, and its two programs run:
#     scenario_size (pheromesh::core) and bus_roundtrip (pheromesh::bus).
# Usage: install_consumer.sh BUILD_DIR SOURCE_DIR DOMAIN
set -euo pipefail
build="$(cd "$1" && pwd)"
src="$(cd "$2" && pwd)"
domain="$3"
work="$(mktemp -d /tmp/phm-install.XXXXXX)"
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
step() { echo "--- $* ($(( $(date +%s) - t0 )) s)"; }
t0=$(date +%s)

step "cmake --install $build --prefix $work/installed"
cmake --install "$build" --prefix "$work/installed" > "$work/install.log" || { cat "$work/install.log"; exit 1; }
mv "$work/installed" "$work/moved"
prefix="$work/moved"

step "layout"
# GNUInstallDirs' libdir depends on the configured prefix (lib or lib/<multiarch>).
cmakedir="$(dirname "$(find "$prefix" -name pheromeshConfig.cmake -path '*/cmake/pheromesh/*')")"
[ -f "$cmakedir/pheromeshConfig.cmake" ] || fail "no pheromeshConfig.cmake under $prefix"
for f in bin/pheromesh bin/pheromesh-uav bin/pheromesh-place bin/pheromesh-ground \
         share/pheromesh/scenarios/small-test.textproto share/pheromesh/scenarios/shao2020-50x50.textproto \
         share/pheromesh/dds/cyclone-onehost.xml share/pheromesh/dds/fastdds-onehost.xml \
         share/pheromesh/idl/pheromesh.idl share/pheromesh/proto/scenario.proto \
         share/doc/pheromesh/README.md share/doc/pheromesh/docs/install.md \
         include/pheromesh/core/scenario.hpp include/pheromesh/shao/policy.hpp include/pheromesh/bus/bus.hpp; do
  [ -e "$prefix/$f" ] || fail "$f is not installed"
done
[ -x "$prefix/bin/pheromesh-uav" ] || fail "pheromesh-uav is not executable"
[ ! -e "$prefix/bin/pheromesh-test-probe" ] || fail "the test probe is installed"
# Nothing of the build or source tree leaks into the installed package files.
if grep -rlF -e "$build" -e "$src" "$cmakedir"; then fail "the CMake package names the build or source tree"; fi
# No header that would need generated code or a vendor header.
if grep -rlE '#include ["<](.*\.pb\.h|dds/|fastdds/|fastrtps/|pheromesh\.h)' "$prefix/include"; then
  fail "an installed header includes generated or vendor headers"
fi

step "the installed pheromesh finds shipped scenarios by name, from another directory"
mkdir "$work/elsewhere"
out="$(cd "$work/elsewhere" && "$prefix/bin/pheromesh" validate small-test)"
grep -qF "$prefix/share/pheromesh/scenarios/small-test.textproto: OK" <<<"$out" || fail "validate small-test said: $out"
out="$(cd "$work/elsewhere" && "$prefix/bin/pheromesh" sim small-test.textproto --ticks 5 --quiet --out sim 2>&1)"
[ -f "$work/elsewhere/sim/metrics.json" ] || fail "sim wrote no sim/metrics.json relative to the current directory: $out"
if out="$(cd "$work/elsewhere" && "$prefix/bin/pheromesh" run no-such-scenario 2>&1)"; then fail "an unknown name was accepted"; fi
grep -qF "'no-such-scenario' is neither a file nor a shipped scenario" <<<"$out" || fail "unknown name: $out"
grep -qE "shipped scenarios \(in $prefix/share/pheromesh/scenarios\): .*small-test" <<<"$out" || fail "unknown name: $out"
# The installed copy never looks into the source tree.
grep -qF "$src" <<<"$out" && fail "the installed pheromesh searched the source tree: $out"

step "consumer project: configure against $prefix"
cmake -S "$src/tests/install/consumer" -B "$work/consumer" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF > "$work/configure.log" 2>&1 \
  || { cat "$work/configure.log"; fail "the consumer does not configure"; }
grep -qF "from $cmakedir" "$work/configure.log" || { cat "$work/configure.log"; fail "pheromesh was not found in $prefix"; }
step "consumer project: build"
cmake --build "$work/consumer" -j2 > "$work/build.log" 2>&1 || { cat "$work/build.log"; fail "the consumer does not build"; }

step "scenario_size (pheromesh::core)"
out="$("$work/consumer/scenario_size" "$prefix/share/pheromesh/scenarios/small-test.textproto" 20)"
echo "$out"
grep -qE '^map [0-9]+ x [0-9]+, ' <<<"$out" || fail "scenario_size printed no map size"
step "bus_roundtrip (pheromesh::bus, domain $domain)"
"$work/consumer/bus_roundtrip" "$domain"
step "done"
