// What the page holds of the console's state, built from the frames of
// GET /api/frame: a full frame replaces everything, a delta updates it.
import type {
  CommandMsg,
  FrameMsg,
  Info,
  Liveness,
  ObstacleMsg,
  RegionMsg,
  SeriesMsg,
  TargetMsg,
} from "./types";

export const TRACK_POINTS = 64; // per UAV, as the ground station keeps
export const SERIES_POINTS = 3600;
export const COMMAND_LOG = 50;

export interface Tile {
  tx: number;
  ty: number;
  x0: number;
  y0: number;
  w: number;
  h: number;
  tick: number;
  q: Uint8Array; // row-major, w*h
}

export interface Uav {
  id: number;
  x: number;
  y: number;
  heading: number;
  role: number;
  tick: number;
  liveness: Liveness;
  track: [number, number][];
}

/** What changed since the renderer last looked; it clears what it consumed. */
export interface Dirty {
  map: boolean; // anything drawn on the heat map
  tilesReset: boolean; // every tile is gone (new layer, full frame)
  tiles: Set<string>; // keys of tiles whose q changed
  header: boolean;
  uavs: boolean;
  regions: boolean;
  targets: boolean;
  series: boolean;
  commands: boolean;
}

export function tileKey(tx: number, ty: number): string {
  return `${tx},${ty}`;
}

function decodeBase64(s: string, n: number): Uint8Array {
  const bin = atob(s);
  const out = new Uint8Array(n);
  const m = Math.min(n, bin.length);
  for (let i = 0; i < m; i++) out[i] = bin.charCodeAt(i);
  return out;
}

export class Model {
  version = 0;
  t_s = 0;
  tick = 0;
  paused = false;
  haveFrame = false;
  layerIndex = -1; // of the tiles held
  layerName = "";
  scale = 1;
  tiles = new Map<string, Tile>();
  uavs = new Map<number, Uav>();
  regions: RegionMsg[] = [];
  targets: TargetMsg[] = [];
  obstacles: ObstacleMsg[] = [];
  series: SeriesMsg[] = [];
  commands: CommandMsg[] = []; // newest first
  dirty: Dirty = {
    map: true,
    tilesReset: true,
    tiles: new Set(),
    header: true,
    uavs: true,
    regions: true,
    targets: true,
    series: true,
    commands: true,
  };

  constructor(readonly info: Info) {}

  /** Forget every tile (the layer changed); the next frame asked for is full. */
  clearTiles(): void {
    this.tiles.clear();
    this.layerIndex = -1;
    this.dirty.tilesReset = true;
    this.dirty.tiles.clear();
    this.dirty.map = true;
  }

  /**
   * Applies one answer of GET /api/frame. `forceFull` treats it as complete
   * (replay answers). Returns false if it brought nothing new (a long poll
   * that timed out).
   */
  apply(f: FrameMsg, forceFull = false): boolean {
    const full = forceFull || f.full === true;
    if (!full && this.haveFrame && f.version <= this.version) return false;
    const d = this.dirty;
    this.haveFrame = true;
    this.version = f.version;
    this.t_s = f.t_s;
    this.tick = f.tick;
    this.paused = f.paused;
    d.header = true;

    // Layer tiles.
    if (f.layer) {
      const layerChanged = f.layer.index !== this.layerIndex;
      if (full || layerChanged) {
        this.tiles.clear();
        d.tilesReset = true;
        d.tiles.clear();
      }
      this.layerIndex = f.layer.index;
      this.layerName = f.layer.name;
      if (f.layer.scale !== this.scale) {
        this.scale = f.layer.scale;
        d.header = true;
      }
      for (const t of f.layer.tiles ?? []) {
        const n = t.w * t.h;
        const key = tileKey(t.tx, t.ty);
        this.tiles.set(key, {
          tx: t.tx,
          ty: t.ty,
          x0: t.x0,
          y0: t.y0,
          w: t.w,
          h: t.h,
          tick: t.tick ?? 0,
          q: decodeBase64(t.q, n),
        });
        d.tiles.add(key);
      }
      d.map = true;
    } else if (full) {
      this.tiles.clear();
      d.tilesReset = true;
      d.tiles.clear();
      d.map = true;
    }

    // UAVs: every UAV is listed; tracks carry the points added since `since`.
    if (f.uavs) {
      if (full) this.uavs.clear();
      for (const u of f.uavs) {
        let v = this.uavs.get(u.id);
        if (!v) {
          v = { id: u.id, x: u.x, y: u.y, heading: u.heading, role: u.role, tick: 0, liveness: u.liveness, track: [] };
          this.uavs.set(u.id, v);
        }
        v.x = u.x;
        v.y = u.y;
        v.heading = u.heading;
        v.role = u.role;
        v.tick = u.tick ?? v.tick;
        v.liveness = u.liveness;
        if (u.track && u.track.length > 0) {
          for (const p of u.track) v.track.push([p[0], p[1]]);
          if (v.track.length > TRACK_POINTS) v.track.splice(0, v.track.length - TRACK_POINTS);
        }
      }
      d.uavs = true;
      d.map = true;
    } else if (full) {
      this.uavs.clear();
      d.uavs = true;
      d.map = true;
    }

    if (f.regions || full) {
      this.regions = f.regions ?? [];
      d.regions = true;
    }
    if (f.targets || full) {
      this.targets = f.targets ?? [];
      d.targets = true;
      d.map = true;
    }
    if (f.obstacles || full) {
      this.obstacles = f.obstacles ?? [];
      d.targets = true;
      d.map = true;
    }

    if (full) {
      this.series = (f.series ?? []).slice(-SERIES_POINTS);
      d.series = true;
    } else if (f.series && f.series.length > 0) {
      for (const s of f.series) this.series.push(s);
      if (this.series.length > SERIES_POINTS) this.series.splice(0, this.series.length - SERIES_POINTS);
      d.series = true;
    }

    if (full) {
      this.commands = (f.commands ?? []).slice().reverse().slice(0, COMMAND_LOG);
      d.commands = true;
    } else if (f.commands && f.commands.length > 0) {
      // The frame lists them oldest first; the log shows the newest first.
      const fresh = f.commands.slice().reverse();
      this.commands = fresh.concat(this.commands).slice(0, COMMAND_LOG);
      d.commands = true;
    }
    return true;
  }

  /** Value of a cell of the held layer, or null if its tile is not held. */
  valueAt(x: number, y: number): number | null {
    const ts = this.info.scenario.tile_size;
    if (ts <= 0) return null;
    const inside = (t: Tile): boolean => x >= t.x0 && y >= t.y0 && x < t.x0 + t.w && y < t.y0 + t.h;
    let t = this.tiles.get(tileKey(Math.floor(x / ts), Math.floor(y / ts)));
    if (!t || !inside(t)) {
      t = undefined;
      for (const c of this.tiles.values()) if (inside(c)) t = c;
    }
    if (!t) return null;
    return ((t.q[(y - t.y0) * t.w + (x - t.x0)] ?? 0) / 255) * this.scale;
  }

  /** Sums of q and of values over the cells of a rectangle that the held tiles cover. */
  rectSum(x0: number, y0: number, w: number, h: number): { q: number; value: number; cells: number } {
    let q = 0;
    let cells = 0;
    for (const t of this.tiles.values()) {
      const xa = Math.max(x0, t.x0);
      const xb = Math.min(x0 + w, t.x0 + t.w);
      const ya = Math.max(y0, t.y0);
      const yb = Math.min(y0 + h, t.y0 + t.h);
      for (let y = ya; y < yb; y++) {
        for (let x = xa; x < xb; x++) {
          q += t.q[(y - t.y0) * t.w + (x - t.x0)]!;
          cells++;
        }
      }
    }
    return { q, value: (q / 255) * this.scale, cells };
  }

  /** Sums over the held tiles of the current layer (for tests and the legend). */
  layerSum(): { layer: number; name: string; tiles: number; q: number; value: number; scale: number } {
    let q = 0;
    for (const t of this.tiles.values()) for (let i = 0; i < t.q.length; i++) q += t.q[i]!;
    return { layer: this.layerIndex, name: this.layerName, tiles: this.tiles.size, q, value: (q / 255) * this.scale, scale: this.scale };
  }
}
