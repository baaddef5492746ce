"""
A biped walking in mud (MuJoCo)
===============================

A 10 kg planar biped walks in the paper's 25 % mud with each of the paper's feet, the mud
force computed by mudrft under each foot every physics step; and the stability of the
coupling: a foot on a spring shot into mud and pulled out, with the explicit and the
stabilised coupling.

Run ``python examples/walk_biped.py [--seconds 10] [--out docs/figures] [--quick]``
(``--quick``: 3 s of walking and no rendered frames, for the docs build). Makes

* ``mujoco_walk_feet.png``: 10 s of walking at W = 25 % with the flat, semi-cylindrical,
  semi-spherical and morphing feet: sinking and vertical mud force of the left foot against
  time, and the summary metrics of ``mudrft walk`` per foot;
* ``mujoco_stability.png``: a 0.3 kg foot on a spring shot into mud and pulled out against
  suction: mechanical energy with the explicit coupling below and above its limit
  :math:`2m/c`, and with the stabilised coupling at 1 and 2 ms;
* ``mujoco_frames.png``: an offscreen-rendered image strip of the flat-foot walk (only if
  MuJoCo can render headless here; skipped otherwise).
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

os.environ.setdefault("MUJOCO_GL", "egl")

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import mudrft
from mudrft.integrations import walk as W
from mudrft.integrations.mujoco import attach, stability_limits

FEET = ("flat", "semi-cylinder", "semi-sphere", "morphing")


def walk_feet(out: Path, seconds: float, dt: float, frames: bool = True) -> dict[str, dict]:
    mud = mudrft.paper_mud(0.25)
    runs = {}
    for name in FEET:
        print(f"walking with {name} feet ...", file=sys.stderr, flush=True)
        runs[name] = W.walk(
            mudrft.feet.by_name(name),
            mud,
            seconds=seconds,
            dt=dt,
            frames=6 if name == "flat" and frames else 0,
        )
        print(f"  {runs[name].summary}", file=sys.stderr)
    fig = plt.figure(figsize=(11, 7.5))
    gs = fig.add_gridspec(3, 4)
    ax_d = fig.add_subplot(gs[0, :])
    ax_f = fig.add_subplot(gs[1, :], sharex=ax_d)
    for name, res in runs.items():
        t = res.table["time [s]"]
        ax_d.plot(t, 1e3 * res.table["left_depth [m]"], label=name, lw=1)
        ax_f.plot(t, res.table["left_Fz [N]"], label=name, lw=1)
    ax_d.set_ylabel("left foot sinking [mm]")
    ax_d.invert_yaxis()
    ax_d.legend(ncol=4, fontsize=8, loc="lower left")
    ax_f.axhline(0, color="k", lw=0.5)
    ax_f.set_ylabel("left foot mud $F_z$ [N]\n(< 0: suction)")
    ax_f.set_xlabel("time [s]")
    keys = (
        ("distance [m]", 1.0, "distance [m]"),
        ("energy_per_step [J]", 1.0, "joint work per step [J]"),
        ("mean_sinking [m]", 1e3, "mean sinking [mm]"),
        ("max_suction [N]", 1.0, "max suction [N]"),
    )
    for i, (key, scale, label) in enumerate(keys):
        ax = fig.add_subplot(gs[2, i])
        vals = [scale * runs[n].summary[key] for n in FEET]
        ax.bar(range(len(FEET)), vals, color=[f"C{j}" for j in range(len(FEET))])
        ax.set_xticks(range(len(FEET)), [n.replace("semi-", "semi-\n") for n in FEET], fontsize=7)
        ax.set_title(label, fontsize=9)
    fig.suptitle(
        f"10 kg planar biped walking in mud (W = 25 %), {seconds:g} s at dt = {dt * 1e3:g} ms, "
        "0.1 m/s command",
        fontsize=10,
    )
    fig.tight_layout()
    fig.savefig(out / "mujoco_walk_feet.png", dpi=110)
    plt.close(fig)
    strip = W.save_strip(runs["flat"].frames, out / "mujoco_frames.png")
    print("frames:", strip if strip is not None else "rendering not available here (skipped)")
    return {n: r.summary for n, r in runs.items()}


def _spring_foot_energy(dt: float, duration: float = 1.2) -> tuple[np.ndarray, np.ndarray]:
    import mujoco

    xml = f"""<mujoco><option timestep="{dt}"><flag energy="enable"/></option><worldbody>
      <body name="foot" pos="0 0 0.013"><joint type="slide" axis="0 0 1" stiffness="300" springref="0.06"/>
      <geom type="box" size="0.0325 0.04 0.013" mass="0.3"/></body></worldbody></mujoco>"""
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    data.qvel[0] = -0.3
    coupling = attach(model, "foot", mudrft.paper_mud(0.25))
    coupling.reset(data)
    mujoco.mj_forward(model, data)
    e0 = float(data.energy.sum())
    t, e = [0.0], [0.0]
    for _ in range(int(duration / dt)):
        try:
            coupling.step(data)
        except mudrft.MudrftError:
            break
        mujoco.mj_forward(model, data)
        t.append(float(data.time))
        e.append(float(data.energy.sum()) - e0)
        if abs(e[-1]) > 1e3:
            break
    return np.array(t), np.array(e)


def stability(out: Path) -> None:
    lim = stability_limits(mudrft.feet.Flat(), mudrft.paper_mud(0.25), mass=0.3, depth=1e-3)[
        "dt_viscous"
    ]
    fig, ax = plt.subplots(1, 2, figsize=(11, 4))
    # the coupling's implicit step, below and above the explicit step's limit 2m/c
    cases = [
        (0.8 * lim, f"dt = 0.8 x 2m/c = {0.8 * lim * 1e3:.2f} ms", "C0"),
        (1.3 * lim, f"dt = 1.3 x 2m/c = {1.3 * lim * 1e3:.2f} ms", "C3"),
        (1e-3, "dt = 1 ms", "C2"),
        (2e-3, "dt = 2 ms", "k"),
    ]
    for dt, label, col in cases:
        t, e = _spring_foot_energy(dt)
        ax[0].plot(t, e, col, label=label, lw=1)
        ax[1].semilogy(t, np.maximum(e, 0) + 1e-9, col, label=label, lw=1)
    ax[0].set_ylim(-0.6, 0.3)
    ax[0].set_xlabel("time [s]")
    ax[0].set_ylabel("E(t) - E(0) [J]")
    ax[0].set_title("mechanical energy (kinetic + gravity + spring)", fontsize=9)
    ax[0].legend(fontsize=7)
    ax[1].set_xlabel("time [s]")
    ax[1].set_ylabel("energy gained above the start [J] (log; 1e-9 = none)")
    ax[1].set_title(
        f"0.3 kg foot on a spring, into mud and out: 2m/c = {lim * 1e3:.2f} ms", fontsize=9
    )
    fig.tight_layout()
    fig.savefig(out / "mujoco_stability.png", dpi=110)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        description="A biped walking in mud, and the coupling's stability."
    )
    parser.add_argument("--seconds", type=float, default=10.0)
    parser.add_argument("--dt", type=float, default=2e-3)
    parser.add_argument("--out", default=None, help="output folder (default docs/figures)")
    parser.add_argument("--quick", action="store_true", help="3 s, no frames (the docs build)")
    args = parser.parse_args([] if argv is None else argv)  # None: the defaults
    out = Path(args.out) if args.out else Path(__file__).resolve().parents[1] / "docs" / "figures"
    out.mkdir(parents=True, exist_ok=True)
    stability(out)
    seconds = min(args.seconds, 3.0) if args.quick else args.seconds
    summaries = walk_feet(out, seconds, args.dt, frames=not args.quick)
    for name, s in summaries.items():
        print(
            f"{name:14s} fell={s['fell']!s:5s} distance={s['distance [m]']:.3f} m  "
            f"energy/step={s['energy_per_step [J]']:.2f} J  sinking={1e3 * s['mean_sinking [m]']:.1f} mm  "
            f"max suction={s['max_suction [N]']:.1f} N"
        )
    return 0


if __name__ == "__main__":
    main(sys.argv[1:])
