#!/usr/bin/env bash
# Discovery (and, with security, the PKI-DH handshakes) time of N processes
# with DDS Security off and on, per vendor, measured in the same run
# (docs/security.md). Each process is a pheromesh-test-probe `discover`: it
# publishes one transient-local health record and reports the time until it
# has read one from every other process (as the integration tests'
# discover_all). Secure probes use identities probe-0.. of a directory made
# here by `pheromesh security init --probes N`. Every probe gives up after
# TIMEOUT_S (default 120 s) and prints how many it had found.
#
#   bench/discovery_secure.sh BUILD [VENDORS] [SIZES]
#   bench/discovery_secure.sh build "cyclone fastdds" "20 100"
# Environment: MODES (default "open secure"), PROFILE (the probes' DDS
# profile, default onehost: multicast discovery), DOMAIN (default 95), PROTECTION (encrypt), STAGGER_S (seconds
# between starting two probes; default 0: all at once), STOP_AFTER_S (SIGTERM
# every probe this long after the last one started, found or not: stopping
# probes mid-handshake; each line says how they ended, a crash being a code
# above 128).
# Run it inside a network namespace of its own (tools: in-netns.sh).
set -euo pipefail
build=${1:?usage: discovery_secure.sh BUILD [VENDORS] [SIZES]}
vendors=${2:-"cyclone fastdds"}
sizes=${3:-"20 100"}
domain=${DOMAIN:-95}
timeout_s=${TIMEOUT_S:-120}
stagger=${STAGGER_S:-0}
probe="$build/bin/pheromesh-test-probe"
# shellcheck source=lib/discover_probes.sh
source "$(dirname "$0")/lib/discover_probes.sh"
max=0
for n in $sizes; do ((n > max)) && max=$n; done
work=$(mktemp -d /tmp/phsec-discovery.XXXXXX)
trap 'rm -rf "$work"' EXIT
"$build/bin/pheromesh" security init "$work/sec" --uavs 1 --regions 1 --probes "$max" \
  --protection "${PROTECTION:-encrypt}" > /dev/null

# run VENDOR N MODE(open|secure): prints one result line
run() {
  local vendor=$1 n=$2 mode=$3 out="$work/$1-$2-$3" pids=()
  mkdir -p "$out"
  for ((i = 0; i < n; i++)); do
    local sec=()
    [[ $mode == secure ]] && sec=(--secure "$work/sec" --identity "probe-$i")
    "$probe" --dds "$vendor" --domain "$domain" --dds-profile "${PROFILE:-onehost}" "${sec[@]}" discover --id "$i" --expect "$n" --timeout "$timeout_s" \
      > "$out/$i.txt" 2> /dev/null &
    pids+=($!)
    [[ $stagger != 0 ]] && sleep "$stagger"
  done
  probes_stop "$out" "$n" "$timeout_s" "${pids[@]}"
  local found median max crashed codes
  read -r found median max < <(probes_times "$out")
  read -r _ crashed codes < <(probes_ends "$out")
  printf "%-8s %4d %-7s all found by %4d/%-4d  median %6s s  max %6s s  stopped: %d crashed (exit codes %s)\n" \
    "$vendor" "$n" "$mode" "$found" "$n" "$median" "$max" "$crashed" "$codes"
}
echo "vendor      N mode    (time until a process has read every other one's record)"
for vendor in $vendors; do
  for n in $sizes; do
    for mode in ${MODES:-open secure}; do run "$vendor" "$n" "$mode"; done
  done
done
