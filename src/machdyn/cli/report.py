"""``machdyn report FILE -o report.html``: the design report of the machine a file describes.

Only reading and calling: the model comes from the machine-file reader
(``machdyn.load`` of the spec format where it is installed, otherwise the
linkage TOML files of ``machdyn linkage``), the page from :mod:`machdyn.report`.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated, Any

import numpy as np
import typer

from ..errors import InputError, MachdynError

__all__ = ["OUTPUT_KINDS", "load_model", "report"]

#: File endings the report is written as.
OUTPUT_KINDS = {".html": "self-contained page", ".pdf": "PDF printed by chromium"}


def load_model(path: Path) -> tuple[Any, dict[str, Any]]:
    """The model a file describes and the report options it implies.

    A machine file (``machdyn = 1``, docs/spec.md) is read by
    :func:`machdyn.spec.load_machine`: its first four-bar or linkage part is
    reported, with the file's speed, mass properties, loads, gravity and units.
    An old ``machdyn linkage`` file (no ``machdyn = 1``) is upgraded on reading.
    """
    return _machine_part(path)


def _machine_part(path: Path) -> tuple[Any, dict[str, Any]]:
    from ..fourbar import FourBar
    from ..linkage import Linkage
    from ..spec import load_machine

    machine = load_machine(path)
    units = getattr(machine, "units", None)
    options: dict[str, Any] = {}
    if units is not None and getattr(units, "length", None):
        options["length_unit"] = units.length
    for part in machine.parts.values():
        v = part.values
        if isinstance(part.model, FourBar):
            motion = v.get("motion", {})
            if "omega2" in motion:
                options["omega2"] = float(motion["omega2"])
            links = [v.get(f"link{i}") for i in (2, 3, 4)]
            if all(links):
                options["mass"] = tuple(float(x.get("mass", 0.0)) for x in links)
                options["inertia"] = tuple(float(x.get("inertia", 0.0)) for x in links)
                options["cg"] = tuple(complex(x.get("cg", 0.0)) for x in links)
                options["gravity"] = float(machine.gravity or 0.0)
                if "torque4" in v.get("loads", {}):
                    options["load_torque4"] = float(v["loads"]["torque4"])
            return part.model, options
        if isinstance(part.model, Linkage):
            options["gravity"] = float(machine.gravity or 0.0)
            first = v.get("motion", {}).get(part.model.drivers[0]) if part.model.drivers else None
            if first is not None:  # a DriverSetting: values in the model's units (radians)
                if first.velocity is not None:
                    options["velocity"] = first.velocity
                values = first.values.values if first.values is not None else ()
                if len(values) > 1:  # the file's range, finely
                    is_angle = first.kind == "angle"
                    lo, hi = float(values[0]), float(values[-1])
                    if is_angle:
                        lo, hi = math.degrees(lo), math.degrees(hi)
                    options["values"] = (lo, hi, is_angle)
            return part.model, options
    kinds = ", ".join(sorted({p.kind for p in machine.parts.values()})) or "none"
    raise InputError(
        str(path),
        f"no four-bar or linkage part to report (parts: {kinds}); the "
        "report covers [fourbar.NAME] and [linkage.NAME] parts",
    )


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
        typer.Option("--speed", help="Input speed, rad/s (default: the file's, or 1)."),
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
    try:
        model, options = load_model(file)
    except MachdynError as err:
        if "cannot be assembled" not in str(err):
            raise
        _unassemblable(file, out, str(err))
        return
    from ..fourbar import FourBar
    from ..report import report as write_report

    options["n"] = samples
    if "values" in options:  # the file's sweep range, at the report's resolution
        lo, hi, is_angle = options.pop("values")
        grid = np.linspace(lo, hi, samples)
        options["values"] = np.radians(grid) if is_angle else grid
    if k is not None:
        options["k"] = k
    if isinstance(model, FourBar):
        if "mass" not in options:
            options.pop("gravity", None)
        options.pop("velocity", None)
        if speed is not None:
            options["omega2"] = speed
    elif speed is not None:
        options["velocity"] = speed
    page = write_report(model, out, **options)
    first = page.split('id="headline">', 1)[1].split("</p>", 1)[0]
    print(f"wrote {out}")
    import html

    print(html.unescape(first))


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
