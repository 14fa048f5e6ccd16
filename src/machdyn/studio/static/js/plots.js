// Plots of any quantity the server computed, against the input, with a cursor tied to the
// drawing: the cursor follows the animation, and clicking or dragging on a plot moves it.

import { h, fmt } from "./dom.js";
import { el } from "./view.js";

const COLOURS = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"];

function swatch(colour) { const i = h("i", {}); i.style.background = colour; return i; }

function unitOf(name) { const m = /\[([^\]]*)\]\s*$/.exec(name); return m ? m[1] : ""; }

// Whether `after` is `before` with some of its occurrences of `old` written `now` (and differs).
function swapped(before, after, old, now) {
  const go = (i, j) => {
    if (i === before.length || j === after.length) return i === before.length && j === after.length;
    if (before.startsWith(old, i) && after.startsWith(now, j) && go(i + old.length, j + now.length)) return true;
    return before[i] === after[j] && go(i + 1, j + 1);
  };
  return before !== after && go(0, 0);
}

function ticks(lo, hi, target = 5) {
  const span = hi - lo || Math.abs(hi) || 1;
  const raw = span / target, p = Math.pow(10, Math.floor(Math.log10(raw)));
  const step = [1, 2, 5, 10].map((m) => m * p).find((s) => s >= raw) || 10 * p;
  const out = [];
  for (let v = Math.ceil(lo / step) * step; v <= hi + step * 1e-9; v += step) out.push(Math.abs(v) < step * 1e-9 ? 0 : v);
  return out;
}

export class Plots {
  constructor(app) {
    this.app = app;
    this.box = document.getElementById("tab-plots");
    this.selected = [];
    this.filter = "";
    this.charts = [];
    this.gone = [];  // asked-for quantities the last answer had no column for (its `unknown`)
    this.seen = null;  // the last answer's names and the design's link and joint names then
  }

  // A link or joint renamed (or its renaming undone or redone): its plots follow the new
  // name. A plot follows only when the new answer has as many columns and the one at its
  // place is its name with the old name written anew; otherwise it is taken off, as before.
  followRenames(r) {
    const part = this.app.store.part || {};
    const before = this.seen;
    this.seen = { names: r.names, ids: new Set([...Object.keys(part.links || {}), ...Object.keys(part.points || {})]) };
    if (!before || !r.unknown || !r.unknown.length || before.names.length !== r.names.length) return;
    const old = [...before.ids].filter((n) => !this.seen.ids.has(n));
    const now = [...this.seen.ids].filter((n) => !before.ids.has(n));
    if (old.length !== 1 || now.length !== 1) return;
    const moved = new Map();
    for (const n of r.unknown) {
      const i = before.names.indexOf(n);
      if (i >= 0 && swapped(n, r.names[i], old[0], now[0])) moved.set(n, r.names[i]);
    }
    this.selected = this.selected.map((n) => moved.get(n) || n);
    r.unknown = r.unknown.filter((n) => !moved.has(n));
  }

  goneText() {
    const n = this.gone.length;
    return `${n === 1 ? "This plot was" : "These plots were"} taken off: ${this.gone.join(", ")} — the design no longer has ${n === 1 ? "that quantity" : "those quantities"} (its link or joint deleted?). Tick others below.`;
  }

  defaults(r) {
    const names = r.names;
    const pick = [];
    // a block (a one-point link) on a fixed guide keeps its angle: plot a link that turns
    const links = (this.app.store.part && this.app.store.part.links) || {};
    const turns = (n) => { const l = links[n.replace(/^theta_/, "").replace(/ \[.*$/, "")]; return !l || l.points.length > 1; };
    const out = names.find((n) => /^theta_/.test(n) && turns(n) && !n.startsWith(r.x_label.split(" ")[0]));
    const lastTheta = names.filter((n) => /^theta_/.test(n) && turns(n)).pop();
    if (lastTheta && lastTheta !== names[0]) pick.push(lastTheta); else if (out) pick.push(out);
    const mu = names.find((n) => /^mu_/.test(n));
    if (mu) pick.push(mu);
    else { const omega = names.filter((n) => /^omega_/.test(n)).pop(); if (omega) pick.push(omega); }
    const torque = names.find((n) => /^[TF]_/.test(n) && (r.summary.drivers || []).some((d) => n.startsWith(`T_${d} `) || n.startsWith(`F_${d} `)));
    if (torque) pick.push(torque);
    return pick;
  }

  wanted() { return this.selected.length ? this.selected : null; }

  setResult(r) {
    this.followRenames(r);
    if (r.unknown && r.unknown.length) {
      this.gone = [...new Set([...this.gone, ...r.unknown])];
      this.selected = this.selected.filter((n) => !r.unknown.includes(n));
      this.app.status(this.goneText());
    }
    if (!this.selected.length || !this.selected.every((n) => r.names.includes(n))) {
      this.selected = this.selected.filter((n) => r.names.includes(n));
      if (!this.selected.length) this.selected = this.defaults(r);
    }
    this.render();
  }

  toggle(name) {
    this.gone = [];
    const i = this.selected.indexOf(name);
    if (i >= 0) this.selected.splice(i, 1); else this.selected.push(name);
    this.app.reanalyse();
  }

  render() {
    const r = this.app.result;
    if (!r) { this.box.replaceChildren(h("p", { class: "empty" }, "Nothing to plot yet.")); return; }
    const missing = this.selected.filter((n) => !(n in r.columns));
    if (missing.length) { this.app.reanalyse(); }
    const key = r.names.join("\n") + "\n" + this.selected.join("\n");
    if (!this.listBox || this.listKey !== key) {
      const filter = h("input", { type: "search", placeholder: "filter quantities (e.g. omega, mu, F_, |V)", value: this.filter, "aria-label": "filter" });
      const list = h("div", { class: "quantities" });
      filter.addEventListener("input", () => { this.filter = filter.value; this.renderList(list, this.app.result); });
      this.renderList(list, r);
      this.listBox = h("div", {}, h("h3", {}, "Quantities"), filter, list);
      this.listKey = key;
    }
    const charts = h("div", { class: "charts" });
    if (this.gone.length) charts.appendChild(h("div", { class: "card note", role: "status" }, this.goneText()));
    this.charts = [];
    const byUnit = new Map();
    for (const name of this.selected) {
      if (!(name in r.columns)) continue;
      const u = unitOf(name);
      if (!byUnit.has(u)) byUnit.set(u, []);
      byUnit.get(u).push(name);
    }
    for (const [u, names] of byUnit) charts.appendChild(this.chart(r, names, u));
    if (!byUnit.size) charts.appendChild(h("p", { class: "empty" }, "Tick quantities below to plot them against the input."));
    if (this.box.firstChild && this.box.firstChild.classList.contains("charts")) {
      this.box.replaceChild(charts, this.box.firstChild);
      if (this.box.lastChild !== this.listBox) this.box.replaceChildren(charts, this.listBox);
    } else this.box.replaceChildren(charts, this.listBox);
    this.cursor();
  }

  renderList(list, r) {
    const f = this.filter.toLowerCase();
    const items = r.names.slice(1).filter((n) => !f || n.toLowerCase().includes(f));
    list.replaceChildren(...items.map((n) => {
      const c = h("input", { type: "checkbox", "data-q": n });
      c.checked = this.selected.includes(n);
      c.addEventListener("change", () => this.toggle(n));
      return h("label", { class: "q" }, c, " ", n);
    }));
  }

  chart(r, names, unit) {
    const W = 420, H = 210, L = 54, R = 10, T = 12, B = 34;
    const svg = el("svg", { class: "chart", viewBox: `0 0 ${W} ${H}`, role: "img", "aria-label": names.join(", ") });
    const xs = r.x;
    const good = xs.map((x, i) => x !== null && r.ok[i]);
    let y0 = Infinity, y1 = -Infinity;
    for (const n of names) for (const [i, v] of r.columns[n].entries()) if (v !== null && good[i]) { y0 = Math.min(y0, v); y1 = Math.max(y1, v); }
    if (!isFinite(y0)) { y0 = -1; y1 = 1; }
    if (y1 - y0 < 1e-12 * Math.max(1, Math.abs(y0))) { y0 -= 1; y1 += 1; }
    const pad = 0.06 * (y1 - y0); y0 -= pad; y1 += pad;
    const xv = xs.filter((x) => x !== null);
    const x0 = Math.min(...xv), x1 = Math.max(...xv);
    const X = (x) => L + (W - L - R) * (x - x0) / ((x1 - x0) || 1);
    const Y = (y) => T + (H - T - B) * (1 - (y - y0) / (y1 - y0));
    // flagged samples: shaded, with the reason
    let start = null;
    for (let i = 0; i <= xs.length; i++) {
      const bad = i < xs.length && !r.ok[i];
      if (bad && start === null) start = i;
      if (!bad && start !== null) {
        const a = X(xs[Math.max(start - 1, 0)]), b = X(xs[Math.min(i, xs.length - 1)]);
        const band = el("rect", { x: a, y: T, width: Math.max(b - a, 1), height: H - T - B, class: "flagged" }, svg);
        el("title", {}, band, r.reason[start]);
        start = null;
      }
    }
    const axes = el("g", { class: "axes" }, svg);
    for (const t of ticks(y0, y1)) {
      el("line", { x1: L, x2: W - R, y1: Y(t), y2: Y(t), class: "gridline" }, axes);
      el("text", { x: L - 4, y: Y(t) + 3, "text-anchor": "end" }, axes, fmt(t, 3));
    }
    for (const t of ticks(x0, x1, 6)) {
      el("line", { x1: X(t), x2: X(t), y1: T, y2: H - B, class: "gridline" }, axes);
      el("text", { x: X(t), y: H - B + 13, "text-anchor": "middle" }, axes, fmt(t, 4));
    }
    el("text", { x: (L + W - R) / 2, y: H - 4, "text-anchor": "middle", class: "label" }, axes, r.x_label);
    el("text", { x: 12, y: (T + H - B) / 2, transform: `rotate(-90 12 ${(T + H - B) / 2})`, "text-anchor": "middle", class: "label" }, axes, unit ? `[${unit}]` : "");
    names.forEach((n, k) => {
      let d = "", pen = false;
      r.columns[n].forEach((v, i) => {
        if (v === null || !good[i] || (i > 0 && pen && xs[i] < xs[i - 1])) { pen = false; if (v === null || !good[i]) return; }
        d += (pen ? "L" : "M") + X(xs[i]).toFixed(1) + " " + Y(v).toFixed(1);
        pen = true;
      });
      el("path", { d, class: "series", stroke: COLOURS[k % COLOURS.length], "data-q": n }, svg);
    });
    for (const m of r.limits || []) {
      if (m.kind === "limit") el("line", { x1: X(xs[m.frame]), x2: X(xs[m.frame]), y1: T, y2: H - B, class: "limitline" }, svg);
    }
    const cursor = el("line", { y1: T, y2: H - B, class: "cursor" }, svg);
    const legend = h("div", { class: "legend" }, ...names.map((n, k) => h("span", {}, swatch(COLOURS[k % COLOURS.length]), n, " = ", h("b", { "data-value": n }, "–"))));
    const pick = (e) => {
      const rect = svg.getBoundingClientRect();
      const x = x0 + (((e.clientX - rect.left) / rect.width) * W - L) / (W - L - R) * (x1 - x0);
      let best = 0, dist = Infinity;
      xs.forEach((v, i) => { if (v !== null && Math.abs(v - x) < dist) { dist = Math.abs(v - x); best = i; } });
      this.app.goTo(best);
    };
    svg.addEventListener("pointerdown", (e) => { svg.setPointerCapture(e.pointerId); pick(e); });
    svg.addEventListener("pointermove", (e) => { if (e.buttons) pick(e); });
    this.charts.push({ cursor, X, names, legend });
    return h("div", { class: "chart-box" }, svg, legend);
  }

  cursor() {
    const r = this.app.result;
    if (!r) return;
    const i = this.app.frame;
    for (const c of this.charts) {
      const x = r.x[i];
      if (x === null) continue;
      c.cursor.setAttribute("x1", c.X(x)); c.cursor.setAttribute("x2", c.X(x));
      for (const n of c.names) {
        const b = c.legend.querySelector(`b[data-value="${CSS.escape(n)}"]`);
        const col = r.columns[n];
        if (b) b.textContent = r.ok[i] && col ? fmt(col[i], 5) : "–";
      }
    }
  }
}
