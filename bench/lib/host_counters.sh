# Host counters the discovery benchmarks read (source it; bash).
#   udp                  "datagrams-received receive-buffer-drops" of this network namespace
#   cpu_of PID...        summed utime+stime [clock ticks] of those still running, read in one pass
#   pss_of PID...        mean PSS [MiB] of those still running ("n/a" if none)
#   now                  seconds since the epoch, with nanoseconds
#   load1                the 1-minute load average
#   window_counters W PID...
#                        sleeps W seconds and prints "elapsed cpu datagrams drops" for that
#                        window: elapsed [s] as measured (a loaded host is slow to take
#                        the readings), cpu [clock ticks] of the PIDs, datagrams and drops
udp() { awk '/^Udp:/ && $2 ~ /^[0-9]+$/ {print $2, $6}' /proc/net/snmp; }
cpu_of() {
  local files=()
  # Only those still there: mawk stops at a file it cannot open.
  for p in "$@"; do [[ -r /proc/$p/stat ]] && files+=("/proc/$p/stat"); done
  ((${#files[@]})) || { echo 0; return; }
  cat "${files[@]}" 2> /dev/null | awk '{s += $14 + $15} END {printf "%d", s}'
}
pss_of() {
  for p in "$@"; do awk '/^Pss:/ {print $2}' "/proc/$p/smaps_rollup" 2> /dev/null; done |
    awk '{s += $1; n++} END {if (n) printf "%.1f", s / n / 1024; else print "n/a"}'
}
now() { date +%s.%N; }
load1() { cut -d' ' -f1 /proc/loadavg; }
window_counters() {
  local window=$1
  shift
  local t0 t1 in0 drop0 in1 drop1 c0 c1
  t0=$(now)
  read -r in0 drop0 < <(udp)
  c0=$(cpu_of "$@")
  sleep "$window"
  read -r in1 drop1 < <(udp)
  c1=$(cpu_of "$@")
  t1=$(now)
  awk -v a="$t0" -v b="$t1" -v c=$((c1 - c0)) -v d=$((in1 - in0)) -v e=$((drop1 - drop0)) \
    'BEGIN {printf "%.3f %d %d %d\n", b - a, c, d, e}'
}
