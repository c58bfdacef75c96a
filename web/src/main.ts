// The pheromesh web console: fetches /api/info, then follows the console's
// frames (long poll in a live console, a time slider in a replay), draws the
// heat map, plots and tables, and posts commands with the page's token.
import { LUT_RGB, css } from "./colormap";
import { $, fmt, fmtValue, setEnabled, setText } from "./dom";
import { HeatMap, PALETTE } from "./heatmap";
import { Model } from "./model";
import { LinePlot } from "./plots";
import { NetStats, type StatsView } from "./stats";
import { CommandLog, type ControlState, RegionTable, TargetsPanel, UavTable } from "./tables";
import type { Command, FrameMsg, Info, SeriesMsg } from "./types";

const sleep = (ms: number): Promise<void> => new Promise((r) => setTimeout(r, ms));

/** What the page exposes for tests and for the curious (window.pheromesh). */
interface PageApi {
  info: Info | null;
  frame: FrameMsg | null; // the last frame received, as sent
  frameQuery: string; // the query string that fetched it
  frameT: number | null; // replay: the time asked for
  stats: StatsView;
  drawn: number; // heat-map draws
  renderMs: number; // moving average of one render (heat map, tables, plots)
  model: Model | null;
  lastCommand: { body: Command; status: number; ok: boolean; message: string } | null;
  palette: { background: number[]; noData: number[]; lut: readonly number[][] };
  cellToClient(x: number, y: number): { x: number; y: number };
  clientToCell(x: number, y: number): { x: number; y: number } | null;
  layerSum(): ReturnType<Model["layerSum"]> | null;
  rectSum(x0: number, y0: number, w: number, h: number): ReturnType<Model["rectSum"]> | null;
  uavs(): { id: number; x: number; y: number; heading: number; role: number; liveness: string; track: number }[];
  busy(): boolean;
}

declare global {
  interface Window {
    pheromesh: PageApi;
  }
}

type Tool = "none" | "obstacle" | "target";

class App {
  readonly model: Model;
  readonly stats: NetStats;
  private readonly heat: HeatMap;
  private readonly plots: { plot: LinePlot; label: HTMLElement; text: (m: Model) => string }[];
  private readonly uavTable: UavTable;
  private readonly regionTable: RegionTable;
  private readonly targets: TargetsPanel;
  private readonly commandLog: CommandLog;
  private readonly layerSelect = $("layer") as HTMLSelectElement;
  private readonly pauseButton = $("pause") as HTMLButtonElement;
  private readonly toolObstacle = $("tool-obstacle") as HTMLButtonElement;
  private readonly toolTarget = $("tool-target") as HTMLButtonElement;
  private readonly obstacleW = $("obstacle-w") as HTMLInputElement;
  private readonly obstacleH = $("obstacle-h") as HTMLInputElement;
  private readonly status = $("status");
  private layer = 0;
  private tool: Tool = "none";
  private needFull = true;
  private abort: AbortController | null = null;
  private layerSwitching = false;
  private rafPending = false;
  private hover: { x: number; y: number } | null = null;
  private lastScale = NaN;
  private lastLayerName = "";
  // Replay.
  private replayT = 0;
  private replayWanted: number | null = null;
  private replayInflight = false;
  private playing = false;
  private playStartWall = 0;
  private playStartT = 0;
  private playTimer: number | undefined;

  constructor(
    readonly info: Info,
    private readonly token: string,
    private readonly api: PageApi,
    stats: NetStats,
  ) {
    this.model = new Model(info);
    this.stats = stats;
    api.model = this.model;
    this.heat = new HeatMap($("heatmap") as HTMLCanvasElement, $("map-wrap"), this.model);
    const pct = (v: number): string => `${Math.round(v * 100)}%`;
    const mkPlot = (id: string, colour: string, value: (s: SeriesMsg) => number, format: (v: number) => string, yMax: (l: number) => number, text: (m: Model) => string) => ({
      plot: new LinePlot($(id) as HTMLCanvasElement, { colour, value, format, yMin: 0, yMax }),
      label: $(`${id}-value`),
      text,
    });
    const last = (m: Model) => m.series[m.series.length - 1];
    this.plots = [
      mkPlot("plot-coverage", "#22d3ee", (s) => s.coverage, pct, () => 1, (m) => (last(m) ? pct(last(m)!.coverage) : "")),
      mkPlot(
        "plot-targets",
        "#22c55e",
        (s) => s.targets_found,
        (v) => String(Math.round(v * 10) / 10),
        (l) => Math.max(1, l),
        (m) => (last(m) ? `${last(m)!.targets_found} / ${m.targets.length}` : ""),
      ),
      mkPlot("plot-uncertainty", "#f59e0b", (s) => s.uncertainty, (v) => v.toFixed(2), (l) => Math.max(1, l), (m) => (last(m) ? last(m)!.uncertainty.toFixed(3) : "")),
    ];
    const controls = (): ControlState => this.controls();
    this.uavTable = new UavTable($("uavs") as HTMLTableElement, $("uav-count"), controls);
    this.regionTable = new RegionTable($("regions") as HTMLTableElement, controls);
    this.targets = new TargetsPanel($("targets"), {
      found: $("count-found"),
      not_found: $("count-not-found"),
      revisit_due: $("count-revisit"),
      obstacles: $("count-obstacles"),
      popup: $("count-popup"),
    });
    this.commandLog = new CommandLog($("commands"));

    api.cellToClient = (x, y) => {
      if (this.heat.resize()) this.invalidate(true);
      return this.heat.cellToClient(x, y);
    };
    api.clientToCell = (x, y) => this.heat.clientToCell(x, y);
    api.layerSum = () => this.model.layerSum();
    api.rectSum = (x0, y0, w, h) => this.model.rectSum(x0, y0, w, h);
    api.uavs = () =>
      [...this.model.uavs.values()].map((u) => ({ id: u.id, x: u.x, y: u.y, heading: u.heading, role: u.role, liveness: u.liveness, track: u.track.length }));
    api.busy = () => this.replayInflight || this.replayWanted !== null;

    this.setupStatic();
    this.setupControls();
    this.drawLegendBar();
    window.addEventListener("resize", () => this.invalidate(true));
    setInterval(() => {
      this.stats.recompute();
      this.model.dirty.header = true;
      this.invalidate();
    }, 1000);
    this.invalidate(true);
  }

  // --- controls -----------------------------------------------------------

  private controls(): ControlState {
    const c = this.info.control;
    let command: string | null = null;
    if (this.info.mode === "replay") command = c.reason || "a replay: there is nothing to control";
    else if (!c.enabled) command = c.reason || "control is disabled on this console";
    else if (!this.token) command = "no token: open the URL with ?token=… that the ground station printed";
    let process = command;
    if (process === null && !c.process_control) {
      process = c.reason || "no process control: the ground station was not started by pheromesh run";
    }
    return { command, process };
  }

  private setupStatic(): void {
    const s = this.info.scenario;
    setText($("hdr-scenario"), s.name);
    $("hdr-scenario").title = s.path ?? "";
    setText($("hdr-policy"), s.policy);
    setText($("hdr-clock"), s.clock ?? "–");
    setText($("hdr-dds"), s.dds ?? "–");
    const mode = $("badge-mode");
    setText(mode, this.info.mode === "replay" ? "REPLAY" : "LIVE");
    mode.dataset["mode"] = this.info.mode;
    document.title = `pheromesh · ${s.name}${this.info.mode === "replay" ? " (replay)" : ""}`;

    // Layers: ?layer= picks the first one (index or name).
    const want = new URLSearchParams(location.search).get("layer");
    s.layers.forEach((name, i) => {
      const o = document.createElement("option");
      o.value = String(i);
      o.textContent = name;
      this.layerSelect.appendChild(o);
      if (want !== null && (want === name || want === String(i))) this.layer = i;
    });
    this.layerSelect.value = String(this.layer);
  }

  private setupControls(): void {
    const c = this.controls();
    setEnabled(this.pauseButton, c.command, "pause / resume every UAV and place agent");
    setEnabled(this.toolObstacle, c.command, "then click the map: a pop-up obstacle centred on the cell");
    setEnabled(this.toolTarget, c.command, "then click the map: a new target on the cell");
    setEnabled(this.obstacleW, c.command, "obstacle width [cells]");
    setEnabled(this.obstacleH, c.command, "obstacle height [cells]");
    if (c.command) this.setStatus(`controls disabled: ${c.command}`, "info");
    else if (c.process) this.setStatus(`kill / restart disabled: ${c.process}`, "info");

    this.layerSelect.addEventListener("change", () => this.setLayer(Number(this.layerSelect.value)));
    this.pauseButton.addEventListener("click", () => {
      const resume = this.model.paused;
      void this.send(resume ? { kind: "resume" } : { kind: "pause" }, resume ? "resume" : "pause");
    });
    this.toolObstacle.addEventListener("click", () => this.setTool(this.tool === "obstacle" ? "none" : "obstacle"));
    this.toolTarget.addEventListener("click", () => this.setTool(this.tool === "target" ? "none" : "target"));
    document.addEventListener("keydown", (e) => {
      if (e.key === "Escape") this.setTool("none");
    });

    // Kill / restart buttons of the tables.
    document.addEventListener("click", (e) => {
      const b = (e.target as Element | null)?.closest?.("button[data-action]") as HTMLButtonElement | null;
      if (!b || b.disabled) return;
      const action = b.dataset["action"];
      if (action === "kill_uav" || action === "restart_uav") {
        const id = Number(b.dataset["uav"]);
        void this.send({ kind: action, uav: id }, `${action === "kill_uav" ? "kill" : "restart"} uav ${id}`);
      } else if (action === "kill_place") {
        const id = Number(b.dataset["region"]);
        void this.send({ kind: "kill_place", region: id }, `kill place agent ${id}`);
      }
    });

    const canvas = this.heat.canvas;
    canvas.addEventListener("mousemove", (e) => {
      this.hover = this.heat.clientToCell(e.clientX, e.clientY);
      this.updateHover();
    });
    canvas.addEventListener("mouseleave", () => {
      this.hover = null;
      this.updateHover();
    });
    canvas.addEventListener("click", (e) => {
      const cell = this.heat.clientToCell(e.clientX, e.clientY);
      if (!cell) return;
      if (this.tool === "obstacle") {
        const r = this.obstacleRect(cell.x, cell.y);
        void this.send({ kind: "obstacle", x0: r.x, y0: r.y, w: r.w, h: r.h }, `obstacle ${r.w}×${r.h} at (${r.x}, ${r.y})`);
      } else if (this.tool === "target") {
        void this.send({ kind: "target", x: cell.x, y: cell.y }, `target at (${cell.x}, ${cell.y})`);
      }
    });
  }

  private obstacleRect(cx: number, cy: number): { x: number; y: number; w: number; h: number } {
    const W = this.info.scenario.width;
    const H = this.info.scenario.height;
    const clampInt = (v: number, lo: number, hi: number): number => Math.min(hi, Math.max(lo, Math.round(Number.isFinite(v) ? v : 3)));
    const w = clampInt(this.obstacleW.valueAsNumber, 1, W);
    const h = clampInt(this.obstacleH.valueAsNumber, 1, H);
    const x = Math.min(W - w, Math.max(0, cx - Math.floor(w / 2)));
    const y = Math.min(H - h, Math.max(0, cy - Math.floor(h / 2)));
    return { x, y, w, h };
  }

  private setTool(t: Tool): void {
    if (t !== "none" && this.controls().command) return;
    this.tool = t;
    this.toolObstacle.setAttribute("aria-pressed", String(t === "obstacle"));
    this.toolTarget.setAttribute("aria-pressed", String(t === "target"));
    this.heat.canvas.dataset["tool"] = t;
    this.updateHover();
  }

  private updateHover(): void {
    const h = this.hover;
    if (!h) {
      setText($("cursor"), "");
      this.heat.preview = null;
    } else {
      const v = this.model.valueAt(h.x, h.y);
      const name = this.model.layerName || this.info.scenario.layers[this.layer] || "";
      setText($("cursor"), `cell (${h.x}, ${h.y}) · ${name} ${v === null ? "no data" : fmtValue(Number(v.toPrecision(3)))}`);
      if (this.tool === "obstacle") {
        const r = this.obstacleRect(h.x, h.y);
        this.heat.preview = { kind: "obstacle", ...r };
      } else if (this.tool === "target") {
        this.heat.preview = { kind: "target", x: h.x, y: h.y, w: 1, h: 1 };
      } else this.heat.preview = null;
    }
    this.model.dirty.map = true;
    this.invalidate();
  }

  private setStatus(text: string, state: "ok" | "error" | "pending" | "info"): void {
    setText(this.status, text);
    this.status.dataset["state"] = state;
  }

  private async send(body: Command, label: string): Promise<void> {
    const c = this.controls();
    const reason = body.kind === "kill_uav" || body.kind === "restart_uav" || body.kind === "kill_place" ? c.process : c.command;
    if (reason) {
      this.setStatus(`${label}: ${reason}`, "error");
      return;
    }
    this.setStatus(`${label}…`, "pending");
    let status = 0;
    let message = "";
    let ok = false;
    try {
      const res = await fetch("/api/command", {
        method: "POST",
        headers: { "Content-Type": "application/json", Authorization: `Bearer ${this.token}` },
        body: JSON.stringify(body),
        cache: "no-store",
      });
      status = res.status;
      const text = await res.text();
      message = text.trim();
      let jsonOk: boolean | undefined;
      try {
        const j = JSON.parse(text) as { ok?: boolean; message?: string; error?: string };
        message = j.message ?? j.error ?? message;
        jsonOk = j.ok;
      } catch {
        // not JSON: keep the text
      }
      ok = res.ok && jsonOk !== false;
      if (ok) this.setStatus(`${label}: ${message || "ok"}`, "ok");
      else {
        const why = status === 401 ? "wrong or missing token" : status === 409 ? "not possible now" : status === 503 ? "a replay" : `HTTP ${status}`;
        this.setStatus(`${label} refused (${why}): ${message}`, "error");
      }
    } catch (e) {
      message = String(e);
      this.setStatus(`${label} failed: ${message}`, "error");
    }
    this.api.lastCommand = { body, status, ok, message };
  }

  private setConnected(ok: boolean, why = ""): void {
    const c = $("conn");
    const state = ok ? "connected" : "disconnected";
    if (c.dataset["state"] !== state) c.dataset["state"] = state;
    setText(c, ok ? "connected" : "disconnected");
    c.title = why;
  }

  // --- layers, frames -----------------------------------------------------

  private setLayer(i: number): void {
    if (i === this.layer) return;
    this.layer = i;
    this.model.clearTiles();
    this.needFull = true;
    this.invalidate();
    if (this.info.mode === "replay") {
      this.requestReplay(this.replayT);
    } else if (this.abort) {
      this.layerSwitching = true;
      this.abort.abort();
    }
  }

  private received(text: string, f: FrameMsg | null, query: string, forceFull: boolean): void {
    const fresh = f !== null && this.model.apply(f, forceFull);
    this.stats.add(text.length, fresh);
    if (fresh && f) {
      this.api.frame = f;
      this.api.frameQuery = query;
      this.invalidate();
    }
  }

  async live(): Promise<void> {
    for (;;) {
      const layer = this.layer;
      const since = this.needFull ? 0 : this.model.version;
      this.needFull = false;
      const query = `layer=${layer}&since=${since}&wait=1`;
      const abort = new AbortController();
      this.abort = abort;
      const t0 = performance.now();
      try {
        const res = await fetch(`/api/frame?${query}`, { cache: "no-store", signal: abort.signal });
        const text = await res.text();
        if (!res.ok) throw new Error(`HTTP ${res.status} ${text.slice(0, 200)}`);
        this.setConnected(true);
        if (layer !== this.layer) {
          // The layer changed while this was under way; ask again, complete.
          this.stats.add(text.length, false);
          this.needFull = true;
          continue;
        }
        const f = text.length > 0 ? (JSON.parse(text) as FrameMsg) : null;
        if (f && !f.full && since > 0 && f.version < since) {
          // The console started again: its versions went back.
          this.stats.add(text.length, false);
          this.needFull = true;
          continue;
        }
        const before = this.stats.frames;
        this.received(text, f, query, false);
        // An answer without news that came back at once: the server did not
        // hold it; do not spin.
        if (this.stats.frames === before && performance.now() - t0 < 100) await sleep(250);
      } catch (e) {
        if (abort.signal.aborted && this.layerSwitching) {
          this.layerSwitching = false;
          this.needFull = true;
          continue;
        }
        this.setConnected(false, String(e));
        this.needFull = this.needFull || !this.model.haveFrame;
        await sleep(1000);
      }
    }
  }

  // --- replay -------------------------------------------------------------

  setupReplay(): void {
    const r = this.info.replay ?? { t0_s: 0, t1_s: 0 };
    const bar = $("replay");
    bar.hidden = false;
    const slider = $("slider") as HTMLInputElement;
    const play = $("replay-play") as HTMLButtonElement;
    slider.min = String(r.t0_s);
    slider.max = String(r.t1_s);
    slider.step = "any";
    slider.value = String(r.t0_s);
    this.replayT = r.t0_s;
    const show = (): void => {
      const shown = this.model.haveFrame ? ` (frame ${fmt(this.model.t_s, 2)} s)` : "";
      setText($("replay-time"), `${fmt(this.replayT, 2)} s / ${fmt(r.t1_s, 2)} s${shown}`);
      setText(play, this.playing ? "❚❚ pause" : "▶ play");
      play.setAttribute("aria-pressed", String(this.playing));
    };
    this.replayShow = show;
    slider.addEventListener("input", () => {
      this.replayT = slider.valueAsNumber;
      if (this.playing) {
        this.playStartT = this.replayT;
        this.playStartWall = performance.now();
      }
      this.requestReplay(this.replayT);
      show();
    });
    play.addEventListener("click", () => {
      if (this.playing) this.stopPlaying();
      else {
        if (this.replayT >= r.t1_s) this.replayT = r.t0_s;
        this.playing = true;
        this.playStartT = this.replayT;
        this.playStartWall = performance.now();
        // About 5 frames per second of recording time, at 1x speed.
        this.playTimer = window.setInterval(() => {
          const t = Math.min(r.t1_s, this.playStartT + (performance.now() - this.playStartWall) / 1000);
          this.replayT = t;
          slider.value = String(t);
          this.requestReplay(t);
          if (t >= r.t1_s) this.stopPlaying();
          show();
        }, 200);
      }
      show();
    });
    show();
    this.requestReplay(this.replayT);
  }

  private replayShow: () => void = () => {};

  private stopPlaying(): void {
    this.playing = false;
    if (this.playTimer !== undefined) clearInterval(this.playTimer);
    this.playTimer = undefined;
    this.replayShow();
  }

  private requestReplay(t: number): void {
    this.replayWanted = t;
    if (!this.replayInflight) void this.pumpReplay();
  }

  private async pumpReplay(): Promise<void> {
    this.replayInflight = true;
    while (this.replayWanted !== null) {
      const t = this.replayWanted;
      this.replayWanted = null;
      const layer = this.layer;
      const query = `t=${t}&layer=${layer}`;
      try {
        const res = await fetch(`/api/frame?${query}`, { cache: "no-store" });
        const text = await res.text();
        if (!res.ok) throw new Error(`HTTP ${res.status} ${text.slice(0, 200)}`);
        this.setConnected(true);
        if (layer !== this.layer) {
          if (this.replayWanted === null) this.replayWanted = t;
          this.stats.add(text.length, false);
          continue;
        }
        const f = JSON.parse(text) as FrameMsg;
        // Every replay answer is complete; apply it even if its version is older.
        const fresh = this.model.apply(f, true);
        this.stats.add(text.length, fresh);
        this.api.frame = f;
        this.api.frameQuery = query;
        this.api.frameT = t;
        this.invalidate();
        this.replayShow();
      } catch (e) {
        this.setConnected(false, String(e));
        if (this.replayWanted === null) this.replayWanted = t;
        await sleep(1000);
      }
    }
    this.replayInflight = false;
  }

  // --- drawing ------------------------------------------------------------

  invalidate(resized = false): void {
    if (resized) this.model.dirty.map = true;
    if (this.rafPending) return;
    this.rafPending = true;
    requestAnimationFrame(() => {
      this.rafPending = false;
      this.render();
    });
  }

  private render(): void {
    const start = performance.now();
    this.renderParts();
    const ms = performance.now() - start;
    this.api.renderMs = this.api.renderMs === 0 ? ms : this.api.renderMs * 0.9 + ms * 0.1;
  }

  private renderParts(): void {
    const m = this.model;
    const d = m.dirty;
    if (this.heat.resize()) d.map = true;
    if (d.map || d.tilesReset || d.tiles.size > 0) {
      this.heat.syncTiles();
      this.heat.draw();
      this.api.drawn = this.heat.draws;
      d.map = false;
    }
    if (d.header) {
      d.header = false;
      this.renderHeader();
    }
    if (d.uavs) {
      d.uavs = false;
      this.uavTable.sync(m);
    }
    if (d.regions) {
      d.regions = false;
      this.regionTable.sync(m);
    }
    if (d.targets) {
      d.targets = false;
      this.targets.sync(m);
    }
    if (d.commands) {
      d.commands = false;
      this.commandLog.sync(m);
    }
    if (d.series || d.targets) {
      d.series = false;
      const total = m.targets.length;
      for (const p of this.plots) {
        p.plot.draw(m.series, p.plot === this.plots[1]!.plot ? total : 0);
        setText(p.label, p.text(m));
      }
    }
  }

  private renderHeader(): void {
    const m = this.model;
    setText($("hdr-tick"), m.haveFrame ? String(m.tick) : "–");
    setText($("hdr-time"), m.haveFrame ? `${fmt(m.t_s, 1)} s` : "–");
    ($("badge-paused") as HTMLElement).hidden = !m.paused;
    const label = m.paused ? "resume" : "pause";
    setText(this.pauseButton, label);
    this.pauseButton.setAttribute("aria-pressed", String(m.paused));
    setText($("hdr-ups"), this.stats.updatesPerSecond.toFixed(1));
    setText($("hdr-kibps"), (this.stats.bytesPerSecond / 1024).toFixed(1));
    if (m.scale !== this.lastScale || m.layerName !== this.lastLayerName) {
      this.lastScale = m.scale;
      this.lastLayerName = m.layerName;
      setText($("legend-layer"), m.layerName || this.info.scenario.layers[this.layer] || "–");
      setText($("legend-mid"), fmtValue(m.scale / 2));
      setText($("legend-max"), fmtValue(m.scale));
      $("legend").title = `value = q / 255 × ${m.scale}`;
    }
  }

  private drawLegendBar(): void {
    const c = $("legend-bar") as HTMLCanvasElement;
    const g = c.getContext("2d");
    if (!g) return;
    c.width = 256;
    c.height = 1;
    for (let q = 0; q < 256; q++) {
      g.fillStyle = css(LUT_RGB[q]!);
      g.fillRect(q, 0, 1, 1);
    }
  }
}

async function fetchInfo(): Promise<Info> {
  const conn = $("conn");
  for (;;) {
    try {
      const res = await fetch("/api/info", { cache: "no-store" });
      if (!res.ok) throw new Error(`HTTP ${res.status}`);
      return (await res.json()) as Info;
    } catch (e) {
      conn.dataset["state"] = "disconnected";
      setText(conn, "disconnected");
      conn.title = String(e);
      await sleep(1000);
    }
  }
}

async function main(): Promise<void> {
  const stats = new NetStats();
  const api: PageApi = {
    info: null,
    frame: null,
    frameQuery: "",
    frameT: null,
    stats: stats.view,
    drawn: 0,
    renderMs: 0,
    model: null,
    lastCommand: null,
    palette: { background: [...PALETTE.background], noData: [...PALETTE.noData], lut: LUT_RGB },
    cellToClient: () => ({ x: NaN, y: NaN }),
    clientToCell: () => null,
    layerSum: () => null,
    rectSum: () => null,
    uavs: () => [],
    busy: () => true,
  };
  window.pheromesh = api;
  const token = new URLSearchParams(location.search).get("token") ?? "";
  const info = await fetchInfo();
  api.info = info;
  const app = new App(info, token, api, stats);
  if (info.mode === "replay") app.setupReplay();
  else void app.live();
}

void main();
