#!/usr/bin/env bash
# The scale benchmark before and after issue 12, with one command: builds
# the bus as it was (commit 65d4b97, a UAV re-creating its per-tile readers
# as it flew) with the measurement code of `pheromesh bench scale` applied
# (bench/baseline/65d4b97-measurement.patch: the same late-tick, discovery
# and resource accounting, nothing else), then runs the same benchmark with
# both builds on the same sizes and prints the two tables. The baseline
# takes today's cli/ (the launcher's resource accounting and the benchmark
# itself) and the scale scenario, so both sides are measured by one code.
#
#   bench/scale_before_after.sh [SIZES] [VENDORS] [EXTRA pheromesh bench scale ARGS...]
#   bench/scale_before_after.sh 25,50,100 cyclone,fastdds
# Keep the host otherwise idle; each run takes about a minute.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
sizes=${1:-25,50,100}
vendors=${2:-cyclone,fastdds}
shift $(( $# > 2 ? 2 : $# ))
base=${BASELINE_DIR:-$root/out/baseline-65d4b97}
if [ ! -x "$base/build/bin/pheromesh" ]; then
  rm -rf "$base"
  git -C "$root" worktree add --detach "$base" 65d4b97
  git -C "$base" apply "$root/bench/baseline/65d4b97-measurement.patch"
  rm -rf "$base/cli"
  cp -r "$root/cli" "$base/cli"
  cp "$root/scenarios/scale-100x100.textproto" "$base/scenarios/"
  cmake -S "$base" -B "$base/build" -DCMAKE_BUILD_TYPE=RelWithDebInfo > /dev/null
  cmake --build "$base/build" -j"$(nproc)" --target pheromesh pheromesh-uav pheromesh-place pheromesh-ground
fi
scenario="$root/scenarios/scale-100x100.textproto"
"$base/build/bin/pheromesh" bench scale "$scenario" --sizes "$sizes" --dds "$vendors" --stop-late-share 0.5 \
  --out "$root/out/bench-before" "$@" > /dev/null
"$root/build/bin/pheromesh" bench scale "$scenario" --sizes "$sizes" --dds "$vendors" --stop-late-share 0.5 \
  --out "$root/out/bench-after" "$@" > /dev/null
echo "## before (65d4b97: per-tile readers re-created while flying)"
sed -n '/^| vendor/,/^$/p' "$root/out/bench-before/scale.md"
echo "## after (fixed endpoints, views from the home place agent, start gate)"
sed -n '/^| vendor/,/^$/p' "$root/out/bench-after/scale.md"
