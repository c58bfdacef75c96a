#!/usr/bin/env bash
# Builds the libFuzzer harnesses in a clang build tree of their own and runs
# each on its seed corpus for a while (docs/fuzzing.md). Used by `make fuzz`
# and by the ctest test Fuzz.EveryHarnessRunsCleanOnItsCorpus.
#
#   fuzz/fuzz.sh [--build DIR] [--seconds N] [--only NAME[,NAME]] [--no-build] [--fresh] [--quick-build]
#
#   --build DIR   the clang tree (default: build-fuzz in the repository)
#   --seconds N   run time per harness (default 60; FUZZ_SECONDS)
#   --only NAMES  these harnesses only (e.g. fuzz_scenario,fuzz_recording)
#   --no-build    run what DIR holds
#   --fresh       start each harness from its seeds only (forget DIR/corpus)
#   --quick-build compile DIR at -O0 -gline-tables-only (NDEBUG as usual)
#                 as a unity build (sources merged into a few translation
#                 units): a cold configure and build in 132 s here
#                 (218 s file by file), a tenth of the executions/s;
#                 for a corpus run of a few seconds (the ctest test), not for
#                 a long search. Without it DIR is RelWithDebInfo (-O2 -g).
#
# One harness at a time, one process each (-jobs=1, the machine is shared).
# New inputs the fuzzer finds go to DIR/corpus/<harness> (kept between runs;
# the seeds in fuzz/corpus/<harness> are only read). A crash leaves its input
# in DIR/artifacts/<harness>/ and makes the script exit 1, after the others ran.
set -uo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="$root/build-fuzz"
seconds="${FUZZ_SECONDS:-60}"
only=""
do_build=1
fresh=0
opt_flags="-O2 -g -DNDEBUG"
unity=OFF
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build="$2"; shift 2 ;;
    --seconds) seconds="$2"; shift 2 ;;
    --only) only="$2"; shift 2 ;;
    --no-build) do_build=0; shift ;;
    --fresh) fresh=1; shift ;;
    --quick-build) opt_flags="-O0 -gline-tables-only -DNDEBUG"; unity=ON; shift ;;
    -h|--help) sed -n '2,22p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "fuzz.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
case "$seconds" in ''|*[!0-9]*) echo "fuzz.sh: --seconds must be a whole number, got '$seconds'" >&2; exit 2 ;; esac

if [ "$do_build" -eq 1 ]; then
  for tool in clang clang++; do
    command -v "$tool" > /dev/null || { echo "fuzz.sh: $tool not found (./scripts/install-deps.sh installs clang)" >&2; exit 2; }
  done
  launcher=()
  if command -v ccache > /dev/null; then
    launcher=(-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  fi
  # The core, the console and the generated Fast DDS types; no DDS library,
  # no web page, no tests (PHEROMESH_CORE_ONLY).
  mkdir -p "$build"
  # The flags are given every time, so a tree configured by one mode and
  # built again by the other is rebuilt with what this run asked for.
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    "-DCMAKE_C_FLAGS_RELWITHDEBINFO=$opt_flags" "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=$opt_flags" \
    -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ "${launcher[@]}" "-DCMAKE_UNITY_BUILD=$unity" \
    -DPHEROMESH_CORE_ONLY=ON -DPHEROMESH_FUZZ=ON -DPHEROMESH_BUILD_TESTS=OFF -DPHEROMESH_BUILD_BENCH=OFF \
    > "$build/configure.log" 2>&1 || { cat "$build/configure.log" >&2; echo "fuzz.sh: configure failed" >&2; exit 2; }
  cmake --build "$build" -j"${FUZZ_JOBS:-2}" --target pheromesh_fuzzers || { echo "fuzz.sh: build failed" >&2; exit 2; }
fi

harnesses=()
for exe in "$build"/bin/fuzz_*; do
  [ -x "$exe" ] || continue
  name="$(basename "$exe")"
  if [ -n "$only" ] && [[ ",$only," != *",$name,"* ]]; then continue; fi
  harnesses+=("$name")
done
if [ ${#harnesses[@]} -eq 0 ]; then
  echo "fuzz.sh: no harness in $build/bin${only:+ matching $only}" >&2
  exit 2
fi

failed=()
summary=()
for name in "${harnesses[@]}"; do
  corpus="$build/corpus/$name"
  artifacts="$build/artifacts/$name"
  log="$build/logs/$name.log"
  [ "$fresh" -eq 1 ] && rm -rf "$corpus"
  mkdir -p "$corpus" "$artifacts" "$(dirname "$log")"
  seeds="$root/fuzz/corpus/$name"
  [ -d "$seeds" ] || seeds=""
  dict="$root/fuzz/dict/$name.dict"
  dict_arg=()
  [ -f "$dict" ] && dict_arg=(-dict="$dict")
  echo "== $name: ${seconds} s"
  # -rss_limit_mb: ASan's shadow plus a 64 MiB record is far below it; more
  # is a leak or an unbounded allocation, which is a finding.
  "$build/bin/$name" -max_total_time="$seconds" -print_final_stats=1 -rss_limit_mb=2048 -timeout=10 \
    -artifact_prefix="$artifacts/" "${dict_arg[@]}" "$corpus" $seeds > "$log" 2>&1
  rc=$?
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  rate=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  last=$(grep -E '^#[0-9]+' "$log" | tail -1)
  cov=$(sed -n 's/.* cov: \([0-9]*\).*/\1/p' <<<"$last")
  ft=$(sed -n 's/.* ft: \([0-9]*\).*/\1/p' <<<"$last")
  units=$(find "$corpus" -type f | wc -l)
  if [ "$rc" -ne 0 ]; then
    failed+=("$name")
    echo "   CRASH (exit $rc): $log"
    grep -E 'ERROR: |runtime error|Test unit written to|SUMMARY' "$log" | head -5 | sed 's/^/   /'
  fi
  line=$(printf '%-22s %8s s %12s execs %8s exec/s  cov %6s  ft %6s  corpus %5s  %s' \
    "$name" "$seconds" "${execs:-?}" "${rate:-?}" "${cov:-?}" "${ft:-?}" "$units" "$([ "$rc" -eq 0 ] && echo ok || echo CRASH)")
  summary+=("$line")
  echo "   $line"
done
echo
echo "fuzz summary (logs in $build/logs):"
printf '  %s\n' "${summary[@]}"
if [ ${#failed[@]} -ne 0 ]; then
  echo "fuzz.sh: crashes in ${failed[*]}; inputs in $build/artifacts/" >&2
  exit 1
fi
