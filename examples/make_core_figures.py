"""
The plate test and the water content
====================================

The constitutive model alone (Sec. II-B of the paper), on the paper's plate protocol at
W = 25 %: intrude at 20 mm/s to 30 mm, hold 1 s, retract at the same speed, vertically and
horizontally; then the vertical plate test across water contents, the paper's rows and the
interpolated ones between them.

* ``core_plate_test.png``: stress against time and depth, with its parts (elastic,
  thixotropic, suction);
* ``core_water_content.png``: the vertical plate test for W = 25 % ... 45 %.

Run from the repository root: ``python examples/make_core_figures.py [--out DIR]``
(default ``docs/figures``).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

import mudrft


def plate_figure(out: Path) -> Path:
    mud = mudrft.paper_mud(0.25)
    fig, axes = plt.subplots(2, 2, figsize=(10, 6.4), constrained_layout=True)
    for row, direction in enumerate(("vertical", "horizontal")):
        tr = mudrft.plate_intrusion(depth=0.03, speed=0.02, hold=1.0, direction=direction)
        res = mudrft.plate_response(tr, mud)
        res.plot(ax=axes[row])
        axes[row, 0].set_title(
            f"{direction} plate test, W = 25 %, 20 mm/s, hold 1 s (L_c = 50 mm)", fontsize=9
        )
        t_r = tr.meta["t_retract"]
        axes[row, 0].axvspan(t_r - tr.meta["hold"], t_r, color="0.92", zorder=0)
    p = out / "core_plate_test.png"
    fig.savefig(p, dpi=120)
    plt.close(fig)
    return p


def water_content_figure(out: Path) -> Path:
    fig, ax = plt.subplots(figsize=(5.5, 3.6), constrained_layout=True)
    tr = mudrft.plate_intrusion(depth=0.03, speed=0.02, hold=1.0)
    for w in (0.25, 0.30, 0.35, 0.40, 0.45):
        res = mudrft.plate_response(tr, mudrft.paper_parameters(w, "vertical"))
        ax.plot(
            res.time,
            res.stress / 1e3,
            label=f"W = {w * 100:g} %" + ("" if w in (0.25, 0.35, 0.45) else " (interp.)"),
        )
    ax.axhline(0, color="0.7", lw=0.6)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("vertical stress [kPa]")
    ax.legend(fontsize=8)
    ax.set_title("Vertical plate test across water contents", fontsize=9)
    p = out / "core_water_content.png"
    fig.savefig(p, dpi=120)
    plt.close(fig)
    return p


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description="Figures of the plate test (docs/figures/core_*.png).")
    ap.add_argument("--out", default=None, help="output folder (default docs/figures)")
    ap.add_argument(
        "--quick", action="store_true", help="accepted for the docs build (already quick)"
    )
    args = ap.parse_args([] if argv is None else argv)  # None: the defaults
    out = Path(args.out) if args.out else Path(__file__).resolve().parents[1] / "docs" / "figures"
    out.mkdir(parents=True, exist_ok=True)
    for path in (plate_figure(out), water_content_figure(out)):
        print("wrote", path.name)
    return 0


if __name__ == "__main__":
    main(sys.argv[1:])
