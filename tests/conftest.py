"""Shared fixtures and test settings."""

from __future__ import annotations

import os

import numpy as np
import pytest
from hypothesis import settings

from machdyn import jit

# Property tests: a fixed, modest budget so the suite is repeatable and quick on CI.
settings.register_profile("ci", max_examples=60, deadline=None, derandomize=True)
settings.register_profile("dev", max_examples=200, deadline=None)
settings.load_profile(os.environ.get("MACHDYN_HYPOTHESIS_PROFILE", "ci"))

# The four-bar's compiled kernels: never by the "auto" rule, which would switch at some
# unpredictable test. The `backend` fixture runs a module on both paths.
jit.set_mode("off")

# Plots are rendered off-screen.
os.environ.setdefault("MPLBACKEND", "Agg")


@pytest.fixture
def rng() -> np.random.Generator:
    """A seeded generator, so random property tests are reproducible."""
    return np.random.default_rng(20101008)


@pytest.fixture(scope="module")
def browser():
    """One headless Chromium per test module (skips with the reason where it is missing)."""
    from browser import chromium

    with chromium() as b:
        yield b


@pytest.fixture(scope="module")
def studio(tmp_path_factory):
    """A studio server per test module, on a free port, saving to a fresh design file."""
    from machdyn.studio.server import Studio

    s = Studio(tmp_path_factory.mktemp("studio") / "design.toml", port=0)
    s.start()
    yield s
    s.stop()


@pytest.fixture(scope="session")
def atlas_1e4(tmp_path_factory):
    """A four-bar atlas of 10^4 entries, as a user's first one (the default build), built
    once per test process; tests only read it (an Atlas's caches change no answer)."""
    from machdyn.synthesis import build_atlas, open_atlas

    folder = tmp_path_factory.mktemp("atlas_1e4")
    build_atlas(folder, 10_000, progress=False)
    return open_atlas(folder)


@pytest.fixture(scope="module", params=["numpy", "compiled"])
def backend(request: pytest.FixtureRequest):
    """Run every test of a module twice: NumPy kernels, then the compiled (numba) ones."""
    if request.param == "compiled":
        pytest.importorskip("numba", reason="numba is not installed on this Python")
        assert jit.load(), f"the compiled kernels do not load: {jit.reason()}"
        jit.set_mode("on")
    yield request.param
    jit.set_mode("off")


@pytest.fixture
def compiled():
    """The compiled kernels serve this test (the suite runs NumPy, "off" above), the mode
    restored after: for tests of what only the compiled path does, or that would take
    minutes on NumPy (timed six-bar and many-point atlas searches)."""
    pytest.importorskip("numba", reason="numba is not installed on this Python")
    assert jit.load(), f"the compiled kernels do not load: {jit.reason()}"
    before = jit.mode()
    jit.set_mode("on")
    yield
    jit.set_mode(before)
