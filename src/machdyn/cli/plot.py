"""``machdyn animate``: a four-bar as a GIF, a browser page, or a still picture.

Only parsing and calling: the poses come from :class:`machdyn.FourBar`, the
pictures from :mod:`machdyn.plot` and :mod:`machdyn.viewer`.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import numpy as np
import typer

from ..errors import InputError
from ..fourbar import FourBar

__all__ = ["OUTPUT_KINDS", "animate"]

#: File name endings ``animate`` can write, and what each one holds.
OUTPUT_KINDS = {
    ".gif": "animated GIF",
    ".html": "self-contained browser page (play/pause, slider, readout)",
    ".png": "still pose with the coupler curve",
    ".svg": "still pose with the coupler curve",
}


def animate(
    r1: Annotated[float, typer.Argument(help="Ground link length O2O4.")],
    r2: Annotated[float, typer.Argument(help="Input link length O2A.")],
    r3: Annotated[float, typer.Argument(help="Coupler length AB.")],
    r4: Annotated[float, typer.Argument(help="Output link length O4B.")],
    out: Annotated[
        Path,
        typer.Option("--out", help="Output file: .gif, .html, .png or .svg."),
    ],
    coupler: Annotated[
        str | None, typer.Option(help="Coupler point P:DELTA_DEG (distance from A, angle from AB).")
    ] = None,
    form: Annotated[int, typer.Option(help="Form 1 or 2, as in the notes.")] = 1,
    frames: Annotated[
        int | None,
        typer.Option(help="Samples per stroke (default 90 for .gif, 360 for .html)."),
    ] = None,
    fps: Annotated[float, typer.Option(help="Frames per second (.gif, .html).")] = 30.0,
    theta2: Annotated[
        float | None,
        typer.Option(help="Input angle of the still pose, degrees (.png, .svg)."),
    ] = None,
) -> None:
    """Draw or animate a four-bar: GIF, HTML page (browser viewer), PNG or SVG."""
    kind = out.suffix.lower()
    if kind not in OUTPUT_KINDS:
        valid = ", ".join(OUTPUT_KINDS)
        raise InputError("--out", f"unknown file type {out.suffix!r}; use one of {valid}")
    if form not in (1, 2):
        raise InputError("--form", f"must be 1 or 2, got {form}")
    if frames is not None and frames < 2:
        raise InputError("--frames", f"must be at least 2, got {frames}")
    from .fourbar import _parse_coupler  # here: cli.fourbar imports the app, which imports us

    fb = FourBar(r1, r2, r3, r4, coupler=_parse_coupler(coupler))
    if kind == ".html":
        from ..viewer import to_html

        to_html(fb, form=form, n=frames or 360, path=out, fps=fps)
        print(f"wrote {out} (open it in a browser)")
    elif kind == ".gif":
        from ..plot import animate as animate_gif

        anim = animate_gif(fb, form=form, n=frames or 90, path=out, fps=fps)
        count = len(list(anim.new_frame_seq()))
        print(f"wrote {out} ({count} frames at {fps:g} fps)")
    else:
        _still(fb, form, None if theta2 is None else float(np.radians(theta2)), out)
        print(f"wrote {out}")


def _still(fb: FourBar, form: int, theta2: float | None, out: Path) -> None:
    from matplotlib.figure import Figure

    from ..plot import draw_fourbar, plot_coupler_curve

    fig = Figure(figsize=(7, 5.5), layout="constrained")
    ax = fig.add_subplot()
    if fb.coupler is not None:
        plot_coupler_curve(fb, form, ax, theta2=theta2)
    else:
        start = fb.input_range(form).lo if theta2 is None else theta2
        draw_fourbar(fb, start, ax=ax, form=form)
    fig.savefig(out, dpi=100)
