"""Benchmark: the morphing foot's column balance (D34), the cases of docs/performance.md.

``python benchmarks/bench_morphing_balance.py [--rounds 5] [--budget 2]`` times, for the
default :class:`mudrft.feet.MorphingFoot`,

* one foot, from curled (deflection 0) at 20 mm and 30 kPa (the float walk);
* the secant derivative's four nudged copies of one foot, as the MJX coupling steps
  them (three identical, the vertical nudge distinct: 30 kPa x (1 + 1e-6));
* 1,000 feet at random depths 5-25 mm and stresses 5-40 kPa (the array scan and
  ``find_root``; seed 0);
* ``mudrft.simulate`` of the morphing foot along the paper's gait at 0.2 m/s, W = 25 %.

Each number is the best of ``--rounds`` rounds of about ``--budget / --rounds`` seconds
(the harness's timer). To compare two trees, run it with each tree's ``src`` first on
``PYTHONPATH``, alternating, and keep the best of each.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from typing import Any

import numpy as np
from harness._timing import best

import mudrft
from mudrft.feet.morphing.equilibrium import balanced_deflection


def run(rounds: int, budget: float) -> dict[str, float]:
    """The four cases: ``one_us``, ``four_us``, ``thousand_ms``, ``simulate_s``; the best
    of ``rounds`` rounds of about ``budget / rounds`` seconds each (the harness's timer)."""
    foot = mudrft.feet.MorphingFoot()
    link, spring = foot.linkage, foot.spring

    def balance(d: Any, s: Any, p: Any) -> Callable[[], Any]:
        return lambda: balanced_deflection(d, s, previous=p, linkage=link, spring=spring)

    d4 = np.full(4, 0.02)
    s4 = np.array([30e3, 30e3, 30e3, 30e3 * (1.0 + 1e-6)])
    rng = np.random.default_rng(0)
    dk, sk = rng.uniform(0.005, 0.025, 1000), rng.uniform(5e3, 40e3, 1000)
    gait, mud = mudrft.gait(speed=0.2), mudrft.paper_mud(0.25)
    kw = {"budget": budget, "repeat": rounds}
    return {
        "one_us": 1e6 * best(balance(0.02, 30e3, 0.0), **kw),
        "four_us": 1e6 * best(balance(d4, s4, np.zeros(4)), **kw),
        "thousand_ms": 1e3 * best(balance(dk, sk, np.zeros(1000)), **kw),
        "simulate_s": best(lambda: mudrft.simulate(foot, mud, gait), **kw),
    }


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=5, help="rounds per case (best is kept)")
    ap.add_argument("--budget", type=float, default=2.0, help="seconds per case")
    args = ap.parse_args(argv)
    r = run(args.rounds, args.budget)
    print(
        f"one foot {r['one_us']:.0f} us | four nudged copies {r['four_us']:.0f} us | "
        f"1,000 feet {r['thousand_ms']:.2f} ms | simulate {r['simulate_s']:.3f} s"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
