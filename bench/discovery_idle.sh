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
# shellcheck source=lib/host_counters.sh
source "$(dirname "$0")/lib/host_counters.sh"
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
  read -r w c d e < <(window_counters "$window" "${pids[@]}")
  pss=$(pss_of "${pids[@]}")
  kill -TERM "${pids[@]}" 2> /dev/null || true
  wait "${pids[@]}" 2> /dev/null || true
  awk -v v="$vendor" -v n="$n" -v c="$c" -v hz="$hz" -v w="$w" -v d="$d" -v e="$e" -v pss="$pss" \
    'BEGIN {printf "| %s | %d | %.2f | %.0f | %.0f | %s |\n", v, n, c / hz / w, d / w, e / w, pss}'
  sleep 3
done
