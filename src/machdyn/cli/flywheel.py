"""``machdyn flywheel``: size a flywheel from a torque curve read from a CSV file.

The CSV holds one cycle: a column of crank angles in degrees and a column of the
torque T12 the linkage requires (a header line and ``#`` comments are allowed).
Only parsing and printing happen here; the physics is :mod:`machdyn.flywheel`.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated

import numpy as np
import typer

from ..errors import InputError
from ..flywheel import disc_flywheel, size_flywheel
from ._common import dumps, print_table

__all__ = ["flywheel", "flywheel_app", "read_curve"]

flywheel_app = typer.Typer(add_completion=False, pretty_exceptions_enable=False)


def read_curve(path: Path) -> tuple[np.ndarray, np.ndarray]:
    r"""Read one cycle of ``theta, torque`` from a CSV file; return θ in radians and T.

    The file of :func:`machdyn.spec.read_torque_csv` (one reader for the
    command line and machine files): the first column the angle (degrees
    unless its header says ``[rad]``), the torque the column ``T12`` or
    ``T_<driver>`` — so the CSV that ``machdyn linkage --csv`` and
    ``machdyn run --csv`` write is read as it is — else the second column.

    Examples
    --------
    >>> import tempfile, pathlib
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     file = pathlib.Path(tmp) / "t.csv"
    ...     _ = file.write_text("theta_deg,T12\n0,1\n90,2\n180,3\n")
    ...     theta, torque = read_curve(file)
    >>> theta.round(4).tolist(), torque.tolist()
    ([0.0, 1.5708, 3.1416], [1.0, 2.0, 3.0])
    """
    from ..spec._tasks import read_torque_csv

    try:
        return read_torque_csv(path)
    except InputError as exc:
        raise InputError("CSV", f"{exc.field}: {exc.message}") from None


@flywheel_app.command()
def flywheel(
    curve: Annotated[
        Path | None, typer.Argument(help="CSV with columns theta (deg), T12 over one cycle.")
    ] = None,
    omega_avg: Annotated[
        float | None,
        typer.Option("--omega-avg", help="Average shaft speed, rad/s (rpm with --rpm)."),
    ] = None,
    k: Annotated[
        float | None, typer.Option("--k", help="Coefficient of fluctuation, e.g. 0.02.")
    ] = None,
    rpm: Annotated[bool, typer.Option("--rpm", help="--omega-avg is in rev/min.")] = False,
    period_deg: Annotated[
        float, typer.Option("--period-deg", help="Angle of one cycle, degrees.")
    ] = 360.0,
    density: Annotated[
        float | None, typer.Option("--density", help="Disc material density, to size a disc.")
    ] = None,
    thickness: Annotated[
        float | None, typer.Option("--thickness", help="Disc thickness, to size a disc.")
    ] = None,
    as_json: Annotated[bool, typer.Option("--json", help="Print JSON instead of tables.")] = False,
    spec: Annotated[
        Path | None,
        typer.Option(
            "--spec",
            help="A machine file (docs/spec.md): size its flywheel part, in the file's units.",
        ),
    ] = None,
    part: Annotated[
        str | None, typer.Option("--part", help="With --spec: the part, when the file has several.")
    ] = None,
    csv: Annotated[
        bool, typer.Option("--csv", help="With --spec: print the lobe table as CSV (with units).")
    ] = False,
) -> None:
    """Size a flywheel: lobe table (Table 11-1), ΔE, I = ΔE/(k ω²) and the achieved k.

    With ``--spec FILE`` the torque curve, speed and k come from the file's
    ``flywheel`` part (its torque may be another part's, e.g. a four-bar's),
    reported as ``machdyn run FILE --part NAME`` does.
    """
    from .run import run_spec_part

    if spec is not None:
        given = {
            "CURVE": curve is not None,
            "--omega-avg": omega_avg is not None,
            "--k": k is not None,
        }
        given |= {"--rpm": rpm, "--period-deg": period_deg != 360.0}
        given |= {"--density": density is not None, "--thickness": thickness is not None}
        run_spec_part(spec, ("flywheel",), part, given=given, json=as_json, csv_out=csv)
        return
    run_spec_part(None, ("flywheel",), part, csv_out=csv)  # refuses --part/--csv without a file
    for option, value in (("CURVE", curve), ("--omega-avg", omega_avg), ("--k", k)):
        if value is None:
            raise InputError(option, "missing: give CURVE --omega-avg W --k K, or --spec FILE")
    assert curve is not None and omega_avg is not None and k is not None
    if (density is None) != (thickness is None):
        raise InputError("--thickness", "give both --density and --thickness to size a disc")
    theta, torque = read_curve(curve)
    omega = omega_avg * 2 * math.pi / 60 if rpm else omega_avg
    try:
        result = size_flywheel(theta, torque, omega, k, period=math.radians(period_deg))
    except InputError as exc:
        if exc.field != "theta":
            raise
        message = exc.message.replace(" (θ in radians here, in degrees in the CLI's CSV)", "")
        if message != exc.message:
            message += " with θ in degrees (not radians)"
        raise InputError("CSV", f"theta column: {message}") from None
    disc = None
    if density is not None and thickness is not None and result.inertia > 0:
        disc = disc_flywheel(result.inertia, density, thickness)

    lobes = result.lobes
    summary = {
        "T_avg": result.torque_avg,
        "delta_E": result.delta_e,
        "theta_omega_max_deg": math.degrees(result.theta_omega_max),
        "theta_omega_min_deg": math.degrees(result.theta_omega_min),
        "omega_avg_rad_s": result.omega_avg,
        "k_requested": result.k,
        "inertia": result.inertia,
        "omega_max_rad_s": result.omega_max,
        "omega_min_rad_s": result.omega_min,
        "k_achieved": result.k_achieved,
    }
    if disc is not None:
        summary |= {"disc_outer_radius": disc.outer_radius, "disc_mass": disc.mass}
    if as_json:
        lobe_rows = {
            "theta_from_deg": np.degrees(lobes.theta_from),
            "theta_to_deg": np.degrees(lobes.theta_to),
            "delta_E": lobes.area,
            "E": lobes.energy,
            "omega_at_end": lobes.omega_at_end.tolist(),
        }
        print(dumps({**summary, "lobes": lobe_rows, "neglects": list(result.neglects)}))
        return
    print_table(
        "Lobes of T12 - T_avg (Table 11-1)",
        ["lobe", "from (deg)", "to (deg)", "dE", "accum. E", "omega at end"],
        [
            [i + 1, a, b, d, e, m]
            for i, (a, b, d, e, m) in enumerate(
                zip(
                    np.degrees(lobes.theta_from),
                    np.degrees(lobes.theta_to),
                    lobes.area,
                    lobes.energy,
                    lobes.omega_at_end,
                    strict=True,
                )
            )
        ],
    )
    print_table("Flywheel", ["quantity", "value"], [[name, v] for name, v in summary.items()])
    print("The estimate neglects " + "; ".join(result.neglects) + ".")
    print("For the fluctuation with the linkage's own inertia: FlywheelResult.simulate(model).")
