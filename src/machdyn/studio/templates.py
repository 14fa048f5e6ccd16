"""The studio's starting mechanisms, as machine documents (``docs/spec.md``).

Each template is a ``[linkage.NAME]`` part drawn in one assembled pose: its
moving pins are placed by the library's own dyad solvers
(:func:`machdyn.linkage.dyads.rrr`, :func:`~machdyn.linkage.dyads.rrp`), so
every drawing closes to machine precision. Lengths in millimetres (Jansen's
leg in centimetres, his numbers), masses in kilograms, the crank turning at
10 rad/s, gravity on.
"""

from __future__ import annotations

import cmath
import math
from typing import Any

__all__ = ["TEMPLATES", "template"]

#: Template names, in the order the page lists them, with a one-line description.
TEMPLATES: dict[str, str] = {
    "four-bar": "crank-rocker 80-40-70-60 with a coupler point (the notes' HW 6, in cm)",
    "slider-crank": "offset slider-crank: crank 20, rod 60, offset 5",
    "watt": "Watt II six-bar: a crank-rocker whose ternary rocker drives a second rocker",
    "stephenson": "Stephenson III six-bar: the coupler point drives a dyad to a third pivot",
    "jansen": "Theo Jansen's leg (his 'holy numbers', cm)",
    "quick-return": "crank-shaper quick return: slotted arm on the crank pin, rod to the ram",
}


def _rrr(A: complex, C: complex, a: float, b: float, sign: int = 1) -> complex:
    from ..linkage.dyads import rrr

    return complex(rrr(A, C, a, b, sign).B)


def _rrp(A: complex, a: float, G: complex, u: complex, sign: int = 1) -> complex:
    from ..linkage.dyads import rrp

    return complex(rrp(A, a, G, u, sign).B)


def _xy(z: complex) -> list[float]:
    return [round(z.real, 12) + 0.0, round(z.imag, 12) + 0.0]


def _bar(points: list[str], mass: float, length: float) -> dict[str, Any]:
    """A slender link: its mass, I_G = m L²/12 and the centre of mass half-way along x."""
    return {
        "points": points,
        "mass": mass,
        "inertia": round(mass * length**2 / 12.0, 6),
        "cg": round(length / 2.0, 6),
    }


def _doc(name: str, title: str, part: dict[str, Any], length: str = "mm") -> dict[str, Any]:
    return {
        "machdyn": 1,
        "title": title,
        "gravity": True,
        "units": {"length": length, "mass": "kg", "force": "N", "torque": "N*m"},
        "linkage": {name: part},
    }


def _fourbar() -> dict[str, Any]:
    O2, O4 = 0j, 80 + 0j
    A = 40 * cmath.exp(1j * math.radians(60))
    B = _rrr(A, O4, 70, 60)
    P = A + 50 * cmath.exp(1j * (cmath.phase(B - A) + math.radians(30)))
    part = {
        "points": {"O2": _xy(O2), "O4": _xy(O4), "A": _xy(A), "B": _xy(B), "P": _xy(P)},
        "ground": ["O2", "O4"],
        "drive": ["crank"],
        "report": ["P"],
        "links": {
            "crank": _bar(["O2", "A"], 0.2, 40),
            "coupler": {**_bar(["A", "B", "P"], 0.5, 70), "cg": "P"},
            "rocker": _bar(["O4", "B"], 0.3, 60),
        },
        "motion": {"crank": {"velocity": "10 rad/s"}},
    }
    return _doc("fourbar", "Four-bar crank-rocker", part)


def _slider_crank() -> dict[str, Any]:
    A = 20 * cmath.exp(1j * math.radians(45))
    B = _rrp(A, 60, 5j, 1 + 0j)
    part = {
        "points": {"O2": [0.0, 0.0], "A": _xy(A), "B": _xy(B)},
        "ground": ["O2"],
        "drive": ["crank"],
        "links": {
            "crank": _bar(["O2", "A"], 0.2, 20),
            "rod": _bar(["A", "B"], 0.4, 60),
            "piston": {"points": ["B"], "mass": 0.5},
        },
        "sliders": {"cylinder": {"block": "piston", "on": "ground", "at": "B", "direction": 0}},
        "motion": {"crank": {"velocity": "10 rad/s"}},
    }
    return _doc("slider_crank", "Offset slider-crank", part)


def _watt() -> dict[str, Any]:
    O4, O6 = 80 + 0j, 120 + 60j
    A = 20 * cmath.exp(1j * math.pi / 6)
    B = _rrr(A, O4, 70, 60)
    C = O4 + 40 * (B - O4) / abs(B - O4) * cmath.exp(-1j * math.radians(35))
    D = _rrr(C, O6, 60, 50, -1)
    part = {
        "points": {
            "O2": [0.0, 0.0],
            "O4": _xy(O4),
            "O6": _xy(O6),
            "A": _xy(A),
            "B": _xy(B),
            "C": _xy(C),
            "D": _xy(D),
        },
        "ground": ["O2", "O4", "O6"],
        "drive": ["crank"],
        "report": ["D"],
        "links": {
            "crank": _bar(["O2", "A"], 0.2, 20),
            "coupler": _bar(["A", "B"], 0.4, 70),
            "rocker": {**_bar(["O4", "B", "C"], 0.6, 60), "cg": 25.0},
            "link5": _bar(["C", "D"], 0.3, 60),
            "output": _bar(["O6", "D"], 0.3, 50),
        },
        "torques": {"output": "-0.5 N*m"},
        "motion": {"crank": {"velocity": "10 rad/s"}},
    }
    return _doc("watt", "Watt II six-bar", part)


def _stephenson() -> dict[str, Any]:
    O4, O6 = 80 + 0j, 40 - 60j
    A = 20 * cmath.exp(1j * math.pi / 6)
    B = _rrr(A, O4, 70, 60)
    P = A + (B - A) / 70 * (30 - 20j)
    D = _rrr(P, O6, 75, 60, -1)
    part = {
        "points": {
            "O2": [0.0, 0.0],
            "O4": _xy(O4),
            "O6": _xy(O6),
            "A": _xy(A),
            "B": _xy(B),
            "P": _xy(P),
            "D": _xy(D),
        },
        "ground": ["O2", "O4", "O6"],
        "drive": ["crank"],
        "report": ["P"],
        "links": {
            "crank": _bar(["O2", "A"], 0.2, 20),
            "coupler": _bar(["A", "B", "P"], 0.5, 70),
            "rocker": _bar(["O4", "B"], 0.3, 60),
            "link5": _bar(["P", "D"], 0.3, 75),
            "output": _bar(["O6", "D"], 0.3, 60),
        },
        "motion": {"crank": {"velocity": "10 rad/s"}},
    }
    return _doc("stephenson", "Stephenson III six-bar", part)


def _jansen() -> dict[str, Any]:
    Y = -38.0 - 7.8j
    X = 15.0 + 0j
    B = _rrr(X, Y, 50.0, 41.5, -1)
    C = _rrr(X, Y, 61.9, 39.3, 1)
    D = _rrr(B, Y, 55.8, 40.1, -1)
    E = _rrr(D, C, 39.4, 36.7, -1)
    F = _rrr(E, C, 65.7, 49.0, -1)
    names = {"O": 0j, "Y": Y, "X": X, "B": B, "C": C, "D": D, "E": E, "F": F}
    part = {
        "points": {k: _xy(v) for k, v in names.items()},
        "ground": ["O", "Y"],
        "drive": ["crank"],
        "report": ["F"],
        "links": {
            "crank": {"points": ["O", "X"]},
            "j": {"points": ["X", "B"]},
            "upper": {"points": ["Y", "B", "D"]},
            "k": {"points": ["X", "C"]},
            "c": {"points": ["Y", "C"]},
            "f": {"points": ["D", "E"]},
            "leg": {"points": ["C", "E", "F"]},
        },
        "motion": {"crank": {"velocity": "1 rad/s"}},
    }
    doc = _doc("jansen", "Jansen's leg", part, length="cm")
    doc.pop("gravity")
    return doc


def _quick_return() -> dict[str, Any]:
    O4 = -80j
    A = 30 * cmath.exp(1j * math.radians(30))
    B = O4 + 150 * (A - O4) / abs(A - O4)
    C = _rrp(B, 60, 75j, 1 + 0j)
    part = {
        "points": {"O2": [0.0, 0.0], "O4": _xy(O4), "A": _xy(A), "B": _xy(B), "C": _xy(C)},
        "ground": ["O2", "O4"],
        "drive": ["crank"],
        "report": ["C"],
        "links": {
            "crank": _bar(["O2", "A"], 0.2, 30),
            "block": {"points": ["A"], "mass": 0.1},
            "arm": _bar(["O4", "B"], 0.8, 150),
            "rod": _bar(["B", "C"], 0.3, 60),
            "ram": {"points": ["C"], "mass": 2.0},
        },
        "sliders": {
            "slot": {"block": "block", "on": "arm", "at": "A", "direction": "B", "through": "O4"},
            "ram_guide": {"block": "ram", "on": "ground", "at": "C", "direction": 0},
        },
        "forces": [{"link": "ram", "at": "C", "force": ["-20 N", "0 N"]}],
        "motion": {"crank": {"velocity": "10 rad/s"}},
    }
    return _doc("quick_return", "Crank-shaper quick return", part)


_BUILD = {
    "four-bar": _fourbar,
    "slider-crank": _slider_crank,
    "watt": _watt,
    "stephenson": _stephenson,
    "jansen": _jansen,
    "quick-return": _quick_return,
}


def template(name: str) -> dict[str, Any]:
    """The machine document of template ``name`` (one of :data:`TEMPLATES`).

    Examples
    --------
    >>> import machdyn
    >>> lk = machdyn.from_spec(template("watt"))
    >>> lk.mobility(), [g.kind for g in lk.groups]
    (1, ['driver', 'RRR', 'RRR'])
    """
    from ..errors import InputError

    if not isinstance(name, str) or name not in _BUILD:
        raise InputError("template", f"must be one of {', '.join(TEMPLATES)}, got {name!r}")
    return _BUILD[name]()
