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
old="$(podman_ image inspect --format '{{.Id}}' "$image" 2> /dev/null || true)"
t0=$(date +%s)
podman_ build --network host --secret "id=ca,src=$ca" \
  -f "$here/deploy/container/Containerfile" -t "$image" "$here"
# The image this one replaced, if nothing else names it (no tag, no container).
new="$(podman_ image inspect --format '{{.Id}}' "$image")"
if [ -n "$old" ] && [ "$old" != "$new" ] && [ "$(podman_ image inspect --format '{{len .RepoTags}}' "$old" 2> /dev/null)" = 0 ]; then
  podman_ rmi "$old" > /dev/null 2>&1 || true
fi
size="$(podman_ image inspect --format '{{.Size}}' "$image")"
echo "build-image: $image built in $(($(date +%s) - t0)) s, $((size / 1000000)) MB"
