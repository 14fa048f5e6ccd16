"""``machdyn balance``: static and two-plane balance of rotors, and the wheel balancer.

Masses are given as ``m,R,angle_deg[,z]`` and bearing forces as
``F,phase_deg,z`` (angles from the rotor's zero reference line). Only parsing and
printing happen here; the physics is :mod:`machdyn.balancing`.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated, Any

import typer

from ..balancing import TwoPlaneBalance, bearing_balance, static_balance, two_plane
from ..errors import InputError
from ..rotor import Rotor
from ._common import dumps, print_table

__all__ = ["balance_app", "parse_numbers"]

balance_app = typer.Typer(
    help="Balance rotating masses (single plane, two planes, balancing machine).",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)


def parse_numbers(field: str, text: str, count: int, names: str) -> list[float]:
    """Parse ``count`` comma-separated numbers, naming the expected fields on error.

    Examples
    --------
    >>> parse_numbers("--mass", "2, 0.5, 30", 3, "m,R,angle_deg")
    [2.0, 0.5, 30.0]
    """
    parts = [p.strip() for p in text.split(",")]
    try:
        values = [float(p) for p in parts]
    except ValueError:
        raise InputError(field, f"expected {names} (numbers), got {text!r}") from None
    if len(values) != count or not all(math.isfinite(v) for v in values):
        raise InputError(field, f"expected {count} finite numbers {names}, got {text!r}")
    return values


def _check_signs(field: str, text: str, values: list[float], names: str) -> None:
    """A mass must be > 0, a radius or force magnitude >= 0 (the angle gives direction)."""
    checks = {"m": (lambda v: v > 0.0, "> 0"), "R": (lambda v: v >= 0.0, ">= 0")}
    checks["F"] = checks["R"]
    for name, value in zip(names.split(","), values, strict=True):
        if name in checks and not checks[name][0](value):
            raise InputError(
                field,
                f"{name} must be {checks[name][1]} in {names} (give the direction by the "
                f"angle, not by a sign), got {text!r}",
            )


def _radius(field: str, value: float | None) -> float | None:
    if value is not None and not (math.isfinite(value) and value > 0.0):
        raise InputError(field, f"must be a positive radius, got {value}")
    return value


SpecOpt = Annotated[
    Path | None,
    typer.Option(
        "--spec", help="A machine file (docs/spec.md): balance its rotor part, in the file's units."
    ),
]
PartOpt = Annotated[
    str | None, typer.Option("--part", help="With --spec: the part, when the file has several.")
]
CsvOpt = Annotated[
    bool, typer.Option("--csv", help="With --spec: print the corrections as CSV (with units).")
]


def _from_spec(
    spec: Path | None,
    part: str | None,
    csv: bool,
    given: dict[str, bool],
    as_json: bool,
    two_plane: bool,
) -> bool:
    """Run ``--spec FILE``'s rotor part as ``machdyn run`` does; False without --spec."""
    from .run import run_spec_part

    def fits(p: Any) -> str | None:
        if (p.model.planes is not None) == two_plane:
            return None
        has, other = ("no correction planes", "static") if two_plane else ("planes", "rotor")
        return f"has {has}: use `machdyn balance {other} --spec`"

    return run_spec_part(spec, ("rotor",), part, given=given, json=as_json, csv_out=csv, fits=fits)


def _phasor(magnitude: float, angle_deg: float) -> complex:
    return magnitude * complex(math.cos(math.radians(angle_deg)), math.sin(math.radians(angle_deg)))


def _report(
    result: TwoPlaneBalance,
    radius_a: float | None,
    radius_b: float | None,
    as_json: bool,
    bearing_loads: dict | None = None,
):
    rows: dict = {
        "plane": ["A", "B"],
        "z": [result.plane_a, result.plane_b],
        "mR": [abs(result.mR_a), abs(result.mR_b)],
        "angle_deg": [result.angle_a_deg, result.angle_b_deg],
    }
    if radius_a is not None:
        rows["mass"] = list(result.masses(radius_a, radius_b))
    if as_json:  # one document: the bearing loads (if asked) under their own key
        print(dumps(rows if bearing_loads is None else {**rows, "bearing_loads": bearing_loads}))
        return
    columns = list(rows)
    print_table("Correction masses", columns, [list(r) for r in zip(*rows.values(), strict=True)])


@balance_app.command("static")
def static(
    mass: Annotated[
        list[str] | None,
        typer.Option("--mass", help="A rotating mass as m,R,angle_deg (repeat)."),
    ] = None,
    radius: Annotated[
        float | None, typer.Option("--radius", help="Radius of the balance mass.")
    ] = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON.")] = False,
    spec: SpecOpt = None,
    part: PartOpt = None,
    csv: CsvOpt = False,
) -> None:
    """Single-plane balance: m_b R_b = -sum(m_i R_i).

    With ``--spec FILE`` the masses are the file's ``rotor`` part (one without
    correction planes), reported as ``machdyn run FILE --part NAME`` does.
    """
    given = {"--mass": bool(mass), "--radius": radius is not None}
    if _from_spec(spec, part, csv, given, as_json, two_plane=False):
        return
    if not mass:
        raise InputError("--mass", "missing: give --mass m,R,angle_deg (repeat), or --spec FILE")
    unbalance = []
    for text in mass:
        m, r, angle = parse_numbers("--mass", text, 3, "m,R,angle_deg")
        _check_signs("--mass", text, [m, r, angle], "m,R,angle_deg")
        unbalance.append(m * _phasor(r, angle))
    radius = _radius("--radius", radius)
    fix = static_balance(unbalance)
    rows = {"mR": abs(fix.mR), "angle_deg": fix.angle_deg}
    if radius is not None:
        rows["mass"] = fix.mass(radius)
    if as_json:
        print(dumps(rows))
        return
    print_table("Balance mass", list(rows), [list(rows.values())])


@balance_app.command("rotor")
def rotor(
    mass: Annotated[
        list[str] | None,
        typer.Option("--mass", help="A rotating mass as m,R,angle_deg,z (repeat)."),
    ] = None,
    plane_a: Annotated[
        float | None, typer.Option("--plane-a", help="Axial position of plane A.")
    ] = None,
    plane_b: Annotated[
        float | None, typer.Option("--plane-b", help="Axial position of plane B.")
    ] = None,
    radius_a: Annotated[
        float | None, typer.Option("--radius-a", help="Radius of the mass in plane A.")
    ] = None,
    radius_b: Annotated[
        float | None, typer.Option("--radius-b", help="Radius in plane B (default: A's).")
    ] = None,
    bearings: Annotated[
        str | None,
        typer.Option("--bearings", help="ZA,ZB: axial positions of two bearings (with --omega)."),
    ] = None,
    omega: Annotated[
        float | None, typer.Option("--omega", help="Speed, rad/s, for the bearing loads.")
    ] = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON.")] = False,
    spec: SpecOpt = None,
    part: PartOpt = None,
    csv: CsvOpt = False,
) -> None:
    """Two-plane dynamic balance of masses at axial positions z (and bearing loads).

    With ``--spec FILE`` the masses and planes are the file's ``rotor`` part,
    reported as ``machdyn run FILE --part NAME`` does.
    """
    given = {"--mass": bool(mass), "--plane-a": plane_a is not None}
    given |= {"--plane-b": plane_b is not None, "--radius-a": radius_a is not None}
    given |= {"--radius-b": radius_b is not None, "--bearings": bearings is not None}
    given["--omega"] = omega is not None
    if _from_spec(spec, part, csv, given, as_json, two_plane=True):
        return
    if not mass:
        raise InputError("--mass", "missing: give --mass m,R,angle_deg,z (repeat), or --spec FILE")
    for option, value in (("--plane-a", plane_a), ("--plane-b", plane_b)):
        if value is None:
            raise InputError(option, "missing: give --plane-a and --plane-b, or --spec FILE")
    assert plane_a is not None and plane_b is not None
    unbalance, z, masses, radii = [], [], [], []
    for text in mass:
        m, r, angle, zi = parse_numbers("--mass", text, 4, "m,R,angle_deg,z")
        _check_signs("--mass", text, [m, r, angle, zi], "m,R,angle_deg,z")
        unbalance.append(m * _phasor(r, angle))
        z.append(zi)
        masses.append(m)
        radii.append(_phasor(r, angle))
    radius_a, radius_b = _radius("--radius-a", radius_a), _radius("--radius-b", radius_b)
    if (bearings is None) != (omega is None):
        raise InputError("--bearings" if bearings is None else "--omega", "give both or neither")
    result = two_plane(unbalance, z, plane_a, plane_b)
    if bearings is None or omega is None:
        _report(result, radius_a, radius_b, as_json)
        return
    z_a, z_b = parse_numbers("--bearings", bearings, 2, "ZA,ZB")
    rotor_ = Rotor.from_masses(masses, radii, z)
    try:  # check the bearings before printing anything
        rotor_.bearing_reactions(omega, z_a, z_b)
    except InputError as exc:
        field = "--bearings" if exc.field.startswith("z_") else "--omega"
        raise InputError(field, exc.message) from None
    loads = _bearing_loads(rotor_, result, z_a, z_b, omega)
    _report(result, radius_a, radius_b, as_json, loads if as_json else None)
    if not as_json:
        print(f"Bearing loads at omega = {omega:g} rad/s: the force of the rotor on each bearing")
        print_table(
            "(phase from the rotor's zero line)",
            ["", "bearing", "|F|", "phase_deg"],
            loads["loads"],
        )


def _bearing_loads(
    rotor: Rotor, fix: TwoPlaneBalance, z_a: float, z_b: float, omega: float
) -> dict:
    """Bearing loads of the rotor at omega (rotor angle 0), before and after the correction."""
    corrected = rotor.with_masses(
        [abs(fix.mR_a), abs(fix.mR_b)],
        [fix.mR_a / max(abs(fix.mR_a), 1e-300), fix.mR_b / max(abs(fix.mR_b), 1e-300)],
        [fix.plane_a, fix.plane_b],
    )
    rows: list[list] = []
    scale = 0.0
    for label, body in (("before", rotor), ("after", corrected)):
        r = body.bearing_reactions(omega, z_a, z_b)
        for name, load in (("A", complex(r.load_a)), ("B", complex(r.load_b))):
            scale = max(scale, abs(load))
            if abs(load) <= 1e-12 * scale:  # rounding left by the correction
                load = 0j
            phase = math.degrees(math.atan2(load.imag, load.real)) % 360.0
            rows.append([label, name, abs(load), phase])
    return {"omega": omega, "bearings": [z_a, z_b], "loads": rows}


@balance_app.command("bearings")
def bearings(
    force: Annotated[
        list[str],
        typer.Option("--force", help="Peak bearing force as F,phase_deg,z (one per bearing)."),
    ],
    omega: Annotated[float, typer.Option("--omega", help="Test speed, rad/s (rpm with --rpm).")],
    plane_a: Annotated[float, typer.Option("--plane-a", help="Axial position of plane A.")],
    plane_b: Annotated[float, typer.Option("--plane-b", help="Axial position of plane B.")],
    radius: Annotated[
        float | None, typer.Option("--radius", help="Rim radius where the masses go.")
    ] = None,
    rpm: Annotated[bool, typer.Option("--rpm", help="--omega is in rev/min.")] = False,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON.")] = False,
) -> None:
    """Wheel balancer: bearing forces measured at omega -> masses in two planes."""
    if len(force) != 2:
        raise InputError(
            "--force",
            f"give exactly two (one per bearing of the balancing machine), got {len(force)}",
        )
    radius = _radius("--radius", radius)
    forces, z = [], []
    for text in force:
        magnitude, phase, zi = parse_numbers("--force", text, 3, "F,phase_deg,z")
        _check_signs("--force", text, [magnitude, phase, zi], "F,phase_deg,z")
        forces.append(_phasor(magnitude, phase))
        z.append(zi)
    speed = omega * 2 * math.pi / 60 if rpm else omega
    _report(bearing_balance(forces, z, speed, plane_a, plane_b), radius, None, as_json)
