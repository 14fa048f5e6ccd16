"""Result values of the vector-loop solver: :class:`Motion` and :class:`SystemReport`."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import UnknownNameError

__all__ = ["Motion", "SystemReport"]


def blank(shape: int | tuple[int, ...]) -> np.ndarray:
    """Empty reasons: an object array of ``''`` (several times faster than ``np.full``).

    Examples
    --------
    >>> blank(2).tolist()
    ['', '']
    """
    out = np.empty(shape, dtype=object)
    out.fill("")
    return out


@dataclass(frozen=True)
class SystemReport:
    """Equation/unknown count of a loop system (what :meth:`LoopSystem.check` returns).

    Attributes
    ----------
    equations : tuple of str
        One label per scalar equation (``"loop 1 x: R2 + R3 - R4 - R1"``, ...).
    variables : tuple of str
        Every variable, in order of first appearance.
    inputs : tuple of str
        The named inputs (empty when none were named yet).
    dof : int
        Degrees of freedom ``len(variables) - len(equations)``.
    groups : tuple of tuple of str
        The unknowns in groups, in solving order (the diagonal blocks of the
        Jacobian's block-triangular form; each keeps its own branch along a
        sweep); empty when no inputs were named.

    Examples
    --------
    >>> r = SystemReport(("loop 1 x: R2 + R3 - R4 - R1", "loop 1 y: R2 + R3 - R4 - R1"),
    ...                  ("theta2", "theta3", "theta4"), ("theta2",), 1)
    >>> r.unknowns
    ('theta3', 'theta4')
    """

    equations: tuple[str, ...]
    variables: tuple[str, ...]
    inputs: tuple[str, ...]
    dof: int
    groups: tuple[tuple[str, ...], ...] = ()

    @property
    def unknowns(self) -> tuple[str, ...]:
        """Variables that are not inputs."""
        return tuple(v for v in self.variables if v not in self.inputs)

    def __str__(self) -> str:
        lines = [
            f"{len(self.variables)} variables, {len(self.equations)} equations: DOF {self.dof}",
            "variables: " + ", ".join(self.variables),
            "inputs: " + (", ".join(self.inputs) if self.inputs else "(none named)"),
            "equations:",
            *(f"  {e}" for e in self.equations),
        ]
        if self.groups:
            lines.append("groups (solving order): " + " | ".join(", ".join(g) for g in self.groups))
        return "\n".join(lines)


@dataclass(frozen=True)
class Motion:
    """Positions and time derivatives of a loop system over a batch of poses.

    Every array has the shape of the (broadcast) input arrays. Angles are in
    radians and *not wrapped*: along a continuation sweep they are continuous,
    for independent samples they lie near the guess.

    Attributes
    ----------
    positions : mapping of str to ndarray
        Every variable (inputs and unknowns). ``m["theta3"]`` is a shortcut.
    velocity, acceleration, jerk : mapping of str to ndarray, or None
        First, second and third time derivatives of every variable; None when
        no input velocity was given to ``solve``.
    points : mapping of str to complex ndarray
        Named points ``x + j y``.
    point_velocity, point_acceleration, point_jerk : mapping or None
        Their derivatives (complex), None like ``velocity``.
    ok : ndarray of bool
        True where the pose was assembled and the Jacobian is regular.
    reason : ndarray of str
        Empty where ``ok``; otherwise why (cannot assemble, singular Jacobian
        (toggle), possible branch jump, lost branch after a gap).
    residual : ndarray
        Largest loop-closure residual per sample, relative to the model's
        characteristic length.
    branch : ndarray of int
        Sign of ``det J_q`` per sample (+1/−1; 0 where not assembled): the
        product of the groups' signs, so constant along a continuation sweep.
    inputs : tuple of str
        Names of the input variables.
    angles : tuple of str
        Names of the variables that are angles (plotted in degrees).
    groups : tuple of tuple of str
        The unknowns of each group (diagonal block of the Jacobian's
        block-triangular form, e.g. each dyad of a six-bar), in solving order.
    group_branch : ndarray of int, shape (len(groups), *shape)
        Sign of each group's determinant per sample (0 where not assembled): a
        group's branch (assembly mode). Along a continuation sweep every ok
        sample has the signs of the sweep's start.

    Examples
    --------
    >>> from machdyn.loops import LoopSystem
    >>> s = (LoopSystem().vector("R1", 8.0, 0.0).vector("R2", 4.0, "theta2")
    ...      .vector("R3", 7.0, "theta3").vector("R4", 6.0, "theta4")
    ...      .loop("R2 + R3 - R4 - R1").point("B", "R2 + R3").inputs("theta2"))
    >>> m = s.solve({"theta2": [0.0, 0.1]}, guess={"theta3": 1.0, "theta4": 1.6},
    ...             velocity={"theta2": 1.0})
    >>> list(m.to_pandas().columns[:5])
    ['theta2', 'theta2_dot', 'theta2_ddot', 'theta2_dddot', 'theta3']
    >>> m.velocity["theta2"].tolist(), bool(m.ok.all())
    ([1.0, 1.0], True)
    """

    positions: Mapping[str, np.ndarray]
    velocity: Mapping[str, np.ndarray] | None
    acceleration: Mapping[str, np.ndarray] | None
    jerk: Mapping[str, np.ndarray] | None
    points: Mapping[str, np.ndarray]
    point_velocity: Mapping[str, np.ndarray] | None
    point_acceleration: Mapping[str, np.ndarray] | None
    point_jerk: Mapping[str, np.ndarray] | None
    ok: np.ndarray
    reason: np.ndarray
    residual: np.ndarray
    branch: np.ndarray
    inputs: tuple[str, ...]
    angles: tuple[str, ...] = ()
    groups: tuple[tuple[str, ...], ...] = ()
    group_branch: np.ndarray | None = None

    def __getitem__(self, name: str) -> np.ndarray:
        """Position of variable ``name``, or of point ``name`` (complex)."""
        if name in self.positions:
            return self.positions[name]
        if name in self.points:
            return self.points[name]
        known = ", ".join([*self.positions, *self.points])
        raise UnknownNameError(
            "name", f"{name!r} is neither a variable nor a point; known: {known}"
        )

    def __len__(self) -> int:
        return int(self.ok.size)

    def to_pandas(self) -> Any:
        """One row per pose: variables, their rates, points (x, y per order), ok, reason.

        Columns: ``theta3``, ``theta3_dot``, ``theta3_ddot``, ``theta3_dddot``,
        ``B_x``, ``B_y``, ``B_vx``, ``B_vy``, ``B_ax``, ``B_ay``, ``B_jx``, ``B_jy``,
        ``ok``, ``reason``. Requires pandas (``pip install machdyn[pandas]``).
        """
        import pandas as pd

        cols: dict[str, np.ndarray] = {}
        for name, value in self.positions.items():
            cols[name] = value.ravel()
            for suffix, rates in (
                ("_dot", self.velocity),
                ("_ddot", self.acceleration),
                ("_dddot", self.jerk),
            ):
                if rates is not None:
                    cols[name + suffix] = rates[name].ravel()
        for name, value in self.points.items():
            for tag, data in (
                ("", self.points),
                ("v", self.point_velocity),
                ("a", self.point_acceleration),
                ("j", self.point_jerk),
            ):
                if data is not None:
                    cols[f"{name}_{tag}x"] = data[name].real.ravel()
                    cols[f"{name}_{tag}y"] = data[name].imag.ravel()
            del value
        cols["ok"] = self.ok.ravel()
        cols["reason"] = self.reason.ravel()
        return pd.DataFrame(cols)

    def plot(self, names: tuple[str, ...] | list[str] | None = None, ax: Any = None) -> Any:
        """Plot variables against the first input (angles in degrees, labelled).

        Parameters
        ----------
        names : sequence of str, optional
            Variables to plot; default every unknown.
        ax : matplotlib Axes, optional
            Where to draw; a new figure otherwise.

        Returns
        -------
        matplotlib Axes
        """
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots()
        names = [n for n in self.positions if n not in self.inputs] if names is None else names

        def shown(name: str) -> tuple[np.ndarray, str]:
            value = np.asarray(self[name]).ravel()
            if name in self.angles:
                return np.degrees(value), f"{name} [deg]"
            return value, name

        x, x_label = shown(self.inputs[0]) if self.inputs else (np.arange(len(self)), "sample")
        for name in names:
            y, label = shown(name)
            ax.plot(x, y, label=label)
        ax.set_xlabel(x_label)
        ax.legend()
        return ax
