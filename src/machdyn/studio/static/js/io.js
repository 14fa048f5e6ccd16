// Files and links: open (button or drag-and-drop), save to the studio's file, download,
// share (the document in the URL fragment), export tables, pictures, DXF and the report.

import { post } from "./api.js";
import { encodeFragment } from "./state.js";

export function download(blob, filename) {
  const url = URL.createObjectURL(blob);
  const a = document.createElement("a");
  a.href = url; a.download = filename;
  document.body.appendChild(a); a.click(); a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 10000);
}

export function wireFiles(app) {
  const store = app.store;
  const input = document.getElementById("open-file");
  const openFile = async (file) => {
    if (!file) return;
    if (file.size > 1_500_000) { app.status(`${file.name}: too large for a machine file`, true); return; }
    try {
      const text = await file.text();
      const { doc, notes } = await post("open", { name: file.name, text });
      app.beforeLoad();
      store.load(doc, true);
      app.afterLoad();
      app.status(`opened ${file.name}`);
      app.notice(notes);
    } catch (err) { app.fail(err); }
  };
  document.getElementById("open").addEventListener("click", () => input.click());
  input.addEventListener("change", () => { openFile(input.files[0]); input.value = ""; });
  const drop = document.getElementById("drop");
  let depth = 0;
  window.addEventListener("dragenter", (e) => { if (e.dataTransfer && [...e.dataTransfer.types].includes("Files")) { depth++; drop.hidden = false; e.preventDefault(); } });
  window.addEventListener("dragleave", () => { depth = Math.max(0, depth - 1); if (!depth) drop.hidden = true; });
  window.addEventListener("dragover", (e) => e.preventDefault());
  window.addEventListener("drop", (e) => { e.preventDefault(); depth = 0; drop.hidden = true; if (e.dataTransfer.files.length) openFile(e.dataTransfer.files[0]); });

  document.getElementById("save").addEventListener("click", () => app.save());
  document.getElementById("download").addEventListener("click", () => app.exportAs("toml"));
  document.getElementById("share").addEventListener("click", async () => {
    const hash = await encodeFragment(store.doc);
    history.replaceState(null, "", "#" + hash);
    const link = location.href;
    try { await navigator.clipboard.writeText(link); app.status(`link copied (${link.length} characters): it opens this design`); }
    catch (err) { app.status("the address bar now holds a link that opens this design"); }
  });
  const exp = document.getElementById("export");
  exp.addEventListener("change", () => { const f = exp.value; exp.value = ""; if (f) app.exportAs(f); });
}
