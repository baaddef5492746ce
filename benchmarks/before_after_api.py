"""Before/after a change, on the public API: alternated processes on two source trees.

Run from the checkout, with the old tree checked out beside it::

    git worktree add /tmp/old f5e9deb
    python benchmarks/before_after_api.py --old-src /tmp/old/src [--rounds 3]

Each round runs one process per tree (``PYTHONPATH`` set to its ``src``), old then new, so
both see about the same load on a shared machine; it prints every round's numbers, and
only the pairs of a round compare. Unlike ``before_after.py`` (the one-physics rewrite's
internal paths), it times only public calls, so any two trees of the last year compare:

* the MuJoCo biped's coupling overhead (:func:`mudrft.integrations.benchmark.mujoco_overhead_ratio`,
  compiled coupling, ``advance`` and ``step``), under Euler and under RK4 [-];
* the closed-form feet's ``force`` on one sample and on 1,000 [µs];
* one ``simulate`` of the flat foot over the 0.2 m/s gait [ms].

Results: docs/performance.md, "Re-measured after the changes of 2026-11-24".
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import timeit
import warnings
from pathlib import Path
from typing import Any

HERE = Path(__file__).resolve().parent


def _best(fn: Any, number: int) -> float:
    return min(timeit.repeat(fn, number=number, repeat=7)) / number


def _rk4_overhead(benchmark: Any) -> float:
    """The biped's overhead ratio under RK4 (the benchmark's robots switched to RK4)."""
    import mujoco

    build = benchmark._robots

    def robots(*args: Any, **kwargs: Any) -> Any:
        model, datas, ctrl, coupling = build(*args, **kwargs)
        model.opt.integrator = mujoco.mjtIntegrator.mjINT_RK4
        return model, datas, ctrl, coupling

    benchmark._robots = robots
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # trees before D150 warn under RK4
            phys, mud, _ = benchmark._triple(1, steps=1000, dt=1e-3, repeats=5, backend="numba")
    finally:
        benchmark._robots = build
    return mud / phys


def measure() -> dict[str, float]:
    """Every number of one tree (the one on ``sys.path``)."""
    import numpy as np

    import mudrft
    from mudrft.integrations import benchmark

    out: dict[str, float] = {}
    r = benchmark.mujoco_overhead_ratio(1.0, batch=(), feet=())
    out["overhead, Euler, advance"] = r["ratio"]
    out["overhead, Euler, step"] = r["ratio_with_contact"]
    out["overhead, RK4, advance"] = _rk4_overhead(benchmark)
    one = (np.array(0.02), np.array([1e3, 0.0, 5e3]), np.array(0.0))
    many = (np.linspace(0, 0.025, 1000), np.tile(one[1], (1000, 1)), np.zeros(1000))
    for name in ("Flat", "SemiCylinder", "SemiSphere"):
        foot = getattr(mudrft.feet, name)()
        out[f"{name}.force, 1 sample [us]"] = _best(lambda f=foot: f.force(*one), 2000) * 1e6
        out[f"{name}.force, 1000 [us]"] = _best(lambda f=foot: f.force(*many), 200) * 1e6
    mud, gait, flat = mudrft.paper_mud(0.25), mudrft.gait(0.2), mudrft.feet.Flat()
    out["simulate, flat, gait 0.2 m/s [ms]"] = (
        _best(lambda: mudrft.simulate(flat, mud, gait), 3) * 1e3
    )
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--old-src", help="the old tree's src/ directory")
    ap.add_argument("--new-src", default=str(HERE.parent / "src"), help="the new tree's src/")
    ap.add_argument("--rounds", type=int, default=3, help="alternated rounds per tree")
    ap.add_argument("--measure", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.measure:
        print(json.dumps(measure()))
        return 0
    if not args.old_src:
        ap.error("--old-src is required (the old tree's src/ directory)")
    rows: dict[str, list[str]] = {}
    for r in range(1, args.rounds + 1):
        for tag, src in (("old", args.old_src), ("new", args.new_src)):
            print(f"round {r}: {tag} ({src})", file=sys.stderr)
            env = {**os.environ, "PYTHONPATH": src}
            cmd = [sys.executable, str(Path(__file__).resolve()), "--measure"]
            done = subprocess.run(cmd, env=env, check=True, capture_output=True, text=True)
            for key, value in json.loads(done.stdout.splitlines()[-1]).items():
                rows.setdefault(key, []).append(f"{tag} {value:.4g}")
    for key, values in rows.items():
        print(f"{key}: " + ", ".join(values))
    return 0


if __name__ == "__main__":
    sys.exit(main())
