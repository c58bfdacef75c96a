// A stand-in MAVLink ground-control station for the integration test
// Mavlink.* (tests/integration/test_mavlink.cpp, docs/mavlink.md): it listens
// where `pheromesh run --mavlink udp:127.0.0.1:PORT` streams, decodes every
// frame with node-mavlink and mavlink-mappings (a MAVLink library nobody here
// wrote), and steers the swarm as an operator would:
//
//   1. waits until every UAV has a HEARTBEAT stream (a quadrotor, ACTIVE), a
//      GLOBAL_POSITION_INT and an ADSB_VEHICLE (callsign PH<id>);
//   2. sends an unsigned COMMAND_LONG pause: no COMMAND_ACK may come back and
//      the UAVs must keep flying (their positions change);
//   3. sends the same pause signed by node-mavlink with the key in
//      --key-file: an ACCEPTED COMMAND_ACK, heartbeats turn STANDBY and the
//      positions stop changing;
//   4. sends a signed continue: ACCEPTED, and the UAVs fly again;
//   5. with --stop, sends a signed disarm (MAV_CMD_COMPONENT_ARM_DISARM, 0):
//      ACCEPTED, and the ground station ends the run (its frames stop).
//
// With --replay 1 it listens to `pheromesh replay --mavlink` instead, which
// holds no key: after step 1 it sends an unsigned pause (ACCEPTED, STANDBY
// heartbeats, the positions stand still), an unsigned continue (ACCEPTED,
// the UAVs move again) and an unsigned disarm (UNSUPPORTED: the stream goes
// on).
//
// Writes --report (JSON: every GLOBAL_POSITION_INT decoded, the counters) and
// exits 0 if every check held, 1 with the reason otherwise.
import dgram from "node:dgram";
import fs from "node:fs";
import { PassThrough } from "node:stream";
import {
  MavLinkPacketParser,
  MavLinkPacketSplitter,
  MavLinkProtocolV2,
  common,
  minimal,
} from "node-mavlink";

const usage =
  "node mavlink_gcs.mjs --port P --uavs N (--key-file FILE | --replay 1) --report FILE [--timeout S] [--stop 1]";
const flags = { timeout: "60", stop: "0", replay: "0" };
for (let i = 2; i < process.argv.length; i += 2) {
  const name = process.argv[i].replace(/^--/, "");
  if (!["port", "uavs", "key-file", "report", "timeout", "stop", "replay"].includes(name) ||
      i + 1 >= process.argv.length) {
    console.error(usage);
    process.exit(2);
  }
  flags[name] = process.argv[i + 1];
}
const replay = flags.replay === "1";
for (const f of ["port", "uavs", "report", ...(replay ? [] : ["key-file"])]) {
  if (flags[f] === undefined) {
    console.error(usage);
    process.exit(2);
  }
}
const uavs = Number(flags.uavs);
const t0 = Date.now();
const deadline = t0 + Number(flags.timeout) * 1000;
const log = (...a) => console.log(`[gcs ${((Date.now() - t0) / 1000).toFixed(1)} s]`, ...a);

const REGISTRY = { ...minimal.REGISTRY, ...common.REGISTRY };
const GROUND_SYSID = 251;
const MAV_TYPE_QUADROTOR = 2;
const MAV_STATE_STANDBY = 3;
const MAV_STATE_ACTIVE = 4;
const MAV_CMD_DO_PAUSE_CONTINUE = 193;
const MAV_CMD_COMPONENT_ARM_DISARM = 400;
const MAV_RESULT_ACCEPTED = 0;
const MAV_RESULT_UNSUPPORTED = 3;

// What was heard.
const heard = {
  crcErrors: 0,
  packets: 0,
  byMsg: {},
  heartbeats: new Map(), // sysid -> { count, type, status }
  positions: [], // { sysid, lat, lon, alt, relativeAlt, hdg, t }
  adsb: new Map(), // callsign -> { icao, lat, lon }
  acks: [], // { command, result, t }
  groundAddress: null,
};

const input = new PassThrough();
const splitter = new MavLinkPacketSplitter({}, { onCrcError: () => heard.crcErrors++ });
const reader = input.pipe(splitter).pipe(new MavLinkPacketParser());
reader.on("data", (packet) => {
  heard.packets++;
  const clazz = REGISTRY[packet.header.msgid];
  if (!clazz) return;
  const name = clazz.MSG_NAME;
  heard.byMsg[name] = (heard.byMsg[name] || 0) + 1;
  const m = packet.protocol.data(packet.payload, clazz);
  const sysid = packet.header.sysid;
  const t = Date.now();
  if (name === "HEARTBEAT" && sysid !== GROUND_SYSID) {
    const h = heard.heartbeats.get(sysid) || { count: 0 };
    heard.heartbeats.set(sysid, { count: h.count + 1, type: m.type, status: m.systemStatus, t });
  } else if (name === "GLOBAL_POSITION_INT") {
    heard.positions.push({ sysid, lat: m.lat, lon: m.lon, alt: m.alt, relativeAlt: m.relativeAlt, hdg: m.hdg, t });
  } else if (name === "ADSB_VEHICLE") {
    heard.adsb.set(m.callsign, { icao: m.ICAOAddress, lat: m.lat, lon: m.lon });
  } else if (name === "COMMAND_ACK") {
    heard.acks.push({ command: m.command, result: m.result, t });
  }
});

const socket = dgram.createSocket("udp4");
socket.on("message", (buf, rinfo) => {
  heard.groundAddress = { address: rinfo.address, port: rinfo.port };
  input.write(buf);
});

const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
async function until(what, cond) {
  while (!cond()) {
    if (Date.now() > deadline) throw new Error(`timed out waiting for ${what}`);
    await sleep(50);
  }
}

let seq = 0;
function commandLong(param1, command = MAV_CMD_DO_PAUSE_CONTINUE) {
  const c = new common.CommandLong();
  c.targetSystem = GROUND_SYSID;
  c.targetComponent = 1;
  c.command = command;
  c._param1 = param1;
  return c;
}
function send(buffer) {
  const g = heard.groundAddress;
  return new Promise((resolve, reject) =>
    socket.send(buffer, g.port, g.address, (err) => (err ? reject(err) : resolve())),
  );
}
async function sendUnsigned(param1) {
  const protocol = new MavLinkProtocolV2(255, 190);
  await send(protocol.serialize(commandLong(param1), seq++ & 255));
}
async function sendSigned(param1, key, command = MAV_CMD_DO_PAUSE_CONTINUE) {
  const protocol = new MavLinkProtocolV2(255, 190, MavLinkProtocolV2.IFLAG_SIGNED);
  await send(protocol.sign(protocol.serialize(commandLong(param1, command), seq++ & 255), 1, key));
}

// The newest position of every UAV system.
function latest() {
  const out = new Map();
  for (const p of heard.positions) out.set(p.sysid, p);
  return out;
}
// How many UAVs moved between two snapshots of latest().
function moved(a, b) {
  let n = 0;
  for (const [sysid, p] of b) {
    const q = a.get(sysid);
    if (q && (q.lat !== p.lat || q.lon !== p.lon)) n++;
  }
  return n;
}
function expect(cond, what) {
  if (!cond) throw new Error(what);
  log("ok:", what);
}

async function main() {
  await new Promise((r) => socket.bind(Number(flags.port), "127.0.0.1", r));
  log(`listening on udp:127.0.0.1:${flags.port}`);
  const systems = [...Array(uavs).keys()].map((i) => i + 1);
  await until("a HEARTBEAT, a GLOBAL_POSITION_INT and an ADSB_VEHICLE of every UAV", () => {
    const pos = latest();
    return systems.every((s) => heard.heartbeats.has(s) && pos.has(s) && heard.adsb.has(`PH${s - 1}`));
  });
  for (const s of systems) {
    const h = heard.heartbeats.get(s);
    expect(h.type === MAV_TYPE_QUADROTOR && h.status === MAV_STATE_ACTIVE, `system ${s} is an ACTIVE quadrotor`);
  }
  expect(heard.adsb.size === uavs, `ADSB_VEHICLE of all ${uavs} UAVs (${[...heard.adsb.keys()].join(" ")})`);
  if (replay) {
    await steerReplay(systems);
  } else {
    await steerSwarm(systems);
  }
  expect(heard.crcErrors === 0, `no CRC error in ${heard.packets} packets`);
  expect(splitter.invalidPackages === 0 && splitter.unknownPackagesCount === 0,
    `node-mavlink found no invalid or unknown packet (valid ${splitter.validPackages})`);
}

// --replay 1: unsigned pause and continue steer the playback; disarm is unsupported.
async function steerReplay(systems) {
  await sendUnsigned(0);
  await until("the COMMAND_ACK of the pause", () => heard.acks.length >= 1);
  expect(heard.acks[0].command === MAV_CMD_DO_PAUSE_CONTINUE && heard.acks[0].result === MAV_RESULT_ACCEPTED,
    "the unsigned pause of a replay is ACCEPTED");
  await until("STANDBY heartbeats", () =>
    systems.every((s) => heard.heartbeats.get(s).status === MAV_STATE_STANDBY && heard.heartbeats.get(s).t > heard.acks[0].t));
  let before = latest();
  await sleep(1500);
  expect(moved(before, latest()) === 0, "no UAV moves while the playback is paused");
  await sendUnsigned(1);
  await until("the COMMAND_ACK of the continue", () => heard.acks.length >= 2);
  expect(heard.acks[1].result === MAV_RESULT_ACCEPTED, "the unsigned continue is ACCEPTED");
  before = latest();
  await sleep(1500);
  expect(moved(before, latest()) > 0, "the UAVs move again after continue");
  const c = new common.CommandLong();
  c.targetSystem = GROUND_SYSID;
  c.targetComponent = 1;
  c.command = MAV_CMD_COMPONENT_ARM_DISARM;
  c._param1 = 0;
  await send(new MavLinkProtocolV2(255, 190).serialize(c, seq++ & 255));
  await until("the COMMAND_ACK of the disarm", () => heard.acks.length >= 3);
  expect(heard.acks[2].command === MAV_CMD_COMPONENT_ARM_DISARM && heard.acks[2].result === MAV_RESULT_UNSUPPORTED,
    "a replay's disarm is UNSUPPORTED");
  const packets = heard.packets;
  await sleep(1000);
  expect(heard.packets > packets, "the stream goes on after the disarm");
}

async function steerSwarm(systems) {
  // 2. Unsigned pause: refused, nothing stops.
  const key = Buffer.from(fs.readFileSync(flags["key-file"], "utf8").trim(), "hex");
  expect(key.length === 32, "the MAVLink key is 32 bytes");
  await sendUnsigned(0);
  let before = latest();
  await sleep(1500);
  expect(heard.acks.length === 0, "no COMMAND_ACK to an unsigned pause");
  expect(moved(before, latest()) > 0, "the UAVs fly on after an unsigned pause");

  // 3. Signed pause: accepted, the swarm stops.
  await sendSigned(0, key);
  await until("the COMMAND_ACK of the signed pause", () => heard.acks.length >= 1);
  expect(heard.acks[0].command === MAV_CMD_DO_PAUSE_CONTINUE && heard.acks[0].result === MAV_RESULT_ACCEPTED,
    "the signed pause is ACCEPTED");
  await until("STANDBY heartbeats", () =>
    systems.every((s) => heard.heartbeats.get(s).status === MAV_STATE_STANDBY && heard.heartbeats.get(s).t > heard.acks[0].t));
  await sleep(1000); // the pause reaches every UAV; the last positions before it arrive
  before = latest();
  await sleep(1500);
  expect(moved(before, latest()) === 0, "no UAV moves while the swarm is paused");

  // 4. Signed continue: accepted, the swarm flies again.
  await sleep(5); // a later signing timestamp than the pause's
  await sendSigned(1, key);
  await until("the COMMAND_ACK of the signed continue", () => heard.acks.length >= 2);
  expect(heard.acks[1].result === MAV_RESULT_ACCEPTED, "the signed continue is ACCEPTED");
  before = latest();
  await sleep(1500);
  expect(moved(before, latest()) > 0, "the UAVs fly again after continue");

  // 5. Signed disarm: the run ends.
  if (flags.stop === "1") {
    await sleep(5);
    await sendSigned(0, key, MAV_CMD_COMPONENT_ARM_DISARM);
    await until("the COMMAND_ACK of the signed disarm", () => heard.acks.length >= 3);
    expect(heard.acks[2].command === MAV_CMD_COMPONENT_ARM_DISARM && heard.acks[2].result === MAV_RESULT_ACCEPTED,
      "the signed disarm (stop) is ACCEPTED");
    let last = heard.packets;
    let quietSince = Date.now();
    await until("the ground station to fall silent (the run ended)", () => {
      if (heard.packets !== last) {
        last = heard.packets;
        quietSince = Date.now();
      }
      return Date.now() - quietSince > 2000;
    });
    log("ok: the stream ended after the stop");
  }
}

let failure = null;
try {
  await main();
} catch (e) {
  failure = e.message;
}
const report = {
  ok: failure === null,
  failure,
  crc_errors: heard.crcErrors,
  packets: heard.packets,
  valid_packets: splitter.validPackages,
  invalid_packets: splitter.invalidPackages,
  unknown_packets: splitter.unknownPackagesCount,
  by_message: heard.byMsg,
  heartbeat_systems: [...heard.heartbeats.keys()].sort((a, b) => a - b),
  adsb: Object.fromEntries(heard.adsb),
  acks: heard.acks,
  positions: heard.positions,
};
fs.writeFileSync(flags.report, JSON.stringify(report, null, 1));
socket.close();
if (failure) {
  log("FAILED:", failure);
  process.exit(1);
}
log("every check held");
