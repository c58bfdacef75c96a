#!/usr/bin/env bash
# One swarm in cells on one "host" and split over H "hosts" (network
# namespaces joined by a bridge, as tests/integration/test_lan.cpp makes
# them), on the same cores, side by side: does a host's cost grow with the
# number of hosts? Each host runs `pheromesh run --hosts H --host-index I
# --dds-peers A,B,...` (no profile flag: cells), a monitor in one more
# namespace runs `pheromesh attach --dds-peers A,B,...` (one host: a plain
# `pheromesh run` and a monitor beside it on its loopback).
#
#   bench/hosts_cells.sh BUILD SCENARIO UAVS "HOSTS..." [VENDOR] [TICKS] [DOMAIN] [OUT]
#   bench/hosts_cells.sh build scenarios/scale-100x100.textproto 300 "1 3" cyclone 100
#
# Prints one row per host count: discovery (launch -> the ground station
# heard every process), late UAV ticks, UAV ticks flown, the swarm's CPU per
# UAV tick (every host's processes), UDP datagrams received per UAV tick in
# the busiest namespace, and how many UAVs the monitor heard. Needs root.
# Every namespace is removed at the end; traffic stays on the bridge.
set -euo pipefail
BUILD=${1:?build dir}
SCENARIO=${2:?scenario}
UAVS=${3:?uavs}
HOSTS_LIST=${4:?"host counts, e.g. \"1 3 4\""}
VENDOR=${5:-cyclone}
TICKS=${6:-100}
DOMAIN=${7:-33}
OUT=${8:-out/bench-hosts-cells}
BIN=$(cd "$BUILD/bin" && pwd)
PFX=phbh
[ "$(id -u)" = 0 ] || { echo "bench/hosts_cells.sh: network namespaces need root" >&2; exit 2; }

address() { echo "10.79.0.$(($1 + 1))"; }
teardown() {
  local i
  for i in $(seq 0 8); do ip netns del "$PFX-h$i" 2> /dev/null || true; done
  ip netns del "$PFX-sw" 2> /dev/null || true
}
trap teardown EXIT

# Namespaces 0..n-1 (hosts) and n (the monitor) on one bridge.
make_net() {
  local n=$1 i
  teardown
  ip netns add "$PFX-sw"
  ip -n "$PFX-sw" link add br0 type bridge mcast_snooping 0
  ip -n "$PFX-sw" link set br0 up
  for i in $(seq 0 "$n"); do
    ip netns add "$PFX-h$i"
    ip -n "$PFX-sw" link add "p$i" type veth peer name eth0 netns "$PFX-h$i"
    ip -n "$PFX-sw" link set "p$i" master br0 up
    ip -n "$PFX-h$i" addr add "$(address "$i")/24" dev eth0
    ip -n "$PFX-h$i" link set eth0 up
    ip -n "$PFX-h$i" link set lo up
    ip -n "$PFX-h$i" route add default dev eth0
  done
}

KEY=$("$BIN/pheromesh" key)
mkdir -p "$OUT"
printf '| hosts | UAVs | vendor | exit codes | discovery s | late %% | ticks flown %% | swarm CPU ms/UAV tick | UDP in/UAV tick (busiest host) | UAVs the monitor heard |\n'
printf '|--:|--:|---|---|--:|--:|--:|--:|--:|--:|\n'
for H in $HOSTS_LIST; do
  make_net "$H"
  peers=""
  for i in $(seq 0 $((H - 1))); do peers="$peers${peers:+,}$(address "$i")"; done
  run_out="$OUT/h$H"
  rm -rf "$run_out"
  mkdir -p "$run_out"
  pids=()
  for i in $(seq 0 $((H - 1))); do
    multi=()
    [ "$H" -gt 1 ] && multi=(--hosts "$H" --host-index "$i" --dds-peers "$peers")
    ip netns exec "$PFX-h$i" env PHEROMESH_CONTROL_KEY="$KEY" "$BIN/pheromesh" run "$SCENARIO" --uavs "$UAVS" \
      --ticks "$TICKS" --dds "$VENDOR" --domain "$DOMAIN" --out "$run_out/host$i" --progress 5 "${multi[@]}" \
      > "$run_out/host$i.txt" 2>&1 &
    pids+=($!)
  done
  # The monitor joins once the ground station started the flight.
  for _ in $(seq 1 600); do
    grep -q "sent to the swarm" "$run_out/host0.txt" 2> /dev/null && break
    sleep 0.5
  done
  # One host's swarm is on that host's loopback: its monitor runs there too.
  if [ "$H" -gt 1 ]; then
    mon_ns="$PFX-h$H" mon_peers=(--dds-peers "$peers")
  else
    mon_ns="$PFX-h0" mon_peers=()
  fi
  ip netns exec "$mon_ns" "$BIN/pheromesh" attach --domain "$DOMAIN" --dds "$VENDOR" "${mon_peers[@]}" \
    --out "$run_out/monitor" --timeout 120 --progress 5 > "$run_out/monitor.txt" 2>&1 &
  monitor=$!
  codes=""
  for p in "${pids[@]}"; do
    c=0
    wait "$p" || c=$?
    codes="$codes${codes:+,}$c"
  done
  wait "$monitor" || true
  python3 - "$run_out" "$H" "$UAVS" "$VENDOR" "$TICKS" "$codes" << 'PY'
import json, os, sys
out, hosts, uavs, vendor, ticks, codes = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4], int(sys.argv[5]), sys.argv[6]
def load(p):
    try:
        return json.load(open(p))
    except Exception:
        return {}
m = load(f"{out}/host0/metrics.json")
hosts_json = [m] + [load(f"{out}/host{i}/host-{i}.json") for i in range(1, hosts)]
def get(d, path):
    for k in path.split("."):
        if not isinstance(d, dict) or k not in d:
            return None
        d = d[k]
    return d
flown = m.get("uav_ticks_flown")
cpu = 0.0
for h in hosts_json:
    for role in ("uav", "place", "ground"):
        for part in ("cpu_user_s", "cpu_sys_s"):
            cpu += get(h, f"resources.{role}.{part}") or 0.0
udp = [h.get("udp_in_datagrams") for h in hosts_json if h.get("udp_in_datagrams") is not None]
mon = load(f"{out}/monitor/metrics.json")
def f(v, p):
    return "n/a" if v is None else f"{v:.{p}f}"
late = m.get("uav_late_share")
print(f"| {hosts} | {uavs} | {vendor} | {codes} | {f(m.get('discovery_s'), 1)} | {f(None if late is None else 100 * late, 2)} | "
      f"{f(None if flown is None else 100.0 * flown / (uavs * ticks), 1)} | {f(1000 * cpu / flown if flown else None, 2)} | "
      f"{f(max(udp) / flown if udp and flown else None, 1)} | {mon.get('uavs', 'n/a')} |")
PY
done
echo "-> $OUT (each host's log and metrics; host0/metrics.json is the swarm's)"
