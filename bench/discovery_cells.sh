#!/usr/bin/env bash
# Discovery scoped to cells (issue 25), measured before it goes into the
# swarm: CELLS hubs (a cell's gateway place agent, pheromesh-test-probe hub)
# and N spokes (a UAV's endpoints, pheromesh-test-probe spoke) split over
# them. Every process announces itself by unicast only: a spoke to its hub's
# well-known port, a hub to nobody (it answers the spokes that announce
# themselves). So a spoke learns its hub alone and a hub its spokes alone,
# instead of every process learning every other one (bench/discovery_idle.sh,
# the flat swarm). For each N it prints one row: the time until every spoke
# has matched its hub and every hub all its spokes, then, over a window, the
# CPU of all the processes (cores), the UDP datagrams the host receives per
# second, the receive-buffer drops per second and the mean PSS of a spoke and
# of a hub; the 1-minute load average before the start (another user of the
# host shows there).
#
#   bench/discovery_cells.sh BUILD VENDOR "SIZES" CELLS [WINDOW_S]
#   bench/discovery_cells.sh build cyclone "100 250 500" 16
#   MODE=shared bench/discovery_cells.sh build fastdds:cyclone "100" 16
# VENDOR: cyclone, fastdds, or HUB:SPOKE (fastdds:cyclone = Fast DDS hubs,
# Cyclone spokes).
# Environment:
#   MODE      domain (default): one DDS domain per cell, DOMAIN + c, the hub
#             participant index 0 there, Fast DDS spokes ids 1..; shared: all
#             cells in domain DOMAIN, hub c at index c, Fast DDS spokes ids
#             CELLS.. (docs/dds.md, "Cell discovery (measured)": the ports).
#   DOMAIN    the (first) domain id, default 20.
#   TIMEOUT_S bound on the wait for discovery, default 180.
#   SETTLE_S  after discovery, before the window, default 5.
#   START_RATE spokes started per second (default 0: all at once).
#   VIEW_WRITERS per-uav (default: a view writer per UAV, as a place agent
#             has), or none (an experiment: without them).
#   NETNS      1: in a network namespace of its own (see below).
#   KEEP      1: keep the processes' output (the directory is named on
#             stderr) to see which hub or spoke did not match.
# Traffic stays on loopback. Every process it started is stopped at the end,
# also on an error or an interrupt.
set -euo pipefail
# NETNS=1: run in a network namespace of its own (root), whose loopback
# carries only this benchmark's traffic, so that the datagram and drop
# counters (per namespace) are ours alone on a shared host.
if [[ ${NETNS:-0} == 1 && -z ${DISCOVERY_CELLS_NETNS:-} ]]; then
  exec unshare -n env DISCOVERY_CELLS_NETNS=1 bash -c 'ip link set lo up && exec "$0" "$@"' "$0" "$@"
fi
build=${1:?usage: discovery_cells.sh BUILD VENDOR "SIZES" CELLS [WINDOW_S]}
vendor=${2:?usage: discovery_cells.sh BUILD VENDOR "SIZES" CELLS [WINDOW_S]}
sizes=${3:?usage: discovery_cells.sh BUILD VENDOR "SIZES" CELLS [WINDOW_S]}
cells=${4:?usage: discovery_cells.sh BUILD VENDOR "SIZES" CELLS [WINDOW_S]}
window=${5:-20}
mode=${MODE:-domain}
base=${DOMAIN:-20}
timeout_s=${TIMEOUT_S:-180}
settle=${SETTLE_S:-5}
rate=${START_RATE:-0}
probe="$build/bin/pheromesh-test-probe"
hub_vendor=${vendor%%:*}
spoke_vendor=${vendor##*:}
case "$mode" in domain | shared) ;; *) echo "MODE must be domain or shared" >&2; exit 2 ;; esac
[[ -x "$probe" ]] || { echo "no $probe (build the target pheromesh-test-probe)" >&2; exit 2; }
hz=$(getconf CLK_TCK)
out=$(mktemp -d "${TMPDIR:-/tmp}/discovery_cells.XXXXXX")
pids=()
stop_all() {
  ((${#pids[@]})) || return 0
  kill -TERM "${pids[@]}" 2> /dev/null || true
  # Bounded: whatever has not ended after 10 s is killed.
  for _ in $(seq 1 20); do
    local alive=0
    for p in "${pids[@]}"; do kill -0 "$p" 2> /dev/null && alive=1 && break; done
    ((alive)) || break
    sleep 0.5
  done
  kill -KILL "${pids[@]}" 2> /dev/null || true
  wait "${pids[@]}" 2> /dev/null || true
  pids=()
}
trap 'stop_all; if [[ ${KEEP:-0} == 1 ]]; then echo "output kept in $out" >&2; else rm -rf "$out"; fi' EXIT
trap 'exit 130' INT TERM
# shellcheck source=lib/host_counters.sh
source "$(dirname "$0")/lib/host_counters.sh"
printf '| hub:spoke | mode | cells | N | load before / after | discovered [s] | spokes matched | hubs matched | CPU [cores] | UDP datagrams/s | rcvbuf drops/s | PSS/spoke [MiB] | PSS/hub [MiB] |\n'
printf '|---|---|---|---|---|---|---|---|---|---|---|---|---|\n'
for n in $sizes; do
  mkdir -p "$out/$n"
  load=$(load1)
  hub_pids=()
  spoke_pids=()
  t0=$(now)
  # Hubs first: a Cyclone spoke announces itself a few times at its start
  # and then only every 30 s (Cyclone's SPDP interval), so a hub that starts
  # later waits for that.
  first=0
  for ((c = 0; c < cells; c++)); do
    k=$((n / cells + (c < n % cells ? 1 : 0)))
    if [[ $mode == domain ]]; then dom=$((base + c)) index=0; else dom=$base index=$c; fi
    "$probe" --dds "$hub_vendor" --domain "$dom" --cell-index "$index" \
      hub --cell "$c" --spokes "$k" --first-uav "$first" --view-writers "${VIEW_WRITERS:-per-uav}" > "$out/$n/h$c.out" 2> "$out/$n/h$c.err" &
    pids+=($!)
    hub_pids+=($!)
    first=$((first + k))
  done
  first=0
  for ((c = 0; c < cells; c++)); do
    k=$((n / cells + (c < n % cells ? 1 : 0)))
    if [[ $mode == domain ]]; then dom=$((base + c)) index=0; else dom=$base index=$c; fi
    for ((j = 0; j < k; j++)); do
      u=$((first + j))
      # A Fast DDS spoke binds ports by participant id: give it one past the
      # hubs', as pheromesh run does, so that it never takes a hub's port.
      if [[ $mode == domain ]]; then pid_arg=$((1 + j)); else pid_arg=$((cells + u)); fi
      "$probe" --dds "$spoke_vendor" --domain "$dom" --cell-peer "$index" --participant-id "$pid_arg" \
        spoke --id "$u" --cell "$c" > "$out/$n/s$u.out" 2> "$out/$n/s$u.err" &
      pids+=($!)
      spoke_pids+=($!)
      if ((rate > 0 && (u + 1) % rate == 0)); then sleep 1; fi
    done
    first=$((first + k))
  done
  # Bounded wait until every spoke and every hub reported its match (or a
  # process died: its file then never says so, and the bound ends the wait).
  deadline=$(($(date +%s) + timeout_s))
  spokes_ok=0 hubs_ok=0
  while (($(date +%s) < deadline)); do
    spokes_ok=$(cat "$out/$n"/s*.out 2> /dev/null | grep -c '^spoke .* matched hub' || true)
    hubs_ok=$(cat "$out/$n"/h*.out 2> /dev/null | grep -c '^hub .* matched' || true)
    ((spokes_ok == n && hubs_ok == cells)) && break
    sleep 0.5
  done
  # The last match as the processes stamped it (epoch seconds), not when
  # this loop noticed it.
  last=$(cat "$out/$n"/*.out 2> /dev/null | awk '/matched/ {for (i = 1; i < NF; i++) if ($i == "at") t = $(i + 1); if (t > m) m = t} END {printf "%.3f", m}')
  if ((spokes_ok == n && hubs_ok == cells)); then
    disc=$(awk -v a="$t0" -v b="$last" 'BEGIN {printf "%.1f", b - a}')
  else
    disc="> $timeout_s"
  fi
  sleep "$settle"
  read -r w c d e < <(window_counters "$window" "${pids[@]}")
  load="$load / $(load1)"
  pss_s=$(pss_of "${spoke_pids[@]}")
  pss_h=$(pss_of "${hub_pids[@]}")
  errors=$(cat "$out/$n"/*.err 2> /dev/null | grep -v '^\s*$' | sort | uniq -c | sort -rn | head -3 || true)
  stop_all
  awk -v v="$vendor" -v m="$mode" -v cl="$cells" -v n="$n" -v l="$load" -v disc="$disc" -v so="$spokes_ok" -v ho="$hubs_ok" \
    -v c="$c" -v hz="$hz" -v w="$w" -v d="$d" -v e="$e" -v ps="$pss_s" -v ph="$pss_h" \
    'BEGIN {printf "| %s | %s | %d | %d | %s | %s | %d/%d | %d/%d | %.2f | %.0f | %.0f | %s | %s |\n",
            v, m, cl, n, l, disc, so, n, ho, cl, c / hz / w, d / w, e / w, ps, ph}'
  # Messages of processes that failed (to stderr, not into the table).
  [[ -z "$errors" ]] || printf '  N=%d, most frequent stderr lines:\n%s\n' "$n" "$errors" >&2
  sleep 3
done
