"""The compiled loop over feet of two or more source trees, timed side by side.

``python benchmarks/bench_numba_loop.py [--feet N] [--what loop|fast] [--samples S]
LABEL=SRC ...`` starts one process per tree (``SRC`` is a tree's ``src/`` directory), each
compiles and warms up, then the processes take turns: each sample times a few calls in one
process, then in the next. Slow drifts of a shared machine (other jobs, clock changes) then
hit every tree alike, which best-of-N runs of one tree after the other do not ensure. The
first tree is the reference of the ratios.

``--what loop`` times the compiled loop of ``BatchedMud(backend="numba")`` alone (its
validation and copies left out), flat feet 1-3 cm deep moving in every direction, W = 30 %,
dt = 1 ms; a tree from before the one-physics rewrite (``mudrft.backends.numba_kernels``)
is called with its own argument order. ``--what fast`` times ``FastMudFoot(backend="numba")
.step`` from Python, one flat foot. Prints, per tree, the best, 10th-percentile and median
sample [ns per foot step], and the median of the per-sample ratios to the first tree.
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


def _serve(what: str, n: int) -> None:
    """Build the workload, print ``ready``, then time one sample per line read on stdin."""
    import numpy as np

    import mudrft

    if what == "fast":
        from mudrft.backends.fast import FastMudFoot

        terrain = mudrft.MudTerrain(mudrft.paper_mud(0.3))
        ff = FastMudFoot(mudrft.feet.Flat(), terrain, backend="numba")
        pos, vel = np.array([0.001, 0.0, -0.01]), np.array([0.02, 0.01, -0.03])

        def call() -> object:
            return ff.step(pos, vel, 1e-3)

        n, reps = 1, 5000
    else:
        from harness.feet import moving_feet

        from mudrft.backends.batch import BatchedMud

        pos, vel = moving_feet(n)
        sim = BatchedMud(
            mudrft.paper_mud(0.3), mudrft.feet.Flat(), n, position=pos + np.array([0, 0, 0.001]),
            backend="numba",
        )  # fmt: skip
        sim.step(pos, vel, 1e-3)
        p, v = np.ascontiguousarray(pos), np.ascontiguousarray(vel)
        if importlib.util.find_spec("mudrft.backends.numba_kernels"):  # before the rewrite
            args = (sim._c, sim._st, sim._out, sim._geom, sim._cfg, p, v, 1e-3)
        else:
            args = (sim._c, sim._st, sim._out, p, v, 1e-3, sim._cfg, sim._geom)

        def call() -> object:
            return sim._nb_step(*args)

        reps = max(3, 20_000 // n)
    for _ in range(20):
        call()
    print("ready", flush=True)
    for _ in sys.stdin:
        t = time.perf_counter()
        for _ in range(reps):
            call()
        print(1e9 * (time.perf_counter() - t) / reps / n, flush=True)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("trees", nargs="*", metavar="LABEL=SRC", help="a label and a src/ directory")
    ap.add_argument("--what", choices=("loop", "fast"), default="loop")
    ap.add_argument("--feet", type=int, default=1000, help="feet in the loop (--what loop)")
    ap.add_argument("--samples", type=int, default=150, help="samples per tree")
    ap.add_argument("--serve", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.serve:
        _serve(args.what, args.feet)
        return 0
    if not args.trees:
        ap.error("give at least one tree, LABEL=SRC")
    procs = {}
    for spec in args.trees:
        label, _, src = spec.partition("=")
        if not src:
            ap.error(f"each tree is LABEL=SRC, got {spec!r}")
        env = {**os.environ, "PYTHONPATH": f"{Path(src).resolve()}{os.pathsep}{HERE}"}
        cmd = [sys.executable, __file__, "--serve", "--what", args.what, "--feet", str(args.feet)]
        p = subprocess.Popen(cmd, env=env, stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
        assert p.stdin is not None and p.stdout is not None
        if p.stdout.readline().strip() != "ready":
            raise SystemExit(f"{label}: the workload did not start (see the error above)")
        procs[label] = p
    samples: dict[str, list[float]] = {label: [] for label in procs}
    for _ in range(args.samples):
        for label, p in procs.items():
            assert p.stdin is not None and p.stdout is not None
            p.stdin.write("go\n")
            p.stdin.flush()
            samples[label].append(float(p.stdout.readline()))
    first = next(iter(samples))
    print(f"load average {os.getloadavg()[0]:.1f}; {args.what}, ns per foot step")
    for label, v in samples.items():
        s = sorted(v)
        ratio = statistics.median(b / a for a, b in zip(samples[first], v, strict=True))
        print(
            f"{label}: best {s[0]:.0f}, p10 {s[len(s) // 10]:.0f}, median "
            f"{statistics.median(s):.0f}; / {first}: {ratio:.3f}"
        )
    for p in procs.values():
        assert p.stdin is not None
        p.stdin.close()
        p.wait()
    return 0


if __name__ == "__main__":
    sys.exit(main())
