"""Monte Carlo tolerance analysis of a drawn Linkage, on the family solver.

:func:`machdyn.tolerance` hands a :class:`~machdyn.linkage.Linkage` here. The
samples' dimensions are drawn as for the four-bar (:mod:`machdyn.tolerance`:
chunks seeded from ``(seed, chunk)``, running sums, envelopes, one float32 per
sample and output), each chunk solved by :class:`machdyn._linkage_family.Family`
(samples × poses at once). A sample that cannot be assembled somewhere in the
sweep is counted under the first group that does not close (or "a length
≤ 0", or a toggle where the rates are undefined), in ``Tolerance.failures``.

The linearised prediction beside the Monte Carlo (``linear_std``,
``worst_case``) uses the exact first derivatives of every output with respect
to every toleranced dimension at the nominal linkage: the family solver run
once with those dimensions as duals (for the drawn coordinates they agree
with the implicit differentiation of the constraints, and for a four-bar loop
with the FourBar's, which the tests check).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from types import MappingProxyType
from typing import Any

import numpy as np

from ._linkage_family import Family
from .errors import InputError

__all__: list[str] = []

#: Samples × poses solved at once inside a chunk.
_BLOCK = 1 << 16
_DISTRIBUTIONS = ("normal", "uniform")
LENGTH_REASON = "a length ≤ 0"
TOGGLE_REASON = "a singular pose (toggle) in the sweep: rates undefined"


@dataclass(frozen=True)
class LinkageJob:
    """Everything a chunk needs (picklable, for Dask workers)."""

    family: Family
    names: tuple[str, ...]
    nominal: np.ndarray
    index: np.ndarray
    tol: np.ndarray
    sigma: np.ndarray
    uniform: np.ndarray
    theta: np.ndarray
    rates: tuple[float, float]
    gravity: float
    outputs: tuple[str, ...]
    nominal_values: dict
    samples: int
    chunk: int
    seed: int
    linear: dict

    @property
    def order(self) -> int:
        """The rates the outputs need (2 for the torque)."""
        return 2 if any(o.startswith("torque.") for o in self.outputs) else 0


def build(lk: Any, tolerances: Any, theta2: Any, samples: Any, distribution: Any, sigmas: Any,
          seed: Any, outputs: Any, omega2: Any, alpha2: Any, gravity: Any,
          chunk: Any) -> LinkageJob:  # fmt: skip
    """Check the request and prepare the job (nominal outputs, linear prediction)."""
    from ._validate import choice, finite_scalar, in_range, integer, nonnegative

    family = Family(lk)
    samples = integer("samples", samples, minimum=1, maximum=10**10)
    chunk = integer("chunk", chunk, minimum=1, maximum=1 << 24)
    seed = integer("seed", seed, minimum=0, maximum=2**63)
    distribution = choice("distribution", distribution, _DISTRIBUTIONS)
    sigmas = in_range("sigmas", sigmas, 0.1, 100.0)
    size = _size(family)
    from .tolerance import _tolerances

    angles = {
        n for n, d in zip(family.names, family.dims, strict=True) if d.kind in ("delta", "angle")
    }
    index, tol, uniform = _tolerances(
        tolerances, family.names, distribution, size, angles=angles, size_is="the linkage's size"
    )
    sigma = np.where(uniform, tol / math.sqrt(3.0), tol / sigmas)
    w2 = finite_scalar("omega2", omega2, "radian / second")
    a2 = finite_scalar("alpha2", alpha2, "radian / second ** 2")
    g = nonnegative("gravity", gravity)
    chosen = _outputs(outputs, family)
    if any(o.startswith("torque.") for o in chosen) and w2 == 0.0:
        raise InputError("omega2", "the driver's torque by the power balance needs a speed ≠ 0")
    theta = _sweep(lk, family, theta2)
    job = LinkageJob(family, family.names, family.nominal, index, tol, sigma, uniform, theta,
                     (w2, a2), g, chosen, {}, samples, chunk, seed, {})  # fmt: skip
    values, ok, reason = _evaluate(job, family.nominal[None, :])
    if not ok[0]:
        raise InputError(
            "theta2",
            f"the nominal linkage is not solved over the sweep ({reason[0]}); sweep inside its "
            "input range",
        )
    drawn = lk.solve(theta)  # the drawn mechanism's own flags: a pose on its other circuit
    if not np.all(drawn.ok):
        bad = int(np.argmin(drawn.ok))
        raise InputError(
            "theta2",
            f"the nominal linkage is not solved at {math.degrees(theta[bad]):.6g} deg "
            f"({drawn.reason[bad]}); sweep inside its input range",
        )
    nominal = {
        name: np.unwrap(np.angle(v[0])) if name.startswith("theta.") else v[0]
        for name, v in values.items()
    }
    job = replace(job, nominal_values=nominal)
    return replace(job, linear=_linear(job))


def _size(family: Family) -> float:
    z = np.array(list(family.points.values()))
    return float(np.abs(z - z.mean()).max()) or 1.0


def _outputs(outputs: Any, family: Family) -> tuple[str, ...]:
    known = family.output_names()
    if outputs is None:
        has_mass = any(m or i for m, i, _ in family.mass.values())
        return tuple(o for o in known if has_mass or not o.startswith("torque."))
    if isinstance(outputs, str):
        outputs = (outputs,)
    try:
        chosen = tuple(outputs)
    except TypeError:
        raise InputError("outputs", f"give a list of names among {', '.join(known)}") from None
    for name in chosen:
        if not isinstance(name, str) or name not in known:
            raise InputError("outputs", f"unknown output {name!r:.40}; known: {', '.join(known)}")
    if not chosen:
        raise InputError("outputs", "give at least one output")
    return chosen


def _sweep(lk: Any, family: Family, theta2: Any) -> np.ndarray:
    from ._validate import finite_array

    if theta2 is None:
        start = float(lk.drawn_inputs[family.driver])
        return start + np.linspace(0.0, 2.0 * np.pi, 360, endpoint=False)
    theta = finite_array("theta2", theta2, "radian").ravel()
    if theta.size == 0:
        raise InputError("theta2", "give at least one driver value")
    return theta


# --------------------------------------------------------------------------------------
# Solving rows of dimensions.


def _evaluate(job: LinkageJob, dims: np.ndarray) -> tuple[dict, np.ndarray, np.ndarray]:
    """Each output's value for the rows of ``dims`` over the sweep, ``ok`` and reasons per row."""
    fam = job.family
    geo = fam.geometry(dims)
    w2, a2 = job.rates
    st, closes = fam.solve(geo, [job.theta, w2, a2], job.order)
    values = {}
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        for name in job.outputs:
            values[name] = fam.value(st, name, job.gravity, w2)
        finite = np.ones(geo.bad.size, dtype=bool)
        for v in values.values():
            finite &= np.all(np.isfinite(v), axis=1)
    reason = np.full(geo.bad.size, "", dtype=object)
    for g in range(closes.shape[0] - 1, -1, -1):  # the first group that fails wins
        reason[~closes[g]] = f"{fam.group_names[g]} does not close"
    reason[geo.bad] = LENGTH_REASON
    ok = closes.all(axis=0) & ~geo.bad
    reason[ok & ~finite] = TOGGLE_REASON
    return values, ok & finite, reason


def _deviation(job: LinkageJob, name: str, value: np.ndarray) -> np.ndarray:
    nominal = job.nominal_values[name]
    if name.startswith("theta."):
        return np.angle(value * np.exp(-1j * nominal))
    return value - nominal


def _linear(job: LinkageJob) -> dict:
    """Exact first derivatives at the nominal linkage: RSS std and worst-case stack-up.

    The family solver runs once with the toleranced dimensions as duals
    (forward differentiation through the closed-form dyads).
    """
    from ._dual import Dual

    fam = job.family
    k, m = job.index.size, job.theta.size
    w2, a2 = job.rates
    with np.errstate(invalid="ignore", divide="ignore"):
        st, _ = fam.solve(fam.seeded(job.index), [job.theta, w2, a2], job.order)
        out = {}
        for name in job.outputs:
            value = fam.value(st, name, job.gravity, w2)
            if not isinstance(value, Dual):  # it does not depend on these dimensions
                d = np.zeros((1, m, k))
            elif name.startswith("theta."):
                d = (value.d / value.v[..., None]).imag
            else:
                d = value.d
            d = np.broadcast_to(d, (1, m, k))[0].T  # (k, m)
            scaled_std = np.abs(d * job.sigma[:, None])
            scaled_tol = np.abs(d * job.tol[:, None])
            out[name] = (np.sqrt(np.sum(scaled_std**2, axis=0)), np.sum(scaled_tol, axis=0))
    return out


def chunk(job: LinkageJob, k: int) -> dict:
    """Running sums, envelopes, per-sample peaks and failure reasons of chunk ``k``."""
    from .tolerance import _Acc, _draw

    n = min(job.chunk, job.samples - k * job.chunk)
    dims = _draw(job, k, n)
    m = job.theta.size
    rows = max(1, _BLOCK // m)
    acc = {name: _Acc(m, n, name.startswith("point.")) for name in job.outputs}
    ok_all = np.zeros(n, dtype=bool)
    failures: dict[str, int] = {}
    for i in range(0, n, rows):
        sl = slice(i, min(n, i + rows))
        values, ok, reason = _evaluate(job, dims[sl])
        ok_all[sl] = ok
        for r in reason[~ok]:
            failures[r] = failures.get(r, 0) + 1
        for name, value in values.items():
            acc[name].add(_deviation(job, name, value[ok]), np.flatnonzero(ok) + i)
    part = {"k": k, "n": n, "assembled": int(ok_all.sum()), "failures": failures}
    for name, a in acc.items():
        part[name] = a.result(dims)
    return part


def finish(job: LinkageJob, parts: list[dict]) -> Any:
    """The :class:`~machdyn.tolerance.Tolerance` of the chunks, with failures by reason."""
    from .tolerance import _combine

    result = _combine(job, parts)
    failures: dict[str, int] = {}
    for p in parts:
        for r, c in p["failures"].items():
            failures[r] = failures.get(r, 0) + c
    ordered = dict(sorted(failures.items(), key=lambda rc: -rc[1]))
    return replace(result, failures=MappingProxyType(ordered))
