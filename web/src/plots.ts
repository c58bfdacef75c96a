// Small line plots of the console's series, drawn by hand on a canvas.
import type { SeriesMsg } from "./types";

export interface PlotOptions {
  colour: string;
  value: (s: SeriesMsg) => number;
  format: (v: number) => string;
  yMin: number;
  /** Upper end of the y axis, given the largest value shown. */
  yMax: (largest: number) => number;
}

function niceTime(s: number): string {
  if (s >= 120) return `${Math.round(s / 60)}m`;
  return `${Math.round(s)}s`;
}

export class LinePlot {
  private readonly ctx: CanvasRenderingContext2D;

  constructor(
    readonly canvas: HTMLCanvasElement,
    private readonly opts: PlotOptions,
  ) {
    const ctx = canvas.getContext("2d");
    if (!ctx) throw new Error("no 2D canvas");
    this.ctx = ctx;
  }

  private fit(): void {
    const dpr = window.devicePixelRatio || 1;
    const w = Math.max(60, Math.round(this.canvas.clientWidth * dpr));
    const h = Math.max(40, Math.round(this.canvas.clientHeight * dpr));
    if (this.canvas.width !== w) this.canvas.width = w;
    if (this.canvas.height !== h) this.canvas.height = h;
  }

  draw(series: readonly SeriesMsg[], extraMax = 0): void {
    this.fit();
    const g = this.ctx;
    const dpr = window.devicePixelRatio || 1;
    const W = this.canvas.width;
    const H = this.canvas.height;
    const o = this.opts;
    g.setTransform(1, 0, 0, 1, 0, 0);
    g.clearRect(0, 0, W, H);
    g.font = `${Math.round(10 * dpr)}px sans-serif`;
    const left = Math.round(34 * dpr);
    const right = W - Math.round(8 * dpr);
    const top = Math.round(8 * dpr);
    const bottom = H - Math.round(16 * dpr);
    const pw = Math.max(1, right - left);
    const ph = Math.max(1, bottom - top);

    let largest = extraMax;
    for (const s of series) largest = Math.max(largest, o.value(s));
    const y0 = o.yMin;
    const y1 = Math.max(y0 + 1e-9, o.yMax(largest));
    const t0 = series.length ? series[0]!.t_s : 0;
    let t1 = series.length ? series[series.length - 1]!.t_s : 1;
    if (t1 <= t0) t1 = t0 + 1;
    const X = (t: number): number => left + ((t - t0) / (t1 - t0)) * pw;
    const Y = (v: number): number => bottom - ((v - y0) / (y1 - y0)) * ph;

    // Axes and grid.
    g.strokeStyle = "rgba(255,255,255,0.12)";
    g.lineWidth = 1;
    g.fillStyle = "rgba(220,225,235,0.7)";
    g.textAlign = "right";
    g.textBaseline = "middle";
    for (let i = 0; i <= 2; i++) {
      const v = y0 + ((y1 - y0) * i) / 2;
      const y = Math.round(Y(v)) + 0.5;
      g.beginPath();
      g.moveTo(left, y);
      g.lineTo(right, y);
      g.stroke();
      g.fillText(o.format(v), left - 4 * dpr, y);
    }
    g.textBaseline = "top";
    g.textAlign = "left";
    g.fillText(niceTime(t0), left, bottom + 3 * dpr);
    g.textAlign = "right";
    g.fillText(niceTime(t1), right, bottom + 3 * dpr);

    if (series.length === 0) {
      g.textAlign = "center";
      g.textBaseline = "middle";
      g.fillText("no data yet", left + pw / 2, top + ph / 2);
      return;
    }

    // The line; many points share a pixel column: draw each column's range.
    g.strokeStyle = o.colour;
    g.lineWidth = Math.max(1, 1.5 * dpr);
    g.lineJoin = "round";
    g.beginPath();
    if (series.length <= pw) {
      series.forEach((s, i) => {
        const x = X(s.t_s);
        const y = Y(o.value(s));
        if (i === 0) g.moveTo(x, y);
        else g.lineTo(x, y);
      });
    } else {
      let col = -1;
      let lo = 0;
      let hi = 0;
      let first = true;
      const flush = (): void => {
        if (col < 0) return;
        if (first) {
          g.moveTo(col, Y(lo));
          first = false;
        } else g.lineTo(col, Y(lo));
        if (hi !== lo) g.lineTo(col, Y(hi));
      };
      for (const s of series) {
        const c = Math.round(X(s.t_s));
        const v = o.value(s);
        if (c !== col) {
          flush();
          col = c;
          lo = v;
          hi = v;
        } else {
          lo = Math.min(lo, v);
          hi = Math.max(hi, v);
        }
      }
      flush();
    }
    g.stroke();
    const last = series[series.length - 1]!;
    g.fillStyle = o.colour;
    g.beginPath();
    g.arc(X(last.t_s), Y(o.value(last)), 2.5 * dpr, 0, Math.PI * 2);
    g.fill();
  }
}
