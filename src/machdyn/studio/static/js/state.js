// The page's one state: the machine document (docs/spec.md), with its history.
// Undo/redo is a stack of documents; the shared URL and the saved file come from the same object.

export const HISTORY = 200;

export class Store {
  constructor() {
    this.doc = null;
    this.past = [];
    this.future = [];
    this.listeners = [];
    this.file = null;
  }

  onChange(fn) { this.listeners.push(fn); }

  emit(committed) { for (const fn of this.listeners) fn(this.doc, committed); }

  // The linkage part being edited (the first one).
  get partName() {
    const parts = this.doc && this.doc.linkage;
    return parts ? Object.keys(parts)[0] : null;
  }

  get part() { return this.partName ? this.doc.linkage[this.partName] : null; }

  // Replace the document (a template, a file, a shared link): history starts over unless kept.
  load(doc, keepHistory = false) {
    if (keepHistory && this.doc) this.pushPast();
    else { this.past = []; this.future = []; }
    this.doc = clone(doc);
    this.emit(true);
  }

  pushPast() {
    this.past.push(JSON.stringify(this.doc));
    if (this.past.length > HISTORY) this.past.shift();
    this.future = [];
  }

  // One edit: fn changes a copy of the document; the old one goes on the undo stack.
  commit(fn) {
    const next = clone(this.doc);
    fn(next, next.linkage ? next.linkage[Object.keys(next.linkage)[0]] : null);
    if (JSON.stringify(next) === JSON.stringify(this.doc)) return false;
    this.pushPast();
    this.doc = next;
    this.emit(true);
    return true;
  }

  // A change in progress (a drag): shown and analysed, put on the undo stack by finish().
  preview(fn) {
    if (!this.dragStart) this.dragStart = JSON.stringify(this.doc);
    fn(this.doc, this.part);
    this.emit(false);
  }

  finish() {
    if (!this.dragStart) return;
    const before = this.dragStart;
    this.dragStart = null;
    if (before === JSON.stringify(this.doc)) return;
    this.past.push(before);
    if (this.past.length > HISTORY) this.past.shift();
    this.future = [];
    this.emit(true);
  }

  undo() {
    if (!this.past.length) return false;
    this.future.push(JSON.stringify(this.doc));
    this.doc = JSON.parse(this.past.pop());
    this.emit(true);
    return true;
  }

  redo() {
    if (!this.future.length) return false;
    this.past.push(JSON.stringify(this.doc));
    this.doc = JSON.parse(this.future.pop());
    this.emit(true);
    return true;
  }
}

export function clone(x) { return x === null || x === undefined ? x : JSON.parse(JSON.stringify(x)); }

// A fresh name: prefix + the first number not used.
export function freshName(prefix, taken) {
  for (let i = 1; ; i++) if (!taken.has(prefix + i)) return prefix + i;
}

// Every name a part uses for links and joints (they share one namespace).
export function elementNames(part) {
  const names = new Set(Object.keys(part.links || {}));
  for (const key of ["sliders", "slots", "actuators", "rolls", "motors", "springs", "torsion_springs"]) {
    for (const n of Object.keys(part[key] || {})) names.add(n);
  }
  names.add("ground");
  return names;
}

// ----------------------------------------------------------------- the URL fragment
function toBase64Url(bytes) {
  let s = "";
  for (let i = 0; i < bytes.length; i += 0x8000) s += String.fromCharCode(...bytes.subarray(i, i + 0x8000));
  return btoa(s).replace(/\+/g, "-").replace(/\//g, "_").replace(/=+$/, "");
}

function fromBase64Url(text) {
  const s = atob(text.replace(/-/g, "+").replace(/_/g, "/"));
  const out = new Uint8Array(s.length);
  for (let i = 0; i < s.length; i++) out[i] = s.charCodeAt(i);
  return out;
}

async function pipe(bytes, stream) {
  const out = new Response(new Blob([bytes]).stream().pipeThrough(stream));
  return new Uint8Array(await out.arrayBuffer());
}

// "#d=" + deflated JSON (base64url); "#j=" when the browser cannot compress.
export async function encodeFragment(doc) {
  const bytes = new TextEncoder().encode(JSON.stringify(doc));
  if (typeof CompressionStream === "function") {
    return "d=" + toBase64Url(await pipe(bytes, new CompressionStream("deflate-raw")));
  }
  return "j=" + toBase64Url(bytes);
}

export async function decodeFragment(hash) {
  const text = hash.replace(/^#/, "");
  if (!text) return null;
  const [kind, data] = [text.slice(0, 2), text.slice(2)];
  if (kind === "d=") {
    const bytes = await pipe(fromBase64Url(data), new DecompressionStream("deflate-raw"));
    return JSON.parse(new TextDecoder().decode(bytes));
  }
  if (kind === "j=") return JSON.parse(new TextDecoder().decode(fromBase64Url(data)));
  return null;
}
