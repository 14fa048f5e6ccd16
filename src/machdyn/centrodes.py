"""Centrodes: the paths of an instant centre, and their rolling; non-circular gears.

The second notes: "A centrode is the curve defined by the locations of the
instant center over the range of motion of a mechanism. Each possible instant
center can create two centrodes, found by considering the motion relative to
each of the two links defining the instant center. One centrode will be called
the fixed centrode and one a moving centrode. The centrodes can then recreate
the motion of the fourbar by rolling (without slip) in contact with each other.
As an example, fourbars can be used to define the profile for non-circular
gears (for example elliptical gears)." (Norton, *Design of Machinery*, sec. 6.5.)

For the motion of link ``j`` relative to link ``i`` the instant centre
``I_ij`` traces the *fixed centrode* in the frame of ``i`` and the *moving
centrode* in the frame of ``j``. A link's frame has its origin at the link's
first point and its x axis along its ``theta`` (the ground's frame is the
world). :meth:`Centrodes.roll` rebuilds the motion of ``j`` relative to ``i``
from the two curves alone — the moving centrode placed so that it touches the
fixed one at the common point, tangent to it, after rolling the same arc
length (no slip) — for comparison with the solved motion.

Two links pivoted on the ground and coupled by non-circular gears move as the
linkage moves them when the gears' pitch curves are the two centrodes of
their relative instant centre (:func:`gear_pitch_curves`): the pitch point
``I_ab`` lies on the line of centres, so ``ω_b/ω_a = −r_a/r_b`` for external
gears.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from ._summary import Summarized
from ._validate import finite_array, integer
from .errors import InputError

__all__ = ["Centrodes", "PitchCurves", "RolledMotion", "centrodes", "gear_pitch_curves"]

#: Below this pole speed (relative to the curve's size per unit parameter) the
#: tangent of a centrode is undefined (a cusp): the rolled pose is not rebuilt there.
_STILL_POLE = 1e-7


@dataclass(frozen=True)
class RolledMotion(Summarized):
    """The motion of the moving link rebuilt by rolling its centrode on the fixed one.

    Attributes
    ----------
    angle : ndarray
        Rotation of the moving link's frame relative to the fixed link's, radians.
    origin : ndarray of complex
        The moving link's frame origin, in the fixed link's frame.
    slip : ndarray
        Arc length rolled on the fixed centrode minus that on the moving one,
        from the first sample (0 when rolling without slip).
    ok : ndarray of bool
        False where the pose could not be rebuilt (the centre at infinity or
        invalid, or the pole standing still: a cusp of the centrode).
    """

    angle: np.ndarray
    origin: np.ndarray
    slip: np.ndarray
    ok: np.ndarray


@dataclass(frozen=True)
class Centrodes(Summarized):
    """The fixed and moving centrodes of ``moving`` relative to ``fixed`` over a sweep.

    Attributes
    ----------
    parameter : ndarray
        The sweep's driver values, one per sample.
    fixed_link, moving_link : str or int
        The two links.
    fixed : ndarray of complex
        ``I_ij`` in the fixed link's frame (NaN where not ok).
    moving : ndarray of complex
        ``I_ij`` in the moving link's frame (NaN where not ok).
    contact : ndarray of complex
        ``I_ij`` in the world.
    angle, origin : ndarray
        The motion to reproduce: the moving frame's rotation relative to the
        fixed frame and its origin in the fixed frame.
    at_infinity : ndarray of bool
        Samples where the centre is a point at infinity (the curves go to
        infinity there: they are NaN).
    ok : ndarray of bool
        Samples with a finite, determined centre.
    reason : ndarray of str
        Why a sample is not ok.
    """

    parameter: np.ndarray
    fixed_link: Any
    moving_link: Any
    fixed: np.ndarray
    moving: np.ndarray
    contact: np.ndarray
    angle: np.ndarray
    origin: np.ndarray
    at_infinity: np.ndarray
    ok: np.ndarray
    reason: np.ndarray
    #: The quantity of ``parameter``: ``"angle"``, or ``"length"`` for a linkage driven by a slide.
    parameter_kind: str = "angle"

    def placed(self, k: int) -> np.ndarray:
        """The moving centrode where it sits at sample ``k``, in the fixed link's frame.

        It touches the fixed centrode at ``fixed[k]``.
        """
        k = integer("k", k)
        if not -self.parameter.size <= k < self.parameter.size:
            raise InputError("k", f"must index one of the {self.parameter.size} samples, got {k}")
        return self.origin[k] + self.moving * np.exp(1j * self.angle[k])

    def roll(self) -> RolledMotion:
        """Rebuild the motion by rolling the moving centrode on the fixed one.

        Uses only the two curves: each is fitted by a quintic spline of the
        sweep parameter (on each run of ok samples); at every sample the moving
        curve is turned so that its tangent lies along the fixed curve's
        (``angle = arg F′ − arg M′``) and moved so that the points touch
        (``origin = F − M e^{j angle}``). ``slip`` compares the arc lengths
        rolled on both curves. Compare ``angle`` and ``origin`` with the
        attributes of the same names (the solved motion).
        """
        from scipy.interpolate import make_interp_spline

        n = self.parameter.size
        angle = np.full(n, np.nan)
        origin = np.full(n, complex(np.nan, np.nan))
        slip = np.full(n, np.nan)
        ok = np.zeros(n, dtype=bool)
        steps = np.diff(self.parameter)
        if not (np.all(steps > 0) or np.all(steps < 0)):
            raise InputError(
                "parameter", "rolling needs a sweep whose driver values run one way (monotonic)"
            )
        direction = 1.0 if steps[0] > 0 else -1.0
        for run in _runs(self.ok):
            if run.stop - run.start < 6:
                continue
            u = direction * self.parameter[run]
            curves = []
            for curve in (self.fixed[run], self.moving[run]):
                fit = make_interp_spline(u, np.stack([curve.real, curve.imag], -1), k=5)
                d = fit.derivative()(u)
                curves.append((curve, d[:, 0] + 1j * d[:, 1], _arc_length(fit, u)))
            (F, dF, sF), (M, dM, sM) = curves
            size = max(float(np.max(np.abs(F))), float(np.max(np.abs(M))), 1e-300)
            size = max(size, float(np.max(np.abs(self.origin[run]))))
            span = max(float(np.ptp(u)), 1e-300)
            moving_pole = np.minimum(np.abs(dF), np.abs(dM)) > _STILL_POLE * size / span
            phi = np.angle(dF) - np.angle(dM)
            angle[run] = np.where(moving_pole, phi, np.nan)
            origin[run] = np.where(moving_pole, F - M * np.exp(1j * phi), np.nan)
            slip[run] = sF - sM
            ok[run] = moving_pole
        return RolledMotion(angle, origin, slip, ok)

    def plot(self, ax: Any = None, frame: int | None = None, **options: Any) -> Any:
        """Draw both centrodes (see :func:`machdyn.draw.centrodes.plot_centrodes`)."""
        from .draw.centrodes import plot_centrodes

        return plot_centrodes(self, ax=ax, frame=frame, **options)

    def to_pandas(self) -> Any:
        """One row per sample: parameter, fixed and moving centrode points, ok, reason.

        A model given units (a machine file's) names the columns with them
        (``fixed_x [mm]``, ``parameter [deg]``) and converts the values.
        """
        import pandas as pd

        from .units import columns, units_of

        system = units_of(self)
        spec = [("parameter", self.parameter_kind if system else None, self.parameter)]
        spec += [
            (name, "length", values)
            for name, values in (
                ("fixed_x", self.fixed.real),
                ("fixed_y", self.fixed.imag),
                ("moving_x", self.moving.real),
                ("moving_y", self.moving.imag),
            )
        ]
        spec += [(n, None, getattr(self, n)) for n in ("at_infinity", "ok", "reason")]
        return pd.DataFrame(columns(system, spec, degrees=True))


@dataclass(frozen=True)
class PitchCurves(Summarized):
    """Pitch curves of the non-circular gears that reproduce two links' motion.

    Attributes
    ----------
    a, b : ndarray of complex
        Each gear's pitch curve about its own pivot, in its link's frame turned
        so that its pivot is the origin (``I_ab − pivot`` in that frame).
    radius_a, radius_b : ndarray
        Pitch radii ``|a|``, ``|b|`` at each sample.
    ratio : ndarray
        ``ω_b / ω_a`` from the pitch radii: ``−r_a / r_b`` for external gears
        (pitch point between the pivots), ``+r_a / r_b`` for internal ones.
    centre_distance : float
        Distance between the pivots.
    external : ndarray of bool
        Where the pitch point lies between the pivots.
    ok : ndarray of bool
    """

    a: np.ndarray
    b: np.ndarray
    radius_a: np.ndarray
    radius_b: np.ndarray
    ratio: np.ndarray
    centre_distance: float
    external: np.ndarray
    ok: np.ndarray


def centrodes(
    model: Any,
    values: Any,
    moving: Any,
    fixed: Any = None,
    *,
    velocity: Any = None,
    form: int = 1,
) -> Centrodes:
    """The fixed and moving centrodes of link ``moving`` relative to link ``fixed``.

    Parameters
    ----------
    model : Linkage or FourBar
        A drawn :class:`~machdyn.linkage.Linkage` (links by name, ground
        ``"ground"``) or a :class:`~machdyn.FourBar` (links 1–4).
    values : array_like
        The sweep: driver values (θ2 for a four-bar), 1-D, in order of motion.
    moving, fixed : link
        The two links; ``fixed`` defaults to the ground.
    velocity : optional
        Driver speeds for a linkage with several drivers.
    form : {1, 2}
        The four-bar's form.

    Returns
    -------
    Centrodes

    Examples
    --------
    A wheel of radius 1 rolling on the ground (its centre held by a rod and a
    block on a guide): the fixed centrode is the ground line, the moving one the
    wheel's rim.

    >>> from machdyn.linkage import Linkage
    >>> lk = (Linkage({"T": (0, 0), "C": (0, 1), "W": (1, 1), "B": (2, 2.5), "O": (0, 2.5)})
    ...       .ground("T", "O").link("wheel", "C", "W").link("rod", "C", "B").link("block", "B")
    ...       .slider("block", "ground", "B", 0.0, through="O")
    ...       .roll("wheel", "C", 1.0, "ground", "T", np.inf).drive("wheel"))
    >>> c = centrodes(lk, np.linspace(0, -1, 5), moving="wheel")
    >>> np.round(c.fixed.imag, 12).tolist(), np.round(np.abs(c.moving), 12).tolist()
    ([0.0, 0.0, 0.0, 0.0, 0.0], [1.0, 1.0, 1.0, 1.0, 1.0])
    """
    values = finite_array("values", values)
    if values.ndim != 1 or values.size < 2:
        raise InputError(
            "values", f"a sweep is a 1-D array of two or more values, got shape {values.shape}"
        )
    ics, frames, bodies = _centres_and_frames(model, values, velocity, form)
    fixed = bodies[0] if fixed is None else fixed
    for field, link in (("moving", moving), ("fixed", fixed)):
        _check_link(field, link, bodies)
    if moving == fixed:
        raise InputError("moving", "a link has no centrode relative to itself: give two links")
    centre = ics[fixed, moving]
    contact = centre.point
    at_inf = centre.at_infinity & ics.valid
    ok = ics.valid & ~at_inf
    reason = np.where(at_inf, f"I({fixed},{moving}) is at infinity", ics.reason)
    (o_i, a_i), (o_j, a_j) = frames[fixed], frames[moving]
    fixed_curve = np.where(ok, (contact - o_i) * np.exp(-1j * a_i), np.nan)
    moving_curve = np.where(ok, (contact - o_j) * np.exp(-1j * a_j), np.nan)
    from .units import with_units

    # a Linkage driven by a slide sweeps a length; a FourBar (no drivers) its crank angle
    drivers = getattr(model, "drivers", ())
    angular = all(d in model._links or d in model._motors for d in drivers)
    result = Centrodes(
        parameter=values,
        fixed_link=fixed,
        moving_link=moving,
        fixed=fixed_curve,
        moving=moving_curve,
        contact=np.where(ok, contact, np.nan),
        angle=a_j - a_i,
        origin=(o_j - o_i) * np.exp(-1j * a_i),
        at_infinity=at_inf,
        ok=ok,
        reason=np.asarray(reason, dtype=object),
        parameter_kind="angle" if angular else "length",
    )
    return with_units(result, getattr(model, "units", None))


def gear_pitch_curves(
    model: Any, values: Any, link_a: Any, link_b: Any, *, velocity: Any = None, form: int = 1
) -> PitchCurves:
    """Pitch curves of non-circular gears on two ground-pivoted links (from their centrodes).

    Both links must turn about fixed pivots (pins with the ground); the pitch
    curve of each gear is the centrode of ``I_ab`` in its link's frame, moved
    to its pivot.

    Examples
    --------
    Two friction wheels of radii 2 and 3 on pivots 5 apart: circular gears.

    >>> from machdyn.linkage import Linkage
    >>> lk = (Linkage({"O2": (0, 0), "O3": (5, 0), "P": (2, 0), "Q": (5, 3)})
    ...       .ground("O2", "O3").link("w2", "O2", "P").link("w3", "O3", "Q")
    ...       .roll("w2", "O2", 2.0, "w3", "O3", 3.0).drive("w2"))
    >>> g = gear_pitch_curves(lk, np.radians([0, 45, 90]), "w2", "w3")
    >>> g.radius_a.round(12).tolist(), g.radius_b.round(12).tolist(), g.ratio.round(12).tolist()
    ([2.0, 2.0, 2.0], [3.0, 3.0, 3.0], [-0.666666666667, -0.666666666667, -0.666666666667])
    """
    c = centrodes(model, values, moving=link_b, fixed=link_a, velocity=velocity, form=form)
    ground = _bodies(model)[0]
    pivots = []
    for field, link in (("link_a", link_a), ("link_b", link_b)):
        g = centrodes(model, values, moving=link, fixed=ground, velocity=velocity, form=form)
        pts = g.fixed[g.ok]
        spread = float(np.max(np.abs(pts - pts[0]))) if pts.size else np.inf
        if link == ground or spread > 1e-9 * _size(g):
            raise InputError(field, f"link {link!r} does not turn about a fixed pivot")
        pivots.append((complex(g.fixed[g.ok][0]), complex(g.moving[g.ok][0])))
    (pa_world, pa_local), (pb_world, pb_local) = pivots
    a = c.fixed - pa_local
    b = c.moving - pb_local
    ra, rb = np.abs(a), np.abs(b)
    external = ra + rb <= abs(pb_world - pa_world) * (1 + 1e-9)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(external, -ra / rb, ra / rb)
    return PitchCurves(a, b, ra, rb, ratio, abs(pb_world - pa_world), external, c.ok)


# --------------------------------------------------------------------------------------


def _check_link(field: str, link: Any, bodies: tuple) -> None:
    known = not isinstance(link, bool | np.bool_) and any(
        type(link) is type(b) and link == b for b in bodies
    )
    if not known:
        raise InputError(field, f"unknown link {link!r}; links: {', '.join(map(str, bodies))}")


def _bodies(model: Any) -> tuple:
    from .fourbar import FourBar

    if isinstance(model, FourBar):
        return (1, 2, 3, 4)
    return ("ground", *model.links)


def _centres_and_frames(model: Any, values: np.ndarray, velocity: Any, form: int):
    """The model's instant centres over the sweep and each link's frame (origin, angle)."""
    from .fourbar import FourBar
    from .linkage import Linkage

    if isinstance(model, FourBar):
        if velocity is not None:
            raise InputError(
                "velocity", "a four-bar's centres do not depend on its speed: leave velocity out"
            )
        m = model.solve(values, form=form)
        zero = np.zeros(values.shape)
        frames = {
            1: (zero + 0j, zero),
            2: (zero + 0j, m.theta2 + zero),
            3: (m.A, m.theta3),
            4: (zero + model.r1, m.theta4),
        }
        return model.instant_centres(values, form=form), frames, (1, 2, 3, 4)
    if not isinstance(model, Linkage):
        raise InputError("model", f"must be a Linkage or a FourBar, got {model!r}")
    from .centres import _solve_with_speeds, linkage_centres

    motion = _solve_with_speeds(model, values, velocity)
    zero = np.zeros(values.shape)
    frames = {"ground": (zero + 0j, zero)}
    for name, link in model.links.items():
        frames[name] = (motion.points[link.points[0]], motion.theta[name])
    return linkage_centres(model, motion), frames, ("ground", *model.links)


def _runs(mask: np.ndarray) -> list[slice]:
    """Maximal runs of True in a 1-D mask, as slices."""
    edges = np.diff(np.concatenate(([0], mask.astype(np.int8), [0])))
    starts, stops = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    return [slice(int(a), int(b)) for a, b in zip(starts, stops, strict=True)]


def _arc_length(fit: Any, u: np.ndarray) -> np.ndarray:
    """Arc length of a spline curve from ``u[0]`` to each ``u``, 5-point Gauss per step."""
    nodes, weights = np.polynomial.legendre.leggauss(5)
    a, b = u[:-1, None], u[1:, None]
    x = 0.5 * (a + b) + 0.5 * (b - a) * nodes
    d = fit.derivative()(x)
    speed = np.hypot(d[..., 0], d[..., 1])
    steps = 0.5 * (b[:, 0] - a[:, 0]) * (speed @ weights)
    return np.concatenate(([0.0], np.cumsum(steps)))


def _size(c: Centrodes) -> float:
    finite = c.contact[c.ok]
    return float(np.max(np.abs(finite))) + 1.0 if finite.size else 1.0
