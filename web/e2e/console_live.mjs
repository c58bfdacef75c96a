#!/usr/bin/env node
// End-to-end test of a live console: the page draws pheromones, lists the
// swarm's UAVs, kills one through its button and sees it die, adds a pop-up
// obstacle by clicking the map and sees the obstacle layer react.
//
//   node console_live.mjs --url 'http://127.0.0.1:8080/?token=T' --uavs 4 \
//        --kill-uav 1 --lease-ms 1000 --screenshot out.png --timeout-s 60
//
// Prints a one-line JSON summary on stdout and exits 0, or says what failed
// on stderr and exits 1.
import { fail, launch, log, openConsole, parseFlags, pollPage, sleep } from "./lib.mjs";

const USAGE = `usage: console_live.mjs --url URL [--uavs N] [--kill-uav ID] [--lease-ms MS]
                        [--screenshot PATH] [--timeout-s S] [--no-obstacle] [--heat-layer L]
  --url URL        the console's URL with ?token=
  --uavs N         the UAV table must have exactly N rows
  --kill-uav ID    click that UAV's kill button; its row must turn dead within lease + 5 s
  --lease-ms MS    the swarm's liveliness lease (default 1000)
  --screenshot P   save a PNG of the page at the end
  --timeout-s S    how long to wait for each step (default 60)
  --no-obstacle    skip the pop-up obstacle step
  --heat-layer L   look for drawn pheromone on layer L only (default: the page's
                   first layer, then the others in turn, a few seconds each)`;

const flags = parseFlags(
  process.argv.slice(2),
  { url: "string", uavs: "number", "kill-uav": "number", "lease-ms": "number", screenshot: "string", "timeout-s": "number", "no-obstacle": "bool", "heat-layer": "string" },
  USAGE,
);
if (!flags.url) fail(`--url is required\n${USAGE}`);
const timeoutMs = (flags["timeout-s"] ?? 60) * 1000;
const leaseMs = flags["lease-ms"] ?? 1000;
const summary = { ok: false, url: flags.url.replace(/token=[^&]*/, "token=…") };
const t0 = Date.now();

const { page, close, pageErrors } = await launch();

// 1. The page loads and receives frames.
log(`loading ${summary.url}`);
await openConsole(page, flags.url, timeoutMs);
const info = await page.evaluate(() => window.pheromesh.info);
if (info.mode !== "live") await fail(`the console is in ${info.mode} mode, not live`);
summary.scenario = info.scenario.name;
log(`first frame after ${Date.now() - t0} ms (scenario ${info.scenario.name}, ${info.scenario.width}x${info.scenario.height})`);

// 2. The heat map shows pheromone: pixels of the colour scale above its
// bottom, not the background, not the grey of missing tiles. Fields start
// empty and not every layer fills at once: stay a few seconds on each layer,
// the page's first one first, until one shows pheromone or the time is up.
const countHeat = () => {
  const c = document.getElementById("heatmap");
  const p = window.pheromesh.palette;
  const d = c.getContext("2d").getImageData(0, 0, c.width, c.height).data;
  const key = (r, g, b) => (r << 16) | (g << 8) | b;
  const warm = new Set();
  for (let q = 8; q < 256; q++) warm.add(key(...p.lut[q]));
  const bg = key(...p.background);
  const grey = key(...p.noData);
  let heat = 0;
  let background = 0;
  let noData = 0;
  for (let i = 0; i < d.length; i += 4) {
    const k = key(d[i], d[i + 1], d[i + 2]);
    if (warm.has(k)) heat++;
    else if (k === bg) background++;
    else if (k === grey) noData++;
  }
  const cell = c.width / window.pheromesh.info.scenario.width;
  const need = Math.max(16, Math.round(cell * cell));
  const m = window.pheromesh.model;
  return { ok: heat >= need, heat, need, background, noData, total: d.length / 4, drawn: window.pheromesh.drawn, layer: m.layerIndex, layerName: m.layerName };
};
const layerNames = info.scenario.layers;
const heatEnd = Date.now() + timeoutMs;
const perLayerMs = Math.max(4000, Math.min(15000, timeoutMs / (2 * Math.max(1, layerNames.length))));
let heatLayer = flags["heat-layer"] !== undefined ? layerNames.indexOf(flags["heat-layer"]) : await page.$eval("#layer", (s) => Number(s.value));
if (heatLayer < 0) await fail(`--heat-layer ${flags["heat-layer"]}: no such layer (${layerNames.join(", ")})`);
let heat = null;
const tried = [];
for (;;) {
  if ((await page.$eval("#layer", (s) => Number(s.value))) !== heatLayer) await page.selectOption("#layer", String(heatLayer));
  const left = heatEnd - Date.now();
  // The page asks for the layer complete; wait for it.
  await pollPage(page, (li) => ({ ok: window.pheromesh.model.layerIndex === li }), heatLayer, Math.min(5000, Math.max(0, left)), 100);
  heat = await pollPage(page, countHeat, null, Math.max(0, Math.min(perLayerMs, left)), 500);
  tried.push(`${layerNames[heatLayer]}: ${heat.heat ?? 0} px`);
  if (heat.ok || Date.now() >= heatEnd || flags["heat-layer"] !== undefined) break;
  heatLayer = (heatLayer + 1) % layerNames.length;
}
if (!heat.ok) {
  await fail(
    `the heat map stayed blank for ${timeoutMs / 1000} s (${tried.join(", ")}): last ${heat.heat} pixels of pheromone colour (need ${heat.need}), ` +
      `${heat.noData} grey (tiles not received), ${heat.background} background, of ${heat.total}; ${heat.drawn} draws`,
  );
}
summary.heat_pixels = heat.heat;
summary.heat_layer = heat.layerName;
log(`heat map drawn on layer ${heat.layerName}: ${heat.heat} pixels of pheromone colour, ${heat.noData} grey`);

// 3. The UAV table has a row per UAV.
if (flags.uavs !== undefined) {
  const n = flags.uavs;
  const rows = await pollPage(
    page,
    (n) => {
      const count = document.querySelectorAll("#uavs tr[data-uav]").length;
      return { ok: count >= n, count };
    },
    n,
    timeoutMs,
  );
  await sleep(500);
  const count = await page.evaluate(() => document.querySelectorAll("#uavs tr[data-uav]").length);
  if (count !== n) {
    const ids = await page.evaluate(() => [...document.querySelectorAll("#uavs tr[data-uav]")].map((r) => r.dataset.uav).join(","));
    await fail(`the UAV table has ${count} rows (ids ${ids || "none"}), expected ${n}${rows.timedOut ? ` (waited ${timeoutMs / 1000} s)` : ""}`);
  }
  summary.uav_rows = count;
  log(`UAV table: ${count} rows`);
}

// 4. Kill a UAV with its button; its row must go dead (maybe stale first).
if (flags["kill-uav"] !== undefined) {
  const id = flags["kill-uav"];
  const sel = `button[data-action="kill_uav"][data-uav="${id}"]`;
  const row = `#uavs tr[data-uav="${id}"]`;
  const btn = await page.$(sel);
  if (!btn) await fail(`no kill button for UAV ${id} (${sel})`);
  if (await btn.isDisabled()) await fail(`the kill button of UAV ${id} is disabled: ${await btn.getAttribute("title")}`);
  const before = await page.$eval(row, (r) => r.dataset.liveness).catch(() => null);
  if (before !== "alive") await fail(`UAV ${id} is '${before}' before the kill, not alive`);
  const clickedAt = Date.now();
  await btn.click();
  const seen = ["alive"];
  const limit = leaseMs + 5000;
  let state = before;
  while (Date.now() - clickedAt < limit) {
    state = await page.$eval(row, (r) => r.dataset.liveness).catch(() => "gone");
    if (seen[seen.length - 1] !== state) seen.push(state);
    if (state === "dead") break;
    await sleep(100);
  }
  const cmd = await page.evaluate(() => window.pheromesh.lastCommand);
  const status = await page.$eval("#status", (s) => s.textContent);
  if (!cmd || !cmd.ok) await fail(`kill uav ${id} was refused: ${status}`);
  if (state !== "dead") await fail(`UAV ${id}'s row went ${seen.join(" → ")} in ${limit} ms, never dead (command said: ${status})`);
  const bad = seen.filter((s) => !["alive", "stale", "dead"].includes(s));
  if (bad.length > 0) await fail(`UAV ${id}'s row went ${seen.join(" → ")}`);
  summary.kill = { uav: id, ms_to_dead: Date.now() - clickedAt, states: seen, message: cmd.message };
  log(`UAV ${id}: ${seen.join(" → ")} in ${summary.kill.ms_to_dead} ms`);
}

// 5. Pop-up obstacle next to a live UAV, on the obstacle layer.
if (!flags["no-obstacle"]) {
  const layerIndex = await page.evaluate(() => [...document.querySelectorAll("#layer option")].findIndex((o) => o.textContent === "obstacle"));
  if (layerIndex < 0) {
    const names = await page.evaluate(() => [...document.querySelectorAll("#layer option")].map((o) => o.textContent).join(", "));
    await fail(`the layer picker has no 'obstacle' layer (it has: ${names})`);
  }
  await page.selectOption("#layer", { label: "obstacle" });
  const loaded = await pollPage(
    page,
    (li) => {
      const f = window.pheromesh.frame;
      const s = window.pheromesh.layerSum();
      return { ok: f && f.layer && f.layer.index === li && s && s.layer === li && s.tiles > 0, tiles: s ? s.tiles : 0 };
    },
    layerIndex,
    timeoutMs,
  );
  if (!loaded.ok) await fail(`the obstacle layer never arrived after picking it (${loaded.tiles} tiles)`);
  // The page's state is built from the frames' `obstacles` (a delta may leave them out when unchanged).
  const base = await page.evaluate(() => ({ sum: window.pheromesh.layerSum(), popups: window.pheromesh.model.obstacles.filter((o) => o.popup).length }));

  // Candidates: live UAVs, those flying away from the east first (the console
  // refuses an obstacle that would cover a flying UAV, and a UAV heading east
  // may be inside the rectangle by the time the command arrives).
  const killed = flags["kill-uav"];
  const candidates = await page.evaluate((killed) => {
    const info = window.pheromesh.info.scenario;
    const rank = [2, 1, 0, 0, 0, 0, 1, 2]; // by heading: 3, 4, 5 best; 7, 0, 1 last
    return window.pheromesh.frame.uavs
      .filter((u) => u.liveness === "alive" && u.id !== killed)
      .sort((a, b) => rank[a.heading & 7] - rank[b.heading & 7] || a.id - b.id)
      .map((u) => {
        let x = Math.round(u.x) + 2;
        if (x >= info.width) x = Math.round(u.x) - 2; // no room east: west
        return { uav: u.id, heading: u.heading, ux: u.x, uy: u.y, x: Math.min(info.width - 1, Math.max(0, x)), y: Math.min(info.height - 1, Math.max(0, Math.round(u.y))) };
      });
  }, killed ?? -1);
  if (candidates.length === 0) await fail("no live UAV to put an obstacle next to");

  const tool = await page.$("#tool-obstacle");
  if (await tool.isDisabled()) await fail(`#tool-obstacle is disabled: ${await tool.getAttribute("title")}`);
  if ((await tool.getAttribute("aria-pressed")) !== "true") await tool.click();
  const onMap = (p) => page.evaluate(({ x, y }) => document.elementFromPoint(x, y)?.id === "heatmap", p);
  let target = null;
  let sent = null;
  let clickedAt = 0;
  const refusals = [];
  for (const c of candidates.slice(0, 3)) {
    // The kill button may have scrolled the map away: the map is whole at the
    // top of the page; the point must land on the canvas, not on the header.
    await page.evaluate(() => window.scrollTo(0, 0));
    let pt = await page.evaluate(({ x, y }) => window.pheromesh.cellToClient(x, y), c);
    if (!(await onMap(pt))) {
      await page.$eval("#heatmap", (el) => el.scrollIntoView({ block: "center" }));
      pt = await page.evaluate(({ x, y }) => window.pheromesh.cellToClient(x, y), c);
      if (!(await onMap(pt))) await fail(`cell (${c.x}, ${c.y}) is at (${pt.x}, ${pt.y}) in the viewport, not on the heat map`);
    }
    const back = await page.evaluate(({ x, y }) => window.pheromesh.clientToCell(x, y), pt);
    if (!back || back.x !== c.x || back.y !== c.y) {
      await fail(`cellToClient(${c.x}, ${c.y}) = (${pt.x}, ${pt.y}) maps back to ${JSON.stringify(back)}`);
    }
    await page.evaluate(() => {
      window.pheromesh.lastCommand = null;
    });
    // The obstacle layer in the rectangle about to be sent, before the click
    // (the page centres a w x h rectangle on the clicked cell).
    c.before = await page.evaluate(({ x, y }) => {
      const w = Number(document.querySelector("#obstacle-w").value) || 3;
      const h = Number(document.querySelector("#obstacle-h").value) || 3;
      return window.pheromesh.rectSum(x - Math.floor(w / 2), y - Math.floor(h / 2), w, h);
    }, c);
    clickedAt = Date.now();
    await page.mouse.click(pt.x, pt.y);
    sent = await pollPage(page, () => ({ ok: window.pheromesh.lastCommand !== null, c: window.pheromesh.lastCommand }), null, 10000, 100);
    if (!sent.ok) await fail(`clicking the map with #tool-obstacle sent no command (status: ${await page.$eval("#status", (s) => s.textContent)})`);
    if (sent.c.body.kind !== "obstacle") await fail(`clicking the map with #tool-obstacle sent ${JSON.stringify(sent.c.body)}`);
    if (sent.c.ok) {
      target = c;
      break;
    }
    refusals.push(`next to uav ${c.uav}: HTTP ${sent.c.status} ${sent.c.message}`);
    log(`obstacle refused ${refusals[refusals.length - 1]}; trying another UAV`);
    if (sent.c.status !== 409 && sent.c.status !== 400) break;
  }
  if (!target) await fail(`the obstacle command was refused: ${refusals.join("; ")}`);
  const gained = await pollPage(
    page,
    (n) => {
      const obs = window.pheromesh.model.obstacles;
      const c = obs.filter((o) => o.popup).length;
      return { ok: c > n, count: c, obstacles: obs };
    },
    base.popups,
    timeoutMs,
  );
  if (!gained.ok) await fail(`frame.obstacles gained no pop-up obstacle in ${timeoutMs / 1000} s (still ${gained.count})`);
  // The UAV next to the pop-up senses it and deposits obstacle marks on its
  // cells (Shao 2020 eq. (3)): the obstacle layer must rise inside the
  // rectangle itself, not just anywhere (diffusion and evaporation move the
  // whole layer all the time).
  const rose = await pollPage(
    page,
    (a) => {
      const s = window.pheromesh.layerSum();
      const r = window.pheromesh.rectSum(a.body.x0, a.body.y0, a.body.w, a.body.h);
      return { ok: s.name === "obstacle" && r !== null && r.q >= a.before.q + 2 && r.value > a.before.value, sum: s, rect: r };
    },
    { body: sent.c.body, before: target.before ?? { q: 0, value: 0 } },
    timeoutMs,
    250,
  );
  if (!rose.ok) {
    await fail(
      `the obstacle layer did not rise inside the pop-up obstacle at (${sent.c.body.x0}, ${sent.c.body.y0}) ` +
        `${sent.c.body.w}x${sent.c.body.h} within ${timeoutMs / 1000} s: sum of q there ${target.before?.q} -> ${rose.rect?.q}`,
    );
  }
  const local = await page.evaluate((b) => window.pheromesh.rectSum(b.x0, b.y0, b.w, b.h), sent.c.body);
  summary.obstacle = {
    near_uav: target.uav,
    refused: refusals,
    q_sum_in_rect: [target.before?.q ?? null, local.q],
    rect: [sent.c.body.x0, sent.c.body.y0, sent.c.body.w, sent.c.body.h],
    ms_to_layer_change: Date.now() - clickedAt,
    q_sum: [base.sum.q, rose.sum.q],
    value_sum: [Number(base.sum.value.toFixed(4)), Number(rose.sum.value.toFixed(4))],
  };
  log(`pop-up obstacle ${JSON.stringify(summary.obstacle.rect)} near UAV ${target.uav}: obstacle layer q sum ${base.sum.q} → ${rose.sum.q}`);
  await sleep(300); // let the page draw the last frame before the screenshot
}

if (flags.screenshot) {
  await page.screenshot({ path: flags.screenshot, fullPage: true });
  summary.screenshot = flags.screenshot;
}
if (pageErrors.length > 0) await fail(`the page reported errors:\n  ${pageErrors.join("\n  ")}`);

const stats = await page.evaluate(() => ({ ...window.pheromesh.stats, drawn: window.pheromesh.drawn }));
summary.ok = true;
summary.frames = stats.frames;
summary.updatesPerSecond = Number(stats.updatesPerSecond.toFixed(2));
summary.bytesPerSecond = Math.round(stats.bytesPerSecond);
summary.bytes = stats.bytes;
summary.drawn = stats.drawn;
summary.seconds = Number(((Date.now() - t0) / 1000).toFixed(1));
await close();
console.log(JSON.stringify(summary));
process.exit(0);
