// Shared by the console's end-to-end scripts: flags, Debian's Chromium
// through playwright-core (never a downloaded browser), failing clearly.
import fs from "node:fs";
import os from "node:os";
import path from "node:path";
import { chromium } from "playwright-core";

export const CHROMIUM = process.env.PHEROMESH_CHROMIUM || "/usr/bin/chromium";

/**
 * Parses `--name value` and `--name=value` flags. `spec` maps each flag to
 * its kind: "string", "number" or "bool"; unknown flags are an error.
 */
export function parseFlags(argv, spec, usage) {
  const out = {};
  for (let i = 0; i < argv.length; i++) {
    const a = argv[i];
    if (a === "-h" || a === "--help") {
      console.log(usage);
      process.exit(0);
    }
    if (!a.startsWith("--")) fail(`unexpected argument '${a}'\n${usage}`);
    let name = a.slice(2);
    let value;
    const eq = name.indexOf("=");
    if (eq >= 0) {
      value = name.slice(eq + 1);
      name = name.slice(0, eq);
    }
    const kind = spec[name];
    if (!kind) fail(`unknown flag --${name}\n${usage}`);
    if (kind === "bool") {
      out[name] = value === undefined ? true : value !== "false" && value !== "0";
      continue;
    }
    if (value === undefined) {
      if (i + 1 >= argv.length) fail(`--${name} needs a value\n${usage}`);
      value = argv[++i];
    }
    if (kind === "number") {
      const n = Number(value);
      if (!Number.isFinite(n)) fail(`--${name} wants a number, got '${value}'`);
      out[name] = n;
    } else out[name] = value;
  }
  return out;
}

let cleanup = [];

/** Prints why and exits 1 (after closing the browser). */
export function fail(message) {
  console.error(`FAIL: ${message}`);
  if (cleanup.length === 0) process.exit(1);
  const tasks = cleanup;
  cleanup = [];
  setTimeout(() => process.exit(1), 10000).unref();
  Promise.allSettled(tasks.map((f) => f()))
    .catch(() => {})
    .finally(() => process.exit(1));
  // Do not run anything else of the caller meanwhile.
  return new Promise(() => {});
}

export function log(message) {
  console.error(`[e2e ${new Date().toISOString().slice(11, 23)}] ${message}`);
}

/** Starts Chromium with a fresh profile; returns { context, page, close }. */
export async function launch({ width = 1440, height = 1000 } = {}) {
  if (!fs.existsSync(CHROMIUM)) await fail(`no Chromium at ${CHROMIUM} (apt-get install chromium)`);
  const profile = fs.mkdtempSync(path.join(os.tmpdir(), "pheromesh-e2e-"));
  let context;
  try {
    context = await chromium.launchPersistentContext(profile, {
      executablePath: CHROMIUM,
      headless: true,
      viewport: { width, height },
      args: [
        "--no-sandbox",
        "--disable-gpu",
        "--disable-quic",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
      ],
    });
  } catch (e) {
    fs.rmSync(profile, { recursive: true, force: true });
    await fail(`could not start Chromium (${CHROMIUM}): ${e.message}`);
  }
  const close = async () => {
    try {
      await context.close();
    } finally {
      fs.rmSync(profile, { recursive: true, force: true });
    }
  };
  cleanup.push(close);
  const page = context.pages()[0] ?? (await context.newPage());
  const pageErrors = [];
  page.on("pageerror", (e) => pageErrors.push(String(e)));
  page.on("console", (m) => {
    if (m.type() !== "error") return;
    // A failed request is the server's answer (a 409, a dropped long poll):
    // the page shows it; the scripts judge what they need from the page.
    if (m.text().startsWith("Failed to load resource")) log(`page: ${m.text()}`);
    else pageErrors.push(`console: ${m.text()}`);
  });
  return { context, page, close, pageErrors };
}

/** Loads the page and waits for the console's first frame. */
export async function openConsole(page, url, timeoutMs) {
  try {
    const res = await page.goto(url, { waitUntil: "load", timeout: timeoutMs });
    if (!res || !res.ok()) await fail(`loading ${url}: HTTP ${res ? res.status() : "no answer"}`);
  } catch (e) {
    await fail(`loading ${url}: ${e.message.split("\n")[0]}`);
  }
  try {
    await page.waitForFunction(() => window.pheromesh && window.pheromesh.info, null, { timeout: timeoutMs });
  } catch {
    await fail(`the page at ${url} never got /api/info (window.pheromesh.info stayed empty)`);
  }
  try {
    await page.waitForFunction(() => window.pheromesh.frame, null, { timeout: timeoutMs, polling: 100 });
  } catch {
    await fail(`the page at ${url} never received a frame (window.pheromesh.frame stayed empty)`);
  }
}

/** Polls `f` (run in the page with `arg`) until it returns something truthy; null after the timeout. */
export async function pollPage(page, f, arg, timeoutMs, intervalMs = 200) {
  const end = Date.now() + timeoutMs;
  let last;
  for (;;) {
    last = await page.evaluate(f, arg);
    if (last && (last.ok === undefined || last.ok)) return last;
    if (Date.now() >= end) return { ...(typeof last === "object" && last ? last : { value: last }), ok: false, timedOut: true };
    await new Promise((r) => setTimeout(r, intervalMs));
  }
}

export const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
