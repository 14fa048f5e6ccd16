"""The four-bar linkage in closed form: positions, velocities, accelerations, jerks.

Conventions of the notes (and of Norton, *Design of Machinery*, ch. 4, 6, 7):
link 1 is the ground ``O2 O4`` along +x (``O2`` at the origin), 2 the input
``O2 A``, 3 the coupler ``A B`` and 4 the output ``O4 B``; the loop is
``R2 + R3 − R4 − R1 = 0``, i.e. ``a e^{jθ2} + b e^{jθ3} − c e^{jθ4} − d = 0``
with ``a, b, c, d = R2, R3, R4, R1``. Angles are in radians, counter-clockwise
from +x; θ3 and θ4 are reported in ``[0, 2π)`` and the fundamental angles φij
in ``(−π, π]``, as in the notes.

The functions at the top (:func:`positions`, :func:`velocities`, ...) are the
vectorised core: they broadcast like ufuncs over any array of input angles.
:class:`FourBar` holds the lengths and calls them.

Solution method
---------------
Positions by the notes' "direct method": the diagonal ``O4 A`` and the law of
cosines in triangle ``O4 A B`` give the direction of link 4, computed as unit
vectors (no inverse trigonometric function until the angles are reported).
Each derivative order is the same 2×2 linear system (the position Jacobian)
solved by Cramer's rule, with the right-hand side from differentiating the loop
(notes, "FOURBAR VELOCITY/ACCELERATION ANALYSIS"; jerk as in review lecture 3):

``j b x3 e^{jθ3} − j c x4 e^{jθ4} = K``  ⇒
``x3 = −Re(K e^{−jθ4}) / (b sin(θ3 − θ4))``,
``x4 = −Re(K e^{−jθ3}) / (c sin(θ3 − θ4))``.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from functools import cached_property
from typing import TYPE_CHECKING, Any

import numpy as np

from . import jit
from ._angles import TWO_PI, wrap_2pi, wrap_pi
from ._flags import Flagged
from ._parallel import for_slices, require_memory
from ._validate import (
    TINY,
    boolean,
    broadcast,
    choice,
    common_length_unit,
    count,
    finite_array,
    finite_scalar,
    input_motion,
    is_scalar,
    length,
    positive_length,
)
from .centres import fourbar_centres
from .classify import Classification, classify
from .errors import AssemblyError, InputError
from .units import UnitSystem, from_quantity_unit

if TYPE_CHECKING:
    from .inversions import InversionTable

__all__ = [
    "STATUS_REASONS",
    "FourBar",
    "FourBarMotion",
    "accelerations",
    "jerks",
    "named_angle",
    "positions",
    "velocities",
]

# --------------------------------------------------------------------------------------
# Per-sample status codes (a uint8 array in results; `.reason` turns them into text).
OK = 0
NOT_ASSEMBLABLE = 1
TOGGLE = 2
WRONG_FORM = 3
INDETERMINATE = 4

#: Human-readable reason for each status code.
STATUS_REASONS: tuple[str, ...] = (
    "",
    "cannot be assembled at this input angle (outside the input link's range)",
    "toggle: coupler and output are collinear, the velocity solution is singular",
    "input angle belongs to the other form (circuit) of this linkage",
    "indeterminate: joint A coincides with O4 (change point)",
)

#: Tolerance on |cos| beyond 1 accepted as a toggle rather than a failure to assemble.
_CLOSE_TOL = 1e-12
#: A link at most this fraction of the longest is a point (Linkage's zero-length rule).
_POINT = 1e-12
#: |sin(θ4 − θ3)| below this is a toggle of links 3 and 4. At a rocker's exact limit
#: rounding leaves up to ~6e-7 (the limit angle itself carries √ε error).
_TOGGLE_TOL = 2e-6
#: Samples are processed in chunks of this size (temporaries stay in cache). Chosen by
#: interleaved measurement: best on one thread, and with two threads larger chunks mean
#: fewer GIL hand-offs between numpy calls.
_CHUNK = 1 << 14


# --------------------------------------------------------------------------------------
# The vectorised core, in unit vectors.


def _unit_vectors(
    r1: float, r2: float, r3: float, r4: float, c2: np.ndarray, s2: np.ndarray, branch: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Unit vectors of links 3 and 4 and a status array, for cos/sin of θ2.

    ``branch`` = +1 puts B on the side that makes φ12 = θ4 − θ3 positive.
    Lengths are scaled by the longest (the unit vectors do not depend on scale),
    so squares neither overflow nor underflow for any representable lengths.
    Lengths and ``branch`` may also be arrays (one value per linkage, e.g. a
    column against a row of input angles) that broadcast with ``c2``/``s2``.
    """
    scale = np.maximum(np.maximum(r1, r2), np.maximum(r3, r4))
    r1, r2, r3, r4 = r1 / scale, r2 / scale, r3 / scale, r4 / scale
    ax = r2 * c2
    ay = r2 * s2
    sx = ax - r1  # diagonal O4 -> A (its y component is ay)
    dd = sx * sx
    dd += ay * ay
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = np.sqrt(dd)
        np.divide(1.0, inv, out=inv)
        # law of cosines at O4 in triangle O4 A B
        cg = dd + (r4 * r4 - r3 * r3)
        cg *= inv
        cg *= 1.0 / (2.0 * r4)
    status = np.zeros(cg.shape, dtype=np.uint8)
    abs_cg = np.abs(cg)
    inside = abs_cg <= 1.0 + _CLOSE_TOL  # False for NaN too (A on O4)
    if not inside.all():  # rare: only then pay for the masks and the clip
        status[~inside] = NOT_ASSEMBLABLE
        status[~np.isfinite(inv)] = INDETERMINATE
        cg = np.clip(cg, -1.0, 1.0)
    elif abs_cg.max() > 1.0:
        cg = np.clip(cg, -1.0, 1.0)
    sg = cg * cg
    np.subtract(1.0, sg, out=sg)
    np.sqrt(sg, out=sg)
    if np.ndim(branch):
        sg *= np.where(branch < 0, -1.0, 1.0)
    elif branch < 0:
        np.negative(sg, out=sg)
    sy = ay
    with np.errstate(invalid="ignore"):  # 0 · ∞ where A sits on O4 (flagged above)
        ux = sx * inv
        uy = sy * inv
        # e^{jθ4} = u · e^{−j·branch·γ}
        e4x = ux * cg + uy * sg
        e4y = uy * cg - ux * sg
        e3x = (r1 + r4 * e4x - ax) * (1.0 / r3)
        e3y = (r4 * e4y - ay) * (1.0 / r3)
    return e3x, e3y, e4x, e4y, status


def _solve_pair(
    b: float,
    c: float,
    kx: np.ndarray,
    ky: np.ndarray,
    e3x: np.ndarray,
    e3y: np.ndarray,
    e4x: np.ndarray,
    e4y: np.ndarray,
    s34: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """Solve ``j b x3 e3 − j c x4 e4 = K`` for (x3, x4) by Cramer's rule."""
    with np.errstate(divide="ignore", invalid="ignore"):
        x3 = -(kx * e4x + ky * e4y) / (b * s34)
        x4 = -(kx * e3x + ky * e3y) / (c * s34)
    return x3, x4


def _rot(p: Any, q: Any, ex: np.ndarray, ey: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Components of ``(p + j q) e`` for a unit vector ``e``."""
    return p * ex - q * ey, p * ey + q * ex


#: Memory per pose of :meth:`FourBar.solve` (8 angle and rate arrays, 6 complex point
#: arrays and the status), for the budget check made before solving.
_BYTES_PER_POSE = 8 * 8 + 6 * 16 + 1


def positions(
    r1: float, r2: float, r3: float, r4: float, theta2: Any, branch: int = 1
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Coupler and output angles of a four-bar for input angles ``theta2``.

    Parameters
    ----------
    r1, r2, r3, r4 : float
        Ground, input, coupler and output lengths.
    theta2 : array_like
        Input angles, radians (finite; NaN marks a sample to skip: it comes out
        not ok).
    branch : {1, -1}
        Sign of φ12 = θ4 − θ3 (the side of the diagonal O4A on which B lies).
        For most classes this is the notes' form 1 (+1) or form 2 (−1); see
        :meth:`FourBar.solve` for GRCR and GRRC.

    Returns
    -------
    theta3, theta4 : ndarray
        Angles in ``[0, 2π)``; NaN where the linkage cannot be assembled.
    ok : ndarray of bool
        False where the linkage cannot be assembled at that input.

    Examples
    --------
    HW 6 (notes): GCRR 8-4-7-6 at θ2 = 0, form 1.

    >>> th3, th4, ok = positions(8, 4, 7, 6, 0.0)
    >>> round(float(np.degrees(th3)), 4), round(float(np.degrees(th4)), 4), bool(ok)
    (58.8114, 93.5833, True)
    """
    r1, r2, r3, r4 = (positive_length(f"r{k}", r) for k, r in enumerate((r1, r2, r3, r4), start=1))
    sign = float(choice("branch", branch, (1, -1)))
    theta2 = finite_array("theta2", theta2, "radian", nan_ok=True)
    require_memory("theta2", 25 * theta2.size, f"{theta2.size:,} poses")
    return _positions(r1, r2, r3, r4, theta2, sign)


def _positions(
    r1: float, r2: float, r3: float, r4: float, theta2: Any, sign: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`positions` for lengths and a branch sign (±1.0) already checked (FourBar's)."""
    theta2 = np.asarray(theta2, dtype=float)
    flat = theta2.ravel()
    theta3 = np.empty(flat.shape)
    theta4 = np.empty(flat.shape)
    ok = np.empty(flat.shape, dtype=bool)
    shape = theta2.shape
    compiled = jit.kernels(flat.size)
    if compiled is not None:
        scale = max(r1, r2, r3, r4)
        lengths = (r1 / scale, r2 / scale, r3 / scale, r4 / scale)
        inputs = flat if flat.flags.writeable else flat.copy()  # one type: no recompiling

        def compiled_kernel(sl: slice) -> int:
            args = (sign, _CLOSE_TOL, inputs[sl], theta3[sl], theta4[sl], ok[sl])
            return compiled.positions(*lengths, *args)

        if jit.run(compiled_kernel, flat.size):
            return theta3.reshape(shape), theta4.reshape(shape), ok.reshape(shape)

    def kernel(part: slice) -> None:
        for lo in range(part.start, part.stop, _CHUNK):
            sl = slice(lo, min(lo + _CHUNK, part.stop))
            t2 = flat[sl]
            e3x, e3y, e4x, e4y, status = _unit_vectors(r1, r2, r3, r4, np.cos(t2), np.sin(t2), sign)
            good = status == OK
            _angle_into(e3y, e3x, good, theta3[sl])
            _angle_into(e4y, e4x, good, theta4[sl])
            ok[sl] = good

    start = time.perf_counter()
    for_slices(kernel, flat.size)
    jit.charge(time.perf_counter() - start)
    return theta3.reshape(shape), theta4.reshape(shape), ok.reshape(shape)


def _angle_into(y: np.ndarray, x: np.ndarray, good: np.ndarray | None, out: np.ndarray) -> None:
    """``out[:] =`` the angle of the unit vector ``(x, y)`` in [0, 2π), NaN where not ``good``.

    For a unit vector ``θ = 2 atan(y / (1 + x)) = 2 atan((1 − x) / y)``; the first
    form is used for ``x ≥ 0`` and the second for ``x < 0``, so neither cancels,
    and ±π comes out exactly (``(1 − x)/y = ±∞``). It agrees with ``atan2`` to a
    few ulp and costs about two thirds as much (``arctan`` is cheaper than
    ``arctan2`` in libm).
    """
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.where(x < 0.0, (1.0 - x) / y, y / (1.0 + x))
        np.arctan(t, out=out)
    out *= 2.0
    np.add(out, TWO_PI, out=out, where=out < 0.0)
    out[out >= TWO_PI] = 0.0  # −ε + 2π rounds to 2π
    out += 0.0  # −0.0 (from atan(−0)) becomes +0.0
    if good is not None and not good.all():
        out[~good] = np.nan


def velocities(
    r2: float, r3: float, r4: float, theta2: Any, theta3: Any, theta4: Any, omega2: Any
) -> tuple[np.ndarray, np.ndarray]:
    """Angular velocities ω3, ω4 (the notes' closed form).

    ``ω3 = a ω2 sin(θ4 − θ2) / (b sin(θ3 − θ4))``,
    ``ω4 = a ω2 sin(θ2 − θ3) / (c sin(θ4 − θ3))``.

    Examples
    --------
    At θ2 = 0 joint A lies on the ground line, so I24 = A and I13 = O4, and
    the instant centres give ω3/ω2 = ω4/ω2 = (A − O2)/(A − O4) = 4/(−4):

    >>> th3, th4, _ = positions(8, 4, 7, 6, 0.0)
    >>> w3, w4 = velocities(4, 7, 6, 0.0, th3, th4, 1.0)
    >>> round(float(w3), 6), round(float(w4), 6)
    (-1.0, -1.0)
    """
    r2, r3, r4, theta2, theta3, theta4, omega2 = _checked_closed_form(
        r2, r3, r4, theta2, theta3, theta4, omega2=omega2
    )
    with np.errstate(divide="ignore", invalid="ignore"):
        omega3 = r2 * omega2 * np.sin(theta4 - theta2) / (r3 * np.sin(theta3 - theta4))
        omega4 = r2 * omega2 * np.sin(theta2 - theta3) / (r4 * np.sin(theta4 - theta3))
    return omega3, omega4


def accelerations(
    r2: float,
    r3: float,
    r4: float,
    theta2: Any,
    theta3: Any,
    theta4: Any,
    omega2: Any,
    omega3: Any,
    omega4: Any,
    alpha2: Any,
) -> tuple[np.ndarray, np.ndarray]:
    """Angular accelerations α3, α4 from the differentiated loop equation.

    Solves ``a(jα2 − ω2²)e^{jθ2} + b(jα3 − ω3²)e^{jθ3} − c(jα4 − ω4²)e^{jθ4} = 0``.
    """
    args = _checked_closed_form(
        r2, r3, r4, theta2, theta3, theta4,
        omega2=omega2, omega3=omega3, omega4=omega4, alpha2=alpha2,
    )  # fmt: skip
    return _derivative_from_angles(*args[:6], _acceleration_rhs, *args[6:])


def jerks(
    r2: float,
    r3: float,
    r4: float,
    theta2: Any,
    theta3: Any,
    theta4: Any,
    omega2: Any,
    omega3: Any,
    omega4: Any,
    alpha2: Any,
    alpha3: Any,
    alpha4: Any,
    jerk2: Any,
) -> tuple[np.ndarray, np.ndarray]:
    """Angular jerks of links 3 and 4 (the notes' review lecture 3 form).

    Solves ``Σ ± r (jφ − 3αω − jω³) e^{jθ} = 0`` for the jerks φ3, φ4.
    """
    args = _checked_closed_form(
        r2, r3, r4, theta2, theta3, theta4,
        omega2=omega2, omega3=omega3, omega4=omega4,
        alpha2=alpha2, alpha3=alpha3, alpha4=alpha4, jerk2=jerk2,
    )  # fmt: skip
    return _derivative_from_angles(*args[:6], _jerk_rhs, *args[6:])


def _checked_closed_form(r2, r3, r4, theta2, theta3, theta4, **rates) -> list:
    """Arguments of the public closed forms, checked: lengths, angles, then rates.

    θ3 and θ4 may hold NaN (the unassembled samples of :func:`positions`): they
    stay NaN in the result. The rates come out broadcast as arrays.
    """
    lengths = [positive_length(f"r{k}", r) for k, r in ((2, r2), (3, r3), (4, r4))]
    angles = {"theta2": finite_array("theta2", theta2, "radian")}
    for name, value in (("theta3", theta3), ("theta4", theta4)):
        angles[name] = finite_array(name, value, "radian", nan_ok=True)
    checked = {name: finite_array(name, value) for name, value in rates.items()}
    broadcast(**angles, **checked)
    return [*lengths, *angles.values(), *checked.values()]


def _derivative_from_angles(r2, r3, r4, theta2, theta3, theta4, rhs, *rates):
    t2, t3, t4 = (np.asarray(t, dtype=float) for t in (theta2, theta3, theta4))
    e2x, e2y, e3x, e3y, e4x, e4y = (
        np.cos(t2),
        np.sin(t2),
        np.cos(t3),
        np.sin(t3),
        np.cos(t4),
        np.sin(t4),
    )
    s34 = e3y * e4x - e3x * e4y
    kx, ky = rhs(r2, r3, r4, e2x, e2y, e3x, e3y, e4x, e4y, *rates)
    return _solve_pair(r3, r4, kx, ky, e3x, e3y, e4x, e4y, s34)


def _velocity_rhs(a, b, c, e2x, e2y, e3x, e3y, e4x, e4y, w2):
    # K = −j a ω2 e2
    return a * w2 * e2y, -a * w2 * e2x


def _acceleration_rhs(a, b, c, e2x, e2y, e3x, e3y, e4x, e4y, w2, w3, w4, al2):
    # K = −a(jα2 − ω2²) e2 + b ω3² e3 − c ω4² e4
    px, py = _rot(-a * w2 * w2, a * al2, e2x, e2y)
    return (
        -px + b * w3 * w3 * e3x - c * w4 * w4 * e4x,
        -py + b * w3 * w3 * e3y - c * w4 * w4 * e4y,
    )


def _jerk_rhs(a, b, c, e2x, e2y, e3x, e3y, e4x, e4y, w2, w3, w4, al2, al3, al4, j2):
    # K = −a(jφ2 − 3α2ω2 − jω2³)e2 − b(−3α3ω3 − jω3³)e3 + c(−3α4ω4 − jω4³)e4
    p2x, p2y = _rot(-3.0 * al2 * w2, j2 - w2**3, e2x, e2y)
    p3x, p3y = _rot(-3.0 * al3 * w3, -(w3**3), e3x, e3y)
    p4x, p4y = _rot(-3.0 * al4 * w4, -(w4**3), e4x, e4y)
    return -a * p2x - b * p3x + c * p4x, -a * p2y - b * p3y + c * p4y


# --------------------------------------------------------------------------------------
# Results


@dataclass(frozen=True, eq=False)
class FourBarMotion(Flagged):
    """Kinematics of a four-bar over a set of input angles (one form).

    Arrays share the broadcast shape of the inputs. Samples that could not be
    solved have ``ok`` False, a ``reason``, and NaN in the affected arrays
    (positions stay finite at a toggle; only the rates are undefined there).

    Attributes
    ----------
    theta2, theta3, theta4 : ndarray
        Link angles, radians in ``[0, 2π)`` (θ2 as given).
    omega2, omega3, omega4 : ndarray
        Angular velocities, rad per time unit (CCW positive). Derivatives above
        the ``order`` asked of :meth:`FourBar.solve` are None.
    alpha2, alpha3, alpha4 : ndarray
        Angular accelerations.
    jerk2, jerk3, jerk4 : ndarray
        Angular jerks (the notes' φ̇ = α̇; named ``jerk`` to avoid φij).
    A, B : ndarray of complex
        Positions of the moving joints (crank pin and output pin).
    coupler, coupler_velocity, coupler_acceleration, coupler_jerk : ndarray of complex or None
        The coupler point P and its derivatives, when the linkage has one.
    status : ndarray of uint8
        0 where solved; otherwise an index into :data:`STATUS_REASONS`.
    form : int
        The form (1 or 2) these poses belong to.
    """

    REASONS = STATUS_REASONS

    theta2: np.ndarray
    theta3: np.ndarray
    theta4: np.ndarray
    omega2: np.ndarray
    omega3: np.ndarray | None
    omega4: np.ndarray | None
    alpha2: np.ndarray
    alpha3: np.ndarray | None
    alpha4: np.ndarray | None
    jerk2: np.ndarray
    jerk3: np.ndarray | None
    jerk4: np.ndarray | None
    A: np.ndarray
    B: np.ndarray
    coupler: np.ndarray | None
    coupler_velocity: np.ndarray | None
    coupler_acceleration: np.ndarray | None
    coupler_jerk: np.ndarray | None
    status: np.ndarray
    form: int
    lengths: tuple[float, float, float, float] = field(repr=False)
    #: The model's unit system (labels of :meth:`to_pandas`); None: unit-free.
    units: Any = field(default=None, repr=False)

    # -- flags -----------------------------------------------------------------
    @property
    def assembled(self) -> np.ndarray:
        """True where the positions are valid (toggles included)."""
        return (self.status == OK) | (self.status == TOGGLE)

    # -- fundamental angles (notes: "FUNDAMENTAL POSITION ANGLES") ------------------
    @cached_property
    def phi12(self) -> np.ndarray:
        """φ12 = θ4 − θ3: the angle between links 3 and 4 (faces links 1 and 2)."""
        return _named_angle("phi12", self.theta2, self.theta3, self.theta4)

    @cached_property
    def phi13(self) -> np.ndarray:
        """φ13 = θ2 − θ4: the angle between links 2 and 4."""
        return _named_angle("phi13", self.theta2, self.theta3, self.theta4)

    @cached_property
    def phi14(self) -> np.ndarray:
        """φ14 = π − θ2 + θ3: the internal angle at A, between links 2 and 3."""
        return _named_angle("phi14", self.theta2, self.theta3, self.theta4)

    @cached_property
    def phi23(self) -> np.ndarray:
        """φ23 = π − θ4: the internal angle at O4, between links 1 and 4."""
        return _named_angle("phi23", self.theta2, self.theta3, self.theta4)

    @cached_property
    def phi24(self) -> np.ndarray:
        """φ24 = θ3: the angle between links 1 and 3."""
        return _named_angle("phi24", self.theta2, self.theta3, self.theta4)

    @cached_property
    def phi34(self) -> np.ndarray:
        """φ34 = θ2: the internal angle at O2, between links 1 and 2."""
        return _named_angle("phi34", self.theta2, self.theta3, self.theta4)

    @cached_property
    def mu(self) -> np.ndarray:
        """Transmission angle μ: the acute angle between coupler and output, [0, π/2]."""
        return _named_angle("mu", self.theta2, self.theta3, self.theta4)

    # -- presentation ------------------------------------------------------------
    def to_pandas(self, degrees: bool = False):
        """A :class:`pandas.DataFrame`, one row per sample (pandas imported lazily).

        Complex positions are split into ``_x`` and ``_y`` columns. With
        ``degrees=True`` angles (not rates) are converted and the columns say so.
        """
        import pandas as pd

        from .units import RATE_KINDS, columns

        degrees = boolean("degrees", degrees)
        angles = (
            "theta2",
            "theta3",
            "theta4",
            "phi12",
            "phi13",
            "phi14",
            "phi23",
            "phi24",
            "phi34",
        )
        spec: list[tuple[str, str | None, Any]] = [
            (name, "angle", getattr(self, name)) for name in (*angles, "mu")
        ]
        for name in ("omega", "alpha", "jerk"):
            for n in (2, 3, 4):
                if getattr(self, f"{name}{n}") is not None:
                    spec.append((f"{name}{n}", RATE_KINDS[name], getattr(self, f"{name}{n}")))
        points = {
            "A": (self.A, "length"),
            "B": (self.B, "length"),
            "P": (self.coupler, "length"),
            "VP": (self.coupler_velocity, "velocity"),
            "AP": (self.coupler_acceleration, "acceleration"),
            "JP": (self.coupler_jerk, "jerk"),
        }
        for name, (value, kind) in points.items():
            if value is not None:
                spec += [(f"{name}_x", kind, value.real), (f"{name}_y", kind, value.imag)]
        spec += [("ok", None, self.ok), ("reason", None, self.reason)]
        table = columns(self.units, spec, degrees)
        return pd.DataFrame(table)

    def __len__(self) -> int:
        return int(np.size(self.theta2))

    def plot(self, **options: Any):
        """Angles and rates against θ2 (see :func:`machdyn.plot.plot_kinematics`)."""
        from .plot import plot_kinematics

        return plot_kinematics(self, **options)


# --------------------------------------------------------------------------------------
# Limits and tables


@dataclass(frozen=True)
class InputRange:
    """Range of the input angle θ2 over one form's motion.

    ``full_turn`` is True when link 2 is a crank; otherwise θ2 runs over
    ``[lo, hi]`` (radians, ``lo < hi``; ``hi`` may exceed π when the range
    contains θ2 = π).
    """

    lo: float
    hi: float
    full_turn: bool

    def grid(self, n: int) -> np.ndarray:
        """``n`` input angles over the range (endpoints included; a crank's 2π omitted).

        A rocker's range is sampled with cosine spacing, denser toward the limits,
        where the other links turn like the square root of the distance to the
        toggle; the poses then come out evenly spaced.
        """
        if self.full_turn:
            return np.linspace(0.0, TWO_PI, n, endpoint=False)
        u = np.linspace(0.0, np.pi, n)
        mid, half = 0.5 * (self.lo + self.hi), 0.5 * (self.hi - self.lo)
        grid = mid - half * np.cos(u)
        grid[0], grid[-1] = self.lo, self.hi
        return grid


@dataclass(frozen=True)
class Toggle:
    """A toggle position: two links collinear.

    Attributes
    ----------
    theta2 : float
        Input angle, radians in ``[0, 2π)``.
    links : tuple of int
        The collinear pair: ``(3, 4)`` is a limit of the input link (a dead
        point when link 2 drives); ``(2, 3)`` a limit of the output link (a
        dead point when link 4 drives).
    kind : str
        ``"extended"`` (end to end) or ``"folded"`` (overlapping).
    branch : int
        Sign of φ12 at the toggle (0 when the toggle is of links 3 and 4,
        which joins the two branches).
    """

    theta2: float
    links: tuple[int, int]
    kind: str
    branch: int


@dataclass(frozen=True)
class Extremum:
    """Range of one angle over a form's motion.

    The angle runs continuously from ``min`` up to ``max``. The pair is centred
    so that its midpoint lies in ``(−π, π]``; when the range contains the
    direction ±π one end lies beyond it (e.g. ``min`` = 146°, ``max`` = 214°).
    ``full_turn`` is True when the angle sweeps all directions (it then has no
    extremum; ``min``/``max`` are −π and π). ``theta2_at_min``/``_max`` are the
    input angles where the ends occur.
    """

    name: str
    min: float
    max: float
    theta2_at_min: float
    theta2_at_max: float
    full_turn: bool


@dataclass(frozen=True)
class TransmissionAngle:
    """Minimum transmission angle μ over a form's motion and where it occurs."""

    min: float
    theta2_at_min: float
    branch: int


@dataclass(frozen=True)
class CouplerCurve:
    """Coupler-point path over one form's motion, in order of travel.

    For a rocker input whose form spans two branches (GRCR, GRRC) the
    second branch is traversed back, so the curve closes.
    """

    theta2: np.ndarray
    branch: np.ndarray
    points: np.ndarray

    def to_pandas(self):
        """A :class:`pandas.DataFrame` with columns ``theta2, branch, x, y``."""
        import pandas as pd

        return pd.DataFrame(
            {
                "theta2": self.theta2,
                "branch": self.branch,
                "x": self.points.real,
                "y": self.points.imag,
            }
        )


# --------------------------------------------------------------------------------------
# The model


_PHI34_FORM_CLASSES = frozenset({"GRCR", "GRRC"})


class FourBar:
    """A planar four-bar linkage (ground R1, input R2, coupler R3, output R4).

    Parameters
    ----------
    r1, r2, r3, r4 : float or pint.Quantity
        Link lengths: ground ``O2O4``, input ``O2A``, coupler ``AB``, output ``O4B``.
        Quantities are converted to the unit of ``r1`` (see :attr:`length_unit`).
    coupler : (p, delta), optional
        A coupler point P at distance ``p`` from joint A and angle ``delta``
        (radians, or a pint angle) from the line AB, counter-clockwise.

    Raises
    ------
    InputError
        For a non-positive or non-finite length, or one that is a point next to the
        longest (at most 1e-12 of it: its two pins at one place to rounding).
    AssemblyError
        If the lengths cannot form a closed chain.

    Examples
    --------
    >>> fb = FourBar(8, 4, 7, 6)           # the notes' HW 6 linkage
    >>> fb.barker_class, fb.is_grashof, fb.cranks
    ('GCRR', True, (2,))
    >>> m = fb.solve(np.radians([0, 15, 30]), omega2=10.0)
    >>> np.round(np.degrees(m.theta4), 3)
    array([93.583, 81.759, 77.426])
    """

    #: The units the model computes in and labels its results with (set by
    #: :func:`machdyn.load`, or from the unit of length quantities); None: unit-free.
    units: UnitSystem | None = None

    def __init__(self, r1: Any, r2: Any, r3: Any, r4: Any, coupler: Any = None) -> None:
        lengths, unit = common_length_unit(r1=r1, r2=r2, r3=r3, r4=r4)
        longest = max(lengths.values())
        for name, value in lengths.items():
            if value <= 0.0:
                raise InputError(name, f"must be a positive length, got {value:g}")
            if value <= _POINT * longest:  # as Linkage: pins within 1e-12 are one place
                raise InputError(
                    name,
                    f"{value:g} is a point next to the longest link ({longest:g}): a link "
                    f"shorter than {_POINT:g} of it has its two pins at one place to rounding; "
                    "model the chain without it",
                )
        self.r1, self.r2, self.r3, self.r4 = (lengths[k] for k in ("r1", "r2", "r3", "r4"))
        self.length_unit: str | None = unit
        self.units = from_quantity_unit(unit)
        self.classification: Classification = classify(self.r1, self.r2, self.r3, self.r4)
        if coupler is None:
            self.coupler: tuple[float, float] | None = None
        else:
            try:
                p, delta = coupler
            except (TypeError, ValueError):
                raise InputError("coupler", f"expected (p, delta), got {coupler!r}") from None
            p = length("coupler p", p, unit)
            if p < 0.0:
                raise InputError("coupler p", f"must be a distance >= 0, got {p:g}")
            delta = finite_scalar("coupler delta", delta, "radian")
            self.coupler = (p, delta)

    @property
    def _extent(self) -> float:
        """The longest length of the linkage (links and coupler point): its scale."""
        return max(*self.lengths, 0.0 if self.coupler is None else self.coupler[0])

    # -- description --------------------------------------------------------------
    def to_spec(self, name: str = "fourbar") -> dict[str, Any]:
        """The four-bar as a machine-file dict (``docs/spec.md``; :func:`machdyn.from_spec`)."""
        from .spec import model_spec

        return model_spec(self, "fourbar", name)

    def __repr__(self) -> str:
        extra = (
            "" if self.coupler is None else f", coupler=({self.coupler[0]:g}, {self.coupler[1]:g})"
        )
        return f"FourBar({self.r1:g}, {self.r2:g}, {self.r3:g}, {self.r4:g}{extra})"

    @property
    def lengths(self) -> tuple[float, float, float, float]:
        """``(r1, r2, r3, r4)``."""
        return (self.r1, self.r2, self.r3, self.r4)

    @property
    def barker_class(self) -> str:
        """Barker's class code, one of the notes' 14 (``"GCCC"`` … ``"CP3X"``)."""
        return self.classification.code

    @property
    def is_grashof(self) -> bool:
        """Grashof condition ``s + l < p + q``."""
        return self.classification.is_grashof

    @property
    def is_assemblable(self) -> bool:
        """Always True for a constructed FourBar (construction checks it)."""
        return True

    @property
    def cranks(self) -> tuple[int, ...]:
        """Moving links that can make full turns relative to the ground."""
        return self.classification.cranks

    @property
    def form_rule(self) -> str:
        """Which angle's sign distinguishes form 1 from form 2 (the notes' table)."""
        return "phi34" if self.barker_class in _PHI34_FORM_CLASSES else "phi12"

    # -- kinematics ---------------------------------------------------------------
    def _branch_and_side(self, form: int, branch: int | None) -> tuple[int, int]:
        form = choice("form", form, (1, 2))
        if branch is not None:
            branch = choice("branch", branch, (1, -1))
        if self.form_rule == "phi12":
            if branch is not None and branch != (1 if form == 1 else -1):
                raise InputError(
                    "branch",
                    f"for a {self.barker_class} the form is the sign of phi12, so "
                    f"form {form} fixes branch {1 if form == 1 else -1}; omit branch",
                )
            return (1 if form == 1 else -1), 0
        branch = 1 if branch is None else choice("branch", branch, (1, -1))
        return branch, (1 if form == 1 else -1)

    def solve(
        self,
        theta2: Any,
        omega2: Any = 0.0,
        alpha2: Any = 0.0,
        form: int = 1,
        *,
        jerk2: Any = 0.0,
        branch: int | None = None,
        order: int = 3,
    ) -> FourBarMotion:
        """Positions, velocities, accelerations and jerks for input angles ``theta2``.

        Parameters
        ----------
        theta2 : array_like
            Input angles, radians (any shape).
        omega2, alpha2, jerk2 : array_like, optional
            Input angular velocity, acceleration and jerk (broadcast against
            ``theta2``); zero by default.
        form : {1, 2}
            The notes' form: the sign of φ12 (form 1: φ12 > 0), except for
            GRCR and GRRC where it is the sign of φ34 = θ2 (the two circuits).
            The form is read at every sample on its own. For a change-point
            linkage (s + l = p + q, e.g. a parallelogram) the two shapes meet
            where all four pivots are in line, so past that point the same form
            is the other shape (a parallelogram becomes the antiparallelogram);
            the change point itself is flagged as a toggle. `Linkage` instead
            follows the drawn shape through by continuity.
        branch : {1, -1}, optional
            Only for GRCR and GRRC: the sign of φ12 within the form (default +1).
        order : {0, 1, 2, 3}
            Highest derivative to compute (0 positions, 1 velocities,
            2 accelerations, 3 jerks). Quantities above it are ``None``.

        Returns
        -------
        FourBarMotion

        Raises
        ------
        AssemblyError
            If ``theta2`` is a single angle at which the form cannot be
            assembled. For arrays such samples are flagged instead.

        Examples
        --------
        The review exam linkage (R1 = 75, R2 = 150, R3 = R4 = 250 mm) at θ2 = 15°:

        >>> m = FourBar(75, 150, 250, 250).solve(np.radians(15), omega2=-5.0, form=2)
        >>> round(float(np.degrees(m.theta3)), 2), round(float(np.degrees(m.theta4)), 2)
        (128.25, 109.85)
        """
        single = is_scalar(theta2)
        shape, arrays = input_motion(
            theta2, omega2, alpha2, jerk2, bytes_per_sample=_BYTES_PER_POSE, length=self._extent
        )
        branch_sign, side = self._branch_and_side(form, branch)
        order = choice("order", order, (0, 1, 2, 3))
        t2, w2, a2, j2 = (x.ravel() for x in arrays)
        out = _solve_flat(self, t2, w2, a2, j2, branch_sign, side, order)
        if single and out["status"][0] in (NOT_ASSEMBLABLE, WRONG_FORM, INDETERMINATE):
            raise AssemblyError(
                f"{self!r}, form {form}, theta2 = {np.degrees(t2[0]):.6g} deg: "
                f"{STATUS_REASONS[out['status'][0]]}; {self._range_hint(form)}"
            )
        reshaped = {
            k: (v.reshape(shape) if isinstance(v, np.ndarray) else v) for k, v in out.items()
        }
        return FourBarMotion(form=form, lengths=self.lengths, units=self.units, **reshaped)

    def _range_hint(self, form: int) -> str:
        rng = self.input_range(form)
        if rng.full_turn:
            return "link 2 is a crank"
        return (
            f"theta2 must lie in [{np.degrees(rng.lo):.6g}, {np.degrees(rng.hi):.6g}] deg "
            f"for form {form}"
        )

    def dynamics(
        self,
        theta2: Any,
        omega2: Any,
        alpha2: Any = 0.0,
        *,
        mass: Any,
        inertia: Any,
        cg: Any,
        form: int = 1,
        gravity: float = 0.0,
        load_torque4: Any = 0.0,
        **options: Any,
    ):
        """Joint forces and driving torque by Newton–Euler (Norton eq. 11.10).

        ``mass = (m2, m3, m4)``, ``inertia = (IG2, IG3, IG4)`` and ``cg = (c2, c3,
        c4)``, each centre of mass a complex position in its link's frame (origin at
        O2, A, O4; x toward A, B, B). Further keyword options (external forces and
        torques, ``branch``) are those of :func:`machdyn.dynamics.fourbar_dynamics`,
        which this calls; it returns a ``FourBarForces`` with ``T12, F12, F32, F43,
        F14`` and the shaking force and moment.
        """
        from .dynamics import fourbar_dynamics

        return fourbar_dynamics(
            self,
            theta2,
            omega2,
            alpha2,
            mass=mass,
            inertia=inertia,
            cg=cg,
            form=form,
            gravity=gravity,
            load_torque4=load_torque4,
            **options,
        )

    # -- ranges, toggles, extrema --------------------------------------------------
    def input_range(self, form: int = 1) -> InputRange:
        """Range of θ2 over the motion of a form (the input rocker's limits).

        The limits are the toggles of links 3 and 4, where the diagonal ``O4A``
        equals ``R3 + R4`` or ``|R3 − R4|``.

        Examples
        --------
        >>> rng = FourBar(6, 9, 3, 8).input_range(form=1)   # GRCR: a rocker above O2O4
        >>> print(rng.full_turn, f"{np.degrees(rng.lo):.4f} {np.degrees(rng.hi):.4f}")
        False 31.5863 92.1226
        """
        choice("form", form, (1, 2))
        if 2 in self.cranks:
            # Decided with the classification's tolerance: a change point whose input
            # just reaches the toggle (cos θ2 = ±1 up to round-off) still turns fully.
            return InputRange(0.0, TWO_PI, True)
        a, b, c, d = (x / max(self.lengths) for x in (self.r2, self.r3, self.r4, self.r1))
        c_lo = (a * a + d * d - (b + c) ** 2) / (2.0 * a * d)
        c_hi = (a * a + d * d - (b - c) ** 2) / (2.0 * a * d)
        if c_lo <= -1.0 and c_hi >= 1.0:
            return InputRange(0.0, TWO_PI, True)
        if c_lo > -1.0 and c_hi < 1.0:  # two disjoint ranges, one each side of the ground line
            lo, hi = float(np.arccos(c_hi)), float(np.arccos(c_lo))
            if self.form_rule == "phi34" and form == 2:
                lo, hi = TWO_PI - hi, TWO_PI - lo
            return InputRange(float(lo), float(hi), False)
        if c_lo > -1.0:  # range contains θ2 = 0
            half = float(np.arccos(c_lo))
            return InputRange(-half, half, False)
        half = float(np.arccos(c_hi))  # range contains θ2 = π
        return InputRange(half, TWO_PI - half, False)

    def toggles(self) -> tuple[Toggle, ...]:
        """Every toggle position: links 3–4 collinear (input limits) or 2–3 (output limits).

        Examples
        --------
        A crank-rocker's output limits are where crank and coupler align:

        >>> for t in FourBar(8, 4, 7, 6).toggles():
        ...     print(f"{np.degrees(t.theta2):8.3f}", t.links, t.kind, t.branch)
          32.157 (2, 3) extended 1
         140.429 (2, 3) folded -1
         219.571 (2, 3) folded 1
         327.843 (2, 3) extended -1
        """
        a, b, c, d = (x / max(self.lengths) for x in (self.r2, self.r3, self.r4, self.r1))
        found: list[Toggle] = []
        # links 3 and 4 collinear: |A − O4| = b + c or |b − c|
        for kind, diag in (("extended", b + c), ("folded", abs(b - c))):
            cos2 = (a * a + d * d - diag * diag) / (2.0 * a * d)
            if abs(cos2) <= 1.0 + _CLOSE_TOL:
                t = float(np.arccos(np.clip(cos2, -1.0, 1.0)))
                # cos θ2 = ±1 (change points): one toggle at exactly 0 or π, not two
                # a round-off apart (arccos turns 1e-16 in cos into 1e-8 rad)
                at_end = abs(np.sin(t)) < 1e-6
                t = float(np.pi * round(t / np.pi)) if at_end else t
                for theta in sorted({t} if at_end else {t, float(wrap_2pi(-t))}):
                    found.append(Toggle(theta, (3, 4), kind, 0))
        # links 2 and 3 collinear: |B − O2| = a + b or |a − b|
        for kind, e in (("extended", a + b), ("folded", abs(a - b))):
            if e == 0.0:
                continue
            cos_psi = (d * d + e * e - c * c) / (2.0 * d * e)
            if abs(cos_psi) > 1.0 + _CLOSE_TOL:
                continue
            psi = float(np.arccos(np.clip(cos_psi, -1.0, 1.0)))
            for sgn in (1.0, -1.0):
                # A lies along O2→B unless folded with b > a, when it points away
                theta = sgn * psi + (np.pi if (kind == "folded" and b > a) else 0.0)
                theta = float(wrap_2pi(theta))
                for br in (1, -1):
                    th3, _, ok = _positions(d, a, b, c, theta, float(br))
                    if ok and abs(np.sin(float(th3) - theta)) < 1e-7:
                        found.append(Toggle(theta, (2, 3), kind, br))
        unique: dict[tuple, Toggle] = {}
        for t in found:
            unique.setdefault((round(t.theta2, 10), t.links, t.kind, t.branch), t)
        return tuple(sorted(unique.values(), key=lambda t: (t.links[0], t.theta2)))

    def _form_samples(self, form: int, n: int) -> list[tuple[np.ndarray, int]]:
        """(θ2 grid, branch) pieces covering the motion of a form."""
        branch_sign, _ = self._branch_and_side(form, None)
        n = count("n", n, minimum=2, bytes_each=64, what="samples")
        rng = self.input_range(form)
        grid = rng.grid(n)
        if self.form_rule == "phi34":
            return [(grid, 1), (grid[::-1], -1)]
        return [(grid, branch_sign)]

    def extrema(self, form: int = 1, n: int = 2001) -> dict[str, Extremum]:
        """Minimum and maximum of θ3, θ4 and every φij over the motion of a form.

        The motion is sampled at ``n`` input angles per branch and each
        extremum refined by a bounded scalar search on the closed form, so the
        result is exact to rounding, not to the sampling step.

        Examples
        --------
        Final exam problem 2: {8, 4, 9, 6} with φ12 > 0. The minimum of φ12
        occurs with links 1 and 2 overlapped (θ2 = 0), where
        cos φ12 = (9² + 6² − 4²)/(2·9·6):

        >>> ex = FourBar(8, 4, 9, 6).extrema(form=1)["phi12"]
        >>> print(f"{np.degrees(ex.min):.4f} at {np.degrees(ex.theta2_at_min):.4f} deg")
        20.7419 at 0.0000 deg
        """
        choice("form", form, (1, 2))
        names = ("theta3", "theta4", "phi12", "phi13", "phi14", "phi23", "phi24", "phi34")
        pieces = self._form_samples(form, n)
        rng = self.input_range(form)
        result: dict[str, Extremum] = {}
        closed = rng.full_turn or len(pieces) > 1  # the motion is a closed cycle
        poses = [_positions(*self.lengths, grid, float(br))[:2] for grid, br in pieces]
        for name in names:
            values = [
                _named_angle(name, grid, th3, th4)
                for (grid, _), (th3, th4) in zip(pieces, poses, strict=True)
            ]
            if _sweeps_all_directions(np.concatenate(values), closed):
                result[name] = Extremum(name, -np.pi, np.pi, np.nan, np.nan, True)
                continue
            # Represent the range as a continuous arc centred in (−π, π]: the angle
            # runs from min up to max, and one end may lie beyond ±π.
            joined = np.concatenate(values)
            turns = np.unwrap(joined[np.isfinite(joined)])  # a change point's pose is NaN
            mid = 0.5 * (turns.min() + turns.max())
            centre = float(wrap_pi(mid))
            best_min: tuple[float, float] | None = None
            best_max: tuple[float, float] | None = None
            for (grid, br), v in zip(pieces, values, strict=True):
                v = centre + wrap_pi(v - centre)
                for sign in (1.0, -1.0):
                    i = int(np.nanargmin(sign * v))
                    t, value = _refine(self, name, grid, i, br, sign, rng, centre)
                    if sign > 0 and (best_min is None or value < best_min[1]):
                        best_min = (t, value)
                    if sign < 0 and (best_max is None or value > best_max[1]):
                        best_max = (t, value)
            assert best_min is not None and best_max is not None
            result[name] = Extremum(
                name,
                float(best_min[1]),
                float(best_max[1]),
                float(wrap_2pi(best_min[0])),
                float(wrap_2pi(best_max[0])),
                False,
            )
        return result

    def inversions(self, n: int = 2001) -> InversionTable:
        """Barker table of the four inversions (each link grounded in turn).

        See :func:`machdyn.inversions.inversions` (the notes' HW 3 #2).

        Examples
        --------
        >>> [inv.code for inv in FourBar(6, 9, 3, 8).inversions()]
        ['GRCR', 'GCRR', 'GCCC', 'GRRC']
        """
        from .inversions import inversions

        return inversions(*self.lengths, n=n)

    def transmission_angle(self, form: int = 1, n: int = 2001) -> TransmissionAngle:
        """Minimum transmission angle μ over the motion of a form, and where it occurs.

        Examples
        --------
        A crank-rocker's minimum μ is at θ2 = 0 or π (Norton sec. 4.10); here at
        θ2 = 0, where cos φ12 = (7² + 6² − 4²)/(2·7·6):

        >>> ta = FourBar(8, 4, 7, 6).transmission_angle()
        >>> print(f"{np.degrees(ta.min):.4f} at {np.degrees(ta.theta2_at_min):.4f} deg")
        34.7719 at 0.0000 deg
        """
        choice("form", form, (1, 2))
        rng = self.input_range(form)
        best: tuple[float, float, int] | None = None
        for grid, br in self._form_samples(form, n):
            values = _angle_of(self, "mu", grid, br)
            i = int(np.nanargmin(values))
            t, v = _refine(self, "mu", grid, i, br, 1.0, rng)
            if best is None or v < best[1]:
                best = (t, v, br)
        assert best is not None
        return TransmissionAngle(float(best[1]), float(wrap_2pi(best[0])), best[2])

    def coupler_curve(self, form: int = 1, n: int = 721) -> CouplerCurve:
        """The coupler point's path over the motion of a form (``n`` samples per branch).

        Raises
        ------
        InputError
            If the linkage was built without a coupler point.
        """
        if self.coupler is None:
            raise InputError(
                "coupler", "this FourBar has no coupler point; pass coupler=(p, delta)"
            )
        thetas, branches, points = [], [], []
        for grid, br in self._form_samples(form, n):
            th3, _, ok = _positions(*self.lengths, grid, float(br))
            p, delta = self.coupler
            pts = self.r2 * np.exp(1j * grid) + p * np.exp(1j * (th3 + delta))
            thetas.append(grid[ok])
            branches.append(np.full(int(ok.sum()), br))
            points.append(pts[ok])
        return CouplerCurve(
            np.concatenate(thetas), np.concatenate(branches), np.concatenate(points)
        )

    # -- pictures (front-end functions in machdyn.plot and machdyn.viewer) ----------
    def draw(self, theta2: Any, form: int = 1, ax: Any = None, **options: Any):
        """Draw the linkage in one pose (see :func:`machdyn.plot.draw_fourbar`)."""
        from .plot import draw_fourbar

        return draw_fourbar(self, theta2, ax=ax, form=form, **options)

    def plot_coupler_curve(self, form: int = 1, ax: Any = None, **options: Any):
        """The coupler curve with the linkage drawn (:func:`machdyn.plot.plot_coupler_curve`)."""
        from .plot import plot_coupler_curve

        return plot_coupler_curve(self, form, ax, **options)

    def animate(self, **options: Any):
        """A matplotlib animation; a GIF with ``path=`` (:func:`machdyn.plot.animate`)."""
        from .plot import animate

        return animate(self, **options)

    def to_html(self, **options: Any) -> str:
        """A self-contained HTML page animating the linkage (:func:`machdyn.viewer.to_html`)."""
        from .viewer import to_html

        return to_html(self, **options)

    def report(self, path: Any = None, **options: Any) -> str:
        """A self-contained HTML design report (and PDF) (:func:`machdyn.report.report`)."""
        from .report import report

        return report(self, path, **options)

    # -- instant centres and mechanical advantage ----------------------------------
    def instant_centres(self, theta2: Any, form: int = 1, *, branch: int | None = None):
        """All six instant centres; I13 and I24 by Kennedy's rule.

        Returns
        -------
        InstantCentres
            Keyed by pairs ``(1, 3)`` etc.; each centre is a point, or a
            direction at infinity where its two Kennedy lines are parallel.

        Examples
        --------
        >>> ics = FourBar(8, 4, 7, 6).instant_centres(np.radians(90))
        >>> ics[1, 2].point
        array(0.+0.j)
        >>> bool(ics[2, 4].at_infinity)
        False
        """
        m = self.solve(theta2, form=form, branch=branch)
        return fourbar_centres(self.r1, m.A, m.B, m.assembled, max(self.lengths))

    def mechanical_advantage(
        self,
        theta2: Any,
        r_in: float = 1.0,
        r_out: float = 1.0,
        form: int = 1,
        *,
        method: str = "power",
        branch: int | None = None,
    ) -> np.ndarray:
        """Mechanical advantage ``F_out / F_in = (r_in ω2) / (r_out ω4)``.

        A force ``F_in`` at radius ``r_in`` on link 2 drives a load ``F_out``
        at radius ``r_out`` on link 4 (the notes' review lecture 2). Signed:
        negative when link 4 turns the opposite way to link 2; +∞ at a toggle of
        links 2 and 3 (the output stops), 0 at a toggle of links 3 and 4 (the
        input's dead point), NaN where the linkage cannot be assembled.

        Parameters
        ----------
        method : {"power", "instant_centres"}
            ``"power"``: ω4/ω2 from the velocity solution (the power identity).
            ``"instant_centres"``: ω4/ω2 from the position of I24 on the ground
            line, ``ω4/ω2 = I12I24 / I14I24`` (Kennedy's rule).

        Examples
        --------
        >>> fb = FourBar(8, 4, 7, 6)
        >>> ma_power = fb.mechanical_advantage(np.radians(60), method="power")
        >>> ma_ic = fb.mechanical_advantage(np.radians(60), method="instant_centres")
        >>> bool(np.isclose(ma_power, ma_ic))
        True
        """
        method = choice("method", method, ("power", "instant_centres"))
        r_in = finite_scalar("r_in", r_in, self.length_unit)
        r_out = finite_scalar("r_out", r_out, self.length_unit)
        if abs(r_out) < TINY:
            raise InputError(
                "r_out", f"must be non-zero (the output force's lever arm), got {r_out:g}"
            )
        m = self.solve(theta2, omega2=1.0, form=form, branch=branch, order=1)
        if method == "power":
            ratio = m.omega4  # ω4 / ω2 with ω2 = 1
        else:
            centres = fourbar_centres(self.r1, m.A, m.B, m.assembled, max(self.lengths))
            ratio = centres.omega_ratio(2, 4)
        with np.errstate(divide="ignore", invalid="ignore"):
            ma = (r_in / r_out) / ratio
        # The two dead points, alike for both methods: at a toggle of links 3 and 4
        # the input cannot move (MA = 0); where link 4 stops (links 2 and 3 aligned)
        # the output force is unbounded.
        ma = np.where(m.status == TOGGLE, 0.0, ma)
        output_stops = np.abs(np.sin(m.theta3 - m.theta2)) < _TOGGLE_TOL
        ma = np.where(output_stops & (m.status == OK), np.inf, ma)
        return np.where(m.assembled, ma, np.nan)


# --------------------------------------------------------------------------------------
# Internals of FourBar


def _solve_flat(
    fb: FourBar,
    t2: np.ndarray,
    w2: np.ndarray,
    a2: np.ndarray,
    j2: np.ndarray,
    branch: int,
    side: int,
    order: int,
) -> dict[str, Any]:
    """Solve flat arrays (threads for large ones); the FourBarMotion fields.

    ``order`` is the highest derivative computed (0 positions … 3 jerks);
    quantities above it are returned as None. The compiled kernel serves the
    call when :mod:`machdyn.jit` says so, NumPy otherwise.
    """
    compiled = jit.kernels(t2.size)
    out = None
    if compiled is not None:
        out = _solve_compiled(compiled, fb, t2, w2, a2, j2, branch, side, order)
    if out is None:
        start = time.perf_counter()
        out = _solve_numpy(fb, t2, w2, a2, j2, branch, side, order)
        jit.charge(time.perf_counter() - start)
    # the inputs are the caller's own copies (made by input_motion)
    return {"theta2": t2, "omega2": w2, "alpha2": a2, "jerk2": j2, **out}


_RATE_NAMES = ("omega3", "omega4", "alpha3", "alpha4", "jerk3", "jerk4")
_POINT_NAMES = ("coupler", "coupler_velocity", "coupler_acceleration", "coupler_jerk")
_DTYPES = {"status": np.uint8, "A": complex, "B": complex, **dict.fromkeys(_POINT_NAMES, complex)}


def _solve_compiled(
    kernels: Any,
    fb: FourBar,
    t2: np.ndarray,
    w2: np.ndarray,
    a2: np.ndarray,
    j2: np.ndarray,
    branch: int,
    side: int,
    order: int,
) -> dict[str, Any] | None:
    """:func:`_solve_flat` by the compiled kernel; None if an input is beyond its range."""
    n = t2.size
    lengths = np.array([fb.r2, fb.r3, fb.r4, fb.r1])
    has_p = fb.coupler is not None
    p, delta = fb.coupler if has_p else (0.0, 0.0)
    coupler = np.array([p, np.cos(delta), np.sin(delta)])
    tolerances = np.array([_CLOSE_TOL, _TOGGLE_TOL])
    fixed = (lengths, lengths / lengths.max(), coupler, float(branch), float(side), tolerances)
    arrays: dict[str, Any] = {"theta2": t2, "omega2": w2, "alpha2": a2, "jerk2": j2}
    out: dict[str, Any] = {}
    for name in kernels.ARRAYS[order]:
        if name not in arrays:  # an output; the coupler point's only if there is one
            wanted = has_p or name not in _POINT_NAMES
            out[name] = np.empty(n, dtype=_DTYPES.get(name, float)) if wanted else None
    arrays.update(out)
    solver = kernels.SOLVERS[order]

    def kernel(sl: slice) -> int:
        args = (
            None if arrays[name] is None else arrays[name][sl] for name in kernels.ARRAYS[order]
        )
        return solver(*fixed, *args)

    if not jit.run(kernel, n):
        return None
    return {**dict.fromkeys((*_RATE_NAMES, *_POINT_NAMES)), **out}


def _solve_numpy(
    fb: FourBar,
    t2: np.ndarray,
    w2: np.ndarray,
    a2: np.ndarray,
    j2: np.ndarray,
    branch: int,
    side: int,
    order: int,
) -> dict[str, Any]:
    """:func:`_solve_flat` in NumPy, chunk by chunk (temporaries stay in cache)."""
    n = t2.size
    names = ["theta3", "theta4", *_RATE_NAMES]
    out: dict[str, np.ndarray | None] = {
        name: (np.empty(n) if k // 2 <= order else None) for k, name in enumerate(names)
    }
    joints = {"A": np.empty(n, dtype=complex), "B": np.empty(n, dtype=complex)}
    has_p = fb.coupler is not None
    point_names = _POINT_NAMES
    points: dict[str, np.ndarray | None] = {
        name: (np.empty(n, dtype=complex) if has_p and k <= order else None)
        for k, name in enumerate(point_names)
    }
    status = np.empty(n, dtype=np.uint8)
    a, b, c, d = fb.r2, fb.r3, fb.r4, fb.r1
    p, delta = fb.coupler if has_p else (0.0, 0.0)
    cd, sd = np.cos(delta), np.sin(delta)

    arrays = {**out, **joints, **points}

    def store(name: str, sl: slice, x: np.ndarray, y: np.ndarray | None = None) -> None:
        target = arrays[name]
        if y is None:
            target[sl] = x
        else:
            target.real[sl], target.imag[sl] = x, y

    def kernel(part: slice) -> None:
        for lo in range(part.start, part.stop, _CHUNK):
            sl = slice(lo, min(lo + _CHUNK, part.stop))
            th2, om2, al2, je2 = t2[sl], w2[sl], a2[sl], j2[sl]
            e2x, e2y = np.cos(th2), np.sin(th2)
            e3x, e3y, e4x, e4y, st = _unit_vectors(d, a, b, c, e2x, e2y, float(branch))
            if side:
                st[(st == OK) & (side * e2y <= 0.0)] = WRONG_FORM
            s34 = e3y * e4x - e3x * e4y
            st[(st == OK) & (np.abs(s34) < _TOGGLE_TOL)] = TOGGLE
            bad = (st != OK) & (st != TOGGLE)
            if bad.any():
                for arr in (e3x, e3y, e4x, e4y):
                    arr[bad] = np.nan
            status[sl] = st
            _angle_into(e3y, e3x, None, out["theta3"][sl])  # NaN already marks failures
            _angle_into(e4y, e4x, None, out["theta4"][sl])
            store("A", sl, a * e2x, a * e2y)
            store("B", sl, d + c * e4x, c * e4y)
            if has_p:
                epx, epy = _rot(cd, sd, e3x, e3y)  # e^{j(θ3 + δ)}
                store("coupler", sl, a * e2x + p * epx, a * e2y + p * epy)
            if order == 0:
                continue
            unit = (e3x, e3y, e4x, e4y, s34)
            toggled = st == TOGGLE
            rates = (e2x, e2y, e3x, e3y, e4x, e4y)

            w3, w4 = _masked_pair(_velocity_rhs, a, b, c, rates, unit, toggled, om2)
            store("omega3", sl, w3)
            store("omega4", sl, w4)
            if has_p:  # V_P = j a ω2 e2 + j p ω3 e_p
                vx, vy = _rot(0.0, a * om2, e2x, e2y)
                qx, qy = _rot(0.0, p * w3, epx, epy)
                store("coupler_velocity", sl, vx + qx, vy + qy)
            if order == 1:
                continue
            al3, al4 = _masked_pair(
                _acceleration_rhs, a, b, c, rates, unit, toggled, om2, w3, w4, al2
            )
            store("alpha3", sl, al3)
            store("alpha4", sl, al4)
            if has_p:  # A_P = a(jα2 − ω2²) e2 + p(jα3 − ω3²) e_p
                vx, vy = _rot(-a * om2 * om2, a * al2, e2x, e2y)
                qx, qy = _rot(-p * w3 * w3, p * al3, epx, epy)
                store("coupler_acceleration", sl, vx + qx, vy + qy)
            if order == 2:
                continue
            je3, je4 = _masked_pair(
                _jerk_rhs, a, b, c, rates, unit, toggled, om2, w3, w4, al2, al3, al4, je2
            )
            store("jerk3", sl, je3)
            store("jerk4", sl, je4)
            if has_p:  # J_P = a(jφ2 − 3α2ω2 − jω2³) e2 + p(jφ3 − 3α3ω3 − jω3³) e_p
                vx, vy = _rot(-3.0 * a * al2 * om2, a * (je2 - om2**3), e2x, e2y)
                qx, qy = _rot(-3.0 * p * al3 * w3, p * (je3 - w3**3), epx, epy)
                store("coupler_jerk", sl, vx + qx, vy + qy)

    for_slices(kernel, n)
    return {**out, **joints, **points, "status": status}


def _masked_pair(rhs, a, b, c, rates, unit, toggled, *args):
    """One derivative order: build the right-hand side, solve, NaN at toggles."""
    x3, x4 = _solve_pair(b, c, *rhs(a, b, c, *rates, *args), *unit)
    if toggled.any():
        x3[toggled] = np.nan
        x4[toggled] = np.nan
    return x3, x4


def _sweeps_all_directions(values: np.ndarray, closed: bool) -> bool:
    """True if an angle sampled along a motion turns through every direction."""
    values = values[np.isfinite(values)]
    if closed:  # winding number of the closed cycle
        turns = np.unwrap(np.append(values, values[0]))
        return abs(turns[-1] - turns[0]) > np.pi
    return bool(np.ptp(np.unwrap(values)) >= TWO_PI - 1e-9)


def named_angle(name: str, theta2: Any, theta3: Any, theta4: Any) -> np.ndarray:
    """θ3, θ4, a fundamental angle φij or the transmission angle μ, from the link angles.

    The notes' table of fundamental position angles, each wrapped to (−π, π]:
    φ12 = θ4 − θ3, φ13 = θ2 − θ4, φ14 = π − θ2 + θ3, φ23 = π − θ4, φ24 = θ3,
    φ34 = θ2; μ is the acute angle between coupler and output, in [0, π/2].

    Examples
    --------
    >>> float(named_angle("phi14", 0.0, np.pi / 2, 0.0) / np.pi)
    -0.5
    """
    name = choice("name", name, ("theta3", "theta4", "mu", *_PHI_NAMES))
    theta2 = finite_array("theta2", theta2, "radian")
    theta3 = finite_array("theta3", theta3, "radian", nan_ok=True)
    theta4 = finite_array("theta4", theta4, "radian", nan_ok=True)
    broadcast(theta2=theta2, theta3=theta3, theta4=theta4)
    return _named_angle(name, theta2, theta3, theta4)


_PHI_NAMES = ("phi12", "phi13", "phi14", "phi23", "phi24", "phi34")


def _named_angle(name: str, theta2: Any, theta3: Any, theta4: Any) -> np.ndarray:
    """:func:`named_angle` for arguments already checked (NaN for unassembled samples)."""
    if name == "theta3":
        return theta3
    if name == "theta4":
        return theta4
    if name == "mu":
        m = np.abs(wrap_pi(np.subtract(theta4, theta3)))
        return np.minimum(m, np.pi - m)
    definitions: Mapping[str, Callable[[], np.ndarray]] = {
        "phi12": lambda: np.subtract(theta4, theta3),
        "phi13": lambda: np.subtract(theta2, theta4),
        "phi14": lambda: np.pi - np.asarray(theta2) + theta3,
        "phi23": lambda: np.pi - np.asarray(theta4),
        "phi24": lambda: theta3,
        "phi34": lambda: theta2,
    }
    return wrap_pi(definitions[name]())


def _angle_of(fb: FourBar, name: str, theta2: np.ndarray, branch: int) -> np.ndarray:
    """One named angle along a branch, from the closed-form positions."""
    th3, th4, _ = _positions(*fb.lengths, theta2, float(branch))
    return _named_angle(name, theta2, th3, th4)


def _refine(
    fb: FourBar,
    name: str,
    grid: np.ndarray,
    i: int,
    branch: int,
    sign: float,
    rng: InputRange,
    centre: float = 0.0,
) -> tuple[float, float]:
    """Refine the extremum near grid[i] by a bounded scalar search (sign +1: min).

    Angles are represented continuously as ``centre + wrap(angle − centre)``.
    """
    from scipy.optimize import minimize_scalar

    lo = grid[max(i - 1, 0)]
    hi = grid[min(i + 1, grid.size - 1)]
    if rng.full_turn:
        step = TWO_PI / grid.size
        lo, hi = grid[i] - step, grid[i] + step
    lo, hi = min(lo, hi), max(lo, hi)

    def f(t: float) -> float:
        v = float(_angle_of(fb, name, np.array([t]), branch)[0])
        if not np.isfinite(v):
            return np.inf
        return sign * (centre + float(wrap_pi(v - centre)))

    best_t, best_v = float(grid[i]), f(float(grid[i]))
    if hi > lo:
        res = minimize_scalar(
            f, bounds=(lo, hi), method="bounded", options={"xatol": 1e-13, "maxiter": 200}
        )
        if res.fun < best_v:
            best_t, best_v = float(res.x), float(res.fun)
        for edge in (lo, hi):  # the bounded search never evaluates the ends
            fe = f(edge)
            if fe < best_v:
                best_t, best_v = float(edge), fe
    return best_t, sign * best_v
