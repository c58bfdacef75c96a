#!/usr/bin/env bash
# podman as this project runs it (docs/deployment.md "Containers"): the runc
# runtime and cgroupfs (no systemd in the CI machines), and our
# containers.conf, which keeps the host's ulimits out of the containers
# (podman's default nofile of 1048576 is above what these hosts allow).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
export CONTAINERS_CONF="${CONTAINERS_CONF:-$here/deploy/container/containers.conf}"
exec podman --runtime runc --cgroup-manager cgroupfs "$@"
