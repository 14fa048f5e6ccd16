"""``machdyn linkage FILE``: a drawn linkage from a machine file, solved and tabulated.

The file is a machine file (``docs/spec.md``) with a ``[linkage.NAME]`` part,
or an old linkage file (read and upgraded on the way). ``--sweep`` and
``--at`` replace a driver's values (in the file's units: degrees for angles,
``[units] length`` for lengths, or with a unit: ``--at "guide=12 mm"``);
``--forces`` adds driver efforts, pin forces and spring loads. Every column is
labelled with its unit. Only parsing, calling and presenting here: the
analysis is :mod:`machdyn.spec`'s linkage part, which calls the library.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Annotated, Any

import numpy as np
import typer

from ..errors import InputError
from ._common import dumps

__all__ = ["driver_values", "linkage", "merged", "pick_part"]


def pick_part(machine: Any, part: str | None) -> Any:
    """The linkage part of ``machine`` (``part`` names it when the file has several)."""
    names = [p.name for p in machine.parts.values() if p.kind == "linkage"]
    if part is not None:
        if part not in names:
            listed = ", ".join(names) or "none"
            raise InputError("--part", f"{part!r} is not a linkage part; linkage parts: {listed}")
        return machine.parts[part]
    if len(names) != 1:
        listed = ", ".join(names) or "none"
        raise InputError(
            "FILE", f"the file has {len(names)} linkage parts ({listed}): pick one with --part"
        )
    return machine.parts[names[0]]


def _assignment(option: str, text: str, drivers: Sequence[str]) -> tuple[str, str]:
    name, sep, value = text.partition("=")
    if not sep:
        raise InputError(
            option, f"expected DRIVER=..., got {text!r}; drivers: {', '.join(drivers)}"
        )
    if name not in drivers:
        raise InputError(option, f"{name!r} is not a driver; drivers: {', '.join(drivers)}")
    return name, value


def driver_values(
    machine: Any, part: Any, sweep: str | None = None, at: Sequence[str] = ()
) -> None:
    """Replace the part's driver values by ``--sweep D=START:STOP:STEP`` and ``--at D=VALUE``.

    Values are in the file's units (degrees for angles) or carry their own
    (``"0 mm:50 mm:5 mm"``).

    Examples
    --------
    >>> from machdyn.spec import load_machine
    >>> machine = load_machine(EXAMPLES / "fourbar.toml")
    >>> part = pick_part(machine, None)
    >>> driver_values(machine, part, at=["crank=45"])
    >>> part.values["motion"]["crank"].values.values.round(6).tolist()  # radians
    [0.785398]
    """
    from ..spec._context import SpecError
    from ..spec._linkage import DriverSetting, angle_drivers
    from ..spec._types import Sweep

    lk = part.model
    angles = angle_drivers(lk)
    motion = dict(part.values.get("motion", {}))
    changes = [("--sweep", sweep)] if sweep is not None else []
    changes += [("--at", item) for item in at]
    given: dict[str, str] = {}
    for option, text in changes:
        name, value = _assignment(option, text, lk.drivers)
        if name in given:  # the last one would silently win
            raise InputError(
                f"{option} {name}",
                f"{name} is already set by {given[name]}; give each driver one value or sweep",
            )
        given[name] = option
        kind = "angle" if name in angles else "length"
        items = value.split(":") if option == "--sweep" else [value]
        if option == "--sweep" and len(items) != 3:
            raise InputError(f"--sweep {name}", f"expected START:STOP:STEP, got {value!r}")
        parsed: list[Any] = []
        for item in items:
            item = item.strip()
            try:
                parsed.append(float(item))
            except ValueError:
                parsed.append(item)
        try:
            grid = Sweep(kind).read(machine.context, (), parsed if len(parsed) == 3 else parsed[0])
        except SpecError as exc:
            raise InputError(f"{option} {name}", exc.message) from None
        old = motion.get(name, DriverSetting(kind))
        motion[name] = DriverSetting(kind, grid, old.velocity, old.acceleration, old.driven_by)
    part.values["motion"] = motion


def merged(tables: Sequence[Any]) -> Any:
    """One table of every column of ``tables`` (each name once; ``ok``, ``reason`` last)."""
    from ..spec._run import ResultTable

    columns: dict[str, np.ndarray] = {}
    kinds: dict[str, str | None] = {}
    for table in tables:
        for name, values in table.columns.items():
            if name in ("ok", "reason"):
                continue
            columns.setdefault(name, values)
            kinds.setdefault(name, table.kinds[name])
    last = tables[-1]
    columns |= {"ok": last.columns["ok"], "reason": last.columns["reason"]}
    kinds |= {"ok": None, "reason": None}
    return ResultTable("all", tables[0].title, columns, kinds)


EXAMPLES = Path(__file__).resolve().parents[3] / "docs" / "examples"


def linkage(
    file: Annotated[
        Path, typer.Argument(help="A machine file with a linkage part (docs/spec.md).")
    ],
    sweep: Annotated[
        str | None,
        typer.Option(help="Sweep one driver: DRIVER=START:STOP:STEP (file units; deg for angles)."),
    ] = None,
    at: Annotated[
        list[str] | None,
        typer.Option(help="Hold a driver: DRIVER=VALUE (file units; deg for angles); repeatable."),
    ] = None,
    forces: Annotated[
        bool, typer.Option("--forces", help="Add driver efforts, pin forces and spring loads.")
    ] = False,
    part: Annotated[
        str | None, typer.Option("--part", help="The linkage part, if the file has several.")
    ] = None,
    json: Annotated[bool, typer.Option("--json", help="Print machine-readable JSON.")] = False,
    csv_out: Annotated[
        Path | None,
        typer.Option("--csv", help="Also write every column to this CSV file (units in header)."),
    ] = None,
) -> None:
    """Solve a drawn linkage from a machine file: positions, velocities, accelerations (forces)."""
    import sys

    from ..spec import load_machine
    from ..spec._legacy import NOTE
    from ..spec._linkage import _refs, run_linkage
    from .run import _print_part, payload, write_csv

    machine = load_machine(file)
    chosen = pick_part(machine, part)
    driver_values(machine, chosen, sweep, at or ())
    uses = sorted(set(_refs(chosen.values).values()))
    result = run_linkage(chosen, machine, machine.run(uses) if uses else {}, forces=forces)
    if csv_out is not None:
        with open(csv_out, "w", newline="", encoding="utf-8") as out:
            write_csv(merged(result.tables).labelled(machine.units), out)
    if machine.legacy:
        print(NOTE.format(file=file), file=sys.stderr)
    if json:
        print(dumps(payload(machine, {chosen.name: result})))
        return
    _print_part(machine, result)
    if csv_out is not None:
        print(f"wrote {csv_out}")
