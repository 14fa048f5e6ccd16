// The side panel: the document (selection, properties with units, lists) and the analysis
// summary (mobility, Assur groups and their assembly, input range, problems).

import { h, fmt, numberInput } from "./dom.js";
import { setDriver, toggleGround, toggleTrace, deleteLink, deleteJoint, deletePoint } from "./tools.js";

export class Panels {
  constructor(app) {
    this.app = app;
    this.design = document.getElementById("tab-design");
    this.analysis = document.getElementById("tab-analysis");
  }

  units() {
    const r = this.app.result;
    const u = (r && r.summary.units) || {};
    return { length: u.length || "", mass: u.mass || "", inertia: u.inertia || "", angle: u.angle || "deg" };
  }

  render() {
    this.renderDesign();
    this.renderAnalysis();
  }

  // -- design -------------------------------------------------------------------------
  renderDesign() {
    const app = this.app, store = app.store, part = store.part;
    const box = h("div", {});
    if (!part) {
      box.appendChild(h("p", { class: "empty" }, "No linkage yet: pick a template above, or draw one with the tools (Ground pivot, Link, Slider)."));
      this.design.replaceChildren(box);
      return;
    }
    const u = this.units();
    const lu = u.length ? ` (${u.length})` : "";
    box.appendChild(h("label", { class: "row" }, "Title ",
      (() => { const i = h("input", { type: "text", value: store.doc.title || "", "aria-label": "title" });
        i.addEventListener("change", () => store.commit((doc) => { doc.title = i.value; })); return i; })()));
    const sel = app.view.selection;
    if (sel) box.appendChild(this.selectionBox(sel, part, lu, u));
    else box.appendChild(h("p", { class: "hint-text" }, "Click a joint or a link to edit it; drag joints to change the design."));
    box.appendChild(this.driverBox(part));
    box.appendChild(this.listBox(part));
    this.design.replaceChildren(box);
  }

  selectionBox(sel, part, lu, u) {
    const app = this.app, store = app.store;
    const box = h("section", { class: "card selection" });
    if (sel.kind === "point" && part.points[sel.name]) {
      const p = part.points[sel.name];
      const on = Object.entries(part.links || {}).filter(([, l]) => l.points.includes(sel.name)).map(([n]) => n);
      box.append(
        h("h3", {}, "Joint ", this.renameInput("rename_point", sel.name)),
        h("div", { class: "grid2" },
          h("label", {}, `x${lu}`, numberInput(p[0], (v) => v !== null && store.commit((d, pt) => { pt.points[sel.name][0] = v; }), { "aria-label": "x" })),
          h("label", {}, `y${lu}`, numberInput(p[1], (v) => v !== null && store.commit((d, pt) => { pt.points[sel.name][1] = v; }), { "aria-label": "y" }))),
        h("label", { class: "check" }, this.check((part.ground || []).includes(sel.name), () => store.commit((d, pt) => toggleGround(pt, sel.name)), "ground pivot"), " ground pivot"),
        h("label", { class: "check" }, this.check((part.report || []).includes(sel.name), () => store.commit((d, pt) => toggleTrace(pt, sel.name)), "trace"), " trace its path (coupler curve)"),
        h("p", { class: "muted" }, on.length ? `on ${on.join(", ")}` : "on no link yet"),
        h("button", { class: "danger", onclick: () => { store.commit((d, pt) => deletePoint(pt, sel.name)); app.select(null); } }, "Delete joint"));
      return box;
    }
    if (sel.kind === "link" && part.links && part.links[sel.name]) {
      const link = part.links[sel.name];
      const sides = (app.result && app.result.summary.lengths[sel.name]) || [];
      const isDriver = (part.drive || []).includes(sel.name);
      box.append(h("h3", {}, "Link ", this.renameInput("rename_link", sel.name)),
        h("p", { class: "muted" }, `${link.points.length === 1 ? "a block" : link.points.length === 2 ? "binary link" : link.points.length === 3 ? "ternary plate" : link.points.length + "-joint plate"}: ${link.points.join(" – ")}`));
      if (sides.length) {
        const t = h("table", { class: "sides" }, h("tr", {}, h("th", {}, "side"), h("th", {}, `length${lu}`)));
        for (const [a, b, len] of sides) {
          t.appendChild(h("tr", {}, h("td", {}, `${a}–${b}`), h("td", {}, numberInput(len, (v) => v !== null && app.edit({ kind: "length", from: a, to: b, value: v }), { "aria-label": `length ${a}-${b}` }))));
        }
        box.appendChild(t);
      }
      const um = u.mass ? ` (${u.mass})` : "", ui = u.inertia ? ` (${u.inertia})` : "";
      const setProp = (key) => (v) => store.commit((d, pt) => { if (v === null) delete pt.links[sel.name][key]; else pt.links[sel.name][key] = v; });
      const cgText = link.cg === undefined ? "" : Array.isArray(link.cg) ? link.cg.join(", ") : String(link.cg);
      const cg = h("input", { type: "text", value: cgText, "aria-label": "cg", title: "a length along the link's x axis, x, y in its frame, or a joint's name" });
      cg.addEventListener("change", () => store.commit((d, pt) => {
        const t = cg.value.trim();
        if (!t) { delete pt.links[sel.name].cg; return; }
        const parts = t.split(",").map((s) => Number(s.trim()));
        pt.links[sel.name].cg = parts.every(isFinite) ? (parts.length === 1 ? parts[0] : parts.slice(0, 2)) : t;
      }));
      box.append(h("div", { class: "grid2" },
        h("label", {}, `mass${um}`, numberInput(link.mass, setProp("mass"), { "aria-label": "mass" })),
        h("label", {}, `I about G${ui}`, numberInput(link.inertia, setProp("inertia"), { "aria-label": "inertia" })),
        h("label", { class: "wide" }, `centre of mass${lu}`, cg)),
      h("div", { class: "buttons" },
        h("button", { disabled: isDriver, onclick: () => store.commit((d, pt) => setDriver(pt, sel.name)) }, isDriver ? "the driver" : "Drive this link"),
        h("button", { id: "add-point", class: app.addingTo === sel.name ? "on" : "", title: "Click on the canvas to add a point carried by this link (a coupler point); its path is traced", onclick: () => app.addPointTo(sel.name) }, "Add a point"),
        h("button", { class: "danger", onclick: () => { store.commit((d, pt) => deleteLink(pt, sel.name)); app.select(null); } }, "Delete link")));
      return box;
    }
    const joint = ["sliders", "slots", "actuators", "motors"].map((k) => part[k] && part[k][sel.name]).find(Boolean);
    if (joint) {
      const isDriver = (part.drive || []).includes(sel.name);
      box.append(h("h3", {}, `Joint ${sel.name}`),
        h("p", { class: "muted" }, Object.entries(joint).map(([k, v]) => `${k}: ${Array.isArray(v) ? v.map((x) => fmt(x)).join(", ") : v}`).join(" · ")),
        part.sliders && part.sliders[sel.name] ? this.guideBox(part, sel.name) : null,
        h("div", { class: "buttons" },
          h("button", { disabled: isDriver, onclick: () => store.commit((d, pt) => setDriver(pt, sel.name)) }, isDriver ? "the driver" : "Drive this joint"),
          h("button", { class: "danger", onclick: () => { store.commit((d, pt) => deleteJoint(pt, sel.name)); app.select(null); } }, "Delete joint")));
      return box;
    }
    return box;
  }

  // A slider's guide: the link it is on (or the ground) and its direction — an angle in the
  // file's angle unit, a vector "dx, dy", or the name of a point the guide runs towards.
  guideBox(part, name) {
    const store = this.app.store, s = part.sliders[name];
    const links = Object.keys(part.links || {}).filter((n) => n !== s.block);
    const on = h("select", { "aria-label": "guide on" }, ...["ground", ...links].map((n) => {
      const o = h("option", { value: n }, n); if (n === s.on) o.selected = true; return o; }));
    on.addEventListener("change", () => store.commit((d, pt) => { pt.sliders[name].on = on.value; }));
    const shown = s.direction === undefined ? "" : Array.isArray(s.direction) ? s.direction.join(", ") : String(s.direction);
    const dir = h("input", { type: "text", value: shown, "aria-label": "guide direction", title: `an angle (${this.units().angle}), a vector dx, dy, or a point's name` });
    dir.addEventListener("change", () => store.commit((d, pt) => {
      const t = dir.value.trim(), nums = t.split(",").map((v) => Number(v.trim()));
      if (!t) delete pt.sliders[name].direction;
      else pt.sliders[name].direction = nums.every((v) => isFinite(v) && t !== "") ? (nums.length === 1 ? nums[0] : nums.slice(0, 2)) : t;
    }));
    return h("div", { class: "grid2" }, h("label", {}, "guide on", on), h("label", {}, `direction (${this.units().angle}, dx, dy or a point)`, dir));
  }

  check(on, fn, label) {
    const c = h("input", { type: "checkbox", "aria-label": label });
    c.checked = on;
    c.addEventListener("change", fn);
    return c;
  }

  renameInput(kind, name) {
    const i = h("input", { type: "text", value: name, class: "name", "aria-label": "name" });
    i.addEventListener("change", () => {
      const v = i.value.trim();
      if (v && v !== name) this.app.edit({ kind, old: name, new: v }, { kind: kind === "rename_point" ? "point" : "link", name: v });
    });
    i.addEventListener("keydown", (e) => { if (e.key === "Enter") i.blur(); });
    return i;
  }

  driverBox(part) {
    const app = this.app, store = app.store;
    const choices = [...Object.keys(part.links || {}).filter((n) => part.links[n].points.length >= 2),
      ...Object.keys(part.sliders || {}), ...Object.keys(part.actuators || {}), ...Object.keys(part.motors || {})];
    const driver = (part.drive || [])[0];
    const select = h("select", { "aria-label": "driver" }, ...choices.map((c) => {
      const o = h("option", { value: c }, c); if (c === driver) o.selected = true; return o; }));
    select.addEventListener("change", () => store.commit((d, pt) => setDriver(pt, select.value)));
    const motion = (part.motion || {})[driver] || {};
    const angle = driver in (part.links || {}) || driver in (part.motors || {});
    const rateUnit = angle ? "rad/s" : `${this.units().length || "length"}/s`;
    const v = h("input", { type: "text", value: motion.velocity === undefined ? "" : String(motion.velocity), placeholder: `1 ${rateUnit}`, "aria-label": "speed", title: `the driver's speed: a number in ${rateUnit}, or with a unit ('120 rpm')` });
    v.addEventListener("change", () => store.commit((d, pt) => {
      pt.motion = pt.motion || {};
      const entry = pt.motion[driver] || {};
      const t = v.value.trim();
      if (!t) delete entry.velocity; else entry.velocity = isFinite(Number(t)) ? Number(t) : t;
      pt.motion[driver] = entry;
      if (!Object.keys(entry).length) delete pt.motion[driver];
      if (!Object.keys(pt.motion).length) delete pt.motion;
    }));
    return h("section", { class: "card" }, h("h3", {}, "Driver"),
      h("div", { class: "grid2" }, h("label", {}, "driven", select), h("label", {}, "speed", v)),
      h("label", { class: "row" }, "gravity ", this.check(!!store.doc.gravity, () => store.commit((doc) => { if (doc.gravity) delete doc.gravity; else doc.gravity = true; }), "gravity"), " along −y"));
  }

  listBox(part) {
    const app = this.app;
    const item = (kind, name, extra) => h("li", { class: app.view.selection && app.view.selection.name === name ? "on" : "" },
      h("a", { href: "#", onclick: (e) => { e.preventDefault(); app.select({ kind, name }); } }, name), extra ? h("span", { class: "muted" }, " " + extra) : null);
    const joints = [];
    for (const key of ["sliders", "slots", "actuators", "motors", "springs", "torsion_springs"]) {
      for (const n of Object.keys(part[key] || {})) joints.push(item("joint", n, key.replace(/s$/, "")));
    }
    return h("section", { class: "card lists" },
      h("h3", {}, "Links"), h("ul", {}, ...Object.entries(part.links || {}).map(([n, l]) => item("link", n, l.points.join("–")))),
      h("h3", {}, "Joints"), h("ul", {}, ...Object.entries(part.points || {}).map(([n]) => item("point", n, (part.ground || []).includes(n) ? "ground" : ""))),
      joints.length ? h("h3", {}, "Sliders and others") : null, joints.length ? h("ul", {}, ...joints) : null);
  }

  // -- analysis -----------------------------------------------------------------------
  renderAnalysis() {
    const app = this.app, r = app.result, box = h("div", {});
    if (app.error) {
      box.appendChild(h("section", { class: "card error" }, h("h3", {}, "Cannot analyse this design"),
        h("p", { class: "message" }, app.error.message), app.error.key ? h("p", { class: "muted" }, `key: ${app.error.key}`) : null));
    }
    if (!r) { this.analysis.replaceChildren(box); return; }
    const s = r.summary;
    const good = r.ok.filter(Boolean).length;
    const range = app.range();
    box.appendChild(h("section", { class: "card" }, h("h3", {}, "Mechanism"),
      h("table", { class: "facts" },
        h("tr", {}, h("th", {}, "mobility (Kutzbach–Gruebler)"), h("td", { "data-key": "mobility" }, String(s.mobility))),
        h("tr", {}, h("th", {}, "driver"), h("td", {}, s.drivers.join(", "))),
        h("tr", {}, h("th", {}, "input range"), h("td", { "data-key": "range" }, range)),
        h("tr", {}, h("th", {}, "poses assembled"), h("td", { "data-key": "assembled" }, `${good} of ${r.ok.length}`)),
        s.classes && s.classes.length ? s.classes.map((c) => h("tr", {}, h("th", {}, `four-bar ${c.links.join("-")}`), h("td", { "data-key": "class" }, c.text))) : null)));
    const groups = h("table", { class: "groups" }, h("tr", {}, h("th", {}, "Assur group"), h("th", {}, "assembly")));
    for (const g of s.groups) {
      const sign = g.kind === "driver" || g.kind === "general" ? "" : g.sign > 0 ? "+ (as drawn)" : "− (as drawn)";
      const flip = s.can_flip && sign ? h("button", { class: "small", onclick: () => app.flip(g.name) }, "switch") : null;
      groups.appendChild(h("tr", {}, h("td", {}, g.name), h("td", {}, sign, flip)));
    }
    box.appendChild(h("section", { class: "card" }, h("h3", {}, "Circuit and branch"), groups,
      h("p", { class: "muted" }, s.can_flip ? "Switch moves a dyad to its other assembly." :
        "Each dyad keeps the assembly of the drawing at every pose; drag a joint across the line of its pivots to change it.")));
    if (r.problems.length) {
      const list = h("ul", { class: "problems" });
      for (const p of r.problems) {
        const where = p.ranges.map(([a, b]) => (a === b ? fmt(a) : `${fmt(a)} to ${fmt(b)}`)).join("; ");
        list.appendChild(h("li", {}, h("b", {}, `${p.count} pose${p.count > 1 ? "s" : ""}`), ` at ${r.x_label} = ${where}: `, p.reason));
      }
      box.appendChild(h("section", { class: "card warn" }, h("h3", {}, "Problems"), list));
    }
    if (r.limits && r.limits.length) {
      box.appendChild(h("section", { class: "card" }, h("h3", {}, "Limit and toggle positions"),
        h("ul", {}, ...r.limits.map((m) => h("li", {}, h("a", { href: "#", onclick: (e) => { e.preventDefault(); app.goTo(m.frame); } }, m.text))))));
    }
    this.analysis.replaceChildren(box);
  }
}
