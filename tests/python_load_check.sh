#!/usr/bin/env bash
# Python only where the policy is Python (agent/python_sibling.hpp):
# pheromesh-uav links no libpython and a UAV of a C++ policy maps none; a UAV
# of a Python policy runs in pheromesh-uav-python, which it execs (read from
# the loader, LD_DEBUG=files); without that sibling a Python scenario is
# refused with its path, and a C++ one still flies.
#
#   tests/python_load_check.sh BIN_DIR SOURCE_DIR DOMAIN
set -euo pipefail
bin=${1:?BIN_DIR}
src=${2:?SOURCE_DIR}
domain=${3:?DOMAIN}
failed=0
fail() { echo "FAIL $*"; failed=1; }
readelf -d "$bin/pheromesh-uav" | grep -q 'NEEDED.*libpython' && fail "pheromesh-uav links libpython" ||
  echo "ok   pheromesh-uav links no libpython"
readelf -d "$bin/pheromesh-uav-python" | grep -q 'NEEDED.*libpython' && echo "ok   pheromesh-uav-python links it" ||
  fail "pheromesh-uav-python links no libpython"
cpp=$src/scenarios/small-test.textproto
py=$src/tests/data/python/counted-walk.textproto
# One UAV alone for one tick (as `pheromesh bench start` starts one).
fly() { # UAV_PROGRAM SCENARIO
  "$1" --scenario "$2" --id 0 --dds cyclone --domain "$domain" --wait-for-places 0 --wait-for-start 0.1 --ticks 1
}
out=$(LD_DEBUG=files fly "$bin/pheromesh-uav" "$cpp" 2>&1) || fail "a C++ UAV: $(tail -3 <<< "$out")"
grep -qE "file=[^ ]*libpython3" <<< "$out" && fail "a C++ UAV mapped libpython" || echo "ok   a C++ UAV maps no libpython"
out=$(LD_DEBUG=files fly "$bin/pheromesh-uav" "$py" 2>&1) || fail "a Python UAV: $(tail -3 <<< "$out")"
# The loader starts a program twice (the exec keeps argv[0]), the second with libpython.
[ "$(grep -c "initialize program" <<< "$out")" -ge 2 ] && grep -qE "file=[^ ]*libpython3" <<< "$out" &&
  echo "ok   a Python UAV runs in pheromesh-uav-python, with libpython" || fail "a Python UAV did not exec its sibling"
alone=$(mktemp -d)
trap 'rm -rf "$alone"' EXIT
cp "$bin/pheromesh-uav" "$alone/"
if out=$(PHEROMESH_DDS_MODULE_DIR=$(dirname "$bin")/lib/pheromesh fly "$alone/pheromesh-uav" "$py" 2>&1); then
  fail "a Python UAV without its sibling flew"
elif grep -q "runs in $alone/pheromesh-uav-python: No such file or directory" <<< "$out"; then
  echo "ok   without its sibling a Python UAV is refused, naming it"
else
  fail "a Python UAV without its sibling: $(tail -3 <<< "$out")"
fi
PHEROMESH_DDS_MODULE_DIR=$(dirname "$bin")/lib/pheromesh fly "$alone/pheromesh-uav" "$cpp" >/dev/null 2>&1 &&
  echo "ok   a C++ UAV needs no sibling" || fail "a C++ UAV without the sibling"
exit $failed
