"""Figures of ``mudrft reproduce``: the paper's Figs. 9, 10, 12, 13, and the verdicts
against the stance depth."""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from ..plotting import require_matplotlib
from .claims import Cell, medium_speed

if TYPE_CHECKING:
    from ..simulation import Result

COLORS = {
    "flat": "tab:blue",
    "semi-cylinder": "tab:orange",
    "semi-sphere": "tab:green",
    "morphing": "tab:red",
}


def _save(plt: Any, fig: Any, path: Path) -> Path:
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def make_figures(
    out: Path,
    runs: Callable[[str, float, float], Result],
    rows: list[dict[str, Any]],
    *,
    feet: list[str],
    speeds: list[float],
    water_contents: list[float],
    by_depth: dict[float, list[Cell]] | None = None,
) -> list[Path]:
    """Write the PNG figures of the headline's ``runs(foot, speed, row)`` to ``out``; their
    paths (the depth figure where ``by_depth``, depth [m] -> the headline's cells, is given)."""
    plt = require_matplotlib()
    v, w = medium_speed(speeds), min(water_contents, key=lambda x: abs(x - 0.25))
    paths = []

    # Fig. 9: forces against time for the fixed feet at medium speed, W = 25 %
    fixed = [f for f in feet if f != "morphing"]
    n = max(len(fixed), 1)
    fig, axes = plt.subplots(n, 3, figsize=(10, 2.4 * n), squeeze=False, constrained_layout=True)
    for i, f in enumerate(fixed):
        r = runs(f, v, w)
        for j, lab in enumerate(("$F_x$", "$F_y$", "$F_z$")):
            ax = axes[i, j]
            ax.plot(r.time, r.force[:, j], color=COLORS.get(f, "k"))
            ax.axhline(0, color="0.75", lw=0.6)
            ax.set_ylabel(f"{lab} [N]")
            if i == 0:
                ax.set_title(lab)
            if i == len(fixed) - 1:
                ax.set_xlabel("time [s]")
        axes[i, 0].annotate(f, (0.02, 0.85), xycoords="axes fraction", fontsize=9)
    fig.suptitle(
        f"Forces over one stepping cycle, {v:g} m/s, W = {w * 100:g} % (cf. paper Fig. 9)",
        fontsize=10,
    )
    paths.append(_save(plt, fig, out / "fig09_forces.png"))

    # Fig. 10: normalized vertical stress over the gait phase: feet, speeds, water contents
    fig, axes = plt.subplots(1, 3, figsize=(12, 3.3), constrained_layout=True)
    ref = "flat" if "flat" in feet else feet[0]
    panels: dict[str, list[tuple[tuple[str, float, float], str, str | None]]] = {
        "(a) foot shape": [((f, v, w), f, COLORS.get(f)) for f in fixed],
        f"(b) speed ({ref})": [((ref, s, w), f"{s:g} m/s", None) for s in speeds],
        f"(c) water content ({ref})": [
            ((ref, v, wc), f"W = {wc * 100:g} %", None) for wc in water_contents
        ],
    }
    for ax, (title, lines) in zip(axes, panels.items(), strict=True):
        for key, label, color in lines:
            r = runs(*key)
            ax.plot(
                r.time / r.time[-1], r.normalized_stress()[:, 2] / 1e3, color=color, label=label
            )
        ax.set_title(title)
        ax.axhline(0, color="0.75", lw=0.6)
        ax.set_xlabel("gait phase [-]")
        ax.legend(fontsize=8)
    axes[0].set_ylabel(r"$F_z/A_z$ [kPa]")
    fig.suptitle(
        f"Normalized vertical stress over one stepping cycle, {v:g} m/s, W = {w * 100:g} % "
        "unless varied (cf. paper Fig. 10)",
        fontsize=10,
    )
    paths.append(_save(plt, fig, out / "fig10_normalized.png"))

    # Fig. 12: vertical stress against depth (hysteresis) for every foot
    fig, ax = plt.subplots(figsize=(5, 3.6), constrained_layout=True)
    for f in feet:
        r = runs(f, v, w)
        ax.plot(r.depth * 1e3, r.normalized_stress()[:, 2] / 1e3, color=COLORS.get(f, "k"), label=f)
    ax.axhline(0, color="0.75", lw=0.6)
    ax.set_xlabel("tip depth [mm]")
    ax.set_ylabel(r"$\sigma_z=F_z/A_z$ [kPa]")
    ax.set_title(
        f"Vertical stress vs depth, {v:g} m/s, W = {w * 100:g} % (cf. paper Fig. 12)", fontsize=10
    )
    ax.legend(fontsize=8)
    paths.append(_save(plt, fig, out / "fig12_hysteresis.png"))

    # Fig. 13: suction and energy bars, and a spider chart
    sel = {
        r["foot"]: r
        for r in rows
        if abs(r["speed [m/s]"] - v) < 1e-9 and abs(r["water_content"] - w) < 1e-9
    }
    names = [f for f in feet if f in sel]
    fig = plt.figure(figsize=(10, 3.8), constrained_layout=True)
    ax1 = fig.add_subplot(1, 2, 1)
    x = np.arange(len(names))
    ax1.bar(
        x - 0.2,
        [sel[f]["max_suction [N]"] for f in names],
        0.4,
        label="max suction [N]",
        color=[COLORS.get(f, "k") for f in names],
    )
    ax2 = ax1.twinx()
    ax2.bar(x + 0.2, [sel[f]["energy [J]"] for f in names], 0.4, label="energy [J]", color="0.6")
    ax1.set_xticks(x, names, fontsize=8)
    ax1.set_ylabel("max suction [N] (colour)")
    ax2.set_ylabel("energy [J] (grey)")
    ax1.set_title("(a) suction and energy (cf. Fig. 13a)", fontsize=10)
    keys = [*(f"impulse_{a} [N s]" for a in "xyz"), "max_suction [N]", "energy [J]"]
    labels = ["impulse |I_x|", "impulse |I_y|", "impulse |I_z|", "max suction", "energy"]
    ang = np.linspace(0, 2 * np.pi, len(keys), endpoint=False)
    ax3 = fig.add_subplot(1, 2, 2, projection="polar")
    mx = {k: max(abs(sel[f][k]) for f in names) or 1.0 for k in keys}
    for f in names:
        vals = [abs(sel[f][k]) / mx[k] for k in keys]
        ax3.plot(np.append(ang, ang[0]), vals + vals[:1], color=COLORS.get(f, "k"), label=f)
    ax3.set_xticks(ang, labels, fontsize=8)
    ax3.set_rlabel_position(110)  # between the spokes, clear of their labels
    ax3.set_title("(b) normalized by the largest foot (cf. Fig. 13b)", fontsize=10)
    ax3.legend(fontsize=7, loc="lower right", bbox_to_anchor=(1.35, -0.1))
    fig.suptitle(f"One stepping cycle, {v:g} m/s, W = {w * 100:g} %", fontsize=10)
    paths.append(_save(plt, fig, out / "fig13_suction_energy.png"))
    if by_depth:
        paths.append(_depth_figure(plt, out / "fig_depth_verdicts.png", by_depth, v, w))
    return paths


#: Colour of each verdict in the depth figure.
VERDICT_COLORS = {
    "agrees": "tab:green",
    "partly": "gold",
    "differs": "tab:red",
    "not evaluated": "0.85",
}


def _depth_figure(
    plt: Any, path: Path, by_depth: dict[float, list[Cell]], speed: float, water: float
) -> Path:
    """The headline's verdicts (claims x stance depths) and their count against the depth."""
    from matplotlib.colors import ListedColormap
    from matplotlib.patches import Patch
    from matplotlib.ticker import MaxNLocator

    depths = sorted(by_depth)
    claims = [c.claim for c in by_depth[depths[0]]]
    names = list(VERDICT_COLORS)
    grid = np.array([[names.index(c.verdict) for c in by_depth[d]] for d in depths]).T
    mm = np.array(depths) * 1e3
    agree = [sum(c.verdict == "agrees" for c in by_depth[d]) for d in depths]
    fig, (top, ax) = plt.subplots(
        2,
        1,
        figsize=(8, 5.2),
        sharex=True,
        gridspec_kw={"height_ratios": [1, 3]},
        constrained_layout=True,
    )
    top.step(mm, agree, where="mid", color="k")
    top.set_ylabel("claims\nreproduced")
    top.set_ylim(min(agree) - 1.5, max(agree) + 1.5)
    top.yaxis.set_major_locator(MaxNLocator(integer=True))
    step = float(np.diff(mm).min()) if len(mm) > 1 else 1.0
    ax.imshow(
        grid,
        aspect="auto",
        cmap=ListedColormap(list(VERDICT_COLORS.values())),
        vmin=-0.5,
        vmax=len(names) - 0.5,
        extent=(mm[0] - step / 2, mm[-1] + step / 2, len(claims) - 0.5, -0.5),
        interpolation="nearest",
    )
    ax.set_yticks(range(len(claims)), claims, fontsize=8)
    ax.set_xlabel("stance depth of the gait [mm] (the fixed feet are 26 mm tall)")
    ax.legend(
        handles=[Patch(color=c, label=n) for n, c in VERDICT_COLORS.items()],
        fontsize=7,
        loc="upper left",
        bbox_to_anchor=(1.0, 1.0),
    )
    fig.suptitle(
        f"The claims of the headline reading against the stance depth, {speed:g} m/s, "
        f"W = {water * 100:g} %",
        fontsize=10,
    )
    return _save(plt, fig, path)
