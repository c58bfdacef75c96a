#!/usr/bin/env python3
"""Where a lockstep tick's CPU goes, by role and thread (docs/benchmarks.md).

Runs `pheromesh run SCENARIO --uavs N --clock lockstep`, reads every thread of
every pheromesh-uav, -place and -ground process from /proc at two moments
WINDOW seconds apart, SKIP seconds after the launch, and prints per lockstep
tick of that window: each (role, thread name) group's CPU (user and system,
/proc/PID/task/TID/stat) and its voluntary and involuntary context switches
(/proc/PID/task/TID/status). The ticks are the ground station's status lines.
Fast DDS names no threads: all of a process's are under its own name.

  bench/lockstep_threads.py [--uavs 100] [--dds cyclone] [--skip 10] [--window 10]
  BIN=/path/to/other/build/bin bench/lockstep_threads.py --dds fastdds

TICKS must outlast SKIP + WINDOW; keep the host otherwise idle.
"""
import argparse
import collections
import os
import re
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
HZ = os.sysconf("SC_CLK_TCK")
ROLES = {"pheromesh-uav": "uav", "pheromesh-place": "place", "pheromesh-groun": "ground"}


def snapshot():
    """{pid/tid: (role, thread, utime, stime, voluntary, involuntary)} of every pheromesh-* thread."""
    out = {}
    for pid in os.listdir("/proc"):
        if not pid.isdigit():
            continue
        try:
            with open(f"/proc/{pid}/comm") as f:
                comm = f.read().strip()
            role = ROLES.get(comm)  # a process name is cut to 15 characters
            if role is None:
                continue
            for tid in os.listdir(f"/proc/{pid}/task"):
                base = f"/proc/{pid}/task/{tid}"
                with open(base + "/comm") as f:
                    thread = f.read().strip()
                with open(base + "/stat") as f:
                    stat = f.read().rsplit(")", 1)[1].split()
                with open(base + "/status") as f:
                    status = f.read()
                vol = int(re.search(r"^voluntary_ctxt_switches:\s+(\d+)", status, re.M).group(1))
                invol = int(re.search(r"^nonvoluntary_ctxt_switches:\s+(\d+)", status, re.M).group(1))
                out[f"{pid}/{tid}"] = (role, thread, int(stat[11]), int(stat[12]), vol, invol)
        except (OSError, AttributeError, IndexError):
            pass  # a thread or process that ended meanwhile
    return out


def ground_tick(log_path):
    with open(log_path, errors="replace") as f:
        ticks = re.findall(r"\[ground\] tick +(\d+) \|", f.read())
    return int(ticks[-1]) if ticks else None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scenario", default=os.path.join(ROOT, "scenarios", "scale-100x100.textproto"))
    ap.add_argument("--uavs", type=int, default=100)
    ap.add_argument("--dds", default="cyclone", choices=["cyclone", "fastdds"])
    ap.add_argument("--ticks", type=int, default=1200, help="lockstep ticks of the run (must outlast the window)")
    ap.add_argument("--skip", type=float, default=10.0, help="seconds after the launch before the window")
    ap.add_argument("--window", type=float, default=10.0, help="seconds between the two readings")
    args = ap.parse_args()
    if args.uavs <= 0 or args.ticks <= 0 or args.skip < 0 or args.window <= 0:
        ap.error("--uavs, --ticks and --window must be positive, --skip not negative")
    binary = os.path.join(os.environ.get("BIN", os.path.join(ROOT, "build", "bin")), "pheromesh")
    if not os.access(binary, os.X_OK):
        sys.exit(f"lockstep_threads: no {binary} (build first, or set BIN)")
    with tempfile.TemporaryDirectory(prefix="pheromesh-lockstep-threads.") as out:
        log_path = os.path.join(out, "run.log")
        with open(log_path, "w") as log:
            run = subprocess.Popen([binary, "run", args.scenario, "--uavs", str(args.uavs), "--clock", "lockstep",
                                    "--ticks", str(args.ticks), "--dds", args.dds, "--out", os.path.join(out, "run")],
                                   stdout=log, stderr=subprocess.STDOUT)
            time.sleep(args.skip)
            t0, a = ground_tick(log_path), snapshot()
            time.sleep(args.window)
            t1, b = ground_tick(log_path), snapshot()
            code = run.wait()
        if code != 0:
            sys.exit(f"lockstep_threads: pheromesh run exited {code}; its log:\n" + open(log_path).read()[-2000:])
    if t0 is None or t1 is None or t1 <= t0 or not a or not b:
        sys.exit("lockstep_threads: the window missed the flight (raise --ticks, or move --skip)")
    ticks = t1 - t0
    groups = collections.defaultdict(lambda: [0, 0, 0, 0, 0])
    for key, now in b.items():
        if key in a:
            g = groups[(now[0], now[1])]
            for i in range(4):
                g[i] += now[2 + i] - a[key][2 + i]
            g[4] += 1
    total = sum(g[0] + g[1] for g in groups.values())
    print(f"{args.uavs} UAVs, {args.dds}: ticks {t0}..{t1}, {ticks / args.window:.1f} ticks/s; "
          f"{total / HZ:.2f} CPU-s in {args.window:.0f} s")
    print("| role | thread | threads | CPU per tick [ms] (user + sys) | share | voluntary / involuntary switches per tick |")
    print("|---|---|--:|--:|--:|--:|")
    for (role, thread), g in sorted(groups.items(), key=lambda kv: -(kv[1][0] + kv[1][1])):
        cpu = g[0] + g[1]
        if cpu == 0 and g[2] < ticks:
            continue
        print(f"| {role} | {thread} | {g[4]} | {1000 * cpu / HZ / ticks:.2f} ({1000 * g[0] / HZ / ticks:.2f} + "
              f"{1000 * g[1] / HZ / ticks:.2f}) | {100 * cpu / max(total, 1):.1f} % | "
              f"{g[2] / ticks:.1f} / {g[3] / ticks:.1f} |")


if __name__ == "__main__":
    main()
