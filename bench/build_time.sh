#!/usr/bin/env bash
# What a cold build of the tree costs, file by file against unity (the
# Makefile's default, UNITY=ON), measured one after the other on the same
# commit: configure + `cmake --build` of everything `make test` builds, from
# an empty build directory, without ccache. Prints both times and their ratio.
#
#   bench/build_time.sh [COMMIT]      (default HEAD; about 30 minutes on 2 cores)
# Keep the host otherwise idle.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
commit=${1:-HEAD}
work=$(mktemp -d /tmp/pheromesh-build-time.XXXXXX)
trap 'git -C "$root" worktree remove --force "$work/src" > /dev/null 2>&1 || true; rm -rf "$work"' EXIT
git -C "$root" worktree add --detach "$work/src" "$commit" > /dev/null 2>&1
jobs=$(nproc)
declare -A took
for unity in OFF ON; do
  tree="$work/build-$unity"
  start=$(date +%s.%N)
  CCACHE_DISABLE=1 cmake -S "$work/src" -B "$tree" -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_UNITY_BUILD=$unity" \
    > "$work/configure-$unity.log" 2>&1 || { cat "$work/configure-$unity.log" >&2; exit 2; }
  CCACHE_DISABLE=1 cmake --build "$tree" -j"$jobs" > "$work/build-$unity.log" 2>&1 ||
    { tail -30 "$work/build-$unity.log" >&2; echo "build_time.sh: the UNITY=$unity build failed" >&2; exit 2; }
  took[$unity]=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
  printf 'UNITY=%-3s  configure + build  %7.1f s\n' "$unity" "${took[$unity]}"
  rm -rf "$tree"
done
printf 'unity / file by file: %.2f (%s, %d jobs)\n' "$(awk -v u="${took[ON]}" -v f="${took[OFF]}" 'BEGIN { print u / f }')" \
  "$(git -C "$root" rev-parse --short "$commit")" "$jobs"
