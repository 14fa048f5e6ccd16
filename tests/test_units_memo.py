"""The on-disk memo of pint's answers is keyed by machdyn's own unit definitions too.

A memo written by a machdyn whose definitions differed (an older one, before ``rev`` was
defined, say) must not be read: its factors and dimensions could be wrong for today's.
"""

from __future__ import annotations

import json

from machdyn import units


def _memo_path(monkeypatch, definitions):
    monkeypatch.setattr(units, "_DEFINITIONS", definitions)
    return units._Memo()._path()


def test_a_memo_written_under_other_definitions_is_not_read(monkeypatch, tmp_path):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    monkeypatch.delenv("MACHDYN_UNIT_CACHE", raising=False)
    today = units._DEFINITIONS
    older = _memo_path(monkeypatch, ())
    older.parent.mkdir(parents=True)
    older.write_text(json.dumps({"factor": {"in|m": 1.0}, "signature": {}}), encoding="utf-8")

    current = _memo_path(monkeypatch, today)
    assert current != older and current.parent == older.parent
    assert units._Memo().table("factor") == {}  # the stale 1.0 is not seen
    # and the memo under today's definitions is the one read back
    current.write_text(json.dumps({"factor": {"in|m": 0.0254}, "signature": {}}), encoding="utf-8")
    assert units._Memo().table("factor") == {"in|m": 0.0254}


def test_rev_is_a_turn():
    # 1 rev/s = 2π rad/s = 60 rpm (pint knows 'revolution' and 'rpm'; machdyn defines 'rev')
    assert abs(units._factor("rev/s", "rad/s") - 2 * 3.141592653589793) < 1e-12
    assert abs(units._factor("rev/min", "rpm") - 1.0) < 1e-12
