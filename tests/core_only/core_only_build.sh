#!/usr/bin/env bash
# CoreOnly.BuildsAndSimulatesWithoutDds: configure a PHEROMESH_CORE_ONLY=ON
# tree with both DDS vendors and npm hidden from CMake, build `pheromesh`,
# and check that it holds no DDS and runs validate, sim, experiment and sweep;
# run, attach, bench, security and replay say the build is core-only.
#   tests/core_only/core_only_build.sh SOURCE_DIR TREE
# The tree is kept between runs (and ccache, if installed, is used), so a
# re-run only rebuilds what changed.
set -u
src=${1:?usage: core_only_build.sh SOURCE_DIR TREE}
tree=${2:?usage: core_only_build.sh SOURCE_DIR TREE}
fail() { echo "core-only: $*" >&2; exit 1; }

mkdir -p "$tree" || fail "cannot make $tree"
launcher=()
if command -v ccache >/dev/null; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
fi
# Hidden: a find_package of a vendor fails, and npm/node are not found.
cmake -S "$src" -B "$tree" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPHEROMESH_CORE_ONLY=ON \
  -DPHEROMESH_BUILD_TESTS=OFF -DPHEROMESH_BUILD_BENCH=OFF "${launcher[@]}" \
  -DCMAKE_DISABLE_FIND_PACKAGE_CycloneDDS=ON -DCMAKE_DISABLE_FIND_PACKAGE_CycloneDDS-CXX=ON \
  -DCMAKE_DISABLE_FIND_PACKAGE_fastrtps=ON -DCMAKE_DISABLE_FIND_PACKAGE_fastcdr=ON \
  -DPHEROMESH_NPM=/nonexistent/npm -DPHEROMESH_NODE=/nonexistent/node --no-warn-unused-cli >"$tree/core-only-configure.log" 2>&1 ||
  { cat "$tree/core-only-configure.log" >&2; fail "configure failed"; }
cmake --build "$tree" -j"${CORE_ONLY_JOBS:-2}" --target pheromesh >"$tree/core-only-build.log" 2>&1 ||
  { tail -50 "$tree/core-only-build.log" >&2; fail "build failed ($tree/core-only-build.log)"; }

# Nothing of a vendor, the console server or npm was looked for or linked.
if grep -E '^(CycloneDDS|CycloneDDS-CXX|fastrtps|fastcdr|HTTPLIB)_' "$tree/CMakeCache.txt" | grep -v NOTFOUND | grep -q .; then
  fail "the core-only tree found a DDS or HTTP package: $(grep -E '^(CycloneDDS|fastrtps|fastcdr|HTTPLIB)_' "$tree/CMakeCache.txt")"
fi
[ -d "$tree/web" ] && fail "the core-only tree configured the web console (npm)"
bin="$tree/bin/pheromesh"
[ -x "$bin" ] || fail "no $bin"
if ldd "$bin" | grep -Ei 'ddsc|ddscxx|fastrtps|fastcdr|fastdds'; then fail "$bin links a DDS library"; fi

out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
"$bin" validate small-test >"$out/validate.txt" 2>&1 || { cat "$out/validate.txt"; fail "validate failed"; }
"$bin" sim small-test --ticks 20 --quiet --tracks --record "$out/sim/sim.phrec" --out "$out/sim" >"$out/sim.txt" 2>&1 ||
  { cat "$out/sim.txt"; fail "sim failed"; }
for f in metrics.json series.csv tracks.csv final_field.txt final_field.csv sim.phrec; do
  [ -s "$out/sim/$f" ] || fail "sim wrote no $f"
done
[ "$(wc -l <"$out/sim/series.csv")" -eq 22 ] || fail "series.csv has $(wc -l <"$out/sim/series.csv") lines, not 22"
"$bin" experiment --list >"$out/list.txt" 2>&1 || { cat "$out/list.txt"; fail "experiment --list failed"; }
"$bin" experiment shao-50x50 --runs 1 --set run.ticks=20 --out "$out/exp" >"$out/exp.txt" 2>&1 ||
  { cat "$out/exp.txt"; fail "experiment failed"; }
[ -s "$out/exp/report.md" ] || fail "experiment wrote no report.md"
"$bin" sweep small-test --set shao.aco.alpha=1,2 --seeds 1-2 --ticks 10 --jobs 2 --quiet --out "$out/sweep" \
  >"$out/sweep.txt" 2>&1 || { cat "$out/sweep.txt"; fail "sweep failed"; }
[ "$(wc -l <"$out/sweep/runs.csv")" -eq 5 ] || fail "runs.csv has $(wc -l <"$out/sweep/runs.csv") lines, not 5"

# What needs DDS or the web console is refused, saying why.
for cmd in "run small-test" "attach" "cell uav 0" "bench scale small-test" "security init $out/sec" "replay $out/sim/sim.phrec" \
  "sweep small-test --distributed --out $out/sweep-d" "experiment shao-50x50 --runs 1 --distributed --out $out/exp-d"; do
  # shellcheck disable=SC2086
  "$bin" $cmd >"$out/refused.txt" 2>&1
  rc=$?
  [ "$rc" -eq 2 ] || { cat "$out/refused.txt"; fail "'pheromesh $cmd' exited $rc, not 2"; }
  grep -q "built core-only" "$out/refused.txt" || { cat "$out/refused.txt"; fail "'pheromesh $cmd' did not say why"; }
done
echo "core-only: built without DDS or npm; validate, sim (--tracks --record), experiment and sweep ran; run, attach, cell, bench, security, replay and --distributed refused"
