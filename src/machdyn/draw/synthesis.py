"""Scenes of synthesis results: the linkage in its precision positions, or tracing its path.

* :class:`~machdyn.synthesis.MotionSynthesis` — one frame per precision
  position (the joints the synthesis returned), the path of the coupler point
  between them behind, and the targets (the coupler point's prescribed
  positions, or those given) marked and numbered;
* :class:`~machdyn.synthesis.PathSynthesis` — the placed linkage turning
  (poses from :meth:`PlacedFourBar.pose`), its coupler curve, and the target
  points with their distances.

The placed linkage's own ``pose`` gives every coordinate; nothing is solved here.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .._validate import integer
from .build import GROUND, PALETTE, TRACE
from .scene import Curve, Item, Readout, Scene

__all__ = ["motion_synthesis_scene", "path_synthesis_scene"]


def _items(has_p: bool) -> tuple[Item, ...]:
    items = [
        Item("line", "link1", ("O2", "O4"), body="1 (ground)", colour=GROUND),
        Item("ground", "ground_O2", ("O2",), body="1 (ground)"),
        Item("ground", "ground_O4", ("O4",), body="1 (ground)"),
    ]
    if has_p:
        items.append(
            Item("plate", "coupler_triangle", ("A", "B", "C"), body="3", colour=PALETTE[1])
        )
    items += [
        Item("bar", "link2", ("O2", "A"), body="2", colour=PALETTE[0]),
        Item("bar", "link3", ("A", "B"), body="3", colour=PALETTE[1]),
        Item("bar", "link4", ("O4", "B"), body="4", colour=PALETTE[2]),
        Item("pin", "joints", ("O2", "A", "B", "O4")),
    ]
    if has_p:
        items.append(Item("point", "coupler_point", ("C",), colour=TRACE))
    return tuple(items)


def motion_synthesis_scene(result: Any, targets: Any = None, n: int = 60) -> Scene:
    """The synthesised linkage in each precision position, over the targets.

    Parameters
    ----------
    result : MotionSynthesis
    targets : array_like of complex, optional
        The prescribed positions of the coupler point (default: where the
        linkage puts its coupler point ``C`` at the precision positions).
    n : int
        Samples of the coupler point's path between the first and last positions.

    Examples
    --------
    >>> from machdyn.synthesis import three_position
    >>> r = three_position(c=[0 + 5.086j, 2.019 + 3.181j, 3.933 + 4.051j],
    ...                    d=[0.741 + 2.703j, 4.428 + 2.529j, 6.304 + 4.83j])
    >>> s = motion_synthesis_scene(r)
    >>> len(s), bool(np.allclose(s.point("A"), r.A))
    (3, True)
    """
    n = integer("n", n, minimum=2)
    pl = result.linkage
    A, B = np.asarray(result.A, complex), np.asarray(result.B, complex)
    k = A.size
    _, _, C, ok = pl.pose(np.asarray(result.theta2, float))
    has_p = pl.fourbar.coupler is not None
    names = ["O2", "O4", "A", "B"] + (["C"] if has_p else [])
    cols = [np.full(k, complex(result.O2)), np.full(k, complex(result.O4)), A, B]
    if has_p:
        cols.append(np.where(ok, C, np.nan))
    marks = np.asarray(C if targets is None else targets, complex).ravel()
    curves = [Curve("targets", marks, "#d62728", "precision positions", "markers")]
    for j in range(k):  # every position at once, faintly, behind the one shown
        chain = np.array([result.O2, A[j], B[j], result.O4], complex)
        curves.append(Curve(f"position{j + 1}", chain, "#bbbbbb", f"position {j + 1}", "dashed"))
    t0, t1 = float(result.theta2[0]), float(result.theta2[-1])
    if result.direction:  # the coupler point's path from the first position to the last
        span = (t1 - t0) % (2 * np.pi) if result.direction > 0 else -((t0 - t1) % (2 * np.pi))
        _, _, path, ok_path = pl.pose(t0 + np.linspace(0.0, span, n))
        curves.insert(
            0,
            Curve(
                "coupler_path",
                np.where(ok_path, path, np.nan),
                TRACE,
                "path of the coupler point",
                "dashed",
            ),
        )
    readout = (
        Readout("position", "", np.arange(1.0, k + 1.0), 0),
        Readout("θ2 (local)", "deg", np.degrees(np.asarray(result.theta2, float))),
    )
    note = "; ".join(result.defects)
    return Scene(
        title=f"motion synthesis: four-bar {'-'.join(f'{v:.4g}' for v in pl.lengths)} "
        f"({pl.fourbar.barker_class}) in its {k} precision positions",
        names=tuple(names),
        xy=np.stack(cols, axis=1),
        items=_items(has_p),
        curves=tuple(curves),
        readout=readout,
        closed=False,
        note=f"defects: {note}" if note else "",
    )


def path_synthesis_scene(result: Any, n: int = 120) -> Scene:
    """The path-synthesis linkage turning, its coupler curve over the target points.

    Examples
    --------
    >>> from machdyn.synthesis import PlacedFourBar
    >>> from machdyn.synthesis.path import PathSynthesis
    >>> pl = PlacedFourBar.from_pivots(O2=0, O4=8, A=4, B=8 + 6j, P=5 + 3j)
    >>> r = PathSynthesis(pl, np.array([5 + 3j]), np.zeros(1), np.zeros(1), "GCRR", True,
    ...                   0.6, True, 0.0, ())
    >>> s = path_synthesis_scene(r, n=12)
    >>> s.names, len(s)
    (('O2', 'O4', 'A', 'B', 'C'), 12)
    """
    n = integer("n", n, minimum=2)
    pl = result.linkage
    theta2 = np.linspace(0.0, 2 * np.pi, n, endpoint=False)
    A, B, C, ok = pl.pose(theta2)
    has_p = pl.fourbar.coupler is not None
    names = ["O2", "O4", "A", "B"] + (["C"] if has_p else [])
    cols = [np.full(n, complex(pl.O2)), np.full(n, complex(pl.O4)), A, B] + ([C] if has_p else [])
    curve = result.curve(max(n, 360))
    curves = (
        Curve("coupler_curve", np.append(curve, curve[:1]), TRACE, "coupler curve"),
        Curve(
            "targets", np.asarray(result.targets, complex), "#000000", "target points", "markers"
        ),
    )
    readout = (Readout("θ2 (local)", "deg", np.degrees(theta2)),)
    worst = float(np.max(result.distance)) if np.size(result.distance) else float("nan")
    note = "; ".join(result.defects)
    return Scene(
        title=f"path synthesis: {result.barker_class} four-bar, largest distance to a target "
        f"{worst:.3g}",
        names=tuple(names),
        xy=np.stack(cols, axis=1),
        items=_items(has_p),
        shown=ok,
        reason=np.where(ok, "", "cannot be assembled").astype(object),
        curves=curves,
        readout=readout,
        closed=bool(ok.all()),
        note=f"defects: {note}" if note else "",
    )
