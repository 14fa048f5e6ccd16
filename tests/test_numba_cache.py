"""numba's on-disk cache under machdyn's guard (machdyn._numba_cache).

Each test writes a small kernel module into a temporary directory and runs it in
fresh interpreters with their own ``NUMBA_CACHE_DIR``, so that the cache starts
empty and nothing is shared with the suite's own compiled kernels. The expected
numbers are written in the kernel's source (2x + point), not read from numba.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest

pytest.importorskip("numba", reason="numba is not installed on this Python")
pytestmark = pytest.mark.slow  # fresh interpreters compiling: ~20 s in all

KERNEL = """
import numpy as np
from {decorator_module} import njit

@njit(cache=True, nogil=True)
def shift(x, point, out):
    for i in range(x.size):
        out[i] = 2.0 * x[i]
        if point is not None:
            out[i] += point[i]
    return 0
"""

# Each run calls the kernel with the arguments named on its command line and prints
# what it computed and whether numba loaded the signature from its cache.
RUN = """
import json, os, sys, time
import numpy as np

if os.environ.get("SLOW_INDEX"):  # widen numba's read-modify-write of the index to a second
    from numba.core import caching

    write = caching.IndexDataCacheFile._save_index

    def slow(self, overloads):
        time.sleep(1.0)
        write(self, overloads)

    caching.IndexDataCacheFile._save_index = slow

import kernel

out = {}
for name in sys.argv[1:]:
    dtype = {"f8": np.float64, "f4": np.float32, "i8": np.int64}[name.split("+")[0]]
    x = np.arange(1, 4).astype(dtype)
    point = np.full(3, 10, dtype=dtype) if name.endswith("+point") else None
    result = np.zeros(3)
    kernel.shift(x, point, result)
    out[name] = result.tolist()
stats = kernel.shift.stats
print(json.dumps({"values": out, "hits": sum(stats.cache_hits.values()),
                  "misses": sum(stats.cache_misses.values())}))
"""


def _module(tmp_path: Path, decorator_module: str) -> Path:
    src = tmp_path / "src"
    src.mkdir()
    (src / "kernel.py").write_text(KERNEL.format(decorator_module=decorator_module))
    (src / "run.py").write_text(RUN)
    return src


def _start(src: Path, cache: Path, *calls: str, start_at: float | None = None) -> subprocess.Popen:
    path = os.pathsep.join([str(src), *sys.path])
    env = {**os.environ, "NUMBA_CACHE_DIR": str(cache), "PYTHONPATH": path}
    if start_at is not None:
        env["SLOW_INDEX"] = "1"
    code = "import runpy, sys; "
    if start_at is not None:  # start the calls together: the race is between their compiles
        code += f"import time; time.sleep(max(0.0, {start_at} - time.time())); "
    code += "sys.argv = ['run.py', *sys.argv[1:]]; runpy.run_path('run.py', run_name='__main__')"
    return subprocess.Popen(
        [sys.executable, "-c", code, *calls],
        cwd=src, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip


def _run(src: Path, cache: Path, *calls: str) -> dict:
    return _finish(_start(src, cache, *calls))


def _finish(process: subprocess.Popen) -> dict:
    out, err = process.communicate(timeout=300)
    assert process.returncode == 0, err
    return json.loads(out.strip().splitlines()[-1])


def _misfile(src: Path, tmp_path: Path) -> Path:
    """A cache whose index sends ``+point`` calls to the machine code of ``point=None``.

    What two processes racing on one cache can leave: each compiled one signature
    and named its data file ``.1.nbc``; the index of one and the data of the other won.
    """
    alone, other = tmp_path / "alone", tmp_path / "other"
    _run(src, alone, "f8")  # point=None's code in .1.nbc
    _run(src, other, "f8+point")  # an index naming .1.nbc for point=array
    (index,) = alone.rglob("*.nbi")
    (foreign,) = other.rglob("*.nbi")
    shutil.copyfile(foreign, index)
    return alone


def test_plain_numba_runs_the_other_signatures_code_from_a_misfiled_index(tmp_path):
    """The premise: numba alone loads the wrong signature's code (drop the guard if this fails)."""
    src = _module(tmp_path, "numba")
    result = _run(src, _misfile(src, tmp_path), "f8+point")
    assert result["values"]["f8+point"] == [2.0, 4.0, 6.0]  # 2x, the point ignored: wrong
    assert result["hits"] == 1


def test_guarded_cache_refuses_another_signatures_code_and_compiles(tmp_path):
    src = _module(tmp_path, "machdyn._numba_cache")
    cache = _misfile(src, tmp_path)
    result = _run(src, cache, "f8+point")
    assert result["values"]["f8+point"] == [12.0, 14.0, 16.0]  # 2x + 10
    assert (result["hits"], result["misses"]) == (0, 1)
    # the fresh compile was saved under its own key: the next process loads the right code
    again = _run(src, cache, "f8+point")
    assert again["values"]["f8+point"] == [12.0, 14.0, 16.0]
    assert (again["hits"], again["misses"]) == (1, 0)
    # and point=None, whose data file the fresh compile overwrote, compiles its own again
    assert _run(src, cache, "f8")["values"]["f8"] == [2.0, 4.0, 6.0]


CALLS = ["f8", "f8+point", "i8+point", "f4+point"]
EXPECTED = {"f8": [2.0, 4.0, 6.0], "f8+point": [12.0, 14.0, 16.0],
            "i8+point": [12.0, 14.0, 16.0], "f4+point": [12.0, 14.0, 16.0]}  # fmt: skip


def _race(tmp_path: Path, decorator_module: str) -> dict:
    """Four processes compile four signatures into one empty cache at the same moment
    (each holding the index a second between reading and writing it); then a fifth loads them."""
    src = _module(tmp_path, decorator_module)
    cache = tmp_path / "shared"
    start_at = time.time() + 4.0  # after every interpreter has imported numba
    processes = [_start(src, cache, call, start_at=start_at) for call in CALLS]
    for process in processes:
        _finish(process)
    return _run(src, cache, *CALLS)


def test_plain_numba_loses_or_mixes_signatures_compiled_at_once(tmp_path):
    """The premise: without a lock the last index written wins (drop the guard if this fails)."""
    loaded = _race(tmp_path, "numba")
    assert loaded["misses"] > 0 or loaded["values"] != EXPECTED


def test_processes_compiling_at_once_keep_every_signature(tmp_path):
    loaded = _race(tmp_path, "machdyn._numba_cache")
    assert loaded["values"] == EXPECTED
    # every signature is in the index, each under its own data file: all four loaded
    assert (loaded["hits"], loaded["misses"]) == (4, 0)
    assert len(list((tmp_path / "shared").rglob("*.nbc"))) == 4


class _Module:
    """A stand-in for a compiled kernel module: ``warm_up`` fails its first ``failures`` calls."""

    def __init__(self, failures: int, error: type[Exception] = RuntimeError) -> None:
        self.calls, self.failures, self.error = 0, failures, error

    def warm_up(self) -> None:
        self.calls += 1
        if self.calls <= self.failures:
            raise self.error("no compiled object yet for <Library 'solve3'>")


def test_warm_calls_once_more_after_a_runtime_error():
    from machdyn import jit

    module = _Module(failures=1)
    jit.warm(module)
    assert module.calls == 2


@pytest.mark.parametrize(("failures", "error", "calls"), [(2, RuntimeError, 2), (1, TypeError, 1)])
def test_warm_raises_a_fault_that_repeats_or_is_not_a_runtime_error(failures, error, calls):
    from machdyn import jit

    module = _Module(failures, error)
    with pytest.raises(error):
        jit.warm(module)
    assert module.calls == calls
