"""Analysing a machine: each part's summary and tables, in the models' units.

Results hold values in the models' internal units with the *kind* of every
column; :class:`ResultTable` converts them to the file's output units and
labels them (``theta3 [deg]``) for the command line, JSON, CSV and pandas.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import units as u

if TYPE_CHECKING:
    from ._machine import Machine, Part

__all__ = ["PartResult", "ResultTable", "Summary", "TorqueCurve", "rounded", "run_machine"]

#: Samples of the turn a flywheel integrates a part's torque over (0.1° steps): its
#: ΔE is a trapezoid sum, O(h²), and at the 10° of a printed table it was off by ~0.1 %.
FLYWHEEL_SAMPLES = 3600


@dataclass(frozen=True)
class TorqueCurve:
    """A part's driving torque as a function of its input angle, at its input speed ``omega``."""

    of: Callable[[np.ndarray], Any]
    omega: float

    def over_turn(self, samples: int = FLYWHEEL_SAMPLES) -> tuple[np.ndarray, np.ndarray]:
        """``(theta, T)`` over one full turn of the input, ``samples`` steps."""
        theta = np.linspace(0.0, 2.0 * np.pi, samples + 1)
        return theta, np.asarray(self.of(theta), dtype=float)


@dataclass
class ResultTable:
    """Named columns (one value per sample) with the kind of quantity of each.

    ``kinds[name]`` is a key of :data:`machdyn.units.KINDS`, or None for a
    column of flags or text (``ok``, ``reason``).
    """

    name: str
    title: str
    columns: dict[str, np.ndarray]
    kinds: dict[str, str | None]

    def __len__(self) -> int:
        return len(next(iter(self.columns.values()))) if self.columns else 0

    def labelled(self, system: u.UnitSystem) -> dict[str, np.ndarray]:
        """The columns in ``system``'s output units, each named with its unit."""
        out = {}
        for name, values in self.columns.items():
            k = self.kinds[name]
            if k is None or (k == "dimensionless" and np.asarray(values).dtype.kind in "iu"):
                out[name] = values
            else:
                out[system.label(name, k)] = system.show(k, np.asarray(values, dtype=float))
        return out

    def to_pandas(self, system: u.UnitSystem) -> Any:
        """A :class:`pandas.DataFrame` of :meth:`labelled` (pandas imported here)."""
        import pandas as pd

        return pd.DataFrame(self.labelled(system))


@dataclass
class Summary:
    """One line of a part's summary: a label, a value and its kind (None: as is)."""

    label: str
    value: Any
    kind: str | None = None

    def shown(self, system: u.UnitSystem) -> tuple[str, Any]:
        """``(label with unit, value in output units)``."""
        if self.kind is None or not _numeric(self.value):
            return self.label, self.value
        value = self.value
        if not isinstance(value, int | float | np.floating):
            value = np.asarray(value, dtype=float)
        return system.label(self.label, self.kind), system.show(self.kind, value)


def _numeric(value: Any) -> bool:
    if isinstance(value, bool):
        return False
    if isinstance(value, int | float | np.floating):
        return True
    if isinstance(value, Sequence | np.ndarray) and not isinstance(value, str):
        return all(_numeric(v) for v in value)
    return False


@dataclass
class PartResult:
    """What analysing one part gave: summary lines, tables, flagged samples, and objects.

    ``objects`` holds the library's own results (``motion``, ``forces``, ...);
    ``speed`` the output speed a part hands to the parts it drives; ``torque``
    its driving torque as a function of its input angle (:class:`TorqueCurve`),
    for a flywheel to integrate over a full turn.
    """

    part: Part
    summary: list[Summary] = field(default_factory=list)
    tables: list[ResultTable] = field(default_factory=list)
    flagged: list[str] = field(default_factory=list)
    objects: dict[str, Any] = field(default_factory=dict)
    speed: float | None = None
    torque: TorqueCurve | None = None

    def table(self, name: str) -> ResultTable:
        """The table called ``name``."""
        for table in self.tables:
            if table.name == name:
                return table
        raise KeyError(name)


def run_machine(machine: Machine, names: Sequence[str] | None = None) -> dict[str, PartResult]:
    """Analyse ``names`` (default all) and what they refer to, in dependency order."""
    from ._machine import kind, order

    wanted = set(machine.parts if names is None else _closure(machine, names))
    results: dict[str, PartResult] = {}
    for name in order(machine):
        if name in wanted:
            part = machine.parts[name]
            results[name] = kind(part.kind).run(part, machine, results)
    return {name: results[name] for name in machine.parts if name in results}


def _closure(machine: Machine, names: Sequence[str]) -> set[str]:
    from ._machine import kind

    out: set[str] = set()
    todo = list(names)
    while todo:
        name = todo.pop()
        if name in out:
            continue
        out.add(name)
        part = machine.parts[name]
        todo.extend(kind(part.kind).refs(part.values).values())
    return out


def rounded(value: float, scale: float) -> float:
    """``value``, or 0.0 when it is round-off next to ``scale`` (a backlash of 1e-16 mm).

    Examples
    --------
    >>> rounded(-8.9e-16, 135.0), rounded(0.02, 135.0)
    (0.0, 0.02)
    """
    return 0.0 if abs(value) <= 1e-12 * abs(scale) else float(value)


def flagged_rows(label: str, inputs: np.ndarray, ok: np.ndarray, reason: np.ndarray) -> list[str]:
    """One line per sample that was not solved: ``theta2 = 200 deg: why``."""
    lines = []
    for value, good, why in zip(np.ravel(inputs), np.ravel(ok), np.ravel(reason), strict=True):
        if not good:
            shown = f"{value:.6g}" if math.isfinite(value) else str(value)
            lines.append(f"{label} = {shown}: {why}")
    return lines
