// Small DOM helpers: user text always goes in as text, never as markup.

export function h(tag, attrs = {}, ...children) {
  const e = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs || {})) {
    if (v === null || v === undefined || v === false) continue;
    if (k.startsWith("on")) e.addEventListener(k.slice(2), v);
    else if (k === "class") e.className = v;
    else if (v === true) e.setAttribute(k, "");
    else e.setAttribute(k, String(v));
  }
  for (const c of children.flat()) {
    if (c === null || c === undefined || c === false) continue;
    e.appendChild(typeof c === "string" || typeof c === "number" ? document.createTextNode(String(c)) : c);
  }
  return e;
}

export function fmt(v, digits = 4) {
  if (v === null || v === undefined || !isFinite(v)) return "–";
  if (v === 0) return "0";
  const a = Math.abs(v);
  if (a >= 1e5 || a < 1e-3) return v.toExponential(digits - 1);
  return Number(v.toPrecision(digits)).toString();
}

// A number input that calls back with a finite number when edited (Enter or leaving it).
export function numberInput(value, onSet, attrs = {}) {
  const input = h("input", { type: "text", inputmode: "decimal", value: value === undefined || value === null ? "" : fmt(value, 8), ...attrs });
  const done = () => {
    const text = input.value.trim();
    if (text === "") return onSet(null);
    const v = Number(text);
    if (!isFinite(v)) { input.classList.add("bad"); return; }
    input.classList.remove("bad");
    onSet(v);
  };
  input.addEventListener("change", done);
  input.addEventListener("keydown", (e) => { if (e.key === "Enter") input.blur(); });
  return input;
}
