#!/usr/bin/env bash
# Package.*: `cpack -G DEB` makes pheromesh_<version>_<arch>.deb (and
# pheromesh-dev, and python3-pheromesh when the build has the Python
# package), then on a clean Debian bookworm in a podman container
#   apt-get install /pkg/pheromesh_*.deb     (apt resolves the Depends alone)
#   cd /tmp && pheromesh run small-test ...   (a shipped scenario by name)
# must exit 0 and write metrics.json with balanced deposit accounting; then
#   apt-get install /pkg/pheromesh-dev_*.deb cmake g++ make
#   examples/repulsive_coverage (a policy plugin) builds and runs in `sim`;
#   apt-get install /pkg/python3-pheromesh_*.deb
#   python3 -c "import pheromesh; pheromesh.sim('small-test', ...)"
# apt reaches the Debian mirror through the host's network; the swarm runs
# in a second container with no network but its own loopback, so it meets
# no other swarm on this host.
# Usage: deb_in_container.sh BUILD_DIR SOURCE_DIR DOMAIN
# Needs root, podman, debootstrap (the base image) and dpkg-dev; exits 77
# (skipped) when podman or dpkg-shlibdeps is missing.
set -euo pipefail
build="$(cd "$1" && pwd)"
src="$(cd "$2" && pwd)"
domain="$3"
podman_() { "$src/scripts/podman.sh" "$@"; }
fail() { echo "FAIL: $*" >&2; exit 1; }
t0=$(date +%s)
step() { echo "--- $* ($(( $(date +%s) - t0 )) s)"; }
for tool in podman dpkg-shlibdeps cpack; do
  command -v "$tool" > /dev/null || { echo "SKIP: $tool is missing (scripts/install-deps.sh installs it)"; exit 77; }
done

tag="$$-$(date +%s)"
container="phmp-deb-install-$tag"
image="localhost/phmp-deb-installed:$tag"
work="$(mktemp -d /var/tmp/phmp-deb.XXXXXX)"
cleanup() {
  podman_ rm -f "$container" > /dev/null 2>&1 || true
  podman_ rmi -f "$image" > /dev/null 2>&1 || true
  rm -rf "$work"
}
trap cleanup EXIT

step "cpack -G DEB"
(cd "$build" && cpack -G DEB -B "$work/pkg") > "$work/cpack.log" 2>&1 || { cat "$work/cpack.log"; fail "cpack failed"; }
version="$(sed -n 's/^CMAKE_PROJECT_VERSION:STATIC=//p' "$build/CMakeCache.txt")"
arch="$(dpkg --print-architecture)"
deb="$work/pkg/pheromesh_${version}_${arch}.deb"
dev="$work/pkg/pheromesh-dev_${version}_${arch}.deb"
[ -f "$deb" ] || { ls -l "$work/pkg"; fail "no $(basename "$deb")"; }
[ -f "$dev" ] || { ls -l "$work/pkg"; fail "no $(basename "$dev")"; }
echo "$(basename "$deb"): $(du -k "$deb" | cut -f1) KiB; $(basename "$dev"): $(du -k "$dev" | cut -f1) KiB"
depends="$(dpkg-deb -f "$deb" Depends)"
echo "Depends: $depends"
# dpkg-shlibdeps names the DDS libraries of both vendors and protobuf.
for lib in libddsc0 libfastrtps libprotobuf; do
  grep -q "$lib" <<<"$depends" || fail "Depends names no $lib: $depends"
done
[ "$(dpkg-deb -f "$deb" Section)" = science ] || fail "Section: $(dpkg-deb -f "$deb" Section)"
[ -n "$(dpkg-deb -f "$deb" Maintainer)" ] || fail "no Maintainer"
# The runtime package has the programs and data, the -dev package the rest.
dpkg-deb -c "$deb" > "$work/deb.list"
dpkg-deb -c "$dev" > "$work/dev.list"
for f in ./usr/bin/pheromesh ./usr/bin/pheromesh-uav ./usr/share/pheromesh/scenarios/small-test.textproto; do
  grep -qE " $f\$" "$work/deb.list" || fail "$f is not in $(basename "$deb")"
done
grep -qE '\.(a|hpp|cmake)$' "$work/deb.list" && fail "$(basename "$deb") holds development files"
grep -qE '/cmake/pheromesh/pheromeshConfig\.cmake$' "$work/dev.list" || fail "no pheromeshConfig.cmake in $(basename "$dev")"
grep -qE '/include/pheromesh/bus/bus\.hpp$' "$work/dev.list" || fail "no bus.hpp in $(basename "$dev")"

step "base image"
"$src/scripts/container-base-image.sh"

step "apt-get install ./$(basename "$deb") on a clean bookworm"
podman_ run --name "$container" --network host -v "$work/pkg:/pkg:ro" docker.io/library/debian:bookworm \
  bash -c "set -e; apt-get update -qq; DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends /pkg/$(basename "$deb")" \
  > "$work/apt.log" 2>&1 || { tail -n 40 "$work/apt.log"; fail "apt-get install failed"; }
grep -E '^(Need to get|After this operation)' "$work/apt.log" || true
podman_ commit -q "$container" "$image" > /dev/null

step "pheromesh run small-test in /tmp (no network but loopback)"
podman_ run --rm --network none "$image" bash -c \
  "cd /tmp && pheromesh run small-test --ticks 20 --dds mixed --domain $domain --out o > run.log 2>&1 \
   || { tail -n 30 run.log; exit 1; }; cat o/metrics.json" > "$work/metrics.json" \
  || { cat "$work/metrics.json"; fail "pheromesh run failed in the container"; }

step "metrics.json"
python3 - "$work/metrics.json" <<'PY'
import json, sys
m = json.load(open(sys.argv[1]))
sent, applied, rejected = m["deposits_sent"], m["deposits_applied"], m["deposits_rejected"]
print(f"ticks {m['ticks']}, uavs {m['uavs']}, place agents {m['place_agents']}, "
      f"deposits sent {sent} = applied {applied} + rejected {rejected}")
assert m["ticks"] == 20, m["ticks"]
assert sent > 0, "no deposits"
assert sent == applied + rejected, "deposit accounting does not balance"
assert m["processes_crashed"] == 0, m["processes_crashed"]
PY
step "pheromesh-dev: examples/repulsive_coverage builds against the installed packages and runs in sim"
# The plugin example as a user of the packages builds it: pheromesh-dev (apt
# resolves its Depends: the headers of Eigen, protobuf, OpenSSL, spdlog and
# the DDS vendors), a compiler and CMake, then `cmake` in the example's
# folder without a prefix (the package's CMake files are in /usr).
podman_ run --rm --network host -v "$work/pkg:/pkg:ro" -v "$src/examples/repulsive_coverage:/example:ro" "$image" \
  bash -c "set -e
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends /pkg/$(basename "$dev") cmake g++ make \
      > /tmp/apt-dev.log 2>&1 || { tail -n 30 /tmp/apt-dev.log; exit 1; }
    cp -r /example /tmp/example && cd /tmp/example && rm -rf build out
    cmake -S . -B build > /tmp/configure.log 2>&1 || { cat /tmp/configure.log; exit 1; }
    cmake --build build -j2 > /tmp/build.log 2>&1 || { tail -n 40 /tmp/build.log; exit 1; }
    pheromesh validate repulsive-coverage.textproto | grep -F 'policy      repulsive_coverage from the plugin /tmp/example/build/librepulsive_coverage.so'
    pheromesh sim repulsive-coverage.textproto --ticks 40 --quiet --out out/sim
    grep -q '\"policy\": \"repulsive_coverage\"' out/sim/metrics.json
    test -s out/sim/final_field.txt" > "$work/example.log" 2>&1 \
  || { cat "$work/example.log"; fail "the example plugin does not build or run against the installed packages"; }
cat "$work/example.log"
py="$work/pkg/python3-pheromesh_${version}_${arch}.deb"
if [ -f "$py" ]; then
  step "python3-pheromesh: import pheromesh, a shipped scenario by name, sim"
  dpkg-deb -c "$py" > "$work/py.list"
  grep -qE '/usr/lib/python3/dist-packages/pheromesh/_pheromesh\.cpython-.*\.so$' "$work/py.list" \
    || fail "no extension in $(basename "$py")"
  podman_ run --rm --network host -v "$work/pkg:/pkg:ro" "$image" \
    bash -c "set -e
      apt-get update -qq
      DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends /pkg/$(basename "$py") \
        > /tmp/apt-py.log 2>&1 || { tail -n 30 /tmp/apt-py.log; exit 1; }
      cd /tmp && python3 -c \"import pheromesh; r = pheromesh.sim('small-test', ticks=20); \
        assert r.fields['target'].shape == (30, 30); assert r.metrics['ticks'] == 20; print('python3-pheromesh: ok', r)\"" \
    > "$work/python.log" 2>&1 || { cat "$work/python.log"; fail "python3-pheromesh does not install or import"; }
  cat "$work/python.log"
fi
step "done"
