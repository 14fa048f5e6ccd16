"""Small helpers shared by the linkage modules: the ground's name, points, frozen tables."""

from __future__ import annotations

import itertools
from collections.abc import Mapping
from types import MappingProxyType
from typing import TYPE_CHECKING, Any

import numpy as np

from .._validate import magnitude, point, text
from ..errors import InputError

if TYPE_CHECKING:
    from .builder import Linkage

#: The name of the fixed link.
GROUND = "ground"


def _complex_point(field: str, value: Any) -> complex:
    """A drawn point, ``(x, y)`` or ``x + yj`` (machdyn._validate.point: finite, within ±1e50)."""
    return point(field, value)


def _name(field: str, value: Any) -> str:
    """A point, link or joint name: non-empty text (machdyn._validate.text)."""
    return text(field, value)


def _link_pair(field: str, links: Any) -> tuple[str, ...]:
    """``()`` or two link names, as ``links=`` of an actuator, spring or motor takes."""
    given = tuple(links) if isinstance(links, list | tuple) else None
    if given is None or len(given) not in (0, 2) or not all(isinstance(n, str) for n in given):
        raise InputError(field, f"give two link names, got {links!r}")
    return given


def _frozen(d: dict[str, np.ndarray]) -> Mapping[str, np.ndarray]:
    for v in d.values():
        v.flags.writeable = False
    return MappingProxyType(d)


def _is_inf(value: Any) -> bool:
    try:
        return bool(np.isposinf(float(magnitude(value))))
    except (TypeError, ValueError, OverflowError):
        return False


def _is_zero(value: Any) -> bool:
    if isinstance(value, Mapping):
        return all(np.all(np.asarray(v) == 0) for v in value.values())
    return bool(np.all(np.asarray(value) == 0))


def _ref_angle(lk: Linkage, link: str) -> float:
    if link == GROUND:
        return 0.0
    p = lk._links[link].points
    if len(p) < 2:
        return 0.0
    z = lk._points[p[1]] - lk._points[p[0]]
    return float(np.angle(z)) if abs(z) else 0.0


def _typical_length(lk: Linkage) -> float:
    """The mean distance from each link's first point to its others (1 if there is none)."""
    sizes = [
        abs(lk._points[q] - lk._points[ln.points[0]])
        for ln in lk._links.values()
        for q in ln.points[1:]
    ]
    sizes = [d for d in sizes if d > 0]
    return float(np.mean(sizes)) if sizes else 1.0


def check_motion(lk: Linkage, motion: Any) -> None:
    """Refuse a motion that ``lk.solve`` did not return (another linkage's, same names or not).

    Its links, the ground points and every link's point-to-point lengths are
    checked on up to 16 solved poses (a motion of another drawing fails at the first).
    """
    if set(motion.theta) != set(lk._links):
        raise InputError(
            "motion",
            f"is not a motion of this linkage (links {', '.join(motion.theta)}, not "
            f"{', '.join(lk._links)}); pass what this linkage's solve() returned",
        )
    there = np.flatnonzero(np.ravel(motion.ok))[:16]  # a few poses tell
    size = max((abs(z) for z in lk._points.values()), default=1.0) or 1.0
    have = motion.points  # (every point of a link; a rolling profile's may be absent)
    for p in (p for p in lk._ground if p in have):
        moved = np.abs(np.ravel(motion.points[p])[there] - lk._points[p])
        if np.any(moved > 1e-7 * size):
            raise InputError(
                "motion",
                f"is not a motion of this linkage: its ground point {p} is not where this "
                "linkage has it; pass what this linkage's solve() returned",
            )
    for name, ln in lk._links.items():
        pts = [p for p in ln.points if p in have]
        for p, q in itertools.pairwise(pts):
            drawn = abs(lk._points[q] - lk._points[p])
            now = np.abs(np.ravel(motion.points[q])[there] - np.ravel(motion.points[p])[there])
            if np.any(np.abs(now - drawn) > 1e-7 * size):
                raise InputError(
                    "motion",
                    f"is not a motion of this linkage: {p}{q} on link {name!r} is "
                    f"{float(now.max()):.6g} long in it, {drawn:.6g} in the drawing; pass what "
                    "this linkage's solve() returned",
                )
