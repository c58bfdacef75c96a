#!/usr/bin/env bash
# Installs what pheromesh needs from Debian bookworm's packages, and nothing
# that is already there. Used by both README commands (make demo / make test).
set -euo pipefail

packages=(
  build-essential cmake pkg-config
  dpkg-dev                               # make package: dpkg-shlibdeps writes the .deb's Depends (also in build-essential)
  cyclonedds-dev cyclonedds-tools        # DDS (C API, idlc, ddsperf)
  libfastrtps-dev libfastcdr-dev fastddsgen fastdds-tools  # Fast DDS (C++ API, fastddsgen, fastdds shm clean)
  libprotobuf-dev protobuf-compiler      # scenario schema
  libeigen3-dev libspdlog-dev libfmt-dev libcli11-dev nlohmann-json3-dev
  libgoogle-perftools-dev                # tcmalloc_minimal, the place agents' and ground station's heap (PHEROMESH_ALLOCATOR, cmake/Allocator.cmake)
  python3-dev python3-pybind11 pybind11-dev python3-numpy  # the Python package (python/, docs/python.md)
  python3-pandas python3-matplotlib python3-pytest jupyter-nbconvert python3-ipykernel  # its tests and the notebook (examples/python)
  libgtest-dev libgmock-dev libbenchmark-dev
  clang libclang-rt-14-dev               # fuzzing: libFuzzer + ASan/UBSan (make fuzz, ctest -L fuzz; docs/fuzzing.md)
  libcpp-httplib-dev libssl-dev zlib1g-dev libbrotli-dev  # web console server (gzip/brotli), command HMAC, DDS Security PKI (security init)
  chromium prometheus curl                 # web console end-to-end test (headless browser, promtool)
  iproute2 nftables util-linux             # network faults: namespaces, veth, bridge (ip), partition/loss (nft); setpriv in a test
  podman runc debootstrap podman-compose catatonit python3-yaml  # container tests: the base image (debootstrap), the image, compose, kube play (its pause image needs catatonit; expand-statefulsets reads YAML)
  containernetworking-plugins golang-github-containernetworking-plugin-dnsname  # podman networks with DNS between containers
)
# The web front-end is built with npm at build time: Debian's nodejs + npm
# (18) build it; the browser test's playwright-core needs Node.js >= 20, which
# the CI machines have. A Node.js already on the machine is used as it is.
if ! command -v npm > /dev/null 2>&1; then
  packages+=(nodejs npm)
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: everything is installed"
  exit 0
fi
echo "install-deps: installing ${missing[*]}"
SUDO=""
[ "$(id -u)" -ne 0 ] && SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
