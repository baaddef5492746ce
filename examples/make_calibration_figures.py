"""
Calibrating the model to a mud
==============================

Fit the model to intrusion logs, check that the reported uncertainties are honest, and
follow a mud whose water content changes, online. All data here are SYNTHETIC: generated
by mudrft's own model plus noise.

Run ``python examples/make_calibration_figures.py [--out docs/figures] [--seeds 20]
[--data] [--quick]`` (``--quick``: 3 seeds, for the docs build).

* ``calibration_fit.png``: fit of the shipped example log (vertical, W = 25 %) against
  its data, and the correlation matrix of the fitted log-parameters;
* ``calibration_coverage.png``: coverage study: for many noise seeds of logs as a lab
  records them (:func:`lab_logs`), the error of each fitted parameter divided by its
  robust standard error, and how often the truth lies in the robust interval;
* ``calibration_online.png``: a stream whose water content steps from 25 % to 35 %:
  classifier probabilities and online estimates.

``--data`` also regenerates the example CSV files in src/mudrft/data (overwriting them).
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import mudrft
from mudrft.calibration import (
    OnlineEstimator,
    StreamClassifier,
    calibrate,
    example_dataset,
    synthetic_dataset,
)
from mudrft.calibration.synthetic import write_example_files

VERDICT = {"identified": "ident.", "weak": "weak", "not identified": "not id.", "fixed": "fixed"}


def fig_fit(out: Path) -> None:
    ds = example_dataset("vertical")
    fit = calibrate(ds, progress=lambda s: print(s, file=sys.stderr))
    print(fit.summary())
    fig = plt.figure(figsize=(13.5, 3.6), constrained_layout=True)
    gs = fig.add_gridspec(1, 4, width_ratios=[1, 1, 1, 1.05])
    axes = [fig.add_subplot(gs[0, j]) for j in range(3)]
    fit.plot(axes=np.array(axes))
    ax = fig.add_subplot(gs[0, 3])
    im = ax.imshow(fit.correlation, vmin=-1, vmax=1, cmap="RdBu_r")
    names = [
        {
            "gamma_dot_c": "gdc",
            "tau_build": "tau_b",
            "tau_leak": "tau_l",
            "epsilon": "eps",
            "sigma_y": "sig_Y",
        }.get(k, k)
        for k in fit.free
    ]
    ax.set_xticks(range(len(names)), names, rotation=90, fontsize=7)
    ax.set_yticks(
        range(len(names)),
        [f"{n} ({VERDICT[fit.identifiability[k]]})" for n, k in zip(names, fit.free, strict=True)],
        fontsize=7,
    )
    ax.set_title("correlation of ln(parameters)", fontsize=9)
    fig.colorbar(im, ax=ax, shrink=0.8)
    fig.suptitle(
        "SYNTHETIC example log (vertical, W = 25 %, 1 % noise): fit against data; "
        f"relative RMSE {100 * fit.relative_rmse:.2f} %",
        fontsize=10,
    )
    fig.savefig(out / "calibration_fit.png", dpi=110)
    plt.close(fig)


def lab_logs(true: mudrft.MudParameters, seed: int) -> mudrft.calibration.IntrusionDataset:
    """Three tests as a lab logs them: a 40 x 40 mm plate resting 5 mm above the mud (the
    tare), the approach, 30 mm deep at 10, 20 and 40 mm/s, a 1 s hold, out of the mud again;
    0.02 mm of depth noise and 0.3 N of force noise, at 100 Hz."""
    return synthetic_dataset(
        true,
        noise=0.0,
        seed=seed,
        hold=1.0,
        dt=0.01,
        characteristic_length=0.04,
        approach=0.005,
        tare=0.2,
        rest=0.2,
        depth_noise=2e-5,
        stress_noise=0.3 / 0.04**2,
    )


def fig_coverage(out: Path, seeds: int) -> None:
    true = mudrft.paper_parameters(0.25, "vertical")
    zs, inside, noise_inside, names = [], [], [], None
    for sd in range(seeds):
        fit = calibrate(lab_logs(true, 1000 + sd))
        names = fit.free
        zs.append(
            [
                math.log(getattr(fit.parameters, k) / getattr(true, k))
                / fit.robust_standard_error[k]
                for k in fit.free
            ]
        )
        truth = {k: getattr(true, k) for k in fit.free}
        inside.append(
            [fit.robust_interval[k][0] <= v <= fit.robust_interval[k][1] for k, v in truth.items()]
        )
        noise_inside.append(
            [
                fit.confidence_interval[k][0] <= v <= fit.confidence_interval[k][1]
                for k, v in truth.items()
            ]
        )
        print(
            f"coverage seed {sd}: relative RMSE {fit.relative_rmse:.4f}, identified "
            f"{list(fit.identified())}",
            file=sys.stderr,
        )
    z = np.array(zs)
    cover, cover_noise = np.mean(inside, axis=0), np.mean(noise_inside, axis=0)
    print("truth within the robust intervals:", dict(zip(names, np.round(cover, 2), strict=True)))
    print(
        "truth within the noise intervals:", dict(zip(names, np.round(cover_noise, 2), strict=True))
    )
    fig, ax = plt.subplots(figsize=(8, 3.4), constrained_layout=True)
    rng = np.random.default_rng(0)
    for j in range(z.shape[1]):
        ax.plot(
            j + 0.15 * rng.standard_normal(z.shape[0]), z[:, j], "o", ms=3, alpha=0.7, color="C0"
        )
        ax.text(j, 3.6, f"{100 * cover[j]:.0f} %", ha="center", fontsize=7)
    ax.axhspan(-1.96, 1.96, color="0.9", zorder=0)
    ax.set_xticks(range(len(names)), names, rotation=30, fontsize=8)
    ax.set_ylim(-4.2, 4.2)
    ax.set_ylabel("(ln p_fit - ln p_true) / robust se")
    ax.set_title(
        f"SYNTHETIC coverage study: {seeds} lab logs (vertical W = 25 %, approach, "
        "tare, 0.02 mm and 0.3 N of noise)\ngrey band: 1.96 errors; numbers: share "
        "of seeds whose truth lies in the robust 95 % interval",
        fontsize=9,
    )
    fig.savefig(out / "calibration_coverage.png", dpi=110)
    plt.close(fig)


def fig_online(out: Path) -> None:
    p25, p35 = mudrft.paper_parameters(0.25), mudrft.paper_parameters(0.35)
    rng = np.random.default_rng(5)
    T, Q, S = [], [], []
    t0 = 0.0
    for p in (p25,) * 3 + (p35,) * 3:
        tr = mudrft.plate_intrusion(depth=0.03, speed=0.02, hold=0.5, rest=0.3, dt=0.01)
        r = mudrft.plate_response(tr, p)
        T.append(tr.time[:-1] + t0)
        Q.append(r.displacement[:-1])
        S.append(r.stress[:-1])
        t0 += tr.time[-1]
    t, q, s = np.concatenate(T), np.concatenate(Q), np.concatenate(S)
    s = s + rng.normal(0.0, 0.01 * np.ptp(s), s.size)
    t_step = T[3][0]
    clf = StreamClassifier()
    exact = OnlineEstimator(p25, forgetting=0.999)
    paper = OnlineEstimator(p25, model="paper", forgetting=0.99)
    prob, ex, pa = [], [], []
    for a, b, c in zip(t, q, s, strict=True):
        clf.update(a, b, c)
        prob.append(clf.probabilities.copy())
        ex.append(exact.update(a, b, c))
        pa.append(paper.update(a, b, c))
        if b <= 0 and clf.best != exact.prior.water_content:
            exact.rebase(mudrft.paper_parameters(clf.best))
    prob = np.array(prob)

    def series(hist: list, key: str) -> np.ndarray:
        return np.array([np.nan if getattr(e, key) is None else getattr(e, key) for e in hist])

    fig, axs = plt.subplots(4, 1, figsize=(8, 8.2), sharex=True, constrained_layout=True)
    axs[0].plot(t, s / 1e3, "0.4", lw=0.6)
    axs[0].set_ylabel("stress [kPa]")
    axs[0].set_title(
        "SYNTHETIC stream: 3 plate cycles at W = 25 %, then 3 at W = 35 % (1 % noise, 100 Hz)",
        fontsize=9,
    )
    for j, lab in enumerate(clf.labels):
        axs[1].plot(t, prob[:, j], label=f"W = {100 * lab:g} %")
    axs[1].set_ylabel("classifier\nprobability")
    axs[1].legend(fontsize=8, loc="center left")
    for ax, key, unit, scale in ((axs[2], "alpha", "kPa", 1e3), (axs[3], "sigma_y", "kPa", 1e3)):
        ax.plot(t, series(ex, key) / scale, "C3", lw=1.2, label="exact regressors (rebased)")
        ax.plot(t, series(pa, key) / scale, "C0", lw=1.0, label="paper's approximation")
        for p, (a0, a1) in ((p25, (t[0], t_step)), (p35, (t_step, t[-1]))):
            ax.hlines(getattr(p, key) / scale, a0, a1, colors="k", linestyles="--", lw=0.8)
        ax.set_ylabel(f"{key} [{unit}]")
        ax.set_ylim(0, 2.2 * max(getattr(p25, key), getattr(p35, key)) / scale)
    axs[2].legend(fontsize=8, loc="upper right")
    axs[3].set_xlabel("time [s]")
    for ax in axs:
        ax.axvline(t_step, color="0.5", lw=0.8, ls=":")
    fig.savefig(out / "calibration_online.png", dpi=110)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(
        description="Figures of calibration (docs/figures/calibration_*.png)."
    )
    ap.add_argument("--out", default=None, help="output folder (default docs/figures)")
    ap.add_argument("--seeds", type=int, default=20)
    ap.add_argument("--data", action="store_true", help="regenerate src/mudrft/data/*.csv")
    ap.add_argument("--quick", action="store_true", help="3 seeds (the docs build)")
    args = ap.parse_args([] if argv is None else argv)  # None: the defaults
    root = Path(__file__).resolve().parents[1] if not args.out or args.data else None
    out = Path(args.out) if args.out else root / "docs" / "figures"
    out.mkdir(parents=True, exist_ok=True)
    if args.data:
        print(write_example_files(root / "src" / "mudrft" / "data", overwrite=True))
    fig_fit(out)
    fig_online(out)
    fig_coverage(out, 3 if args.quick else args.seeds)
    return 0


if __name__ == "__main__":
    main(sys.argv[1:])
