"""``machdyn gear ...``: spur-gear pairs, minimum teeth, profiles and trains.

Only parsing and presenting live here; every number comes from
:mod:`machdyn.gears`. Angles are read and printed in degrees (labelled), and
an error names the command-line option, not the library parameter behind it.
Register with ``app.add_typer(gear_app, name="gear")``.
"""

from __future__ import annotations

import math
from collections.abc import Iterator
from contextlib import contextmanager
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
PhiOpt = Annotated[
    float, typer.Option("--phi", help="Pressure angle in degrees (standard: 14.5, 20, 25).")
]
SystemOpt = Annotated[str, typer.Option("--system", help="Tooth system: full_depth or stub.")]

#: Pressure angles the CLI accepts, in degrees: from below the oldest standard
#: (14.5°) to the library's upper limit. A value under 10 is most likely radians.
PHI_RANGE_DEG = (10.0, 45.0)


@contextmanager
def _options(default: str | None = None, **flags: str) -> Iterator[None]:
    """Re-raise the library's :class:`InputError` with the CLI option as its field.

    ``flags`` maps library parameter names to option names; ``default``, if
    given, replaces any other field.
    """
    try:
        yield
    except InputError as exc:
        field = flags.get(exc.field, default)
        if field is None:
            raise
        raise InputError(field, exc.message) from None


def _phi_rad(phi_deg: float, option: str = "--phi") -> float:
    """Check a pressure angle typed in degrees and return it in radians."""
    lo, hi = PHI_RANGE_DEG
    if not (math.isfinite(phi_deg) and lo <= phi_deg < hi):
        hint = ""
        if 0.0 < phi_deg < math.radians(hi):
            as_deg = math.degrees(phi_deg)
            hint = f", which looks like radians ({as_deg:.4g}°): type {option} {as_deg:.4g}"
        raise InputError(
            option,
            f"the pressure angle in degrees must be at least {lo:g} and below {hi:g} (standard:"
            f" 14.5, 20, 25); got {phi_deg:g}{hint}",
        )
    return math.radians(phi_deg)


def _gear(
    teeth: int,
    module: float | None,
    pd: float | None,
    phi_deg: float,
    system: str,
    shift: float = 0.0,
    internal: bool = False,
    thinning: float = 0.0,
    *,
    teeth_option: str = "--teeth",
    shift_option: str = "--shift",
    thinning_option: str = "--thin-p",
) -> Any:
    from ..gears import Gear

    if module is None and pd is None:
        raise InputError("--module", "give the size as --module M or --pd P_d")
    if module is not None and pd is not None:
        raise InputError("--module", "give the size as --module M or --pd P_d, not both")
    phi = _phi_rad(phi_deg)
    flags = {
        "teeth": teeth_option,
        "module": "--module",
        "diametral_pitch": "--pd",
        "system": "--system",
        "profile_shift": shift_option,
        "thickness_reduction": thinning_option,
    }
    with _options(**flags):
        return Gear(
            teeth,
            module=module,
            diametral_pitch=pd,
            pressure_angle=phi,
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
    driver: str = "pinion",
) -> Any:
    from ..gears import GearPair

    pinion = _gear(
        np_, module, pd, phi, system, xp, False, thin_p,
        teeth_option="--np", shift_option="--xp", thinning_option="--thin-p",
    )  # fmt: skip
    gear = _gear(
        ng, module, pd, phi, system, xg, internal, thin_g,
        teeth_option="--ng", shift_option="--xg", thinning_option="--thin-g",
    )  # fmt: skip
    flags = {"center_distance": "--center-distance", "profile_shift": "--xp/--xg"}
    with _options(gear="--ng", pinion="--np", driver="--driver", **flags):
        return GearPair(pinion, gear, center_distance, driver=driver)


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
DriverOpt = Annotated[
    str,
    typer.Option(
        "--driver", help="Which member drives: pinion or gear (splits approach and recess)."
    ),
]


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
    driver: DriverOpt = "pinion",
    json: JsonOpt = False,
) -> None:
    """Geometry, contact ratio and interference check of a pinion and gear."""
    from ..gears import undercut

    pair = _pair(
        np_, ng, module, pd, phi, system, xp, xg, internal, center_distance, thin_p, thin_g,
        driver,
    )  # fmt: skip
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
        "driver",
        "path_of_approach",
        "path_of_recess",
        "angle_of_approach_pinion_deg",
        "angle_of_recess_pinion_deg",
        "angle_of_approach_gear_deg",
        "angle_of_recess_gear_deg",
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
        rad = _phi_rad(a)
        with _options(k="--k", gear_teeth="--ng"):
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

    gear = _gear(teeth, module, pd, phi, system, shift, internal)
    with _options(points="--points", teeth="--teeth"):
        out = gear_outline(gear, points)
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
    driver: DriverOpt = "pinion",
) -> None:
    """Draw a meshing pair with its pitch and base circles and path of contact."""
    import matplotlib.pyplot as plt

    from ..gears import plot_mesh

    if not math.isfinite(angle):
        raise InputError("--angle", f"must be a finite angle in degrees, got {angle:g}")
    pair = _pair(
        np_, ng, module, pd, phi, system, xp, xg, internal, center_distance, 0.0, 0.0, driver
    )
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
    from ..gears import stage_ratio, train_value

    parsed: list[tuple[Any, ...]] = []
    for i, text in enumerate(stages.split(",")):
        parts = text.strip().split(":")
        try:
            nums = (float(parts[0]), float(parts[1]))
        except (ValueError, IndexError):
            raise InputError(
                f"stage {i + 1}", f"expected DRIVER:DRIVEN[:KIND], got {text!r}"
            ) from None
        if len(parts) > 3:
            raise InputError(f"stage {i + 1}", f"expected DRIVER:DRIVEN[:KIND], got {text!r}")
        with _options(default=f"stage {i + 1}"):
            stage_ratio(*nums, *parts[2:3])  # checks the numbers and the kind
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

    rad = _phi_rad(phi)
    flags = {"min_teeth": "--min-teeth", "max_teeth": "--max-teeth", "tolerance": "--tolerance"}
    with _options(ratio="RATIO", **flags):
        t = reverted_compound(
            ratio, min_teeth=min_teeth, max_teeth=max_teeth, tolerance=tolerance, pressure_angle=rad
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
    with _options(sun="--sun", planet="--planet", ring="--ring"):
        train = PlanetaryTrain.simple(sun=sun, planet=planet, ring=ring)
    with _options(default="--speed"):
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
