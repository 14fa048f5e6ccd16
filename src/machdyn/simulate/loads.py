"""Loads for :func:`machdyn.simulate` that depend on position, speed or time.

The model's own constant loads (gravity, springs, dampers, a constant
``load_torque4``, friction) go to :func:`machdyn.simulate` as the model's
force-analysis options. The loads here are the ones that change in time or
with the motion: a torque on a link, or a force at a point of a link, given as
a constant or as a law ``f(t, x, v)`` of time and of the load's *own*
coordinate:

* a :func:`torque` on a link: ``x`` is that link's angle θ (radians, not
  wrapped) and ``v`` its angular velocity ω;
* a :func:`force` at a point: ``x`` is the point's position and ``v`` its
  velocity, complex ``x + jy`` (for a slider, ``x.real`` is its travel along
  the slide), and the law returns the complex force ``Fx + jFy``.

Its generalised force on the input coordinate ``q`` is the power per unit
input speed: ``T ∂θ/∂q`` or ``Re(conj(F) ∂P/∂q)`` (virtual work).

Examples
--------
A torque resisting the output link's motion like a viscous brake, and a
piston force that switches on at t = 1 s:

>>> brake = torque(4, lambda t, theta, omega: -0.5 * omega)
>>> gas = force(4, 0.0, step(1.0, 0.0, -200.0))
>>> gas.breakpoints
(1.0,)
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from .._validate import complex_scalar, finite_scalar, text
from ..errors import InputError
from .motors import call_law

__all__ = ["Load", "Step", "force", "step", "torque"]


@dataclass(frozen=True)
class Step:
    """A value that jumps from ``before`` to ``after`` at time ``at`` (a load step).

    Callable as a load law ``f(t, x, v)``; the simulation splits its integration
    at ``at`` so the jump is exact.

    Examples
    --------
    >>> s = step(2.0, 0.0, -10.0)
    >>> float(s(1.0, 0.0, 0.0)), float(s(2.0, 0.0, 0.0))
    (0.0, -10.0)
    """

    at: float
    before: complex | float
    after: complex | float

    @property
    def breakpoints(self) -> tuple[float, ...]:
        """``(at,)``."""
        return (self.at,)

    def __call__(self, t: Any, x: Any = 0.0, v: Any = 0.0) -> Any:
        """``before`` until ``at``, ``after`` from then on (any ``x``, ``v``)."""
        if np.ndim(t) == 0:
            return self.after if t >= self.at else self.before
        return np.where(np.asarray(t) >= self.at, self.after, self.before)


def step(at: float, before: float | complex, after: float | complex) -> Step:
    """A load that steps from ``before`` to ``after`` at time ``at`` (see :class:`Step`).

    Examples
    --------
    >>> step(1.0, 0.0, -5.0)
    Step(at=1.0, before=0.0, after=-5.0)
    """
    at = finite_scalar("at", at, "second")
    values = []
    for name, value in (("before", before), ("after", after)):
        z = complex_scalar(name, value)
        values.append(z.real if z.imag == 0.0 else z)
    return Step(at, values[0], values[1])


@dataclass(frozen=True)
class Load:
    """A torque on a link (``point is None``) or a force at a point of a link.

    Build it with :func:`torque` or :func:`force`.

    Attributes
    ----------
    link : int or str
        The link it acts on (2, 3, 4 for a FourBar or SliderCrank; a link name
        for a Linkage).
    value : float, complex or callable
        The torque (real) or force (complex), or a law ``f(t, x, v)``.
    point : complex, str or None
        Where a force acts: a complex position in the link's frame (FourBar,
        SliderCrank: origin at the link's first joint, x toward its second) or
        a point name (Linkage). None for a torque.
    """

    link: int | str
    value: Any
    point: complex | str | None = None

    @property
    def is_torque(self) -> bool:
        """True for a torque, False for a force at a point."""
        return self.point is None

    @property
    def breakpoints(self) -> tuple[float, ...]:
        """Times where the value jumps (from a :class:`Step` or a ``breakpoints`` attribute)."""
        return tuple(getattr(self.value, "breakpoints", ()))

    def __call__(self, t: Any, x: Any, v: Any) -> Any:
        """The load's value at time ``t`` for its coordinate ``x`` and rate ``v``."""
        if callable(self.value):
            what = "torque" if self.is_torque else "force"
            out = call_law(self.value, t, x, v, f"{what} on {self.link}")
            if self.is_torque and np.iscomplexobj(out):
                if np.any(np.imag(out) != 0.0):
                    raise InputError(f"torque on {self.link}", "a torque is a real number")
                out = np.real(out)
            return out
        if np.ndim(t) == 0:
            return self.value
        return np.broadcast_to(self.value, np.shape(t))

    def describe(self) -> str:
        """``"torque on 4"`` or ``"force on 3 at (1+2j)"``."""
        if self.is_torque:
            return f"torque on {self.link}"
        return f"force on {self.link} at {self.point}"


def torque(link: int | str, value: float | Callable[..., Any]) -> Load:
    """A torque on ``link``: a constant or a law ``f(t, theta, omega)`` of the link's own motion.

    Examples
    --------
    >>> torque(4, -5.0).describe()
    'torque on 4'
    """
    link = _link(link)
    if not callable(value):
        value = finite_scalar("value", value)
    return Load(link, value, None)


def force(link: int | str, point: complex | str, value: complex | Callable[..., Any]) -> Load:
    """A force at ``point`` of ``link``: a constant ``Fx + jFy`` or a law ``f(t, P, V)``.

    ``point`` is a complex position in the link's frame (FourBar and
    SliderCrank; the slider's frame is its pin B) or a point name (Linkage).

    Examples
    --------
    >>> force(3, 3.5 + 1j, -10j).describe()
    'force on 3 at (3.5+1j)'
    """
    link = _link(link)
    point = text("point", point) if isinstance(point, str) else complex_scalar("point", point)
    if not callable(value):
        value = complex_scalar("value", value)
    return Load(link, value, point)


def _link(link: Any) -> int | str:
    if isinstance(link, str) and link:
        return link
    if isinstance(link, int | np.integer) and not isinstance(link, bool) and 1 <= link < 1000:
        return int(link)
    raise InputError("link", f"a link number (2, 3, 4) or a link name, got {link!r:.60}")
