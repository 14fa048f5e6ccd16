"""A linkage's groups list their joints in one order, whatever Python's string hashing.

The groups were found by walking a set of link names, so a group's joints (what
``Linkage.groups`` shows, and what reports and messages name) came out in an
order that changed with ``PYTHONHASHSEED`` from one process to the next. The
expected order here is the one the joints were declared in, read off the builder
calls below, not off machdyn.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys

PROGRAM = """
import json
from machdyn.linkage import Linkage

slider = (Linkage({"O2": 0j, "A": 1.7 + 1j, "B": 3.5 + 0j, "O5": 10 + 0j, "E": 11 + 0j})
          .ground("O2", "O5")
          .link("crank", "O2", "A").link("rod", "A", "B").link("block", "B").link("arm", "O5", "E"))
slider.slider("block", "ground", "B", 0.0, through="O2", name="guide")
slider.drive("crank", "arm")
fourbar = (Linkage({"O2": 0j, "A": 1j, "B": 3 + 2j, "O4": 4 + 0j}).ground("O2", "O4")
           .link("crank", "O2", "A").link("coupler", "A", "B").link("rocker", "O4", "B")
           .drive("crank"))
print(json.dumps([[list(g.joints) for g in lk.groups] for lk in (slider, fourbar)]))
"""


def _groups(seed: int) -> list:
    env = {**os.environ, "PYTHONHASHSEED": str(seed)}
    out = subprocess.run([sys.executable, "-c", PROGRAM], env=env, capture_output=True,
                         text=True, check=True)  # fmt: skip
    return json.loads(out.stdout)


def test_groups_list_their_joints_in_declared_order_under_any_hash_seed():
    seen = [_groups(seed) for seed in (0, 1, 2, 3, 5)]
    slider, fourbar = seen[0]
    # the dyad (rod, block): pin A (crank-rod), pin B (rod-block), then the slider's guide
    assert slider[-1] == ["pin A", "pin B", "guide"]
    # the dyad (coupler, rocker): the coupler's pins A and B, then the rocker's O4
    assert fourbar[-1] == ["pin A", "pin B", "pin O4"]
    assert all(s == seen[0] for s in seen[1:])
