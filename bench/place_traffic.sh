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
measure() {  # BUILD_ROOT SCENARIO OUT -> "bytes per place agent and tick|tile samples per UAV and tick|ticks/s"
  rm -rf "$3"
  "$1/build/bin/pheromesh" run "$root/scenarios/$2.textproto" --uavs "$uavs" --ticks "$ticks" --clock lockstep \
    --dds "$vendor" --out "$3" > "$3.log" 2>&1 || { echo "a run failed: $3.log" >&2; exit 1; }
  python3 - "$3/metrics.json" <<'PY'
import json, sys
m = json.load(open(sys.argv[1]))
print(f"{m['place_bytes_received_per_tick'] / 1000:.1f}|{m['tile_samples_per_uav_tick']:.2f}|{m['lockstep']['ticks_per_s']:.1f}")
PY
}
printf '| build | map | place agents | received per place agent and tick [kB] | tile samples per UAV and tick | lockstep ticks/s |\n|---|---|---|---|---|---|\n'
declare -A first
for side in before after; do
  dir=$([ "$side" = before ] && echo "$base" || echo "$root")
  for sc in scale-100x100 scale-400x400; do
    IFS='|' read -r kb tiles rate < <(measure "$dir" "$sc" "$root/out/place-traffic-$side-$sc")
    [ "$sc" = scale-100x100 ] && first[$side]=$kb
    growth=$(awk -v a="${first[$side]}" -v b="$kb" 'BEGIN {printf "%.1f", b / a}')
    printf '| %s | %s | 16 | %s (x%s) | %s | %s |\n' "$side" "$sc" "$kb" "$growth" "$tiles" "$rate"
  done
done
echo
echo "$uavs UAVs, $ticks lockstep ticks, $vendor; before: d362a46 + the byte count; after: this tree."
measure_ground() {  # BUILD_ROOT SCENARIO OUT -> "ground kB per tick|place agent kB per tick|late share %"
  rm -rf "$3"
  "$1/build/bin/pheromesh" run "$root/scenarios/$2.textproto" --uavs "$rt_uavs" --ticks "$rt_ticks" --rate 20 \
    --dds "$vendor" --out "$3" > "$3.log" 2>&1 || { echo "a run failed: $3.log" >&2; exit 1; }
  python3 - "$3/metrics.json" <<'PY'
import json, sys
m = json.load(open(sys.argv[1]))
print(f"{m['ground_bytes_received_per_tick'] / 1000:.1f}|{m['place_bytes_received_per_tick'] / 1000:.1f}|{100 * m['uav_late_share']:.1f}")
PY
}
echo
printf '| build | map | ground station received per tick [kB] | per place agent and tick [kB] | UAV ticks late [%%] |\n|---|---|---|---|---|\n'
for side in before after; do
  dir=$([ "$side" = before ] && echo "$base" || echo "$root")
  for sc in scale-100x100 scale-400x400; do
    IFS='|' read -r gkb pkb late < <(measure_ground "$dir" "$sc" "$root/out/ground-traffic-$side-$sc")
    [ "$sc" = scale-100x100 ] && first[g$side]=$gkb
    growth=$(awk -v a="${first[g$side]}" -v b="$gkb" 'BEGIN {printf "%.1f", b / a}')
    printf '| %s | %s | %s (x%s) | %s | %s |\n' "$side" "$sc" "$gkb" "$growth" "$pkb" "$late"
  done
done
echo
echo "$rt_uavs UAVs, $rt_ticks realtime ticks at 20 Hz, $vendor."
