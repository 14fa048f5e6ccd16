"""Scenes of machine elements: a cam turning under its follower, a gear pair in mesh.

Both draw the model's own geometry: the cam surface and pitch curve of a
:class:`~machdyn.cams.CamProfile` (in the cam frame, turned by the cam angle of
each frame) with the roller on the pitch curve's point (or the flat face at
``base radius + s``); the tooth outlines of :func:`machdyn.gears.profile.mesh_outlines`
turned by the pinion angle and by the pair's velocity ratio, with the line of
action from first to last contact. Nothing is solved here.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .._validate import integer
from .build import PALETTE
from .scene import Curve, Item, Readout, Scene

__all__ = ["cam_scene", "gear_scene"]


def cam_scene(profile: Any, n: int = 120, length_unit: str = "") -> Scene:
    """The cam turning (counter-clockwise) under its follower, one frame per cam angle.

    Examples
    --------
    >>> import numpy as np
    >>> from machdyn import cams
    >>> prog = cams.CamProgram([cams.Segment("rise", np.pi / 2, 1.0, "cycloidal"),
    ...                         cams.Segment("fall", np.pi / 2, 1.0, "cycloidal"),
    ...                         cams.Segment("dwell", np.pi)])
    >>> cam = cams.TranslatingRoller(prime_radius=3.0, roller_radius=0.5).profile(prog, n=360)
    >>> s = cam_scene(cam, n=36)
    >>> z = s.point("roller") * np.exp(-1j * s.angles["cam"])  # back into the cam frame
    >>> bool(np.allclose(z, cam.pitch[::10]))
    True
    """
    n = integer("n", n, minimum=2)
    size = profile.theta.size
    k = np.arange(min(n, size)) * size // min(n, size)  # evenly spaced samples of the turn
    theta = np.asarray(profile.theta)[k]
    turn = np.exp(1j * theta)  # the cam frame turned by the cam angle: fixed = cam · e^{jθ}
    frames = theta.size
    surface = np.asarray(profile.surface, complex)
    names = ["O"]
    cols = [np.zeros(frames, complex)]
    items = [Item("ground", "cam_pivot", ("O",), body="ground")]
    items.append(
        Item(
            "shape",
            "cam",
            ("O",),
            body="cam",
            colour=PALETTE[0],
            angle="cam",
            outline=surface,
            closed=True,
            label="cam",
        )
    )
    r = float(profile.roller_radius)
    if profile.pitch is not None:  # a roller follower: the roller's centre on the pitch curve
        centre = np.asarray(profile.pitch, complex)[k] * turn
        top = centre + 1j * 2.2 * max(profile.prime_radius, 1e-9) * 0.35
        names += ["roller", "stem"]
        cols += [centre, top]
        items.append(
            Item("bar", "follower", ("roller", "stem"), body="follower", colour=PALETTE[1])
        )
        items.append(
            Item(
                "wheel",
                "roller",
                ("roller",),
                body="follower",
                colour=PALETTE[1],
                angle="roller",
                size=r,
            )
        )
        items.append(Item("pin", "pins", ("O", "roller")))
    else:  # a flat face at base radius + s on the follower's axis
        s = np.asarray(profile.s)[k]
        centre = 1j * (profile.base_radius + s)
        width = float(profile.face_width or profile.base_radius)
        names += ["face_a", "face_b", "stem"]
        cols += [
            centre - 0.6 * width,
            centre + 0.6 * width,
            centre + 1j * 0.8 * profile.base_radius,
        ]
        items.append(Item("bar", "face", ("face_a", "face_b"), body="follower", colour=PALETTE[1]))
        names.append("foot")
        cols.append(centre)
        items.append(Item("bar", "follower", ("foot", "stem"), body="follower", colour=PALETTE[1]))
        items.append(Item("pin", "pins", ("O",)))
    angles = {"cam": theta, "roller": np.zeros(frames)}
    t = np.linspace(0, 2 * np.pi, 181)
    curves = [
        Curve(
            "base_circle", profile.base_radius * np.exp(1j * t), "#999999", "base circle", "dashed"
        )
    ]
    readout = (
        Readout("cam angle θ", "deg", np.degrees(theta)),
        Readout("s", length_unit or "model units", np.asarray(profile.s)[k], 4),
        Readout("pressure angle φ", "deg", np.degrees(np.asarray(profile.pressure_angle)[k])),
        Readout("ρ surface", length_unit or "model units", np.asarray(profile.rho_surface)[k], 3),
    )
    return Scene(
        title=f"cam with a {profile.follower} follower",
        names=tuple(names),
        xy=np.stack(cols, axis=1),
        items=tuple(items),
        angles=angles,
        curves=tuple(curves),
        readout=readout,
        length_unit=length_unit,
        closed=True,
    )


def gear_scene(pair: Any, n: int = 120, teeth: int | None = None, points: int = 12) -> Scene:
    """A gear pair in mesh: both gears turning, the line of action from first to last contact.

    The pinion turns counter-clockwise through ``teeth`` tooth pitches (all of
    its teeth by default) in ``n`` frames; the gear turns by the pair's
    velocity ratio (the other way for an external pair).

    Examples
    --------
    >>> from machdyn.gears import Gear, GearPair
    >>> s = gear_scene(GearPair(Gear(18, module=1.0), Gear(40, module=1.0)), n=12)
    >>> [i.gid for i in s.items if i.kind == "shape"]
    ['pinion', 'gear']
    >>> round(float(s.angles["gear"][1] - s.angles["gear"][0]) / float(s.angles["pinion"][1]), 4)
    -0.45
    """
    from ..gears.profile import mesh_outlines

    n = integer("n", n, minimum=2)
    p, g = pair.pinion, pair.gear
    teeth = p.teeth if teeth is None else integer("teeth", teeth, minimum=1)
    pin, gear = mesh_outlines(pair, 0.0, points)
    c = -pair.center_distance if pair.internal else pair.center_distance
    pin_local = np.asarray(pin.x) + 1j * np.asarray(pin.y)
    gear_local = np.asarray(gear.x) + 1j * np.asarray(gear.y) - c
    theta_p = np.linspace(0.0, 2 * np.pi * teeth / p.teeth, n, endpoint=False)
    ratio = p.teeth / g.teeth
    theta_g = (1.0 if pair.internal else -1.0) * ratio * theta_p
    frames = theta_p.size
    phi = pair.operating_pressure_angle
    rp_op, rg_op = pair.operating_pitch_radii
    d = complex(np.sin(phi), np.cos(phi))
    pitch = complex(rp_op, 0.0)
    toward_first = -1.0 if pair.driver == "pinion" else 1.0
    first = pitch + toward_first * pair.path_of_approach * d
    last = pitch - toward_first * pair.path_of_recess * d
    names = ("Op", "Og", "first", "last", "pitch")
    cols = [np.full(frames, z) for z in (0j, complex(c), first, last, pitch)]
    items = (
        Item(
            "shape",
            "pinion",
            ("Op",),
            body=f"pinion N = {p.teeth}",
            colour=PALETTE[0],
            angle="pinion",
            outline=pin_local,
            closed=True,
        ),
        Item(
            "shape",
            "gear",
            ("Og",),
            body=f"gear N = {g.teeth}",
            colour=PALETTE[3],
            angle="gear",
            outline=gear_local,
            closed=not pair.internal,
        ),
        Item("line", "line_of_action", ("first", "last"), body="line of action", colour="#000000"),
        Item("point", "contact", ("first", "pitch"), colour="#d62728"),
        Item("pin", "centres", ("Op", "Og")),
    )
    t = np.linspace(0, 2 * np.pi, 241)
    curves = []
    for name, centre, radius in (("pinion_pitch", 0j, rp_op), ("gear_pitch", complex(c), rg_op)):
        curves.append(
            Curve(name, centre + radius * np.exp(1j * t), "#999999", "pitch circle", "dashed")
        )
    for name, centre, radius in (
        ("pinion_base", 0j, p.base_radius),
        ("gear_base", complex(c), g.base_radius),
    ):
        curves.append(
            Curve(name, centre + radius * np.exp(1j * t), "#cccccc", "base circle", "dashed")
        )
    readout = (
        Readout("pinion angle", "deg", np.degrees(theta_p)),
        Readout("gear angle", "deg", np.degrees(theta_g)),
        Readout("contact ratio", "", np.full(frames, pair.contact_ratio), 3),
    )
    return Scene(
        title=f"gear pair {p.teeth}/{g.teeth}{' (internal)' if pair.internal else ''}: "
        f"contact ratio {pair.contact_ratio:.3f}, φ' = {np.degrees(phi):.2f}°",
        names=names,
        xy=np.stack(cols, axis=1),
        items=items,
        angles={"pinion": theta_p, "gear": theta_g},
        curves=tuple(curves),
        readout=readout,
        closed=teeth == p.teeth,
    )
