#!/usr/bin/env bash
# deploy/container/entrypoint.sh without containers: the programs it starts are
# stand-ins that print their command line, and each case runs in a UTS
# namespace of its own (unshare --uts) with the hostname a pod would have.
#   entrypoint_test.sh SRC OUT        (root, for unshare)
set -euo pipefail
SRC=$1 OUT=$2
ENTRY="$SRC/deploy/container/entrypoint.sh"
fail() { echo "FAIL: $*" >&2; exit 1; }
[ "$(id -u)" = 0 ] || { echo "SKIP: needs root for unshare --uts"; exit 77; }
rm -rf "$OUT"
mkdir -p "$OUT/prefix/bin" "$OUT/prefix/share/pheromesh/scenarios"
for p in pheromesh-place pheromesh-uav pheromesh-ground; do
  cat > "$OUT/prefix/bin/$p" << 'STUB'
#!/usr/bin/env bash
echo "$(basename "$0") $* [profile=${PHEROMESH_DDS_PROFILE:-}] [cell=${PHEROMESH_CELL:-}] [id=${PHEROMESH_PARTICIPANT_ID:-}]"
exit "${STUB_EXIT:-0}"
STUB
  chmod +x "$OUT/prefix/bin/$p"
done
# `pheromesh cell` stands in too: it prints the environment of a cell named
# after its arguments (the real one is unit-tested: NamedCells.*).
cat > "$OUT/prefix/bin/pheromesh" << 'STUB'
#!/usr/bin/env bash
[ "$1" = cell ] || exit 99
if [ -n "${STUB_CELL_EXIT:-}" ]; then echo "pheromesh cell: place-7 did not resolve" >&2; exit "$STUB_CELL_EXIT"; fi
shift
args="$*" names="place-{region}"
echo "PHEROMESH_CELL=stub:${args// /,}:${PHEROMESH_PLACE_NAME:-$names}"
[ "$1" = uav ] && echo "PHEROMESH_PARTICIPANT_ID=1"
exit 0
STUB
chmod +x "$OUT/prefix/bin/pheromesh"
: > "$OUT/prefix/share/pheromesh/scenarios/small-test.textproto"
S="$OUT/prefix/share/pheromesh/scenarios/small-test.textproto"

# run HOSTNAME [VAR=VALUE...] -- ARGS...: the entrypoint's output and exit code.
run() {
  local host=$1
  shift
  local env=()
  while [ "$1" != -- ]; do
    env+=("$1")
    shift
  done
  shift
  unshare --uts env -i PATH="$PATH" PHEROMESH_PREFIX="$OUT/prefix" "${env[@]}" \
    bash -c 'hostname "$0" && exec "$@"' "$host" "$ENTRY" "$@" 2>&1 && echo "rc=0" || echo "rc=$?"
}
expect() {  # WHAT OUTPUT WANTED
  grep -qF -- "$3" <<< "$2" || fail "$1: expected '$3' in: $2"
}

out=$(run place-3 PHEROMESH_SCENARIO=small-test -- place)
expect "region from the StatefulSet pod's hostname" "$out" "pheromesh-place --scenario $S --region 3 [profile=cells]"
expect "cells by default: the cell of place 3 from pheromesh cell" "$out" "[cell=stub:place,3,--scenario,$S:place-{region}]"
out=$(run uav-5 PHEROMESH_SCENARIO=small-test PHEROMESH_PLACE_NAME='place-{region}.swarm' -- uav)
expect "a UAV's cell, the names from the environment, and its Fast DDS id" "$out" \
  "[cell=stub:uav,5,--scenario,$S:place-{region}.swarm] [id=1]"
out=$(run uav-5 PHEROMESH_SCENARIO=small-test PHEROMESH_CELL=peers=10.0.0.1:0 -- uav)
expect "a cell given is kept" "$out" "[cell=peers=10.0.0.1:0]"
out=$(run uav-5 PHEROMESH_SCENARIO=small-test STUB_CELL_EXIT=3 -- uav)
expect "no cell: the process does not start, the reason is shown" "$out" "place-7 did not resolve"
expect "... and named" "$out" "uav: no cell: pheromesh cell failed"
expect "... with exit code 64" "$out" "rc=64"
grep -qF "pheromesh-uav" <<< "$out" && fail "a UAV without a cell started: $out"
out=$(run uav-12 ROLE=uav PHEROMESH_SCENARIO=small-test -- --ticks 50)
expect "role from \$ROLE, id from the hostname, flags passed on" "$out" "pheromesh-uav --scenario $S --id 12 --ticks 50"
out=$(run uav-12 PHEROMESH_UAV_ID=5 PHEROMESH_SCENARIO="$S" -- uav)
expect "\$PHEROMESH_UAV_ID before the hostname" "$out" "--id 5 "
out=$(run uav-007 PHEROMESH_SCENARIO=small-test -- uav)
expect "an ordinal with leading zeros is decimal" "$out" "--id 7 "
out=$(run ground PHEROMESH_SCENARIO=small-test -- uav)
expect "no index anywhere is an error" "$out" "no id: set \$PHEROMESH_UAV_ID"
expect "... with exit code 64" "$out" "rc=64"
out=$(run place-1 -- place)
expect "no scenario is an error that lists the shipped ones" "$out" "one of: small-test"
out=$(run place-1 PHEROMESH_SCENARIO=nope -- place)
expect "an unknown scenario is an error" "$out" "scenario $OUT/prefix/share/pheromesh/scenarios/nope.textproto does not exist"
out=$(run uav-1 PHEROMESH_SCENARIO=small-test PHEROMESH_DDS_PEERS=a,b -- uav)
expect "peers make the default profile lan-unicast" "$out" "[profile=lan-unicast]"
out=$(run uav-1 PHEROMESH_SCENARIO=small-test PHEROMESH_DDS_PROFILE=onehost -- uav)
expect "a profile given is kept" "$out" "[profile=onehost]"
out=$(run ground PHEROMESH_SCENARIO=small-test PHEROMESH_HTTP=8080 PHEROMESH_ARGS="--lease-ms 2000" -- ground --until-done)
expect "ground: out folder, console on every interface, PHEROMESH_ARGS, then the command line" "$out" \
  "pheromesh-ground --scenario $S --out /var/lib/pheromesh/out --http 8080 --http-bind 0.0.0.0 --lease-ms 2000 --until-done"
out=$(run watcher PHEROMESH_OUT=/o PHEROMESH_DDS_PROFILE=lan -- monitor)
expect "monitor: attach, no scenario needed with flat discovery" "$out" "pheromesh-ground --attach --out /o [profile=lan]"
out=$(run watcher PHEROMESH_SCENARIO=small-test -- monitor)
expect "monitor in cells: a member of every hub's cell" "$out" "[profile=cells] [cell=stub:monitor,--scenario,$S:place-{region}]"
out=$(run watcher -- monitor)
expect "monitor in cells: the scenario says how many hubs" "$out" "monitor: no scenario"
out=$(run x -- echo hello)
expect "any other first argument runs as it is" "$out" "hello"
out=$(run x -- bogus-role-name-that-is-no-program)
expect "... and fails as exec does" "$out" "rc=127"

# Peers: wait until the names resolve to enough addresses, at most the timeout.
out=$(run uav-1 PHEROMESH_SCENARIO=small-test PHEROMESH_DDS_PEERS=127.0.0.1,127.0.0.2 PHEROMESH_WAIT_PEERS=2 -- uav)
expect "peers that resolve start at once" "$out" "pheromesh-uav"
t0=$(date +%s)
out=$(run uav-1 PHEROMESH_SCENARIO=small-test PHEROMESH_DDS_PEERS=127.0.0.1 PHEROMESH_WAIT_PEERS=3 PHEROMESH_WAIT_PEERS_S=2 -- uav)
expect "too few peers: a warning after the timeout" "$out" "resolve to 1 of 3 addresses; starting anyway"
expect "... then it starts" "$out" "pheromesh-uav"
[ $(($(date +%s) - t0)) -ge 2 ] || fail "the peer wait ended before its timeout"

# hold: a clean end holds until SIGTERM, which then ends it with 0; a failure
# is passed on at once.
out=$(run uav-2 PHEROMESH_SCENARIO=small-test PHEROMESH_AFTER_EXIT=hold STUB_EXIT=3 -- uav)
expect "hold passes a failure on" "$out" "rc=3"
unshare --uts env -i PATH="$PATH" PHEROMESH_PREFIX="$OUT/prefix" PHEROMESH_SCENARIO=small-test PHEROMESH_AFTER_EXIT=hold \
  bash -c 'hostname uav-2 && exec "$@"' x "$ENTRY" uav > "$OUT/hold.log" 2>&1 &
pid=$!
for _ in $(seq 1 50); do grep -q "holding until stopped" "$OUT/hold.log" && break; sleep 0.1; done
grep -q "holding until stopped" "$OUT/hold.log" || fail "hold: no 'holding' line: $(cat "$OUT/hold.log")"
sleep 0.3
kill -0 "$pid" 2> /dev/null || fail "hold: the entrypoint exited after a clean end"
kill -TERM "$pid"
rc=0
wait "$pid" || rc=$?
[ "$rc" = 0 ] || fail "hold: SIGTERM ended it with $rc, not 0"
echo "entrypoint: all cases pass"
