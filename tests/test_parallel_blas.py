"""``one_blas_thread`` limits every BLAS the wrapped code uses, whatever was imported first.

The atlas synthesis's refinements run scipy's trf, whose SVDs go through scipy's own
OpenBLAS (not numpy's). In a fresh process scipy is imported lazily inside the wrapped
call; the limit must reach that library too. Checked in a new interpreter with
threadpoolctl's own report of the loaded libraries.
"""

from __future__ import annotations

import json
import subprocess
import sys

SCRIPT = """
import json
from threadpoolctl import threadpool_info
from machdyn._parallel import one_blas_thread

@one_blas_thread
def inside():
    import scipy.optimize  # (what refine imports lazily)
    return [i["num_threads"] for i in threadpool_info() if i["user_api"] == "blas"]

print(json.dumps(inside()))
"""


def test_a_fresh_process_runs_scipys_blas_on_one_thread_too():
    out = subprocess.run(
        [sys.executable, "-c", SCRIPT], capture_output=True, text=True, check=True, timeout=120
    )
    threads = json.loads(out.stdout.strip().splitlines()[-1])
    assert threads, "no BLAS library reported"
    assert threads == [1] * len(threads)
