#!/usr/bin/env bash
# What one UAV tick sends, by DDS topic and RTPS submessage: a realtime swarm
# on loopback captured whole with tcpdump, then counted by
# bench/lib/rtps_topics.py in a window after discovery (docs/benchmarks.md,
# "Where a UAV tick goes"). Run as root (tcpdump on lo); keep the host idle.
#
#   bench/tick_traffic.sh [UAVS] [TICKS] [SKIP_S] [WINDOW_S] [more pheromesh run arguments]
#   bench/tick_traffic.sh 100 100 8 10
#   BIN=/path/to/other/build/bin bench/tick_traffic.sh 100 100 8 10 --dds fastdds
#   RATE=30 bench/tick_traffic.sh 100 900 10 6 --clock lockstep
# RATE (default 5, the scenario's rate) is the swarm's ticks per second in
# the window, which the counts are divided by: a lockstep swarm's is its
# conductor's pace (`pheromesh bench lockstep`, or the run's ticks over its
# flight); pheromesh_uav_state DATA near 1.00 per UAV tick checks it.
# SKIP_S must leave discovery and the start out (the run prints when
# discovery completed, in seconds after the launch; the capture starts about
# a second before the launch) and SKIP_S + WINDOW_S must end before the last
# tick (TICKS at the scenario's 5 Hz).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
uavs=${1:-100}
ticks=${2:-100}
skip=${3:-8}
window=${4:-10}
shift $(($# < 4 ? $# : 4))
bin=${BIN:-$root/build/bin}
rate=${RATE:-5}
command -v tcpdump >/dev/null || { echo "tick_traffic: needs tcpdump (apt-get install tcpdump)" >&2; exit 2; }
out=$(mktemp -d /tmp/pheromesh-tick-traffic.XXXXXX)
trap 'rm -rf "$out"' EXIT
tcpdump -i lo -s 0 -B 262144 -U -w "$out/run.pcap" udp 2>"$out/tcpdump.txt" &
dump=$!
sleep 1
"$bin/pheromesh" run "$root/scenarios/scale-100x100.textproto" --uavs "$uavs" --ticks "$ticks" --out "$out/run" "$@" \
  2>&1 | grep -E "discovery complete|done:" || true
kill -INT "$dump"
wait "$dump" || true
grep -E "captured|dropped by kernel" "$out/tcpdump.txt" || true
python3 "$root/bench/lib/rtps_topics.py" "$out/run.pcap" "$skip" "$window" "$uavs" "$rate"
