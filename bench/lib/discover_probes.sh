# shellcheck shell=bash
# What the discovery benchmarks do with a set of `pheromesh-test-probe
# discover` processes (source it; bash). Each probe writes its output to
# OUT/<id>.txt: "discovered N in S s" once it has heard every other one.
#   probes_stop OUT N TIMEOUT_S PID...
#                        every probe stays until told (its record is
#                        transient-local only while it lives): waits until all
#                        N have heard every other one, or the probes' own
#                        timeout (+5 s) has passed (or STOP_AFTER_S), then
#                        stops and reaps them;
#                        each probe's exit code goes to OUT/exit-codes
#   probes_times OUT     "FOUND MEDIAN MAX" of the probes that heard every
#                        other one (seconds; "-" when none did)
#   probes_ends OUT      how the probes ended: "CLEAN CRASHED CODES", CLEAN
#                        those that exited 0 when stopped, CRASHED those
#                        that died of a signal (code > 128: a segmentation
#                        fault, an abort), CODES each code and how many
#                        ("1x60,5x40": the probe's exit codes, 1 its own
#                        timeout, 5 its watchdog past a SIGTERM)
probes_stop() {
  local out=$1 n=$2 timeout_s=$3
  shift 3
  local deadline=$((SECONDS + timeout_s + 5))
  # STOP_AFTER_S: stop them this long after the last one started, found or
  # not (stopping probes mid-handshake: issue 42).
  [[ -n ${STOP_AFTER_S:-} ]] && deadline=$((SECONDS + STOP_AFTER_S))
  while ((SECONDS < deadline)); do
    (($(cat "$out"/*.txt 2> /dev/null | grep -c '^discovered') >= n)) && break
    sleep 0.5
  done
  kill -TERM "$@" 2> /dev/null || true
  local code
  : > "$out/exit-codes"
  for p in "$@"; do
    code=0
    wait "$p" || code=$?
    echo "$code" >> "$out/exit-codes"
  done
}
probes_ends() {
  awk '$1 == 0 {c++} $1 > 128 {k++} {n[$1]++}
       END {s = ""; for (x in n) s = s (s == "" ? "" : ",") x "x" n[x]; print c + 0, k + 0, s}' "$1/exit-codes"
}
probes_times() {
  cat "$1"/*.txt | awk '/^discovered/ {print $4}' | sort -n |
    awk 'NF {a[++k] = $1} END {if (k) print k, a[int((k + 1) / 2)], a[k]; else print 0, "-", "-"}'
}
