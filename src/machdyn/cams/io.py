"""Export a cam profile: CSV table and DXF outline (ezdxf, imported lazily)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from ..errors import InputError, ModelError
from .geometry import CamProfile, format_ranges

__all__ = ["write_csv", "write_dxf"]

# How to cure an undercut, per follower (Norton §8.7), and the sizing function that does it.
_UNDERCUT_CURE = {
    "translating roller": ("enlarge the prime circle or use a smaller roller", "size_roller"),
    "oscillating roller": (
        "enlarge the prime circle or use a smaller roller",
        "size_oscillating_roller",
    ),
    "translating flat-faced": ("enlarge the base circle", "size_flat_face"),
}


def undercut_refusal(
    profile: CamProfile, override: str = "pass allow_undercut=True", see: str | None = None
) -> str:
    """Why an undercut cam's outline is refused, the cure for its follower, and ``override``.

    ``see`` points to the sizing tool (default: the ``machdyn.cams`` sizing
    function for the follower). The CLI passes its own wording
    (``"pass --allow-undercut"``, ``"--size"``).

    Examples
    --------
    >>> from machdyn.cams import CamProgram, TranslatingFlatFace
    >>> steep = CamProgram.double_dwell(1.0, np.pi / 6, np.pi / 6)
    >>> cam = TranslatingFlatFace(0.5).profile(steep, n=360)
    >>> "enlarge the base circle (see machdyn.cams.size_flat_face)" in undercut_refusal(cam)
    True
    """
    if not cannot_be_cut(profile):
        raise ValueError("undercut_refusal: this cam passes both undercut tests")
    where = []
    if profile.is_undercut:
        where.append(f"undercut at θ = {format_ranges(profile.undercut_ranges())}")
    if profile.has_surface_loop:
        loops = format_ranges(profile.surface_loop_ranges())
        where.append(f"its outline crosses itself, cutting away θ = {loops}")
    cure, function = _UNDERCUT_CURE.get(profile.follower, ("enlarge the cam", "size_roller"))
    see = f"machdyn.cams.{function}" if see is None else see
    return (
        f"the cam is {'; '.join(where)}; the follower would not follow the law there. "
        f"To make it, {cure} (see {see}), or {override} to write it anyway"
    )


def cannot_be_cut(profile: CamProfile) -> bool:
    """Whether the cam's outline loses material its follower needs: undercut, by either test.

    The local test (:attr:`CamProfile.undercut`, radius of curvature) or the global
    one (:attr:`CamProfile.surface_loop`, the sampled outline crossing itself).
    """
    return profile.is_undercut or profile.has_surface_loop


def write_csv(profile: CamProfile, path: Any) -> Path:
    """Write θ (deg), s, v, a, j, pitch and surface x/y, φ (deg), ρ and undercut as CSV.

    Lengths are in the units of the program and radii; ``v, a, j`` are per
    radian of cam angle. Empty cells mean "not defined" (no pitch curve for a
    flat face); ``rho`` of ±inf marks an inflection.

    Examples
    --------
    >>> import tempfile, os
    >>> from machdyn.cams import CamProgram, TranslatingRoller
    >>> cam = TranslatingRoller(3.0, 0.5).profile(
    ...     CamProgram.double_dwell(1.0, np.pi / 3, np.pi / 3), n=36)
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     out = write_csv(cam, os.path.join(tmp, "cam.csv"))
    ...     print(out.read_text().splitlines()[0][:29])
    theta_deg,s,v,a,j,pitch_x,pit
    """
    path = Path(path)
    columns = profile._columns()
    names = list(columns)
    lines = [",".join(names)]
    table = [columns[k] for k in names]
    for row in zip(*table, strict=True):
        cells = []
        for value in row:
            if isinstance(value, np.bool_ | bool):
                cells.append("1" if value else "0")
            elif np.isnan(value):
                cells.append("")
            else:
                cells.append(repr(float(value)))
        lines.append(",".join(cells))
    try:
        path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    except OSError as exc:
        raise InputError("path", f"cannot write {path}: {exc.strerror}") from None
    return path


def write_dxf(
    profile: CamProfile, path: Any, allow_undercut: bool = False, unit: str | None = None
) -> Path:
    """Write the cam outline (closed polyline) with its base/prime circles and pitch curve.

    Layers: ``CAM`` (surface), ``PITCH`` (pitch curve, roller followers),
    ``BASE_CIRCLE``, ``PRIME_CIRCLE``. An undercut cam's outline intersects
    itself and cannot be made: it is refused unless ``allow_undercut`` is true.
    ``unit`` is the length unit of the cam's numbers (``"mm"``, ``"in"``): the
    file's ``$INSUNITS`` says so (without it, 0: unitless).
    """
    if cannot_be_cut(profile) and not allow_undercut:
        raise ModelError(undercut_refusal(profile))
    try:
        import ezdxf
    except ImportError:  # pragma: no cover - depends on the environment
        raise ModelError("DXF output needs ezdxf: pip install 'machdyn[dxf]'") from None
    from ..units import set_dxf_units

    path = Path(path)
    doc = ezdxf.new("R2010")
    set_dxf_units(doc, unit)
    msp = doc.modelspace()
    for name, color in (("CAM", 7), ("PITCH", 3), ("BASE_CIRCLE", 5), ("PRIME_CIRCLE", 4)):
        doc.layers.add(name, color=color)
    outline = profile.surface
    msp.add_lwpolyline(
        np.column_stack((outline.real, outline.imag)).tolist(),
        close=True,
        dxfattribs={"layer": "CAM"},
    )
    if profile.pitch is not None:
        msp.add_lwpolyline(
            np.column_stack((profile.pitch.real, profile.pitch.imag)).tolist(),
            close=True,
            dxfattribs={"layer": "PITCH"},
        )
        msp.add_circle((0.0, 0.0), profile.prime_radius, dxfattribs={"layer": "PRIME_CIRCLE"})
    msp.add_circle((0.0, 0.0), profile.base_radius, dxfattribs={"layer": "BASE_CIRCLE"})
    try:
        doc.saveas(path)
    except OSError as exc:
        raise InputError("path", f"cannot write {path}: {exc.strerror}") from None
    return path
