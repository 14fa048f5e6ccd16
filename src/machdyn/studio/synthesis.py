"""Synthesis from the page: three-position motion generation and path generation.

Both call :mod:`machdyn.synthesis` and turn each result into a linkage
document the page can open (the pivots and joints the synthesis placed, in
position 1 or at the first target), with the result's own checks (circuit,
branch and order defects, transmission angle, distance to the targets).
"""

from __future__ import annotations

import math
import os
import tempfile
import threading
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError

__all__ = ["motion", "path"]

#: Entries of the small atlas built for a session when no atlas is installed.
SMALL_ATLAS = 8192

_atlas_lock = threading.Lock()
_small: dict[str, Any] = {}


def _points(body: dict, key: str, count: int | None = None) -> list[complex]:
    value = body.get(key)
    if not isinstance(value, list) or not all(
        isinstance(p, list) and len(p) == 2 and all(_real(v) for v in p) for p in value
    ):
        raise InputError(key, "must be a list of [x, y] pairs of finite numbers")
    if count is not None and len(value) != count:
        raise InputError(key, f"needs {count} points, got {len(value)}")
    return [complex(float(x), float(y)) for x, y in value]


def _real(v: Any) -> bool:
    return isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v)


def _point(body: dict, key: str) -> complex | None:
    if body.get(key) is None:
        return None
    return _points({key: [body[key]]}, key, 1)[0]


def _xy(z: complex) -> list[float]:
    return [float(z.real), float(z.imag)]


def _units(body: dict) -> dict[str, str]:
    units = body.get("units")
    if units is None:
        return {}
    if not isinstance(units, dict) or not all(isinstance(v, str) for v in units.values()):
        raise InputError("units", "must be a [units] table of unit names")
    return units


def _doc(title: str, name: str, pts: dict[str, complex], coupler: list[str], units: dict) -> dict:
    doc: dict[str, Any] = {"machdyn": 1, "title": title}
    if units:
        doc["units"] = units
    doc["linkage"] = {
        name: {
            "points": {k: _xy(v) for k, v in pts.items()},
            "ground": ["O2", "O4"],
            "drive": ["crank"],
            "report": [p for p in coupler if p not in ("A", "B")][:1] or ["A"],
            "links": {
                "crank": {"points": ["O2", "A"]},
                "coupler": {"points": coupler},
                "rocker": {"points": ["O4", "B"]},
            },
        }
    }
    return doc


def motion(body: dict) -> dict[str, Any]:
    """Three-position motion generation from the page's picked points.

    ``c``, ``d`` (3 positions each), then either ``A``, ``B`` (moving pivots on the
    coupler, position 1) or ``O2``, ``O4`` (fixed pivots).
    """
    from ..synthesis import three_position, three_position_fixed_pivots

    c, d = _points(body, "c", 3), _points(body, "d", 3)
    A, B = _point(body, "A"), _point(body, "B")
    O2, O4 = _point(body, "O2"), _point(body, "O4")
    if O2 is not None or O4 is not None:
        if O2 is None or O4 is None:
            raise InputError("O2" if O2 is None else "O4", "give both fixed pivots, or neither")
        s = three_position_fixed_pivots(c, d, O2, O4)
    else:
        s = three_position(c, d, A=A, B=B)
    A1, B1 = complex(s.A[0]), complex(s.B[0])
    pts = {"O2": complex(s.O2), "O4": complex(s.O4), "A": A1, "B": B1}
    coupler = ["A", "B"]
    scale = max(abs(c[0] - d[0]), 1e-12)
    for name, z in (("C", c[0]), ("D", d[0])):
        if min(abs(z - A1), abs(z - B1)) > 1e-9 * scale:
            pts[name] = z
            coupler.append(name)
    doc = _doc("Three-position synthesis", "motion", pts, coupler, _units(body))
    return {
        "doc": doc,
        "O2": _xy(s.O2),
        "O4": _xy(s.O4),
        "A": [_xy(z) for z in s.A],
        "B": [_xy(z) for z in s.B],
        "lengths": [float(s.r1), float(s.r2), float(s.r3), float(s.r4)],
        "theta2_deg": [float(v) for v in np.degrees(s.theta2)],
        "direction": int(s.direction),
        "mu_min_deg": None if not np.isfinite(s.mu_min) else float(np.degrees(s.mu_min)),
        "class": s.fourbar.barker_class,
        "defects": list(s.defects),
    }


def _atlas() -> tuple[Any, str]:
    """The installed atlas, or a small one built once for this session (with a note)."""
    from ..synthesis import build_atlas, open_atlas

    folder = Path(os.environ.get("MACHDYN_ATLAS") or "~/.cache/machdyn/fourbar.atlas").expanduser()
    if (folder / "manifest.json").is_file():
        try:
            return open_atlas(folder), f"atlas {folder}"
        except Exception:  # a stale or broken atlas: fall back, and say so
            pass
    with _atlas_lock:
        if "atlas" not in _small:
            tmp = tempfile.mkdtemp(prefix="machdyn-studio-atlas-")
            build_atlas(
                Path(tmp) / "small.atlas", SMALL_ATLAS, chunk_size=SMALL_ATLAS, progress=False
            )
            _small["atlas"] = open_atlas(Path(tmp) / "small.atlas")
    return _small["atlas"], (
        f"a small atlas of {SMALL_ATLAS:,} coupler curves built for this session; "
        "'machdyn atlas build' makes the full one (better matches)"
    )


def path(body: dict) -> dict[str, Any]:
    """Path generation from target points (``targets``, ``closed``, ``n``) via the atlas."""
    from ..synthesis import path_from_atlas

    targets = _points(body, "targets")
    closed = body.get("closed", True)
    if not isinstance(closed, bool):
        raise InputError("closed", "must be true or false")
    n = body.get("n", 5)
    if not isinstance(n, int) or isinstance(n, bool) or not 1 <= n <= 10:
        raise InputError("n", "must be a whole number from 1 to 10")
    atlas, source = _atlas()
    res = path_from_atlas(np.array(targets), atlas, closed=closed, n=n)
    units = _units(body)
    out = []
    for i, cand in enumerate((*res.candidates, *res.rejected[: max(0, n - len(res.candidates))])):
        pl = cand.linkage
        theta = float(np.ravel(cand.theta2)[0])
        A, B, P, _ = pl.pose(theta)
        pts = {
            "O2": complex(pl.O2),
            "O4": complex(pl.O4),
            "A": complex(A),
            "B": complex(B),
            "P": complex(P),
        }
        curve = np.ravel(cand.curve(240))
        out.append(
            {
                "rank": i + 1,
                "doc": _doc(
                    f"Path synthesis candidate {i + 1}", "path", pts, ["A", "B", "P"], units
                ),
                "max_distance": float(np.max(cand.distance)),
                "class": cand.barker_class,
                "crank": bool(cand.is_crank),
                "mu_min_deg": float(np.degrees(cand.mu_min)),
                "defects": list(cand.defects),
                "curve": [_xy(z) if np.isfinite(z) else None for z in curve],
            }
        )
    return {"candidates": out, "near": bool(res.near), "note": res.note, "source": source}
