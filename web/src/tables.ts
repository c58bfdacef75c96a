// The region table, the UAV table, the target list and the command log.
import { el, fmt, fmtInt, setAttr, setEnabled, setText } from "./dom";
import { ROLE_NAMES, TARGET_COLOURS } from "./heatmap";
import type { Model, Uav } from "./model";
import type { RegionMsg } from "./types";

/** Why controls are disabled (null: enabled). */
export interface ControlState {
  command: string | null; // pause, obstacles, targets
  process: string | null; // kill / restart
}

const HEADING_ARROWS = ["→", "↗", "↑", "↖", "←", "↙", "↓", "↘"];

function badge(cell: HTMLElement, liveness: string): void {
  let b = cell.firstElementChild as HTMLElement | null;
  if (!b) {
    b = el("span");
    cell.appendChild(b);
  }
  setAttr(b, "class", `badge live-${liveness}`);
  setText(b, liveness);
}

function actionButton(action: string, key: string, id: number, label: string, title: string): HTMLButtonElement {
  const b = el("button", { type: "button", "data-action": action, [key]: String(id), class: "small" }, label);
  b.dataset["title"] = title;
  return b;
}

/** Rows keyed by id, kept in id order, updated in place. */
class KeyedRows<T> {
  private readonly rows = new Map<number, { tr: HTMLTableRowElement; cells: HTMLTableCellElement[] }>();

  constructor(
    private readonly tbody: HTMLTableSectionElement,
    private readonly attr: string,
    private readonly columns: number,
    private readonly make: (tr: HTMLTableRowElement, cells: HTMLTableCellElement[], id: number) => void,
    private readonly update: (tr: HTMLTableRowElement, cells: HTMLTableCellElement[], item: T) => void,
  ) {}

  sync(items: Iterable<[number, T]>): void {
    const seen = new Set<number>();
    const sorted = [...items].sort((a, b) => a[0] - b[0]);
    let prev: HTMLTableRowElement | null = null;
    for (const [id, item] of sorted) {
      seen.add(id);
      let row = this.rows.get(id);
      if (!row) {
        const tr = el("tr", { [`data-${this.attr}`]: String(id) });
        const cells: HTMLTableCellElement[] = [];
        for (let i = 0; i < this.columns; i++) {
          const td = el("td");
          cells.push(td);
          tr.appendChild(td);
        }
        this.make(tr, cells, id);
        row = { tr, cells };
        this.rows.set(id, row);
      }
      // Keep the id order without touching rows already in place.
      const want: Element | null = prev ? prev.nextElementSibling : this.tbody.firstElementChild;
      if (want !== row.tr) this.tbody.insertBefore(row.tr, want);
      this.update(row.tr, row.cells, item);
      prev = row.tr;
    }
    for (const [id, row] of this.rows) {
      if (!seen.has(id)) {
        row.tr.remove();
        this.rows.delete(id);
      }
    }
  }

  forEachRow(f: (tr: HTMLTableRowElement) => void): void {
    for (const r of this.rows.values()) f(r.tr);
  }
}

function updateButtons(tr: HTMLElement, controls: ControlState): void {
  for (const b of tr.querySelectorAll<HTMLButtonElement>("button[data-action]")) {
    setEnabled(b, controls.process, b.dataset["title"] ?? "");
  }
}

export class UavTable {
  private readonly rows: KeyedRows<Uav>;
  private readonly count: HTMLElement;

  constructor(table: HTMLTableElement, count: HTMLElement, private readonly controls: () => ControlState) {
    this.count = count;
    const tbody = table.tBodies[0] ?? table.createTBody();
    this.rows = new KeyedRows(
      tbody,
      "uav",
      8,
      (_tr, cells, id) => {
        setText(cells[0]!, String(id));
        cells[2]!.className = "num";
        cells[3]!.className = "num";
        cells[5]!.className = "num";
        const act = cells[7]!;
        act.className = "actions";
        act.appendChild(actionButton("kill_uav", "data-uav", id, "kill", `SIGKILL uav ${id}`));
        act.appendChild(actionButton("restart_uav", "data-uav", id, "restart", `start uav ${id} again`));
      },
      (tr, cells, u) => {
        setAttr(tr, "data-liveness", u.liveness);
        setText(cells[1]!, ROLE_NAMES[u.role] ?? String(u.role));
        setText(cells[2]!, fmt(u.x, 1));
        setText(cells[3]!, fmt(u.y, 1));
        setText(cells[4]!, `${HEADING_ARROWS[u.heading & 7] ?? "?"} ${u.heading}`);
        setText(cells[5]!, fmtInt(u.tick));
        badge(cells[6]!, u.liveness);
        updateButtons(tr, this.controls());
      },
    );
  }

  sync(m: Model): void {
    this.rows.sync(m.uavs.entries());
    let alive = 0;
    for (const u of m.uavs.values()) if (u.liveness === "alive") alive++;
    const expected = m.info.scenario.uavs_expected;
    setText(this.count, `${alive} alive / ${m.uavs.size}${expected ? ` (expected ${expected})` : ""}`);
  }

  refreshControls(): void {
    const c = this.controls();
    this.rows.forEachRow((tr) => updateButtons(tr, c));
  }
}

export class RegionTable {
  private readonly rows: KeyedRows<RegionMsg>;

  constructor(table: HTMLTableElement, private readonly controls: () => ControlState) {
    const tbody = table.tBodies[0] ?? table.createTBody();
    this.rows = new KeyedRows(
      tbody,
      "region",
      7,
      (_tr, cells, id) => {
        setText(cells[0]!, String(id));
        for (let i = 2; i <= 5; i++) cells[i]!.className = "num";
        cells[6]!.className = "actions";
        cells[6]!.appendChild(actionButton("kill_place", "data-region", id, "kill", `SIGKILL the place agent of region ${id}`));
      },
      (tr, cells, r) => {
        setAttr(tr, "data-liveness", r.liveness);
        badge(cells[1]!, r.liveness);
        setText(cells[2]!, fmtInt(r.tick));
        setText(cells[3]!, fmt(r.tick_rate_hz, 1));
        setText(cells[4]!, fmt(r.deposits_per_s, 1));
        const rej = cells[5]!;
        let a = rej.firstElementChild as HTMLElement | null;
        let b = rej.lastElementChild as HTMLElement | null;
        if (!a || a === b) {
          a = el("span", { class: "applied" });
          b = el("span", { class: "rejected" });
          rej.replaceChildren(a, document.createTextNode(" / "), b);
        }
        setText(a, fmtInt(r.deposits_applied));
        setText(b!, fmtInt(r.deposits_rejected));
        setAttr(b!, "class", (r.deposits_rejected ?? 0) > 0 ? "rejected warn" : "rejected");
        setAttr(rej, "title", `received ${fmtInt(r.deposits_received)}, applied ${fmtInt(r.deposits_applied)}, rejected ${fmtInt(r.deposits_rejected)}, samples refused as implausible ${fmtInt(r.samples_refused)}`);
        updateButtons(tr, this.controls());
      },
    );
  }

  sync(m: Model): void {
    this.rows.sync(m.regions.map((r) => [r.id, r] as [number, RegionMsg]));
  }

  refreshControls(): void {
    const c = this.controls();
    this.rows.forEachRow((tr) => updateButtons(tr, c));
  }
}

const STATUS_TEXT: Record<string, string> = { not_found: "not found", found: "found", revisit_due: "revisit due" };

export class TargetsPanel {
  constructor(private readonly list: HTMLElement, private readonly counts: Record<string, HTMLElement>) {}

  sync(m: Model): void {
    let found = 0;
    let notFound = 0;
    let revisit = 0;
    for (const t of m.targets) {
      if (t.status === "found") found++;
      else if (t.status === "revisit_due") revisit++;
      else notFound++;
    }
    let popup = 0;
    for (const o of m.obstacles) if (o.popup) popup++;
    setText(this.counts["found"]!, String(found));
    setText(this.counts["not_found"]!, String(notFound));
    setText(this.counts["revisit_due"]!, String(revisit));
    setText(this.counts["obstacles"]!, String(m.obstacles.length));
    setText(this.counts["popup"]!, String(popup));

    // The list is short (tens of targets); rebuild it when targets change.
    const items: HTMLElement[] = [];
    for (const t of m.targets) {
      const li = el("li", { "data-target": String(t.index), "data-status": t.status });
      const dot = el("span", { class: "dot" });
      dot.style.background = TARGET_COLOURS[t.status] ?? "#fff";
      li.appendChild(dot);
      let s = `#${t.index} (${t.x}, ${t.y}) ${STATUS_TEXT[t.status] ?? t.status}`;
      if (t.status !== "not_found" && t.found_by !== undefined && t.found_by >= 0) {
        s += ` by uav ${t.found_by} @ tick ${t.found_tick ?? "?"}`;
      }
      if (t.popup) s += " · pop-up";
      li.appendChild(document.createTextNode(s));
      items.push(li);
    }
    this.list.replaceChildren(...items);
  }
}

export class CommandLog {
  constructor(private readonly list: HTMLElement) {}

  sync(m: Model): void {
    const items = m.commands.map((c) => {
      const li = el("li", { "data-ok": String(c.ok) });
      li.appendChild(el("span", { class: "t" }, `${fmt(c.t_s, 1)} s`));
      li.appendChild(el("span", { class: `badge ${c.ok ? "ok" : "err"}` }, c.ok ? "ok" : "refused"));
      li.appendChild(el("span", { class: "what" }, c.what));
      if (c.result) li.appendChild(el("span", { class: "result" }, c.result));
      if (c.who) li.appendChild(el("span", { class: "who" }, c.who));
      return li;
    });
    if (items.length === 0) items.push(el("li", { class: "empty" }, "no commands yet"));
    this.list.replaceChildren(...items);
  }
}
