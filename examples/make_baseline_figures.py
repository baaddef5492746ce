"""
Mud against the baseline terrains
=================================

The same foot and motion on mud and on the terrains mudrft ships for comparison: granular
resistive force theory (sand), a linear stiffness, a Maxwell-type mud and rigid ground.
The linear stiffness and the Maxwell constants are re-derived from the W = 25 % plate
test first.

Run from the repository root: ``python examples/make_baseline_figures.py [--out DIR]``
(default ``docs/figures``). Writes

* ``baselines_s6.png``: Fig. S6-style plate test -- (a) normalised force against
  normalised depth for mud and sand (granular RFT), (b) stress against time and (c)
  against depth for the mud model, the Maxwell-type reconstruction and the linear model;
* ``baselines_gait.png``: Fig. S5-style forces over one gait cycle (flat foot, 0.2 m/s);
* ``baselines_rft_alpha.png``: Li et al.'s generic alpha_z, alpha_x maps;

and prints the re-derivation of the default linear stiffness and Maxwell constants.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import mudrft
from mudrft.baselines import (
    GranularRFT,
    LinearStiffness,
    MaxwellMud,
    compare,
    fit_maxwell,
    fit_stiffness,
    summarize,
)
from mudrft.baselines.plots import plot_gait, plot_s6
from mudrft.terrains.granular_rft import li2013_alpha


def log(msg: str) -> None:
    print(msg, file=sys.stderr)


def plot_rft_alpha(*, resolution: int = 121) -> Any:
    """Maps of Li et al.'s generic alpha_z and alpha_x over attack and intrusion angles."""
    b = np.linspace(-np.pi / 2, np.pi / 2, resolution)
    g = np.linspace(-np.pi / 2, np.pi / 2, resolution)
    B, G = np.meshgrid(b, g, indexing="xy")
    ax_, az = li2013_alpha(B, G)
    fig, ax = plt.subplots(1, 2, figsize=(10, 4.2), constrained_layout=True)
    lim = float(max(np.abs(az).max(), np.abs(ax_).max()))
    for a, val, name in ((ax[0], az, "alpha_z (lift)"), (ax[1], ax_, "alpha_x (drag)")):
        im = a.pcolormesh(
            np.degrees(B), np.degrees(G), val, cmap="RdBu_r", vmin=-lim, vmax=lim, shading="auto"
        )
        a.contour(np.degrees(B), np.degrees(G), val, levels=[0.0], colors="k", linewidths=0.8)
        a.set(
            xlabel="attack angle beta [deg]",
            ylabel="intrusion angle gamma [deg] (90 = down)",
            title=f"generic {name} [-] (Li et al. 2013)",
        )
        fig.colorbar(im, ax=a)
    return fig


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(
        description="Figures of the baselines (docs/figures/baselines_*.png)."
    )
    ap.add_argument("--out", default=None, help="output folder (default docs/figures)")
    ap.add_argument(
        "--quick", action="store_true", help="accepted for the docs build (already quick)"
    )
    args = ap.parse_args([] if argv is None else argv)  # None: the defaults
    OUT = Path(args.out) if args.out else Path(__file__).resolve().parents[1] / "docs" / "figures"
    OUT.mkdir(parents=True, exist_ok=True)

    log("1/4 re-deriving the defaults from the W = 25 % plate test")
    tr = mudrft.plate_intrusion()
    ref = mudrft.plate_response(tr, mudrft.paper_mud(0.25))
    load = tr.velocity[:, 2] < 0
    k = fit_stiffness(ref.displacement[load], ref.stress[load])
    log(f"    linear stiffness k = {k:.4g} N/m^3")
    fit = fit_maxwell(tr, ref.stress)
    m = fit.model
    log(
        f"    Maxwell: G = {m.modulus:.4g} Pa, lambda_M = {m.relaxation:.4g} s, "
        f"sigma_Y = {m.sigma_y:.4g} Pa, omega_s = {m.omega:.4g} rad/s, r_b = {m.release:.4g}; "
        f"rmse {fit.rmse:.4g} Pa ({fit.message})"
    )

    log("2/4 Fig. S6-style plate test (50 x 50 mm plate, L_c = 50 mm, 40 mm high)")
    plate = mudrft.feet.Flat(length=0.05, width=0.05, height=0.04)
    runs = compare(
        plate,
        tr,
        {
            "mud": mudrft.terrains.Mud(0.25),
            "granular-rft": GranularRFT(),
            "maxwell": MaxwellMud(),
            "linear": LinearStiffness(),
        },
    )
    fig = plot_s6(runs)
    fig.savefig(OUT / "baselines_s6.png", dpi=110)
    plt.close(fig)
    for r in summarize(runs):
        log(
            "    "
            + ", ".join(f"{k} {v:.4g}" if isinstance(v, float) else str(v) for k, v in r.items())
        )

    log("3/4 Fig. S5-style gait cycle (flat foot, 0.2 m/s)")
    foot = mudrft.feet.Flat()
    g = compare(
        foot,
        mudrft.gait(0.2),
        {
            "mud": mudrft.terrains.Mud(0.25),
            "granular-rft": GranularRFT(),
            "maxwell": MaxwellMud(),
            "linear": LinearStiffness(),
        },
    )
    fig = plot_gait(
        g, title="flat foot (80 x 65 mm), one gait cycle at 0.2 m/s (prescribed motion)"
    )
    fig.savefig(OUT / "baselines_gait.png", dpi=110)
    plt.close(fig)

    log("4/4 generic RFT coefficients")
    fig = plot_rft_alpha()
    fig.savefig(OUT / "baselines_rft_alpha.png", dpi=110)
    plt.close(fig)
    print("wrote baselines_s6.png, baselines_gait.png, baselines_rft_alpha.png")


if __name__ == "__main__":
    main(sys.argv[1:])
