"""``machdyn run FILE``: analyse whatever a machine file describes (see ``docs/spec.md``).

Prints, for each part, a short summary and its tables with every column
labelled in the file's output units; ``--json`` and ``--csv`` carry the same
labels; ``--out DIR`` writes everything. Only parsing, calling and presenting
happen here: the analyses are the library's, reached through :mod:`machdyn.spec`.
"""

from __future__ import annotations

import csv
import io
import math
from collections.abc import Callable
from pathlib import Path
from typing import Annotated, Any

import numpy as np
import typer

from ..errors import InputError
from ._common import dumps, print_table

__all__ = [
    "emit",
    "load_part",
    "payload",
    "pick_part",
    "run",
    "run_spec_part",
    "table_rows",
    "write_csv",
]


def _cell(value: Any) -> Any:
    if isinstance(value, np.bool_ | bool):
        return bool(value)
    if isinstance(value, float | np.floating):
        value = float(value)
        return value if math.isfinite(value) else None
    if isinstance(value, np.integer):
        return int(value)
    return value


def table_rows(columns: dict[str, np.ndarray]) -> list[list[Any]]:
    """Rows of plain values (NaN as None) from labelled columns."""
    arrays = [np.asarray(v, dtype=object) for v in columns.values()]
    return [[_cell(a[i]) for a in arrays] for i in range(len(arrays[0]) if arrays else 0)]


def _shown(value: Any) -> Any:
    """A summary value for JSON: numbers, lists of numbers, or text."""
    if isinstance(value, list | tuple | np.ndarray):
        return [_cell(v) for v in value]
    return _cell(value)


def payload(machine: Any, results: dict[str, Any]) -> dict[str, Any]:
    """Everything ``--json`` prints: summaries and tables per part, labelled with units."""
    system = machine.units
    parts = {}
    for name, r in results.items():
        summary = {}
        for item in r.summary:
            label, value = item.shown(system)
            summary[label] = _shown(value)
        tables = {}
        for table in r.tables:
            cols = table.labelled(system)
            tables[table.name] = {
                "title": table.title,
                "columns": list(cols),
                "rows": table_rows(cols),
            }
        parts[name] = {
            "kind": r.part.kind,
            "summary": summary,
            "tables": tables,
            "flagged": r.flagged,
        }
    return {
        "machdyn": 1,
        "title": machine.title,
        "units": system.to_spec(),
        "parts": parts,
    }


def write_csv(columns: dict[str, np.ndarray], out: Any) -> None:
    """Write labelled columns as CSV (``ok`` as true/false, no value as an empty cell)."""
    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(list(columns))
    for row in table_rows(columns):
        writer.writerow(
            [
                "" if v is None else (str(v).lower() if isinstance(v, bool) else _repr(v))
                for v in row
            ]
        )


def _repr(value: Any) -> Any:
    return repr(value) if isinstance(value, float) else value


def _summary_text(value: Any) -> str:
    if isinstance(value, list | tuple | np.ndarray):
        return ", ".join(_summary_text(v) for v in value)
    if isinstance(value, float | np.floating):
        return f"{float(value):.6g}" if math.isfinite(value) else "-"
    return str(value)


def _print_part(machine: Any, r: Any) -> None:
    system = machine.units
    print(f"{r.part.kind} {r.part.name}")
    items = [item.shown(system) for item in r.summary]
    width = max((len(label) for label, _ in items), default=0)
    for label, value in items:
        print(f"  {label.ljust(width)}  {_summary_text(value)}")
    for table in r.tables:
        cols = table.labelled(system)
        if "ok" in cols:
            cols["ok"] = np.where(np.asarray(cols["ok"], dtype=bool), "yes", "NO")
        cols.pop("reason", None)
        cols = {k: _small(v) for k, v in cols.items()}
        print()
        # plain text: rich's import and layout would cost a third of the 0.6 s budget
        print_table(table.title, list(cols), table_rows(cols), plain=True)
    if r.flagged:
        print()
        for line in r.flagged:
            print(f"  {line}")
    print()


def _small(values: Any) -> Any:
    """A column of small numbers (all below 0.01) as ``1.234e-04`` text, not ``0.0000``."""
    a = np.asarray(values)
    if a.dtype.kind != "f":
        return values
    finite = np.abs(a[np.isfinite(a)])
    if not finite.size or finite.max() == 0.0 or finite.max() >= 0.01:
        return values
    return np.array([f"{v:.3e}" if math.isfinite(v) else "-" for v in a], dtype=object)


def _units_line(system: Any) -> str:
    if system.is_unit_free:
        return "units: none (bare numbers, any consistent system); angles in deg"
    shown = ", ".join(f"{k} {v}" for k, v in system.to_spec().items())
    return f"units: {shown}"


def run(
    file: Annotated[Path, typer.Argument(help="A machine file (.toml or .json; docs/spec.md).")],
    part: Annotated[
        str | None, typer.Option("--part", help="Analyse only this part (and what it uses).")
    ] = None,
    json: Annotated[bool, typer.Option("--json", help="Print JSON (columns with units).")] = False,
    csv_out: Annotated[
        bool, typer.Option("--csv", help="Print the part's main table as CSV (units in header).")
    ] = False,
    out: Annotated[
        Path | None,
        typer.Option("--out", help="Write every table (CSV), result.json and machine.toml here."),
    ] = None,
) -> None:
    """Analyse a machine file and print every part's results, each column with its unit."""
    from ..spec import load_machine

    if json and csv_out:
        raise InputError("--csv", "choose one of --json and --csv")
    machine = load_machine(file)
    if machine.legacy:
        import sys

        from ..spec._legacy import NOTE

        print(NOTE.format(file=file), file=sys.stderr)
    if part is not None and part not in machine.parts:
        raise InputError("--part", f"{part!r} is not a part; parts: {', '.join(machine.parts)}")
    if out is not None and out.exists() and not out.is_dir():
        raise InputError("--out", f"{out} is a file, not a folder")
    results = machine.run([part] if part else None)
    if part is not None:
        results = {part: results[part]}
    emit(machine, results, file, json=json, csv_out=csv_out, out=out)


def emit(
    machine: Any,
    results: dict[str, Any],
    file: Path,
    *,
    json: bool = False,
    csv_out: bool = False,
    out: Path | None = None,
) -> None:
    """Print (and with ``out`` write) analysed parts as ``machdyn run`` does."""
    from ..spec import dumps as spec_dumps

    if out is not None:
        out.mkdir(parents=True, exist_ok=True)
        for name, r in results.items():
            for table in r.tables:
                with open(out / f"{name}-{table.name}.csv", "w", newline="", encoding="utf-8") as f:
                    write_csv(table.labelled(machine.units), f)
        (out / "result.json").write_text(dumps(payload(machine, results)) + "\n", encoding="utf-8")
        (out / "machine.toml").write_text(spec_dumps(machine.to_spec()), encoding="utf-8")
    if json:
        print(dumps(payload(machine, results)))
    elif csv_out:
        tabled = {n: r for n, r in results.items() if r.tables}
        if len(tabled) != 1:
            raise InputError(
                "--csv",
                f"the file has {len(tabled)} parts with tables ({', '.join(tabled) or 'none'}): "
                "pick one with --part NAME, or write them all with --out DIR",
            )
        r = next(iter(tabled.values()))
        buffer = io.StringIO()
        write_csv(r.tables[0].labelled(machine.units), buffer)
        print(buffer.getvalue(), end="")
    else:
        heading = machine.title or Path(file).name
        print(f"{heading}  ({_units_line(machine.units)})\n")
        for r in results.values():
            _print_part(machine, r)
        if out is not None:
            print(f"wrote {out}/ (CSV per table, result.json, machine.toml)")


def pick_part(
    machine: Any,
    kinds: tuple[str, ...],
    part: str | None,
    file: Path,
    fits: Callable[[Any], str | None] | None = None,
) -> str:
    """The name of the part of one of ``kinds`` that a sub-command's ``--spec`` analyses.

    ``part`` (``--part NAME``) chooses among several; errors name the file's parts.
    ``fits(part)`` (optional) says why a part of the right kind does not fit
    this command (None: it fits).
    """
    wanted = " or ".join(kinds)
    fits = fits or (lambda p: None)
    present = ", ".join(f"{p.kind} {p.name}" for p in machine.parts.values()) or "no parts"
    if part is not None:
        if part not in machine.parts:
            raise InputError("--part", f"{part!r} is not a part of {file}; its parts: {present}")
        if machine.parts[part].kind not in kinds:
            kind = machine.parts[part].kind
            raise InputError("--part", f"{part!r} is a {kind} part of {file}, not a {wanted}")
        why = fits(machine.parts[part])
        if why:
            raise InputError("--part", f"{part!r} of {file} {why}")
        return part
    of_kind = [p for p in machine.parts.values() if p.kind in kinds]
    fitting = [p.name for p in of_kind if not fits(p)]
    if of_kind and not fitting:
        raise InputError(
            "--spec", f"{of_kind[0].kind} part {of_kind[0].name!r} of {file} {fits(of_kind[0])}"
        )
    if not fitting:
        raise InputError(
            "--spec",
            f"{file} has no {wanted} part (it holds {present}); `machdyn run {file}` "
            "analyses those",
        )
    if len(fitting) > 1:
        raise InputError(
            "--part",
            f"{file} has {len(fitting)} {wanted} parts ({', '.join(fitting)}): pick one with "
            "--part NAME",
        )
    return fitting[0]


def load_part(
    file: Path,
    kinds: tuple[str, ...],
    part: str | None,
    fits: Callable[[Any], str | None] | None = None,
) -> tuple[Any, str]:
    """Read a machine file for a sub-command's ``--spec``: ``(machine, part name)``."""
    from ..spec import load_machine

    if part is not None and (not isinstance(part, str) or not part.strip()):
        raise InputError("--part", f"a part's name, got {part!r}")
    machine = load_machine(file)
    return machine, pick_part(machine, kinds, part, file, fits)


def run_spec_part(
    file: Path | None,
    kinds: tuple[str, ...],
    part: str | None,
    *,
    given: dict[str, bool] | None = None,
    json: bool = False,
    csv_out: bool = False,
    fits: Callable[[Any], str | None] | None = None,
) -> bool:
    """A sub-command's ``--spec FILE``: analyse the file's part as ``machdyn run --part`` does.

    ``given`` maps the command's model options to whether they were given:
    the model comes from the file, so any of them is refused. Without a file
    (no ``--spec``) nothing runs and False is returned; ``--part`` and ``--csv``
    are then refused, as they only go with a file.
    """
    if file is None:
        for option, value in (("--part", part is not None), ("--csv", csv_out)):
            if value:
                raise InputError(option, "goes with --spec FILE (a machine file)")
        return False
    for option, was_given in (given or {}).items():
        if was_given:
            raise InputError(
                option, "the model comes from --spec FILE; give it by options or by the file"
            )
    if json and csv_out:
        raise InputError("--csv", "choose one of --json and --csv")
    machine, name = load_part(file, kinds, part, fits)
    results = machine.run([name])
    emit(machine, {name: results[name]}, file, json=json, csv_out=csv_out)
    return True


spec_app = typer.Typer(
    help="Machine files: check one, upgrade an old linkage file, print the JSON Schema.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)


@spec_app.command("check")
def check(file: Annotated[Path, typer.Argument(help="A machine file (.toml or .json).")]) -> None:
    """Read a machine file completely (units, names, references) without analysing it."""
    from ..spec import load_machine

    machine = load_machine(file)
    listed = ", ".join(f"{p.kind} {p.name}" for p in machine.parts.values())
    print(f"{file}: ok ({listed}; {_units_line(machine.units)})")


@spec_app.command("upgrade")
def upgrade(
    file: Annotated[Path, typer.Argument(help="An old `machdyn linkage` file.")],
) -> None:
    """Print an old linkage file (no ``machdyn = 1``) in the machine-file format."""
    import tomllib

    from ..spec import dumps as spec_dumps
    from ..spec import load_machine
    from ..spec._legacy import upgrade as upgraded

    load_machine(file)  # read completely first: errors name the old file's lines
    doc = tomllib.loads(Path(file).read_text(encoding="utf-8"))
    if "machdyn" in doc:
        raise InputError(str(file), "is a machine file already (it has machdyn = 1)")
    print(spec_dumps(upgraded(doc)), end="")


@spec_app.command("schema")
def schema_cmd(
    path: Annotated[
        bool, typer.Option("--path", help="Print where the schema file is instead of its text.")
    ] = False,
) -> None:
    """Print the JSON Schema of machine files (for editors that check TOML/JSON files)."""
    from ..spec import schema

    if path:
        from ..spec import __file__ as spec_init

        print(Path(spec_init).with_name("machdyn.schema.json"))
        return
    print(dumps(schema()))
