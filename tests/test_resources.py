"""Resource guards: the memory budget refuses big requests up front; the cam checks scale."""

from __future__ import annotations

import tracemalloc

import numpy as np
import pytest

from machdyn import FourBar, InputError, SliderCrank
from machdyn._parallel import format_bytes, memory_limit, physical_memory, require_memory
from machdyn.cams import CamProgram, TranslatingRoller
from machdyn.cams._interference import _candidate_pairs, polyline_crossings
from machdyn.cli import main


@pytest.mark.parametrize(
    ("text", "expected"),
    [("2G", 2 * 2**30), ("500M", 500 * 2**20), ("1.5GB", int(1.5 * 2**30)), ("4096", 4096)],
)
def test_memory_limit_reads_the_environment(monkeypatch, text, expected):
    monkeypatch.setenv("MACHDYN_MEMORY_LIMIT", text)
    assert memory_limit() == expected


def test_memory_limit_defaults_to_half_the_machine(monkeypatch):
    monkeypatch.delenv("MACHDYN_MEMORY_LIMIT", raising=False)
    assert memory_limit() == int(0.5 * physical_memory())
    monkeypatch.setenv("MACHDYN_MEMORY_LIMIT", "0.25")  # a fraction of the machine
    assert memory_limit() == int(0.25 * physical_memory())
    monkeypatch.setenv("MACHDYN_MEMORY_LIMIT", "lots")  # unreadable: the default
    assert memory_limit() == int(0.5 * physical_memory())


def test_require_memory_names_the_field_and_the_size(monkeypatch):
    monkeypatch.setenv("MACHDYN_MEMORY_LIMIT", "1G")
    require_memory("n", 2**29, "half a gigabyte")
    with pytest.raises(InputError) as err:
        require_memory("n", 3 * 2**30, "3 GB of samples")
    assert err.value.field == "n"
    assert "3 GB" in str(err.value) and "1 GB allowed" in str(err.value)
    assert format_bytes(10**400) == "9.09e+287 TB"  # a Python integer beyond the float range


def test_a_solve_beyond_the_budget_is_refused_before_any_work(monkeypatch):
    """10^8 poses (about 20 GB of results) are refused before any of it is allocated."""
    monkeypatch.setenv("MACHDYN_MEMORY_LIMIT", "1G")
    theta2 = np.broadcast_to(0.3, (10**8,))  # a view: no memory of its own
    for model in (FourBar(8, 4, 7, 6), SliderCrank(2, 6)):
        tracemalloc.start()
        with pytest.raises(InputError, match="100,000,000 poses need about") as err:
            model.solve(theta2, omega2=1.0)
        assert err.value.field == "theta2"
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        assert peak < 2**20  # not even a copy of theta2 (800 MB) was made
    monkeypatch.setenv("MACHDYN_MEMORY_LIMIT", "8G")
    assert FourBar(8, 4, 7, 6).solve(np.broadcast_to(0.3, (1000,)), 1.0).ok.all()


def test_sizes_are_checked_against_the_budget(monkeypatch):
    monkeypatch.setenv("MACHDYN_MEMORY_LIMIT", "100M")
    program = CamProgram.double_dwell(1.0, 1.0, 1.0)
    with pytest.raises(InputError, match="cam samples need about"):
        TranslatingRoller(4.0, 0.5).profile(program, n=10**6)
    with pytest.raises(InputError) as err:
        FourBar(8, 4, 7, 6).extrema(n=10**8)
    assert err.value.field == "n"


def test_cli_refuses_too_many_points_in_one_line(monkeypatch, capsys):
    monkeypatch.setenv("MACHDYN_MEMORY_LIMIT", "1G")
    cam = ["cam", "-s", "rise:cycloidal:1:60", "-s", "dwell:120", "-s", "fall:cycloidal:1:60"]
    cam += ["-s", "dwell:120", "--prime-radius", "4", "--roller-radius", "0.5"]
    assert main([*cam, "--points", "360"]) == 0
    capsys.readouterr()
    assert main([*cam, "--points", "100000000"]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("machdyn: error: --points:")


def _circle(n: int, wobble: float = 0.0) -> np.ndarray:
    t = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    return (5.0 + wobble * np.sin(7 * t)) * np.exp(1j * t)


def test_crossing_candidates_grow_linearly_with_the_points():
    """The work of the self-intersection check is its candidate pairs: O(n), not n^1.7."""
    counts = []
    for n in (10_000, 80_000):
        z = _circle(n, 0.5)
        start, end = z, np.roll(z, -1)
        counts.append(_candidate_pairs(start, end)[0].size)
    assert counts[1] < 10 * counts[0]  # 8x the points: at most ~8x the pairs


def test_crossings_of_a_dense_outline_are_found():
    """A figure eight of 200,000 points crosses itself once, where the lobes meet."""
    t = np.linspace(0.0, 2.0 * np.pi, 200_000, endpoint=False)
    eight = np.sin(t) + 1j * np.sin(t) * np.cos(t)
    tau_a, tau_b, point = polyline_crossings(eight)
    assert tau_a.size == 1
    assert abs(point[0]) < 1e-4
    assert abs((tau_b[0] - tau_a[0]) - 100_000) < 2  # half-way round: t = 0 and t = pi
