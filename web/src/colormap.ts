// The heat map's colour scale: 256 entries indexed by the quantised value q
// (value = q / 255 * scale). Dark violet for nothing, through purple and red
// to pale yellow, chosen so that none of it is a neutral grey (the colour of
// tiles not received yet) and none of it is the cyan / green / white of the
// overlays drawn on top.

export type Rgb = [number, number, number];

// (position 0..1, colour) stops, linearly interpolated in RGB.
const STOPS: [number, Rgb][] = [
  [0.0, [14, 10, 32]],
  [0.12, [46, 16, 92]],
  [0.3, [112, 26, 112]],
  [0.5, [184, 52, 84]],
  [0.7, [234, 110, 40]],
  [0.87, [248, 184, 52]],
  [1.0, [252, 246, 170]],
];

/** Canvas background outside the map. */
export const BACKGROUND: Rgb = [15, 17, 23];
/** Cells of tiles not received yet. */
export const NO_DATA: Rgb = [96, 96, 96];

function build(): Rgb[] {
  const out: Rgb[] = [];
  for (let q = 0; q < 256; q++) {
    const p = q / 255;
    let i = 0;
    while (i < STOPS.length - 2 && p > STOPS[i + 1]![0]) i++;
    const [p0, c0] = STOPS[i]!;
    const [p1, c1] = STOPS[i + 1]!;
    const f = p1 > p0 ? Math.min(1, Math.max(0, (p - p0) / (p1 - p0))) : 0;
    out.push([
      Math.round(c0[0] + (c1[0] - c0[0]) * f),
      Math.round(c0[1] + (c1[1] - c0[1]) * f),
      Math.round(c0[2] + (c1[2] - c0[2]) * f),
    ]);
  }
  return out;
}

/** RGB of each q. */
export const LUT_RGB: readonly Rgb[] = build();

/** The same as 32-bit RGBA words in the byte order of ImageData on this machine. */
export const LUT32: Uint32Array = (() => {
  const lut = new Uint32Array(256);
  const bytes = new Uint8Array(lut.buffer);
  for (let q = 0; q < 256; q++) {
    const [r, g, b] = LUT_RGB[q]!;
    bytes[q * 4] = r;
    bytes[q * 4 + 1] = g;
    bytes[q * 4 + 2] = b;
    bytes[q * 4 + 3] = 255;
  }
  return lut;
})();

export const NO_DATA32: number = (() => {
  const w = new Uint32Array(1);
  const b = new Uint8Array(w.buffer);
  b[0] = NO_DATA[0];
  b[1] = NO_DATA[1];
  b[2] = NO_DATA[2];
  b[3] = 255;
  return w[0]!;
})();

export function css(c: Rgb): string {
  return `rgb(${c[0]},${c[1]},${c[2]})`;
}
