#!/usr/bin/env bash
# What a place agent receives per tick, before and after issue 25's local
# traffic, with one command. Builds the tree as it was (commit d362a46:
# every place agent received every region's whole field each tick) with only
# the byte count applied (bench/baseline/d362a46-bytes-measurement.patch:
# core::payload_bytes, BusStats.bytes_taken, PlaceHealth.bytes_received and
# metrics.json place_bytes_received_per_tick, nothing else), then runs the
# same lockstep swarm with both builds on scale-100x100 and on scale-400x400
# (the same 16 regions and tiles on a map of 16x the area) and prints one
# table. Lockstep, so both builds fly exactly the same ticks.
#
#   bench/place_traffic.sh [UAVS] [TICKS] [VENDOR]
#   bench/place_traffic.sh 50 60 cyclone
# A second table: what the ground station receives per tick in realtime at
# 20 Hz (RT_UAVS UAVs, RT_TICKS ticks; default 20 and 120): before, every
# region's whole field every tick; after, the tiles changed since the last
# send at the console's 5 Hz (core::FieldToGround). The patch also counts
# the ground station's bytes (metrics.json ground_bytes_received_per_tick).
# AFTER_EXTRA: more `pheromesh run` arguments for this tree's runs only, e.g.
# AFTER_EXTRA="--dds-profile cells" (the baseline has no cells).
# Payload bytes (core::payload_bytes: the samples' fields, without DDS and
# UDP headers). Keep the host otherwise idle; each run takes seconds.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
uavs=${1:-50}
ticks=${2:-60}
vendor=${3:-cyclone}
base=${BASELINE_DIR:-$root/out/baseline-d362a46}
if [ ! -x "$base/build/bin/pheromesh" ]; then
  rm -rf "$base"
  git -C "$root" worktree add --detach "$base" d362a46
  git -C "$base" apply "$root/bench/baseline/d362a46-bytes-measurement.patch"
  cp "$root/scenarios/scale-400x400.textproto" "$base/scenarios/"
  cmake -S "$base" -B "$base/build" -DCMAKE_BUILD_TYPE=RelWithDebInfo > /dev/null
  cmake --build "$base/build" -j"$(nproc)" --target pheromesh pheromesh-uav pheromesh-place pheromesh-ground
fi
rt_uavs=${RT_UAVS:-20}
rt_ticks=${RT_TICKS:-120}
mkdir -p "$root/out"
# run_one BUILD_ROOT SCENARIO OUT EXPR ARGS...: one `pheromesh run`; prints the
# Python expression EXPR of its metrics.json (m).
run_one() {
  local build=$1 sc=$2 out=$3 expr=$4
  shift 4
  rm -rf "$out"
  "$build/build/bin/pheromesh" run "$root/scenarios/$sc.textproto" "$@" --dds "$vendor" --out "$out" > "$out.log" 2>&1 ||
    { echo "a run failed: $out.log" >&2; exit 1; }
  python3 -c "import json, sys; m = json.load(open(sys.argv[1])); print($expr)" "$out/metrics.json"
}
# table NAME EXPR ARGS...: one row per build and map; EXPR gives "A|B|C", and
# A's growth from scale-100x100 to scale-400x400 is shown beside it.
table() {
  local name=$1 expr=$2
  shift 2
  for side in before after; do
    local dir first=""
    dir=$([ "$side" = before ] && echo "$base" || echo "$root")
    for sc in scale-100x100 scale-400x400; do
      local extra=()
      [ "$side" = after ] && [ -n "${AFTER_EXTRA:-}" ] && read -r -a extra <<< "$AFTER_EXTRA"
      row=$(run_one "$dir" "$sc" "$root/out/$name-$side-$sc" "$expr" "$@" "${extra[@]}")  # set -e: a failed run ends the bench
      IFS='|' read -r a b c <<< "$row"
      [ -z "$first" ] && first=$a
      growth=$(awk -v x="$first" -v y="$a" 'BEGIN {printf "%.1f", y / x}')
      printf '| %s | %s | %s (x%s) | %s | %s |\n' "$side" "$sc" "$a" "$growth" "$b" "$c"
    done
  done
}
printf '| build | map | received per place agent and tick [kB] | tile samples per UAV and tick | lockstep ticks/s |\n|---|---|---|---|---|\n'
table place-traffic \
  "f\"{m['place_bytes_received_per_tick'] / 1000:.1f}|{m['tile_samples_per_uav_tick']:.2f}|{m['lockstep']['ticks_per_s']:.1f}\"" \
  --uavs "$uavs" --ticks "$ticks" --clock lockstep
echo
echo "$uavs UAVs, $ticks lockstep ticks, 16 place agents, $vendor; before: d362a46 + the byte count; after: this tree${AFTER_EXTRA:+ with $AFTER_EXTRA}."
echo
printf '| build | map | ground station received per tick [kB] | per place agent and tick [kB] | UAV ticks late [%%] |\n|---|---|---|---|---|\n'
table ground-traffic \
  "f\"{m['ground_bytes_received_per_tick'] / 1000:.1f}|{m['place_bytes_received_per_tick'] / 1000:.1f}|{100 * m['uav_late_share']:.1f}\"" \
  --uavs "$rt_uavs" --ticks "$rt_ticks" --rate 20
echo
echo "$rt_uavs UAVs, $rt_ticks realtime ticks at 20 Hz, $vendor${AFTER_EXTRA:+; after with $AFTER_EXTRA}."
