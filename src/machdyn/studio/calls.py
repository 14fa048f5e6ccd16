"""The studio's API calls: each takes the request's JSON object and returns JSON (or a file).

Arguments are checked here (a missing or wrong field is an
:class:`~machdyn.errors.InputError` naming it, shown in the page); the work is
a call of :mod:`machdyn.studio.analysis`, :mod:`~machdyn.studio.document`,
:mod:`~machdyn.studio.exports` or :mod:`~machdyn.studio.synthesis`, which use
only the library's public API.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from ..errors import InputError, MachdynError

if TYPE_CHECKING:
    from .server import Studio

__all__ = ["calls"]


def _field(body: dict, name: str, kind: type | tuple[type, ...], default: Any = ...) -> Any:
    if name not in body:
        if default is ...:
            raise InputError(name, "missing from the request")
        return default
    value = body[name]
    if value is None and default is not ...:
        return default
    if not isinstance(value, kind) or (isinstance(value, bool) and kind is not bool):
        raise InputError(name, f"has the wrong type ({type(value).__name__})")
    return value


def calls(studio: Studio) -> dict[str, tuple[Callable[[dict], Any], bool]]:
    """The API of ``studio``: call name → (function of the request body, runs in the slow pool)."""
    from . import document, exports, synthesis
    from .analysis import analyse
    from .templates import TEMPLATES, template

    def session(body: dict) -> dict:
        return document.session(studio.file, TEMPLATES)

    def make_template(body: dict) -> dict:
        return {"doc": document.normalise(template(_field(body, "name", str)))}

    def run_analysis(body: dict) -> dict:
        quantities = _field(body, "quantities", list, None)
        if quantities is not None and not all(isinstance(q, str) for q in quantities):
            raise InputError("quantities", "must be a list of column names")
        options = dict(
            part=_field(body, "part", str, None),
            samples=_field(body, "samples", int, 360),
            quantities=quantities,
            centres=_field(body, "centres", bool, False),
        )
        doc = _field(body, "doc", dict)
        try:
            return analyse(doc, **options)
        except MachdynError as exc:
            # a design the library refuses is an answer (a sketch in progress), not a failed
            # request: the page shows the reason and the key, and draws the document as given
            from .server import _key_of

            return {"refused": str(exc), "kind": type(exc).__name__, **_key_of(exc)}

    def open_text(body: dict) -> dict:
        doc, notes = document.read_text(_field(body, "text", str), _field(body, "name", str))
        return {"doc": doc, "notes": notes}

    def save(body: dict) -> dict:
        return document.save(studio.file, _field(body, "doc", dict))

    def edit(body: dict) -> dict:
        return {"doc": document.edit(_field(body, "doc", dict), _field(body, "op", dict))}

    def export(body: dict) -> Any:
        return exports.export(
            _field(body, "doc", dict),
            _field(body, "format", str),
            part=_field(body, "part", str, None),
            frame=_field(body, "frame", int, None),
        )

    def synth_motion(body: dict) -> dict:
        return synthesis.motion(body)

    def synth_path(body: dict) -> dict:
        return synthesis.path(body)

    return {
        "session": (session, False),
        "template": (make_template, False),
        "analyse": (run_analysis, False),
        "open": (open_text, False),
        "save": (save, False),
        "edit": (edit, False),
        "export": (export, True),
        "synth_motion": (synth_motion, True),
        "synth_path": (synth_path, True),
    }
