"""A design report of a machine: one self-contained HTML page (and a PDF where Chromium is).

``report(model, path)`` — or ``model.report(path)`` — writes everything the
library can say about the model: the model and its (animated) drawing,
mobility and class, circuits and toggles, the input range, φ and μ extremes,
mechanical advantage, kinematics plots, peak pin forces and input torque and
where they occur, shaking force and moment, flywheel, balancing — and a
self-check section with independent checks on this very machine. Every
number comes from the public API; the page loads nothing from the network.

Examples
--------
>>> from machdyn import FourBar
>>> page = report(FourBar(8, 4, 7, 6), n=72)
>>> page.startswith("<!DOCTYPE html>"), "GCRR" in page
(True, True)
"""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path
from typing import Any

from ..errors import InputError

__all__ = ["report", "to_pdf"]


def report(model: Any, path: str | Path | None = None, **options: Any) -> str:
    """The design report of ``model`` as an HTML page (also written to ``path``).

    Parameters
    ----------
    model : model or Machine
        A FourBar, SliderCrank, InvertedSliderCrank, Linkage, CamProfile,
        GearPair, GearTrain, PlanetaryTrain, Rotor or RotorBalance; a
        :class:`machdyn.spec.Machine` (``machdyn.spec.load_machine(path)``)
        gives one page with every part (see :mod:`machdyn.report.machine`).
    path : str or Path, optional
        Where to write the page (``.html``); ``.pdf`` prints it with Chromium.
    **options
        FourBar: ``form``, ``omega2``, ``n``, ``mass``, ``inertia``, ``cg``,
        ``gravity``, ``load_torque4``, ``k`` (flywheel), ``mu_limit_deg``.
        SliderCrank: ``form``, ``omega2``, ``n``, ``mass`` (m2, m3, m4), ``inertia``
        (IG2, IG3), ``cg`` (c2, c3), ``gravity``, ``load_force4``, ``k``.
        InvertedSliderCrank: ``form``, ``omega2``, ``n``, ``mass`` (m2, m3, m4),
        ``inertia`` (IG2, IG3, IG4), ``cg`` (c2, c3, c4), ``gravity``,
        ``load_torque4``, ``friction``, ``mu``, ``beta``, ``k``.
        Machine: ``n``, ``k``, ``speed`` (every mechanism's input speed).
        Linkage: ``values`` (driver sweep), ``velocity``, ``n``, ``gravity``, ``k``.
        GearPair: ``input_speed`` (the driver's), ``torque`` (the driver's: tooth loads).
        GearTrain: ``input_speed``, ``torque`` (the input shaft's).
        PlanetaryTrain: ``speeds`` (two members' speeds), ``torque`` (``{member: T}``).
        Rotor / RotorBalance: ``speed``, ``bearings`` (z_A, z_B); a Rotor also
        ``planes`` (z of the correction planes).

    Returns
    -------
    str
        The page.
    """
    from ..cams import CamProfile
    from ..fourbar import FourBar
    from ..gears import GearPair, GearTrain, PlanetaryTrain
    from ..linkage import Linkage
    from ..slidercrank import InvertedSliderCrank, SliderCrank
    from ..spec import Machine

    if isinstance(model, Machine):
        from .machine import machine_report

        page = machine_report(model, **options).html()
    elif isinstance(model, SliderCrank):
        from .slidercrank import slidercrank_report

        page = slidercrank_report(model, **options).html()
    elif isinstance(model, InvertedSliderCrank):
        from .slidercrank import inverted_report

        page = inverted_report(model, **options).html()
    elif isinstance(model, CamProfile):
        from .elements import cam_report

        page = cam_report(model, **options).html()
    elif isinstance(model, GearPair | GearTrain | PlanetaryTrain):
        from .gears import gear_report, planetary_report, train_report

        make = {GearPair: gear_report, GearTrain: train_report, PlanetaryTrain: planetary_report}
        page = make[type(model)](model, **options).html()
    elif _is_rotor(model):
        from .rotor import rotor_report

        page = rotor_report(model, **options).html()
    elif isinstance(model, FourBar):
        from .fourbar import fourbar_report

        page = fourbar_report(model, **options).html()
    elif isinstance(model, Linkage):
        from .linkage import linkage_report

        page = linkage_report(model, **options).html()
    else:
        raise InputError(
            "model",
            f"no report for a {type(model).__name__}; give a FourBar, SliderCrank, "
            "InvertedSliderCrank, Linkage, cam profile, gear pair, gear train, planetary "
            "train, Rotor or RotorBalance",
        )
    if path is not None:
        path = Path(path)
        if path.suffix.lower() == ".pdf":
            html_path = path.with_suffix(".html")
            html_path.write_text(page, encoding="utf-8")
            to_pdf(html_path, path)
        else:
            path.write_text(page, encoding="utf-8")
    return page


def _is_rotor(model: Any) -> bool:
    from ..rotor import Rotor
    from ..spec import RotorBalance

    return isinstance(model, Rotor | RotorBalance)


def to_pdf(html_path: str | Path, pdf_path: str | Path) -> Path:
    """Print an HTML report to PDF with headless Chromium (``chromium --print-to-pdf``).

    Raises
    ------
    InputError
        If no ``chromium`` is on the PATH (then open the page in any browser
        and print it, or run ``chromium --headless --print-to-pdf=out.pdf report.html``).
    """
    exe = (
        shutil.which("chromium")
        or shutil.which("chromium-browser")
        or shutil.which("google-chrome")
    )
    if exe is None:
        raise InputError(
            "path",
            "PDF needs chromium on the PATH; write .html and print it from a "
            "browser, or: chromium --headless --print-to-pdf=out.pdf report.html",
        )
    html_path, pdf_path = Path(html_path).resolve(), Path(pdf_path).resolve()
    subprocess.run(
        [
            exe,
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--no-pdf-header-footer",
            f"--print-to-pdf={pdf_path}",
            html_path.as_uri(),
        ],
        check=True,
        capture_output=True,
        timeout=120,
    )
    return pdf_path
