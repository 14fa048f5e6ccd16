"""``machdyn fourbar`` and ``machdyn demo``: classify and analyse a four-bar.

Angles are printed in degrees (labelled); lengths in the user's unit.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any

import numpy as np
import typer

from ..errors import InputError
from ..fourbar import FourBar, FourBarMotion
from ._common import dumps, parse_range_deg, print_table
from .app import app

#: The built-in demonstration linkage: the notes' HW 6 crank-rocker with a coupler point.
DEMO = {"r1": 8.0, "r2": 4.0, "r3": 7.0, "r4": 6.0, "coupler": "5:30"}


def _parse_coupler(text: str | None) -> tuple[float, float] | None:
    if text is None:
        return None
    try:
        p, delta = (float(x) for x in text.split(":"))
    except ValueError:
        raise InputError("--coupler", f"expected P:DELTA_DEG (e.g. 5:30), got {text!r}") from None
    return p, np.radians(delta)


def analyse(
    r1: float,
    r2: float,
    r3: float,
    r4: float,
    theta2_deg: np.ndarray,
    form: int,
    omega2: float,
    alpha2: float,
    coupler: tuple[float, float] | None,
) -> dict[str, Any]:
    """Everything the command prints, as plain data (also the ``--json`` payload)."""
    fb = FourBar(r1, r2, r3, r4, coupler=coupler)
    c = fb.classification
    rng = fb.input_range(form)
    motion = fb.solve(np.radians(theta2_deg), omega2=omega2, alpha2=alpha2, form=form)
    extrema = fb.extrema(form)
    mu = fb.transmission_angle(form)
    payload: dict[str, Any] = {
        "lengths": {"r1": r1, "r2": r2, "r3": r3, "r4": r4},
        "class": {
            "code": c.code,
            "number": c.number,
            "name": c.name,
            "condition": c.condition,
            "grashof": c.is_grashof,
            "cranks": list(c.cranks),
            "form_rule": fb.form_rule,
        },
        "form": form,
        "input_range_deg": None if rng.full_turn else [np.degrees(rng.lo), np.degrees(rng.hi)],
        "toggles": [
            {
                "theta2_deg": np.degrees(t.theta2),
                "links": list(t.links),
                "kind": t.kind,
                "branch": t.branch,
            }
            for t in fb.toggles()
        ],
        "extrema_deg": {
            name: None
            if e.full_turn
            else {
                "min": np.degrees(e.min),
                "max": np.degrees(e.max),
                "theta2_at_min": np.degrees(e.theta2_at_min),
                "theta2_at_max": np.degrees(e.theta2_at_max),
            }
            for name, e in extrema.items()
        },
        "min_transmission_angle_deg": {
            "mu": np.degrees(mu.min),
            "theta2": np.degrees(mu.theta2_at_min),
        },
        "omega2": omega2,
        "alpha2": alpha2,
        "kinematics": _rows(motion),
    }
    return payload


def _rows(m: FourBarMotion) -> list[dict[str, Any]]:
    rows = []
    for k in range(len(m)):
        row: dict[str, Any] = {
            "theta2_deg": np.degrees(m.theta2[k]),
            "theta3_deg": np.degrees(m.theta3[k]),
            "theta4_deg": np.degrees(m.theta4[k]),
            "omega3": m.omega3[k],
            "omega4": m.omega4[k],
            "alpha3": m.alpha3[k],
            "alpha4": m.alpha4[k],
            "mu_deg": np.degrees(m.mu[k]),
            "ok": bool(m.ok[k]),
            "reason": m.reason[k],
        }
        if m.coupler is not None:
            row["P"] = complex(m.coupler[k])
            row["AP"] = complex(m.coupler_acceleration[k])
        rows.append(row)
    return rows


def _print(payload: dict[str, Any]) -> None:
    c, L = payload["class"], payload["lengths"]
    print(f"Four-bar R1={L['r1']:g} R2={L['r2']:g} R3={L['r3']:g} R4={L['r4']:g}")
    cranks = ", ".join(map(str, c["cranks"])) or "none"
    print(f"  class  {c['code']} (Barker #{c['number']}: {c['name']}), {c['condition']}")
    print(f"  full turns relative to the ground: links {cranks}")
    rng = payload["input_range_deg"]
    form = payload["form"]
    sign = "phi34 = theta2" if c["form_rule"] == "phi34" else "phi12"
    print(f"  form   {form} ({sign} {'> 0' if form == 1 else '< 0'})")
    if rng is None:
        print("  input  link 2 turns fully")
    else:
        print(f"  input  theta2 from {rng[0]:.4f} to {rng[1]:.4f} deg (rocker)")
    for t in payload["toggles"]:
        print(
            f"  toggle theta2 = {t['theta2_deg']:9.4f} deg: links {t['links'][0]} and "
            f"{t['links'][1]} {t['kind']}" + (f" (branch {t['branch']:+d})" if t["branch"] else "")
        )
    if "placed" in payload:
        o2, theta1 = payload["placed"]["O2"], payload["placed"]["theta1_deg"]
        print(f"  placed O2 = ({o2.real:g}, {o2.imag:g}), theta1 = {theta1:g} deg: P and AP in "
              "the plane's frame, angles from O2 -> O4")  # fmt: skip
    mu = payload["min_transmission_angle_deg"]
    print(f"  min transmission angle mu = {mu['mu']:.4f} deg at theta2 = {mu['theta2']:.4f} deg")
    rows = []
    for name, e in payload["extrema_deg"].items():
        if e is None:
            rows.append([name, "full turn", "", "", ""])
        else:
            rows.append([name, e["min"], e["theta2_at_min"], e["max"], e["theta2_at_max"]])
    print()
    print_table(
        f"Limits over form {form} (degrees)",
        ["angle", "min", "at theta2", "max", "at theta2"],
        rows,
    )
    print()
    kin = payload["kinematics"]
    has_p = bool(kin) and "P" in kin[0]
    cols = [
        "theta2 deg",
        "theta3 deg",
        "theta4 deg",
        "omega3",
        "omega4",
        "alpha3",
        "alpha4",
        "mu deg",
    ]
    if has_p:
        cols += ["Px", "Py"]
    table = []
    for r in kin:
        if not r["ok"] and np.isnan(r["theta3_deg"]):
            table.append([r["theta2_deg"], *["-"] * (len(cols) - 1)])
            continue
        row = [
            r["theta2_deg"],
            r["theta3_deg"],
            r["theta4_deg"],
            r["omega3"],
            r["omega4"],
            r["alpha3"],
            r["alpha4"],
            r["mu_deg"],
        ]
        if has_p:
            row += [r["P"].real, r["P"].imag]
        table.append(row)
    title = (
        f"Kinematics, omega2 = {payload['omega2']:g} rad/s, "
        f"alpha2 = {payload['alpha2']:g} rad/s^2 (omega in rad/s, alpha in rad/s^2)"
    )
    print_table(title, cols, table)
    flagged = [r for r in kin if not r["ok"]]
    for r in flagged:
        print(f"  theta2 = {r['theta2_deg']:g} deg: {r['reason']}")


def inversions_payload(r1: float, r2: float, r3: float, r4: float) -> dict[str, Any]:
    """The inversion table as plain data (the ``--inversions --json`` payload)."""
    table = FourBar(r1, r2, r3, r4).inversions()
    return {
        "lengths": {"r1": r1, "r2": r2, "r3": r3, "r4": r4},
        "inversions": [
            {
                "grounded": inv.grounded,
                "links": list(inv.links),
                "lengths": list(inv.lengths),
                "class": {
                    "code": inv.code,
                    "number": inv.classification.number,
                    "name": inv.classification.name,
                },
                "form_rule": inv.form_rule,
                "ranges_deg": {
                    name: {which: r.degrees() for which, r in ranges.items()}
                    for name, ranges in inv.ranges.items()
                },
                "text": {
                    name: {which: r.text() for which, r in ranges.items()}
                    for name, ranges in inv.ranges.items()
                },
            }
            for inv in table
        ],
    }


def _print_inversions(payload: dict[str, Any]) -> None:
    L = payload["lengths"]
    print(f"Inversions of the chain R1={L['r1']:g} R2={L['r2']:g} R3={L['r3']:g} R4={L['r4']:g}")
    print("(link k grounded: the links are renumbered k, k+1, ... around the loop)")
    for inv in payload["inversions"]:
        c = inv["class"]
        lengths = ", ".join(f"{x:g}" for x in inv["lengths"])
        rule = "phi34" if inv["form_rule"] == "phi34" else "phi12"
        print()
        print(
            f"Link {inv['grounded']} grounded: {{{lengths}}} {c['code']} "
            f"(Barker #{c['number']}: {c['name']}); form 1: {rule} > 0, form 2: {rule} < 0"
        )
        print_table(
            "ranges in degrees",
            ["angle", "form 1", "form 2", "common to both"],
            [[name, t["form1"], t["form2"], t["common"]] for name, t in inv["text"].items()],
        )


def _from_spec(spec: Path, part: str | None) -> dict[str, Any]:
    """Lengths, coupler point, form and motion of a machine file's four-bar part."""
    from ..spec import load_machine
    from ..spec._fourbar import placement

    machine = load_machine(spec)
    names = [p.name for p in machine.parts.values() if p.kind == "fourbar"]
    if part is None and len(names) != 1:
        listed = ", ".join(names) or "none"
        raise InputError("--spec", f"the file has {len(names)} four-bar parts ({listed}): --part")
    name = part if part is not None else names[0]
    if name not in names:
        raise InputError(
            "--part", f"{name!r} is not a four-bar part; four-bars: {', '.join(names)}"
        )
    chosen = machine.parts[name]
    fb, motion = chosen.model, chosen.values.get("motion", {})
    out: dict[str, Any] = {
        "lengths": fb.lengths,
        "coupler": fb.coupler,
        "form": chosen.values.get("form"),
        "unit": None if machine.units.is_unit_free else machine.units.length,
    }
    placed = placement(chosen.values)
    if placed is not None:  # P in the plane's frame
        out["placed"] = placed
    if "theta2" in motion:
        out["theta2"] = np.degrees(motion["theta2"].values)
    for key in ("omega2", "alpha2"):  # rad per the file's time unit
        if key in motion:
            out[key] = motion[key]
    return out


def _place(payload: dict[str, Any], o2: complex, theta1: float) -> None:
    """A placed four-bar (a file's ``O2``, ``theta1``): its coupler point in the plane's frame.

    The angles stay measured from O2 → O4, as in ``machdyn run`` (docs/spec.md).
    """
    turn = complex(np.exp(1j * theta1))
    payload["placed"] = {"O2": o2, "theta1_deg": float(np.degrees(theta1))}
    for row in payload["kinematics"]:
        if "P" in row:
            row["P"] = o2 + turn * row["P"]
            row["AP"] = turn * row["AP"]


def _write_csv(payload: dict[str, Any], path: Path, unit: str | None) -> None:
    """The kinematics table, every column with its unit in the header (csv module)."""
    import csv

    names = ["theta2_deg", "theta3_deg", "theta4_deg", "omega3", "omega4", "alpha3", "alpha4"]
    header = ["theta2 [deg]", "theta3 [deg]", "theta4 [deg]", "omega3 [rad/s]", "omega4 [rad/s]"]
    header += ["alpha3 [rad/s^2]", "alpha4 [rad/s^2]", "mu [deg]"]
    names.append("mu_deg")
    rows = payload["kinematics"]
    has_p = bool(rows) and "P" in rows[0]
    if has_p:
        length, accel = (f" [{unit}]", f" [{unit}/s^2]") if unit else ("", "")
        header += [f"P_x{length}", f"P_y{length}", f"AP_x{accel}", f"AP_y{accel}"]
    header += ["ok", "reason"]

    def cell(value: Any) -> str:
        value = float(value)
        return repr(value) if np.isfinite(value) else ""

    with open(path, "w", newline="", encoding="utf-8") as out:
        writer = csv.writer(out)
        writer.writerow(header)
        for r in rows:
            line = [cell(r[k]) for k in names]
            if has_p:
                line += [cell(r["P"].real), cell(r["P"].imag)]
                line += [cell(r["AP"].real), cell(r["AP"].imag)]
            writer.writerow([*line, str(bool(r["ok"])).lower(), r["reason"]])


@app.command()
def fourbar(
    r1: Annotated[float | None, typer.Argument(help="Ground link length O2O4.")] = None,
    r2: Annotated[float | None, typer.Argument(help="Input link length O2A.")] = None,
    r3: Annotated[float | None, typer.Argument(help="Coupler length AB.")] = None,
    r4: Annotated[float | None, typer.Argument(help="Output link length O4B.")] = None,
    theta2: Annotated[
        str | None, typer.Option(help="Input angles in degrees: START:STOP:STEP or one angle.")
    ] = None,
    form: Annotated[int | None, typer.Option(help="Form 1 or 2, as in the notes.")] = None,
    omega2: Annotated[float | None, typer.Option(help="Input angular velocity, rad/s.")] = None,
    rpm: Annotated[
        float | None, typer.Option("--rpm", help="Input speed in rev/min (instead of --omega2).")
    ] = None,
    alpha2: Annotated[
        float | None, typer.Option(help="Input angular acceleration, rad/s^2.")
    ] = None,
    coupler: Annotated[
        str | None, typer.Option(help="Coupler point P:DELTA_DEG (distance from A, angle from AB).")
    ] = None,
    spec: Annotated[
        Path | None,
        typer.Option("--spec", help="A machine file: its four-bar part (options override it)."),
    ] = None,
    part: Annotated[
        str | None, typer.Option("--part", help="The four-bar part, if the file has several.")
    ] = None,
    csv_out: Annotated[
        Path | None, typer.Option("--csv", help="Also write the kinematics table to this CSV file.")
    ] = None,
    json: Annotated[bool, typer.Option("--json", help="Print machine-readable JSON.")] = False,
    inversions: Annotated[
        bool,
        typer.Option(
            "--inversions",
            help="Print the Barker table of the four inversions (each link grounded) instead.",
        ),
    ] = False,
) -> None:
    """Classify a four-bar and print its limits and a kinematics table."""
    given = [r for r in (r1, r2, r3, r4) if r is not None]
    file: dict[str, Any] = {}
    if spec is not None:
        if given:
            raise InputError("--spec", "give the four lengths or --spec FILE, not both")
        file = _from_spec(spec, part)
    elif len(given) != 4:
        raise InputError("R1 R2 R3 R4", f"give the four lengths (or --spec FILE); got {len(given)}")
    elif part is not None:
        raise InputError("--part", "--part picks a part of a --spec file")
    if inversions:
        table = inversions_payload(*file.get("lengths", given))
        if json:
            print(dumps(table))
        else:
            _print_inversions(table)
        return
    if omega2 is not None and rpm is not None:
        raise InputError("--rpm", "give --omega2 (rad/s) or --rpm, not both")
    form = form if form is not None else (file.get("form") or 1)
    if form not in (1, 2):
        raise InputError("--form", f"must be 1 or 2, got {form}")
    if rpm is not None:
        if not np.isfinite(rpm):
            raise InputError("--rpm", f"must be finite, got {rpm}")
        omega2 = rpm * 2.0 * np.pi / 60.0
    omega = omega2 if omega2 is not None else file.get("omega2", 1.0)
    alpha = alpha2 if alpha2 is not None else file.get("alpha2", 0.0)
    if theta2 is not None:
        grid = parse_range_deg(theta2)
    else:
        grid = file.get("theta2", parse_range_deg("0:360:30"))
    lengths = file.get("lengths", given)
    point = _parse_coupler(coupler) if coupler is not None else file.get("coupler")
    payload = analyse(*lengths, grid, form, omega, alpha, point)
    if "placed" in file:
        _place(payload, *file["placed"])
    if csv_out is not None:
        _write_csv(payload, csv_out, file.get("unit"))
    if json:
        print(dumps(payload))
    else:
        _print(payload)
        if csv_out is not None:
            print(f"\nwrote {csv_out}")


@app.command()
def demo(
    json: Annotated[bool, typer.Option("--json", help="Print machine-readable JSON.")] = False,
) -> None:
    """Analyse the notes' HW 6 crank-rocker (8, 4, 7, 6) with a coupler point."""
    payload = analyse(
        DEMO["r1"],
        DEMO["r2"],
        DEMO["r3"],
        DEMO["r4"],
        parse_range_deg("0:360:30"),
        1,
        10.0,
        0.0,
        _parse_coupler(DEMO["coupler"]),
    )
    if json:
        print(dumps(payload))
        return
    print("machdyn demo: the notes' HW 6 four-bar, driven at omega2 = 10 rad/s\n")
    _print(payload)
    print("\nTry: machdyn fourbar 6 9 3 8 --theta2 40:90:10   (a GRCR, link 2 rocks)")
