"""The first minute of a new user, timed as whole processes (issue 40).

Each figure is the best of ``--repeat`` fresh processes on this machine:

* ``import mudrft``;
* ``mudrft --help``;
* the first :func:`mudrft.simulate` of a closed-form foot over the paper's 0.2 m/s gait in a
  fresh process, with numba's cache warm (every run after the first on a machine) and cold
  (the first run after install: ``NUMBA_CACHE_DIR`` pointed at an empty folder);
* ``mudrft reproduce`` into a new folder, cache warm and cold.

Run from a checkout with mudrft installed: ``python benchmarks/bench_first_minute.py``.
Results go in docs/performance.md; tests never assert on them.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time

SIMULATE = (
    "import mudrft; mudrft.simulate(mudrft.feet.SemiCylinder(), mudrft.paper_mud(0.25), "
    "mudrft.gait(speed=0.2))"
)


def _time(cmd: list[str], *, cold: bool, cwd: str) -> float:
    env = dict(os.environ)
    with tempfile.TemporaryDirectory() as cache:
        if cold:
            env["NUMBA_CACHE_DIR"] = cache
        t0 = time.perf_counter()
        subprocess.run(cmd, check=True, env=env, cwd=cwd, capture_output=True)
        return time.perf_counter() - t0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    py = sys.executable
    with tempfile.TemporaryDirectory() as work:
        cases = {
            "import mudrft": ([py, "-c", "import mudrft"], False),
            "mudrft --help": ([py, "-m", "mudrft", "--help"], False),
            "first simulate, warm cache": ([py, "-c", SIMULATE], False),
            "first simulate, cold cache": ([py, "-c", SIMULATE], True),
            "mudrft reproduce, warm cache": ([py, "-m", "mudrft", "reproduce", "--out", "r", "--force"], False),
            "mudrft reproduce, cold cache": ([py, "-m", "mudrft", "reproduce", "--out", "r", "--force"], True),
        }  # fmt: skip
        _time(cases["first simulate, warm cache"][0], cold=False, cwd=work)  # warm the cache
        for name, (cmd, cold) in cases.items():
            times = [_time(cmd, cold=cold, cwd=work) for _ in range(args.repeat)]
            print(f"{name:32s} best {min(times):6.2f} s   (of {args.repeat}: "
                  + ", ".join(f"{t:.2f}" for t in times) + ")")  # fmt: skip
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
