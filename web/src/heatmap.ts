// The heat map: the chosen pheromone layer, one pixel per cell in an
// offscreen canvas that is updated tile by tile (each tile's base64 decoded
// once into an ImageData), drawn scaled onto #heatmap with the regions,
// obstacles, targets, UAVs and their tracks on top.
import { BACKGROUND, LUT32, NO_DATA, NO_DATA32, css } from "./colormap";
import type { Model, Tile } from "./model";

export const ROLE_COLOURS = ["#22d3ee", "#ffffff", "#60a5fa"]; // searcher, leader, follower
export const ROLE_NAMES = ["searcher", "leader", "follower"];
export const TARGET_COLOURS: Record<string, string> = {
  not_found: "#f87171",
  found: "#22c55e",
  revisit_due: "#e879f9",
};
const GREYED = "#9ca3af";
const POPUP_OUTLINE = "#38bdf8";

export interface ToolPreview {
  kind: "obstacle" | "target";
  x: number;
  y: number;
  w: number;
  h: number;
}

export class HeatMap {
  private readonly ctx: CanvasRenderingContext2D;
  private readonly layer: HTMLCanvasElement;
  private readonly layerCtx: CanvasRenderingContext2D;
  private readonly W: number;
  private readonly H: number;
  private cs = 1; // backing pixels per cell
  private ox = 0;
  private oy = 0;
  private dpr = 1;
  private hatch: CanvasPattern | null = null;
  private hatchPopup: CanvasPattern | null = null;
  draws = 0;
  preview: ToolPreview | null = null;

  constructor(
    readonly canvas: HTMLCanvasElement,
    private readonly wrap: HTMLElement,
    private readonly model: Model,
  ) {
    const ctx = canvas.getContext("2d", { alpha: false });
    if (!ctx) throw new Error("no 2D canvas");
    this.ctx = ctx;
    this.W = Math.max(1, model.info.scenario.width);
    this.H = Math.max(1, model.info.scenario.height);
    this.layer = document.createElement("canvas");
    this.layer.width = this.W;
    this.layer.height = this.H;
    const lctx = this.layer.getContext("2d");
    if (!lctx) throw new Error("no 2D canvas");
    this.layerCtx = lctx;
    this.resetLayer();
  }

  /** Fits the canvas to its container; true if its size changed. */
  resize(): boolean {
    const dpr = window.devicePixelRatio || 1;
    const availW = Math.max(100, this.wrap.clientWidth);
    const availH = Math.max(160, Math.floor(window.innerHeight * 0.78));
    let cssW = availW;
    let cssH = (availW * this.H) / this.W;
    if (cssH > availH) {
      cssH = availH;
      cssW = (availH * this.W) / this.H;
    }
    cssW = Math.floor(cssW);
    cssH = Math.floor(cssH);
    const bw = Math.round(cssW * dpr);
    const bh = Math.round(cssH * dpr);
    if (bw === this.canvas.width && bh === this.canvas.height && dpr === this.dpr) return false;
    this.dpr = dpr;
    this.canvas.style.width = `${cssW}px`;
    this.canvas.style.height = `${cssH}px`;
    this.canvas.width = bw;
    this.canvas.height = bh;
    this.cs = Math.min(bw / this.W, bh / this.H);
    this.ox = (bw - this.W * this.cs) / 2;
    this.oy = (bh - this.H * this.cs) / 2;
    this.hatch = this.makeHatch("rgba(200,200,210,0.45)");
    this.hatchPopup = this.makeHatch("rgba(56,189,248,0.6)");
    return true;
  }

  private makeHatch(colour: string): CanvasPattern | null {
    const n = Math.max(6, Math.round(7 * this.dpr));
    const c = document.createElement("canvas");
    c.width = n;
    c.height = n;
    const g = c.getContext("2d");
    if (!g) return null;
    g.strokeStyle = colour;
    g.lineWidth = Math.max(1, this.dpr);
    g.beginPath();
    g.moveTo(0, n);
    g.lineTo(n, 0);
    g.moveTo(-n / 2, n / 2);
    g.lineTo(n / 2, -n / 2);
    g.moveTo(n / 2, n * 1.5);
    g.lineTo(n * 1.5, n / 2);
    g.stroke();
    return this.ctx.createPattern(c, "repeat");
  }

  private resetLayer(): void {
    const img = this.layerCtx.createImageData(this.W, this.H);
    new Uint32Array(img.data.buffer).fill(NO_DATA32);
    this.layerCtx.putImageData(img, 0, 0);
  }

  private putTile(t: Tile): void {
    const img = this.layerCtx.createImageData(t.w, t.h);
    const px = new Uint32Array(img.data.buffer);
    const q = t.q;
    for (let i = 0; i < px.length; i++) px[i] = LUT32[q[i]!]!;
    this.layerCtx.putImageData(img, t.x0, t.y0);
  }

  /** Brings the offscreen layer up to date with the model's tiles. */
  syncTiles(): void {
    const d = this.model.dirty;
    if (d.tilesReset) {
      this.resetLayer();
      for (const t of this.model.tiles.values()) this.putTile(t);
      d.tilesReset = false;
    } else {
      for (const key of d.tiles) {
        const t = this.model.tiles.get(key);
        if (t) this.putTile(t);
      }
    }
    d.tiles.clear();
  }

  // Cell (x, y) (fractional allowed) to backing-store pixels of its top-left corner.
  private px(x: number): number {
    return this.ox + x * this.cs;
  }
  private py(y: number): number {
    return this.oy + y * this.cs;
  }

  /** Client (viewport) coordinates of the centre of cell (x, y). */
  cellToClient(x: number, y: number): { x: number; y: number } {
    const r = this.canvas.getBoundingClientRect();
    const k = r.width / this.canvas.width;
    return { x: r.left + (this.ox + (x + 0.5) * this.cs) * k, y: r.top + (this.oy + (y + 0.5) * this.cs) * k };
  }

  /** The cell under client coordinates, or null outside the map. */
  clientToCell(cx: number, cy: number): { x: number; y: number } | null {
    const r = this.canvas.getBoundingClientRect();
    if (r.width <= 0) return null;
    const k = this.canvas.width / r.width;
    const x = Math.floor(((cx - r.left) * k - this.ox) / this.cs);
    const y = Math.floor(((cy - r.top) * k - this.oy) / this.cs);
    if (x < 0 || y < 0 || x >= this.W || y >= this.H) return null;
    return { x, y };
  }

  draw(): void {
    this.draws++;
    const g = this.ctx;
    const m = this.model;
    const cs = this.cs;
    const dpr = this.dpr;
    g.setTransform(1, 0, 0, 1, 0, 0);
    g.fillStyle = css(BACKGROUND);
    g.fillRect(0, 0, this.canvas.width, this.canvas.height);
    g.imageSmoothingEnabled = false;
    g.drawImage(this.layer, this.ox, this.oy, this.W * cs, this.H * cs);

    // Region boundaries, faint.
    g.lineWidth = Math.max(1, dpr);
    g.strokeStyle = "rgba(255,255,255,0.22)";
    g.setLineDash([4 * dpr, 3 * dpr]);
    for (const r of m.info.scenario.regions) {
      g.strokeRect(this.px(r.x0), this.py(r.y0), r.w * cs, r.h * cs);
    }
    g.setLineDash([]);
    if (cs * m.info.scenario.tile_size > 40 * dpr) {
      g.fillStyle = "rgba(255,255,255,0.35)";
      g.font = `${Math.round(10 * dpr)}px sans-serif`;
      g.textBaseline = "top";
      for (const r of m.info.scenario.regions) g.fillText(`R${r.id}`, this.px(r.x0) + 3 * dpr, this.py(r.y0) + 2 * dpr);
    }

    // Obstacles: dark and hatched; pop-up ones outlined in blue, dashed.
    for (const o of m.obstacles) {
      const x = this.px(o.x0);
      const y = this.py(o.y0);
      const w = o.w * cs;
      const h = o.h * cs;
      g.fillStyle = "rgba(8,8,10,0.72)";
      g.fillRect(x, y, w, h);
      const pat = o.popup ? this.hatchPopup : this.hatch;
      if (pat) {
        g.fillStyle = pat;
        g.fillRect(x, y, w, h);
      }
      if (o.popup) {
        g.strokeStyle = POPUP_OUTLINE;
        g.lineWidth = 2 * dpr;
        g.setLineDash([4 * dpr, 3 * dpr]);
        g.strokeRect(x + dpr, y + dpr, w - 2 * dpr, h - 2 * dpr);
        g.setLineDash([]);
      } else {
        g.strokeStyle = "rgba(0,0,0,0.9)";
        g.lineWidth = dpr;
        g.strokeRect(x, y, w, h);
      }
    }

    // Tracks.
    g.lineJoin = "round";
    g.lineCap = "round";
    g.lineWidth = Math.max(1, Math.min(1.5 * dpr, cs * 0.25));
    for (const u of m.uavs.values()) {
      if (u.track.length < 2) continue;
      const live = u.liveness === "alive";
      g.strokeStyle = live ? (ROLE_COLOURS[u.role] ?? "#a3e635") : GREYED;
      g.globalAlpha = live ? 0.45 : 0.25;
      g.beginPath();
      const p0 = u.track[0]!;
      g.moveTo(this.px(p0[0] + 0.5), this.py(p0[1] + 0.5));
      for (let i = 1; i < u.track.length; i++) {
        const p = u.track[i]!;
        g.lineTo(this.px(p[0] + 0.5), this.py(p[1] + 0.5));
      }
      g.stroke();
    }
    g.globalAlpha = 1;

    // Targets.
    const tr = Math.max(4 * dpr, cs * 0.45);
    for (const t of m.targets) {
      const cx = this.px(t.x + 0.5);
      const cy = this.py(t.y + 0.5);
      const col = TARGET_COLOURS[t.status] ?? "#ffffff";
      g.lineWidth = Math.max(1.5, 2 * dpr);
      if (t.status === "revisit_due") {
        g.beginPath();
        g.moveTo(cx, cy - tr * 1.2);
        g.lineTo(cx + tr * 1.2, cy);
        g.lineTo(cx, cy + tr * 1.2);
        g.lineTo(cx - tr * 1.2, cy);
        g.closePath();
        g.fillStyle = col;
        g.fill();
        g.strokeStyle = "#111";
        g.stroke();
      } else if (t.status === "found") {
        g.beginPath();
        g.arc(cx, cy, tr, 0, Math.PI * 2);
        g.fillStyle = col;
        g.fill();
        g.strokeStyle = "#111";
        g.stroke();
      } else {
        g.beginPath();
        g.arc(cx, cy, tr, 0, Math.PI * 2);
        g.strokeStyle = "#111";
        g.lineWidth = Math.max(2.5, 4 * dpr);
        g.stroke();
        g.strokeStyle = col;
        g.lineWidth = Math.max(1.5, 2 * dpr);
        g.stroke();
        g.beginPath();
        g.arc(cx, cy, Math.max(1, tr * 0.25), 0, Math.PI * 2);
        g.fillStyle = col;
        g.fill();
      }
      if (t.popup) {
        g.beginPath();
        g.arc(cx, cy, tr * 1.7, 0, Math.PI * 2);
        g.strokeStyle = POPUP_OUTLINE;
        g.lineWidth = dpr;
        g.setLineDash([2 * dpr, 2 * dpr]);
        g.stroke();
        g.setLineDash([]);
      }
    }

    // UAVs: triangles along the heading (0..7, 45 degrees counter-clockwise
    // from east; y grows downward, so up on screen is north).
    const s = Math.max(6 * dpr, cs * 0.8);
    const label = cs >= 9 * dpr;
    if (label) {
      g.font = `${Math.round(10 * dpr)}px sans-serif`;
      g.textBaseline = "middle";
    }
    for (const u of m.uavs.values()) {
      const cx = this.px(u.x + 0.5);
      const cy = this.py(u.y + 0.5);
      const a = ((u.heading % 8) * Math.PI) / 4;
      const dx = Math.cos(a);
      const dy = -Math.sin(a);
      const live = u.liveness === "alive";
      g.beginPath();
      g.moveTo(cx + dx * s, cy + dy * s);
      g.lineTo(cx - dx * s * 0.6 - dy * s * 0.6, cy - dy * s * 0.6 + dx * s * 0.6);
      g.lineTo(cx - dx * s * 0.6 + dy * s * 0.6, cy - dy * s * 0.6 - dx * s * 0.6);
      g.closePath();
      g.fillStyle = live ? (ROLE_COLOURS[u.role] ?? "#a3e635") : GREYED;
      g.fill();
      g.lineWidth = Math.max(1, dpr);
      g.strokeStyle = "#0b0b0b";
      g.stroke();
      if (u.liveness === "dead" || u.liveness === "stale") {
        const c = s * 0.7;
        g.strokeStyle = u.liveness === "dead" ? "#ef4444" : "#facc15";
        g.lineWidth = Math.max(1.5, 2 * dpr);
        g.beginPath();
        g.moveTo(cx - c, cy - c);
        g.lineTo(cx + c, cy + c);
        g.moveTo(cx + c, cy - c);
        g.lineTo(cx - c, cy + c);
        g.stroke();
      }
      if (label) {
        g.fillStyle = live ? "rgba(255,255,255,0.85)" : "rgba(200,200,200,0.6)";
        g.fillText(String(u.id), cx + s * 0.9, cy - s * 0.7);
      }
    }

    // What a click would add.
    const p = this.preview;
    if (p) {
      g.strokeStyle = "#f8fafc";
      g.lineWidth = Math.max(1, 1.5 * dpr);
      g.setLineDash([3 * dpr, 3 * dpr]);
      if (p.kind === "obstacle") {
        g.strokeRect(this.px(p.x), this.py(p.y), p.w * cs, p.h * cs);
      } else {
        g.beginPath();
        g.arc(this.px(p.x + 0.5), this.py(p.y + 0.5), tr * 1.4, 0, Math.PI * 2);
        g.stroke();
      }
      g.setLineDash([]);
    }

    // Map border.
    g.strokeStyle = "rgba(255,255,255,0.5)";
    g.lineWidth = Math.max(1, dpr);
    g.strokeRect(this.ox, this.oy, this.W * cs, this.H * cs);
  }
}

/** The colours the e2e tests need to tell drawn pheromone from the rest. */
export const PALETTE = { background: BACKGROUND, noData: NO_DATA };
