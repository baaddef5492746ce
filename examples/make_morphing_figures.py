"""
The passive morphing foot
=========================

The paper's morphing foot as mudrft reconstructs it (the paper gives no dimensions for
its springs, linkage and pads; decisions D30-D39): its linkage, its response on rigid
ground, its three modes in mud and a gait cycle beside the fixed feet.

Run from the repository root: ``python examples/make_morphing_figures.py [--out DIR]
[--quick]``. Writes

* ``morphing_linkage.png``: the linkage and pads at four deflections (section and 3D view);
* ``morphing_rigid_ground.png``: pad angle and force against deflection on rigid ground
  (like the paper's Fig. S3);
* ``morphing_modes.png``: vertical stress against depth for the expanded, retracted and
  morphing modes in W = 25 % mud (like Fig. S4b), for a vertical intrusion-retraction
  and for one gait cycle at 0.2 m/s;
* ``morphing_gait.png``: the morphing foot beside the fixed feet over a gait cycle, with
  its pad angle and seal factor;

and replaces the generated tables (sensitivity, the four feet over a gait cycle) between
the markers in ``docs/model.md`` (the paper's claims are made by
``examples/make_claims_matrix.py``). With ``--quick`` (the docs build) it skips the
sensitivity table and prints the feet table instead of writing ``docs/model.md``.
Progress goes to stderr.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

import mudrft
from mudrft.feet import Flat, MorphingFoot, SemiCylinder, SemiSphere
from mudrft.plotting import require_matplotlib
from mudrft.simulation import simulate, static_sinking

FIG = Path("docs") / "figures"  # the output folder; main() sets it from --out
MUD = mudrft.paper_mud(0.25)
GAIT = mudrft.gait(0.2)
PLUNGE = mudrft.plate_intrusion(depth=0.03, speed=0.02, hold=1.0, dt=1e-3)
LOAD = 49.0  # [N] half a 10 kg biped, as `mudrft reproduce` (D13)
COLORS = {
    "expanded": "tab:blue",
    "retracted": "tab:orange",
    "morphing": "tab:red",
    "flat": "tab:blue",
    "semi-cylinder": "tab:orange",
    "semi-sphere": "tab:green",
}


def say(msg: str) -> None:
    print(msg, file=sys.stderr, flush=True)


def loop_area(res: mudrft.Result) -> float:
    """Vertical hysteresis loop area, the integral of Fz d(depth) over the run [J]."""
    ddepth = -res.velocity[:, 2]
    return float(np.trapezoid(res.force[:, 2] * ddepth, res.time))


# -- figures ---------------------------------------------------------------------------------------
def fig_linkage(plt):
    foot = MorphingFoot()
    g = foot.geometry
    fracs = (0.0, 1 / 3, 2 / 3, 1.0)
    fig = plt.figure(figsize=(12, 6.6), constrained_layout=True)
    for i, fr in enumerate(fracs):
        dl = fr * foot.stroke
        ax = fig.add_subplot(2, 4, i + 1)
        p = foot.linkage_points(dl)
        zb = p["B"][1]
        for s in (1.0, -1.0):  # the section shows the linkages on both sides

            def xy(q, s=s):
                return np.array([s * q[0], q[1]]) * 1e3

            A, C, B, P = xy(p["A"]), xy(p["C"]), xy(p["B"]), xy(p["P"])
            ax.plot(*np.c_[A, P], color="tab:green", lw=4, solid_capstyle="butt")  # pad
            ax.plot(*np.c_[A, C], color="k", lw=2)  # crank arm of the lower link
            ax.plot(*np.c_[C, B], color="tab:purple", lw=1.6)  # coupler (upper link)
            for q, mk in ((A, "o"), (C, "o"), (B, "s")):
                ax.plot(*q, mk, color="k", ms=4, mfc="w")
        rb, h = g.base_radius * 1e3, g.pivot_height * 1e3
        ax.add_patch(plt.Rectangle((-rb, 0), 2 * rb, h, color="0.55"))  # base pad
        rc = g.column_radius * 1e3
        ax.add_patch(plt.Rectangle((-rc, h), 2 * rc, (zb + 0.004) * 1e3 - h, fc="0.85", ec="0.5"))
        ax.add_patch(
            plt.Rectangle((-rc - 1.5, zb * 1e3 - 2), 2 * rc + 3, 40, fc="0.7", ec="0.4", alpha=0.8)
        )
        ax.axhline(0, color="saddlebrown", lw=0.8, ls=":")
        th = math.degrees(float(foot.pad_angle(dl)))
        f = float(foot.rigid_ground(dl).force)
        ax.set_title(
            f"deflection {dl * 1e3:.1f} mm\npad angle {th:.0f}°, spring {f:.1f} N", fontsize=9
        )
        ax.set_xlim(-52, 52)
        ax.set_ylim(-4, 62)
        ax.set_aspect("equal")
        ax.set_xlabel("r [mm]")
        if i == 0:
            ax.set_ylabel("z above tip [mm]")
        ax3 = fig.add_subplot(2, 4, 5 + i, projection="3d")
        from mpl_toolkits.mplot3d.art3d import Poly3DCollection

        corners = foot.pad_corners(dl) * 1e3
        ax3.add_collection3d(
            Poly3DCollection(list(corners), fc="tab:green", ec="k", lw=0.4, alpha=0.85)
        )
        t = np.linspace(0, 2 * np.pi, 40)
        ax3.plot(rb * np.cos(t), rb * np.sin(t), 0 * t, color="0.3")
        ax3.plot(rb * np.cos(t), rb * np.sin(t), 0 * t + h, color="0.3")
        ax3.set_xlim(-50, 50)
        ax3.set_ylim(-50, 50)
        ax3.set_zlim(0, 50)
        ax3.set_box_aspect((1, 1, 0.5), zoom=1.35)
        ax3.view_init(elev=28, azim=-60)
        ax3.set_xticks([-40, 0, 40])
        ax3.set_yticks([-40, 0, 40])
        ax3.set_zticks([0, 40])
        ax3.tick_params(labelsize=7)
    fig.suptitle(
        "Morphing foot (reconstruction, D30): one linkage per pad — pad (green) on the lower "
        "link, crank arm (black), coupler (purple) to the upper column",
        fontsize=10,
    )
    path = FIG / "morphing_linkage.png"
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def fig_rigid_ground(plt):
    foot = MorphingFoot()
    d = np.linspace(0.0, foot.stroke, 400)
    r = foot.rigid_ground(d)
    th = np.degrees(r.pad_angle)
    chord = th[0] + (th[-1] - th[0]) * d / d[-1]
    fig, ax = plt.subplots(1, 2, figsize=(9, 3.8), constrained_layout=True)
    ax[0].plot(d * 1e3, th[0] - th, "k", lw=1.8, label="slider-crank linkage")
    ax[0].plot(d * 1e3, th[0] - chord, "--", color="tab:red", lw=1, label="linear")
    ax[0].set_xlabel("foot deflection [mm]")
    ax[0].set_ylabel(r"pad expanding angle $d\theta$ [deg]")
    ax[0].set_title(f"(a) max departure from linear {np.abs(th - chord).max():.1f} deg", fontsize=9)
    ax[0].legend(fontsize=8)
    knee = foot.spring.knee_deflection * 1e3
    ax[1].plot(d * 1e3, r.force, "k", lw=1.8)
    ax[1].axvline(knee, color="0.6", ls=":", lw=1)
    ks, kh = foot.spring.series_stiffness, foot.spring.hard_stiffness
    ax[1].text(
        knee * 0.45,
        foot.spring.knee_force * 1.6,
        f"soft region\n{ks / 1e3:.2f} N/mm",
        ha="center",
        fontsize=8,
    )
    ax[1].text(
        knee - 0.3,
        float(r.force[-1]) * 0.75,
        f"hard region\n{kh / 1e3:.1f} N/mm",
        ha="right",
        fontsize=8,
    )
    ax[1].set_xlabel("foot deflection [mm]")
    ax[1].set_ylabel(r"vertical force $F_z$ [N]")
    ax[1].set_title("(b) two stiffness regions (soft stage bottoms out)", fontsize=9)
    path = FIG / "morphing_rigid_ground.png"
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


def fig_modes(plt):
    aref = float(MorphingFoot().footprint_area(MorphingFoot().stroke))
    fig, ax = plt.subplots(1, 2, figsize=(10, 3.8), constrained_layout=True)
    out = {}
    for j, (label, tr) in enumerate(
        (
            ("vertical intrusion 30 mm at 20 mm/s, hold 1 s", PLUNGE),
            ("one gait cycle at 0.2 m/s", GAIT),
        )
    ):
        for mode in ("expanded", "retracted", "morphing"):
            res = simulate(MorphingFoot(mode=mode), MUD, tr)
            out[(j, mode)] = res
            ax[j].plot(
                res.depth * 1e3,
                res.force[:, 2] / aref / 1e3,
                color=COLORS[mode],
                lw=1.5,
                label=mode,
            )
        ax[j].axhline(0, color="0.6", lw=0.6)
        ax[j].set_xlabel("sinking depth of the tip [mm]")
        ax[j].set_ylabel(r"$F_z/A_{spread}$ [kPa]")
        ax[j].set_title(f"({'ab'[j]}) W = 25 %, {label}", fontsize=9)
        ax[j].legend(fontsize=8)
    fig.suptitle(
        f"Morphing foot modes (like Fig. S4b); stress = Fz / spread footprint "
        f"{aref * 1e6:.0f} mm$^2$",
        fontsize=10,
    )
    path = FIG / "morphing_modes.png"
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path, out


def fig_gait(plt, runs):
    foot = MorphingFoot()
    fig, ax = plt.subplots(1, 2, figsize=(10, 3.8), constrained_layout=True)
    for name, res in runs.items():
        ax[0].plot(res.time, res.force[:, 2], color=COLORS[name], lw=1.5, label=name)
    ax[0].axhline(0, color="0.6", lw=0.6)
    ax[0].set_xlabel("time [s]")
    ax[0].set_ylabel(r"$F_z$ [N]")
    ax[0].set_title("(a) vertical force over a gait cycle (0.2 m/s, W = 25 %)", fontsize=9)
    ax[0].legend(fontsize=8)
    ter = mudrft.MudTerrain(MUD)
    st = ter.initial_state(foot, GAIT.position[0])
    th, seal = [float(np.degrees(st.foot.pad_angle))], [1.0]
    for k in range(1, len(GAIT)):
        st, _ = ter.step(
            foot, st, GAIT.position[k], GAIT.velocity[k], GAIT.time[k] - GAIT.time[k - 1]
        )
        th.append(float(np.degrees(st.foot.pad_angle)))
        seal.append(float(foot.seal_factor(st.foot)))
    ax[1].plot(GAIT.time, th, "k", lw=1.5, label="pad angle (left axis)")
    ax[1].set_ylabel("pad angle [deg] (0 = flat)")
    ax[1].set_xlabel("time [s]")
    a2 = ax[1].twinx()
    a2.plot(GAIT.time, seal, color="tab:red", lw=1.2, label="seal factor")
    a2.plot(
        GAIT.time, GAIT.depth / GAIT.depth.max(), color="0.6", ls="--", lw=1, label="depth / max"
    )
    a2.set_ylabel("seal factor, depth / max [-]")
    a2.set_ylim(-0.05, 1.05)
    h1, l1 = ax[1].get_legend_handles_labels()
    h2, l2 = a2.get_legend_handles_labels()
    a2.legend(h1 + h2, l1 + l2, fontsize=8, loc="center right")
    ax[1].set_title("(b) morphing foot: pads spread in stance, curl on lift-off", fontsize=9)
    path = FIG / "morphing_gait.png"
    fig.savefig(path, dpi=130)
    plt.close(fig)
    return path


# -- tables ----------------------------------------------------------------------------------------
def sensitivity_table() -> str:
    base = MorphingFoot()
    rows = []
    cases = [
        ("soft_stiffness", "N/m", base.spring.soft_stiffness, (0.5, 1.0, 2.0, 4.0)),
        ("hard_stiffness", "N/m", base.spring.hard_stiffness, (0.5, 1.0, 2.0, 8.0)),
        ("pad_length", "mm", base.geometry.pad_length, (0.5, 1.0, 2.0)),
        ("seal_length", "mm", base.seal_length, (0.5, 1.0, 2.0, 1e6)),
    ]
    for name, unit, v0, factors in cases:
        for fac in factors:
            foot = base.replace(**{name: v0 * fac})
            g = simulate(foot, MUD, GAIT)
            p = simulate(foot, MUD, PLUNGE)
            mg, mp = g.metrics(), p.metrics()
            sink = static_sinking(foot, MUD, LOAD)
            shown = (
                f"{v0 * fac * (1e3 if unit == 'mm' else 1.0):g} {unit}"
                if fac < 1e3
                else "inf (seal kept)"
            )
            flab = f"x{fac:g}" if fac < 1e3 else "x inf"
            rows.append(
                f"| {name} | {flab} | {shown} | {mg['max_suction']:.1f} | "
                f"{mg['suction_ratio'] * 100:.0f} % | {mg['energy']:.2f} | {loop_area(g):.2f} | "
                f"{mp['max_suction']:.1f} | {mp['energy']:.2f} | {sink * 1e3:.1f} | "
                f"{foot.characteristic_length * 1e3:.1f} |"
            )
            say(f"  sensitivity {name} x{fac:g} done")
    head = (
        "| parameter | factor | value | gait max suction [N] | gait suction / support | "
        "gait energy [J] | gait Fz loop [J] | plunge max suction [N] | plunge energy [J] | "
        "static sinking under 49 N [mm] | L_c [mm] |\n|---|---|---|---|---|---|---|---|---|---|---|"
    )
    return head + "\n" + "\n".join(rows)


def feet_table(gait_runs: dict) -> str:
    """The four feet over the gait cycle (the paper's claims are in section 12, from
    ``mudrft reproduce``); sinking from the relaxed mud's balance (decision D13)."""
    m = {k: v.metrics() for k, v in gait_runs.items()}
    loops = {k: loop_area(v) for k, v in gait_runs.items()}
    feet = {"flat": Flat(), "semi-cylinder": SemiCylinder(), "semi-sphere": SemiSphere()}
    feet["morphing"] = MorphingFoot()
    sink = {name: static_sinking(foot, MUD, LOAD) for name, foot in feet.items()}
    lines = [
        "| foot | peak support [N] | max suction [N] | suction / support | energy [J] | "
        "Fz loop [J] | static sinking under 49 N [mm] |",
        "|---|---|---|---|---|---|---|",
    ]
    for k in m:
        lines.append(
            f"| {k} | {m[k]['peak_support']:.1f} | {m[k]['max_suction']:.1f} | "
            f"{m[k]['suction_ratio'] * 100:.0f} % | {m[k]['energy']:.2f} | {loops[k]:.2f} | "
            f"{sink[k] * 1e3:.1f} |"
        )
    return "\n".join(lines)


def replace_between(text: str, tag: str, body: str) -> str:
    start, end = f"<!-- {tag}:start -->", f"<!-- {tag}:end -->"
    i, j = text.index(start) + len(start), text.index(end)
    return text[:i] + "\n" + body + "\n" + text[j:]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description="Figures and tables of the morphing foot.")
    ap.add_argument("--out", default=None, help="output folder (default docs/figures)")
    ap.add_argument(
        "--quick",
        action="store_true",
        help="no sensitivity table; print the feet table, leave docs/model.md alone",
    )
    args = ap.parse_args([] if argv is None else argv)  # None: the defaults
    global FIG
    FIG = Path(args.out) if args.out else Path(__file__).resolve().parents[1] / "docs" / "figures"
    plt = require_matplotlib()
    FIG.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    say(f"wrote {fig_linkage(plt)}")
    say(f"wrote {fig_rigid_ground(plt)}")
    path, _ = fig_modes(plt)
    say(f"wrote {path}")
    runs = {}
    for foot in (Flat(), SemiCylinder(), SemiSphere(), MorphingFoot()):
        runs[foot.name] = simulate(foot, MUD, GAIT)
    say(f"wrote {fig_gait(plt, runs)}")
    if args.quick:
        print(feet_table(runs))
        return 0
    say("sensitivity table (12 feet x gait + plunge) ...")
    sens = sensitivity_table()
    say("feet table ...")
    table = feet_table(runs)
    FRAGMENT = Path(__file__).resolve().parents[1] / "docs" / "model.md"
    text = FRAGMENT.read_text()
    text = replace_between(text, "sensitivity", sens)
    text = replace_between(text, "morphing-feet", table)
    FRAGMENT.write_text(text)
    say(f"updated tables in {FRAGMENT}")
    say(f"done in {time.perf_counter() - t0:.0f} s")
    return 0


if __name__ == "__main__":
    main(sys.argv[1:])
