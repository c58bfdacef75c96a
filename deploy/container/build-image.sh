#!/usr/bin/env bash
# Builds the pheromesh image from this tree (deploy/container/Containerfile):
#   deploy/container/build-image.sh [IMAGE]        default localhost/pheromesh:latest ($PHEROMESH_IMAGE)
#   deploy/container/build-image.sh --programs-from BUILD [IMAGE]
#       the programs of BUILD, a build of this tree made on this host (which
#       must run the image's Debian release, bookworm), instead of compiling
#       them in the image: `cmake --install BUILD --component runtime --strip`
#       into a scratch folder handed to the build, and the Debian packages of
#       every library they load (ldd, dpkg -S) added to the runtime stage.
#       Seconds instead of a quarter of an hour when BUILD is already built;
#       the image then holds BUILD's programs (with Python policies if BUILD
#       has them), not a compile of its own.
# Makes the base image first when it is missing (scripts/container-base-image.sh),
# builds with the host's network (apt and npm reach their registries the way
# the host does) and gives npm the host's CA bundle as a build secret, so a
# registry path that re-signs TLS with a local CA works in the image as on
# the host. Every layer is reused while its inputs are unchanged: a second
# build of the same sources takes seconds.
set -euo pipefail
here="$(cd "$(dirname "$0")/../.." && pwd)"
programs_from=""
if [ "${1:-}" = --programs-from ]; then
  [ $# -ge 2 ] || { echo "build-image: --programs-from needs a build folder" >&2; exit 2; }
  programs_from="$(cd "$2" 2> /dev/null && pwd)" || { echo "build-image: no build folder '$2'" >&2; exit 2; }
  shift 2
fi
case "${1:-}" in -*) echo "build-image: unknown option '$1' (usage: build-image.sh [--programs-from BUILD] [IMAGE])" >&2; exit 2 ;; esac
image="${1:-${PHEROMESH_IMAGE:-localhost/pheromesh:latest}}"
staging=""
extra=()
if [ -n "$programs_from" ]; then
  [ -f "$programs_from/CMakeCache.txt" ] || { echo "build-image: $programs_from is not a CMake build folder" >&2; exit 2; }
  for p in pheromesh pheromesh-uav pheromesh-place pheromesh-ground; do
    [ -x "$programs_from/bin/$p" ] || { echo "build-image: $programs_from/bin/$p is not built (cmake --build $programs_from)" >&2; exit 2; }
  done
  codename="$(. /etc/os-release && echo "${VERSION_CODENAME:-}")"
  [ "$codename" = bookworm ] || {
    echo "build-image: --programs-from needs programs built on Debian bookworm, the image's release; this host runs '${codename:-unknown}'" >&2
    exit 2
  }
  staging="$(mktemp -d /var/tmp/pheromesh-image-programs.XXXXXX)"
  cmake --install "$programs_from" --component runtime --strip --prefix "$staging" > "$staging.install.log" 2>&1 || {
    cat "$staging.install.log" >&2
    echo "build-image: cmake --install $programs_from failed" >&2
    exit 1
  }
  rm -f "$staging.install.log"
  # The packages of the libraries the programs load, resolved on this host
  # (the runtime stage installs the usual ones anyway; apt skips repeats).
  libs="$(find "$staging/bin" "$staging/lib" -type f \( -perm -u+x -o -name '*.so*' \) -exec ldd {} + 2> /dev/null |
    awk -v own="$staging/" '$2 == "=>" && $3 ~ /^\// && index($3, own) != 1 {print $3}' | sort -u || true)"
  pkgs=""
  for lib in $libs; do
    owner="$(dpkg -S "$lib" 2> /dev/null || dpkg -S "$(realpath "$lib")" 2> /dev/null || true)"
    [ -n "$owner" ] || { echo "build-image: no Debian package owns $lib, which the programs load" >&2; continue; }
    pkgs="$pkgs ${owner%%:*}"
  done
  pkgs="$(tr ' ' '\n' <<< "$pkgs" | sed '/^$/d' | sort -u | tr '\n' ' ')"
  extra=(--build-arg PROGRAMS=host --build-context "host-install=$staging" --build-arg "EXTRA_PACKAGES=$pkgs")
fi
"$here/scripts/container-base-image.sh"
ca="${PHEROMESH_BUILD_CA:-/etc/ssl/certs/ca-certificates.crt}"
empty=""
if [ ! -s "$ca" ]; then
  empty="$(mktemp)"
  ca="$empty"
fi
trap '[ -z "$empty" ] || rm -f "$empty"; [ -z "$staging" ] || rm -rf "$staging"' EXIT
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
  podman_ build --network host --secret "id=ca,src=$ca" "${extra[@]}" "$@" -f "$here/deploy/container/Containerfile" \
    -t "$tag" "$here"
}
# The build stage is tagged too (IMAGE-build): its size can be read, and
# `podman image prune` does not take the layers the next build reuses.
build_image="${image%:*}-build"
[ "$build_image" != "$image" ] || build_image="$image-build"
[[ "$image" == *:* ]] && build_image="$build_image:${image##*:}"
old="$(id_of "$image")" old_build="$(id_of "$build_image")"
t0=$(date +%s)
build "$image"
drop_if_orphaned "$old"
size="$(podman_ image inspect --format '{{.Size}}' "$image")"
if [ -n "$programs_from" ]; then
  echo "build-image: $image built in $(($(date +%s) - t0)) s from the programs of $programs_from: $((size / 1000000)) MB"
  exit 0
fi
build "$build_image" --target build > /dev/null
drop_if_orphaned "$old_build"
build_size="$(podman_ image inspect --format '{{.Size}}' "$build_image")"
echo "build-image: $image built in $(($(date +%s) - t0)) s: $((size / 1000000)) MB; build stage $build_image $((build_size / 1000000)) MB"
