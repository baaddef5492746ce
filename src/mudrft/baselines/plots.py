"""Figures of the terrain comparisons (supplementary Figs. S5, S6); needs matplotlib."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from .._validation import MudrftError
from ..plotting import require_matplotlib
from .compare import History, normalized_loop

__all__ = ["plot_gait", "plot_s6"]

_STYLE = {
    "mud": {"color": "C0", "lw": 2.0},
    "granular-rft": {"color": "C1", "lw": 1.6},
    "granular-rft3d": {"color": "C4", "lw": 1.6, "ls": (0, (5, 1))},
    "maxwell": {"color": "C2", "lw": 1.6, "ls": "--"},
    "linear": {"color": "C3", "lw": 1.6, "ls": "-."},
    "rigid": {"color": "C7", "lw": 1.4, "ls": ":"},
}


def plot_s6(plate: Mapping[str, History], *, sand: str = "granular-rft") -> Any:
    """Fig. S6-style figure from a vertical plate test; returns the matplotlib Figure.

    (a) normalised force against normalised depth, mud against sand; (b) vertical stress
    :math:`F_z/A_z` [Pa] against time and (c) against depth. ``plate`` is
    :func:`mudrft.baselines.compare`'s result on :func:`mudrft.plate_intrusion`; ``sand``
    names the granular history.
    """
    if not isinstance(plate, Mapping) or not plate:
        raise MudrftError("plate must be a non-empty mapping {terrain: History} (compare's result)")
    plt = require_matplotlib()
    fig, ax = plt.subplots(1, 3, figsize=(13.5, 4.0), constrained_layout=True)
    loops = (
        ("mud", "mud (this model)"),  # its water content is the run's, not always 25 %
        (sand, "sand (granular RFT)"),
        ("granular-rft3d", "sand (3D-RFT)"),
    )
    for name, label in loops:
        if name in plate:
            x, y = normalized_loop(plate[name])
            ax[0].plot(x, y, label=label, **_STYLE.get(name, {}))
    _note_if_empty(ax[0], [n for n, _ in loops])
    ax[0].axhline(0, color="k", lw=0.5)
    ax[0].set(
        xlabel="normalised depth d / d_max [-]",
        ylabel="normalised force F_z / max|F_z| [-]",
        title="(a) intrusion-hold-retraction: mud vs sand",
    )
    if ax[0].get_legend_handles_labels()[0]:
        ax[0].legend(loc="lower right", fontsize=8)
    labels = {
        "mud": "this model (Chen 2026)",
        "maxwell": "Maxwell-type (AIM24, reconstructed)",
        "linear": "linear stiffness (Godon 2022)",
    }
    for name in ("mud", "maxwell", "linear"):
        if name in plate:
            h = plate[name]
            ax[1].plot(h.time, h.sigma_z / 1e3, label=labels[name], **_STYLE[name])
            mud = np.where(h.depth > 0, 1.0, np.nan)  # the stress-depth loop in the mud only
            ax[2].plot(
                h.depth * 1e3 * mud, h.sigma_z / 1e3 * mud, label=labels[name], **_STYLE[name]
            )
    for a in ax[1:]:
        a.axhline(0, color="k", lw=0.5)
        _note_if_empty(a, list(labels))
    ax[1].set(xlabel="time [s]", ylabel="stress F_z / A_z [kPa]", title="(b) time history")
    ax[2].set(xlabel="depth [mm]", ylabel="stress F_z / A_z [kPa]", title="(c) stress-depth")
    if ax[1].lines[1:]:
        ax[1].legend(fontsize=8)
    return fig


def _note_if_empty(ax: Any, names: list[str]) -> None:
    """Say on a panel that none of its terrains was run (only the zero line is drawn)."""
    if not ax.get_legend_handles_labels()[0]:
        ax.text(
            0.5, 0.5, "not run: " + ", ".join(names), ha="center", va="center",
            transform=ax.transAxes, fontsize=9, color="0.4",
        )  # fmt: skip


def plot_gait(
    gait: Mapping[str, History], *, title: str = "", exclude: tuple[str, ...] = ("rigid",)
) -> Any:
    """Fig. S5-style figure: Fx, Fy, Fz over one gait cycle for the terrains given.

    ``exclude`` drops terrains by name (by default rigid ground: only a penalty spring).
    """
    shown = {k: v for k, v in gait.items() if k not in exclude}
    if not shown:
        raise MudrftError("gait must hold at least one History that is not excluded")
    plt = require_matplotlib()
    fig, ax = plt.subplots(1, 3, figsize=(13.5, 3.8), constrained_layout=True)
    for name, h in shown.items():
        phase = (h.time - h.time[0]) / (h.time[-1] - h.time[0]) * 100
        for k in range(3):
            ax[k].plot(phase, h.force[:, k], label=name, **_STYLE.get(name, {}))
    for k, comp in enumerate(("F_x", "F_y", "F_z")):
        ax[k].axhline(0, color="k", lw=0.5)
        ax[k].axvline(50, color="k", lw=0.5, ls=":")
        ax[k].set(xlabel="gait cycle [%] (stance | swing)", ylabel=f"{comp} [N]")
    ax[0].legend(fontsize=8)
    if title:
        fig.suptitle(title)
    return fig
