#!/usr/bin/env bash
# How long N processes on this host take to discover each other with the
# one-host profile, per vendor, with the reliable-writer heartbeat pheromesh
# gives a swarm of that size and with Cyclone's default (100 ms), measured in
# the same run (docs/dds.md, "One host, 100+ processes"). Each process is a
# pheromesh-test-probe `discover`: it publishes one transient-local health
# record and reports the time until it has read one from every other process
# (as the integration test Vendors.TheOneHostProfile... does). Every probe
# gives up after TIMEOUT_S (default 150 s) and prints how many it had heard.
#
#   bench/discovery_profile.sh BUILD [VENDORS] [SIZES] [HEARTBEATS]
#   bench/discovery_profile.sh build "cyclone mixed" "60 105" "sized default"
# HEARTBEATS: "sized" (--swarm-processes N, as `pheromesh run` sets it: 1 s
# above 40 processes) and/or "default" (--swarm-processes 0: Cyclone's
# 100 ms). Environment: DOMAIN (default 96), PROFILE (default onehost).
# Keep the host otherwise idle; one run at a time.
set -euo pipefail
build=${1:?usage: discovery_profile.sh BUILD [VENDORS] [SIZES] [HEARTBEATS]}
vendors=${2:-"cyclone fastdds mixed"}
sizes=${3:-"60 105"}
heartbeats=${4:-"sized default"}
domain=${DOMAIN:-96}
profile=${PROFILE:-onehost}
timeout_s=${TIMEOUT_S:-150}
probe="$build/bin/pheromesh-test-probe"
# shellcheck source=lib/discover_probes.sh
source "$(dirname "$0")/lib/discover_probes.sh"
[[ -x $probe ]] || { echo "discovery_profile.sh: no $probe (build the tree first)" >&2; exit 2; }
work=$(mktemp -d /tmp/phm-discovery.XXXXXX)
trap 'rm -rf "$work"' EXIT

# run VENDOR N HEARTBEAT: prints one result line
run() {
  local vendor=$1 n=$2 hb=$3 out="$work/$1-$2-$3" pids=() swarm
  mkdir -p "$out"
  swarm=$n
  [[ $hb == default ]] && swarm=0
  for ((i = 0; i < n; i++)); do
    "$probe" --dds "$vendor" --domain "$domain" --dds-profile "$profile" --swarm-processes "$swarm" \
      discover --id "$i" --expect "$n" --timeout "$timeout_s" > "$out/$i.txt" 2> /dev/null &
    pids+=($!)
  done
  probes_stop "$out" "$n" "$timeout_s" "${pids[@]}"
  local found median max heard
  read -r found median max < <(probes_times "$out")
  # Of the probes that timed out: the fewest and the most processes heard.
  heard=$(cat "$out"/*.txt | awk '/^timeout: discovered/ {v = $3; if (min == "" || v < min) min = v; if (v > mx) mx = v}
                                  END {print min == "" ? "" : "timed out hearing " min "-" mx}')
  printf "%-8s %4d heartbeat %-8s all found by %4d/%-4d  median %6s s  max %6s s  %s\n" "$vendor" "$n" "$hb" \
    "$found" "$n" "$median" "$max" "$heard"
  domain=$((domain + 1))
}

echo "vendor      N (time until a probe has read every other one's record; timeout ${timeout_s} s)"
for vendor in $vendors; do
  for n in $sizes; do
    for hb in $heartbeats; do run "$vendor" "$n" "$hb"; done
  done
done
