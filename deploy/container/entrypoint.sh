#!/usr/bin/env bash
# One image, every role (docs/deploy-containers.md). The role is the first
# argument or $ROLE:
#   place    pheromesh-place  --region R   R from $PHEROMESH_REGION, else the hostname's ordinal
#   uav      pheromesh-uav    --id I       I from $PHEROMESH_UAV_ID, else the hostname's ordinal
#   ground   pheromesh-ground              the swarm's ground station, writes $PHEROMESH_OUT/metrics.json
#   monitor  pheromesh-ground --attach     watches a running swarm: in cells it names every
#                                          hub (the scenario gives their number), else it
#                                          needs only the domain
# The hostname's ordinal is the number after its last '-': a Kubernetes
# StatefulSet names its pods place-0, place-1, ... and each pod's hostname is
# its name, so a StatefulSet of place agents owns regions 0..replicas-1.
# Any other first argument is run as it is (`pheromesh validate ...`, `bash`).
#
# Environment (each also has a flag of the same meaning; flags after the role
# are passed on and come last, so they win):
#   PHEROMESH_SCENARIO     scenario file, or the name of a shipped one (small-test);
#                          needed by monitor only in cells
#   PHEROMESH_DDS          cyclone | fastdds                       (read by the processes)
#   PHEROMESH_DOMAIN       DDS domain id                           (read by the processes)
#   PHEROMESH_DDS_PROFILE  DDS profile; default cells, or lan-unicast when
#                          PHEROMESH_DDS_PEERS is set (a container's loopback reaches no
#                          peer, so the processes' own default, onehost, is never right here)
#   PHEROMESH_PLACE_NAME   cells: the name of region {region}'s place agent (default
#                          place-{region}: compose's service names; on Kubernetes the
#                          StatefulSet's pods under its headless Service,
#                          place-{region}.pheromesh-swarm)
#   PHEROMESH_GROUND_NAME  cells: the ground station's name (default ground)
#                          In cells each process names only the hubs it talks to, by
#                          these names (`pheromesh cell`, run here before the process):
#                          every hub takes participant index 0 at its own address
#   PHEROMESH_DDS_PEERS    lan-unicast: peers, host names or addresses (read by the processes)
#   PHEROMESH_CONTROL_KEY  the swarm's shared command key, 64 hex digits (read by the processes)
#   PHEROMESH_OUT          ground, monitor: folder for metrics.json (default /var/lib/pheromesh/out)
#   PHEROMESH_HTTP         ground/monitor: serve the web console on this port, on every interface
#   PHEROMESH_ARGS         more flags, split on spaces, before the command line's
#   PHEROMESH_WAIT_PEERS   lan-unicast: wait (up to PHEROMESH_WAIT_PEERS_S, 120 s) until
#                          the names of PHEROMESH_DDS_PEERS resolve to this many addresses
#                          in all before starting: peers are resolved once, at process
#                          start, and a pod that starts with its neighbours may find none
#                          yet. In cells the names of the hubs are always waited for, up
#                          to PHEROMESH_WAIT_PEERS_S
#   PHEROMESH_AFTER_EXIT   exit (default) | hold: after the process ends with 0, keep the
#                          container running until it is stopped. Under a StatefulSet or
#                          a Deployment (restartPolicy Always) a finished UAV or place
#                          agent would otherwise be started again and fly a second time.
set -euo pipefail

prefix="${PHEROMESH_PREFIX:-/opt/pheromesh}" # another prefix only for tests
die() {
  echo "pheromesh-entrypoint: $*" >&2
  exit 64
}

role="${ROLE:-}"
case "${1:-}" in
  place | uav | ground | monitor)
    role="$1"
    shift
    ;;
  "" | -*) ;;
  *) exec "$@" ;;
esac
[ -n "$role" ] || die "no role: give place, uav, ground or monitor as the first argument or in \$ROLE"

# The number after the last '-' of the hostname (place-3 -> 3), or nothing.
ordinal() {
  local h
  h="$(cat /proc/sys/kernel/hostname)"
  h="${h%%.*}"
  case "${h##*-}" in
    '' | *[!0-9]*) return 1 ;;
    *) echo "$((10#${h##*-}))" ;;
  esac
}

index() {  # VAR WHAT
  local v="${!1:-}"
  if [ -z "$v" ]; then
    v="$(ordinal)" || die "$role: no $2: set \$$1, or run in a container whose hostname ends in -N ($role-3)"
  fi
  case "$v" in '' | *[!0-9]*) die "$role: \$$1 must be a number, not '$v'" ;; esac
  echo "$v"
}

scenario() {
  local s="${PHEROMESH_SCENARIO:-}"
  if [ -z "$s" ]; then
    local names=("$prefix"/share/pheromesh/scenarios/*.textproto)
    names=("${names[@]##*/}")
    die "$role: no scenario: set \$PHEROMESH_SCENARIO to a file or one of: ${names[*]%.textproto}"
  fi
  if [ ! -e "$s" ] && [ "${s#*/}" = "$s" ]; then s="$prefix/share/pheromesh/scenarios/${s%.textproto}.textproto"; fi
  [ -f "$s" ] || die "$role: scenario $s does not exist"
  echo "$s"
}

if [ -z "${PHEROMESH_DDS_PROFILE:-}" ]; then
  if [ -n "${PHEROMESH_DDS_PEERS:-}" ]; then
    export PHEROMESH_DDS_PROFILE=lan-unicast
  else
    export PHEROMESH_DDS_PROFILE=cells
  fi
fi

extra=()
# shellcheck disable=SC2206 # split on purpose: flags without spaces inside
[ -n "${PHEROMESH_ARGS:-}" ] && extra=(${PHEROMESH_ARGS})
http=()
[ -n "${PHEROMESH_HTTP:-}" ] && http=(--http "$PHEROMESH_HTTP" --http-bind 0.0.0.0)

case "$role" in
  place)
    region="$(index PHEROMESH_REGION region)"
    cmd=("$prefix/bin/pheromesh-place" --scenario "$(scenario)" --region "$region")
    ;;
  uav)
    id="$(index PHEROMESH_UAV_ID id)"
    cmd=("$prefix/bin/pheromesh-uav" --scenario "$(scenario)" --id "$id")
    ;;
  ground)
    cmd=("$prefix/bin/pheromesh-ground" --scenario "$(scenario)" --out "${PHEROMESH_OUT:-/var/lib/pheromesh/out}" "${http[@]}")
    ;;
  monitor)
    cmd=("$prefix/bin/pheromesh-ground" --attach --out "${PHEROMESH_OUT:-/var/lib/pheromesh/out}" "${http[@]}")
    ;;
esac
cmd+=("${extra[@]}" "$@")

# Cells: the hubs this process talks to, by name (pheromesh cell prints
# PHEROMESH_CELL and, for a member, its Fast DDS participant id).
if [ "$PHEROMESH_DDS_PROFILE" = cells ] && [ -z "${PHEROMESH_CELL:-}" ]; then
  at=()
  case "$role" in
    place) at=("$region") ;;
    uav) at=("$id") ;;
  esac
  cell_env="$("$prefix/bin/pheromesh" cell "$role" "${at[@]}" --scenario "$(scenario)")" ||
    die "$role: no cell: pheromesh cell failed (above); set PHEROMESH_PLACE_NAME and PHEROMESH_GROUND_NAME to the hubs' names"
  while IFS= read -r line; do
    if [ -n "$line" ]; then export "${line?}"; fi
  done <<< "$cell_env"
fi

# Distinct IPv4 addresses the peer names resolve to now.
peer_addresses() {
  local IFS=, p
  for p in ${PHEROMESH_DDS_PEERS:-}; do getent ahostsv4 "$p" || true; done | awk '{print $1}' | sort -u | wc -l
}
if [ -n "${PHEROMESH_WAIT_PEERS:-}" ]; then
  want="$PHEROMESH_WAIT_PEERS"
  deadline=$(($(date +%s) + ${PHEROMESH_WAIT_PEERS_S:-120}))
  while have="$(peer_addresses)" && [ "$have" -lt "$want" ]; do
    if [ "$(date +%s)" -ge "$deadline" ]; then
      echo "pheromesh-entrypoint: $role: peers '$PHEROMESH_DDS_PEERS' resolve to $have of $want addresses; starting anyway" >&2
      break
    fi
    sleep 1
  done
fi

if [ "${PHEROMESH_AFTER_EXIT:-exit}" != hold ]; then
  exec "${cmd[@]}"
fi
# hold: stay the parent, pass SIGTERM/SIGINT on, and after a clean end sleep
# until stopped.
"${cmd[@]}" &
child=$!
trap 'kill -TERM "$child" 2> /dev/null || true' TERM
trap 'kill -INT "$child" 2> /dev/null || true' INT
while kill -0 "$child" 2> /dev/null; do wait "$child" || true; done
rc=0
wait "$child" || rc=$? # the exit status bash kept when it reaped the child
if [ "$rc" -ne 0 ]; then exit "$rc"; fi
echo "pheromesh-entrypoint: $role finished; holding until stopped (PHEROMESH_AFTER_EXIT=hold)" >&2
trap 'exit 0' TERM INT
while :; do
  sleep 3600 &
  wait $! || true
done
