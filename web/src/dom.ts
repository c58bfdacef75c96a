// Tiny DOM helpers: the page is plain DOM, updated in place so that rows keep
// their identity (a click never lands on a row that was just replaced).

export function $(id: string): HTMLElement {
  const e = document.getElementById(id);
  if (!e) throw new Error(`the page has no #${id}`);
  return e;
}

export function el<K extends keyof HTMLElementTagNameMap>(
  tag: K,
  attrs: Record<string, string> = {},
  text?: string,
): HTMLElementTagNameMap[K] {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (k === "class") e.className = v;
    else e.setAttribute(k, v);
  }
  if (text !== undefined) e.textContent = text;
  return e;
}

/** Sets text only when it differs (no layout work for unchanged cells). */
export function setText(e: Element, s: string): void {
  if (e.textContent !== s) e.textContent = s;
}

export function setAttr(e: Element, name: string, value: string): void {
  if (e.getAttribute(name) !== value) e.setAttribute(name, value);
}

/** Enables a control, or disables it with the reason as its tooltip. */
export function setEnabled(e: HTMLButtonElement | HTMLInputElement | HTMLSelectElement, reason: string | null, title = ""): void {
  const disabled = reason !== null;
  if (e.disabled !== disabled) e.disabled = disabled;
  setAttr(e, "title", disabled ? reason : title);
}

export function fmt(v: number | undefined, digits = 1): string {
  if (v === undefined || v === null || !Number.isFinite(v)) return "–";
  return v.toFixed(digits);
}

/** A value of the colour scale: short, without trailing zeros. */
export function fmtValue(v: number): string {
  if (v === 0) return "0";
  const a = Math.abs(v);
  if (a >= 1000) return v.toExponential(1);
  if (a >= 100) return v.toFixed(0);
  if (a >= 1) return String(Number(v.toFixed(2)));
  return String(Number(v.toPrecision(2)));
}

export function fmtInt(v: number | undefined): string {
  if (v === undefined || v === null || !Number.isFinite(v)) return "–";
  return String(Math.round(v));
}
