"""Open ``[fourbar]``, ``[slider_crank]`` and ``[inverted_slider_crank]`` parts in the studio.

The studio edits drawn linkages (``[linkage.NAME]``). A file from ``machdyn synth
path``, or one written by hand with a ``[fourbar.NAME]``, ``[slider_crank.NAME]`` or
``[inverted_slider_crank.NAME]`` part, is turned into the same machine drawn as a
linkage: its points placed in one assembled pose (the part's ``form``/``branch``; a
placed four-bar's ``O2`` and ``theta1``), its links named as the textbooks name them,
the coupler point traced, the masses, loads, gravity, the input's motion and the
file's units kept. What a linkage part has no key for is listed in the notes the page
shows (nothing is dropped without a word).

Only the library computes the pose: ``FourBar.solve``, ``SliderCrank.solve`` and
``InvertedSliderCrank.solve`` at the drawn input; the page's analysis then runs on the
drawn linkage (the other code path), so the two can be compared
(``tests/test_studio_convert.py``).
"""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from ..errors import InputError

__all__ = ["CONVERTED", "linkage_document"]

#: Part kinds the studio opens as a drawn linkage.
CONVERTED = ("fourbar", "slider_crank", "inverted_slider_crank")

#: How a note naming what the drawing does not keep begins (Save refuses to lose it).
NOT_KEPT = "Not kept: "

#: Tables of these parts a linkage part has no key for, and why.
_NOT_KEPT = {
    "simulate": "the forward-dynamics table of `machdyn simulate`; a linkage part has none",
    "tolerance": (
        "its tolerances are of r1..r4, p, delta; a linkage's are of drawn points (docs/spec.md)"
    ),
}


def linkage_document(machine: Any) -> tuple[dict[str, Any], list[str]]:
    """The machine as a spec document the studio can edit, and notes for the page.

    A machine with a ``linkage`` part, or with no part of a kind in :data:`CONVERTED`, is
    returned as it is (no notes). Otherwise its first such part becomes a linkage
    part of the same name; the other parts are kept as they are.

    Examples
    --------
    >>> from machdyn.spec import read
    >>> m = read({"machdyn": 1, "fourbar": {"a": {"r1": 8, "r2": 4, "r3": 7, "r4": 6,
    ...           "coupler": {"p": 5, "delta": 30}}}})
    >>> doc, notes = linkage_document(m)
    >>> part = doc["linkage"]["a"]
    >>> sorted(part["links"]), part["report"], part["drive"]
    (['coupler', 'crank', 'rocker'], ['P'], ['crank'])
    >>> print(notes[0])
    Opened [fourbar.a] as a drawn linkage: crank O2–A, coupler A–B–P, rocker O4–B,
    drawn at theta2 = 0 deg.
    """
    parts = machine.parts.values()
    if any(p.kind == "linkage" for p in parts):
        return machine.to_spec(), []
    part = next((p for p in parts if p.kind in CONVERTED), None)
    if part is None:
        return machine.to_spec(), []
    convert = {"fourbar": _fourbar, "slider_crank": _slider_crank}.get(part.kind, _inverted)
    values, notes = convert(part, machine)
    if "notes" in part.values:
        values["notes"] = part.values["notes"]
    from ..spec._machine import Part

    new = {
        n: (Part("linkage", n, values, None) if p is part else p) for n, p in machine.parts.items()
    }
    doc = dataclasses.replace(machine, parts=new).to_spec()
    for key, why in _NOT_KEPT.items():
        if key in part.values:
            notes.append(f"{NOT_KEPT}[{part.kind}.{part.name}.{key}] ({why}).")
    if "form" in part.values or "branch" in part.values:
        notes.append("Its form/branch is the drawn assembly, which the linkage keeps.")
    others = [f"[{p.kind}.{p.name}]" for p in parts if p is not part]
    if others:
        notes.append(f"The file's other parts ({', '.join(others)}) are kept as they are.")
    notes.append("Save writes the design back as a [linkage] part.")
    return doc, notes


# ------------------------------------------------------------------- shared
def _drawn(
    part: Any,
    solve: Any,
    sweep: np.ndarray,
    limits: tuple[float, float] | None,
    skew: Any = None,
) -> tuple[float, Any]:
    """The input to draw at: the sweep's first assembled value clear of a toggle.

    Else the middle of the input's range (a rocker's sweep starts at a toggle).
    ``skew(t, motion)``, if given, is an angle whose sine is small near a pose to pass
    over while another one is clear: a four-bar's transmission angle (a toggle), an
    inverted slider-crank's θ2 − θ4 (the crank along the slot, hidden under the
    slotted link).
    """
    tries = [float(sweep[0])]
    if limits is not None:
        tries.append(0.5 * (limits[0] + limits[1]))
    tries += [float(t) for t in sweep[1:]]
    first = None
    for t in tries:
        m = solve(np.array([t]))  # (an array: a pose that does not close is flagged, not raised)
        clear = skew is None or abs(np.sin(float(np.ravel(skew(t, m))[0]))) > 0.02
        if bool(np.ravel(m.ok)[0]):
            if clear:
                return t, m
            first = first or (t, m)
    if first is not None:
        return first
    raise InputError(
        f"{part.kind}.{part.name}.motion.theta2",
        "the studio cannot draw it: it assembles at no input of this sweep (nor mid-range)",
    )


def _z(value: Any) -> complex:
    return complex(np.ravel(value)[0])


def _motion(part: Any, lk_driver: str, sweep: np.ndarray, theta1: float) -> dict[str, Any]:
    """The crank's absolute angles (theta2 + theta1) and the part's rates."""
    from ..spec._linkage import DriverSetting
    from ..spec._types import Grid

    m = part.values.get("motion", {})
    old = m.get("theta2")
    if old is not None and old.explicit is None:
        grid = Grid(old.start + theta1, old.stop + theta1, old.step)
    else:
        grid = Grid.of(sweep + theta1)
    setting = DriverSetting("angle", grid, m.get("omega2"), m.get("alpha2"), m.get("driven_by"))
    return {lk_driver: setting}


def _mass(table: dict | None, where: str, notes: list[str]) -> dict[str, Any]:
    """A link's mass keys (a four-bar's link frames are the linkage's: first joint, x to next)."""
    if not table:
        return {}
    if not table["mass"]:
        if table.get("inertia"):
            notes.append(f"{NOT_KEPT}{where} inertia (a linkage link needs a mass to have one).")
        return {}
    return {k: table[k] for k in ("mass", "inertia", "cg") if k in table}


def _guide_friction(loads: dict) -> dict[str, Any]:
    """A slider part's Coulomb or viscous friction as the drawn guide's (none if smooth)."""
    friction = loads.get("friction", "smooth")
    if friction == "coulomb" and loads.get("mu"):
        return {"friction": {"guide": {"coulomb": loads["mu"]}}}
    if friction == "viscous" and loads.get("beta"):
        return {"friction": {"guide": {"viscous": loads["beta"]}}}
    return {}


def _loads(v: dict, names: dict[int, str]) -> dict[str, Any]:
    """``torques`` and ``[[forces]]`` of the linkage from the part's ``[loads]``."""
    loads = v.get("loads", {})
    torques: dict[str, float] = {}
    for key, value in loads.get("torques", {}).items():
        name = names[int(key.removeprefix("link"))]
        torques[name] = torques.get(name, 0.0) + value
    if "torque4" in loads:
        torques[names[4]] = torques.get(names[4], 0.0) + loads["torque4"]
    forces = [
        {"link": names[f["link"]], "at": complex(f["at"]), "force": complex(f["force"])}
        for f in loads.get("force", [])
    ]
    out: dict[str, Any] = {}
    if torques:
        out["torques"] = torques
    if forces:
        out["forces"] = forces
    return out


def _opened(part: Any, machine: Any, links: dict[str, dict], theta: float) -> str:
    listed = ", ".join(f"{n} {'–'.join(e['points'])}" for n, e in links.items())
    angle = machine.units.show("angle", theta)
    unit = machine.units.display("angle")
    return (
        f"Opened [{part.kind}.{part.name}] as a drawn linkage: {listed}, "
        f"drawn at theta2 = {float(angle):.6g} {unit}."
    )


# ------------------------------------------------------------------- four-bar
def _fourbar(part: Any, machine: Any) -> tuple[dict[str, Any], list[str]]:
    from ..spec._fourbar import input_angles, placement

    fb, v = part.model, part.values
    form, branch = v.get("form", 1), v.get("branch")
    o2, theta1 = placement(v) or (0j, 0.0)
    turn = complex(np.exp(1j * theta1))
    rng = fb.input_range(form)
    limits = None if rng.full_turn else (rng.lo, rng.hi)
    sweep = input_angles(part)
    solve = lambda t: fb.solve(t, 1.0, 0.0, form, branch=branch)  # noqa: E731
    t0, m = _drawn(part, solve, sweep, limits, skew=lambda t, m: m.mu)
    local = {"O2": 0j, "O4": complex(fb.r1), "A": _z(m.A), "B": _z(m.B)}
    if fb.coupler is not None:
        local["P"] = _z(m.coupler)
    cranks = fb.classification.cranks
    names = {
        2: "crank" if 2 in cranks else "input",
        3: "coupler",
        4: "output" if 4 in cranks else "rocker",
    }
    links = {
        names[2]: {"points": ["O2", "A"]},
        names[3]: {"points": ["A", "B", *(["P"] if "P" in local else [])]},
        names[4]: {"points": ["O4", "B"]},
    }
    notes: list[str] = []
    for k, name in names.items():
        links[name] |= _mass(v.get(f"link{k}"), f"[{part.kind}.{part.name}.link{k}]", notes)
    values: dict[str, Any] = {
        "points": {k: o2 + turn * z for k, z in local.items()},
        "ground": ["O2", "O4"],
        "drive": [names[2]],
        **({"report": ["P"]} if "P" in local else {}),
        "links": links,
        "motion": _motion(part, names[2], sweep, theta1),
        **_loads(v, names),
    }
    notes.insert(0, _opened(part, machine, links, t0))
    if "O2" in v or "theta1" in v:
        notes.insert(1, "Its placement (O2, theta1) is the drawing's: theta2 is the crank's angle "
                        "from the plane's +x minus theta1.")  # fmt: skip
    return values, notes


# ------------------------------------------------------------------- slider-crank
def _slider_crank(part: Any, machine: Any) -> tuple[dict[str, Any], list[str]]:
    from ..spec._fourbar import input_angles

    sc, v = part.model, part.values
    form = v.get("form", 1)
    limits = sc.input_range()
    sweep = input_angles(part)
    t0, m = _drawn(part, lambda t: sc.solve(t, 1.0, 0.0, form), sweep, limits)
    points = {"O2": 0j, "A": _z(m.A), "B": _z(m.B)}
    if sc.point is not None:
        points["P"] = _z(m.coupler)
    crank = "crank" if sc.crank_rotates else "input"
    names = {2: crank, 3: "coupler", 4: "slider"}
    links = {
        crank: {"points": ["O2", "A"]},
        "coupler": {"points": ["A", "B", *(["P"] if "P" in points else [])]},
        "slider": {"points": ["B"]},
    }
    notes: list[str] = []
    for k in (2, 3):
        links[names[k]] |= _mass(v.get(f"link{k}"), f"[{part.kind}.{part.name}.link{k}]", notes)
    block = v.get("link4")
    if block:
        links["slider"] |= _mass({"mass": block["mass"]}, "", notes)
        extra = [k for k in ("inertia", "cg") if block.get(k)]
        if extra:
            notes.append(
                f"{NOT_KEPT}[{part.kind}.{part.name}.link4] {' and '.join(extra)} (the slider "
                f"does not turn; machdyn run does not use {'it' if len(extra) == 1 else 'them'} "
                "either)."
            )
    loads = v.get("loads", {})
    values: dict[str, Any] = {
        "points": points,
        "ground": ["O2"],
        "drive": [crank],
        **({"report": ["P"]} if "P" in points else {}),
        "links": links,
        "sliders": {"guide": {"block": "slider", "on": "ground", "at": "B", "direction": 0.0}},
        "motion": _motion(part, crank, sweep, 0.0),
        **_loads(v, names),
    }
    if loads.get("force4"):
        values.setdefault("forces", []).append(
            {"link": "slider", "at": "B", "force": complex(loads["force4"])}
        )
    values |= _guide_friction(loads)
    notes.insert(0, _opened(part, machine, links, t0))
    return values, notes


# ------------------------------------------------------------------- inverted slider-crank
def _inverted(part: Any, machine: Any) -> tuple[dict[str, Any], list[str]]:
    """Norton's inversion #3: a block on the crank pin A slides in the slotted link O4.

    The slot is the line y = c of link 4's frame (origin O4, x along the slot): A − O4 =
    (b + jc)·e^{jθ4}. The slotted link carries O4 and a point S on its x axis; the block
    slides along it at A.
    """
    from ..spec._fourbar import input_angles

    isc, v = part.model, part.values
    form = v.get("form", 1)
    sweep = input_angles(part)
    t0, m = _drawn(
        part, lambda t: isc.solve(t, 1.0, 0.0, form), sweep, None, skew=lambda t, m: t - m.theta4
    )
    theta4 = float(np.ravel(m.theta4)[0])
    O4 = complex(isc.d)
    points = {"O2": 0j, "O4": O4, "A": _z(m.A), "S": O4 + (isc.a + isc.d) * np.exp(1j * theta4)}
    crank = "crank"
    full = isc.d + abs(isc.c) < isc.a  # the slotted link turns fully when O4 is inside the circle
    names = {2: crank, 3: "slider", 4: "output" if full else "rocker"}
    links = {
        crank: {"points": ["O2", "A"]},
        names[4]: {"points": ["O4", "S"]},
        "slider": {"points": ["A"]},
    }
    notes: list[str] = []
    for k in (2, 4):
        links[names[k]] |= _mass(v.get(f"link{k}"), f"[{part.kind}.{part.name}.link{k}]", notes)
    # the block is a one-point link: its frame is the plane's axes at the drawing, turning
    # with it; the part's block frame has x along the slot, so its vectors turn by θ4 there
    turn = complex(np.exp(1j * theta4))
    block = dict(v.get("link3") or {})
    if "cg" in block:
        block["cg"] = complex(block["cg"]) * turn
    links["slider"] |= _mass(block, f"[{part.kind}.{part.name}.link3]", notes)
    loads = v.get("loads", {})
    forces = [
        {**f, "at": complex(f["at"]) * turn} if f["link"] == 3 else f
        for f in loads.get("force", [])
    ]
    values: dict[str, Any] = {
        "points": points,
        "ground": ["O2", "O4"],
        "drive": [crank],
        "links": links,
        "sliders": {"guide": {"block": "slider", "on": names[4], "at": "A", "direction": theta4}},
        "motion": _motion(part, crank, sweep, 0.0),
        **_loads({"loads": loads | {"force": forces}}, names),
    }
    values |= _guide_friction(loads)
    notes.insert(0, _opened(part, machine, links, t0))
    return values, notes
