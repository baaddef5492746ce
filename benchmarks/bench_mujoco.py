"""Cost of the mud coupling in MuJoCo (thin script over the harness).

``python benchmarks/bench_mujoco.py [--seconds S] [--json FILE]``; see
``benchmarks/harness/mujoco_cost.py``. ``mudrft bench`` runs the same function.
"""

from __future__ import annotations

import sys

from harness.mujoco_cost import main, mujoco_overhead_ratio

__all__ = ["main", "mujoco_overhead_ratio"]

if __name__ == "__main__":
    sys.exit(main())
