// The studio's page: wires the document store, the server, the canvas, the panels, the plots
// and synthesis. The server answers; the page draws.

import { Store, decodeFragment, encodeFragment } from "./state.js";
import { post, Analyst } from "./api.js";
import { View } from "./view.js";
import { Panels } from "./panels.js";
import { Plots } from "./plots.js";
import { Synthesis } from "./synth.js";
import { wireFiles, download } from "./io.js";
import { h } from "./dom.js";
import { addPoint, addPivot, addLink, addSlider, toggleGround, deletePoint, deleteLink, deleteJoint } from "./tools.js";

const BLANK = { machdyn: 1, title: "New linkage", units: { length: "mm", mass: "kg", force: "N", torque: "N*m" },
  linkage: { linkage: { points: {}, ground: [], drive: [], links: {} } } };

class App {
  constructor() {
    this.store = new Store();
    this.view = new View(document.getElementById("canvas"));
    this.panels = new Panels(this);
    this.plots = new Plots(this);
    this.synth = new Synthesis(this);
    this.result = null; this.error = null;
    this.frame = 0; this.playing = false; this.speed = 1; this.order = [0]; this.pos = 0;
    this.tool = "select"; this.pending = []; this.fitNext = true; this.editing = false;
    this.analyst = new Analyst((r, tag) => this.onResult(r, tag), (e, tag) => this.onError(e, tag));
    this.store.onChange((doc, committed) => this.onDoc(committed));
    this.stats = { requests: 0, drawn: 0 };
  }

  // -- status -------------------------------------------------------------------------
  status(text, bad = false) {
    const s = document.getElementById("status");
    s.textContent = text; s.className = bad ? "bad" : "";
  }
  // Messages about what was opened (a [fourbar] drawn as a linkage, what it could not keep):
  // shown under the toolbar until dismissed or another design is opened.
  notice(lines) {
    const box = document.getElementById("notice");
    document.getElementById("notice-text").replaceChildren(...(lines || []).map((t) => h("li", {}, t)));
    box.hidden = !(lines && lines.length);
  }
  hint(text) { document.getElementById("hint").textContent = text; }
  fail(err) {
    this.status(err.message + (err.key ? ` (${err.key})` : ""), true);
    if (err.status >= 500 || err.status === 0) console.warn("studio:", err.message);
  }

  // -- document changes ---------------------------------------------------------------
  onDoc(committed) {
    const part = this.store.part;
    this.view.doc = this.store.doc; this.view.part = part;
    if (!part) { this.result = null; this.view.scene = null; this.draw(); this.panels.render(); return; }
    this.reanalyse();
    if (committed) { this.panels.render(); this.updateHash(); }
    this.draw();
    document.getElementById("undo").disabled = !this.store.past.length;
    document.getElementById("redo").disabled = !this.store.future.length;
  }

  reanalyse() {
    const part = this.store.part;
    if (!part) return;
    const carried = new Set([...(part.ground || []), ...Object.values(part.links || {}).flatMap((l) => l.points)]);
    const loose = Object.keys(part.points || {}).filter((n) => !carried.has(n));
    if (!Object.keys(part.links || {}).length || !(part.drive || []).length || loose.length) {
      this.result = null; this.error = null; this.view.scene = null; this.view.problem = "sketch";
      if (this.tool === "select") this.hint(loose.length ? `A sketch: ${loose.join(", ")} on no link yet.` : "A sketch: add ground pivots and links (the first link on a ground pivot drives).");
      this.banner(); this.draw();
      return;
    }
    this.stats.requests++;
    this.analyst.request({
      doc: this.store.doc, samples: 360, quantities: this.plots.wanted(),
      centres: document.getElementById("centres").checked,
    }, { t: performance.now(), editing: this.editing });
  }

  onResult(r, tag) {
    if (this.error || document.getElementById("status").className === "bad") this.status("");
    this.result = r; this.error = null;
    const v = this.view;
    v.scene = { ...r.scene, closed_turn: r.closed && r.ok.every(Boolean) };
    v.problem = null;
    v.traces = (this.store.part && this.store.part.report) || [];
    v.centres = r.centres || null;
    v.limits = r.limits || [];
    this.order = this.playOrder(r);
    if (this.editing || !this.playing || tag.editing) this.frame = r.drawn;
    if (this.frame >= r.ok.length) this.frame = r.drawn;
    this.pos = Math.max(0, this.order.indexOf(this.frame));
    const slider = document.getElementById("frame");
    slider.max = String(r.ok.length - 1);
    if (this.fitNext) { v.fit(); this.fitNext = false; }
    this.plots.setResult(r);
    this.draw();
    this.banner();
    if (!this.editing) { this.panels.render(); }
    this.stats.drawn++;
    const now = performance.now();
    this.lastLatency = now - tag.t;
    // where a drag step's time goes: the server's analysis, the rest of the round trip, drawing
    this.timing = { total: now - tag.t, server: tag.server, cpu: tag.cpu, trip: tag.received - tag.t - (tag.server || 0), draw: now - tag.received };
    document.body.dataset.analysed = String(this.stats.drawn);
    const s = r.summary;
    v.svg.setAttribute("aria-label", `drawing of ${s.part}: mobility ${s.mobility}, driven by ${s.drivers.join(", ")}; ${r.ok.filter(Boolean).length} of ${r.ok.length} poses assembled`);
  }

  onError(err, tag) {
    this.error = err;
    this.result = null;
    this.view.problem = err.message;
    this.view.centres = null;
    if (this.fitNext) { this.view.fit(); this.fitNext = false; }
    this.draw();
    this.banner();
    this.panels.render();
    this.status(err.message + (err.key ? ` (${err.key})` : ""), true);
    this.lastLatency = performance.now() - tag.t;
    this.stats.drawn++;
    document.body.dataset.analysed = String(this.stats.drawn);
  }

  banner() {
    const b = document.getElementById("banner");
    const r = this.result;
    let text = "";
    if (this.error) text = "Cannot analyse: " + this.error.message;
    else if (r && r.problems.length) {
      const bad = r.ok.filter((v) => !v).length;
      text = `${bad} of ${r.ok.length} poses cannot be solved: ${r.problems[0].reason}` + (r.problems.length > 1 ? ` (+${r.problems.length - 1} more, see Analysis)` : "");
    }
    b.hidden = !text; b.textContent = text;
    b.className = this.error ? "banner error" : "banner";
  }

  updateHash() {
    clearTimeout(this.hashTimer);
    this.hashTimer = setTimeout(async () => {
      if (!this.store.doc) return;
      history.replaceState(null, "", "#" + await encodeFragment(this.store.doc));
    }, 300);
  }

  // Before another design is loaded: its plots start from its own defaults (the last
  // design's quantities are not asked for, nor reported missing).
  beforeLoad() { this.plots.selected = []; this.plots.gone = []; }

  afterLoad() {
    const part = this.store.part;
    this.fitNext = !!(part && Object.keys(part.points || {}).length);  // a blank sheet keeps the view
    this.select(null); this.playing = false; this.syncPlay();
    if (this.fitNext) { this.view.fit(); this.draw(); }
  }

  async edit(op, select) {
    try {
      const { doc } = await post("edit", { doc: this.store.doc, op });
      this.store.commit((d) => { for (const k of Object.keys(d)) delete d[k]; Object.assign(d, doc); });
      if (select) this.select(select);
    } catch (err) { this.fail(err); }
  }

  flip(group) { this.edit({ kind: "flip", group }); }

  select(sel) { this.view.selection = sel; this.panels.renderDesign(); this.draw(); }

  // -- playback -----------------------------------------------------------------------
  // The frames the animation visits: the whole turn, or there and back over the run of
  // assembled poses that holds the drawn one.
  playOrder(r) {
    const n = r.ok.length, ok = r.ok;
    if (ok.every(Boolean)) return r.closed ? [...Array(n).keys()] : [...[...Array(n).keys()], ...[...Array(n).keys()].reverse().slice(1, -1)];
    if (!ok[r.drawn]) return [r.drawn];
    let lo = r.drawn, hi = r.drawn;
    const wrap = r.closed;
    const prev = (i) => (wrap ? (i - 1 + n) % n : i - 1), next = (i) => (wrap ? (i + 1) % n : i + 1);
    for (let k = 0; k < n && prev(lo) >= 0 && ok[prev(lo)] && prev(lo) !== hi; k++) lo = prev(lo);
    for (let k = 0; k < n && next(hi) < n && ok[next(hi)] && next(hi) !== lo; k++) hi = next(hi);
    const run = [];
    for (let i = lo; ; i = next(i)) { run.push(i); if (i === hi) break; }
    return [...run, ...run.slice().reverse().slice(1, -1)];
  }

  goTo(frame) {
    this.playing = false; this.syncPlay();
    this.frame = frame;
    const k = this.order.indexOf(frame); if (k >= 0) this.pos = k;
    this.draw();
  }

  syncPlay() { document.getElementById("play").textContent = this.playing ? "❚❚" : "▶"; }

  tick(t) {
    if (this.playing && this.result && this.order.length > 1) {
      if (this.last === undefined) this.last = t;
      const rate = 90 * this.speed * this.order.length / 360 / (this.result.closed ? 1 : 1);
      const steps = Math.floor((t - this.last) * rate / 1000);
      if (steps > 0) {
        this.pos = (this.pos + steps) % this.order.length;
        this.frame = this.order[this.pos];
        this.last += steps * 1000 / rate;
        this.draw();
      }
    } else this.last = undefined;
    requestAnimationFrame((tt) => this.tick(tt));
  }

  draw() {
    const v = this.view;
    v.frame = this.frame;
    v.showHandles = !this.playing;
    v.render();
    const r = this.result;
    document.getElementById("frame").value = String(this.frame);
    const out = document.getElementById("readout");
    if (r && r.scene.readout) {
      out.textContent = r.scene.readout.slice(0, 3).map((q) => `${q.label} = ${q.v[this.frame] === null ? "–" : Number(q.v[this.frame]).toFixed(q.digits)} ${q.unit}`).join("   ");
    } else out.textContent = "";
    this.plots.cursor();
  }

  range() {
    const r = this.result;
    if (!r) return "–";
    const ang = r.summary.angle_drivers.includes(r.summary.drivers[0]);
    if (r.ok.every(Boolean) && r.closed) return "a full turn (crank)";
    const xs = this.order.map((i) => r.x[i]).filter((x) => x !== null);
    if (!xs.length) return "does not move";
    return `${Math.min(...xs).toFixed(2)} to ${Math.max(...xs).toFixed(2)} ${ang ? "" : ""}(${r.x_label})`;
  }

  // -- saving and exporting -----------------------------------------------------------
  async save() {
    try { const r = await post("save", { doc: this.store.doc }); this.status(`saved ${r.saved}`); }
    catch (err) { this.fail(err); }
  }

  async exportAs(format) {
    if (!this.store.doc) return;
    this.status(`exporting ${format}…`);
    try {
      const { blob, filename } = await post("export", { doc: this.store.doc, format, frame: this.frame });
      download(blob, filename);
      this.status(`exported ${filename}`);
    } catch (err) { this.fail(err); }
  }

  // -- pointer editing -----------------------------------------------------------------
  setTool(tool) {
    this.tool = tool; this.pending = []; this.view.rubber = null;
    for (const b of document.querySelectorAll("[data-tool]")) { b.classList.toggle("on", b.dataset.tool === tool); b.setAttribute("aria-pressed", String(b.dataset.tool === tool)); }
    const hints = {
      select: "", ground: "Click to place a ground pivot, or click a joint to make it (or unmake it) a ground pivot.",
      link: "Click joints or empty space, one after another; Enter, a double-click or clicking the last joint again ends the link.",
      slider: "Click the joint that slides, then a point along its guide (click a link to make the guide move with that link).",
    };
    this.hint(hints[tool] || "");
    this.draw();
  }

  snap(xy) {
    if (!document.getElementById("snap").checked) return xy;
    const s = this.view.gridStep() / 2;
    return xy.map((v) => Math.round(v / s) * s + 0);
  }

  // The joint under the pointer (within 10 px), or null.
  pointNear(px, py) {
    const part = this.store.part;
    if (!part) return null;
    let best = null, dist = 10;
    for (const name of Object.keys(part.points)) {
      const at = this.view.pointAt(name);
      if (!at) continue;
      const d = Math.hypot(this.view.sx(at[0]) - px, this.view.sy(at[1]) - py);
      if (d < dist) { dist = d; best = name; }
    }
    return best;
  }

  ensurePart() {
    if (this.store.part) return;
    this.store.load(BLANK, true);
  }

  wireCanvas() {
    const svg = this.view.svg;
    let drag = null;
    const local = (e) => { const r = svg.getBoundingClientRect(); return [e.clientX - r.left, e.clientY - r.top]; };
    svg.addEventListener("pointerdown", (e) => {
      const [px, py] = local(e);
      const world = this.snap(this.view.toWorld(px, py));
      const near = this.pointNear(px, py);
      const body = e.target.closest ? (e.target.closest("[data-body]") || {}).dataset : null;
      if (this.synth.active() && e.button === 0) {
        this.synth.pick(near ? this.view.pointAt(near) : world);
        if (this.synth.picking === "path") { drag = { sketch: true, x: px, y: py }; svg.setPointerCapture(e.pointerId); }  // or draw it
        return;
      }
      if (this.addingTo && e.button === 0) {
        const link = this.addingTo;
        this.addingTo = null; this.hint("");
        let name = null;
        this.store.commit((d, p) => {
          name = addPoint(p, world);
          p.links[link].points.push(name);
          p.report = [...(p.report || []), name];
        });
        this.select({ kind: "point", name });
        return;
      }
      if (e.button === 1 || (e.button === 0 && this.tool === "select" && !near && !(body && body.body))) {
        drag = { pan: true, x: px, y: py, tx: this.view.tx, ty: this.view.ty, moved: false };
        svg.setPointerCapture(e.pointerId);
        return;
      }
      if (e.button !== 0) return;
      if (this.tool === "select") {
        if (near) {
          this.playing = false; this.syncPlay();
          if (this.result) this.frame = this.result.drawn;
          this.select({ kind: "point", name: near });
          drag = { point: near, moved: false };
          this.editing = true;
          svg.setPointerCapture(e.pointerId);
        } else if (body && body.body && body.body !== "ground") {
          const part = this.store.part;
          const kind = part.links && part.links[body.body] ? "link" : "joint";
          this.select({ kind, name: body.body });
        }
      } else if (this.tool === "ground") {
        this.ensurePart();
        if (near) this.store.commit((d, p) => toggleGround(p, near));
        else this.store.commit((d, p) => { addPivot(p, world); });
      } else if (this.tool === "link") {
        this.ensurePart();
        let name = near;
        if (name && this.pending[this.pending.length - 1] === name) { this.finishLink(); return; }
        if (!name) { this.store.commit((d, p) => { name = addPoint(p, world); }); }
        this.pending.push(name);
        this.hint(`link: ${this.pending.join(" – ")} (Enter ends it, Esc cancels)`);
      } else if (this.tool === "slider") {
        this.ensurePart();
        if (!this.pending.length) {
          let name = near;
          if (!name) this.store.commit((d, p) => { name = addPoint(p, world); });
          this.pending = [name];
          this.hint(`slider at ${name}: now click along its guide (a link, or empty space for the ground)`);
        } else {
          const at = this.pending[0];
          const p0 = this.view.pointAt(at);
          const on = body && body.body && this.store.part.links[body.body] && !this.store.part.links[body.body].points.includes(at) ? body.body : "ground";
          const dir = [world[0] - p0[0], world[1] - p0[1]];
          if (Math.hypot(dir[0], dir[1]) === 0) return;
          this.store.commit((d, p) => addSlider(p, at, on, dir));
          this.pending = []; this.setTool("select");
        }
      }
    });
    svg.addEventListener("pointermove", (e) => {
      const [px, py] = local(e);
      if (drag && drag.pan) {
        this.view.tx = drag.tx + px - drag.x; this.view.ty = drag.ty + py - drag.y;
        drag.moved = drag.moved || Math.hypot(px - drag.x, py - drag.y) > 3;
        this.draw();
      } else if (drag && drag.sketch) {  // a path drawn freehand: a target every 24 px
        if (Math.hypot(px - drag.x, py - drag.y) >= 24) { drag.x = px; drag.y = py; this.synth.pick(this.view.toWorld(px, py)); }
      } else if (drag && drag.point) {
        const xy = this.snap(this.view.toWorld(px, py));
        drag.moved = true;
        this.store.preview((d, p) => { p.points[drag.point] = xy; });
      } else if ((this.tool === "link" || this.tool === "slider") && this.pending.length) {
        const from = this.view.pointAt(this.pending[this.pending.length - 1]);
        this.view.rubber = from ? { from, to: this.snap(this.view.toWorld(px, py)) } : null;
        this.draw();
      }
    });
    const end = () => {
      if (drag && drag.point) { this.editing = false; this.store.finish(); }
      else if (drag && drag.pan && !drag.moved) this.select(null);
      drag = null;
    };
    svg.addEventListener("pointerup", end);
    svg.addEventListener("pointercancel", end);
    svg.addEventListener("dblclick", () => { if (this.tool === "link") this.finishLink(); });
    svg.addEventListener("wheel", (e) => {
      e.preventDefault();
      const [px, py] = local(e);
      this.view.zoomAt(px, py, Math.exp(-e.deltaY * 0.0015));
      this.draw();
    }, { passive: false });
    window.addEventListener("resize", () => this.draw());
  }

  // The next click on the canvas adds a point to ``link`` (drawn there; traced).
  addPointTo(link) {
    this.addingTo = this.addingTo === link ? null : link;
    this.hint(this.addingTo ? `Click where the new point of ${link} goes (Esc cancels).` : "");
    this.panels.renderDesign();
  }

  finishLink() {
    const pts = [...new Set(this.pending)];
    this.pending = []; this.view.rubber = null;
    if (pts.length >= 2) this.store.commit((d, p) => { const n = addLink(p, pts); this.view.selection = { kind: "link", name: n }; });
    this.hint(this.tool === "link" ? "Next link: click its joints." : "");
    this.draw();
  }

  deleteSelection() {
    const s = this.view.selection;
    if (!s) return;
    this.store.commit((d, p) => (s.kind === "point" ? deletePoint(p, s.name) : s.kind === "link" ? deleteLink(p, s.name) : deleteJoint(p, s.name)));
    this.select(null);
  }

  wireKeys() {
    window.addEventListener("keydown", (e) => {
      const typing = ["INPUT", "SELECT", "TEXTAREA"].includes(document.activeElement.tagName);
      const ctrl = e.ctrlKey || e.metaKey;
      if (ctrl && e.key.toLowerCase() === "z" && !typing) { e.preventDefault(); e.shiftKey ? this.store.redo() : this.store.undo(); }
      else if (ctrl && e.key.toLowerCase() === "y" && !typing) { e.preventDefault(); this.store.redo(); }
      else if (ctrl && e.key.toLowerCase() === "s") { e.preventDefault(); this.save(); }
      else if (typing) return;
      else if (e.key === "Delete" || e.key === "Backspace") this.deleteSelection();
      else if (e.key === "Escape") { this.addingTo = null; this.pending = []; this.view.rubber = null; if (this.synth.active()) this.synth.stop(); this.setTool("select"); }
      else if (e.key === "Enter" && this.tool === "link") this.finishLink();
      else if (e.key === " ") { e.preventDefault(); this.togglePlay(); }
      else if (e.key === "f") { this.view.fit(); this.draw(); }
      else if (e.key.startsWith("Arrow")) { e.preventDefault(); this.arrow(e.key.slice(5), e.shiftKey, e.altKey); }
      else if (e.key === "+" || e.key === "=" || e.key === "-") { const [w, h] = this.view.size(); this.view.zoomAt(w / 2, h / 2, e.key === "-" ? 1 / 1.25 : 1.25); this.draw(); }
      else if ({ s: 1, g: 1, l: 1, p: 1 }[e.key]) this.setTool({ s: "select", g: "ground", l: "link", p: "slider" }[e.key]);
    });
  }

  // Arrow keys: move the selected joint by one snap step (Shift: ten, Alt: a tenth), or pan.
  arrow(dir, big, fine) {
    const [ux, uy] = { Left: [-1, 0], Right: [1, 0], Up: [0, 1], Down: [0, -1] }[dir] || [0, 0];
    const s = this.view.selection, part = this.store.part;
    if (s && s.kind === "point" && part && part.points[s.name]) {
      const step = this.view.gridStep() / 2 * (big ? 10 : fine ? 0.1 : 1);
      const round = (v) => Math.round(v / step * 1e6) / 1e6 * step;  // no 0.1 + 0.2 drift
      this.store.commit((d, p) => { const q = p.points[s.name]; p.points[s.name] = [round(q[0] + ux * step), round(q[1] + uy * step)]; });
      this.status(`${s.name} moved to (${this.store.part.points[s.name].map((v) => +v.toFixed(6)).join(", ")})`);
    } else {
      this.view.tx -= ux * 40 * (big ? 5 : 1); this.view.ty += uy * 40 * (big ? 5 : 1);
      this.draw();
    }
  }

  togglePlay() { this.playing = !this.playing; this.syncPlay(); this.draw(); }

  wireControls() {
    document.getElementById("play").addEventListener("click", () => this.togglePlay());
    document.getElementById("frame").addEventListener("input", (e) => this.goTo(Number(e.target.value)));
    document.getElementById("speed").addEventListener("change", (e) => { this.speed = Number(e.target.value); });
    document.getElementById("undo").addEventListener("click", () => this.store.undo());
    document.getElementById("redo").addEventListener("click", () => this.store.redo());
    document.getElementById("delete").addEventListener("click", () => this.deleteSelection());
    document.getElementById("fit").addEventListener("click", () => { this.view.fit(); this.draw(); });
    document.getElementById("centres").addEventListener("change", () => this.reanalyse());
    for (const b of document.querySelectorAll("[data-tool]")) b.addEventListener("click", () => this.setTool(b.dataset.tool));
    for (const b of document.querySelectorAll("[data-tab]")) {
      b.addEventListener("click", () => {
        for (const o of document.querySelectorAll("[data-tab]")) { o.classList.toggle("on", o === b); o.setAttribute("aria-selected", String(o === b)); }
        for (const t of document.querySelectorAll(".tab")) t.hidden = t.id !== "tab-" + b.dataset.tab;
        if (b.dataset.tab === "synthesis") this.synth.render();
      });
    }
    const tpl = document.getElementById("template");
    tpl.addEventListener("change", async () => {
      const name = tpl.value; tpl.value = "";
      if (!name) return;
      if (name === "blank") { this.beforeLoad(); this.store.load(BLANK, true); this.afterLoad(); this.notice([]); this.status("a blank sheet: place ground pivots, then links"); return; }
      try { const { doc } = await post("template", { name }); this.beforeLoad(); this.store.load(doc, true); this.afterLoad(); this.notice([]); this.status(`template: ${name}`); }
      catch (err) { this.fail(err); }
    });
  }

  async start() {
    this.wireCanvas(); this.wireKeys(); this.wireControls(); wireFiles(this);
    document.getElementById("notice-close").addEventListener("click", () => this.notice([]));
    let session = null;
    try { session = await post("session", {}); } catch (err) { this.fail(err); }
    if (session) {
      const tpl = document.getElementById("template");
      const blank = document.createElement("option"); blank.value = "blank"; blank.textContent = "blank sheet"; tpl.appendChild(blank);
      for (const [name, what] of Object.entries(session.templates)) {
        const o = document.createElement("option"); o.value = name; o.textContent = name; o.title = what; tpl.appendChild(o);
      }
      this.store.file = session.file;
      document.getElementById("save").disabled = !session.file;
      if (session.file) document.title = `${session.file} — machdyn studio`;
    }
    let doc = null;
    try { doc = await decodeFragment(location.hash); } catch (err) { this.status("the link's design could not be read: " + err.message, true); }
    if (doc) { this.store.load(doc); this.status("opened the design in the link"); }
    else if (session && session.doc) { this.store.load(session.doc); this.status(`opened ${session.file}`); this.notice(session.notes); }
    else if (session && session.error) { this.status(session.error, true); }
    else {
      try { const { doc: d } = await post("template", { name: "four-bar" }); this.store.load(d); this.status("a four-bar to start from: drag its joints, or pick a template"); }
      catch (err) { this.fail(err); }
    }
    this.panels.render(); this.synth.render();
    requestAnimationFrame((t) => this.tick(t));
  }
}

const app = new App();
window.studio = app;  // for tests and the benchmark: state only, no physics
app.start();
