// Editing the document with the pointer: select and drag joints, add ground pivots, links
// and sliders, delete. Every edit is a plain change of the spec document (names, points).

import { elementNames, freshName } from "./state.js";

export function pointNames(part) { return new Set(Object.keys(part.points || {})); }

export function addPoint(part, xy, prefix = "P") {
  const name = freshName(prefix, pointNames(part));
  part.points[name] = xy;
  return name;
}

// A new ground pivot, named as the textbooks do: O2, O4, O6, ... (the pivots of links 2, 4, 6
// of a four-bar or six-bar; the ground is link 1).
export function addPivot(part, xy) {
  const taken = pointNames(part);
  let i = 2;
  while (taken.has(`O${i}`)) i += 2;
  part.points[`O${i}`] = xy;
  part.ground = [...(part.ground || []), `O${i}`];
  return `O${i}`;
}

export function deletePoint(part, name) {
  delete part.points[name];
  part.ground = (part.ground || []).filter((p) => p !== name);
  if (part.report) part.report = part.report.filter((p) => p !== name);
  for (const [ln, link] of Object.entries(part.links || {})) {
    link.points = link.points.filter((p) => p !== name);
    if (link.cg === name) delete link.cg;
    if (!link.points.length) deleteLink(part, ln);
  }
  for (const key of ["sliders", "slots"]) {
    for (const [jn, j] of Object.entries(part[key] || {})) {
      if ([j.at, j.pin, j.through, j.direction].includes(name)) delete part[key][jn];
    }
  }
  for (const key of ["actuators", "springs", "torsion_springs", "motors"]) {
    for (const [jn, j] of Object.entries(part[key] || {})) {
      if ([j.start, j.end, j.at].includes(name)) delete part[key][jn];
    }
  }
  tidy(part);
}

export function deleteLink(part, name) {
  if (!part.links || !part.links[name]) return;
  delete part.links[name];
  part.drive = (part.drive || []).filter((d) => d !== name);
  for (const key of ["sliders", "slots"]) {
    for (const [jn, j] of Object.entries(part[key] || {})) {
      if (j.block === name || j.on === name || j.link === name) deleteJoint(part, jn);
    }
  }
  if (part.torques) delete part.torques[name];
  if (part.motion) delete part.motion[name];
  if (part.forces) part.forces = part.forces.filter((f) => f.link !== name);
  tidy(part);
}

export function deleteJoint(part, name) {
  for (const key of ["sliders", "slots", "actuators", "rolls", "motors", "springs", "torsion_springs"]) {
    if (part[key] && part[key][name]) delete part[key][name];
  }
  part.drive = (part.drive || []).filter((d) => d !== name);
  if (part.motion) delete part.motion[name];
  if (part.friction) delete part.friction[name];
  tidy(part);
}

// Empty tables are left out of the document (the spec refuses some of them).
function tidy(part) {
  for (const key of ["sliders", "slots", "actuators", "rolls", "motors", "springs", "torsion_springs", "torques", "motion", "friction"]) {
    if (part[key] && !Object.keys(part[key]).length) delete part[key];
  }
  if (part.forces && !part.forces.length) delete part.forces;
  if (part.report && !part.report.length) delete part.report;
}

// A new link is named by its role, as the textbooks and MotionGen/PMKS+ users say: the first
// link on a ground pivot is the crank (it drives), another one on a ground pivot a rocker,
// a floating one a coupler (then rocker2, coupler2, ...).
export function roleName(part, points) {
  const grounded = points.some((p) => (part.ground || []).includes(p));
  const role = !grounded ? "coupler" : (part.drive || []).length ? "rocker" : "crank";
  const taken = elementNames(part);
  if (!taken.has(role)) return role;
  for (let i = 2; ; i++) if (!taken.has(role + i)) return role + i;
}

export function addLink(part, points) {
  const name = roleName(part, points);
  part.links = part.links || {};
  part.links[name] = { points };
  // the first link on a ground pivot drives until the user picks another driver
  if (!(part.drive || []).length && points.some((p) => (part.ground || []).includes(p))) part.drive = [name];
  return name;
}

export function addSlider(part, at, on, direction) {
  const names = elementNames(part);
  const block = freshName("block", names);
  names.add(block);
  const name = freshName("slider", names);
  part.links = part.links || {};
  part.links[block] = { points: [at] };
  part.sliders = part.sliders || {};
  part.sliders[name] = { block, on, at, direction };
  return name;
}

export function toggleGround(part, name) {
  const ground = part.ground || [];
  part.ground = ground.includes(name) ? ground.filter((p) => p !== name) : [...ground, name];
}

export function setDriver(part, name) {
  const old = part.drive || [];
  part.drive = [name];
  if (part.motion) {
    const keep = part.motion[old[0]];
    part.motion = {};
    if (keep && keep.velocity !== undefined && (name in (part.links || {})) === (old[0] in (part.links || {}))) {
      part.motion[name] = { velocity: keep.velocity };
    }
    tidy(part);
  }
}

export function toggleTrace(part, name) {
  const report = part.report || [];
  part.report = report.includes(name) ? report.filter((p) => p !== name) : [...report, name];
  tidy(part);
}
