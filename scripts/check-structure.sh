#!/usr/bin/env bash
# The module map of docs/architecture.md, checked on the #include lines:
#   - a paper's room (common/core/papers/<paper>) includes the shared core
#     and its own room only;
#   - the shared core includes no room (the policy table,
#     src/policy/policy_table.cpp, names each room's entry without including it),
#     and nothing of the bus, the runtime, auth or the console;
#   - auth, bus and runtime include nothing of the console;
#   - the MAVLink library (common/mavlink) includes only itself, and the
#     core nothing of it;
#   - the shared core's sources are in its rooms (common/core/src/<room>:
#     field, protocol, scenario, policy, swarm, util), none beside them;
#   - the UAV and place agent shells include no room and nothing of the console;
#   - the ground station includes no room;
#   - the front door (cli/) parses and dispatches; its rooms: launch/
#     includes nothing of sweep/, experiments/ or bench/; experiments/ nothing
#     of sweep/ or bench/; sweep/ nothing of bench/; and no room includes
#     cli/ but for its shared scenario overrides and `sim` runner.
# It also keeps functions short (STYLE.md, "Short functions"): no function
# definition outside tests is over 80 lines (scripts/function-lengths.awk
# measures them), but for the allow-list below, which may only shrink.
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
# The shared core's sources live in rooms by concern (docs/architecture.md,
# "Module map"); its public headers keep one folder, pheromesh/core/.
core_rooms="field|protocol|scenario|policy|swarm|util"
report "every source of common/core/src is in one of its rooms ($core_rooms)" \
  "$(find common/core/src -mindepth 1 -maxdepth 1 -type f; find common/core/src -mindepth 1 -maxdepth 1 -type d | grep -vE "/($core_rooms)\$"; find common/core/src -mindepth 3 -type f)"
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
# --- short functions ---------------------------------------------------------
# No function outside tests over 80 lines, from its signature's last line to
# its closing brace. A table is data plus a loop. The allow-list holds the
# functions not yet split, as "FILE FUNCTION"; an entry whose function has
# become short must go (the check says so), so the list only shrinks.
max_function_lines=80
allowed_long_functions=$(grep -v '^#' <<'EOF'
EOF
)
long_functions=$(find agent placeagent groundstation cli launch sweep experiments bench common \
                   \( -name '*.cpp' -o -name '*.hpp' \) -not -path '*test*' -print 2>/dev/null | sort |
                 xargs -r awk -v limit="$max_function_lines" -f scripts/function-lengths.awk)
over=""
while read -r where n name; do
  [ -z "$where" ] && continue
  grep -qxF "${where%%:*} $name" <<<"$allowed_long_functions" && continue
  over+="$where: $name is $n lines"$'\n'
done <<<"$long_functions"
report "no function over $max_function_lines lines (split it: named helpers, tables as data)" "${over%$'\n'}"
stale=""
while read -r file name; do
  [ -z "$file" ] && continue
  grep -qE "^$file:[0-9]+ [0-9]+ $name\$" <<<"$long_functions" || stale+="$file $name"$'\n'
done <<<"$allowed_long_functions"
report "allow-listed long function is short now (or gone): remove it from the list" "${stale%$'\n'}"
if [ "$bad" -ne 0 ]; then
  echo "check-structure: the module map of docs/architecture.md or the function-length limit is broken (above)" >&2
  exit 1
fi
echo "check-structure: ok"
