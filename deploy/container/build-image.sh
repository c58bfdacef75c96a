#!/usr/bin/env bash
# Builds the pheromesh image from this tree (deploy/container/Containerfile):
#   deploy/container/build-image.sh [IMAGE]        default localhost/pheromesh:latest ($PHEROMESH_IMAGE)
# Makes the base image first when it is missing (scripts/container-base-image.sh),
# builds with the host's network (apt and npm reach their registries the way
# the host does) and gives npm the host's CA bundle as a build secret, so a
# registry path that re-signs TLS with a local CA works in the image as on
# the host. Every layer is reused while its inputs are unchanged: a second
# build of the same sources takes seconds.
set -euo pipefail
here="$(cd "$(dirname "$0")/../.." && pwd)"
image="${1:-${PHEROMESH_IMAGE:-localhost/pheromesh:latest}}"
"$here/scripts/container-base-image.sh"
ca="${PHEROMESH_BUILD_CA:-/etc/ssl/certs/ca-certificates.crt}"
empty=""
if [ ! -s "$ca" ]; then
  empty="$(mktemp)"
  ca="$empty"
fi
trap '[ -z "$empty" ] || rm -f "$empty"' EXIT
podman_() { "$here/scripts/podman.sh" "$@"; }
id_of() { podman_ image inspect --format '{{.Id}}' "$1" 2> /dev/null || true; }
# Drops the image OLD if the build left it without a name (and no container uses it).
drop_if_orphaned() {
  if [ -n "$1" ] && [ "$(podman_ image inspect --format '{{len .RepoTags}}' "$1" 2> /dev/null)" = 0 ]; then
    podman_ rmi "$1" > /dev/null 2>&1 || true
  fi
}
build() {  # TAG [--target STAGE]
  local tag=$1
  shift
  podman_ build --network host --secret "id=ca,src=$ca" "$@" -f "$here/deploy/container/Containerfile" -t "$tag" "$here"
}
# The build stage is tagged too (IMAGE-build): its size can be read, and
# `podman image prune` does not take the layers the next build reuses.
build_image="${image%:*}-build"
[ "$build_image" != "$image" ] || build_image="$image-build"
[[ "$image" == *:* ]] && build_image="$build_image:${image##*:}"
old="$(id_of "$image")" old_build="$(id_of "$build_image")"
t0=$(date +%s)
build "$image"
build "$build_image" --target build > /dev/null
drop_if_orphaned "$old"
drop_if_orphaned "$old_build"
size="$(podman_ image inspect --format '{{.Size}}' "$image")"
build_size="$(podman_ image inspect --format '{{.Size}}' "$build_image")"
echo "build-image: $image built in $(($(date +%s) - t0)) s: $((size / 1000000)) MB; build stage $build_image $((build_size / 1000000)) MB"
