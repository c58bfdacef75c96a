#!/usr/bin/env bash
# Web console under load: a 100x100 Shao 2020 map (16 place agents) with
# 50 UAV processes. Prints what a browser receives (updates/s, bytes/s on
# the wire and before compression) and the ground station's CPU with no
# browser attached (baseline) and with one attached, in the same run.
# usage: bench/console_bench.sh [BUILD_DIR] [UAVS] [SECONDS]
# NICE_SWARM=N (default 0) runs the swarm at nice N and the ground station
# back at 0: on a 2-core host 66 swarm processes saturate both cores, and
# this shows the console when the swarm does not starve it (as when the
# UAVs run on their own hosts).
set -euo pipefail
BUILD=${1:-build}
UAVS=${2:-50}
SECONDS_MEASURED=${3:-30}
SRC=$(cd "$(dirname "$0")/.." && pwd)
PORT=18531
DOMAIN=71
OUT=$BUILD/bench-out/console
rm -rf "$OUT"
mkdir -p "$OUT"
NICE_SWARM=${NICE_SWARM:-0}
nice -n "$NICE_SWARM" "$BUILD/bin/pheromesh" run "$SRC/scenarios/shao2020-100x100.textproto" --uavs "$UAVS" --rate 10 \
  --duration $((SECONDS_MEASURED * 2 + 90)) --domain "$DOMAIN" --http "$PORT" --no-record --out "$OUT/run" \
  > "$OUT/launcher.log" 2>&1 &
LPID=$!
trap 'kill $LPID 2> /dev/null || true; wait 2> /dev/null || true' EXIT
URL=
for _ in $(seq 1 300); do
  URL=$(grep -o "http://127.0.0.1:$PORT/?token=[0-9a-f]*" "$OUT/launcher.log" | head -1 || true)
  [ -n "$URL" ] && curl -sf "http://127.0.0.1:$PORT/api/info" > /dev/null && break
  sleep 0.2
done
GPID=$(pgrep -f "pheromesh-ground .*--domain $DOMAIN" | head -1)
[ -n "$GPID" ] || { echo "no ground station"; exit 1; }
# Wait for the swarm: every UAV alive in the console.
for _ in $(seq 1 600); do
  n=$( (curl -sf "http://127.0.0.1:$PORT/api/frame" || true) |
    node -e "let s='';process.stdin.on('data',d=>s+=d).on('end',()=>console.log(JSON.parse(s).uavs.filter(u=>u.liveness==='alive').length))" 2> /dev/null || echo 0)
  [ "$n" -ge "$UAVS" ] && break
  sleep 0.5
done
echo "swarm up: $n of $UAVS UAVs alive; ground station pid $GPID; swarm at nice $NICE_SWARM"
[ "$NICE_SWARM" != 0 ] && renice -n 0 -p "$GPID" > /dev/null
cpu() { awk '{print $14 + $15}' "/proc/$GPID/stat"; }
HZ=$(getconf CLK_TCK)
c0=$(cpu); t0=$(date +%s.%N)
sleep "$SECONDS_MEASURED"
c1=$(cpu); t1=$(date +%s.%N)
pct() { awk -v c="$1" -v hz="$HZ" -v t="$2" 'BEGIN { printf "%.2f", c / hz / t * 100 }'; }
base=$(pct $((c1 - c0)) "$(awk -v a="$t0" -v b="$t1" 'BEGIN { print b - a }')")
node "$BUILD/web/e2e/console_measure.mjs" --url "$URL" --seconds "$SECONDS_MEASURED" > "$OUT/browser.json" &
MPID=$!
sleep 5  # page loaded and attached
c2=$(cpu); t2=$(date +%s.%N)
wait "$MPID"
c3=$(cpu); t3=$(date +%s.%N)
with=$(pct $((c3 - c2)) "$(awk -v a="$t2" -v b="$t3" 'BEGIN { print b - a }')")
# Wire size: the same long-poll answers with and without compression.
v=0 wire=0 plain=0
for _ in $(seq 1 20); do
  read -r size v < <(curl -s --compressed -w '%{size_download} ' "http://127.0.0.1:$PORT/api/frame?since=$v&wait=1&layer=2" -o "$OUT/answer.json"; grep -o '"version":[0-9]*' "$OUT/answer.json" | cut -d: -f2)
  wire=$((wire + size)); plain=$((plain + $(stat -c %s "$OUT/answer.json")))
done
printf 'console bench: %s UAVs, 100x100 map, 16 place agents, console 5 Hz\n' "$UAVS"
printf '  browser: %s\n' "$(cat "$OUT/browser.json")"
printf '  20 long-poll answers (path layer): %d bytes on the wire, %d decompressed (%.1f x smaller)\n' "$wire" "$plain" \
  "$(awk -v a="$plain" -v b="$wire" 'BEGIN { print a / b }')"
printf '  ground station CPU: %.1f %% of a core without a browser, %.1f %% with one (ratio %.2f)\n' \
  "$base" "$with" "$(awk -v a="$with" -v b="$base" 'BEGIN { print a / (b + 0.0001) }')"
