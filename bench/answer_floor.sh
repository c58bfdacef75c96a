#!/usr/bin/env bash
# What answering one sample costs a process on this host, by where the answer
# is written: on the main thread woken by a wait set (how every pheromesh
# process answers today: the receive thread takes the datagram and wakes the
# main thread through a condition variable), or in the receive thread itself
# (a data-available listener). Cyclone's ddsperf ping/pong, our one-host
# profile, a ping of a view's size (10 696 B, as `bench scale` floors) at a
# fixed rate, so that both modes answer the same number of samples; each mode
# runs REPEAT times, the modes alternating. It prints, per run, the CPU
# (user + system, /usr/bin/time) of the answering process (pong) and of the
# asking one (ping) per round trip, and the context switches ddsperf counted
# in the ping's last second (docs/benchmarks.md, "Answering in the receive
# thread"). Keep the host otherwise idle.
#
#   bench/answer_floor.sh [RATE_HZ] [SECONDS] [REPEAT] [SIZE_B]
#   bench/answer_floor.sh 2000 10 2
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
rate=${1:-2000}
secs=${2:-10}
repeat=${3:-2}
size=${4:-10696}
for tool in ddsperf /usr/bin/time; do
  command -v "$tool" >/dev/null || {
    echo "answer_floor: needs $tool (apt-get install cyclonedds-tools time)" >&2
    exit 2
  }
done
case "$rate$secs$repeat$size" in *[!0-9]*)
  echo "answer_floor: RATE_HZ, SECONDS, REPEAT and SIZE_B are whole numbers" >&2
  exit 2
  ;;
esac
if [ "$rate" -lt 1 ] || [ "$secs" -lt 2 ] || [ "$repeat" -lt 1 ] || [ "$size" -lt 12 ]; then
  echo "answer_floor: needs RATE_HZ >= 1, SECONDS >= 2, REPEAT >= 1, SIZE_B >= 12" >&2
  exit 2
fi
out=$(mktemp -d /tmp/pheromesh-answer-floor.XXXXXX)
trap 'rm -rf "$out"' EXIT
export CYCLONEDDS_URI="file://$root/deploy/dds/cyclone-onehost.xml"
domain=$((200 + $$ % 30))  # away from the swarms' default domain 0
echo "| run | answered in | round trips | answering process CPU per round trip [us] | asking process [us] | ping's context switches in its last second (voluntary + involuntary) |"
echo "|--:|---|--:|--:|--:|--:|"
for ((i = 1; i <= repeat; i++)); do
  for mode in waitset listener; do
    /usr/bin/time -f "%U %S" -o "$out/pong.time" ddsperf -i "$domain" -D $((secs + 2)) pong "$mode" >"$out/pong.txt" 2>&1 &
    pong=$!
    sleep 0.5
    /usr/bin/time -f "%U %S" -o "$out/ping.time" ddsperf -i "$domain" -D "$secs" ping "${rate}Hz" size "$size" "$mode" \
      >"$out/ping.txt" 2>&1 || true
    wait "$pong" || true
    python3 - "$out" "$i" "$mode" <<'EOF'
import re, sys
out, run, mode = sys.argv[1:]
def cpu(name):
    user, system = open(f"{out}/{name}.time").read().split()[-2:]
    return float(user) + float(system)
text = open(f"{out}/ping.txt").read()
trips = sum(int(n) for n in re.findall(r" cnt (\d+)", text))
switches = re.findall(r"vcsw:(\d+) ivcsw:(\d+)", text)
last = f"{switches[-1][0]} + {switches[-1][1]}" if switches else "n/a"
if trips == 0:
    print(f"| {run} | {mode} | 0 | n/a | n/a | {last} |  (no round trip: see ddsperf's output)")
else:
    print(f"| {run} | {mode} | {trips} | {cpu('pong') / trips * 1e6:.1f} | {cpu('ping') / trips * 1e6:.1f} | {last} |")
EOF
  done
done
