#!/usr/bin/env bash
# What DDS discovery alone costs on this host: P processes that each create
# exactly a UAV's endpoints (pheromesh-test-probe idle) and publish nothing.
# For each P, after a settling time, it measures over a window the CPU the P
# processes use (cores), the UDP datagrams the host receives per second, the
# receive-buffer drops per second and the mean PSS per process. If idle
# participants alone saturate the host at some P, a swarm of P UAVs cannot
# keep time there whatever pheromesh does: the limit is the vendor's
# discovery (SPDP/SEDP and its reliability traffic), not our code.
#
#   bench/discovery_idle.sh BUILD [VENDOR] [SIZES] [WINDOW_S]
#   bench/discovery_idle.sh build cyclone "50 100 150 200" 20
# Environment: SETTLE_S (default 20) before the window; EXTRA_ENV, e.g.
# EXTRA_ENV="ROS_DISCOVERY_SERVER=127.0.0.1:11811" with a Fast DDS discovery
# server running.
set -euo pipefail
build=${1:?usage: discovery_idle.sh BUILD [VENDOR] [SIZES] [WINDOW_S]}
vendor=${2:-cyclone}
sizes=${3:-"50 100 150 200"}
window=${4:-20}
settle=${SETTLE_S:-20}
probe="$build/bin/pheromesh-test-probe"
domain=${DOMAIN:-60}
hz=$(getconf CLK_TCK)
udp() { awk '/^Udp:/ && $2 ~ /^[0-9]+$/ {print $2, $6}' /proc/net/snmp; }
cpu_of() {  # summed utime+stime [ticks] of the given pids, read in one pass
  local files=()
  for p in "$@"; do files+=("/proc/$p/stat"); done
  awk '{s += $14 + $15} END {print s + 0}' "${files[@]}" 2> /dev/null
}
now() { date +%s.%N; }
printf '| vendor | P | CPU [cores] | UDP datagrams/s | rcvbuf drops/s | PSS/process [MiB] |\n|---|---|---|---|---|---|\n'
for n in $sizes; do
  pids=()
  for ((i = 0; i < n; i++)); do
    env ${EXTRA_ENV:-} "$probe" --dds "$vendor" --domain "$domain" idle --id "$i" > /dev/null 2>&1 &
    pids+=($!)
  done
  sleep "$settle"
  # The window is what elapsed between the two readings (a loaded host is
  # slow to take them), not the nominal one.
  t0=$(now)
  read -r in0 drop0 < <(udp)
  c0=$(cpu_of "${pids[@]}")
  sleep "$window"
  read -r in1 drop1 < <(udp)
  c1=$(cpu_of "${pids[@]}")
  t1=$(now)
  pss=$(for p in "${pids[@]}"; do awk '/^Pss:/ {print $2}' /proc/$p/smaps_rollup 2>/dev/null; done |
        awk '{s += $1; n++} END {if (n) printf "%.1f", s / n / 1024; else print "n/a"}')
  kill -TERM "${pids[@]}" 2> /dev/null || true
  wait "${pids[@]}" 2> /dev/null || true
  awk -v v="$vendor" -v n="$n" -v c=$((c1 - c0)) -v hz="$hz" -v w="$(awk -v a="$t0" -v b="$t1" 'BEGIN {print b - a}')" -v d=$((in1 - in0)) -v e=$((drop1 - drop0)) -v pss="$pss" \
    'BEGIN {printf "| %s | %d | %.2f | %.0f | %.0f | %s |\n", v, n, c / hz / w, d / w, e / w, pss}'
  sleep 3
done
