"""Scenes of the closed-form models, built from their own solved motion.

:func:`scene` is the one entry point: give it a model (``FourBar``,
``SliderCrank``, ``InvertedSliderCrank``, a ``Linkage``, a cam, a gear pair or
a synthesis result) and it solves the model's motion with the model's own
methods and returns a :class:`~machdyn.draw.scene.Scene`. Nothing here solves
a loop: points come from ``solve()``; the only arithmetic is where a symbol is
placed (the ends of a slide line drawn under a block, an offset arm's foot
from the solved angle).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .._validate import choice, finite_scalar, integer
from ..errors import InputError
from ..fourbar import FourBar
from ..slidercrank import (
    InvertedSliderCrank,
    InvertedSliderCrankMotion,
    SliderCrank,
    SliderCrankMotion,
)
from .scene import Curve, Item, Readout, Scene

__all__ = ["PALETTE", "describe", "fourbar_scene", "inverted_scene", "scene", "slidercrank_scene"]

#: Colours of moving bodies in the order they are listed (matplotlib's default cycle).
PALETTE = (
    "#1f77b4",
    "#ff7f0e",
    "#2ca02c",
    "#9467bd",
    "#8c564b",
    "#e377c2",
    "#17becf",
    "#bcbd22",
    "#d62728",
    "#7f7f7f",
)
GROUND = "#888888"
TRACE = "#d62728"


def _flat(values: Any) -> np.ndarray:
    return np.ravel(np.asarray(values))


def _nan_where(values: Any, keep: np.ndarray) -> np.ndarray:
    return np.where(keep, _flat(values), np.nan)


def _deg(values: Any, keep: np.ndarray) -> np.ndarray:
    return np.degrees(_nan_where(np.asarray(values, dtype=float), keep))


def _unit(model: Any) -> str:
    """The length unit the model's coordinates are in ('' when it has none).

    A model built from pint quantities names it in ``length_unit``; one read
    from a machine file computes in its unit system's length unit.
    """
    unit = getattr(model, "length_unit", None)
    system = getattr(model, "units", None)
    if not unit and system is not None and not getattr(system, "is_unit_free", True):
        unit = system.internal("length")
    return str(unit or "")


# --------------------------------------------------------------------------------------
# Four-bar


def describe(fourbar: FourBar) -> str:
    """A four-bar's name for titles: lengths, coupler point with δ in degrees, unit.

    Examples
    --------
    >>> describe(FourBar(8, 4, 7, 6, coupler=(5, np.radians(30))))
    'four-bar 8-4-7-6 (GCRR), P: p = 5, δ = 30°'
    """
    text = "four-bar " + "-".join(f"{v:g}" for v in fourbar.lengths)
    if fourbar.length_unit:
        text += f" {fourbar.length_unit}"
    text += f" ({fourbar.barker_class})"
    if fourbar.coupler is not None:
        p, delta = fourbar.coupler
        text += f", P: p = {p:g}, δ = {np.degrees(delta):.4g}°"
    return text


def fourbar_scene(
    fourbar: FourBar,
    motion: Any,
    *,
    coupler_curve: np.ndarray | None = None,
    closed: bool = False,
) -> Scene:
    """The scene of a four-bar over the poses of ``motion``.

    Parameters
    ----------
    fourbar : FourBar
    motion : FourBarMotion or machdyn.plot.Sweep
        Solved poses, one frame each (flattened).
    coupler_curve : ndarray of complex, optional
        A static coupler curve drawn behind the linkage.
    closed : bool
        Whether the frames make one cycle.

    Examples
    --------
    >>> fb = FourBar(8, 4, 7, 6, coupler=(5, 0.5))
    >>> s = fourbar_scene(fb, fb.solve(np.radians([0, 90])))
    >>> s.names, len(s)
    (('O2', 'O4', 'A', 'B', 'P'), 2)
    >>> bool(np.allclose(s.point("B"), fb.solve(np.radians([0, 90])).B))
    True
    """
    assembled = _flat(motion.assembled).astype(bool)
    frames = assembled.size
    A, B = _nan_where(motion.A, assembled), _nan_where(motion.B, assembled)
    names = ["O2", "O4", "A", "B"]
    cols = [np.zeros(frames, complex), np.full(frames, complex(fourbar.r1)), A, B]
    has_p = motion.coupler is not None
    if has_p:
        names.append("P")
        cols.append(_nan_where(motion.coupler, assembled))
    items = [
        Item("line", "link1", ("O2", "O4"), body="1 (ground)", colour=GROUND),
        Item("ground", "ground_O2", ("O2",), body="1 (ground)"),
        Item("ground", "ground_O4", ("O4",), body="1 (ground)"),
    ]
    if has_p:
        items.append(
            Item("plate", "coupler_triangle", ("A", "B", "P"), body="3", colour=PALETTE[1])
        )
    items += [
        Item("bar", "link2", ("O2", "A"), body="2", colour=PALETTE[0]),
        Item("bar", "link3", ("A", "B"), body="3", colour=PALETTE[1]),
        Item("bar", "link4", ("O4", "B"), body="4", colour=PALETTE[2]),
        Item("pin", "joints", ("O2", "A", "B", "O4")),
    ]
    if has_p:
        items.append(Item("point", "coupler_point", ("P",), colour=TRACE))
    ok = _flat(motion.ok).astype(bool)
    readout = [
        Readout("θ2", "deg", np.degrees(_flat(motion.theta2).astype(float))),
        Readout("θ3", "deg", _deg(motion.theta3, assembled)),
        Readout("θ4", "deg", _deg(motion.theta4, assembled)),
        Readout("μ", "deg", _deg(motion.mu, assembled)),
    ]
    if motion.omega3 is not None:
        readout += [
            Readout("ω3", "rad/s", _nan_where(motion.omega3, ok).astype(float), 4),
            Readout("ω4", "rad/s", _nan_where(motion.omega4, ok).astype(float), 4),
        ]
    curves = ()
    if coupler_curve is not None:
        curves = (
            Curve("coupler_curve", np.asarray(coupler_curve, complex), TRACE, "coupler curve"),
        )
    form = getattr(motion, "form", None)
    return Scene(
        title=describe(fourbar) + (f", form {form}" if form is not None else ""),
        names=tuple(names),
        xy=np.stack(cols, axis=1),
        items=tuple(items),
        shown=assembled,
        reason=_flat(motion.reason),
        curves=curves,
        readout=tuple(readout),
        length_unit=_unit(fourbar),
        closed=closed,
    )


# --------------------------------------------------------------------------------------
# Slider-cranks


def _guide_ends(centre_line: np.ndarray, margin: float) -> tuple[float, float]:
    values = centre_line[np.isfinite(centre_line)]
    if values.size == 0:
        return -margin, margin
    return float(values.min() - margin), float(values.max() + margin)


def slidercrank_scene(slidercrank: SliderCrank, motion: SliderCrankMotion) -> Scene:
    """The scene of an offset slider-crank: crank, rod, block on its guide.

    The slide line is drawn at the offset ``c`` under the block, over the
    range the solved slider positions cover.

    Examples
    --------
    By hand, ``|B − A| = 6`` with ``B = (d, 0.5)``: at θ2 = 0, A = (2, 0) and
    ``d = 2 + √35.75``; at 90°, A = (0, 2) and ``d = √33.75``:

    >>> sc = SliderCrank(2.0, 6.0, 0.5)
    >>> s = slidercrank_scene(sc, sc.solve(np.radians([0, 90])))
    >>> [round(float(v), 6) for v in s.point("B").real]
    [7.97913, 5.809475]
    """
    assembled = _flat(motion.assembled).astype(bool)
    frames = assembled.size
    a, b, c = slidercrank.a, slidercrank.b, slidercrank.c
    A, B = _nan_where(motion.A, assembled), _nan_where(motion.B, assembled)
    block = 0.22 * b
    lo, hi = _guide_ends(B.real, block)
    names = ["O2", "A", "B", "G1", "G2"]
    cols = [
        np.zeros(frames, complex),
        A,
        B,
        np.full(frames, complex(lo, c)),
        np.full(frames, complex(hi, c)),
    ]
    has_p = motion.coupler is not None
    if has_p:
        names.append("P")
        cols.append(_nan_where(motion.coupler, assembled))
    items = [
        Item("ground", "ground_O2", ("O2",), body="1 (ground)"),
        Item("guide", "slide_guide", ("G1", "G2"), body="ground", colour="#000000"),
        Item(
            "slider",
            "slider",
            ("B",),
            body="4 (slider)",
            colour=PALETTE[2],
            angle="guide",
            size=block,
        ),
    ]
    if has_p:
        items.append(
            Item("plate", "coupler_triangle", ("A", "B", "P"), body="3", colour=PALETTE[1])
        )
    items += [
        Item("bar", "link2", ("O2", "A"), body="2", colour=PALETTE[0]),
        Item("bar", "link3", ("A", "B"), body="3", colour=PALETTE[1]),
        Item("pin", "joints", ("O2", "A", "B")),
    ]
    if has_p:
        items.append(Item("point", "coupler_point", ("P",), colour=TRACE))
    ok = _flat(motion.ok).astype(bool)
    readout = [
        Readout("θ2", "deg", np.degrees(_flat(motion.theta2).astype(float))),
        Readout("θ3", "deg", _deg(motion.theta3, assembled)),
        Readout("d", _unit(slidercrank) or "model units", _nan_where(motion.d, assembled), 4),
        Readout("ḋ", (_unit(slidercrank) or "model units") + "/s", _nan_where(motion.d_dot, ok), 4),
    ]
    del a
    return Scene(
        title=f"{slidercrank!r}, form {motion.form}",
        names=tuple(names),
        xy=np.stack(cols, axis=1),
        items=tuple(items),
        shown=assembled,
        reason=_flat(motion.reason),
        angles={"guide": np.zeros(frames)},
        readout=tuple(readout),
        length_unit=_unit(slidercrank),
        closed=bool(slidercrank.crank_rotates),
    )


def inverted_scene(model: InvertedSliderCrank, motion: InvertedSliderCrankMotion) -> Scene:
    """The scene of Norton's inverted slider-crank: a block on the crank pin slides in link 4.

    Link 4 is drawn from O4 (with its offset arm when ``c ≠ 0``) along the
    solved angle θ4 past the block.

    Examples
    --------
    >>> isc = InvertedSliderCrank(2.0, 4.0)
    >>> s = inverted_scene(isc, isc.solve(np.radians([90.0])))
    >>> complex(s.point("A")[0]).imag
    2.0
    """
    assembled = np.isfinite(_flat(motion.b))
    frames = assembled.size
    theta4 = _nan_where(motion.theta4, assembled).astype(float)
    e4 = np.exp(1j * theta4)
    O4 = complex(model.d)
    foot = O4 + 1j * model.c * e4  # where the slot line meets the offset arm
    b = _nan_where(motion.b, assembled).astype(float)
    reach = float(np.nanmax(np.abs(b))) if assembled.any() else model.a + model.d
    block = 0.18 * (model.a + model.d) * 0.5
    sign = 1.0 if motion.form == 1 else -1.0
    end = foot + sign * (reach + 1.2 * block) * e4
    names = ("O2", "O4", "A", "F", "E")
    cols = [
        np.zeros(frames, complex),
        np.full(frames, O4),
        _nan_where(motion.A, assembled),
        foot,
        end,
    ]
    items = [
        Item("ground", "ground_O2", ("O2",), body="1 (ground)"),
        Item("ground", "ground_O4", ("O4",), body="1 (ground)"),
        Item("line", "link1", ("O2", "O4"), body="1 (ground)", colour=GROUND),
        Item("bar", "link4", ("F", "E"), body="4", colour=PALETTE[2]),
    ]
    if model.c != 0.0:
        items.append(Item("bar", "link4_arm", ("O4", "F"), body="4", colour=PALETTE[2]))
    items += [
        Item(
            "slider",
            "slider",
            ("A",),
            body="3 (block)",
            colour=PALETTE[1],
            angle="theta4",
            size=block,
        ),
        Item("bar", "link2", ("O2", "A"), body="2", colour=PALETTE[0]),
        Item("pin", "joints", ("O2", "A", "O4")),
    ]
    readout = (
        Readout("θ2", "deg", np.degrees(_flat(motion.theta2).astype(float))),
        Readout("θ4", "deg", np.degrees(theta4)),
        Readout("b", _unit(model) or "model units", b, 4),
    )
    return Scene(
        title=f"{model!r}, form {motion.form}",
        names=names,
        xy=np.stack(cols, axis=1),
        items=tuple(items),
        shown=assembled,
        reason=_flat(motion.reason),
        angles={"theta4": np.where(assembled, theta4, 0.0)},
        readout=readout,
        length_unit=_unit(model),
        closed=bool(assembled.all()),
    )


# --------------------------------------------------------------------------------------
# One entry point


def _turn(n: int) -> np.ndarray:
    return np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)


def scene(model: Any, *, n: int = 120, form: int = 1, theta2: Any = None, **options: Any) -> Scene:
    """The scene of any drawable model over its motion (solved here by the model).

    Parameters
    ----------
    model : FourBar, SliderCrank, InvertedSliderCrank, Linkage, Scene, or any
        object with a ``scene()`` method (cams, gear pairs, synthesis results).
    n : int
        Frames per stroke of the default motion.
    form : {1, 2}
        The form (circuit) of a closed-form model.
    theta2 : array_like, optional
        Explicit input angles (radians) of the frames.
    **options
        Passed to the model's own ``scene()``.

    Examples
    --------
    >>> len(scene(FourBar(8, 4, 7, 6), n=36))
    36
    >>> scene(SliderCrank(2.0, 6.0), n=10).names[:3]
    ('O2', 'A', 'B')
    """
    if isinstance(model, Scene):
        return model
    n = integer("n", n, minimum=1)
    if isinstance(model, FourBar):
        from .fourbar import sweep

        s = sweep(model, form, n, theta2)
        curve = None
        if model.coupler is not None:
            curve = model.coupler_curve(form, max(n, 360)).points
            if theta2 is None and (model.input_range(form).full_turn or model.form_rule == "phi34"):
                curve = np.append(curve, curve[:1])
        return fourbar_scene(model, s, coupler_curve=curve, closed=theta2 is None)
    choice("form", form, (1, 2))
    omega2 = finite_scalar("omega2", options.pop("omega2", 1.0), "radian / second")
    if isinstance(model, SliderCrank):
        if theta2 is None:
            rng = model.input_range()
            if rng is None:
                theta2 = _turn(n)
            else:
                go = np.linspace(rng[0], rng[1], n)
                theta2 = np.concatenate([go, go[-2:0:-1]])
        with np.errstate(invalid="ignore", divide="ignore"):
            return slidercrank_scene(model, model.solve(np.ravel(theta2), omega2, form=form))
    if isinstance(model, InvertedSliderCrank):
        t = _turn(n) if theta2 is None else np.ravel(theta2)
        with np.errstate(invalid="ignore", divide="ignore"):
            return inverted_scene(model, model.solve(t, omega2, form=form))
    from ..cams import CamProfile
    from ..gears import GearPair, GearTrain, PlanetaryTrain
    from ..linkage import Linkage

    if isinstance(model, GearTrain | PlanetaryTrain):  # schematics turning at the shaft speeds
        from .gears import planetary_scene, train_scene

        if isinstance(model, GearTrain):
            return train_scene(model, options.pop("omega_in", 1.0), n=n, **options)
        return planetary_scene(model, options.pop("speeds", None), n=n, **options)
    if isinstance(model, CamProfile):
        from .elements import cam_scene

        return cam_scene(model, n=n, **options)
    if isinstance(model, GearPair):
        from .elements import gear_scene

        return gear_scene(model, n=n, **options)
    from ..synthesis import MotionSynthesis, PathSynthesis

    if isinstance(model, MotionSynthesis):
        from .synthesis import motion_synthesis_scene

        return motion_synthesis_scene(model, options.pop("targets", None))
    if isinstance(model, PathSynthesis):
        from .synthesis import path_synthesis_scene

        return path_synthesis_scene(model, n=n)
    if isinstance(model, Linkage):
        from .linkage import scene_of_linkage

        return scene_of_linkage(model, options.pop("values", None), n=n, **options)
    if hasattr(model, "scene"):
        return model.scene(n=n, **options)
    raise InputError(
        "model",
        f"cannot draw a {type(model).__name__}; expected a FourBar, SliderCrank, "
        "InvertedSliderCrank, Linkage, cam, gear pair, gear or planetary train, synthesis "
        "result or Scene",
    )
