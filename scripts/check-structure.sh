#!/usr/bin/env bash
# The module map of docs/architecture.md, checked on the #include lines:
#   - a paper's room (common/core/papers/<paper>) includes the shared core
#     and its own room only;
#   - the shared core includes no room (the policy table,
#     src/policy_table.cpp, names each room's entry without including it),
#     and nothing of the bus, the runtime, auth or the console;
#   - auth, bus and runtime include nothing of the console;
#   - the MAVLink library (common/mavlink) includes only itself, and the
#     core nothing of it;
#   - the UAV and place agent shells include no room and nothing of the console;
#   - the ground station includes no room;
#   - the front door (cli/) parses and dispatches; its rooms: launch/
#     includes nothing of sweep/, experiments/ or bench/; experiments/ nothing
#     of sweep/ or bench/; sweep/ nothing of bench/; and no room includes
#     cli/ but for its shared scenario overrides and `sim` runner.
# Usage: check-structure.sh [repo root]; prints each violation, exits 1 if any.
set -u
root="${1:-$(cd "$(dirname "$0")/.." && pwd)}"
cd "$root" || exit 2
# Every folder of common/core/papers is a room: "shao|liu|...".
papers=$(cd common/core/papers && ls -d -- */ | tr -d / | paste -sd'|')
bad=0
report() {  # report RULE HITS: prints each hit with its rule
  [ -z "$2" ] && return
  while IFS= read -r hit; do echo "$hit   <- $1"; done <<<"$2"
  bad=1
}
inc() { grep -rnE --include='*.hpp' --include='*.cpp' --include='*.h' '^[[:space:]]*#[[:space:]]*include[[:space:]]*"pheromesh/' "$@" 2>/dev/null; }

for dir in common/core/papers/*/; do
  p=$(basename "$dir")
  report "room $p may include pheromesh/core/ and pheromesh/$p/ only" "$(inc "$dir" | grep -vE "\"pheromesh/(core|$p)/")"
done
report "the shared core includes no room" \
  "$(inc common/core/include common/core/src | grep -E "\"pheromesh/($papers)/")"
report "the core includes no bus, runtime, auth or console" \
  "$(inc common/core/include common/core/src common/core/papers | grep -E '"pheromesh/(bus|runtime|auth|console)/')"
report "the report includes only the core" "$(inc common/report | grep -vE '"pheromesh/(core|report)/')"
report "the front door includes only the core, report and console" \
  "$(inc common/frontdoor | grep -vE '"pheromesh/(core|report|console|frontdoor)/')"
report "the core includes no report" "$(inc common/core | grep -E '"pheromesh/report/')"
report "the core includes no Python (pypolicy registers a hook: core/python_policy.hpp)" \
  "$(inc common/core | grep -E '"pheromesh/pypolicy/'; grep -rlE --include='*.hpp' --include='*.cpp' '#[[:space:]]*include[[:space:]]*[<"](Python\.h|pybind11/)' common/core)"
report "the MAVLink library includes only itself" "$(inc common/mavlink | grep -vE '"pheromesh/mavlink/')"
report "the core includes no MAVLink" "$(inc common/core | grep -E '"pheromesh/mavlink/')"
report "auth, bus and runtime include nothing of the console" "$(inc common/auth common/bus common/runtime | grep -E '"pheromesh/console/')"
report "UAV and place shells include no console and no room" "$(inc agent placeagent | grep -E "\"pheromesh/(console|$papers)/")"
report "the ground station includes no room" "$(inc groundstation | grep -E "\"pheromesh/($papers)/")"
# The front door's rooms include one another by folder ("launch/run_plan.hpp").
room_inc() { grep -rnE --include='*.hpp' --include='*.cpp' '^[[:space:]]*#[[:space:]]*include[[:space:]]*"(cli|launch|sweep|experiments|bench)/' "$@" 2>/dev/null; }
report "launch/ includes nothing of sweep/, experiments/ or bench/" "$(room_inc launch | grep -E '"(sweep|experiments|bench)/')"
report "experiments/ includes nothing of sweep/ or bench/" "$(room_inc experiments | grep -E '"(sweep|bench)/')"
report "sweep/ includes nothing of bench/" "$(room_inc sweep | grep -E '"bench/')"
report "no room includes cli/ but its scenario overrides and sim runner" \
  "$(room_inc launch sweep experiments bench | grep -E '"cli/' | grep -vE '"cli/(scenario_overrides|sim_command)\.hpp"')"
if [ "$bad" -ne 0 ]; then
  echo "check-structure: the module map of docs/architecture.md is broken (above)" >&2
  exit 1
fi
echo "check-structure: ok"
