#!/usr/bin/env bash
# check_metrics.py passes a balanced, finished swarm and fails each way a
# swarm can fall short (the guard that the container tests' check can fail).
#   check_metrics_test.sh SRC OUT
set -euo pipefail
SRC=$1 OUT=$2
CHECK="$SRC/tests/container/check_metrics.py"
fail() { echo "FAIL: $*" >&2; exit 1; }
mkdir -p "$OUT"
good='{"uavs": 2, "place_agents": 1, "place_agents_finished": 1, "coverage": 0.5, "processes_crashed": 0,
  "deposits_sent": 10, "deposits_applied": 9, "deposits_rejected": 1, "deposits_lost": 0,
  "uav_status": {"0": {"finished": true}, "1": {"finished": true}}}'
echo "$good" > "$OUT/good.json"
python3 "$CHECK" "$OUT/good.json" 2 1 || fail "a good swarm was refused"
# Each variant breaks one thing; each must be refused, naming it.
while IFS='|' read -r what patch expect; do
  python3 -c "import json,sys; m=json.load(open(sys.argv[1])); m.update(json.loads(sys.argv[2])); json.dump(m, open(sys.argv[3],'w'))" \
    "$OUT/good.json" "$patch" "$OUT/bad.json"
  if msg=$(python3 "$CHECK" "$OUT/bad.json" 2 1 2>&1); then fail "$what: accepted"; fi
  grep -qF "$expect" <<< "$msg" || fail "$what: refused without saying '$expect': $msg"
done << 'CASES'
a UAV that did not finish|{"uav_status": {"0": {"finished": true}, "1": {"finished": false}}}|UAVs that finished: [0]
a UAV missing|{"uav_status": {"0": {"finished": true}}}|UAVs that finished: [0]
a place agent that did not finish|{"place_agents_finished": 0}|place agents 1, finished 0
unbalanced deposits|{"deposits_applied": 8}|deposits_sent 10 != applied 8
lost deposits|{"deposits_applied": 8, "deposits_lost": 1}|deposits_lost 1, expected 0
no coverage|{"coverage": 0}|coverage 0
no deposits|{"deposits_sent": 0, "deposits_applied": 0, "deposits_rejected": 0}|deposited nothing
a crash|{"processes_crashed": 1}|processes_crashed 1
CASES
echo "check_metrics: every case refused as it should be"
