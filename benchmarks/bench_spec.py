"""Cold-start time of ``machdyn run`` on the HW 6 four-bar file (target: <= 0.6 s wall).

Each command runs in a fresh process (wall time, and the CPU time it used:
on a shared machine the CPU time is the steadier figure), interleaved with the peers it is compared
against (the machine is shared: ratios to peers measured in the same rounds are
steadier than absolute times): ``machdyn fourbar 8 4 7 6`` (the same linkage
from the command line) and a bare ``python -c "import numpy"`` (the floor of
any machdyn command). The unit cache (``units-*.json``) is warmed first, as it
is after a file's units have been seen once.

    python benchmarks/bench_spec.py [rounds]
"""

from __future__ import annotations

import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
HW6 = str(ROOT / "docs" / "examples" / "hw6.toml")
MACHDYN = [str(Path(sys.executable).parent / "machdyn")]  # the console script

COMMANDS = {
    "machdyn run hw6.toml": [*MACHDYN, "run", HW6],
    "machdyn fourbar 8 4 7 6": [*MACHDYN, "fourbar", "8", "4", "7", "6"],
    "python -c 'import numpy'": [sys.executable, "-c", "import numpy"],
}


def wall(command: list[str]) -> tuple[float, float]:
    """Wall time and CPU time (user + system) of one run of ``command``."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL)
    elapsed = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return elapsed, cpu


def main(rounds: int = 15) -> None:
    for command in COMMANDS.values():  # warm the file system, numba's and the unit cache
        wall(command)
    times: dict[str, list[tuple[float, float]]] = {name: [] for name in COMMANDS}
    for _ in range(rounds):
        for name, command in COMMANDS.items():
            times[name].append(wall(command))
    run = [w for w, _ in times["machdyn run hw6.toml"]]
    print(f"{'command':28s} {'wall best':>10s} {'median':>8s} {'CPU best':>9s}   ratio to run")
    for name, values in times.items():
        walls = [w for w, _ in values]
        ratio = statistics.median(v / r for v, r in zip(walls, run, strict=True))
        cpu = min(c for _, c in values)
        print(
            f"{name:28s} {min(walls):9.3f}s {statistics.median(walls):7.3f}s {cpu:8.3f}s"
            f"   {ratio:6.2f}"
        )


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 15)
