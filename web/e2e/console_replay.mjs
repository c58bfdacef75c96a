#!/usr/bin/env node
// End-to-end test of a replay console: moves the time slider to the end and
// checks that the page then shows what the live console showed at the end of
// the run (a live `GET /api/frame?since=0` answer saved by the test harness).
//
//   node console_replay.mjs --url http://127.0.0.1:8081/ --expect-json final.json \
//        --screenshot replay.png [--timeout-s 60]
//
// Compares the UAVs (id, x, y, liveness), the targets, the obstacles and the
// tiles of the expected answer's layer. Prints a one-line JSON summary and
// exits 0, or lists the differences on stderr and exits 1.
import fs from "node:fs";
import { fail, launch, log, openConsole, parseFlags, pollPage, sleep } from "./lib.mjs";

const USAGE = `usage: console_replay.mjs --url URL --expect-json PATH [--screenshot PATH] [--timeout-s S]`;
const flags = parseFlags(process.argv.slice(2), { url: "string", "expect-json": "string", screenshot: "string", "timeout-s": "number" }, USAGE);
if (!flags.url || !flags["expect-json"]) fail(`--url and --expect-json are required\n${USAGE}`);
const timeoutMs = (flags["timeout-s"] ?? 60) * 1000;

let expected;
try {
  expected = JSON.parse(fs.readFileSync(flags["expect-json"], "utf8"));
} catch (e) {
  fail(`cannot read ${flags["expect-json"]}: ${e.message}`);
}
if (!expected || typeof expected !== "object" || !Array.isArray(expected.uavs)) fail(`${flags["expect-json"]} is not a /api/frame answer`);

const { page, close, pageErrors } = await launch();
log(`loading ${flags.url}`);
await openConsole(page, flags.url, timeoutMs);
const info = await page.evaluate(() => window.pheromesh.info);
if (info.mode !== "replay") await fail(`the console is in ${info.mode} mode, not replay`);
if (!info.replay) await fail("/api/info of the replay has no `replay` object");

// The expected answer's layer.
const layer = expected.layer ? expected.layer.index : 0;
const current = await page.$eval("#layer", (s) => Number(s.value));
if (current !== layer) {
  const ok = await page.$(`#layer option[value="${layer}"]`);
  if (!ok) await fail(`the layer picker has no layer ${layer}`);
  await page.selectOption("#layer", String(layer));
}

// Slider to the end (End key, as a person would), then wait for that frame.
const slider = await page.$("#slider");
if (!slider) await fail("the replay page has no #slider");
await slider.focus();
await page.keyboard.press("End");
const max = await page.$eval("#slider", (s) => ({ value: s.valueAsNumber, max: Number(s.max) }));
if (Math.abs(max.value - max.max) > 1e-9) await fail(`the slider is at ${max.value} after End, its max is ${max.max}`);
if (Math.abs(max.max - info.replay.t1_s) > 1e-6) await fail(`the slider's max ${max.max} is not replay.t1_s ${info.replay.t1_s}`);
const got = await pollPage(
  page,
  ({ t, layer }) => {
    const p = window.pheromesh;
    const f = p.frame;
    return { ok: p.frameT !== null && Math.abs(p.frameT - t) < 1e-9 && !p.busy() && f && f.layer && f.layer.index === layer, frameT: p.frameT };
  },
  { t: max.max, layer },
  timeoutMs,
  100,
);
if (!got.ok) await fail(`the page never showed the frame at t=${max.max} (last asked t=${got.frameT})`);
await sleep(300); // drawn
const frame = await page.evaluate(() => window.pheromesh.frame);
log(`frame at t=${max.max}: version ${frame.version}, t_s ${frame.t_s}, ${frame.uavs.length} UAVs`);

// Compare.
const diffs = [];
const near = (a, b) => Math.abs(Number(a) - Number(b)) <= 1e-6;
const byKey = (list, key) => new Map((list ?? []).map((x) => [key(x), x]));

const gu = byKey(frame.uavs, (u) => u.id);
const eu = byKey(expected.uavs, (u) => u.id);
for (const [id, e] of eu) {
  const g = gu.get(id);
  if (!g) {
    diffs.push(`uav ${id}: missing in the replay`);
    continue;
  }
  if (!near(g.x, e.x) || !near(g.y, e.y)) diffs.push(`uav ${id}: at (${g.x}, ${g.y}), live (${e.x}, ${e.y})`);
  if (g.liveness !== e.liveness) diffs.push(`uav ${id}: ${g.liveness}, live ${e.liveness}`);
}
for (const id of gu.keys()) if (!eu.has(id)) diffs.push(`uav ${id}: in the replay only`);

const targetFields = ["x", "y", "status", "found_by", "found_tick", "popup"];
const gt = byKey(frame.targets, (t) => t.index);
const et = byKey(expected.targets, (t) => t.index);
for (const [i, e] of et) {
  const g = gt.get(i);
  if (!g) {
    diffs.push(`target ${i}: missing in the replay`);
    continue;
  }
  for (const k of targetFields) {
    if (k in e && JSON.stringify(g[k]) !== JSON.stringify(e[k])) diffs.push(`target ${i}: ${k} ${JSON.stringify(g[k])}, live ${JSON.stringify(e[k])}`);
  }
}
for (const i of gt.keys()) if (!et.has(i)) diffs.push(`target ${i}: in the replay only`);

const obstacleKey = (o) => `${o.x0},${o.y0} ${o.w}x${o.h}${o.popup ? " popup" : ""}`;
const go = (frame.obstacles ?? []).map(obstacleKey).sort();
const eo = (expected.obstacles ?? []).map(obstacleKey).sort();
if (JSON.stringify(go) !== JSON.stringify(eo)) diffs.push(`obstacles: [${go.join("; ")}], live [${eo.join("; ")}]`);

if (expected.layer) {
  const gl = frame.layer ?? { tiles: [] };
  if (gl.name !== expected.layer.name) diffs.push(`layer: ${gl.name}, live ${expected.layer.name}`);
  if (!near(gl.scale, expected.layer.scale)) diffs.push(`layer ${expected.layer.name}: scale ${gl.scale}, live ${expected.layer.scale}`);
  const tk = (t) => `${t.tx},${t.ty}`;
  const gtiles = byKey(gl.tiles, tk);
  const etiles = byKey(expected.layer.tiles, tk);
  for (const [k, e] of etiles) {
    const g = gtiles.get(k);
    if (!g) diffs.push(`tile ${k}: missing in the replay`);
    else if (g.x0 !== e.x0 || g.y0 !== e.y0 || g.w !== e.w || g.h !== e.h) diffs.push(`tile ${k}: rect ${g.x0},${g.y0} ${g.w}x${g.h}, live ${e.x0},${e.y0} ${e.w}x${e.h}`);
    else if (g.q !== e.q) {
      const a = Buffer.from(g.q, "base64");
      const b = Buffer.from(e.q, "base64");
      let n = 0;
      for (let i = 0; i < Math.max(a.length, b.length); i++) if (a[i] !== b[i]) n++;
      diffs.push(`tile ${k}: ${n} of ${e.w * e.h} cells differ`);
    }
  }
  for (const k of gtiles.keys()) if (!etiles.has(k)) diffs.push(`tile ${k}: in the replay only`);
  // The page decoded what it received.
  const held = await page.evaluate(() => window.pheromesh.layerSum());
  if (held.tiles !== gtiles.size) diffs.push(`the page holds ${held.tiles} tiles of the ${gtiles.size} received`);
}

if (flags.screenshot) await page.screenshot({ path: flags.screenshot, fullPage: true });
if (pageErrors.length > 0) diffs.push(...pageErrors.map((e) => `page error: ${e}`));
if (diffs.length > 0) {
  const shown = diffs.slice(0, 40);
  await fail(`the replay's last frame differs from ${flags["expect-json"]} in ${diffs.length} ways:\n  ${shown.join("\n  ")}${diffs.length > shown.length ? `\n  … and ${diffs.length - shown.length} more` : ""}`);
}
const stats = await page.evaluate(() => window.pheromesh.stats);
await close();
console.log(
  JSON.stringify({
    ok: true,
    t_s: max.max,
    version: frame.version,
    uavs: eu.size,
    targets: et.size,
    obstacles: eo.length,
    tiles: expected.layer ? expected.layer.tiles.length : 0,
    frames: stats.frames,
    screenshot: flags.screenshot ?? null,
  }),
);
process.exit(0);
