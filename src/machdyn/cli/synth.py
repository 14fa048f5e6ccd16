"""``machdyn synth ...``: three-position motion, function and path generation (from an atlas).

Registered by the application as ``app.add_typer(synth_app, name="synth")``.
Only parsing and presentation live here; the synthesis is
:mod:`machdyn.synthesis`. Angles are in degrees on the command line.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import numpy as np
import typer

from .._expression import parse_function
from ..errors import AssemblyError, InputError
from ._common import dumps, print_table
from .run import run_spec_part

__all__ = [
    "candidate_spec",
    "parse_function",
    "parse_points",
    "read_points_csv",
    "sixbar_spec",
    "synth_app",
]

synth_app = typer.Typer(
    name="synth",
    help="Synthesis of four-bars: three-position motion, function and path generation.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)


SpecOpt = Annotated[
    Path | None,
    typer.Option("--spec", help="A machine file (docs/spec.md): solve its task of this kind."),
]
PartOpt = Annotated[
    str | None, typer.Option("--part", help="With --spec: the part, when the file has several.")
]
CsvOpt = Annotated[
    bool, typer.Option("--csv", help="With --spec: print the main table as CSV (with units).")
]


def _missing(option: str, value: object, what: str) -> None:
    if value is None:
        raise InputError(option, f"missing: give {what}, or --spec FILE")


def parse_points(text: str, field: str, count: int) -> list[complex]:
    """Parse ``"x,y; x,y; ..."`` into complex points.

    Examples
    --------
    >>> parse_points("0,5.086; 2.019,3.181", "--c", 2)
    [5.086j, (2.019+3.181j)]
    """
    parts = [p for p in text.replace("\n", ";").split(";") if p.strip()]
    points = []
    for part in parts:
        xy = part.replace(" ", "").split(",")
        try:
            x, y = (float(v) for v in xy)
        except ValueError:
            raise InputError(field, f"expected 'x,y; x,y; ...', could not read {part!r}") from None
        points.append(complex(x, y))
    if len(points) != count:
        raise InputError(field, f"expected {count} points 'x,y; x,y; x,y', got {len(points)}")
    return points


def _pair(text: str, field: str) -> tuple[float, float]:
    try:
        a, b = (float(v) for v in text.split(":"))
    except ValueError:
        raise InputError(field, f"expected START:END, got {text!r}") from None
    return a, b


def _point(z: complex) -> str:
    return f"({z.real:.4f}, {z.imag:.4f})"


@synth_app.command("three-position")
def three_position_cmd(
    c: Annotated[str | None, typer.Option("--c", help="C1..C3 as 'x,y; x,y; x,y'.")] = None,
    d: Annotated[str | None, typer.Option("--d", help="D1..D3 as 'x,y; x,y; x,y'.")] = None,
    o2: Annotated[
        str | None, typer.Option("--o2", help="Fixed pivot O2 'x,y' (inverted problem).")
    ] = None,
    o4: Annotated[str | None, typer.Option("--o4", help="Fixed pivot O4 'x,y'.")] = None,
    json: Annotated[bool, typer.Option("--json", help="Print JSON instead of tables.")] = False,
    spec: SpecOpt = None,
    part: PartOpt = None,
    csv: CsvOpt = False,
) -> None:
    """Four-bar through three positions of a coupler line CD (pivots by bisectors).

    With --o2 and --o4 the fixed pivots are given and the moving pivots are
    found by inversion. Exits with status 1 if the linkage has a circuit,
    branch or order defect (reported on stderr). With ``--spec FILE`` the task
    is the file's ``motion_synthesis`` part, reported as ``machdyn run`` does.
    """
    from ..synthesis import three_position, three_position_fixed_pivots
    from ..synthesis.placed import form_of

    given = {"--c": c is not None, "--d": d is not None}
    given |= {"--o2": o2 is not None, "--o4": o4 is not None}
    if run_spec_part(spec, ("motion_synthesis",), part, given=given, json=json, csv_out=csv):
        return
    _missing("--c", c, "--c and --d (three points each)")
    _missing("--d", d, "--c and --d (three points each)")
    assert c is not None and d is not None
    cs = parse_points(c, "--c", 3)
    ds = parse_points(d, "--d", 3)
    if (o2 is None) != (o4 is None):
        raise InputError("--o2", "give both --o2 and --o4 (fixed pivots), or neither")
    if o2 is None:
        s = three_position(cs, ds)
    else:
        s = three_position_fixed_pivots(
            cs, ds, parse_points(o2, "--o2", 1)[0], parse_points(o4, "--o4", 1)[0]
        )
    if json:
        print(
            dumps(
                {
                    "O2": s.O2,
                    "O4": s.O4,
                    "theta1_deg": float(np.degrees(s.theta1)),
                    "r1": s.r1,
                    "r2": s.r2,
                    "r3": s.r3,
                    "r4": s.r4,
                    "barker_class": s.fourbar.barker_class,
                    "A": s.A,
                    "B": s.B,
                    "theta2_deg": np.degrees(s.theta2),
                    "branch": s.branch,
                    "form": form_of(s.branch),
                    "direction": s.direction,
                    "mu_min_deg": float(np.degrees(s.mu_min)),
                    "defects": list(s.defects),
                }
            )
        )
    else:
        print_table(
            "Three-position synthesis",
            ["quantity", "value"],
            [
                ["O2", _point(s.O2)],
                ["O4", _point(s.O4)],
                ["ground angle theta1 (deg)", float(np.degrees(s.theta1))],
                ["r1 ground", s.r1],
                ["r2 input", s.r2],
                ["r3 coupler", s.r3],
                ["r4 output", s.r4],
                ["Barker class", s.fourbar.barker_class],
                ["form (FourBar, as in the notes)", form_of(s.branch)],
                ["min transmission angle (deg)", float(np.degrees(s.mu_min))],
            ],
        )
        print_table(
            "Positions",
            ["position", "A", "B", "theta2 (deg)", "branch"],
            [
                [
                    k + 1,
                    _point(s.A[k]),
                    _point(s.B[k]),
                    float(np.degrees(s.theta2[k])),
                    int(s.branch[k]),
                ]
                for k in range(3)
            ],
        )
    if s.defects:
        raise AssemblyError("the linkage cannot do the job: " + "; ".join(s.defects))


@synth_app.command("function")
def function_cmd(
    f: Annotated[
        str | None, typer.Option("--f", help="y = f(x), e.g. 'log10(x)' or 'x**1.5'.")
    ] = None,
    x: Annotated[str | None, typer.Option("--x", help="Range of x, START:END.")] = None,
    theta2: Annotated[
        str | None, typer.Option("--theta2", help="Input angles, START:END (deg).")
    ] = None,
    theta4: Annotated[
        str | None, typer.Option("--theta4", help="Output angles, START:END (deg).")
    ] = None,
    n: Annotated[int, typer.Option("--n", help="Precision points (3 exact, more LSQ).")] = 3,
    spacing: Annotated[str, typer.Option("--spacing", help="chebyshev or uniform.")] = "chebyshev",
    r1: Annotated[float, typer.Option("--r1", help="Ground length (scale).")] = 1.0,
    samples: Annotated[int, typer.Option("--samples", help="Structural-error samples.")] = 11,
    json: Annotated[bool, typer.Option("--json", help="Print JSON instead of tables.")] = False,
    spec: SpecOpt = None,
    part: PartOpt = None,
    csv: CsvOpt = False,
) -> None:
    """Four-bar function generator by Freudenstein's equation, with its structural error.

    With ``--spec FILE`` the task is the file's ``function_synthesis`` part,
    reported as ``machdyn run FILE --part NAME`` does.
    """
    from ..synthesis import function_generator

    given = {"--f": f is not None, "--x": x is not None, "--theta2": theta2 is not None}
    given |= {"--theta4": theta4 is not None, "--n": n != 3, "--spacing": spacing != "chebyshev"}
    given |= {"--r1": r1 != 1.0, "--samples": samples != 11}
    if run_spec_part(spec, ("function_synthesis",), part, given=given, json=json, csv_out=csv):
        return
    what = "--f, --x, --theta2 and --theta4"
    for option, value in (("--f", f), ("--x", x), ("--theta2", theta2), ("--theta4", theta4)):
        _missing(option, value, what)
    assert f is not None and x is not None and theta2 is not None and theta4 is not None
    for option, value, most in (("--n", n, 10_000), ("--samples", samples, 100_000)):
        if not 1 <= value <= most:
            raise InputError(option, f"must be between 1 and {most:,}, got {value:,}")
    func = parse_function(f)
    x_range = _pair(x, "--x")
    t2 = np.radians(_pair(theta2, "--theta2"))
    t4 = np.radians(_pair(theta4, "--theta4"))
    g = function_generator(func, x_range, t2, t4, n=n, spacing=spacing, r1=r1)
    se = g.structural_error(n=samples)
    if json:
        print(
            dumps(
                {
                    "r1": g.r1,
                    "r2": g.r2,
                    "r3": g.r3,
                    "r4": g.r4,
                    "K": g.k,
                    "barker_class": g.fourbar.barker_class,
                    "branch": g.branch,
                    "input_offset_deg": float(np.degrees(g.input_offset)),
                    "output_offset_deg": float(np.degrees(g.output_offset)),
                    "x_precision": g.x_precision,
                    "structural_error": {"x": se.x, "error": se.error, "ok": se.ok},
                    "max_abs_error": se.max_abs,
                    "defects": list(g.defects),
                }
            )
        )
    else:
        print_table(
            f"Function generator for y = {f}",
            ["quantity", "value"],
            [
                ["r1 ground", g.r1],
                ["r2 input", g.r2],
                ["r3 coupler", g.r3],
                ["r4 output", g.r4],
                ["K1, K2, K3", ", ".join(f"{k:.6g}" for k in g.k)],
                ["Barker class", g.fourbar.barker_class],
                ["input link offset (deg)", float(np.degrees(g.input_offset))],
                ["output link offset (deg)", float(np.degrees(g.output_offset))],
                ["precision points x", ", ".join(f"{v:.6g}" for v in g.x_precision)],
                ["max |structural error|", f"{se.max_abs:.3e}"],
            ],
        )
        print_table(
            "Structural error",
            ["x", "f(x)", "generated", "error"],
            [
                [float(a), float(b), float(c), "-" if np.isnan(e) else f"{e:.3e}"]
                for a, b, c, e in zip(se.x, se.y_desired, se.y_generated, se.error, strict=True)
            ],
        )
    if g.defects:
        raise AssemblyError("the linkage cannot generate the function: " + "; ".join(g.defects))


def read_points_csv(file: Path, timing: bool) -> tuple[np.ndarray, np.ndarray | None]:
    r"""Target points from a CSV file: ``x,y`` per line (``x,y,theta2_deg`` with timing).

    Cells are separated by commas, semicolons, tabs or spaces (one kind per line). A
    first line whose cells are all words is a header; blank lines and lines starting
    with ``#`` are skipped. Every other line holds exactly two numbers (three with
    timing), each finite: an empty cell, a missing or extra column or a NaN is refused
    with its line, never read as something else. A third column without timing (a
    timed file in an untimed run) is ignored with a warning.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> f = pathlib.Path(tempfile.mkdtemp()) / "p.csv"
    >>> _ = f.write_text("x,y,theta2\n0,0,0\n1,0.5,90\n")
    >>> pts, th = read_points_csv(f, timing=True)
    >>> pts, np.degrees(th)
    (array([0.+0.j , 1.+0.5j]), array([ 0., 90.]))
    >>> _ = f.write_text("x;y\n0;0\n1;0.5\n")
    >>> read_points_csv(f, timing=False)[0]
    array([0.+0.j , 1.+0.5j])
    """
    import csv
    import warnings

    text = Path(file).read_text(encoding="utf-8-sig")  # (a byte-order mark is not a cell)
    want = 3 if timing else 2
    what = "x, y, theta2 (deg)" if timing else "x, y"
    rows = []
    first, ignored = True, False
    for number, line in enumerate(text.splitlines(), 1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        header, first = first, False
        for sep in (";", ",", "\t"):
            if sep in line:
                cells = [c.strip() for c in next(csv.reader([line], delimiter=sep))]
                break
        else:
            cells = line.split()
        if header and all(c and any(ch.isalpha() for ch in c) and not _is_number(c) for c in cells):
            continue  # a header: words only ("x, y, theta2_deg"; not "nan" nor "1,5")
        values = []
        for k, cell in enumerate(cells, 1):
            if not cell:
                raise InputError(str(file), f"line {number}: cell {k} is empty; expected {what}")
            if not _is_number(cell):
                hint = " (decimal commas are not read: write 1.5, not 1,5)" if "," in cell else ""
                raise InputError(
                    str(file), f"line {number}: expected numbers {what}, got {cell!r}{hint}"
                )
            values.append(float(cell))
        if len(values) == 3 and not timing:  # a timed file in an untimed run: said, not silent
            if not ignored:
                warnings.warn(
                    f"{file}: the third column (input angles?) is ignored; add --timing to "
                    "prescribe them",
                    UserWarning,
                    stacklevel=2,
                )
            ignored = True
            values = values[:2]
        if len(values) != want:
            raise InputError(str(file), f"line {number}: expected {what}, got {len(values)} values")
        bad = [c for c, v in zip(cells, values, strict=False) if not np.isfinite(v)]
        if bad:
            raise InputError(
                str(file), f"line {number}: {bad[0]!r} is not a finite number; expected {what}"
            )
        rows.append(values)
    if not rows:
        raise InputError(str(file), f"holds no points (expected lines '{what}')")
    data = np.array(rows, dtype=float)
    points = data[:, 0] + 1j * data[:, 1]
    return points, (np.radians(data[:, 2]) if timing else None)


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


@synth_app.command("path")
def path_cmd(
    points: Annotated[
        Path | None,
        typer.Argument(help="CSV of target points 'x,y' (with --timing 'x,y,theta2_deg')."),
    ] = None,
    open_path: Annotated[
        bool, typer.Option("--open", help="An open path (or part of a closed one).")
    ] = False,
    timing: Annotated[
        bool, typer.Option("--timing", help="Third column: input angle at each point (deg).")
    ] = False,
    n: Annotated[int, typer.Option("-n", "--n", help="How many linkages to print.")] = 5,
    atlas: Annotated[
        Path | None,
        typer.Option(
            "--atlas",
            help="Atlas folder (default $MACHDYN_ATLAS or ~/.cache/machdyn/fourbar.atlas).",
        ),
    ] = None,
    no_crank: Annotated[
        bool, typer.Option("--no-crank", help="Do not require link 2 to turn fully.")
    ] = False,
    mu_min: Annotated[
        float, typer.Option("--mu-min", help="Smallest transmission angle (deg).")
    ] = 30.0,
    out: Annotated[
        Path, typer.Option("--out", help="Folder for the candidates' spec files.")
    ] = Path("path_candidates"),
    scheduler: Annotated[
        str | None, typer.Option("--scheduler", help="Query on a Dask scheduler (tcp://HOST:PORT).")
    ] = None,
    verify: Annotated[
        bool, typer.Option("--verify/--no-verify", help="Check the atlas's CRCs first (~1 s/GB).")
    ] = True,
    time_limit: Annotated[
        float | None,
        typer.Option(
            "--time-limit",
            help="Seconds for the synthesis (after opening the atlas): the best found by then.",
        ),
    ] = None,
    json: Annotated[bool, typer.Option("--json", help="Print JSON instead of a table.")] = False,
    spec: SpecOpt = None,
    part: PartOpt = None,
    csv: CsvOpt = False,
) -> None:
    """Four-bars whose coupler point passes through the target points, from an atlas.

    Prints the candidates with their errors and writes each one's spec
    (machdyn = 1 TOML, with the placement in the plane) into --out.
    Exits with status 1 when no candidate is free of defects. With ``--spec
    FILE`` the task is the file's ``path_synthesis`` part, solved as
    ``machdyn run FILE --part NAME`` does.
    """
    from ..synthesis import open_atlas, path_from_atlas
    from .atlas import default_atlas

    given = {"POINTS": points is not None, "--open": open_path, "--timing": timing}
    given |= {"--atlas": atlas is not None, "--scheduler": scheduler is not None}
    given |= {"--time-limit": time_limit is not None}
    if run_spec_part(spec, ("path_synthesis",), part, given=given, json=json, csv_out=csv):
        return
    _missing("POINTS", points, "a CSV of target points")
    assert points is not None
    if not 1 <= n <= 100:
        raise InputError("-n", f"must be between 1 and 100, got {n}")
    if not 0.0 <= mu_min < 90.0:
        raise InputError("--mu-min", f"must be between 0 and 90 deg, got {mu_min:g}")
    targets, theta = read_points_csv(points, timing)
    if out.exists() and not out.is_dir():  # (before the synthesis, not after it)
        raise InputError("--out", f"{out} is a file; give a folder for the candidates' specs")
    if time_limit is not None:  # (before the atlas is opened and verified)
        from .._validate import nonnegative

        time_limit = nonnegative("--time-limit", time_limit, "second")
    options = dict(
        closed=not open_path, timing=theta, n=n, crank=not no_crank, mu_min=np.radians(mu_min),
        time_limit=time_limit,
    )  # fmt: skip
    opened = open_atlas(atlas or default_atlas(), verify=verify)
    if scheduler is None:
        res = path_from_atlas(targets, opened, **options)
    else:
        from ..synthesis.atlas_dask import client_for

        with client_for(scheduler) as client:
            res = path_from_atlas(targets, opened, client=client, **options)
    shown = res.candidates or res.rejected[:n]
    size = float(np.max(np.abs(res.targets - res.targets.mean())))
    out.mkdir(parents=True, exist_ok=True)
    files = []
    six = bool(shown) and hasattr(shown[0], "chain")
    for i, c in enumerate(shown, 1):
        file = out / f"candidate_{i}.toml"
        title = f"candidate {i} for {points.name}"
        file.write_text(sixbar_spec(c, title) if six else candidate_spec(c, title))
        files.append(str(file))
    if six:
        _print_sixbars(res, shown, files, size, json)
    elif json:
        print(dumps({
            "candidates": [_candidate_json(c, size, f) for c, f in zip(shown, files, strict=True)],
            "defect_free": bool(res.candidates),
            "near": res.near,
            "note": res.note,
            "seconds": res.seconds,
        }))  # fmt: skip
    else:
        fits, shapes = [], []
        for i, c in enumerate(shown, 1):
            pl = c.linkage
            fits.append(_fit_row(i, c, size))
            p, delta = pl.fourbar.coupler
            shapes.append([
                i, *(f"{v:.5g}" for v in (*pl.lengths, p)), f"{np.degrees(delta):.2f}",
                f"{pl.O2.real:.5g}", f"{pl.O2.imag:.5g}", f"{np.degrees(pl.theta1):.2f}",
            ])  # fmt: skip
        title = (
            "Path synthesis from the atlas"
            if res.candidates
            else "Best linkages found (with defects)"
        )
        print_table(title, FIT_COLUMNS, fits)
        print_table(
            "Their geometry (lengths in the points' units; delta: coupler point from AB)",
            ["#", "r1", "r2", "r3", "r4", "p", "delta(deg)", "O2 x", "O2 y", "theta1(deg)"],
            shapes,
        )
        print(f"specs: {', '.join(files)}")
        # linkages with defects that come far nearer than the defect-free ones: what stops them
        miss = min((float(np.max(c.distance)) for c in res.candidates), default=0.0)
        closer = [c for c in res.rejected if np.max(c.distance) < 0.5 * miss]
        if closer:
            rows = [_fit_row(i, c, size) for i, c in enumerate(closer[:n], 1)]
            print_table("Closer linkages with defects (not written)", FIT_COLUMNS, rows)
        secs = res.seconds
        print(
            f"retrieve {secs['retrieve']:.2f} s, refine {secs['refine']:.2f} s, "
            f"total {secs['total']:.2f} s"
        )
        if res.note:
            print(f"note: {res.note}")
    if not res.candidates:
        raise AssemblyError(res.note or "no defect-free linkage found for these targets")


#: Columns of a four-bar result's row (:func:`_fit_row`).
FIT_COLUMNS = ["#", "max dist", "% of size", "class", "mu min(deg)", "defects"]


def _fit_row(i: int, c, size: float) -> list:
    """Result ``c``'s row of the tables of fits: its worst miss, class, angle and defects."""
    worst = float(np.max(c.distance))
    return [i, f"{worst:.3e}", f"{100 * worst / size:.2e}", c.barker_class, _deg(c.mu_min),
            "; ".join(c.defects) or "-"]  # fmt: skip


def _deg(angle: float) -> str:
    """An angle in degrees for a table; "-" when there is none (NaN)."""
    return f"{np.degrees(angle):.1f}" if np.isfinite(angle) else "-"


def _print_sixbars(res, shown, files, size, json) -> None:
    """The six-bar candidates: a table or JSON."""
    names = ("O2x", "O2y", "theta1", "r1", "r2", "r3", "r4", "cu", "cv", "du", "dv", "a", "b",
             "pu", "pv")  # fmt: skip
    rows = [
        {
            "chain": c.chain, "max_distance": float(np.max(c.distance)),
            "max_distance_over_size": float(np.max(c.distance) / size),
            "design": dict(zip(names, map(float, c.design), strict=True)),
            "theta2_deg": np.degrees(c.theta2), "defects": list(c.defects), "spec": f,
        }
        for c, f in zip(shown, files, strict=True)
    ]  # fmt: skip
    if json:
        print(dumps({"candidates": rows, "defect_free": bool(res.candidates), "near": res.near,
                     "note": res.note, "seconds": res.seconds}))  # fmt: skip
        return
    print_table(
        "Six-bar path synthesis from the atlas",
        ["#", "max dist", "% of size", "chain", "defects"],
        [[i, f"{r['max_distance']:.3e}", f"{100 * r['max_distance_over_size']:.2e}", r["chain"],
          "; ".join(r["defects"]) or "-"] for i, r in enumerate(rows, 1)],
    )  # fmt: skip
    print(f"specs: {', '.join(files)}")
    if res.note:
        print(f"note: {res.note}")


def sixbar_spec(c, title: str) -> str:
    """A six-bar result as a machine file (``machdyn = 1``; docs/spec.md's linkage part).

    Drawn at the first target's pose (the points in the plane), driven by the crank
    round a turn from there.
    """
    lk = c.linkage

    def names(points) -> str:
        return ", ".join(f'"{p}"' for p in points)

    lines = ["machdyn = 1", f'title = "{title}: {c.chain}"', "", "[linkage.candidate]",
             f"ground = [{names(lk.ground_points)}]", 'drive = ["crank"]', 'report = ["P"]',
             "", "[linkage.candidate.points]"]  # fmt: skip
    for name, z in lk.points.items():
        lines.append(f"{name} = [{float(z.real)!r}, {float(z.imag)!r}]")
    lines += ["", "[linkage.candidate.links]"]
    for name, link in lk.links.items():
        if name != "ground":
            lines.append(f"{name} = {{ points = [{names(link.points)}] }}")
    start = float(np.degrees(c.design[2] + c.theta2[0]))
    lines += ["", "[linkage.candidate.motion]",
              f'crank = {{ sweep = ["{start!r} deg", "{start + 360!r} deg", 10] }}']  # fmt: skip
    return "\n".join(lines) + "\n"


def _candidate_json(c, size: float, file: str) -> dict:
    pl = c.linkage
    return {
        "r1": pl.lengths[0], "r2": pl.lengths[1], "r3": pl.lengths[2], "r4": pl.lengths[3],
        "p": pl.fourbar.coupler[0], "delta_deg": float(np.degrees(pl.fourbar.coupler[1])),
        "O2": pl.O2, "theta1_deg": float(np.degrees(pl.theta1)), "branch": pl.branch,
        "barker_class": c.barker_class, "max_distance": float(np.max(c.distance)),
        "max_distance_over_size": float(np.max(c.distance) / size),
        "distance": c.distance, "theta2_deg": np.degrees(c.theta2),
        "mu_min_deg": float(np.degrees(c.mu_min)), "defects": list(c.defects), "spec": file,
    }  # fmt: skip


def candidate_spec(c, title: str) -> str:
    """A path-synthesis result as a machine file (``machdyn = 1``; docs/spec.md's fourbar).

    The placement in the plane is the part's ``O2`` and ``theta1`` (global =
    O2 + e^{j theta1}·local); the worst target distance is in ``notes``.
    """
    from ..synthesis.placed import form_of

    pl = c.linkage
    r1, r2, r3, r4 = pl.lengths
    p, delta = pl.fourbar.coupler
    form = form_of(pl.branch)
    note = (
        f"path synthesis from an atlas; assembly sign of phi12 = {pl.branch:+d}; "
        f"worst target distance {np.max(c.distance):.6g}"
    )
    lines = [
        "machdyn = 1",
        f'title = "{title}"',
        "",
        "[fourbar.candidate]",
        f"r1 = {float(r1)!r}",
        f"r2 = {float(r2)!r}",
        f"r3 = {float(r3)!r}",
        f"r4 = {float(r4)!r}",
        f'coupler = {{ p = {float(p)!r}, delta = "{float(np.degrees(delta))!r} deg" }}',
        f"O2 = [{float(pl.O2.real)!r}, {float(pl.O2.imag)!r}]",
        f'theta1 = "{float(np.degrees(pl.theta1))!r} deg"',
    ]
    if c.barker_class in ("GRCR", "GRRC"):
        lines.append(f"branch = {pl.branch}")
    else:
        lines.append(f"form = {form}")
    lines.append(f'notes = "{note}"')
    return "\n".join(lines) + "\n"
