// The canvas: draws the server's scene (solved coordinates per frame), the document's joints
// as handles, traces, instant centres and synthesis marks, in an SVG with zoom and pan.
// Only drawing happens here: every coordinate comes from the server or from the user.

const NS = "http://www.w3.org/2000/svg";

export function el(tag, attrs = {}, parent = null, text = null) {
  const e = document.createElementNS(NS, tag);
  for (const [k, v] of Object.entries(attrs)) if (v !== null && v !== undefined) e.setAttribute(k, String(v));
  if (text !== null) e.textContent = text;
  if (parent) parent.appendChild(e);
  return e;
}

export class View {
  constructor(svg) {
    this.svg = svg;
    this.scale = 4;          // screen px per drawing unit
    this.tx = 300; this.ty = 300;
    this.scene = null;       // the server's scene (frame data)
    this.frame = 0;
    this.doc = null; this.part = null;
    this.selection = null;   // {kind: "point"|"link"|"joint", name}
    this.traces = [];        // point names whose paths are drawn
    this.centres = null;     // instant centres from the server
    this.marks = [];         // synthesis marks: {x, y, label, colour, kind}
    this.curves = [];        // extra curves: {pts: [[x,y]|null], colour, dashed}
    this.rubber = null;      // tool preview: {from: [x,y], to: [x,y]}
    this.showHandles = true;
    this.problem = null;     // the document cannot be solved: draw it as given
    this.limits = [];        // frames marked as limit/toggle positions
    this.root = el("g", {}, svg);
  }

  // -- coordinates ------------------------------------------------------------------
  sx(x) { return this.tx + this.scale * x; }
  sy(y) { return this.ty - this.scale * y; }
  toWorld(px, py) { return [(px - this.tx) / this.scale, (this.ty - py) / this.scale]; }

  size() {
    const r = this.svg.getBoundingClientRect();
    return [r.width || 800, r.height || 600];
  }

  fit() {
    const pts = [];
    const pushXY = (x, y) => { if (x !== null && y !== null && isFinite(x) && isFinite(y)) pts.push([x, y]); };
    if (this.part) for (const p of Object.values(this.part.points || {})) pushXY(p[0], p[1]);
    if (this.scene) {
      const n = this.scene.names.length;
      for (let j = 0; j < n; j++) for (let i = 0; i < this.scene.frames; i += 6) pushXY(this.X(j, i), this.Y(j, i));
    }
    for (const m of this.marks) pushXY(m.x, m.y);
    if (!pts.length) { pts.push([-10, -10], [10, 10]); }
    const xs = pts.map((p) => p[0]), ys = pts.map((p) => p[1]);
    const [x0, x1, y0, y1] = [Math.min(...xs), Math.max(...xs), Math.min(...ys), Math.max(...ys)];
    const [w, h] = this.size();
    const span = Math.max(x1 - x0, y1 - y0, 1e-9);
    // clear of the view bar (top) and the play bar (bottom) drawn over the canvas
    const top = 100, bottom = h - 75;
    this.scale = Math.min((w - 80) / Math.max(x1 - x0, span * 0.2), (bottom - top) / Math.max(y1 - y0, span * 0.2));
    this.tx = w / 2 - this.scale * (x0 + x1) / 2;
    this.ty = (top + bottom) / 2 + this.scale * (y0 + y1) / 2;
  }

  zoomAt(px, py, factor) {
    const [x, y] = this.toWorld(px, py);
    this.scale = Math.min(Math.max(this.scale * factor, 1e-6), 1e9);
    this.tx = px - this.scale * x;
    this.ty = py + this.scale * y;
  }

  // A "nice" grid spacing: about 40 px, 1-2-5 steps, in drawing units.
  gridStep() {
    const raw = 40 / this.scale;
    const p = Math.pow(10, Math.floor(Math.log10(raw)));
    for (const m of [1, 2, 5, 10]) if (m * p >= raw) return m * p;
    return 10 * p;
  }

  // -- scene data ---------------------------------------------------------------------
  X(j, i) { const c = this.scene.x[j]; return Array.isArray(c) ? c[i] : c; }
  Y(j, i) { const c = this.scene.y[j]; return Array.isArray(c) ? c[i] : c; }
  ok(j, i) { const x = this.X(j, i), y = this.Y(j, i); return x !== null && y !== null && x !== undefined; }

  // Where a named point is drawn now: its solved position in this frame, or the document's.
  pointAt(name) {
    if (this.scene && !this.problem) {
      const j = this.scene.names.indexOf(name);
      if (j >= 0 && this.ok(j, this.frame)) return [this.X(j, this.frame), this.Y(j, this.frame)];
    }
    const p = this.part && this.part.points[name];
    return p ? [p[0], p[1]] : null;
  }

  // -- drawing ------------------------------------------------------------------------
  render() {
    const root = el("g", {});
    this.drawGrid(root);
    const world = el("g", { class: "world" }, root);
    for (const c of this.curves) this.drawCurve(world, c.pts, c.colour, c.dashed, c.cls);
    if (this.scene && !this.problem) {
      this.drawTraces(world);
      this.drawItems(world);
      this.drawLimits(world);
    } else if (this.part) {
      this.drawDocument(world);
    }
    if (this.centres) this.drawCentres(world);
    this.drawMarks(world);
    if (this.showHandles && this.part) this.drawHandles(world);
    if (this.rubber) {
      const { from, to } = this.rubber;
      el("line", { x1: this.sx(from[0]), y1: this.sy(from[1]), x2: this.sx(to[0]), y2: this.sy(to[1]), class: "rubber" }, world);
    }
    this.svg.replaceChild(root, this.root);
    this.root = root;
  }

  drawGrid(root) {
    const [w, h] = this.size();
    const step = this.gridStep();
    const g = el("g", { class: "grid" }, root);
    const [x0, y1] = this.toWorld(0, 0), [x1, y0] = this.toWorld(w, h);
    let d = "";
    for (let x = Math.ceil(x0 / step) * step; x <= x1; x += step) d += `M${this.sx(x).toFixed(1)} 0V${h}`;
    for (let y = Math.ceil(y0 / step) * step; y <= y1; y += step) d += `M0 ${this.sy(y).toFixed(1)}H${w}`;
    el("path", { d }, g);
    el("path", { d: `M${this.sx(0)} 0V${h}M0 ${this.sy(0)}H${w}`, class: "axes" }, g);
  }

  drawCurve(g, pts, colour, dashed, cls = "curve") {
    let d = "", pen = false;
    for (const p of pts) {
      if (!p || p[0] === null || p[1] === null) { pen = false; continue; }
      d += (pen ? "L" : "M") + this.sx(p[0]).toFixed(1) + " " + this.sy(p[1]).toFixed(1);
      pen = true;
    }
    if (d) el("path", { d, class: cls, stroke: colour, "stroke-dasharray": dashed ? "6 4" : null }, g);
  }

  drawTraces(g) {
    const s = this.scene;
    for (const name of this.traces) {
      const j = s.names.indexOf(name);
      if (j < 0) continue;
      const pts = [];
      for (let i = 0; i < s.frames; i++) pts.push(this.ok(j, i) ? [this.X(j, i), this.Y(j, i)] : null);
      if (s.closed_turn && pts[0]) pts.push(pts[0]);
      this.drawCurve(g, pts, "#d62728", false, "trace");
    }
  }

  drawLimits(g) {
    const s = this.scene;
    for (const mark of this.limits) {
      for (const name of this.traces) {
        const j = s.names.indexOf(name);
        if (j < 0 || !this.ok(j, mark.frame)) continue;
        const x = this.sx(this.X(j, mark.frame)), y = this.sy(this.Y(j, mark.frame));
        const m = el("g", { class: "limit " + mark.kind }, g);
        el("rect", { x: x - 4, y: y - 4, width: 8, height: 8, transform: `rotate(45 ${x} ${y})` }, m);
        el("title", {}, m, mark.text);
      }
    }
  }

  itemPoints(it) { return it.p.map((j) => (this.ok(j, this.frame) ? [this.sx(this.X(j, this.frame)), this.sy(this.Y(j, this.frame))] : null)); }

  drawItems(g) {
    const s = this.scene, i = this.frame;
    const unit = Math.max(s.size / 100 * this.scale, 0.5);  // the scene's unit, in px
    for (const it of s.items) {
      const pts = this.itemPoints(it);
      if (pts.some((p) => p === null) && it.k !== "pin" && it.k !== "point") continue;
      const sel = this.selection && (this.selection.name === it.body) ? " selected" : "";
      const attrs = { "data-body": it.body || null, class: `item ${it.k}${sel}` };
      const ang = it.a ? s.angles[it.a][i] : 0;
      switch (it.k) {
        case "bar": case "line":
          el("line", { ...attrs, x1: pts[0][0], y1: pts[0][1], x2: pts[1][0], y2: pts[1][1], stroke: it.colour }, g);
          break;
        case "plate":
          el("polygon", { ...attrs, points: pts.map((p) => p.join(",")).join(" "), fill: it.colour, stroke: it.colour }, g);
          break;
        case "pin":
          for (const p of pts) if (p) el("circle", { class: "pin", cx: p[0], cy: p[1], r: 4.5 }, g);
          break;
        case "point":
          for (const p of pts) if (p) el("circle", { class: "cpoint", cx: p[0], cy: p[1], r: 4, fill: it.colour }, g);
          break;
        case "ground": {
          const [x, y] = pts[0];
          const gg = el("g", { class: "groundsym" }, g);
          el("path", { d: `M${x} ${y}L${x - 9} ${y + 14}H${x + 9}Z` }, gg);
          let h = `M${x - 13} ${y + 14}H${x + 13}`;
          for (let k = -12; k <= 10; k += 5) h += `M${x + k} ${y + 14}l-4 5`;
          el("path", { d: h, class: "hatch" }, gg);
          break;
        }
        case "guide": {
          const [p, q] = pts;
          const gg = el("g", { class: "guide", "data-body": it.body }, g);
          el("line", { x1: p[0], y1: p[1], x2: q[0], y2: q[1], stroke: it.colour }, gg);
          if (it.body === "ground") {
            const dx = q[0] - p[0], dy = q[1] - p[1], L = Math.hypot(dx, dy) || 1;
            const nx = dy / L * 1, ny = -dx / L * 1;  // screen normal (below the line)
            const off = (it.size * this.scale) * 0.35;
            let h = "";
            for (let t = 0; t <= L; t += 8) {
              const bx = p[0] + dx / L * t - nx * off, by = p[1] + dy / L * t - ny * off;
              h += `M${bx} ${by}l${-dx / L * 5 - nx * 5} ${-dy / L * 5 - ny * 5}`;
            }
            el("path", { d: h, class: "hatch" }, gg);
            el("line", { x1: p[0] - nx * off, y1: p[1] - ny * off, x2: q[0] - nx * off, y2: q[1] - ny * off, class: "hatch" }, gg);
          }
          break;
        }
        case "slider": {
          const L = (it.size || 8 * s.size / 100) * this.scale, H = 0.55 * L;
          const [x, y] = pts[0];
          el("rect", { ...attrs, x: x - L / 2, y: y - H / 2, width: L, height: H, fill: it.colour, transform: `rotate(${-ang} ${x} ${y})` }, g);
          break;
        }
        case "shape": case "wheel": {
          const [x, y] = pts[0];
          const a = ang * Math.PI / 180, c = Math.cos(a), sn = Math.sin(a);
          let outline = it.outline;
          if (it.k === "wheel") { outline = []; for (let k = 0; k <= 48; k++) outline.push([it.size * Math.cos(k * Math.PI / 24), it.size * Math.sin(k * Math.PI / 24)]); }
          const ps = (outline || []).map(([u, v]) => `${x + this.scale * (u * c - v * sn)},${y - this.scale * (u * sn + v * c)}`).join(" ");
          el(it.closed ? "polygon" : "polyline", { ...attrs, points: ps, stroke: it.colour, fill: it.closed ? it.colour : "none" }, g);
          break;
        }
        case "spring": case "damper": case "actuator": {
          const [p, q] = pts;
          const dx = q[0] - p[0], dy = q[1] - p[1], L = Math.hypot(dx, dy) || 1;
          const ux = dx / L, uy = dy / L, nx = -uy, ny = ux;
          if (it.k === "spring") {
            let d = `M${p[0]} ${p[1]}`;
            const n = 12, amp = 5;
            for (let k = 1; k < n; k++) {
              const t = 0.15 + 0.7 * k / n, sgn = k % 2 ? 1 : -1;
              d += `L${p[0] + dx * t + nx * amp * sgn} ${p[1] + dy * t + ny * amp * sgn}`;
            }
            d += `L${q[0]} ${q[1]}`;
            el("path", { ...attrs, d, stroke: it.colour }, g);
          } else {
            el("line", { ...attrs, x1: p[0], y1: p[1], x2: p[0] + dx * 0.6, y2: p[1] + dy * 0.6, stroke: it.colour, class: `item ${it.k} barrel` }, g);
            el("line", { ...attrs, x1: p[0] + dx * 0.3, y1: p[1] + dy * 0.3, x2: q[0], y2: q[1], class: `item ${it.k} rod` }, g);
          }
          break;
        }
        case "motor": {
          const [x, y] = pts[0], r = 13;
          el("path", { class: "motor", d: `M${x + r} ${y}A${r} ${r} 0 1 0 ${x} ${y + r}m-4 -3l4 3l-4 3` }, g);
          break;
        }
        default: break;
      }
    }
    void unit;
  }

  // The document as drawn, when it cannot be solved: its points and links, greyed.
  drawDocument(g) {
    const pts = this.part.points || {};
    for (const [name, link] of Object.entries(this.part.links || {})) {
      const ps = link.points.filter((p) => pts[p]).map((p) => [this.sx(pts[p][0]), this.sy(pts[p][1])]);
      const sel = this.selection && this.selection.name === name ? " selected" : "";
      if (ps.length >= 3) el("polygon", { class: "item plate unsolved" + sel, "data-body": name, points: ps.map((p) => p.join(",")).join(" ") }, g);
      else if (ps.length === 2) el("line", { class: "item bar unsolved" + sel, "data-body": name, x1: ps[0][0], y1: ps[0][1], x2: ps[1][0], y2: ps[1][1] }, g);
    }
    for (const name of this.part.ground || []) {
      if (!pts[name]) continue;
      const x = this.sx(pts[name][0]), y = this.sy(pts[name][1]);
      el("path", { class: "groundsym", d: `M${x} ${y}L${x - 9} ${y + 14}H${x + 9}Z` }, g);
    }
    for (const [name, s] of Object.entries(this.part.sliders || {})) {
      const p = pts[s.at];
      if (!p) continue;
      el("rect", { class: "item slider unsolved", "data-body": name, x: this.sx(p[0]) - 10, y: this.sy(p[1]) - 6, width: 20, height: 12 }, g);
    }
  }

  drawCentres(g) {
    const c = this.centres, i = this.frame;
    if (!c.ok[i]) return;
    const gg = el("g", { class: "centres" }, g);
    for (const ic of c.centres) {
      const x = ic.x[i], y = ic.y[i];
      if (x === null || y === null) continue;
      const px = this.sx(x), py = this.sy(y);
      const [w, h] = this.size();
      if (px < -50 || py < -50 || px > w + 50 || py > h + 50) continue;
      const primary = ic.method === "joint";
      el("circle", { cx: px, cy: py, r: primary ? 5 : 4, class: primary ? "ic primary" : "ic" }, gg);
      el("text", { x: px + 6, y: py - 6, class: "ic-label" }, gg, `${ic.pair[0]}·${ic.pair[1]}`);
    }
  }

  drawMarks(g) {
    for (const m of this.marks) {
      const x = this.sx(m.x), y = this.sy(m.y);
      const gg = el("g", { class: "mark " + (m.kind || "") }, g);
      if (m.kind === "pivot") el("path", { d: `M${x} ${y}l-8 13h16z`, stroke: m.colour }, gg);
      else el("circle", { cx: x, cy: y, r: 6, stroke: m.colour }, gg);
      if (m.to) el("line", { x1: x, y1: y, x2: this.sx(m.to[0]), y2: this.sy(m.to[1]), stroke: m.colour }, gg);
      if (m.label) el("text", { x: x + 8, y: y + 16 }, gg, m.label);
    }
  }

  // Each link's name where it is drawn (the middle of a bar, the centre of a plate, below a
  // block), so that the names a file gives its links (crank, coupler, rocker) are on the drawing.
  drawLinkNames(g) {
    const gg = el("g", { class: "link-names" }, g);
    for (const [name, link] of Object.entries(this.part.links || {})) {
      const at = link.points.map((p) => this.pointAt(p)).filter(Boolean);
      if (!at.length) continue;
      const xs = at.map((p) => this.sx(p[0])), ys = at.map((p) => this.sy(p[1]));
      let x = xs.reduce((a, b) => a + b) / xs.length, y = ys.reduce((a, b) => a + b) / ys.length;
      let anchor = "middle";
      if (at.length === 1) { x -= 6; y -= 24; anchor = "end"; }  // a block: above, left of its pin's name
      else if (at.length === 2) {  // beside the bar: 14 px off its middle, on its lower side
        const dx = xs[1] - xs[0], dy = ys[1] - ys[0], L = Math.hypot(dx, dy) || 1;
        let nx = -dy / L, ny = dx / L;
        if (ny < 0 || (ny === 0 && nx < 0)) { nx = -nx; ny = -ny; }
        x += nx * 10; y += ny * 14 + 4;
        if (Math.abs(nx) > 0.7) anchor = nx > 0 ? "start" : "end";  // a steep bar: beside it
      }
      el("text", { x, y, class: "link-name", "text-anchor": anchor, "data-link": name }, gg, name);
    }
  }

  drawHandles(g) {
    this.drawLinkNames(g);
    const gg = el("g", { class: "handles" }, g);
    for (const name of Object.keys(this.part.points || {})) {
      const at = this.pointAt(name);
      if (!at) continue;
      const x = this.sx(at[0]), y = this.sy(at[1]);
      const sel = this.selection && this.selection.kind === "point" && this.selection.name === name;
      el("circle", { cx: x, cy: y, r: 9, class: "handle" + (sel ? " selected" : ""), "data-point": name }, gg);
      el("text", { x: x + 8, y: y - 8, class: "label" }, gg, name);
    }
  }
}
