"""Benchmark of the calibration: offline fits of three-trial datasets, and the per-sample
cost of the online estimators.

Run ``python benchmarks/bench_calibration.py [--quick] [--json FILE]``. Timings are the
best of several repeats (robust to other load on the machine). Results and their
discussion are in docs/performance.md.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import sys
import time
import warnings
from collections.abc import Callable
from typing import Any

import numpy as np

import mudrft
from mudrft.calibration import (
    OnlineEstimator,
    StreamClassifier,
    calibrate,
    example_dataset,
    synthetic_dataset,
)


def _best(fn: Callable[[], Any], repeat: int) -> tuple[float, Any]:
    best, out = float("inf"), None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def lab_logs(seed: int = 0) -> Any:
    """Issue 39's rig as a lab logs it: a 40 x 40 mm plate, 10, 20 and 40 mm/s to 30 mm, a 1 s
    hold, 500 Hz; 0.2 s at rest 5 mm above the mud, the approach, the retraction out of it;
    0.02 mm of depth noise, 0.3 N of force noise (SYNTHETIC)."""
    return synthetic_dataset(
        mudrft.paper_parameters(0.25), noise=0.0, seed=seed, hold=1.0, dt=0.002,
        characteristic_length=0.04, approach=0.005, tare=0.2, rest=0.2,
        depth_noise=2e-5, stress_noise=0.3 / 0.04**2,
    )  # fmt: skip


def bench_fits(repeat: int) -> list[dict[str, Any]]:
    cases = [
        (
            "lab logs W=25 % (3 trials, 500 Hz, depth and force noise; thinned to 1 in 3)",
            lab_logs(),
        ),
        ("example vertical W=25 % (3 trials, dt 25 ms)", example_dataset("vertical")),
        ("example horizontal W=25 % (3 trials, dt 25 ms)", example_dataset("horizontal")),
        (
            "synthetic vertical W=25 % (3 trials, dt 10 ms)",
            synthetic_dataset(mudrft.paper_parameters(0.25), noise=0.01, seed=1, dt=0.01),
        ),
    ]
    rows = []
    for name, ds in cases:
        with warnings.catch_warnings():  # the 500 Hz logs are thinned, with a warning
            warnings.simplefilter("ignore")
            sec, fit = _best(lambda ds=ds: calibrate(ds), repeat)
        sims = sum(s.simulations for s in fit.stages)
        rows.append(
            {
                "case": name,
                "samples": int(sum(len(t) for t in ds)),
                "seconds": sec,
                "simulations": sims,
                "status": fit.status,
                "relative_rmse": fit.relative_rmse,
                "identified": list(fit.identified()),
                "stage_seconds": {s.name: round(s.seconds, 3) for s in fit.stages},
                "depth": list(fit.depth_notes),
            }
        )
        print(f"{name}: {sec:.2f} s, {sims} batched simulations, {fit.status}", file=sys.stderr)
    return rows


def _stream(cycles: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    T, Q, S = [], [], []
    t0 = 0.0
    p = mudrft.paper_parameters(0.25)
    for _ in range(cycles):
        tr = mudrft.plate_intrusion(depth=0.03, speed=0.02, hold=0.5, rest=0.3, dt=0.01)
        r = mudrft.plate_response(tr, p)
        T.append(tr.time[:-1] + t0)
        Q.append(r.displacement[:-1])
        S.append(r.stress[:-1])
        t0 += tr.time[-1]
    return np.concatenate(T), np.concatenate(Q), np.concatenate(S)


def bench_online(repeat: int, cycles: int) -> list[dict[str, Any]]:
    t, q, s = _stream(cycles)
    makers = {
        "OnlineEstimator(model='exact'), 25 tau_build filters": lambda: OnlineEstimator(
            mudrft.paper_parameters(0.25)
        ),
        "OnlineEstimator(model='paper'), 25 tau_build filters": lambda: OnlineEstimator(
            mudrft.paper_parameters(0.25), model="paper"
        ),
        "StreamClassifier, 3 candidate sets": StreamClassifier,
        "StreamClassifier, 21 candidate sets": lambda: StreamClassifier(
            water_contents=np.linspace(0.25, 0.45, 21)
        ),
    }
    rows = []
    for name, make in makers.items():

        def run(make: Callable[[], Any] = make) -> None:
            obj = make()
            for a, b, c in zip(t, q, s, strict=True):
                obj.update(a, b, c)

        sec, _ = _best(run, repeat)
        us = 1e6 * sec / t.size
        rows.append({"estimator": name, "samples": int(t.size), "us_per_sample": us})
        print(f"{name}: {us:.0f} us per sample", file=sys.stderr)
    return rows


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="one repeat, short streams")
    ap.add_argument("--json", default=None, help="write the results to this JSON file")
    args = ap.parse_args(argv)
    repeat = 1 if args.quick else 3
    res = {
        "machine": {
            "cpus": os.cpu_count(),
            "python": platform.python_version(),
            "numpy": np.__version__,
            "platform": platform.platform(),
        },
        "fits": bench_fits(repeat),
        "online": bench_online(repeat, 2 if args.quick else 5),
    }
    text = json.dumps(res, indent=2)
    if args.json:
        with open(args.json, "w", encoding="utf-8") as fh:
            fh.write(text + "\n")
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
