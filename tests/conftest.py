"""Shared fixtures and test settings."""

from __future__ import annotations

import os

import numpy as np
import pytest
from hypothesis import settings

# Property tests: a fixed, modest budget so the suite is repeatable and quick on CI.
settings.register_profile("ci", max_examples=60, deadline=None, derandomize=True)
settings.register_profile("dev", max_examples=200, deadline=None)
settings.load_profile(os.environ.get("MACHDYN_HYPOTHESIS_PROFILE", "ci"))

# Plots are rendered off-screen.
os.environ.setdefault("MPLBACKEND", "Agg")


@pytest.fixture
def rng() -> np.random.Generator:
    """A seeded generator, so random property tests are reproducible."""
    return np.random.default_rng(20101008)
