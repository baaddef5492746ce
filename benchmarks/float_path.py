"""The single-foot float paths on several source trees, alternated round by round.

::

    git worktree add /tmp/old ecac30f     # the last commit before the one-physics rewrite
    python benchmarks/float_path.py /tmp/old/src src [more trees] [--rounds 5] [--numba]

Each round runs one process per tree, in the order given, and prints per tree the best of
15 repeats (µs): one channel step on Python floats (before the rewrite the hand-written
``kernels.scalar_channel_step``, after it ``on_floats(kernel.channel_update)``) and one
``FastMudFoot`` step on the python backend (and on numba with ``--numba``), then the ratio
of each tree to the first. Quicker and tighter than ``before_after.py`` for these rows.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import timeit
from pathlib import Path


def measure(numba: bool) -> dict[str, float]:
    """The float paths of the ``mudrft`` on ``sys.path`` [µs]."""
    import numpy as np

    import mudrft
    from mudrft.backends.fast import FastMudFoot

    def best(f, n):
        return 1e6 * min(timeit.repeat(f, number=n, repeat=15)) / n

    p = mudrft.paper_parameters(0.25)
    try:
        from mudrft._specialize import on_floats
        from mudrft.constitutive import kernel
        from mudrft.constitutive.state import ChannelState

        update = on_floats(kernel.channel_update)
        c = kernel.ChannelConstants(*(float(v) for v in kernel.channel_constants(p)))
        s = ChannelState(*[0.0] * len(ChannelState._fields))
        out = {"float": best(lambda: update(c, s, 0.1, 1.0, 1e-3), 2000)}
    except ImportError:  # before the rewrite
        from mudrft.backends import kernels

        row = [float(v) for v in kernels.constant_rows(kernels.channel_constants(p))]
        cs = [0.0] * 5
        out = {
            "float": best(
                lambda: kernels.scalar_channel_step(row, 0, cs, 0, 0.1, 1.0, 1e-3, 1.0, 1.0), 2000
            )
        }
    terrain = mudrft.MudTerrain(mudrft.paper_mud(0.3))
    pos, vel = np.array([0.001, 0.0, -0.01]), np.array([0.02, 0.01, -0.03])
    for b in ["python"] + (["numba"] if numba else []):
        ff = FastMudFoot(mudrft.feet.Flat(), terrain, backend=b)
        ff.step(pos, vel, 1e-3)
        out[b] = best(lambda ff=ff: ff.step(pos, vel, 1e-3), 500 if b == "python" else 5000)
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("trees", nargs="*", help="src/ directories; the first is the reference")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--numba", action="store_true")
    ap.add_argument("--measure", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.measure:
        print(json.dumps(measure(args.numba)))
        return 0
    for r in range(args.rounds):
        got = []
        for src in args.trees:
            env = {**os.environ, "PYTHONPATH": str(Path(src).resolve())}
            cmd = [sys.executable, __file__, "--measure"] + (["--numba"] if args.numba else [])
            done = subprocess.run(cmd, env=env, check=True, capture_output=True, text=True)
            got.append(json.loads(done.stdout.strip().splitlines()[-1]))
        ref = got[0]
        print(f"round {r + 1} (load {os.getloadavg()[0]:.1f}): " + "; ".join(
            f"{k}: " + " / ".join(f"{g[k]:.3f}" for g in got) + " µs = "
            + " / ".join(f"x{g[k] / ref[k]:.2f}" for g in got[1:])
            for k in ref
        ))  # fmt: skip
    return 0


if __name__ == "__main__":
    sys.exit(main())
