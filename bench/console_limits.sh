#!/usr/bin/env bash
# The web console under hostile clients, against a real ground station
# (`pheromesh run` of scenarios/small-test.textproto with --http):
#   1. /metrics latency (p50 / p99 / max) with no other client and with
#      SLOW slow or idle connections open, in the same run
#      (pheromesh-bench-console);
#   2. the ground station's resident memory before and after a 1 GiB POST
#      without a token, sent as curl sends it (Expect: 100-continue) and
#      without Expect (the body follows the headers at once).
# BENCH_BIN=DIR takes pheromesh-bench-console from DIR (to measure an older
# build's console with this build's client).
# Starts DDS processes: run it in a network namespace of your own.
# usage: bench/console_limits.sh [BUILD_DIR] [SLOW] [REQUESTS]
set -euo pipefail
BUILD=${1:-build}
SLOW=${2:-50}
REQUESTS=${3:-200}
SRC=$(cd "$(dirname "$0")/.." && pwd)
PORT=${PORT:-18650}
DOMAIN=${DOMAIN:-216}
OUT=$BUILD/bench-out/console-limits
rm -rf "$OUT"
mkdir -p "$OUT"
"$BUILD/bin/pheromesh" run "$SRC/scenarios/small-test.textproto" --duration 120 --domain "$DOMAIN" --http "$PORT" \
  --no-record --out "$OUT/run" > "$OUT/launcher.log" 2>&1 &
LPID=$!
BIG=$(mktemp /tmp/phcon-bench-XXXXXX)
trap 'kill $LPID 2> /dev/null || true; wait 2> /dev/null || true; rm -f "$BIG"' EXIT
for _ in $(seq 1 300); do
  curl -sf "http://127.0.0.1:$PORT/api/info" > /dev/null && break
  sleep 0.2
done
GPID=$(pgrep -f "pheromesh-ground .*--domain $DOMAIN" | head -1)
[ -n "$GPID" ] || { echo "no ground station"; exit 1; }
sleep 3  # the swarm up and frames flowing
"${BENCH_BIN:-$BUILD/bin}/pheromesh-bench-console" --port "$PORT" --slow "$SLOW" --requests "$REQUESTS"

[ "${SKIP_POST:-0}" = 1 ] && exit 0  # SKIP_POST=1: latency only (e.g. against an older build)
rss() { awk '/^VmRSS/ {print $2}' "/proc/$GPID/status"; }
hwm() { awk '/^VmHWM/ {print $2}' "/proc/$GPID/status"; }  # peak RSS
truncate -s 1G "$BIG"  # sparse: no disk, curl streams it
URL="http://127.0.0.1:$PORT/api/command"
r0=$(rss)
h0=$(hwm)
t0=$(date +%s.%N)
code1=$(curl -s -o /dev/null -w '%{http_code}' --max-time 60 -X POST -H 'Content-Type: application/json' -T "$BIG" "$URL" || true)
t1=$(date +%s.%N)
code2=$(curl -s -o /dev/null -w '%{http_code}' --max-time 60 -X POST -H 'Content-Type: application/json' -H 'Expect:' \
  -T "$BIG" "$URL" || true)
t2=$(date +%s.%N)
sleep 1
r1=$(rss)
h1=$(hwm)
printf '1 GiB POST without a token: %s with Expect: 100-continue (%.2f s), %s without (%.2f s)\n' "$code1" \
  "$(awk -v a="$t0" -v b="$t1" 'BEGIN { print b - a }')" "$code2" "$(awk -v a="$t1" -v b="$t2" 'BEGIN { print b - a }')"
printf 'ground station RSS: %d KiB before, %d KiB after (%+d KiB); peak RSS: %d KiB before, %d KiB after (%+d KiB)\n' \
  "$r0" "$r1" $((r1 - r0)) "$h0" "$h1" $((h1 - h0))
curl -s "http://127.0.0.1:$PORT/metrics" | grep -E '^pheromesh_console_(http_refused_total|commands_total)' || true
