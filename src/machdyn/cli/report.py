"""``machdyn report FILE -o report.html``: the design report of the machine a file describes.

Only reading and calling: the machine comes from the machine-file reader
(:func:`machdyn.spec.load_machine`; old ``machdyn linkage`` files are upgraded
there), the page from :func:`machdyn.report.machine.machine_report` (every
part of the file; one part's page as it is).
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import numpy as np
import typer

from ..errors import InputError, MachdynError

__all__ = ["OUTPUT_KINDS", "report"]

#: File endings the report is written as.
OUTPUT_KINDS = {".html": "self-contained page", ".pdf": "PDF printed by chromium"}


def report(
    file: Annotated[Path, typer.Argument(help="Machine file (TOML).")],
    out: Annotated[Path, typer.Option("--out", "-o", help="Output: .html or .pdf.")],
    samples: Annotated[int, typer.Option("--samples", help="Poses over the cycle.")] = 360,
    k: Annotated[
        float | None,
        typer.Option("--k", help="Coefficient of fluctuation: size a flywheel for it."),
    ] = None,
    speed: Annotated[
        float | None,
        typer.Option(
            "--speed",
            help="Input speed of every mechanism, rad per time unit (default: the file's).",
        ),
    ] = None,
) -> None:
    """Write the design report of the machine in FILE: one self-contained HTML page (or PDF)."""
    kind = out.suffix.lower()
    if kind not in OUTPUT_KINDS:
        raise InputError(
            "--out", f"unknown file type {out.suffix!r}; use one of {', '.join(OUTPUT_KINDS)}"
        )
    if samples < 8 or samples > 100_000:
        raise InputError("--samples", f"must be between 8 and 100000, got {samples}")
    if k is not None and not 0.0 < k < 0.5:
        raise InputError("--k", f"must be in (0, 0.5), got {k:g}")
    if speed is not None and not (np.isfinite(speed) and speed != 0.0):
        raise InputError("--speed", f"must be a finite non-zero speed, got {speed:g}")
    from ..report.machine import machine_report
    from ..spec import load_machine

    try:
        page = machine_report(load_machine(file), n=samples, k=k, speed=speed)
    except MachdynError as err:
        if "cannot be assembled" not in str(err):
            raise
        _unassemblable(file, out, str(err))
        return
    text = page.html()
    if kind == ".pdf":
        from ..report import to_pdf

        html_path = out.with_suffix(".html")
        html_path.write_text(text, encoding="utf-8")
        to_pdf(html_path, out)
    else:
        out.write_text(text, encoding="utf-8")
    print(f"wrote {out}")
    print(page.headline)


def _unassemblable(file: Path, out: Path, message: str) -> None:
    """A report whose first line says the machine cannot be assembled, with the file as given."""
    from ..report.page import Page, esc

    page = Page(file.stem, f"{file.name}: cannot be assembled anywhere — {message}")
    page.failed = True
    text = file.read_text(encoding="utf-8", errors="replace")
    page.section("model", "The machine as given", f"<pre>{esc(text)}</pre>")
    html_text = page.html()
    if out.suffix.lower() == ".pdf":
        from ..report import to_pdf

        html_path = out.with_suffix(".html")
        html_path.write_text(html_text, encoding="utf-8")
        to_pdf(html_path, out)
    else:
        out.write_text(html_text, encoding="utf-8")
    print(f"wrote {out}")
    print(f"{file.name}: cannot be assembled anywhere — {message}")
