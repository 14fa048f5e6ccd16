// Synthesis in the page: three-position motion generation (positions and pivots picked on the
// canvas) and path generation (points clicked or drawn on the canvas, or read from a CSV file).

import { h, fmt } from "./dom.js";
import { post } from "./api.js";

const POS = ["C1", "D1", "C2", "D2", "C3", "D3"];

export class Synthesis {
  constructor(app) {
    this.app = app;
    this.box = document.getElementById("tab-synthesis");
    this.motion = { pts: [], pivots: "moving", extra: [], result: null };
    this.path = { pts: [], closed: true, result: null, preview: null };
    this.picking = null;  // "motion" | "pivots" | "path"
  }

  // A click on the canvas while picking (world coordinates, already snapped).
  pick(xy) {
    if (this.picking === "motion") {
      this.motion.pts.push(xy);
      if (this.motion.pts.length >= 6) this.stop();
    } else if (this.picking === "pivots") {
      this.motion.extra.push(xy);
      if (this.motion.extra.length >= 2) this.stop();
    } else if (this.picking === "path") {
      this.path.pts.push(xy);
    }
    this.show();
    this.render();
    return true;
  }

  start(kind) {
    this.picking = kind;
    if (kind === "motion") { this.motion.pts = []; this.motion.extra = []; this.motion.result = null; }
    if (kind === "pivots") { this.motion.extra = []; this.motion.result = null; }
    if (kind === "path") { this.path.pts = []; this.path.result = null; this.path.preview = null; }
    this.app.hint(kind === "path" ? "Click target points along the path, or draw it with the mouse held down; press Done when finished."
      : kind === "pivots" ? `Click the ${this.motion.pivots === "fixed" ? "fixed pivots O2 then O4" : "moving pivots A then B (position 1)"}.`
        : "Click C1, D1 (position 1), then C2, D2 and C3, D3.");
    this.show(); this.render();
  }

  stop() { this.picking = null; this.app.hint(""); this.render(); }

  active() { return this.picking !== null; }

  // Marks and curves on the canvas for the task and its result.
  show() {
    const v = this.app.view, marks = [], curves = [];
    const m = this.motion;
    for (let k = 0; k + 1 < m.pts.length; k += 2) {
      marks.push({ x: m.pts[k][0], y: m.pts[k][1], to: m.pts[k + 1], label: `C${k / 2 + 1}D${k / 2 + 1}`, colour: "#7b3294", kind: "target" });
    }
    if (m.pts.length % 2) marks.push({ x: m.pts[m.pts.length - 1][0], y: m.pts[m.pts.length - 1][1], label: POS[m.pts.length - 1], colour: "#7b3294", kind: "target" });
    const names = m.pivots === "fixed" ? ["O2", "O4"] : ["A", "B"];
    m.extra.forEach((p, k) => marks.push({ x: p[0], y: p[1], label: names[k], colour: "#1b7837", kind: m.pivots === "fixed" ? "pivot" : "target" }));
    if (m.result) {
      const r = m.result;
      marks.push({ x: r.O2[0], y: r.O2[1], label: "O2", colour: "#1b7837", kind: "pivot" }, { x: r.O4[0], y: r.O4[1], label: "O4", colour: "#1b7837", kind: "pivot" });
      r.A.forEach((a, k) => curves.push({ pts: [r.O2, a, r.B[k], r.O4], colour: r.defects.length ? "#d62728" : "#1b7837", dashed: k > 0, cls: "synth" }));
    }
    const p = this.path;
    p.pts.forEach((q, k) => marks.push({ x: q[0], y: q[1], label: String(k + 1), colour: "#e66101", kind: "target" }));
    if (p.preview) {
      curves.push({ pts: p.preview.curve, colour: "#e66101", dashed: false, cls: "synth" });
      const pts = p.preview.doc.linkage.path.points;
      marks.push({ x: pts.O2[0], y: pts.O2[1], label: "O2", colour: "#e66101", kind: "pivot" }, { x: pts.O4[0], y: pts.O4[1], label: "O4", colour: "#e66101", kind: "pivot" });
      curves.push({ pts: [pts.O2, pts.A, pts.B, pts.O4], colour: "#e66101", dashed: true, cls: "synth" });
    }
    v.marks = marks; v.curves = curves;
    v.svg.classList.toggle("dimmed", !!(this.picking || m.pts.length || p.pts.length));
    this.app.draw();
  }

  clear() { this.motion = { pts: [], pivots: this.motion.pivots, extra: [], result: null }; this.path = { pts: [], closed: this.path.closed, result: null, preview: null }; this.picking = null; this.show(); this.render(); }

  async runMotion() {
    const m = this.motion;
    const c = [m.pts[0], m.pts[2], m.pts[4]], d = [m.pts[1], m.pts[3], m.pts[5]];
    const body = { c, d, units: (this.app.store.doc && this.app.store.doc.units) || undefined };
    if (m.extra.length === 2) {
      if (m.pivots === "fixed") { body.O2 = m.extra[0]; body.O4 = m.extra[1]; } else { body.A = m.extra[0]; body.B = m.extra[1]; }
    }
    try {
      m.result = await post("synth_motion", body);
      this.app.status(m.result.defects.length ? `synthesis: ${m.result.defects.join("; ")}` : "synthesis: the linkage moves the coupler through the three positions in order", !!m.result.defects.length);
    } catch (err) { m.result = null; this.app.fail(err); }
    this.show(); this.render();
  }

  async runPath() {
    const p = this.path;
    this.app.status("path synthesis: searching the atlas…");
    this.busy = true; this.render();
    try {
      p.result = await post("synth_path", { targets: p.pts, closed: p.closed, n: 5, units: (this.app.store.doc && this.app.store.doc.units) || undefined });
      p.preview = p.result.candidates[0] || null;
      this.app.status(`path synthesis: ${p.result.candidates.length} candidates (${p.result.source})${p.result.note ? " — " + p.result.note : ""}`);
    } catch (err) { p.result = null; this.app.fail(err); }
    this.busy = false;
    this.show(); this.render();
  }

  readCsv(file) {
    file.text().then((text) => {
      const pts = [];
      for (const line of text.split(/\r?\n/)) {
        const cells = line.split(/[,;\t ]+/).filter(Boolean).map(Number);
        if (cells.length >= 2 && cells.slice(0, 2).every(isFinite)) pts.push([cells[0], cells[1]]);
      }
      if (pts.length < 3) { this.app.status(`${file.name}: no x,y rows found`, true); return; }
      this.path.pts = pts; this.path.result = null; this.path.preview = null;
      this.show(); this.render(); this.app.view.fit(); this.app.draw();
    });
  }

  render() {
    const m = this.motion, p = this.path, app = this.app;
    const picking = (k) => this.picking === k;
    const pivotSel = h("select", { "aria-label": "pivots" },
      h("option", { value: "moving" }, "moving pivots: C and D"), h("option", { value: "picked" }, "moving pivots: pick A, B"), h("option", { value: "fixed" }, "fixed pivots: pick O2, O4"));
    pivotSel.value = m.pivots === "fixed" ? "fixed" : m.extra.length || m.pivots === "picked" ? "picked" : "moving";
    pivotSel.addEventListener("change", () => { m.pivots = pivotSel.value; m.extra = []; m.result = null; if (m.pivots !== "moving") this.start("pivots"); else { this.show(); this.render(); } });
    const res = m.result;
    const motion = h("section", { class: "card" }, h("h3", {}, "Three-position motion generation"),
      h("p", { class: "muted" }, `Positions of the coupler line CD: ${m.pts.length} of 6 points picked.`),
      h("div", { class: "buttons" },
        h("button", { class: picking("motion") ? "on" : "", onclick: () => this.start("motion") }, "Pick positions"),
        pivotSel,
        h("button", { disabled: m.pts.length < 6 || (m.pivots !== "moving" && m.extra.length < 2), onclick: () => this.runMotion(), id: "run-motion" }, "Synthesise")),
      res ? h("div", { class: "result" },
        h("table", { class: "facts" },
          h("tr", {}, h("th", {}, "O2, O4"), h("td", {}, `(${fmt(res.O2[0])}, ${fmt(res.O2[1])}), (${fmt(res.O4[0])}, ${fmt(res.O4[1])})`)),
          h("tr", {}, h("th", {}, "r1, r2, r3, r4"), h("td", { "data-key": "lengths" }, res.lengths.map((v) => fmt(v)).join(", "))),
          h("tr", {}, h("th", {}, "class"), h("td", {}, res.class)),
          h("tr", {}, h("th", {}, "θ2 at the positions"), h("td", {}, res.theta2_deg.map((v) => fmt(v, 4) + "°").join(", "))),
          h("tr", {}, h("th", {}, "μ min"), h("td", {}, res.mu_min_deg === null ? "–" : fmt(res.mu_min_deg, 3) + "°"))),
        res.defects.length ? h("ul", { class: "defects" }, ...res.defects.map((d) => h("li", {}, d))) : h("p", { class: "good" }, "No circuit, branch or order defect."),
        h("button", { onclick: () => app.store.load(res.doc, true) || app.afterLoad(), id: "open-motion" }, "Open as design")) : null);
    const cands = p.result ? p.result.candidates : [];
    const closed = h("input", { type: "checkbox", "aria-label": "closed path" });
    closed.checked = p.closed;
    closed.addEventListener("change", () => { p.closed = closed.checked; });
    const csv = h("input", { type: "file", accept: ".csv,.txt", hidden: true });
    csv.addEventListener("change", () => csv.files[0] && this.readCsv(csv.files[0]));
    const path = h("section", { class: "card" }, h("h3", {}, "Path generation"),
      h("p", { class: "muted" }, `${p.pts.length} target points.`),
      h("div", { class: "buttons" },
        h("button", { id: "pick-path", class: picking("path") ? "on" : "", onclick: () => (picking("path") ? this.stop() : this.start("path")) }, picking("path") ? "Done" : "Click or draw points"),
        h("button", { onclick: () => csv.click() }, "Load CSV"), csv,
        h("label", { class: "check" }, closed, " closed"),
        h("button", { disabled: p.pts.length < 5 || this.busy, onclick: () => this.runPath(), id: "run-path" }, this.busy ? "Searching…" : "Synthesise")),
      cands.length ? h("table", { class: "candidates" }, h("tr", {}, h("th", {}, "#"), h("th", {}, "worst distance"), h("th", {}, "class"), h("th", {}, "μ min"), h("th", {}, "")),
        ...cands.map((c) => h("tr", { class: p.preview === c ? "on" : "", onmouseenter: () => { p.preview = c; this.show(); } },
          h("td", {}, String(c.rank)), h("td", {}, fmt(c.max_distance, 3)), h("td", {}, c.class + (c.defects.length ? " ⚠" : "")), h("td", {}, fmt(c.mu_min_deg, 3) + "°"),
          h("td", {}, h("button", { class: "small", onclick: () => { app.store.load(c.doc, true); app.afterLoad(); } }, "Open"))))) : null);
    this.box.replaceChildren(motion, path, h("button", { onclick: () => this.clear() }, "Clear synthesis marks"));
  }
}
