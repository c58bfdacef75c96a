#!/usr/bin/env node
// Measures what a live console sends to one page: attaches, waits for the
// first frame, records for S seconds and prints
//   {"updates_per_s":…, "bytes_per_s":…, "frames":…, "avg_frame_bytes":…, …}
//
//   node console_measure.mjs --url 'http://127.0.0.1:8080/?token=T' --seconds 10
import { fail, launch, log, openConsole, parseFlags, sleep } from "./lib.mjs";

const USAGE = "usage: console_measure.mjs --url URL [--seconds S] [--timeout-s S]";
const flags = parseFlags(process.argv.slice(2), { url: "string", seconds: "number", "timeout-s": "number" }, USAGE);
if (!flags.url) fail(`--url is required\n${USAGE}`);
const seconds = flags.seconds ?? 10;
if (!(seconds > 0)) fail("--seconds must be > 0");
const timeoutMs = (flags["timeout-s"] ?? 60) * 1000;

const { page, close, pageErrors } = await launch();
await openConsole(page, flags.url, timeoutMs);
const sample = () =>
  page.evaluate(() => {
    const p = window.pheromesh;
    return { t: performance.now(), frames: p.stats.frames, answers: p.stats.answers, bytes: p.stats.bytes, drawn: p.drawn, renderMs: p.renderMs, version: p.frame ? p.frame.version : 0 };
  });
const a = await sample();
log(`recording ${seconds} s`);
await sleep(seconds * 1000);
const b = await sample();
if (pageErrors.length > 0) await fail(`the page reported errors:\n  ${pageErrors.join("\n  ")}`);
await close();
const dt = (b.t - a.t) / 1000;
const frames = b.frames - a.frames;
const bytes = b.bytes - a.bytes;
console.log(
  JSON.stringify({
    seconds: Number(dt.toFixed(3)),
    updates_per_s: Number((frames / dt).toFixed(3)),
    bytes_per_s: Math.round(bytes / dt),
    frames,
    answers: b.answers - a.answers,
    avg_frame_bytes: frames > 0 ? Math.round(bytes / frames) : 0,
    versions: b.version - a.version,
    draws_per_s: Number(((b.drawn - a.drawn) / dt).toFixed(3)),
    render_ms: Number(b.renderMs.toFixed(3)),
  }),
);
process.exit(0);
