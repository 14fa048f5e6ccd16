"""Drawings, animations and engineering plots of every model (the front-end).

One drawing path serves every model: :func:`scene` turns a model's *solved*
motion into a :class:`Scene` (points per frame, and how to draw them), and two
back ends render it — matplotlib (:func:`draw`, :func:`animate`: PNG, SVG,
GIF, MP4) and the browser (:func:`to_svg`, :func:`to_html`: an inline SVG and
a self-contained page that plays the motion). No kinematics is computed here.

matplotlib is imported only when a matplotlib function runs.

Examples
--------
>>> from machdyn import FourBar
>>> import machdyn.draw as md
>>> s = md.scene(FourBar(8, 4, 7, 6, coupler=(5, 0.5)), n=36)
>>> len(s), s.names
(36, ('O2', 'O4', 'A', 'B', 'P'))
>>> md.to_svg(s).startswith("<svg")
True
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from .build import scene
from .html import to_svg
from .scene import Curve, Item, Readout, Scene

__all__ = [
    "Curve",
    "Item",
    "Readout",
    "Scene",
    "animate",
    "draw",
    "scene",
    "to_html",
    "to_svg",
]


def draw(model: Any, frame: int | None = None, ax: Any = None, **options: Any) -> Any:
    """Draw ``model`` in one pose on matplotlib Axes (see :func:`machdyn.draw.mpl.draw_scene`).

    ``options`` go to :func:`scene` (``n``, ``form``, ``theta2``, ...) and to
    the renderer (``labels``, ``status``). ``instant_centres=True`` also marks
    the model's instant centres in that pose (``model.instant_centres``, for a
    four-bar, slider-crank, inverted slider-crank or linkage): a centre inside
    the view is a labelled cross, one outside an arrow at the border labelled
    with its coordinates, one at infinity an arrow along its direction.

    Examples
    --------
    >>> from machdyn import InvertedSliderCrank, SliderCrank
    >>> ax = draw(InvertedSliderCrank(2.0, 4.0), n=8)
    >>> ax = draw(SliderCrank(2.0, 6.0), 1, n=8, instant_centres=True)
    >>> [t.get_gid() for t in ax.texts if t.get_gid() == "centre_arrow_I14"]  # at infinity
    ['centre_arrow_I14']
    >>> import matplotlib.pyplot as plt; plt.close("all")
    """
    from .mpl import draw_scene

    render = {k: options.pop(k) for k in ("labels", "status", "title") if k in options}
    centres = bool(options.pop("instant_centres", False))
    s = scene(model, **options)
    ax = draw_scene(s, frame, ax, **render)
    if centres:
        from .fourbar import draw_centres

        k = (s.first_shown() if frame is None else frame) % len(s)
        draw_centres(ax, _centres_at(model, s, k, options.get("form", 1)), tuple(s.xy[k]))
    return ax


def _centres_at(model: Any, s: Scene, k: int, form: int) -> Any:
    """The model's instant centres in frame ``k`` of its scene (inputs read off the readout)."""
    from ..errors import InputError

    inputs = {r.label: r for r in s.readout}
    if hasattr(model, "drivers") and hasattr(model, "instant_centres"):  # a Linkage
        values = {}
        for d in model.drivers:
            r = inputs.get(f"θ {d} (driver)") or inputs.get(f"{d} (driver)")
            v = float(r.values[k])
            values[d] = np.radians(v) if r.unit == "deg" else v
        return model.instant_centres(values)
    if "θ2" in inputs and hasattr(model, "instant_centres"):
        return model.instant_centres(np.radians(float(inputs["θ2"].values[k])), form)
    raise InputError("instant_centres", f"a {type(model).__name__} has no instant centres to draw")


def animate(model: Any, path: str | Path | None = None, **options: Any) -> Any:
    """Animate ``model``: a matplotlib animation, saved to ``path`` (.gif, .mp4, .html).

    See :func:`machdyn.plot.animate` for the options.
    """
    from .fourbar import animate as animate_model

    return animate_model(model, path=path, **options)


def to_html(model: Any, path: str | Path | None = None, **options: Any) -> str:
    """A self-contained HTML page that plays ``model``'s motion (see :mod:`machdyn.draw.html`).

    Examples
    --------
    >>> from machdyn import SliderCrank
    >>> to_html(SliderCrank(2.0, 6.0), n=12).startswith("<!DOCTYPE html>")
    True
    """
    from .html import to_html as page

    render = {k: options.pop(k) for k in ("fps", "labels", "title") if k in options}
    return page(scene(model, **options), path, **render)
