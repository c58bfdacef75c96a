#!/usr/bin/env python3
"""What a swarm's UDP datagrams carry, per UAV tick, by DDS topic and RTPS
submessage (bench/tick_traffic.sh). Reads a pcap of loopback (Ethernet link
type, as tcpdump -i lo writes it), learns which writer publishes which topic
from the discovery (SEDP) announcements it holds, and counts the DATA,
HEARTBEAT and ACKNACK submessages of every topic inside a window.

  rtps_topics.py PCAP SKIP_S WINDOW_S UAVS RATE_HZ

SKIP_S: the window starts this long after the first packet (leave discovery
out); the UAV ticks of the window are UAVS x RATE_HZ x WINDOW_S. A writer
whose announcement was not captured is "?"; built-in (discovery, liveliness)
endpoints are "builtin". Acknowledgements name the writer they answer. A
heartbeat with the FINAL flag (its writer wants no answer; a reader that
misses a sample still asks) counts as "HEARTBEAT(final)", apart from those
that ask for an ACKNACK."""
import collections
import struct
import sys

KINDS = {0x15: "DATA", 0x16: "DATA_FRAG", 0x07: "HEARTBEAT", 0x06: "ACKNACK", 0x08: "GAP"}
SEDP_PUBLICATIONS = b"\x00\x00\x03\xc2"  # RTPS 2.x builtin publications writer


def params(buf, le):
    """A parameter list: pid -> value (the first of each), up to PID_SENTINEL."""
    out, p = {}, 0
    while p + 4 <= len(buf):
        pid, ln = struct.unpack("<HH" if le else ">HH", buf[p:p + 4])
        if pid == 1:
            break
        out.setdefault(pid, buf[p + 4:p + 4 + ln])
        p += 4 + ln
    return out


def cdr_string(b, le):
    n = struct.unpack("<I" if le else ">I", b[:4])[0]
    return b[4:4 + n - 1].decode(errors="replace")


def learn_topic(body, flags, le, topics):
    """A SEDP publication: remember which writer GUID publishes which topic."""
    q = 20  # extraFlags, octetsToInlineQos, readerId, writerId, writerSN
    if flags & 2:  # inline QoS first: skip it
        while q + 4 <= len(body):
            pid, ln = struct.unpack("<HH" if le else ">HH", body[q:q + 4])
            q += 4 + ln
            if pid == 1:
                break
    enc = body[q:q + 4]
    if len(enc) < 4:
        return
    ps = params(body[q + 4:], enc[1] in (1, 3))
    if 0x5A in ps and 0x05 in ps:  # PID_ENDPOINT_GUID, PID_TOPIC_NAME
        topics[ps[0x5A][:16]] = cdr_string(ps[0x05], enc[1] in (1, 3))


def packets(path):
    with open(path, "rb") as f:
        f.read(24)
        while True:
            h = f.read(16)
            if len(h) < 16:
                return
            ts, tu, incl, _ = struct.unpack("<IIII", h)
            yield ts + tu / 1e6, f.read(incl)


def main():
    path, skip, window, uavs, rate = sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), int(sys.argv[4]), float(sys.argv[5])
    ticks = uavs * rate * window
    topics, seen, t0 = {}, [], None
    for t, pkt in packets(path):
        t0 = t if t0 is None else t0
        ip = pkt[14:]
        if len(ip) < 28 or ip[9] != 17:
            continue
        payload = ip[(ip[0] & 15) * 4 + 8:]
        if payload[:4] != b"RTPS" or len(payload) < 20:
            continue
        prefix, dst, subs, p = payload[8:20], None, [], 20
        while p + 4 <= len(payload):
            sid, flags = payload[p], payload[p + 1]
            le = flags & 1
            ln = struct.unpack("<H" if le else ">H", payload[p + 2:p + 4])[0]
            body = payload[p + 4:p + 4 + ln] if ln else payload[p + 4:]
            if sid == 0x0E:  # INFO_DST: the acknowledgements that follow answer its participant's writers
                dst = body[:12]
            if sid in KINDS and len(body) >= 12:
                if sid == 0x06:
                    key = (dst or b"") + body[4:8]
                elif sid in (0x15, 0x16):
                    key = prefix + body[8:12]
                    if body[8:12] == SEDP_PUBLICATIONS and sid == 0x15:
                        learn_topic(body, flags, le, topics)
                else:
                    key = prefix + body[4:8]
                kind = KINDS[sid] + ("(final)" if sid == 0x07 and flags & 2 else "")
                subs.append((kind, key, len(body)))
            if ln == 0:
                break
            p += 4 + ln
        seen.append((t - t0, subs))
    count, size, datagrams = collections.Counter(), collections.Counter(), 0
    for t, subs in seen:
        if not skip <= t < skip + window:
            continue
        datagrams += 1
        for kind, key, n in subs:
            topic = topics.get(key, "builtin" if key[-1] >= 0xC0 else "?")
            count[(topic, kind)] += 1
            size[(topic, kind)] += n
    print(f"window {skip:g}-{skip + window:g} s, {ticks:.0f} UAV ticks: {datagrams / ticks:.2f} RTPS datagrams per UAV tick"
          f" ({len(topics)} writers' topics learnt)")
    print(f"  {'topic':28s} {'submessage':16s} {'per UAV tick':>12s} {'mean bytes':>10s}")
    for (topic, kind), v in sorted(count.items(), key=lambda kv: -kv[1]):
        print(f"  {topic:28s} {kind:16s} {v / ticks:12.3f} {size[(topic, kind)] / v:10.0f}")


if __name__ == "__main__":
    main()
