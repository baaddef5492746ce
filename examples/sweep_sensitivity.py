"""
Which mud parameter moves suction most: a sensitivity study on a sweep
======================================================================

Which parameter of the mud moves suction most? A sensitivity study on top of a sweep.

A Latin hypercube sample (seeded) of factors on six mud parameters, each between half and
twice the paper's value at W = 25 % (log-uniform), for the semi-cylindrical foot at the
medium gait; every point's largest suction is computed (in this process, or on a local
Dask cluster with ``--workers``), and the parameters are ranked by Spearman's rank
correlation with it
(:func:`mudrft.sweep.sensitivity`). The figure shows the ranking and the suction against
the two leading factors.

Run ``python examples/sweep_sensitivity.py [--n 64] [--workers 2] [--serial]
[--store S.zarr] [--out docs/figures/sweep_sensitivity.png]`` (needs ``mudrft[sweep,plot]``).
``--out`` is the figure's path, or a folder to write ``sweep_sensitivity.png`` into;
``--quick`` (the documentation build) samples 16 points.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

import mudrft

#: The mud parameters whose factors are sampled (both directions' values are scaled).
FACTORS = ("sigma_y", "tau_build", "tau_leak", "epsilon", "eta_m", "alpha")


def spec(n: int = 64, seed: int = 0) -> dict[str, Any]:
    """The sweep: a Latin hypercube over the factors, max suction at every point."""
    return {
        "sweep": {"design": "lhs", "n": n, "seed": seed, "metrics": ["max_suction"]},
        "foot": {"kind": "semi-cylinder"},
        "mud": {
            "water_content": 0.25,
            **{f"{k}_scale": {"low": 0.5, "high": 2.0, "log": True} for k in FACTORS},
        },
        "motion": {"kind": "gait", "speed": 0.2},
    }


def figure(ds: Any, ranked: list[tuple[str, float]], path: Path) -> None:
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 3, figsize=(12, 3.6), layout="constrained")
    names = [n.removesuffix("_scale") for n, _ in ranked]
    axes[0].barh(names[::-1], [v for _, v in ranked][::-1], color="tab:blue")
    axes[0].axvline(0, color="k", lw=0.8)
    axes[0].set_xlabel("Spearman rank correlation with max suction")
    axes[0].set_title(f"{ds.sizes['point']} points, Latin hypercube")
    for ax, (name, rho) in zip(axes[1:], ranked[:2], strict=False):
        ax.scatter(ds[name], ds["max_suction"], s=12)
        ax.set_xscale("log")
        ax.set_xlabel(f"{name} (factor on the paper's value)")
        ax.set_ylabel("max suction [N]")
        ax.set_title(f"rho = {rho:+.2f}")
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv: list[str] | None = None) -> list[tuple[str, float]]:
    ap = argparse.ArgumentParser(description="Which parameter of the mud moves suction most.")
    ap.add_argument("--n", type=int, default=64, help="sample size")
    ap.add_argument("--workers", type=int, default=None, help="run on a local Dask cluster")
    ap.add_argument("--serial", action="store_true", help="never start a Dask cluster")
    ap.add_argument("--store", help="a .zarr store to write (and --resume from)")
    ap.add_argument("--out", help="write the figure here (a PNG path, or a folder)")
    ap.add_argument("--quick", action="store_true", help="16 points, serial (docs build)")
    args = ap.parse_args(argv)
    if args.quick:
        args.n, args.serial = 16, True
    ds = mudrft.sweep(
        spec(args.n),
        store=args.store,
        resume=bool(args.store),
        scheduler="serial" if args.serial else None,
        workers=None if args.serial else args.workers,
        progress=True,
    )
    ranked = mudrft.sweep.sensitivity(ds, "max_suction")
    print("parameter     Spearman rho with max suction")
    for name, rho in ranked:
        print(f"{name.removesuffix('_scale'):12s}  {rho:+.2f}")
    if args.out:
        out = Path(args.out)
        if out.suffix.lower() != ".png":  # a folder
            out.mkdir(parents=True, exist_ok=True)
            out = out / "sweep_sensitivity.png"
        figure(ds, ranked, out)
        print(f"wrote {out}")
    return ranked


if __name__ == "__main__":
    main()
