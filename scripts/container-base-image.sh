#!/usr/bin/env bash
# Makes the Debian bookworm base image that deploy/container/Containerfile
# starts FROM, when there is no image registry: debootstrap a minimal
# bookworm and import it into podman under the name the Containerfile uses.
# Does nothing when the image exists already (the container tests reuse it).
#   scripts/container-base-image.sh [IMAGE]     default docker.io/library/debian:bookworm
# Needs root, debootstrap and the Debian mirror (MIRROR, default the one apt uses).
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
image="${1:-docker.io/library/debian:bookworm}"
podman_() { "$here/scripts/podman.sh" "$@"; }
if podman_ image exists "$image"; then
  echo "container-base-image: $image exists"
  exit 0
fi
mirror="${MIRROR:-}"
if [ -z "$mirror" ]; then
  mirror="$(grep -hE '^[[:space:]]*(URIs:|deb )' /etc/apt/sources.list /etc/apt/sources.list.d/* 2>/dev/null \
    | grep -oE 'https?://[^ ]+/debian/?( |$)' | grep -v security | head -n1 | tr -d ' ' || true)"
  mirror="${mirror:-http://deb.debian.org/debian}"
fi
command -v debootstrap > /dev/null || { echo "container-base-image: debootstrap is missing (scripts/install-deps.sh installs it)" >&2; exit 1; }
root="$(mktemp -d /var/tmp/pheromesh-bookworm.XXXXXX)"
trap 'rm -rf "$root"' EXIT
t0=$(date +%s)
echo "container-base-image: debootstrap bookworm from $mirror into $root"
debootstrap --variant=minbase bookworm "$root" "$mirror" > "$root.log" 2>&1 || { tail -n 20 "$root.log" >&2; exit 1; }
rm -f "$root.log"
# Leave apt's lists out of the image (as Debian's official image does).
rm -rf "$root"/var/lib/apt/lists/* "$root"/var/cache/apt/*.bin
# `podman import` sets no environment: give the image Debian's PATH, as the
# official image has, or `command: [sh, ...]` in a pod spec finds nothing.
tar -C "$root" -c . | podman_ import --change 'CMD ["/bin/bash"]' \
  --change 'ENV PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin' - "$image" > /dev/null
echo "container-base-image: $image made in $(( $(date +%s) - t0 )) s"
