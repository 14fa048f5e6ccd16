"""Tolerance analysis: Monte Carlo over the dimensions of a linkage, beside the stack-up.

``machdyn.tolerance(model, tolerances, ...)`` draws ``samples`` linkages whose
dimensions deviate from the nominal ones within their tolerances (normal, with
the tolerance at ``sigmas`` standard deviations, or uniform within ±tolerance,
per dimension), solves all of them over the sweep at once (the batched
closed forms of :mod:`machdyn.fourbar` and :mod:`machdyn.slidercrank`: link
lengths are columns, input angles a row) and reports, for each output, the
distribution of its deviation from the nominal value at every pose: mean,
standard deviation, envelope (lowest and highest; for a point, the largest
distance), and the distribution over the samples of the peak deviation over
the sweep (coupler-path deviation, output-angle error, peak-torque change),
with the worst sample's dimensions.

A sample that cannot be assembled at some pose of the sweep is *counted*, not
averaged away: ``failed`` and ``failed_fraction``, and a warning when most
samples fail. Each sample keeps the nominal linkage's assembly at every pose
(the sign of ``sin(θ4 − θ3)`` of a four-bar, of ``cos θ3`` of a slider-crank),
so no sample is read on another circuit.

Beside the Monte Carlo: the first-order prediction from
:func:`machdyn.sensitivity` — the standard deviation ``√Σ (∂y/∂p σ_p)²``
(``linear_std``) and the worst-case stack-up ``Σ |∂y/∂p| t_p``
(``worst_case``) — which the Monte Carlo must approach as the tolerances shrink.

Large runs: the samples are drawn and solved in chunks (``chunk`` samples at a
time; each chunk seeds its own generator from ``(seed, chunk index)``, so the
result does not depend on where a chunk runs) and only running sums, the
envelopes and one float32 per sample and output are kept: memory does not grow
with the number of poses. ``scheduler="local"`` runs the chunks on a Dask
``LocalCluster``, an address (``tcp://host:8786``) on any Dask scheduler.

Examples
--------
The notes' HW 6 crank-rocker with every length ±0.01 (3σ):

>>> import numpy as np
>>> from machdyn import FourBar
>>> fb = FourBar(8, 4, 7, 6)
>>> t = tolerance(fb, {"r1": 0.01, "r2": 0.01, "r3": 0.01, "r4": 0.01}, samples=4000)
>>> spread = t.outputs["theta4"]
>>> bool(abs(spread.std.max() / spread.linear_std.max() - 1.0) < 0.05)
True
>>> t.failed, bool(spread.high.max() <= spread.worst_case.max())
(0, True)
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

import numpy as np

from .errors import InputError

__all__ = ["Spread", "Tolerance", "tolerance"]

#: Default samples per chunk (one Dask task each).
CHUNK = 1 << 15
#: Elements (samples × poses) solved at once inside a chunk: the temporaries stay small.
_BLOCK = 1 << 16
_DISTRIBUTIONS = ("normal", "uniform")


@dataclass(frozen=True, eq=False)
class Spread:
    """How one output deviates from its nominal value over the Monte Carlo samples.

    Deviations are ``sample − nominal`` at the same input angle (for angles the
    signed angle between them, radians; for points the complex difference).
    Statistics are over the assembled samples.

    Attributes
    ----------
    name : str
        The output (``theta3``, ``theta4``, ``d``, ``coupler``, ``T12``).
    nominal : ndarray
        Its nominal value at each pose (complex for a point).
    mean : ndarray
        Mean deviation at each pose (complex for a point).
    std : ndarray
        Standard deviation of the deviation; for a point the RMS distance
        ``√E|ΔP|²``.
    low, high : ndarray
        Envelope: the smallest and largest deviation at each pose; for a point
        ``low`` is 0 and ``high`` the largest distance.
    peak : ndarray of float32
        Per assembled sample, the largest ``|deviation|`` over the sweep
        (its distribution: e.g. ``np.quantile(peak, 0.99)``).
    worst : float
        The largest ``peak``; ``worst_dimensions`` are that sample's dimensions.
    worst_dimensions : ndarray
        The dimensions of the worst sample (in the order of ``Tolerance.dimensions``).
    linear_std : ndarray
        First-order prediction of ``std`` from the sensitivities.
    worst_case : ndarray
        First-order worst-case stack-up ``Σ |∂y/∂p| t_p`` at each pose.
    """

    name: str
    nominal: np.ndarray
    mean: np.ndarray
    std: np.ndarray
    low: np.ndarray
    high: np.ndarray
    peak: np.ndarray = field(repr=False)
    worst: float
    worst_dimensions: np.ndarray
    linear_std: np.ndarray
    worst_case: np.ndarray

    def __repr__(self) -> str:
        return (
            f"Spread({self.name}: std ≤ {_top(self.std):.4g} (linear {_top(self.linear_std):.4g}), "
            f"envelope {-_top(-self.low):.4g} … {_top(self.high):.4g}, "
            f"worst case (stack-up) {_top(self.worst_case):.4g})"
        )


def _top(values: np.ndarray) -> float:
    """The largest finite value (NaN when there is none)."""
    finite = values[np.isfinite(values)]
    return float(finite.max()) if finite.size else math.nan


@dataclass(frozen=True, eq=False)
class Tolerance:
    """A Monte Carlo tolerance run (see :func:`tolerance`).

    Attributes
    ----------
    theta : ndarray
        The sweep's input angles (M,).
    dimensions : tuple of str
        The toleranced dimensions.
    nominal_dimensions, tolerances, sigma : ndarray
        Their nominal values, tolerances (±) and standard deviations.
    distributions : tuple of str
        ``"normal"`` or ``"uniform"`` per dimension.
    samples, failed : int
        Samples drawn; those that cannot be assembled at some pose of the sweep.
    outputs : mapping of str to Spread
        Each output's deviation statistics.
    warnings : tuple of str
        What the numbers do not show on their own (most samples failing, ...).
    failures : mapping of str to int
        The unassembled samples by reason (for a Linkage: the first group that
        does not close, "a length ≤ 0", or a toggle), most frequent first.
    """

    theta: np.ndarray
    dimensions: tuple[str, ...]
    nominal_dimensions: np.ndarray
    tolerances: np.ndarray
    sigma: np.ndarray
    distributions: tuple[str, ...]
    samples: int
    failed: int
    outputs: Mapping[str, Spread]
    warnings: tuple[str, ...] = ()
    failures: Mapping[str, int] = field(default_factory=lambda: MappingProxyType({}))

    @property
    def failed_fraction(self) -> float:
        """Fraction of the samples that cannot be assembled over the whole sweep."""
        return self.failed / self.samples

    def __repr__(self) -> str:
        lines = [
            f"Tolerance({self.samples:,} samples x {self.theta.size} poses, "
            f"{self.failed:,} unassembled ({100 * self.failed_fraction:.3g} %))"
        ]
        lines += [f"  unassembled: {r}: {c:,}" for r, c in self.failures.items()]
        lines += [f"  {s!r}" for s in self.outputs.values()]
        lines += [f"  warning: {w}" for w in self.warnings]
        return "\n".join(lines)


def tolerance(
    model: Any,
    tolerances: Mapping[str, Any],
    theta2: Any = None,
    *,
    samples: int = 100_000,
    distribution: str = "normal",
    sigmas: float = 3.0,
    seed: int = 0,
    outputs: Any = None,
    form: int = 1,
    branch: int | None = None,
    omega2: float = 1.0,
    alpha2: float = 0.0,
    mass: Any = None,
    inertia: Any = None,
    cg: Any = None,
    gravity: float = 0.0,
    load: float = 0.0,
    chunk: int = CHUNK,
    scheduler: str | None = None,
    workers: int | None = None,
) -> Tolerance:
    """Monte Carlo tolerance analysis of a FourBar, SliderCrank or drawn Linkage over a sweep.

    Parameters
    ----------
    model : FourBar, SliderCrank or Linkage
        The nominal linkage. A :class:`~machdyn.linkage.Linkage` (one driven
        crank, RRR dyads, RRP dyads on straight ground guides: four-bars, Watt
        and Stephenson six-bars, slider-cranks and six-bars with a slider) is
        solved by the family solver (:mod:`machdyn._linkage_family`).
    tolerances : mapping
        ``{dimension: t}`` (±t) or ``{dimension: (t, "uniform")}``; dimensions
        as in :func:`machdyn.sensitivity` (``r1`` … ``r4``, ``p``, ``delta`` of a
        four-bar; ``crank``, ``coupler``, ``offset``, ``p``, ``delta`` of a
        slider-crank), in the model's units (``delta`` in radians). Of a
        Linkage: ``"P.x"``/``"P.y"`` (a drawn point, in every link carrying it),
        ``"F-S"`` (a link's first two points: its length, the ground's too),
        ``"Q.p"``/``"Q.delta"`` (a further point's distance from the link's
        first point and angle from its first → second line: the coupler-point
        parameters), ``"guide.angle"``/``"guide.offset"`` (a ground slider's
        guide line, named as its joint); an unknown name is refused with the
        list of valid ones. A Linkage's outputs include ``"length.guide"``,
        the slide displacement.
    theta2 : array_like, optional
        Input angles of the sweep, radians; default 360 poses over a turn (or
        inside the input's range when it rocks; a Linkage: a turn from its
        drawn crank angle).
    samples : int
        Number of Monte Carlo linkages.
    distribution : {"normal", "uniform"}
        The default distribution; ``sigmas``: a normal tolerance is this many
        standard deviations (3: ±t holds 99.73 %).
    seed : int
        Seed of the random numbers (chunk ``k`` draws from ``(seed, k)``).
    outputs : sequence of str, optional
        Default: ``theta3``, ``theta4`` (four-bar) or ``theta3``, ``d``
        (slider-crank), ``coupler`` when the model has a coupler point, and
        ``T12`` (four-bar) when ``mass`` is given. Of a Linkage:
        ``theta.<link>``, ``point.<P>`` (moving points) and
        ``torque.<driver>`` (by the power balance, from the links' own masses,
        at ``omega2``, ``alpha2``, ``gravity``; default when a link has mass).
    form, branch : optional
        The assembly, as in the model's ``solve``.
    omega2, alpha2, mass, inertia, cg, gravity, load : optional
        For ``T12``, as in :func:`machdyn.sensitivity`.
    chunk : int
        Samples per chunk (the memory of one chunk is bounded by it).
    scheduler : str, optional
        ``None``: in this process; ``"local"``: a Dask ``LocalCluster`` of
        ``workers`` processes; an address such as ``tcp://host:8786``.

    Returns
    -------
    Tolerance

    Raises
    ------
    InputError
        A negative or non-finite tolerance, an unknown dimension or output, a
        sweep where the nominal linkage does not assemble, bad counts.

    Examples
    --------
    A slider-crank's stroke error from a ±0.1 mm crank (uniform), in mm:

    >>> from machdyn import SliderCrank
    >>> t = tolerance(SliderCrank(50.0, 200.0), {"crank": (0.1, "uniform")}, samples=2000)
    >>> round(float(t.outputs["d"].high.max()), 3)   # ∂d/∂crank ≤ 1 (= 1 at the dead centres)
    0.1

    A drawn four-bar's coupler point P, crank and coupler ±0.01, P's angle ±0.002 rad:

    >>> from machdyn.linkage import Linkage
    >>> lk = (Linkage({"O2": 0, "O4": 8, "A": 4, "B": 7.625 + 5.7547j, "P": 5 + 3j})
    ...       .ground("O2", "O4").link("crank", "O2", "A").link("coupler", "A", "B", "P")
    ...       .link("rocker", "O4", "B").drive("crank"))
    >>> t = tolerance(lk, {"O2-A": 0.01, "A-B": 0.01, "P.delta": 0.002}, samples=4000)
    >>> s = t.outputs["point.P"]
    >>> bool(abs(s.std.max() / s.linear_std.max() - 1.0) < 0.05), t.failed
    (True, 0)
    """
    from .linkage import Linkage

    if isinstance(model, Linkage):
        from . import _linkage_tolerance as family

        if mass is not None or inertia is not None or cg is not None or load or branch:
            raise InputError(
                "model", "a Linkage carries its own masses (link(..., mass=, inertia=, cg=)); "
                "mass/inertia/cg/load/branch are for FourBar and SliderCrank"
            )  # fmt: skip
        ljob = family.build(model, tolerances, theta2, samples, distribution, sigmas, seed,
                            outputs, omega2, alpha2, gravity, chunk)  # fmt: skip
        return family.finish(ljob, _run(ljob, scheduler, workers, family.chunk))
    job = _Job.build(
        model, tolerances, theta2, samples, distribution, sigmas, seed, outputs,
        form, branch, omega2, alpha2, (mass, inertia, cg, gravity, load), chunk,
    )  # fmt: skip
    parts = _run(job, scheduler, workers)
    return _combine(job, parts)


# --------------------------------------------------------------------------------------
# The job: everything a chunk needs (picklable, for Dask workers).


@dataclass(frozen=True)
class _Job:
    kind: str  # "fourbar" | "slidercrank"
    names: tuple[str, ...]  # all dimensions of the model
    nominal: np.ndarray  # their nominal values
    index: np.ndarray  # which dimensions are toleranced
    tol: np.ndarray
    sigma: np.ndarray
    uniform: np.ndarray  # bool per toleranced dimension
    theta: np.ndarray
    sign: np.ndarray  # the nominal assembly at each pose
    outputs: tuple[str, ...]
    nominal_values: dict
    torque: tuple | None
    rates: tuple[float, float]
    samples: int
    chunk: int
    seed: int
    linear: dict

    @classmethod
    def build(cls, model, tolerances, theta2, samples, distribution, sigmas, seed, outputs,
              form, branch, omega2, alpha2, props, chunk) -> _Job:  # fmt: skip
        from ._validate import choice, finite_scalar, in_range, integer
        from .fourbar import FourBar
        from .sensitivity import sensitivity
        from .slidercrank import SliderCrank

        if isinstance(model, FourBar):
            kind, names = "fourbar", ("r1", "r2", "r3", "r4")
            nominal = list(model.lengths)
            if model.coupler is not None:
                names += ("p", "delta")
                nominal += list(model.coupler)
        elif isinstance(model, SliderCrank):
            kind, names = "slidercrank", ("crank", "coupler", "offset")
            nominal = [model.a, model.b, model.c]
            if model.point is not None:
                names += ("p", "delta")
                nominal += list(model.point)
        else:
            raise InputError(
                "model", f"tolerance takes a FourBar or SliderCrank; got {type(model).__name__}"
            )
        samples = integer("samples", samples, minimum=1, maximum=10**10)
        chunk = integer("chunk", chunk, minimum=1, maximum=1 << 24)
        seed = integer("seed", seed, minimum=0, maximum=2**63)
        distribution = choice("distribution", distribution, _DISTRIBUTIONS)
        sigmas = in_range("sigmas", sigmas, 0.1, 100.0)
        size = max(abs(v) for v in nominal[:4])
        index, tol, uniform = _tolerances(tolerances, names, distribution, size)
        sigma = np.where(uniform, tol / math.sqrt(3.0), tol / sigmas)
        theta = _sweep(model, theta2, form)
        mass = props[0]
        has_point = len(names) > (4 if kind == "fourbar" else 3)
        default = (("theta3", "theta4") if kind == "fourbar" else ("theta3", "d")) + (
            ("coupler",) if has_point else ()
        )
        if kind == "fourbar" and mass is not None:
            default += ("T12",)
        outputs = _outputs(outputs, default, kind, mass is not None)
        w2 = finite_scalar("omega2", omega2, "radian / second")
        a2 = finite_scalar("alpha2", alpha2, "radian / second ** 2")
        s = sensitivity(
            model, theta, omega2=w2, alpha2=a2, form=form, branch=branch,
            **(dict(zip(("mass", "inertia", "cg", "gravity", "load"), props, strict=True))
               if mass is not None else {}),
        )  # fmt: skip
        if not s.ok.all():
            bad = int(np.argmin(s.ok))
            raise InputError(
                "theta2",
                f"the nominal linkage is not solved at {math.degrees(theta[bad]):.6g} deg "
                f"({s.reasons[s.status[bad]]}); sweep inside its input range",
            )
        if kind == "fourbar":
            sign = np.where(np.sin(s.nominal["theta4"] - s.nominal["theta3"]) < 0, -1.0, 1.0)
        else:
            sign = np.where(np.cos(s.nominal["theta3"]) < 0, -1.0, 1.0)
        linear = {}
        for name in outputs:
            d = s.derivative[name][:, index]
            linear[name] = (
                np.sqrt(np.sum(np.abs(d * sigma) ** 2, axis=-1)),
                np.sum(np.abs(d * tol), axis=-1),
            )
        torque = None
        if "T12" in outputs:  # mass properties already checked by sensitivity
            torque = (*props, model.length_unit)
        return cls(
            kind, names, np.asarray(nominal, dtype=float), index, tol, sigma, uniform, theta,
            sign, outputs, {n: s.nominal[n] for n in outputs}, torque, (w2, a2), samples,
            chunk, seed, linear,
        )  # fmt: skip


def _tolerances(
    tolerances: Any,
    names: tuple[str, ...],
    default: str,
    size: float,
    *,
    angles: Any = ("delta",),
    size_is: str = "the longest link",
):
    """Indices, tolerances and uniform flags of ``{dimension: t | (t, distribution)}``.

    ``angles`` names the dimensions that are angles (bounded by π); the others are
    bounded by ``size`` (``size_is`` says what it is in the message).
    """
    from ._validate import choice, nonnegative

    if not isinstance(tolerances, Mapping) or not tolerances:
        raise InputError(
            "tolerances", f"give a mapping {{dimension: tolerance}} of some of {', '.join(names)}"
        )
    index, tol, uniform = [], [], []
    for name, value in tolerances.items():
        if not isinstance(name, str) or name not in names:
            raise InputError(
                "tolerances", f"unknown dimension {name!r:.40}; known: {', '.join(names)}"
            )
        how = default
        if isinstance(value, tuple | list):
            if len(value) != 2:
                raise InputError(f"tolerances[{name}]", "give t or (t, 'normal' | 'uniform')")
            value, how = value
            how = choice(f"tolerances[{name}]", how, _DISTRIBUTIONS)
        t = nonnegative(f"tolerances[{name}]", value)
        limit, what = (math.pi, "pi radians") if name in angles else (size, size_is)
        if not t <= limit:
            raise InputError(
                f"tolerances[{name}]", f"{t:.6g} is larger than {what} ({limit:.6g}): give ±t"
            )
        index.append(names.index(name))
        tol.append(t)
        uniform.append(how == "uniform")
    return np.array(index), np.array(tol), np.array(uniform)


def _sweep(model: Any, theta2: Any, form: int) -> np.ndarray:
    from ._validate import choice, finite_array

    choice("form", form, (1, 2))
    if theta2 is None:
        from .fourbar import FourBar

        if isinstance(model, FourBar):
            rng = model.input_range(form)
            limits = None if rng.full_turn else (rng.lo, rng.hi)
        else:
            limits = model.input_range()
        if limits is None:
            return np.linspace(0.0, 2.0 * np.pi, 360, endpoint=False)
        return np.linspace(*limits, 362)[1:-1]  # inside the toggles
    theta = finite_array("theta2", theta2, "radian").ravel()
    if theta.size == 0:
        raise InputError("theta2", "give at least one input angle")
    return theta


def _outputs(outputs: Any, default: tuple[str, ...], kind: str, has_mass: bool):
    if outputs is None:
        return default
    if isinstance(outputs, str):
        outputs = (outputs,)
    known = default + (("T12",) if kind == "fourbar" and not has_mass else ())
    try:
        chosen = tuple(outputs)
    except TypeError:
        raise InputError("outputs", f"give a list of names among {', '.join(default)}") from None
    for name in chosen:
        if not isinstance(name, str) or name not in default:
            needs_mass = isinstance(name, str) and name == "T12" and name in known
            hint = " (T12 needs mass=, inertia=, cg=)" if needs_mass else ""
            raise InputError(
                "outputs", f"unknown output {name!r:.40}{hint}; known: {', '.join(default)}"
            )
    if not chosen:
        raise InputError("outputs", "give at least one output")
    return chosen


# --------------------------------------------------------------------------------------
# Chunks: draw, solve, accumulate.


def _draw(job: _Job, k: int, n: int) -> np.ndarray:
    """The dimensions of chunk ``k``'s ``n`` samples (n, all dimensions)."""
    rng = np.random.default_rng([job.seed, k])
    dims = np.repeat(job.nominal[None, :], n, axis=0)
    for i, t, s, u in zip(job.index, job.tol, job.sigma, job.uniform, strict=True):
        dims[:, i] += rng.uniform(-t, t, n) if u else s * rng.standard_normal(n)
    return dims


def _solve(job: _Job, dims: np.ndarray) -> tuple[dict[str, np.ndarray], np.ndarray]:
    """Deviations of each output for the rows of ``dims`` at every pose, and ``ok`` per row."""
    theta = job.theta
    c2, s2 = np.cos(theta), np.sin(theta)
    cols = [dims[:, i : i + 1] for i in range(dims.shape[1])]
    nom = job.nominal_values
    out: dict[str, np.ndarray] = {}
    if job.kind == "fourbar":
        from .fourbar import OK, _unit_vectors

        r1, r2, r3, r4 = cols[:4]
        with np.errstate(invalid="ignore", divide="ignore"):
            bad = (r1 <= 0) | (r2 <= 0) | (r3 <= 0) | (r4 <= 0)
            e3x, e3y, e4x, e4y, status = _unit_vectors(
                np.abs(r1), np.abs(r2), np.abs(r3), np.abs(r4), c2, s2, job.sign
            )
        ok = np.all(status == OK, axis=1) & ~bad[:, 0]
    else:
        a, b, c = cols[:3]
        with np.errstate(invalid="ignore", divide="ignore"):
            e3y = (a * s2 - c) / b
            ok = np.all(np.abs(e3y) <= 1.0, axis=1) & (a[:, 0] > 0) & (b[:, 0] > 0)
            e3x = job.sign * np.sqrt(1.0 - e3y * e3y)  # the nominal's sign of cos θ3
        e4x = e4y = None
    for name in job.outputs:
        if name in ("theta3", "theta4"):
            ex, ey = (e3x, e3y) if name == "theta3" else (e4x, e4y)
            nc, ns = np.cos(nom[name]), np.sin(nom[name])
            out[name] = np.arctan2(ey * nc - ex * ns, ex * nc + ey * ns)  # angle from nominal
        elif name == "d":
            out[name] = cols[0] * c2 - cols[1] * e3x - nom["d"]
        elif name == "coupler":
            p, delta = cols[-2], cols[-1]
            pr, pi = p * np.cos(delta), p * np.sin(delta)
            if job.kind != "fourbar":
                pr, pi = -pr, -pi  # the notes' slider-crank point: −p e^{jδ} e^{jθ3} from A
            crank = cols[1] if job.kind == "fourbar" else cols[0]
            dev = np.empty(np.broadcast_shapes(e3x.shape, c2.shape), dtype=complex)
            dev.real = crank * c2 + pr * e3x - pi * e3y - nom["coupler"].real
            dev.imag = crank * s2 + pr * e3y + pi * e3x - nom["coupler"].imag
            out[name] = dev
        elif name == "T12":
            theta3, theta4 = np.arctan2(e3y, e3x), np.arctan2(e4y, e4x)
            out[name] = _torque(job, cols, theta3, theta4) - nom["T12"]
    return out, ok


def _torque(job: _Job, cols: list[np.ndarray], theta3: Any, theta4: Any) -> np.ndarray:
    """``T12`` of each row by virtual work (the sensitivity's duals, with no directions)."""
    from ._dual import lift
    from .sensitivity import fourbar_outputs

    lengths = tuple(lift(c, 0) for c in cols[:4])
    coupler = tuple(lift(c, 0) for c in cols[4:6]) if len(cols) > 4 else None
    w2, a2 = job.rates
    values = fourbar_outputs(lengths, coupler, job.theta, theta3, theta4, w2, a2, job.torque)
    return values["T12"].v


def _chunk(job: _Job, k: int) -> dict:
    """Running sums, envelopes, per-sample peaks and the worst sample of chunk ``k``."""
    n = min(job.chunk, job.samples - k * job.chunk)
    dims = _draw(job, k, n)
    m = job.theta.size
    rows = max(1, _BLOCK // m)
    acc = {name: _Acc(m, n, np.iscomplexobj(job.nominal_values[name])) for name in job.outputs}
    ok_all = np.zeros(n, dtype=bool)
    for i in range(0, n, rows):
        sl = slice(i, min(n, i + rows))
        dev, ok = _solve(job, dims[sl])
        ok_all[sl] = ok
        for name, value in dev.items():
            acc[name].add(value[ok], np.flatnonzero(ok) + i)
    part = {"k": k, "n": n, "assembled": int(ok_all.sum())}
    for name, a in acc.items():
        part[name] = a.result(dims)
    return part


#: Per-sample peaks are kept in float32 (half the memory) unless one is larger than this.
_FLOAT32_MAX = float(np.finfo(np.float32).max)


class _Acc:
    """Statistics of one output's deviations, accumulated block by block."""

    def __init__(self, m: int, n: int, is_point: bool) -> None:
        self.point = is_point
        self.total = np.zeros(m, dtype=complex if is_point else float)
        self.squares = np.zeros(m)
        self.low = np.full(m, np.inf)
        self.high = np.full(m, -np.inf)
        self.peak = np.full(n, np.nan, dtype=np.float32)

    def add(self, dev: np.ndarray, rows: np.ndarray) -> None:
        if not rows.size:
            return
        size = np.abs(dev)
        self.total += dev.sum(axis=0)
        self.squares += np.sum(size * size, axis=0)
        if self.point:
            self.high = np.maximum(self.high, size.max(axis=0))
            self.low = np.zeros_like(self.low)
        else:
            self.low = np.minimum(self.low, dev.min(axis=0))
            self.high = np.maximum(self.high, dev.max(axis=0))
        peak = size.max(axis=1)
        if self.peak.dtype == np.float32 and np.any(peak > _FLOAT32_MAX):  # kept, not inf
            self.peak = self.peak.astype(float)
        self.peak[rows] = peak

    def result(self, dims: np.ndarray) -> dict:
        peak = self.peak[np.isfinite(self.peak)]
        worst = np.nan
        worst_dims = np.full(dims.shape[1], np.nan)
        if peak.size:
            w = int(np.nanargmax(self.peak))
            worst, worst_dims = float(self.peak[w]), dims[w]
        return dict(total=self.total, squares=self.squares, low=self.low, high=self.high,
                    peak=peak, worst=worst, worst_dims=worst_dims)  # fmt: skip


def _run(job: Any, scheduler: str | None, workers: int | None, run: Any = None) -> list[dict]:
    from ._validate import integer, text

    run = _chunk if run is None else run
    chunks = range(-(-job.samples // job.chunk))
    if workers is not None:
        workers = integer("workers", workers, minimum=1, maximum=1024)
    if scheduler is None:
        return [run(job, k) for k in chunks]
    scheduler = text("scheduler", scheduler)
    from .synthesis.atlas_dask import map_chunks

    parts = list(map_chunks(run, [(job, k) for k in chunks], scheduler, workers))
    return sorted(parts, key=lambda p: p["k"])


def _combine(job: Any, parts: list[dict]) -> Tolerance:
    assembled = sum(p["assembled"] for p in parts)
    failed = job.samples - assembled
    outputs = {}
    for name in job.outputs:
        got = [p[name] for p in parts]
        total = sum(g["total"] for g in got)
        squares = sum(g["squares"] for g in got)
        low = np.min([g["low"] for g in got], axis=0)
        high = np.max([g["high"] for g in got], axis=0)
        peak = np.concatenate([g["peak"] for g in got])
        best = max(got, key=lambda g: -np.inf if np.isnan(g["worst"]) else g["worst"])
        with np.errstate(invalid="ignore", divide="ignore"):
            mean = total / assembled if assembled else total * np.nan
            if np.iscomplexobj(total):
                std = np.sqrt(squares / assembled) if assembled else squares * np.nan
            else:
                var = squares / assembled - mean * mean if assembled else squares * np.nan
                std = np.sqrt(np.maximum(var * assembled / max(assembled - 1, 1), 0.0))
        if not assembled:
            low, high = low * np.nan, high * np.nan
        outputs[name] = Spread(
            name, job.nominal_values[name], mean, std, low, high, peak, best["worst"],
            best["worst_dims"][job.index], *job.linear[name],
        )  # fmt: skip
    warnings = []
    if failed and assembled == 0:
        warnings.append("no sample can be assembled over the sweep: the statistics are NaN")
    elif failed > job.samples / 2:
        warnings.append(
            f"most samples ({failed:,} of {job.samples:,}) cannot be assembled over the sweep: "
            "the statistics describe only the assembled minority"
        )
    elif failed:
        warnings.append(f"{failed:,} of {job.samples:,} samples cannot be assembled over the sweep")
    return Tolerance(
        theta=job.theta,
        dimensions=tuple(job.names[i] for i in job.index),
        nominal_dimensions=job.nominal[job.index],
        tolerances=job.tol,
        sigma=job.sigma,
        distributions=tuple("uniform" if u else "normal" for u in job.uniform),
        samples=job.samples,
        failed=failed,
        outputs=MappingProxyType(outputs),
        warnings=tuple(warnings),
        failures=MappingProxyType({"cannot be assembled over the sweep": failed} if failed else {}),
    )
