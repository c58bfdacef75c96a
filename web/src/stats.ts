// What the page received: frames and bytes, in total and over the last few
// seconds (bytes are the length of each answer's text).

const WINDOW_MS = 5000;

/** Plain numbers, updated in place (window.pheromesh.stats). */
export interface StatsView {
  frames: number; // answers that brought a newer frame
  answers: number; // every answer, frames or not
  bytes: number;
  updatesPerSecond: number; // frames over the last 5 s
  bytesPerSecond: number; // bytes over the last 5 s
}

export class NetStats {
  readonly view: StatsView = { frames: 0, answers: 0, bytes: 0, updatesPerSecond: 0, bytesPerSecond: 0 };
  private readonly events: { t: number; bytes: number; frame: boolean }[] = [];
  private readonly start = performance.now();

  get frames(): number {
    return this.view.frames;
  }
  get updatesPerSecond(): number {
    return this.view.updatesPerSecond;
  }
  get bytesPerSecond(): number {
    return this.view.bytesPerSecond;
  }

  add(bytes: number, frame: boolean): void {
    const v = this.view;
    v.answers++;
    v.bytes += bytes;
    if (frame) v.frames++;
    this.events.push({ t: performance.now(), bytes, frame });
    this.recompute();
  }

  recompute(): void {
    const now = performance.now();
    while (this.events.length > 0 && now - this.events[0]!.t > WINDOW_MS) this.events.shift();
    const span = Math.max(1, Math.min(WINDOW_MS, now - this.start)) / 1000;
    let f = 0;
    let b = 0;
    for (const e of this.events) {
      b += e.bytes;
      if (e.frame) f++;
    }
    this.view.updatesPerSecond = f / span;
    this.view.bytesPerSecond = b / span;
  }
}
