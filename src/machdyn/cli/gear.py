"""``machdyn gear ...``: spur-gear pairs, minimum teeth, profiles and trains.

Only parsing and presenting live here; every number comes from
:mod:`machdyn.gears`. Angles are read and printed in degrees (labelled).
Register with ``app.add_typer(gear_app, name="gear")``.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated, Any

import typer

from ..errors import InputError
from ._common import dumps, print_table

__all__ = ["gear_app"]

gear_app = typer.Typer(
    name="gear",
    help="Involute spur gears: pair geometry, contact ratio, interference, profiles, trains.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)

JsonOpt = Annotated[bool, typer.Option("--json", help="Print JSON instead of a table.")]
ModuleOpt = Annotated[
    float | None, typer.Option("--module", "-m", help="Module m = d/N in mm (lengths in mm).")
]
PitchOpt = Annotated[
    float | None,
    typer.Option("--pd", help="Diametral pitch P_d = N/d in teeth per inch (lengths in in)."),
]
PhiOpt = Annotated[float, typer.Option("--phi", help="Pressure angle in degrees.")]
SystemOpt = Annotated[str, typer.Option("--system", help="Tooth system: full_depth or stub.")]


def _gear(
    teeth: int,
    module: float | None,
    pd: float | None,
    phi_deg: float,
    system: str,
    shift: float = 0.0,
    internal: bool = False,
    thinning: float = 0.0,
) -> Any:
    from ..gears import Gear

    if module is None and pd is None:
        raise InputError("--module", "give the size as --module M or --pd P_d")
    return Gear(
        teeth,
        module=module,
        diametral_pitch=pd,
        pressure_angle=math.radians(phi_deg),
        system=system,
        profile_shift=shift,
        internal=internal,
        thickness_reduction=thinning,
    )


def _pair(
    np_: int,
    ng: int,
    module: float | None,
    pd: float | None,
    phi: float,
    system: str,
    xp: float,
    xg: float,
    internal: bool,
    center_distance: float | None,
    thin_p: float,
    thin_g: float,
) -> Any:
    from ..gears import GearPair

    pinion = _gear(np_, module, pd, phi, system, xp, False, thin_p)
    gear = _gear(ng, module, pd, phi, system, xg, internal, thin_g)
    return GearPair(pinion, gear, center_distance)


PinionOpt = Annotated[int, typer.Option("--np", help="Pinion teeth N_p.")]
GearOpt = Annotated[int, typer.Option("--ng", help="Gear teeth N_g.")]
XpOpt = Annotated[float, typer.Option("--xp", help="Pinion profile-shift coefficient.")]
XgOpt = Annotated[float, typer.Option("--xg", help="Gear profile-shift coefficient.")]
InternalOpt = Annotated[bool, typer.Option("--internal", help="The gear is an internal (ring).")]
CenterOpt = Annotated[
    float | None,
    typer.Option(
        "--center-distance", "-C", help="Operating centre distance (default: tight mesh)."
    ),
]
ThinPOpt = Annotated[float, typer.Option("--thin-p", help="Pinion tooth-thickness reduction.")]
ThinGOpt = Annotated[float, typer.Option("--thin-g", help="Gear tooth-thickness reduction.")]


@gear_app.command("pair")
def pair_cmd(
    np_: PinionOpt,
    ng: GearOpt,
    module: ModuleOpt = None,
    pd: PitchOpt = None,
    phi: PhiOpt = 20.0,
    system: SystemOpt = "full_depth",
    xp: XpOpt = 0.0,
    xg: XgOpt = 0.0,
    internal: InternalOpt = False,
    center_distance: CenterOpt = None,
    thin_p: ThinPOpt = 0.0,
    thin_g: ThinGOpt = 0.0,
    json: JsonOpt = False,
) -> None:
    """Geometry, contact ratio and interference check of a pinion and gear."""
    from ..gears import undercut

    pair = _pair(
        np_, ng, module, pd, phi, system, xp, xg, internal, center_distance, thin_p, thin_g
    )
    summary = pair.summary()
    summary["length_unit"] = "in" if pd is not None else "mm"
    p, g = pair.pinion, pair.gear
    summary["undercut_pinion"] = bool(
        undercut(p.teeth, p.pressure_angle, p.profile_shift, p.addendum_constant)
    )
    summary["undercut_gear"] = (
        False
        if g.internal
        else bool(undercut(g.teeth, g.pressure_angle, g.profile_shift, g.addendum_constant))
    )
    if json:
        print(dumps(summary))
        return
    keys = [k for k in summary["pinion"] if k not in ("teeth", "internal")]
    rows = [[k, summary["pinion"][k], summary["gear"][k]] for k in keys]
    unit = summary["length_unit"]
    title = f"Gears: N_p = {p.teeth}, N_g = {g.teeth} (lengths in {unit}, angles in degrees)"
    print_table(title, ["", "pinion", "gear"], rows)
    mesh_keys = [
        "standard_center_distance",
        "center_distance",
        "operating_pressure_angle_deg",
        "velocity_ratio",
        "length_of_action",
        "base_pitch",
        "contact_ratio",
        "contact_ratio_rating",
        "angle_of_approach_pinion_deg",
        "angle_of_recess_pinion_deg",
        "backlash",
        "interference_gear_tip",
        "interference_pinion_tip",
        "undercut_pinion",
        "undercut_gear",
    ]
    print_table("Mesh", ["", "value"], [[k, _show(summary[k])] for k in mesh_keys])


def _show(value: Any) -> Any:
    return ("yes" if value else "no") if isinstance(value, bool) else value


@gear_app.command("min-teeth")
def min_teeth_cmd(
    phi: Annotated[
        list[float] | None, typer.Option("--phi", help="Pressure angle(s) in degrees.")
    ] = None,
    k: Annotated[float, typer.Option("--k", help="Addendum constant (1 full, 0.8 stub).")] = 1.0,
    gear_teeth: Annotated[
        int | None, typer.Option("--ng", help="Also the minimum pinion for this gear.")
    ] = None,
    json: JsonOpt = False,
) -> None:
    """Minimum pinion teeth free of interference: against a rack, equal gears, a gear."""
    from ..gears import min_pinion_teeth, min_teeth_equal_gears, min_teeth_rack

    angles = phi or [14.5, 20.0, 25.0]
    rows = []
    for a in angles:
        rad = math.radians(a)
        row = {
            "pressure_angle_deg": a,
            "k": k,
            "rack": min_teeth_rack(rad, k),
            "equal_gears": min_teeth_equal_gears(rad, k),
        }
        if gear_teeth is not None:
            row[f"gear_{gear_teeth}"] = min_pinion_teeth(gear_teeth, rad, k)
        rows.append(row)
    if json:
        print(dumps(rows))
        return
    columns = list(rows[0])
    print_table("Minimum pinion teeth", columns, [[r[c] for c in columns] for r in rows])


@gear_app.command("profile")
def profile_cmd(
    teeth: Annotated[int, typer.Option("--teeth", "-N", help="Number of teeth.")],
    output: Annotated[Path, typer.Option("--output", "-o", help="File: .svg, .dxf, .csv, .png")],
    module: ModuleOpt = None,
    pd: PitchOpt = None,
    phi: PhiOpt = 20.0,
    system: SystemOpt = "full_depth",
    shift: Annotated[float, typer.Option("--shift", help="Profile-shift coefficient.")] = 0.0,
    internal: InternalOpt = False,
    points: Annotated[int, typer.Option("--points", help="Points per flank.")] = 60,
) -> None:
    """Write a gear's outline (involute flanks, tip, trochoid fillet) to a file."""
    from ..gears import gear_outline

    out = gear_outline(_gear(teeth, module, pd, phi, system, shift, internal), points)
    suffix = output.suffix.lower()
    if suffix == ".svg":
        out.to_svg(output)
    elif suffix == ".dxf":
        out.to_dxf(output)
    elif suffix == ".csv":
        out.to_csv(output)
    elif suffix == ".png":
        import matplotlib.pyplot as plt

        ax = out.plot()
        ax.figure.savefig(output, dpi=150)
        plt.close(ax.figure)
    else:
        raise InputError("--output", f"use a .svg, .dxf, .csv or .png file, got {output.name!r}")
    note = " (undercut)" if out.undercut else ""
    print(f"wrote {output} ({out.x.size} points, fillet: {out.fillet}){note}")


@gear_app.command("plot")
def plot_cmd(
    np_: PinionOpt,
    ng: GearOpt,
    output: Annotated[Path, typer.Option("--output", "-o", help="Image file (.png, .svg).")],
    module: ModuleOpt = None,
    pd: PitchOpt = None,
    phi: PhiOpt = 20.0,
    system: SystemOpt = "full_depth",
    xp: XpOpt = 0.0,
    xg: XgOpt = 0.0,
    internal: InternalOpt = False,
    center_distance: CenterOpt = None,
    angle: Annotated[float, typer.Option("--angle", help="Pinion angle in degrees.")] = 0.0,
) -> None:
    """Draw a meshing pair with its pitch and base circles and path of contact."""
    import matplotlib.pyplot as plt

    from ..gears import plot_mesh

    pair = _pair(np_, ng, module, pd, phi, system, xp, xg, internal, center_distance, 0.0, 0.0)
    ax = plot_mesh(pair, math.radians(angle))
    ax.figure.savefig(output, dpi=150)
    plt.close(ax.figure)
    print(f"wrote {output}")


@gear_app.command("train")
def train_cmd(
    stages: Annotated[
        str,
        typer.Argument(
            help="Stages DRIVER:DRIVEN[:KIND], comma-separated; KIND is external (default),"
            " internal, open_belt, crossed_belt or chain. Example: 14:54,14:56"
        ),
    ],
    json: JsonOpt = False,
) -> None:
    """Train value (signed ω_out/ω_in) of a simple or compound train."""
    from ..gears import train_value

    parsed: list[tuple[Any, ...]] = []
    for i, text in enumerate(stages.split(",")):
        parts = text.strip().split(":")
        try:
            nums = (float(parts[0]), float(parts[1]))
        except (ValueError, IndexError):
            raise InputError(
                f"stage {i + 1}", f"expected DRIVER:DRIVEN[:KIND], got {text!r}"
            ) from None
        parsed.append((*nums, *parts[2:3]))
    value = train_value(parsed)
    if json:
        print(dumps({"train_value": value, "ratio": 1 / value}))
        return
    print(f"train value ω_out/ω_in = {value:.6g}   (ratio ω_in/ω_out = {1 / value:.6g})")


@gear_app.command("reverted")
def reverted_cmd(
    ratio: Annotated[float, typer.Argument(help="Target ω_in/ω_out, e.g. 18.")],
    min_teeth: Annotated[int, typer.Option("--min-teeth")] = 12,
    max_teeth: Annotated[int, typer.Option("--max-teeth")] = 100,
    tolerance: Annotated[float, typer.Option("--tolerance")] = 1e-3,
    phi: PhiOpt = 20.0,
    json: JsonOpt = False,
) -> None:
    """Tooth numbers of a two-stage reverted compound train for a target ratio."""
    from ..gears import reverted_compound

    t = reverted_compound(
        ratio,
        min_teeth=min_teeth,
        max_teeth=max_teeth,
        tolerance=tolerance,
        pressure_angle=math.radians(phi),
    )
    result = {"teeth": list(t.teeth), "ratio": t.ratio, "target": t.target, "error": t.error}
    if json:
        print(dumps(result))
        return
    n2, n3, n4, n5 = t.teeth
    print_table(
        f"Reverted compound train for {ratio:g}:1",
        ["N2", "N3", "N4", "N5", "N2+N3", "ratio", "error"],
        [[n2, n3, n4, n5, t.tooth_sum, t.ratio, f"{t.error:.2e}"]],
    )


@gear_app.command("planetary")
def planetary_cmd(
    sun: Annotated[int, typer.Option("--sun", help="Sun teeth.")],
    planet: Annotated[int, typer.Option("--planet", help="Planet teeth.")],
    ring: Annotated[int, typer.Option("--ring", help="Ring teeth (= sun + 2 planet).")],
    speed: Annotated[
        list[str],
        typer.Option(
            "--speed",
            help="Known speed MEMBER=VALUE (member: sun, planet, ring, arm); give two."
            " A fixed member is MEMBER=0.",
        ),
    ],
    json: JsonOpt = False,
) -> None:
    """Speeds of a sun-planet-ring train by the tabular method (checked by Willis)."""
    from ..gears import PlanetaryTrain, willis

    known: dict[str, float] = {}
    for text in speed:
        name, _, value = text.partition("=")
        try:
            known[name.strip()] = float(value)
        except ValueError:
            raise InputError("--speed", f"expected MEMBER=VALUE, got {text!r}") from None
    train = PlanetaryTrain.simple(sun=sun, planet=planet, ring=ring)
    table = train.table(**known)
    arm, first = table["arm"], table["sun"]
    check = float(willis(train.train_value, first=first, arm=arm))
    if not math.isclose(check, table["ring"], rel_tol=1e-9, abs_tol=1e-9):
        raise InputError(
            "--speed", "tabular method and Willis' formula disagree"
        )  # pragma: no cover
    if json:
        print(
            dumps(
                {
                    "train_value": train.train_value,
                    "members": list(table.members),
                    "with_arm": table.with_arm,
                    "relative_to_arm": table.relative,
                    "total": table.total,
                }
            )
        )
        return
    rows = [
        [m, a, r, t]
        for m, a, r, t in zip(
            table.members, table.with_arm, table.relative, table.total, strict=True
        )
    ]
    print_table(
        f"Planetary train (tabular method), R = {train.train_value:g}",
        ["member", "with arm", "relative to arm", "total"],
        rows,
    )
