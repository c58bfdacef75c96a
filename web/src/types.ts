// The JSON of the console's HTTP API (docs/console.md), as the page reads it.
// Every field the page does not strictly need is optional, so that an older or
// newer ground station still renders.

export type Liveness = "alive" | "stale" | "dead" | "finished";
export type TargetStatus = "not_found" | "found" | "revisit_due";

export interface RegionRect {
  id: number;
  x0: number;
  y0: number;
  w: number;
  h: number;
}

export interface ScenarioInfo {
  name: string;
  path?: string;
  policy: string;
  width: number;
  height: number;
  tile_size: number;
  ticks?: number;
  tick_rate_hz?: number;
  uavs_expected?: number;
  lease_ms?: number;
  sensor_radius?: number;
  clock?: string;
  dds?: string;
  layers: string[];
  regions: RegionRect[];
}

export interface ControlInfo {
  enabled: boolean;
  process_control: boolean;
  reason?: string;
}

export interface ReplayInfo {
  t0_s: number;
  t1_s: number;
  frames?: number;
}

export interface Info {
  mode: "live" | "replay";
  scenario: ScenarioInfo;
  control: ControlInfo;
  replay?: ReplayInfo;
}

export interface TileMsg {
  tx: number;
  ty: number;
  x0: number;
  y0: number;
  w: number;
  h: number;
  tick?: number;
  q: string; // base64 of w*h bytes, row-major
}

export interface LayerMsg {
  index: number;
  name: string;
  scale: number;
  tiles?: TileMsg[];
}

export interface UavMsg {
  id: number;
  x: number;
  y: number;
  heading: number; // 0..7, 45 degree steps counter-clockwise from east
  role: number; // 0 searcher, 1 leader, 2 follower
  tick?: number;
  liveness: Liveness;
  track?: [number, number][]; // points added after `since`
}

export interface RegionMsg {
  id: number;
  liveness: Liveness;
  tick?: number;
  tick_rate_hz?: number;
  deposits_per_s?: number;
  deposits_received?: number;
  deposits_applied?: number;
  deposits_rejected?: number;
  samples_refused?: number; // well-formed samples its place agent refused as implausible
}

export interface TargetMsg {
  index: number;
  x: number;
  y: number;
  status: TargetStatus;
  found_by?: number;
  found_tick?: number;
  popup?: boolean;
}

export interface ObstacleMsg {
  x0: number;
  y0: number;
  w: number;
  h: number;
  popup?: boolean;
}

export interface SeriesMsg {
  t_s: number;
  tick?: number;
  coverage: number;
  targets_found: number;
  uncertainty: number;
}

export interface CommandMsg {
  t_s: number;
  who?: string;
  what: string;
  ok: boolean;
  result?: string;
}

export interface FrameMsg {
  version: number;
  t_s: number;
  tick: number;
  paused: boolean;
  full: boolean;
  layer?: LayerMsg;
  uavs?: UavMsg[];
  regions?: RegionMsg[];
  targets?: TargetMsg[];
  obstacles?: ObstacleMsg[];
  series?: SeriesMsg[];
  commands?: CommandMsg[];
}

// Bodies of POST /api/command.
export type Command =
  | { kind: "pause" }
  | { kind: "resume" }
  | { kind: "kill_uav"; uav: number }
  | { kind: "restart_uav"; uav: number }
  | { kind: "kill_place"; region: number }
  | { kind: "obstacle"; x0: number; y0: number; w: number; h: number }
  | { kind: "target"; x: number; y: number };
