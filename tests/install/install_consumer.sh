#!/usr/bin/env bash
# Install.*: `cmake --install` into a temporary prefix, move the prefix
# elsewhere (a relocated install must still work), then
#   - the layout of docs/install.md is there (and no test program), with the
#     DDS modules in lib/pheromesh and no program linking a vendor itself;
#   - the installed `pheromesh` finds a shipped scenario by name from another
#     directory, and an unknown name lists the shipped ones;
#   - the installed Python package (when built) imports from the moved
#     prefix, finds the shipped scenarios and `pheromesh` there, and simulates;
#   - tests/install/consumer, a project of its own, finds the package with
#     find_package(pheromesh CONFIG), builds, and its two programs run:
#     scenario_size (pheromesh::core) and bus_roundtrip (pheromesh::bus);
#   - examples/repulsive_coverage, a policy plugin, builds against it, the
#     installed pheromesh validates, simulates and flies its scenario in
#     lockstep (the same final field), and refuses a wrong SHA-256 pin.
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
# The DDS modules beside the CMake package's libdir, and no program linking a
# vendor: each process loads the one it uses (docs/install.md).
libdir="$(dirname "$(dirname "$cmakedir")")"
for v in cyclone fastdds; do
  [ -f "$libdir/pheromesh/libpheromesh_dds_$v.so" ] || fail "lib/pheromesh/libpheromesh_dds_$v.so is not installed"
done
for p in pheromesh pheromesh-uav pheromesh-place pheromesh-ground; do
  if ldd "$prefix/bin/$p" | grep -E 'libddsc|libfastrtps'; then fail "$p links a DDS vendor itself"; fi
done
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

pydir="$prefix/lib/python3/dist-packages"
if [ -d "$pydir/pheromesh" ]; then
  step "the installed Python package finds the shipped scenarios and the pheromesh of the moved prefix"
  py="$(sed -n 's/^Python_EXECUTABLE:FILEPATH=//p' "$build/CMakeCache.txt")"
  out="$(cd "$work/elsewhere" && PYTHONPATH="$pydir" "${py:-python3}" -c "
import pheromesh
s = pheromesh.Scenario.load('small-test')
r = pheromesh.sim(s, ticks=5)
print(s.path); print(pheromesh.program()); print(r.metrics['ticks'], r.fields['path'].shape)" 2>&1)" \
    || fail "import pheromesh from $pydir: $out"
  grep -qxF "$prefix/share/pheromesh/scenarios/small-test.textproto" <<<"$out" || fail "Python found small-test elsewhere: $out"
  grep -qxF "$prefix/bin/pheromesh" <<<"$out" || fail "Python's pheromesh.program() is not the moved one: $out"
  grep -qxF "5 (30, 30)" <<<"$out" || fail "Python sim: $out"
fi

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
step "examples/repulsive_coverage: a policy plugin built against $prefix"
# Copied as a user would take it, built in its own build/ folder, where the
# example's scenario looks for the library.
cp -r "$src/examples/repulsive_coverage" "$work/example"
rm -rf "$work/example/build"
cmake -S "$work/example" -B "$work/example/build" -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF > "$work/example-configure.log" 2>&1 \
  || { cat "$work/example-configure.log"; fail "the example plugin does not configure"; }
cmake --build "$work/example/build" -j2 > "$work/example-build.log" 2>&1 \
  || { cat "$work/example-build.log"; fail "the example plugin does not build"; }
plugin="$work/example/build/librepulsive_coverage.so"
[ -f "$plugin" ] || fail "no $plugin"
# It exports the three symbols of PHEROMESH_POLICY_PLUGIN and nothing of the
# core it links (a second copy of the scenario schema's generated code would
# abort the process that loads it).
exported="$(nm -D --defined-only "$plugin" | awk '{print $3}' | grep -v '^_' | sort | tr '\n' ' ')"
[ "$exported" = "pheromesh_policy_plugin pheromesh_policy_plugin_abi pheromesh_policy_plugin_layout " ] \
  || fail "the plugin exports: $exported"
if nm "$plugin" | grep -q 'scenario_2eproto'; then fail "the plugin links the scenario schema's generated code"; fi
scenario="$work/example/repulsive-coverage.textproto"
out="$("$prefix/bin/pheromesh" validate "$scenario")" || fail "validate: $out"
sha="$(sha256sum "$plugin" | cut -d' ' -f1)"
grep -qF "policy      repulsive_coverage from the plugin $plugin (SHA-256 $sha, not pinned)" <<<"$out" \
  || fail "validate does not name the library and its SHA-256: $out"
step "the example in sim, and in lockstep on Cyclone DDS (domain $domain): the same final field"
(cd "$work" && "$prefix/bin/pheromesh" sim "$scenario" --ticks 40 --quiet --out ex-sim) > "$work/ex-sim.log" 2>&1 \
  || { cat "$work/ex-sim.log"; fail "sim of the example failed"; }
(cd "$work" && "$prefix/bin/pheromesh" run "$scenario" --ticks 40 --clock lockstep --dds cyclone --domain "$domain" \
  --out ex-lockstep) > "$work/ex-lockstep.log" 2>&1 || { tail -n 30 "$work/ex-lockstep.log"; fail "lockstep run of the example failed"; }
grep -qF "policy repulsive_coverage from the plugin $plugin" "$work/ex-lockstep.log" \
  || fail "run does not say which library it loads: $(cat "$work/ex-lockstep.log")"
cmp "$work/ex-sim/final_field.txt" "$work/ex-lockstep/final_field.txt" \
  || fail "the lockstep run's final_field.txt differs from the simulator's"
grep -q '"policy": "repulsive_coverage"' "$work/ex-sim/metrics.json" || fail "sim ran another policy"
step "a pin that does not match is refused, naming this host"
sed "s|# sha256: \"...\"|sha256: \"$(printf '0%.0s' $(seq 64))\"|" "$scenario" > "$work/example/pinned.textproto"
if out="$("$prefix/bin/pheromesh" validate "$work/example/pinned.textproto" 2>&1)"; then fail "a wrong pin was accepted"; fi
grep -qF "host $(hostname): the plugin library $plugin has SHA-256 $sha, but the scenario pins" <<<"$out" \
  || fail "wrong pin: $out"
step "done"
