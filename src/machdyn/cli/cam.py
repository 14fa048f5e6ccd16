"""``machdyn cam``: analyse a cam program and its radial cam from the command line.

Angles are typed in degrees, lengths as plain numbers in any one unit; every
printed quantity is labelled. The program comes from ``--segment`` options
(``MOTION:LAW:H:BETA_DEG``, or ``dwell:BETA_DEG``) or a TOML file
(``--program cam.toml``, see :func:`load_program_file`). No physics lives here.
"""

from __future__ import annotations

import re
import tomllib
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Annotated, Any

import numpy as np
import typer

from .. import cams
from ..cams.geometry import format_ranges
from ..cams.io import cannot_be_cut, undercut_refusal
from ..cams.program import MOTIONS, closure_message
from ..errors import InputError, ModelError
from ._common import dumps, print_table

__all__ = ["cam_app", "load_program_file", "load_table", "parse_segment"]

cam_app = typer.Typer(
    help="Cam design: svaj program, continuity, pressure angle, curvature, undercut.",
    add_completion=False,
    pretty_exceptions_enable=False,
)

FOLLOWERS = ("roller", "flat", "oscillating")
FOLLOWER_KEYS = (
    "type",
    "prime_radius",
    "roller_radius",
    "base_radius",
    "eccentricity",
    "pivot_distance",
    "arm_length",
    "pivot_side",
)
SEGMENT_KEYS = ("motion", "law", "h", "h_deg", "beta_deg", "b", "c", "d")
_SCCA = re.compile(r"^scca\(([^)]*)\)$", re.IGNORECASE)


def _law(token: str, field: str) -> cams.MotionLaw:
    match = _SCCA.match(token.strip())
    if match:
        parts = [p for p in re.split(r"[,\s]+", match.group(1)) if p]
        if len(parts) != 3:
            raise InputError(field, f"scca takes three fractions scca(b,c,d), got {token!r}")
        b, c, d = (_number(p, field) for p in parts)
        return cams.get_law("scca", b=b, c=c, d=d)
    try:
        return cams.get_law(token)
    except InputError as exc:
        raise InputError(field, exc.message) from None


def _number(text: Any, field: str) -> float:
    if isinstance(text, bool):  # TOML true/false would otherwise pass as 1.0/0.0
        raise InputError(field, f"expected a number, got {str(text).lower()}")
    try:
        return float(text)
    except (TypeError, ValueError):
        raise InputError(field, f"expected a number, got {text!r}") from None


@contextmanager
def _renamed(fields: dict[str, str], prefix: str = "") -> Iterator[None]:
    """Re-raise a library :class:`InputError` under the name the user typed."""
    try:
        yield
    except InputError as exc:
        if exc.field not in fields:
            raise
        raise InputError(fields[exc.field], prefix + exc.message) from None


def _segment(
    motion: str,
    beta_deg: float,
    h: float,
    law: Any,
    oscillating: bool,
    where: str,
    fields: dict[str, str],
) -> cams.Segment:
    """Build a segment from values typed in degrees, naming ``fields`` in errors."""
    if not beta_deg > 0.0:
        raise InputError(fields["beta"], f"{where}the angle must be positive, got {beta_deg:g}°")
    if motion != "dwell" and not h > 0.0:
        unit = "°" if oscillating else ""
        raise InputError(fields["h"], f"{where}a {motion} needs a positive lift, got {h:g}{unit}")
    with _renamed(fields, where):
        if motion == "dwell":
            return cams.Segment("dwell", np.radians(beta_deg))
        lift = float(np.radians(h)) if oscillating else h
        return cams.Segment(motion, np.radians(beta_deg), lift, law)


def parse_segment(text: str, oscillating: bool = False) -> cams.Segment:
    """Parse ``rise:LAW:H:BETA_DEG``, ``fall:LAW:H:BETA_DEG`` or ``dwell:BETA_DEG``.

    ``H`` is a length, or degrees for an oscillating follower. ``LAW`` is a law
    name or ``scca(b,c,d)``.

    Examples
    --------
    >>> seg = parse_segment("rise:cycloidal:1.5:60")
    >>> seg.motion, seg.law.name, seg.h, round(float(np.degrees(seg.beta)), 9)
    ('rise', 'cycloidal', 1.5, 60.0)
    >>> parse_segment("dwell:120").motion
    'dwell'
    """
    field = "--segment"
    fields = dict.fromkeys(("motion", "beta", "h", "law"), field)
    where = f"{text}: "
    parts = text.split(":")
    motion = parts[0].strip().lower()
    if motion == "dwell":
        if len(parts) != 2:
            raise InputError(field, f"a dwell is dwell:BETA_DEG, got {text!r}")
        return _segment("dwell", _number(parts[1], field), 0.0, None, oscillating, where, fields)
    if motion not in ("rise", "fall") or len(parts) != 4:
        raise InputError(
            field,
            f"expected rise:LAW:H:BETA_DEG, fall:LAW:H:BETA_DEG or dwell:BETA_DEG; got {text!r}",
        )
    h = _number(parts[2], field)
    beta = _number(parts[3], field)
    return _segment(motion, beta, h, _law(parts[1], field), oscillating, where, fields)


def load_program_file(path: Path) -> tuple[list[dict[str, Any]], dict[str, Any], dict[str, Any]]:
    """Read a TOML cam file: ``[[segments]]``, optional ``[follower]`` and top-level keys.

    Each segment has ``motion``, ``beta_deg`` and for a rise/fall ``law`` and
    ``h`` (length, or ``h_deg`` for an oscillating follower), plus ``b, c, d``
    for ``law = "scca"``. ``[follower]`` holds ``type`` and the radii (same
    names as the options, with underscores). Top level: ``rpm``.
    """
    try:
        data = tomllib.loads(Path(path).read_text(encoding="utf-8"))
    except OSError as exc:
        raise InputError("--program", f"cannot read {path}: {exc.strerror}") from None
    except UnicodeDecodeError as exc:
        raise InputError(
            "--program", f"{path} is not UTF-8 text (byte {exc.start}); save it as UTF-8"
        ) from None
    except tomllib.TOMLDecodeError as exc:
        raise InputError("--program", f"{path} is not valid TOML: {exc}") from None
    segments = data.pop("segments", None)
    if not isinstance(segments, list) or not segments:
        raise InputError("--program", f"{path} needs at least one [[segments]] table")
    follower = data.pop("follower", {})
    if not isinstance(follower, dict):
        raise InputError("--program", "[follower] must be a table")
    unknown_keys = sorted(set(follower) - set(FOLLOWER_KEYS))
    if unknown_keys:
        raise InputError(
            "[follower]",
            f"unknown keys {unknown_keys} in {path}; valid: {', '.join(FOLLOWER_KEYS)}",
        )
    known = {"rpm"}
    unknown = set(data) - known
    if unknown:
        raise InputError("--program", f"unknown top-level keys {sorted(unknown)}; valid: rpm")
    return segments, follower, data


def _machine_cam(path: Path) -> tuple[Any, dict[str, Any], dict[str, Any]] | None:
    """The cam part of a machine file (``machdyn = 1``): program, follower keys, rpm, unit.

    None for an old ``--program`` cam file. The numbers are the file's own
    (lengths in its ``[units]``); options given on the command line override them.
    """
    import dataclasses

    try:
        if "machdyn" not in tomllib.loads(Path(path).read_text(encoding="utf-8")):
            return None
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError):
        return None  # load_program_file says what is wrong with it
    from ..spec import Cam, load_machine

    machine = load_machine(path)
    parts = [p for p in machine.parts.values() if p.kind == "cam"]
    if len(parts) != 1 or not isinstance(parts[0].model, Cam):
        names = ", ".join(p.name for p in parts) or "none"
        raise InputError(
            "--program",
            f"{path} needs exactly one cam part with segments and a follower (cams: {names}); "
            "machdyn run analyses every part",
        )
    part, model = parts[0], parts[0].model
    kind = {
        cams.TranslatingRoller: "roller",
        cams.TranslatingFlatFace: "flat",
        cams.OscillatingRoller: "oscillating",
    }[type(model.follower)]
    follower = {"type": kind, **dataclasses.asdict(model.follower)}
    top: dict[str, Any] = {}
    if "speed" in part.values:
        top["rpm"] = abs(part.values["speed"]) * 60.0 / (2.0 * np.pi)
    if not machine.units.is_unit_free:
        top["unit"] = machine.units.length
        top["units"] = machine.units
    return model.program, follower, top


def _segment_from_table(table: Any, index: int, oscillating: bool) -> cams.Segment:
    field = f"segments[{index}]"
    if not isinstance(table, dict):
        raise InputError(
            field,
            f"must be a [[segments]] table (motion, law, h, beta_deg), got {table!r}",
        )
    unknown = set(table) - set(SEGMENT_KEYS)
    if unknown:
        raise InputError(field, f"unknown keys {sorted(unknown)}; valid: {', '.join(SEGMENT_KEYS)}")
    if "beta_deg" not in table or "motion" not in table:
        raise InputError(field, "needs motion and beta_deg")
    motion = str(table["motion"]).lower()
    if motion not in MOTIONS:
        raise InputError(
            f"{field}.motion",
            f"must be one of {', '.join(MOTIONS)}; got {table['motion']!r}",
        )
    beta = _number(table["beta_deg"], f"{field}.beta_deg")
    key = "h_deg" if oscillating else "h"
    fields = {
        "motion": f"{field}.motion",
        "beta": f"{field}.beta_deg",
        "h": f"{field}.{key}",
        "law": f"{field}.law",
        **{k: f"{field}.{k}" for k in "bcd"},
    }
    if motion == "dwell":
        return _segment("dwell", beta, 0.0, None, oscillating, "", fields)
    name = str(table.get("law", ""))
    if name.lower() == "scca":
        with _renamed(fields):
            law = cams.get_law("scca", **{k: _number(table.get(k), f"{field}.{k}") for k in "bcd"})
    else:
        law = _law(name, f"{field}.law")
    if key not in table:
        raise InputError(field, f"a {motion} needs {key}")
    h = _number(table[key], f"{field}.{key}")
    return _segment(motion, beta, h, law, oscillating, "", fields)


def _pick(cli_value: Any, file: dict[str, Any], key: str, default: Any = None) -> Any:
    return cli_value if cli_value is not None else file.get(key, default)


def _build_follower(kind: str, opts: dict[str, Any], fields: dict[str, str]) -> Any:
    """The follower object; ``fields`` names each option as the user gave it."""

    def need(name: str) -> float:
        if opts.get(name) is None:
            raise InputError(fields[name], f"is required for a {kind} follower")
        return _number(opts[name], fields[name])

    with _renamed(fields):
        if kind == "roller":
            return cams.TranslatingRoller(
                need("prime_radius"), need("roller_radius"), opts.get("eccentricity") or 0.0
            )
        if kind == "flat":
            return cams.TranslatingFlatFace(need("base_radius"), opts.get("eccentricity") or 0.0)
        return cams.OscillatingRoller(
            need("prime_radius"),
            need("roller_radius"),
            need("pivot_distance"),
            need("arm_length"),
            opts["pivot_side"],
        )


def _option_names(file_follower: dict[str, Any], cli_values: dict[str, Any]) -> dict[str, str]:
    """``--roller-radius``, or ``[follower] roller_radius`` when the value came from the file."""
    flags = {key: "--" + key.replace("_", "-") for key in FOLLOWER_KEYS}
    flags["type"] = "--follower"
    return {
        key: f"[follower] {key}" if cli_values.get(key) is None and key in file_follower else flag
        for key, flag in flags.items()
    }


def _check_output(path: Path | None, option: str) -> None:
    """Refuse an output path whose folder does not exist, before any work is done."""
    if path is None:
        return
    folder = Path(path).parent
    if not folder.is_dir():
        raise InputError(option, f"cannot write {path}: the folder {folder} does not exist")


def _build_program(
    segs: list[cams.Segment], oscillating: bool, field: str, source: str
) -> cams.CamProgram:
    """The program, with its errors stated in the units and option the user typed."""
    try:
        return cams.CamProgram(segs)
    except InputError as exc:
        if exc.field != "segments":
            raise
        message = exc.message
        rises = sum(seg.h for seg in segs if seg.motion == "rise")
        falls = sum(seg.h for seg in segs if seg.motion == "fall")
        if oscillating and message == closure_message(rises, falls):
            message = closure_message(float(np.degrees(rises)), float(np.degrees(falls)), "°")
        raise InputError(field, source + message) from None


@cam_app.callback(invoke_without_command=True)
def cam(
    ctx: typer.Context,
    segment: Annotated[
        list[str] | None,
        typer.Option(
            "--segment",
            "-s",
            metavar="MOTION:LAW:H:BETA_DEG",
            help="rise:LAW:H:BETA_DEG, fall:LAW:H:BETA_DEG or dwell:BETA_DEG (repeat, in order)",
        ),
    ] = None,
    program: Annotated[
        Path | None,
        typer.Option(
            "--program", help="TOML cam file, or a machine file with one cam part (docs/spec.md)"
        ),
    ] = None,
    table: Annotated[
        Path | None,
        typer.Option(
            "--table",
            help="critical path motion: CSV of theta_deg,s points (one turn) instead of segments",
        ),
    ] = None,
    degree: Annotated[int, typer.Option(help="spline degree for --table (3-7)")] = 5,
    smoothing: Annotated[
        float, typer.Option(help="RMS deviation allowed from the --table points (0: through)")
    ] = 0.0,
    follower: Annotated[
        str | None, typer.Option(help="roller | flat | oscillating (default roller)")
    ] = None,
    prime_radius: Annotated[float | None, typer.Option(help="prime circle radius Rp")] = None,
    roller_radius: Annotated[float | None, typer.Option(help="roller radius Rf")] = None,
    base_radius: Annotated[float | None, typer.Option(help="base circle Rb (flat face)")] = None,
    eccentricity: Annotated[float | None, typer.Option(help="follower offset ε")] = None,
    pivot_distance: Annotated[
        float | None, typer.Option(help="cam centre to rocker pivot (oscillating)")
    ] = None,
    arm_length: Annotated[
        float | None, typer.Option(help="pivot to roller centre (oscillating)")
    ] = None,
    pivot_side: Annotated[
        str | None, typer.Option(help="right | left: rocker pivot at (+C, 0) or (-C, 0)")
    ] = None,
    rpm: Annotated[float | None, typer.Option(help="cam speed, rev/min (time units)")] = None,
    points: Annotated[int, typer.Option(help="samples over the turn")] = 3600,
    max_pressure_angle: Annotated[float, typer.Option(help="design limit on |φ|, degrees")] = 30.0,
    face_width: Annotated[
        float | None, typer.Option(help="flat face width to check (symmetric face)")
    ] = None,
    size: Annotated[bool, typer.Option("--size", help="also report the smallest cam")] = False,
    min_rho: Annotated[
        float | None, typer.Option(help="least radius of curvature wanted (flat-face --size)")
    ] = None,
    csv: Annotated[Path | None, typer.Option("--csv", help="write the profile table")] = None,
    dxf: Annotated[Path | None, typer.Option("--dxf", help="write the cam outline")] = None,
    unit: Annotated[
        str | None,
        typer.Option("--unit", help="length unit of the numbers (mm, in, ...): the DXF says so"),
    ] = None,
    allow_undercut: Annotated[
        bool, typer.Option(help="write the DXF even if the cam is undercut")
    ] = False,
    svaj_plot: Annotated[Path | None, typer.Option(help="save svaj diagrams (PNG/SVG)")] = None,
    profile_plot: Annotated[Path | None, typer.Option(help="save the cam drawing")] = None,
    json: Annotated[bool, typer.Option("--json", help="print JSON instead of tables")] = False,
    strict: Annotated[bool, typer.Option(help="exit with status 1 if a design rule fails")] = False,
) -> None:
    """Analyse a cam: continuity, peak svaj, pressure angle, curvature, undercut, rules."""
    if ctx.invoked_subcommand is not None:
        return
    outputs = {"--csv": csv, "--dxf": dxf, "--svaj-plot": svaj_plot, "--profile-plot": profile_plot}
    for option, path in outputs.items():
        _check_output(path, option)
    file_segments: list[dict[str, Any]] = []
    file_follower: dict[str, Any] = {}
    file_top: dict[str, Any] = {}
    if table is not None and (segment or program is not None):
        raise InputError("--table", "give the motion as --table, --segment or --program, not two")
    if program is not None:
        if segment:
            raise InputError("--segment", "give segments either with --segment or --program")
        from_machine = _machine_cam(program)
        if from_machine is None:
            file_segments, file_follower, file_top = load_program_file(program)
        else:
            machine_program, file_follower, file_top = from_machine
    elif not segment and table is None:
        raise InputError(
            "--segment", "give the program as --segment options, --program FILE or --table FILE"
        )

    cli_values = {
        "type": follower,
        "prime_radius": prime_radius,
        "roller_radius": roller_radius,
        "base_radius": base_radius,
        "eccentricity": eccentricity,
        "pivot_distance": pivot_distance,
        "arm_length": arm_length,
        "pivot_side": pivot_side,
    }
    fields = _option_names(file_follower, cli_values)
    kind = str(_pick(follower, file_follower, "type", "roller")).lower()
    kind = {"translating": "roller", "flat-faced": "flat", "flat_face": "flat"}.get(kind, kind)
    if kind not in FOLLOWERS:
        raise InputError(fields["type"], f"must be one of {', '.join(FOLLOWERS)}; got {kind!r}")
    oscillating = kind == "oscillating"
    prog: cams.CamProgram | cams.CriticalPathMotion
    if table is not None:
        theta_deg, values = load_table(table)
        if oscillating:
            values = np.radians(values)
        names = {"degree": "--degree", "smoothing": "--smoothing"}
        with _renamed({"theta": "--table", "s": "--table"}, f"{table}: "), _renamed(names):
            prog = cams.CriticalPathMotion.from_degrees(theta_deg, values, degree, smoothing)
    elif program is not None and from_machine is not None:
        prog = machine_program
    elif program is not None:
        segs = [_segment_from_table(t, i, oscillating) for i, t in enumerate(file_segments)]
        prog = _build_program(segs, oscillating, "--program", f"{program}: ")
    else:
        segs = [parse_segment(text, oscillating) for text in segment or []]
        prog = _build_program(segs, oscillating, "--segment", "")
    max_phi_deg = _number(max_pressure_angle, "--max-pressure-angle")
    if not 0.0 < max_phi_deg < 90.0:
        raise InputError(
            "--max-pressure-angle",
            f"must be between 0 and 90 degrees (the notes allow up to 30), got {max_phi_deg:g}",
        )
    limit = float(np.radians(max_phi_deg))

    opts = {
        "prime_radius": _pick(prime_radius, file_follower, "prime_radius"),
        "roller_radius": _pick(roller_radius, file_follower, "roller_radius"),
        "base_radius": _pick(base_radius, file_follower, "base_radius"),
        "eccentricity": _pick(eccentricity, file_follower, "eccentricity"),
        "pivot_distance": _pick(pivot_distance, file_follower, "pivot_distance"),
        "arm_length": _pick(arm_length, file_follower, "arm_length"),
        "pivot_side": _pick(pivot_side, file_follower, "pivot_side", "right"),
    }
    fol = _build_follower(kind, opts, fields)
    speed = _pick(rpm, file_top, "rpm")

    with _renamed({"n": "--points"}):
        motion = _labelled(prog.sample(points), file_top.get("units"), oscillating)
    source = "--table" if table is not None else "--program" if program else "--segment"
    with _renamed({"s": source}):
        profile = _labelled(fol.profile(motion), file_top.get("units"), oscillating)
    continuity = prog.continuity()
    with _renamed({"face_width": "--face-width"}):
        checks = profile.checks(max_pressure_angle=limit, face_width=face_width)
    opts["min_rho"] = min_rho
    sizing = None
    if size:
        with _renamed({"min_radius_of_curvature": "--min-rho", **fields}):
            sizing = _sizing(kind, motion, opts, limit)
    omega = None
    if speed is not None:
        rpm_field = "--rpm" if rpm is not None else f"{program}: rpm"
        omega = 2.0 * np.pi * _positive(rpm_field, speed) / 60.0

    payload = _payload(prog, motion, profile, continuity, checks, sizing, omega, kind)
    length = unit or file_top.get("unit")
    if length and kind != "oscillating":
        payload["length_unit"] = length  # of s, radii, rho; v, a, j per rad; V, A, J per s
    if json:
        print(dumps(payload))
    else:
        _print_report(prog, motion, profile, continuity, checks, sizing, omega, kind, length)

    if csv is not None:
        with _renamed({"path": "--csv"}):
            profile.to_csv(csv)
    if dxf is not None:
        if cannot_be_cut(profile) and not allow_undercut:
            raise ModelError(undercut_refusal(profile, "pass --allow-undercut", see="--size"))
        with _renamed({"path": "--dxf", "unit": "--unit"}):
            profile.to_dxf(dxf, allow_undercut=allow_undercut, unit=unit or file_top.get("unit"))
    if svaj_plot is not None or profile_plot is not None:
        _save_plots(motion, profile, svaj_plot, profile_plot)
    if strict and (not continuity.ok or not all(c.passed for c in checks)):
        raise typer.Exit(1)


def _labelled(result: Any, system: Any, oscillating: bool) -> Any:
    """A motion or profile of a machine file's cam, with the file's units attached.

    Its table (``--csv``, ``to_pandas()``) then names every column with its unit.
    """
    from ..units import with_units

    object.__setattr__(result, "lift", "angle" if oscillating else "length")
    return with_units(result, system)


def _positive(field: str, value: Any) -> float:
    """Return ``value`` as a positive number or raise naming ``field``."""
    out = _number(value, field)
    if not out > 0.0:
        raise InputError(field, f"must be positive, got {out:g}")
    return out


def _sizing(kind: str, motion: cams.Motion, opts: dict[str, Any], limit: float) -> Any:
    if kind == "roller":
        return cams.size_roller(
            motion, opts["roller_radius"], opts.get("eccentricity") or 0.0, limit
        )
    if kind == "flat":
        if opts.get("min_rho") is None:
            raise InputError("--min-rho", "is required to size a flat-faced cam")
        return cams.size_flat_face(motion, opts["min_rho"])
    return cams.size_oscillating_roller(
        motion,
        opts["roller_radius"],
        opts["pivot_distance"],
        opts["arm_length"],
        limit,
        pivot_side=opts["pivot_side"],
    )


def _follower_text(profile: cams.CamProfile, kind: str) -> str:
    if kind == "flat":
        return f"translating flat-faced, base radius Rb = {profile.base_radius:g}"
    return (
        f"{profile.follower}, prime radius Rp = {profile.prime_radius:g}, roller radius "
        f"Rf = {profile.roller_radius:g}, base radius Rb = {profile.base_radius:g}"
    )


def _segments_text(prog: cams.CamProgram | cams.CriticalPathMotion, kind: str) -> list[str]:
    if isinstance(prog, cams.CriticalPathMotion):
        unit = "°" if kind == "oscillating" else ""
        s_shown = np.degrees(prog.s) if kind == "oscillating" else prog.s
        out = [
            f"  critical path motion: {prog.theta.size} points, periodic B-spline of degree "
            f"{prog.degree}" + (f", smoothing (RMS) {prog.smoothing:g}" if prog.smoothing else ""),
            f"  largest deviation from the points: {prog.residual:.3g}",
        ]
        out += [
            f"    θ = {np.degrees(t):8.3f}°  s = {v:.6g}{unit}"
            for t, v in zip(prog.theta, s_shown, strict=True)
        ]
        return out
    out = []
    for k, seg in enumerate(prog.segments, start=1):
        beta = np.degrees(seg.beta)
        if seg.motion == "dwell":
            out.append(f"  {k}. dwell over {beta:g}°")
        else:
            h = f"{np.degrees(seg.h):g}°" if kind == "oscillating" else f"{seg.h:g}"
            out.append(f"  {k}. {seg.motion} {h} over {beta:g}°, {seg.law.name}")
    return out


def _print_report(
    prog: cams.CamProgram | cams.CriticalPathMotion,
    motion: cams.Motion,
    profile: cams.CamProfile,
    continuity: cams.ContinuityReport,
    checks: list[cams.DesignCheck],
    sizing: Any,
    omega: float | None,
    kind: str,
    length: str | None = None,
) -> None:
    deg = np.degrees
    unit = "rad" if kind == "oscillating" else (length or "length")
    print("cam program (angles in degrees):")
    for line in _segments_text(prog, kind):
        print(line)
    for line in continuity.lines():
        print(line)
    peaks = motion.peaks()
    rows = [
        ["s", peaks["s"], f"{unit}"],
        ["v", peaks["v"], f"{unit}/rad"],
        ["a", peaks["a"], f"{unit}/rad²"],
        ["j", peaks["j"], f"{unit}/rad³"],
    ]
    columns = ["quantity", "peak |value|", "unit"]
    if omega is not None:
        timed = motion.in_time(omega).peaks()
        for row, key, u in zip(rows, ("s", "V", "A", "J"), ("", "/s", "/s²", "/s³"), strict=True):
            row.append(timed[key])
            row.append(f"{unit}{u}")
        columns += [f"at {omega * 60 / (2 * np.pi):g} rpm", "unit"]
    print_table("peak follower motion (per radian of cam angle)", columns, rows)
    print(f"follower: {_follower_text(profile, kind)}")
    if kind != "flat":
        print(
            f"pressure angle: max |φ| = {abs(deg(profile.pressure_angle_max)):.2f}° at "
            f"θ = {deg(profile.theta_pressure_angle_max):.1f}°"
        )
        print(
            f"radius of curvature: min convex ρ of pitch curve = {profile.rho_min:.4g} at "
            f"θ = {deg(profile.theta_rho_min):.1f}° (roller radius {profile.roller_radius:g})"
        )
    else:
        print(
            f"radius of curvature: min ρ of cam = {profile.rho_min:.4g} at "
            f"θ = {deg(profile.theta_rho_min):.1f}°; face width ≥ {profile.face_width:.4g}"
        )

    if profile.is_undercut:
        print(
            f"undercut: YES at θ = {format_ranges(profile.undercut_ranges())} (radius of curvature)"
        )
    else:
        print("undercut: none by the radius of curvature")
    if profile.has_surface_loop:
        print(
            f"surface loops: YES, cutting away θ = {format_ranges(profile.surface_loop_ranges())}"
        )
    else:
        print("surface loops: none (the outline does not cross itself)")
    print("design rules:")
    for check in checks:
        print(f"  {check.line()}")
    if sizing is not None:
        print(
            f"smallest cam: prime radius {sizing.prime_radius:.4g}, base radius "
            f"{sizing.base_radius:.4g} (governed by {sizing.governed_by})"
        )


def _payload(
    prog: cams.CamProgram | cams.CriticalPathMotion,
    motion: cams.Motion,
    profile: cams.CamProfile,
    continuity: cams.ContinuityReport,
    checks: list[cams.DesignCheck],
    sizing: Any,
    omega: float | None,
    kind: str,
) -> dict[str, Any]:
    deg = np.degrees
    out: dict[str, Any] = {
        "follower": profile.follower,
        "segments": _segments_payload(prog, kind),
        "continuity": {
            "ok": continuity.ok,
            "discontinuities": [
                {
                    "theta_deg": float(deg(d.theta)),
                    "quantity": d.quantity,
                    "jump": d.jump,
                    "where": d.where,
                }
                for d in continuity.discontinuities
            ],
            "notes": list(continuity.notes),
        },
        "peaks_per_rad": motion.peaks(),
        "base_radius": profile.base_radius,
        "prime_radius": profile.prime_radius,
        "roller_radius": profile.roller_radius,
        "pressure_angle_max_deg": float(deg(abs(profile.pressure_angle_max))),
        "theta_pressure_angle_max_deg": float(deg(profile.theta_pressure_angle_max)),
        "rho_min": profile.rho_min,
        "theta_rho_min_deg": float(deg(profile.theta_rho_min)),
        "undercut": profile.is_undercut,
        "undercut_ranges_deg": [
            [float(deg(a)), float(deg(b))] for a, b in profile.undercut_ranges()
        ],
        "surface_loop": profile.has_surface_loop,
        "surface_loop_ranges_deg": [
            [float(deg(a)), float(deg(b))] for a, b in profile.surface_loop_ranges()
        ],
        "checks": [{"name": c.name, "passed": c.passed, "detail": c.detail} for c in checks],
    }
    if profile.face_width is not None:
        out["face_width_min"] = profile.face_width
    if omega is not None:
        out["rpm"] = omega * 60 / (2 * np.pi)
        out["peaks_time"] = motion.in_time(omega).peaks()
    if sizing is not None:
        out["sizing"] = {
            "prime_radius": sizing.prime_radius,
            "base_radius": sizing.base_radius,
            "governed_by": sizing.governed_by,
        }
    return out


def _segments_payload(
    prog: cams.CamProgram | cams.CriticalPathMotion, kind: str
) -> list[dict[str, Any]] | dict[str, Any]:
    deg = np.degrees
    if isinstance(prog, cams.CriticalPathMotion):
        return {
            "critical_path": True,
            "degree": prog.degree,
            "smoothing": prog.smoothing,
            "residual": prog.residual,
            "theta_deg": deg(prog.theta).tolist(),
            "s": (deg(prog.s) if kind == "oscillating" else prog.s).tolist(),
        }
    return [
        {
            "motion": seg.motion,
            "law": seg.law.name,
            "h": float(deg(seg.h)) if kind == "oscillating" else seg.h,
            "beta_deg": float(deg(seg.beta)),
        }
        for seg in prog.segments
    ]


def load_table(path: Path) -> tuple[np.ndarray, np.ndarray]:
    r"""Read a critical-path table: lines ``theta_deg,s`` (a header and ``#`` comments allowed).

    Examples
    --------
    >>> import tempfile, pathlib
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = pathlib.Path(d) / "t.csv"
    ...     _ = p.write_text("theta_deg,s\n0,0\n90,1\n# peak\n180,2\n")
    ...     load_table(p)[1].tolist()
    [0.0, 1.0, 2.0]
    """
    try:
        text = Path(path).read_text(encoding="utf-8")
    except OSError as exc:
        raise InputError("--table", f"cannot read {path}: {exc.strerror}") from None
    except UnicodeDecodeError as exc:
        raise InputError("--table", f"{path} is not UTF-8 text (byte {exc.start})") from None
    rows: list[tuple[float, float]] = []
    header = False
    for number, line in enumerate(text.splitlines(), start=1):
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        cells = [c.strip() for c in re.split(r"[,;\t ]+", line) if c.strip()]
        try:
            values = [float(c) for c in cells]
        except ValueError:
            if not rows and not header:
                header = True  # the first line that is not numbers: column names
                continue
            raise InputError(
                "--table", f"{path}, line {number}: expected theta_deg,s numbers, got {line!r}"
            ) from None
        if len(values) != 2:
            raise InputError(
                "--table", f"{path}, line {number}: expected two numbers theta_deg,s, got {line!r}"
            )
        rows.append((values[0], values[1]))
    if not rows:
        raise InputError("--table", f"{path} holds no theta_deg,s points")
    data = np.array(rows)
    return data[:, 0], data[:, 1]


def _save_plots(
    motion: cams.Motion, profile: cams.CamProfile, svaj: Path | None, drawing: Path | None
) -> None:
    import matplotlib

    matplotlib.use("Agg")

    if svaj is not None:
        fig = motion.plot()
        _save(fig, svaj, "--svaj-plot")
    if drawing is not None:
        ax = profile.plot()
        _save(ax.figure, drawing, "--profile-plot")


def _save(fig: Any, path: Path, option: str) -> None:
    import matplotlib.pyplot as plt

    try:
        fig.savefig(path, dpi=120, bbox_inches="tight")
    except OSError as exc:
        raise InputError(option, f"cannot write {path}: {exc.strerror}") from None
    except ValueError as exc:  # matplotlib: unknown file format
        formats = ", ".join(sorted(fig.canvas.get_supported_filetypes()))
        raise InputError(option, f"{exc}; use one of {formats}") from None
    finally:
        plt.close(fig)


@cam_app.command("laws")
def laws() -> None:
    """List the motion laws with their peak v and a factors (× h/β, × h/β²)."""
    x = np.linspace(0.0, 1.0, 20001)
    rows = []
    for name in cams.LAW_NAMES:
        if name in ("dwell", "scca"):
            continue
        values = cams.get_law(name)(x, 1.0, 1.0)
        rows.append([name, float(np.abs(values.v).max()), float(np.abs(values.a).max())])
    print_table("motion laws (rise h over β)", ["law", "v_max·β/h", "a_max·β²/h"], rows)
    print("also: scca(b,c,d) with b + c + d = 1, and polynomial laws from the Python API")
