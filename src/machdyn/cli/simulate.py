"""``machdyn simulate FILE`` and ``machdyn tolerance FILE``: machines in time, and tolerances.

Both read a machine file (docs/spec.md) through :func:`machdyn.spec.load_machine`:
the part's own model, masses, loads and gravity, and its ``[<part>.simulate]``
table (motor, flywheel, when to stop) or ``[<part>.tolerance]`` table (the ±
tolerance of each dimension, samples, distribution). They print a summary and
tables labelled with the file's units, like ``machdyn run`` (``--json``,
``--csv``); ``simulate --plot FILE`` draws the run. Only reading, calling and
presenting happen here: the physics is :mod:`machdyn.simulate` and
:mod:`machdyn.tolerance`.
"""

from __future__ import annotations

import io
import math
from pathlib import Path
from typing import Annotated, Any

import numpy as np
import typer

from ..errors import InputError
from ._common import dumps

__all__ = ["simulate_command", "tolerance_command"]

#: Rows of the time table printed as text (``--csv``/``--json`` give every sample).
_PRINTED_ROWS = 41
_KINDS = ("fourbar", "slider_crank")


def _part(machine: Any, name: str | None, key: str, kinds: tuple[str, ...] = _KINDS) -> Any:
    """The part to analyse: ``--part``, else the one part that has a ``[<part>.<key>]`` table."""
    takes = " or ".join(kinds)
    if name is not None:
        if name not in machine.parts:
            raise InputError("--part", f"{name!r} is not a part; parts: {', '.join(machine.parts)}")
        part = machine.parts[name]
        if part.kind not in kinds:
            raise InputError("--part", f"{name!r} is a {part.kind}; {key} takes a {takes}")
        return part
    found = [p for p in machine.parts.values() if p.kind in kinds and key in p.values]
    if len(found) == 1:
        return found[0]
    if found:
        names = ", ".join(p.name for p in found)
        raise InputError("--part", f"several parts have a [{key}] table ({names}): pick one")
    raise InputError(key, f"no {takes} part has a [<kind>.<name>.{key}] table (docs/spec.md)")


def _dynamics(part: Any, machine: Any) -> dict[str, Any]:
    """The part's masses and constant loads (the file must give the links' masses)."""
    from ..spec._simulate import dynamics_options

    options = dynamics_options(part, machine)
    if options is None:
        raise InputError(
            f"{part.kind}.{part.name}",
            "simulating needs the links' masses: add [link2], [link3], [link4] tables",
        )
    return options


def _motor(spec: dict | None) -> Any:
    from ..simulate import ConstantTorque, DCMotor, InductionMotor

    if spec is None:
        return None
    options = {k: spec[k] for k in ("ratio", "inertia", "off_at") if k in spec}
    if spec["kind"] == "dc":
        return DCMotor(spec["stall_torque"], spec["no_load_speed"], **options)
    if spec["kind"] == "induction":
        return InductionMotor.from_rating(
            spec["rated_torque"],
            rated_speed=spec["rated_speed"],
            synchronous_speed=spec["synchronous_speed"],
            breakdown_factor=spec.get("breakdown_factor", 2.5),
            **options,
        )
    return ConstantTorque(spec["torque"], **options)


def _stall_in_units(event: Any, units: Any, run: Any) -> str:
    """A stall's message with its efforts (and a slider's position) in the file's output units.

    :mod:`machdyn.simulate` words it in the model's internal units, which a machine
    file in mm, say, does not show (0.3 N·m would read 300000).
    """
    from ..simulate._integrate import stall_words

    def shown(kind: str, value: float) -> str:
        return f"{float(units.show(kind, value)):.6g} {units.display(kind)}".rstrip()

    effort = "torque" if run.angular else "force"
    verb = "cannot start" if event.message.startswith("the motor cannot start") else "stalls"
    where = f"{run.coordinate} = {shown('angle' if run.angular else 'length', event.theta)}"
    given, need, deficit = (shown(effort, v) for v in (event.given, event.need, event.deficit))
    return stall_words(verb, where, given, need, deficit)


def _worded(run: Any, units: Any) -> dict[str, str]:
    """Each stall's message in the file's output units, by the message machdyn gave."""
    return {e.message: _stall_in_units(e, units, run) for e in run.events if e.kind == "stall"}


def _simulation_result(part: Any, run: Any, units: Any) -> Any:
    from ..spec._run import PartResult, ResultTable, Summary

    out = PartResult(part, objects={"simulation": run})
    worded = _worded(run, units)
    out.summary += [
        Summary("status", run.status),
        Summary("message", worded.get(run.message, run.message)),
        Summary("table", run.table),
        Summary("duration", float(run.t[-1]), "time"),
        Summary("added inertia (flywheel, motor)", run.added_inertia, "inertia"),
    ]
    steady = run.steady
    if steady is not None:
        out.summary += [
            Summary("steady: cycle time", steady.cycle_time, "time"),
            Summary("steady: omega avg", steady.omega_avg, "angular_velocity"),
            Summary("steady: omega min, max", [steady.omega_min, steady.omega_max],
                    "angular_velocity"),
            Summary("steady: k = (max - min) / avg", steady.k),
        ]  # fmt: skip
    for e in run.events:
        if e.kind == "stall":
            effort = "torque" if run.angular else "force"
            out.summary.append(Summary("stall: the motor's deficit", e.deficit, effort))
    residual = float(np.max(np.abs(run.energy.residual))) if run.t.size else math.nan
    out.summary.append(Summary("energy balance residual (max)", residual, "energy"))
    kind = "angle" if run.angular else "length"
    rate = "angular_velocity" if run.angular else "velocity"
    accel = "angular_acceleration" if run.angular else "acceleration"
    effort = "torque" if run.angular else "force"
    columns = {"t": run.t, "theta2": run.theta, "omega2": run.omega, "alpha2": run.alpha,
               "T_motor": run.motor_torque}  # fmt: skip
    kinds = {"t": "time", "theta2": kind, "omega2": rate, "alpha2": accel, "T_motor": effort}
    title = f"Motion of {part.name} in time"
    out.tables.append(ResultTable("motion", title, columns, kinds))
    if run.events:
        ev = run.events
        columns = {
            "event": np.array([e.kind for e in ev]),
            "t": np.array([e.t for e in ev]),
            "theta2": np.array([e.theta for e in ev]),
            "omega2": np.array([e.omega for e in ev]),
            "message": np.array([worded.get(e.message, e.message) for e in ev]),
        }
        kinds = {"event": None, "t": "time", "theta2": kind, "omega2": rate, "message": None}
        out.tables.append(ResultTable("events", f"Events of {part.name}", columns, kinds))
    return out


def _printed(result: Any, machine: Any, heading: str) -> None:
    from .run import _print_part, _units_line

    print(f"{heading}  ({_units_line(machine.units)})\n")
    for table in result.tables:  # long tables thinned for reading (--csv, --json: all)
        n = len(table)
        if n > _PRINTED_ROWS and table.name != "events":
            step = math.ceil(n / (_PRINTED_ROWS - 1))
            keep = np.r_[np.arange(0, n - 1, step), n - 1]
            table.columns = {k: np.asarray(v)[keep] for k, v in table.columns.items()}
            table.title += f" (one row in {step}; --csv or --json for every sample)"
    _print_part(machine, result)


def _emit(machine: Any, result: Any, file: Path, json: bool, csv_out: bool) -> None:
    from .run import payload, write_csv

    if json and csv_out:
        raise InputError("--csv", "choose one of --json and --csv")
    if json:
        print(dumps(payload(machine, {result.part.name: result})))
    elif csv_out:
        buffer = io.StringIO()
        write_csv(result.tables[0].labelled(machine.units), buffer)
        print(buffer.getvalue(), end="")
    else:
        _printed(result, machine, machine.title or Path(file).name)


def simulate_command(
    file: Annotated[Path, typer.Argument(help="A machine file with a [<part>.simulate] table.")],
    part: Annotated[str | None, typer.Option("--part", help="The part to simulate.")] = None,
    json: Annotated[bool, typer.Option("--json", help="Print JSON (columns with units).")] = False,
    csv_out: Annotated[
        bool, typer.Option("--csv", help="Print every time sample as CSV (units in the header).")
    ] = False,
    plot: Annotated[
        Path | None, typer.Option("--plot", help="Draw θ, ω and the motor torque to this image.")
    ] = None,
) -> None:
    """Forward dynamics: the motion a motor gives a four-bar or slider-crank (start-up, steady)."""
    from ..simulate import simulate
    from ..spec import load_machine

    machine = load_machine(file)
    p = _part(machine, part, "simulate")
    spec = p.values.get("simulate", {})
    stops = [k for k in ("t_end", "turns", "until") if k in spec]
    if len(stops) != 1:
        raise InputError(
            f"{p.kind}.{p.name}.simulate",
            'give exactly one of t_end, turns, until = "steady" (when to stop)',
        )
    keys = ("t_end", "turns", "until", "theta0", "omega0", "samples", "max_evaluations")
    options = {k: spec[k] for k in keys if k in spec}
    run = simulate(p.model, _motor(spec.get("motor")), flywheel=spec.get("flywheel", 0.0),
                   **options, **_dynamics(p, machine))  # fmt: skip
    if plot is not None:
        import matplotlib

        matplotlib.use("Agg")
        title = _worded(run, machine.units).get(run.message, run.message)
        fig = run.plot(units=machine.units, title=title)
        fig.savefig(plot, dpi=120)
    _emit(machine, _simulation_result(p, run, machine.units), file, json, csv_out)
    if plot is not None and not (json or csv_out):
        print(f"wrote {plot}")


def _tolerance_result(part: Any, t: Any, placed: tuple[complex, float] | None = None) -> Any:
    """The tolerance tables of a part (``placed``: a placed four-bar's O2, θ1 for its points)."""
    from ..spec._run import PartResult, ResultTable, Summary

    out = PartResult(part, objects={"tolerance": t})
    kind_of = {"delta": "angle"}
    out.summary += [
        Summary("samples", f"{t.samples:,} x {t.theta.size} poses"),
        Summary("unassembled", f"{t.failed:,} ({100 * t.failed_fraction:.3g} %)"),
    ]
    for name, tol, dist in zip(t.dimensions, t.tolerances, t.distributions, strict=True):
        how = "3 sigma" if dist == "normal" else "uniform"
        kind = "angle" if name.endswith(".delta") else kind_of.get(name, "length")
        out.summary.append(Summary(f"+/- {name} ({how})", float(tol), kind))
    output_kinds = {"theta3": "angle", "theta4": "angle", "d": "length", "coupler": "length",
                    "T12": "torque", "theta": "angle", "point": "length",
                    "torque": "torque"}  # fmt: skip
    for reason, count in t.failures.items():
        out.summary.append(Summary(f"unassembled: {reason}", f"{count:,}"))
    for name, s in t.outputs.items():
        kind = output_kinds[name.split(".", 1)[0]]
        point = name == "coupler" or name.startswith("point.")
        what = "distance" if point else "deviation"
        with np.errstate(invalid="ignore"):
            q99 = float(np.quantile(s.peak, 0.99)) if s.peak.size else math.nan
        out.summary += [
            Summary(f"{name}: worst sample, peak {what}", s.worst, kind),
            Summary(f"{name}: 99 % of samples within", q99, kind),
            Summary(f"{name}: worst-case stack-up (1st order, max)", float(np.max(s.worst_case)),
                    kind),
        ]  # fmt: skip
        columns = {
            "theta2": t.theta,
            f"{name}_nominal": s.nominal,
            "std": s.std,
            "std_linear": s.linear_std,
            "low": s.low,
            "high": s.high,
            "stack_up": s.worst_case,
        }
        if point:
            o2, theta1 = placed or (0j, 0.0)
            nominal = o2 + np.exp(1j * theta1) * s.nominal  # the plane's, as `machdyn run`
            columns = {"theta2": t.theta, "P_nominal_x": nominal.real,
                       "P_nominal_y": nominal.imag, "rms": s.std, "rms_linear": s.linear_std,
                       "max": s.high, "stack_up": s.worst_case}  # fmt: skip
        kinds = {k: kind for k in columns} | {"theta2": "angle"}
        if point:
            kinds |= {"P_nominal_x": "length", "P_nominal_y": "length"}
        title = f"{name} of {part.name}: spread of the {what} from nominal, {t.samples:,} samples"
        out.tables.append(ResultTable(name, title, columns, kinds))
    out.flagged += [f"warning: {w}" for w in t.warnings]
    return out


def _linkage_tolerance(p: Any, machine: Any, samples: int | None, scheduler: str | None,
                       workers: int | None) -> Any:  # fmt: skip
    """``machdyn.tolerance`` of a linkage part: its drive's sweep and speed, the file's gravity."""
    from ..tolerance import tolerance

    spec = dict(p.values["tolerance"])
    dims = spec.pop("dimensions")
    if samples is not None:
        spec["samples"] = samples
    lk = p.model
    setting = p.values.get("motion", {}).get(lk.drivers[0]) if len(lk.drivers) == 1 else None
    theta2 = setting.values.values if setting is not None and setting.values else None
    omega2 = setting.velocity if setting is not None and setting.velocity else 1.0
    alpha2 = setting.acceleration if setting is not None and setting.acceleration else 0.0
    return tolerance(lk, dims, theta2, omega2=omega2, alpha2=alpha2,
                     gravity=machine.gravity or 0.0, scheduler=scheduler, workers=workers,
                     **spec)  # fmt: skip


def tolerance_command(
    file: Annotated[Path, typer.Argument(help="A machine file with a [<part>.tolerance] table.")],
    part: Annotated[str | None, typer.Option("--part", help="The part to analyse.")] = None,
    samples: Annotated[
        int | None, typer.Option("--samples", help="Monte Carlo samples (overrides the file).")
    ] = None,
    scheduler: Annotated[
        str | None,
        typer.Option("--scheduler", help="'local' (a Dask LocalCluster) or tcp://host:8786."),
    ] = None,
    workers: Annotated[
        int | None, typer.Option("--workers", help="Worker processes of the LocalCluster.")
    ] = None,
    json: Annotated[bool, typer.Option("--json", help="Print JSON (columns with units).")] = False,
    csv_out: Annotated[
        bool, typer.Option("--csv", help="Print the first output's table as CSV.")
    ] = False,
) -> None:
    """Monte Carlo tolerance analysis of a four-bar, slider-crank or linkage, beside stack-up."""
    from ..spec import load_machine
    from ..tolerance import tolerance

    machine = load_machine(file)
    p = _part(machine, part, "tolerance", (*_KINDS, "linkage"))
    if p.kind == "linkage":
        t = _linkage_tolerance(p, machine, samples, scheduler, workers)
        _emit(machine, _tolerance_result(p, t), file, json, csv_out)
        return
    spec = dict(p.values.get("tolerance", {}))
    options = {k: spec.pop(k) for k in ("distribution", "sigmas", "samples", "seed") if k in spec}
    if samples is not None:
        options["samples"] = samples
    if not spec:
        raise InputError(f"{p.kind}.{p.name}.tolerance", "give the ± tolerance of some dimension")
    motion = p.values.get("motion", {})
    theta2 = motion["theta2"].values if "theta2" in motion else None
    from ..spec._fourbar import placement

    dyn, placed, note = {}, placement(p.values) if p.kind == "fourbar" else None, None
    loads = p.values.get("loads", {})
    if p.kind == "fourbar" and any(f"link{n}" in p.values for n in (2, 3, 4)):
        if "force" in loads or "torques" in loads:  # T12 here takes torque4 and gravity only
            note = "T12 is not toleranced: its [[loads.force]]/loads.torques are not taken here"
        else:
            dyn = _fourbar_torque_options(p, machine, placed)
    form, branch = p.values.get("form", 1), p.values.get("branch")  # (branch: GRCR/GRRC)
    t = tolerance(p.model, spec, theta2, form=form, branch=branch, scheduler=scheduler,
                  workers=workers, **options, **dyn)  # fmt: skip
    result = _tolerance_result(p, t, placed)
    if note:
        result.flagged.append(f"warning: {note}")
    _emit(machine, result, file, json, csv_out)


def _fourbar_torque_options(p: Any, machine: Any, placed: Any) -> dict[str, Any]:
    """A four-bar part's masses, speed, torque4 and gravity as ``tolerance`` takes them.

    Placed (O2, θ1): gravity along the plane's −y is the vector −j g e^{−jθ1} in its frame.
    """
    from ..spec._fourbar import _masses, input_motion

    dyn = dict(_masses(p.values, (2, 3, 4)) or {})
    _, dyn["omega2"], dyn["alpha2"] = input_motion(p, machine, {})
    dyn["load"] = p.values.get("loads", {}).get("torque4", 0.0)
    g = float(machine.gravity or 0.0)
    dyn["gravity"] = g if placed is None or not g else -1j * g * np.exp(-1j * placed[1])
    return dyn
