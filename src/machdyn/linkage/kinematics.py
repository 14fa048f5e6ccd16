"""Kinematics of a drawn linkage: solving the compiled loops, and the motion result."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from .._summary import Summarized
from .._validate import finite_array
from ..errors import InputError, ModelError
from ..loops.result import Motion
from ._common import _is_zero, _ref_angle

if TYPE_CHECKING:
    from .builder import Linkage
    from .view import Link


def solve(
    lk: Linkage,
    values: Any,
    velocity: Any = None,
    acceleration: Any = 0.0,
    jerk: Any = None,
    continuation: bool | None = None,
) -> LinkageMotion:
    """The body of :meth:`Linkage.solve` (see there)."""
    if continuation is not None:
        from .._validate import boolean

        continuation = boolean("continuation", continuation)
    model = lk._compile()
    drivers = tuple(lk._drivers)
    vals = _per_driver("values", values, drivers, required=True)
    vel = None if velocity is None else _per_driver("velocity", velocity, drivers, True)
    acc = _per_driver("acceleration", acceleration, drivers, False)
    if vel is None and acceleration is not None and not _is_zero(acceleration):
        raise ModelError("acceleration needs the driver velocity too (velocity=...)")
    jrk = None if jerk is None else _per_driver("jerk", jerk, drivers, False)
    if vel is None and jrk is not None:
        raise ModelError("jerk needs the driver velocity too (velocity=...)")
    shapes = {v.shape for v in vals.values()}
    try:
        shape = shapes.pop() if len(shapes) == 1 else np.broadcast_shapes(*shapes)
    except ValueError:
        raise InputError(
            "values",
            f"driver arrays of shapes {[np.shape(v) for v in vals.values()]} do not broadcast",
        ) from None
    n = math.prod(shape)
    cont = continuation if continuation is not None else (len(shape) <= 1 and n > 1)
    _rates_match(shape, velocity=vel, acceleration=acc, jerk=jrk)
    _warn_degrees(lk, vals)
    return _closed()(lk, model, vals, vel, acc, jrk, shape, bool(cont) or n == 1)


def _closed():
    """:func:`machdyn.linkage.sweep.solve_closed` (imported once: sweep imports this module)."""
    global _solve_closed
    if _solve_closed is None:
        from .sweep import solve_closed

        _solve_closed = solve_closed
    return _solve_closed


_solve_closed = None
#: Radians beyond this look like degrees (``machdyn.units.DEGREE_TURNS`` turns), set on first use.
_degree_limit = 0.0


def _warn_degrees(lk: Linkage, vals: dict[str, np.ndarray]) -> None:
    """Warn when an angle driver's (validated) values look like degrees.

    ``machdyn.units.warn_if_degrees``, called only when a value is beyond
    :data:`~machdyn.units.DEGREE_TURNS` turns (two reductions, no temporary).
    """
    global _degree_limit
    if not _degree_limit:
        from ..units import DEGREE_TURNS

        _degree_limit = DEGREE_TURNS * 2.0 * math.pi
    top = _degree_limit
    for name, v in vals.items():
        if not v.shape:  # one value (an editor's call): no reductions
            if -top <= float(v) <= top:
                continue
        elif not v.size or (v.max() <= top and v.min() >= -top):
            continue
        if name in lk._links or name in lk._motors:
            from ..units import warn_if_degrees

            warn_if_degrees(name, v, stacklevel=5)


def _per_driver(field: str, value: Any, drivers: tuple[str, ...], required: bool):
    if len(drivers) == 1 and type(value) in (float, int):  # the editor's one-pose call
        return {drivers[0]: finite_array(field, value)}
    if isinstance(value, Mapping):
        extra = [k for k in value if k not in drivers]
        if extra:
            raise ModelError(
                f"{field} given for {', '.join(extra)}, which are not drivers "
                f"({', '.join(drivers)})"
            )
        missing = [d for d in drivers if d not in value]
        if missing and required:
            raise ModelError(f"{field}: no value for driver(s) {', '.join(missing)}")
        return {d: finite_array(f"{field}[{d}]", value.get(d, 0.0)) for d in drivers}
    if len(drivers) != 1 and not required and np.ndim(value) == 0:
        return {d: finite_array(f"{field}[{d}]", value) for d in drivers}
    if len(drivers) != 1:
        raise ModelError(
            f"{field}: give a mapping {{driver: values}} for the drivers {', '.join(drivers)}"
        )
    return {drivers[0]: finite_array(field, value)}


@dataclass(frozen=True)
class LinkageMotion(Summarized):
    """Kinematics of a :class:`Linkage` over a batch of driver values.

    Arrays have the broadcast shape of the driver values. Angles in radians,
    not wrapped; positions are complex ``x + jy``.

    Attributes
    ----------
    inputs : mapping of driver name to ndarray
        The driver values as given.
    theta, omega, alpha : mapping of link name to ndarray
        Angle of each moving link (its first→second point line), angular
        velocity and acceleration (None without ``velocity``).
    points, point_velocity, point_acceleration : mapping of point name to complex ndarray
        Every named point (joints and coupler points).
    cg, cg_velocity, cg_acceleration : mapping of link name to complex ndarray
        Centre of mass of each moving link (its first point for a massless link).
    lengths, length_rate, length_acceleration : mapping of joint name to ndarray
        Slider and slot displacements, actuator lengths, and their rates.
    ok : ndarray of bool
        True where assembled and away from toggles.
    reason : ndarray of str
        Why a sample is not ok ('' where it is).
    angle_drivers : frozenset of str
        The drivers whose values are angles (links, motors), for labels.
    jerk, point_jerk, cg_jerk, length_jerk : mapping, optional
        Third derivatives (angular jerk ``dα/dt`` of each link, ...), computed
        when :meth:`Linkage.solve` is given ``jerk=`` (None otherwise).
    loop_motion : machdyn.loops.Motion
        The same motion solved by the vector-loop core: every loop variable of
        :meth:`Linkage.loop_system` (computed at the first access).

    Examples
    --------
    >>> from machdyn.linkage import Linkage
    >>> import numpy as np
    >>> lk = (Linkage({"O2": (0, 0), "O4": (8, 0), "A": (4, 0), "B": (7.625, 35.859375**0.5)})
    ...       .ground("O2", "O4").link("crank", "O2", "A").link("coupler", "A", "B")
    ...       .link("rocker", "O4", "B").drive("crank"))
    >>> m = lk.solve([0.0, 0.1], velocity=1.0)
    >>> sorted(m.theta), m.points["B"].shape
    (['coupler', 'crank', 'rocker'], (2,))
    """

    inputs: Mapping[str, np.ndarray]
    theta: Mapping[str, np.ndarray]
    omega: Mapping[str, np.ndarray] | None
    alpha: Mapping[str, np.ndarray] | None
    points: Mapping[str, np.ndarray]
    point_velocity: Mapping[str, np.ndarray] | None
    point_acceleration: Mapping[str, np.ndarray] | None
    cg: Mapping[str, np.ndarray]
    cg_velocity: Mapping[str, np.ndarray] | None
    cg_acceleration: Mapping[str, np.ndarray] | None
    lengths: Mapping[str, np.ndarray]
    length_rate: Mapping[str, np.ndarray] | None
    length_acceleration: Mapping[str, np.ndarray] | None
    ok: np.ndarray
    reason: np.ndarray
    angle_drivers: frozenset[str] = frozenset()
    jerk: Mapping[str, np.ndarray] | None = None
    #: The linkage's unit system (labels of :meth:`to_pandas`); None: unit-free.
    units: Any = field(default=None, repr=False, compare=False)
    point_jerk: Mapping[str, np.ndarray] | None = None
    cg_jerk: Mapping[str, np.ndarray] | None = None
    length_jerk: Mapping[str, np.ndarray] | None = None
    _loop: Any = field(default=None, repr=False, compare=False)

    @classmethod
    def _make(cls, **fields: Any) -> LinkageMotion:
        """The motion from every field, without the frozen ``__init__``'s one call per field.

        For :func:`machdyn.linkage.sweep.solve_closed`, which gives them all
        (an editor's one-pose solve pays for every microsecond).
        """
        self = object.__new__(cls)
        self.__dict__.update(fields)
        return self

    @property
    def loop_motion(self) -> Motion:
        """The motion solved by the vector-loop core (every loop variable), on first access."""
        if callable(self._loop):
            object.__setattr__(self, "_loop", self._loop())
        return self._loop

    def angle(self, link: str) -> np.ndarray:
        """Angle ``theta`` of ``link`` (radians)."""
        return _lookup(self.theta, link, "link")

    def plot(self, links: Sequence[str] | None = None, ax: Any = None) -> Any:
        """Plot link angles (degrees) against the first driver (degrees if an angle).

        Parameters
        ----------
        links : sequence of str, optional
            Links to plot; default all but the driven ones.
        ax : matplotlib Axes, optional

        Returns
        -------
        matplotlib Axes
        """
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots()
        driver, x = next(iter(self.inputs.items()))
        is_angle = driver in self.angle_drivers
        xs = np.degrees(np.ravel(x)) if is_angle else np.ravel(x)
        names = [n for n in self.theta if n not in self.inputs] if links is None else links
        for name in names:
            ax.plot(xs, np.degrees(np.ravel(self.angle(name))), label=f"theta {name} [deg]")
        ax.set_xlabel(f"{driver} [deg]" if is_angle else driver)
        ax.legend()
        return ax

    def __len__(self) -> int:
        return int(self.ok.size)

    def to_pandas(self) -> Any:
        """One row per sample: drivers, link angles and rates, points, centres of mass.

        Columns ``theta_<link>``, ``omega_<link>``, ``alpha_<link>``, ``<P>_x``,
        ``<P>_y``, ``<P>_vx`` ..., ``G_<link>_x`` ..., ``ok``, ``reason``.
        """
        import pandas as pd

        from ..units import columns

        spec: list[tuple[str, str | None, Any]] = [
            (k, "angle" if k in self.angle_drivers else "length", v) for k, v in self.inputs.items()
        ]
        kinds = {"theta": "angle", "omega": "angular_velocity", "alpha": "angular_acceleration"}
        for tag, table in (("theta", self.theta), ("omega", self.omega), ("alpha", self.alpha)):
            spec += [(f"{tag}_{k}", kinds[tag], v) for k, v in (table or {}).items()]
        spec += [(f"d_{k}", "length", v) for k, v in self.lengths.items()]
        for prefix, groups in (
            ("", (self.points, self.point_velocity, self.point_acceleration)),
            ("G_", (self.cg, self.cg_velocity, self.cg_acceleration)),
        ):
            for tag, kind, table in zip(
                ("", "v", "a"), ("length", "velocity", "acceleration"), groups, strict=True
            ):
                for k, v in (table or {}).items():
                    spec.append((f"{prefix}{k}_{tag}x", kind, np.ravel(v).real))
                    spec.append((f"{prefix}{k}_{tag}y", kind, np.ravel(v).imag))
        spec += [("ok", None, self.ok), ("reason", None, self.reason)]
        cols = columns(self.units, spec)
        return pd.DataFrame(cols)


def _lookup(table: Mapping[str, np.ndarray] | None, key: str, what: str) -> np.ndarray:
    if table is None:
        raise ModelError("no rates were computed: solve with velocity=...")
    from ..errors import UnknownNameError
    from ._common import _name

    if _name(what, key) not in table:
        raise UnknownNameError(what, f"unknown {what} {key!r}; known: {', '.join(table)}")
    return table[key]


def _cg_drawn(lk: Linkage, ln: Link) -> complex:
    p0 = lk._points[ln.points[0]]
    if ln.cg is None:
        return p0
    if isinstance(ln.cg, str):
        return lk._points[ln.cg]
    return p0 + ln.cg * np.exp(1j * _ref_angle(lk, ln.name))


def _rates_match(shape: tuple[int, ...], **rates: dict[str, np.ndarray] | None) -> None:
    """Refuse driver rates whose arrays do not broadcast to the driver values' shape."""
    for kind, table in rates.items():
        for d, a in (table or {}).items():
            if a.shape == shape or not a.shape:  # the usual cases: nothing to broadcast
                continue
            try:
                ok = np.broadcast_shapes(a.shape, shape) == shape
            except ValueError:
                ok = False
            if not ok:
                raise InputError(
                    f"{kind}[{d}]", f"shape {a.shape} does not match the driver values' {shape}"
                )
