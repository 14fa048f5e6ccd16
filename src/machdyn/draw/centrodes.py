"""Drawing centrodes: the fixed centrode, the moving one where it sits, and the contact.

No kinematics here: everything comes from a :class:`machdyn.centrodes.Centrodes`.
Every artist carries a ``gid`` (``"fixed_centrode"``, ``"moving_centrode"``,
``"centrode_contact"``) so that it can be found again (and tested).
"""

from __future__ import annotations

from typing import Any

import numpy as np

__all__ = ["plot_centrodes"]


def plot_centrodes(
    c: Any, ax: Any = None, frame: int | None = None, *, title: str | None = None
) -> Any:
    """Draw both centrodes of ``c`` in the fixed link's frame.

    The fixed centrode is a solid line; the moving centrode is drawn where it
    sits at sample ``frame`` (default: the middle ok sample), touching the fixed
    one at the contact point (marked). Where the centre runs off to infinity
    the curves are broken, not joined across.

    Parameters
    ----------
    c : Centrodes
        From :func:`machdyn.centrodes.centrodes`.
    ax : matplotlib Axes, optional
    frame : int, optional
        The sample at which to place the moving centrode.
    title : str, optional

    Returns
    -------
    matplotlib Axes

    Examples
    --------
    >>> import numpy as np
    >>> from machdyn import FourBar
    >>> from machdyn.centrodes import centrodes
    >>> c = centrodes(FourBar(8, 4, 7, 6), np.radians(np.linspace(20, 80, 61)), moving=3)
    >>> ax = plot_centrodes(c)
    >>> sorted(a.get_gid() for a in ax.lines)
    ['centrode_contact', 'fixed_centrode', 'moving_centrode']
    >>> import matplotlib.pyplot as plt; plt.close("all")
    """
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots()
    ok = np.flatnonzero(c.ok)
    if frame is None:
        frame = int(ok[ok.size // 2]) if ok.size else 0
    fixed = np.where(c.ok, c.fixed, np.nan)
    placed = np.where(c.ok, c.placed(frame), np.nan)
    (line,) = ax.plot(fixed.real, fixed.imag, "-", color="C0", label="fixed centrode")
    line.set_gid("fixed_centrode")
    (line,) = ax.plot(placed.real, placed.imag, "--", color="C3", label="moving centrode")
    line.set_gid("moving_centrode")
    touch = complex(fixed[frame]) if bool(c.ok[frame]) else complex(np.nan, np.nan)
    (mark,) = ax.plot([touch.real], [touch.imag], "o", color="k", ms=5, label="contact I")
    mark.set_gid("centrode_contact")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x")
    ax.set_ylabel("y")
    ax.legend(loc="best", fontsize=8)
    ax.set_title(
        title
        if title is not None
        else f"centrodes of link {c.moving_link} relative to link {c.fixed_link}"
    )
    return ax
