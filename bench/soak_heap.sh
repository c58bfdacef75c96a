#!/usr/bin/env bash
# Where a place agent's memory goes in a soak (docs/benchmarks.md, "The
# hour"): `pheromesh bench soak` in cells, with place agent REGION (one that
# no fault restarts in the soak's time) run under heaptrack's preload, and
# heaptrack_print's peak consumers of that process at the end.
#
# The binaries are copied into OUT/bin first, so a rebuild of BUILD during
# the soak cannot break its restarts; pheromesh-place there is a wrapper
# that execs the real program (the launcher's signals reach it) and, for
# REGION only, with LD_PRELOAD=libheaptrack_preload.so.
#
#   bench/soak_heap.sh BUILD [REGION] [DURATION] [FAULT_EVERY] [OUT]
#   bench/soak_heap.sh build 13 12m 30s out/soak-heap
# Needs heaptrack (apt-get install heaptrack). Keep the host otherwise idle.
set -euo pipefail
build=${1:?usage: soak_heap.sh BUILD [REGION] [DURATION] [FAULT_EVERY] [OUT]}
region=${2:-13}
duration=${3:-12m}
fault_every=${4:-30s}
out=${5:-out/soak-heap}
preload=/usr/lib/heaptrack/libheaptrack_preload.so
interpret=/usr/lib/heaptrack/libexec/heaptrack_interpret
for f in "$preload" "$interpret"; do
  [ -e "$f" ] || { echo "soak_heap.sh: $f is missing: apt-get install heaptrack" >&2; exit 2; }
done
command -v heaptrack_print > /dev/null || { echo "soak_heap.sh: heaptrack_print is missing: apt-get install heaptrack" >&2; exit 2; }
src=$(cd "$(dirname "$0")/.." && pwd)
out=$(mkdir -p "$out" && cd "$out" && pwd)
rm -rf "${out:?}/bin" "${out:?}/heap" "${out:?}/soak"
mkdir -p "$out/bin/real" "$out/heap"
for p in pheromesh pheromesh-uav pheromesh-place pheromesh-ground; do cp "$build/bin/$p" "$out/bin/real/"; done
cp "$out/bin/real/pheromesh" "$out/bin/real/pheromesh-uav" "$out/bin/real/pheromesh-ground" "$out/bin/"
cat > "$out/bin/pheromesh-place" << EOF
#!/bin/sh
case " \$* " in
  *" --region $region "*)
    trace="$out/heap/pheromesh-place.\$\$"
    mkfifo "\$trace.fifo"
    "$interpret" < "\$trace.fifo" | gzip > "\$trace.gz" &
    LD_PRELOAD="$preload" DUMP_HEAPTRACK_OUTPUT="\$trace.fifo" exec "$out/bin/real/pheromesh-place" "\$@" ;;
esac
exec "$out/bin/real/pheromesh-place" "\$@"
EOF
chmod +x "$out/bin/pheromesh-place"
(cd "$src" && "$out/bin/pheromesh" bench soak scenarios/scale-100x100.textproto --processes 200 --duration "$duration" \
  --fault-every "$fault_every" --sample-every 10s --warmup 60s --out "$out/soak" --extra "--dds-profile cells")
sleep 2  # the interpreter finishes writing after the process ends
rm -f "$out"/heap/*.fifo
for trace in "$out"/heap/pheromesh-place.*.gz; do
  heaptrack_print -f "$trace" --print-peaks 1 --print-allocators 0 --print-temporary 0 -n 12 -s 2 > "${trace%.gz}.peaks.txt"
  echo "== $trace: $(grep -E '^(peak heap memory consumption|peak RSS)' "${trace%.gz}.peaks.txt" | tr '\n' ' ')"
  grep -E '^[0-9.]+[KMG]? peak memory consumed' "${trace%.gz}.peaks.txt" | head -5
done
