"""Cost of the mud coupling in MuJoCo (thin script; the benchmark lives in the package).

``python benchmarks/bench_mujoco.py [--seconds S] [--json FILE]``; see
:mod:`mudrft.integrations.benchmark`. ``mudrft bench`` runs the same function.
"""

from __future__ import annotations

import sys

from mudrft.integrations.benchmark import main, mujoco_overhead_ratio

__all__ = ["main", "mujoco_overhead_ratio"]

if __name__ == "__main__":
    sys.exit(main())
