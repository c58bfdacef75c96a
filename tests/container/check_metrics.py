#!/usr/bin/python3
"""Checks a swarm's metrics.json the way the container tests need it:
   check_metrics.py METRICS.json UAVS PLACES
Exit 0 when every UAV finished, every place agent finished, the deposit
accounting balances with nothing lost (sent = applied + rejected + lost,
lost = 0), coverage > 0 and no process crashed; else 1, naming each failure.
"""
import json
import sys


def problems(m, uavs, places):
    out = []
    if m.get("uavs") != uavs:
        out.append(f"uavs {m.get('uavs')}, expected {uavs}")
    status = m.get("uav_status") or {}
    finished = sorted(int(k) for k, v in status.items() if v.get("finished"))
    if finished != list(range(uavs)):
        out.append(f"UAVs that finished: {finished}, expected 0..{uavs - 1}")
    if m.get("place_agents") != places or m.get("place_agents_finished") != places:
        out.append(f"place agents {m.get('place_agents')}, finished {m.get('place_agents_finished')}, expected {places}")
    sent, applied = m.get("deposits_sent", -1), m.get("deposits_applied", -1)
    rejected, lost = m.get("deposits_rejected", -1), m.get("deposits_lost", -1)
    if sent <= 0:
        out.append(f"deposits_sent {sent}: the UAVs deposited nothing")
    if sent != applied + rejected + lost:
        out.append(f"deposits_sent {sent} != applied {applied} + rejected {rejected} + lost {lost}")
    if lost != 0:
        out.append(f"deposits_lost {lost}, expected 0")
    if not m.get("coverage", 0) > 0:
        out.append(f"coverage {m.get('coverage')}, expected > 0")
    if m.get("processes_crashed", 0) != 0:
        out.append(f"processes_crashed {m.get('processes_crashed')}")
    return out


def main():
    path, uavs, places = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    with open(path, encoding="utf-8") as f:
        m = json.load(f)
    found = problems(m, uavs, places)
    for p in found:
        print(f"check_metrics: {path}: {p}", file=sys.stderr)
    if not found:
        print(f"check_metrics: {path}: {uavs} UAVs and {places} place agents finished, coverage {m['coverage']:.3f}, "
              f"deposits sent {m['deposits_sent']} = applied {m['deposits_applied']} + rejected "
              f"{m['deposits_rejected']} + lost {m['deposits_lost']}")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
