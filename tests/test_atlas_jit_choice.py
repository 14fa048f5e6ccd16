"""path_from_atlas makes one choice of kernels for a synthesis: compiled unless switched off."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

from machdyn.synthesis import build_atlas

SCRIPT = """
import sys
import numpy as np
from machdyn import jit
from machdyn.synthesis import path_from_atlas
theta = np.linspace(0.3, 2.3, 7)
targets = np.exp(1j * theta) * (2 + 0.3 * np.cos(3 * theta))  # an open arc
res = path_from_atlas(targets, sys.argv[1], closed=False, n=1)
print(jit.active(), "numba" in sys.modules)
"""


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    path = tmp_path_factory.mktemp("atlas")
    build_atlas(path, 2_000, chunk_size=1_000, progress=False)
    return path


@pytest.mark.parametrize(("mode", "want"), [("auto", "True True"), ("off", "False False")])
def test_a_fresh_process_synthesises_on_the_kernels_the_mode_picks(folder, mode, want):
    # a user's script in a fresh process: with MACHDYN_JIT=auto (the default) the
    # synthesis loads the compiled kernels, the search the benchmarks measure (before
    # 2026-11-25 auto left it on NumPy and scipy's trf: every gate asked for fewer poses
    # than jit.BUDGET); with off, numba is not even imported
    pytest.importorskip("numba")
    env = dict(os.environ, MACHDYN_JIT=mode)
    out = subprocess.run([sys.executable, "-c", SCRIPT, str(folder)], env=env,
                         capture_output=True, text=True, timeout=600, check=True)  # fmt: skip
    assert out.stdout.split()[-2:] == want.split()
