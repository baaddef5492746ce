"""
Closed forms and meshes of the paper's feet
===========================================

The resultant force of the flat, semi-cylindrical and semi-spherical feet for a uniform
10 kPa stress in each channel: the closed forms of eqs. (12)-(14) as mudrft implements
them (errata E20-E23 corrected), the printed finals beside them, and the surface integral
of eqs. (6)-(7) over a triangle mesh of each foot, which converges to the closed form.

Run from the repository root: ``python examples/make_feet_figures.py [--out docs/figures]``:

* ``feet_fz_depth.png``: F_z against depth for the three feet, closed form and mesh,
  with the printed (erroneous) finals of eqs. (13)-(14) for comparison;
* ``feet_fxy_heading.png``: F_x, F_y against the heading in every quadrant;
* ``feet_convergence.png``: mesh error against resolution (second order);
* ``feet_meshes.png``: the generated meshes.
"""

from __future__ import annotations

import argparse
import math
import os
import sys

import numpy as np

from mudrft.feet import Flat, SemiCylinder, SemiSphere
from mudrft.feet.closed_form import printed_semicylinder_fz, printed_semisphere_fz

SIGMA = 10e3  # a uniform 10 kPa channel stress [Pa] (order of the paper's alpha)
FEET = (Flat(), SemiCylinder(), SemiSphere())
COLORS = {"flat": "tab:blue", "semi-cylinder": "tab:orange", "semi-sphere": "tab:green"}


def fz_depth(plt, out: str) -> str:
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    d = np.linspace(0.0, 0.04, 161)
    dm = np.linspace(0.0025, 0.04, 16)
    for foot in FEET:
        c = COLORS[foot.name]
        ax.plot(
            d * 1e3,
            foot.resultant(d, [0, 0, SIGMA], 0.0)[:, 2],
            color=c,
            label=f"{foot.name}: closed form",
        )
        mesh = foot.to_mesh(resolution=24)
        ax.plot(
            dm * 1e3,
            mesh.resultant(dm, [0, 0, SIGMA], 0.0)[:, 2],
            "o",
            color=c,
            ms=4,
            mfc="none",
            label=f"{foot.name}: mesh ({len(mesh):,} facets)",
        )
    dp = np.linspace(1e-4, 0.026, 80)
    cyl, sph = FEET[1], FEET[2]
    ax.plot(
        dp * 1e3,
        printed_semicylinder_fz(dp, SIGMA, radius=cyl.radius, width=cyl.width),
        "--",
        color=COLORS["semi-cylinder"],
        lw=1,
        label="semi-cylinder: printed eq. (13c) (E20)",
    )
    ax.plot(
        dp * 1e3,
        printed_semisphere_fz(dp, SIGMA, radius=sph.radius),
        "--",
        color=COLORS["semi-sphere"],
        lw=1,
        label="semi-sphere: printed eq. (14b) (E21)",
    )
    ax.axvline(26, color="0.6", lw=0.8, ls=":")
    ax.text(26.5, 44, "foot height 26 mm:\nburied beyond (D26)", fontsize=7, color="0.4")
    ax.set(
        xlabel="tip depth z [mm]",
        ylabel=r"$F_z$ [N]",
        title=r"Vertical force, uniform $\sigma_z$ = 10 kPa (paper dimensions)",
    )
    ax.legend(fontsize=7, loc="lower right")
    ax.grid(alpha=0.3)
    path = os.path.join(out, "feet_fz_depth.png")
    fig.tight_layout()
    fig.savefig(path, dpi=150)
    plt.close(fig)
    return path


def fxy_heading(plt, out: str) -> str:
    fig, axes = plt.subplots(1, 3, figsize=(11, 3.6), sharey=True)
    h = np.linspace(-math.pi, math.pi, 361)
    hm = np.linspace(-math.pi, math.pi, 25)
    depth = 0.02

    def stress(hh: np.ndarray) -> np.ndarray:  # resisting channels: sign of the motion
        sx = np.where(np.cos(hh) < 0, -SIGMA, SIGMA)
        sy = np.where(np.sin(hh) < 0, -SIGMA, SIGMA)
        return np.stack([sx, sy, np.zeros_like(hh)], -1)

    for ax, foot in zip(axes, FEET, strict=True):
        f = foot.force(depth, stress(h), h)
        mesh = foot.to_mesh(resolution=24)
        fm = mesh.force(depth, stress(hm), hm)
        ax.plot(np.degrees(h), f[:, 0], color="tab:red", label=r"$F_x$ closed form")
        ax.plot(np.degrees(h), f[:, 1], color="tab:purple", label=r"$F_y$ closed form")
        ax.plot(
            np.degrees(hm), fm[:, 0], "o", color="tab:red", mfc="none", ms=4, label=r"$F_x$ mesh"
        )
        ax.plot(
            np.degrees(hm), fm[:, 1], "s", color="tab:purple", mfc="none", ms=4, label=r"$F_y$ mesh"
        )
        ax.set(title=f"{foot.name}, z = 20 mm", xlabel="heading of the motion [deg]")
        ax.set_xticks([-180, -90, 0, 90, 180])
        ax.axhline(0, color="0.5", lw=0.6)
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("force of the mud on the foot [N]")
    axes[0].legend(fontsize=7)
    fig.suptitle(
        r"Horizontal forces oppose the motion in every quadrant ($|\sigma_x|=|\sigma_y|$"
        " = 10 kPa)",
        fontsize=10,
    )
    path = os.path.join(out, "feet_fxy_heading.png")
    fig.tight_layout()
    fig.savefig(path, dpi=150)
    plt.close(fig)
    return path


def convergence(plt, out: str) -> str:
    fig, ax = plt.subplots(figsize=(5.6, 4.0))
    levels = np.array([4, 8, 16, 32, 64])
    s = np.array([SIGMA, SIGMA, SIGMA])
    for foot, mk in ((FEET[1], "o"), (FEET[2], "s")):
        for depth, ls in ((foot.height, "-"), (0.0113, ":")):
            ref = foot.resultant(depth, s, 0.4)
            err = np.array(
                [
                    np.abs(foot.to_mesh(resolution=n).resultant(depth, s, 0.4) - ref) / np.abs(ref)
                    for n in levels
                ]
            )
            for k, comp in enumerate(("x", "z")):
                kk = 0 if comp == "x" else 2
                ax.loglog(
                    levels,
                    err[:, kk],
                    mk + ls,
                    ms=4,
                    color=COLORS[foot.name],
                    alpha=1.0 if k else 0.55,
                    label=f"{foot.name} $F_{comp}$, z = {depth * 1e3:.1f} mm",
                )
    ax.loglog(levels, 0.5 * (levels / 4.0) ** -2, "k--", lw=1, label="slope -2")
    ax.set(
        xlabel="resolution (segments from tip to rim)",
        ylabel="relative error vs closed form",
        title="Mesh integration converges at second order",
    )
    ax.set_xticks(levels, [str(n) for n in levels])
    ax.minorticks_off()
    ax.legend(fontsize=6.5, ncol=1)
    ax.grid(alpha=0.3, which="both")
    path = os.path.join(out, "feet_convergence.png")
    fig.tight_layout()
    fig.savefig(path, dpi=150)
    plt.close(fig)
    return path


def meshes(plt, out: str) -> str:
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    fig = plt.figure(figsize=(10, 3.4))
    for i, (foot, res) in enumerate(zip(FEET, (2, 6, 6), strict=True)):
        ax = fig.add_subplot(1, 3, i + 1, projection="3d")
        m = foot.to_mesh(resolution=res)
        tri = m.triangles * 1e3
        shade = 0.35 + 0.55 * np.clip(m.elements().normals @ np.array([0.3, -0.5, 0.8]), 0, 1)
        ax.add_collection3d(
            Poly3DCollection(tri, facecolors=plt.cm.Greys(shade), edgecolor="k", linewidths=0.2)
        )
        lim = np.abs(tri[..., :2]).max()
        ax.set_box_aspect((1, 1, 26 / lim))
        ax.set(
            xlim=(-lim, lim),
            ylim=(-lim, lim),
            zlim=(0, 26),
            xlabel="x [mm]",
            ylabel="y [mm]",
            zlabel="z [mm]",
            title=f"{foot.name}: {len(m)} facets",
        )
        ax.view_init(elev=-25, azim=-55)
        ax.tick_params(labelsize=6)
    path = os.path.join(out, "feet_meshes.png")
    fig.tight_layout()
    fig.savefig(path, dpi=150)
    plt.close(fig)
    return path


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description="Figures of the feet (docs/figures/feet_*.png).")
    ap.add_argument("--out", default=os.path.join("docs", "figures"), help="output folder")
    ap.add_argument(
        "--quick", action="store_true", help="accepted for the docs build (already quick)"
    )
    args = ap.parse_args([] if argv is None else argv)  # None: the defaults
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    os.makedirs(args.out, exist_ok=True)
    for make in (fz_depth, fxy_heading, convergence, meshes):
        print(f"wrote {os.path.basename(make(plt, args.out))}")
    return 0


if __name__ == "__main__":
    main(sys.argv[1:])
