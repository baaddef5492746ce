"""What a biped walk returns and writes: its tables, the CSV files, the plot, the images."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from ..plotting import require_matplotlib
from .mujoco._lazy import _mujoco

if TYPE_CHECKING:
    import mujoco

__all__ = [
    "ANKLE_HEIGHT", "STEP_COLUMNS", "WALK_COLUMNS", "WalkResult", "plot_walk", "save_strip",
]  # fmt: skip

#: Columns of the per-physics-step table (``walk.csv``), with units.
WALK_COLUMNS = (
    "time [s]", "x [m]", "z [m]", "pitch [rad]", "left_depth [m]", "right_depth [m]",
    "left_Fx [N]", "left_Fz [N]", "right_Fx [N]", "right_Fz [N]", "joint_power [W]",
    "joint_energy [J]", "joint_abs_energy [J]", "left_x [m]", "right_x [m]", "step",
)  # fmt: skip
#: Columns of the per-gait-step table (``steps.csv``), with units.
STEP_COLUMNS = (
    "step", "t_start [s]", "stance", "energy [J]", "absolute_work [J]", "sinking [m]",
    "max_suction [N]", "slip [m]", "shank_in_mud", "advance [m]",
)  # fmt: skip
#: Height of the shank's lower end (the ankle) above the sole [m]: deeper than this the
#: shank is in the mud, whose force on it the coupling does not model.
ANKLE_HEIGHT = 0.04


@dataclass(frozen=True, eq=False)
class WalkResult:
    """Outcome of :func:`mudrft.integrations.walk.walk`.

    Attributes
    ----------
    table : dict of str -> ndarray
        Per physics step, keys :data:`WALK_COLUMNS`.
    steps : dict of str -> ndarray
        Per gait step, keys :data:`STEP_COLUMNS` (complete steps only).
    summary : dict
        ``fell`` (bool), ``distance [m]``, ``energy_per_step [J]``, ``mean_sinking [m]``,
        ``max_suction [N]`` and the run settings.
    frames : list of ndarray
        Offscreen-rendered RGB images (empty unless asked for and rendering works).
    """

    table: dict[str, np.ndarray]
    steps: dict[str, np.ndarray]
    summary: dict[str, Any]
    frames: list = field(default_factory=list)


def _renderer(model: mujoco.MjModel) -> mujoco.Renderer | None:
    """An offscreen renderer, or None where OpenGL is not available."""
    try:
        return _mujoco().Renderer(model, 240, 320)
    except Exception:  # any GL failure only means "no images"
        return None


def _per_step(table: dict[str, NDArray[np.float64]]) -> dict[str, NDArray[np.float64]]:
    r"""Per complete gait step (``step`` column; even steps stand on the left foot),
    :data:`STEP_COLUMNS`: ``energy [J]`` the servos' positive work
    (:math:`\sum_j\max(\tau_j\dot q_j,0)\,\Delta t`), ``absolute_work [J]``, ``sinking [m]``
    deepest stance-foot depth, ``max_suction [N]``, ``slip [m]`` of the stance foot in the mud,
    ``shank_in_mud`` (deeper than :data:`ANKLE_HEIGHT`) and ``advance [m]`` of the torso.
    """
    t = table["time [s]"]
    step = table["step"].astype(int)
    out: dict[str, list[float]] = {c: [] for c in STEP_COLUMNS}
    last = int(step[-1])
    for k in range(0, last):  # the last step may be cut short
        sel = step == k
        if not np.any(sel):
            continue
        stance = k % 2
        side = "left" if stance == 0 else "right"
        first = int(np.argmax(sel))
        e, a = table["joint_energy [J]"], table["joint_abs_energy [J]"]
        depth = table[f"{side}_depth [m]"][sel]
        x_in = table[f"{side}_x [m]"][sel][depth > 0]
        fz = np.minimum(table["left_Fz [N]"][sel], table["right_Fz [N]"][sel])
        out["step"].append(k)
        out["t_start [s]"].append(float(t[sel][0]))
        out["stance"].append(stance)
        out["energy [J]"].append(float(e[sel][-1] - (e[first - 1] if first > 0 else 0.0)))
        out["absolute_work [J]"].append(float(a[sel][-1] - (a[first - 1] if first > 0 else 0.0)))
        out["sinking [m]"].append(float(depth.max()))
        out["max_suction [N]"].append(float(max(0.0, -fz.min())))
        out["slip [m]"].append(float(x_in.max() - x_in.min()) if len(x_in) else 0.0)
        out["shank_in_mud"].append(float(depth.max() > ANKLE_HEIGHT))
        out["advance [m]"].append(float(table["x [m]"][sel][-1] - table["x [m]"][sel][0]))
    return {c: np.asarray(v, dtype=float) for c, v in out.items()}


def _write_csv(path: Path, table: dict[str, NDArray[np.float64]], columns: tuple[str, ...]) -> None:
    """Write ``table`` as CSV: a header of ``columns`` (units in brackets), one row each."""
    data = np.column_stack([table[c] for c in columns])  # (0, len(columns)) when empty
    np.savetxt(path, data, delimiter=",", header=",".join(columns), comments="", fmt="%.9g")


def plot_walk(result: WalkResult, path: Path) -> Path:
    """Plot a walk against time (PNG at ``path``, returned): torso x and z [m], foot
    sinking [mm], vertical mud force per foot [N] (< 0: suction), joint work [J]. Needs matplotlib.
    """
    plt = require_matplotlib()

    tb = result.table
    t = tb["time [s]"]
    fig, ax = plt.subplots(4, 1, figsize=(8, 9), sharex=True)
    ax[0].plot(t, tb["x [m]"], label="torso x")
    ax[0].plot(t, tb["z [m]"], label="torso z")
    ax[0].set_ylabel("[m]")
    ax[0].legend(loc="upper left")
    for side, c in (("left", "C0"), ("right", "C1")):
        ax[1].plot(t, 1e3 * tb[f"{side}_depth [m]"], c, label=f"{side} foot")
        ax[2].plot(t, tb[f"{side}_Fz [N]"], c, label=f"{side} foot")
    ax[1].set_ylabel("sinking [mm]")
    ax[1].invert_yaxis()
    ax[1].legend(loc="lower left")
    ax[2].axhline(0.0, color="k", lw=0.5)
    ax[2].set_ylabel("mud $F_z$ [N]\n(< 0: suction)")
    ax[3].plot(t, tb["joint_energy [J]"], "k", label="positive")
    ax[3].plot(t, tb["joint_abs_energy [J]"], "k--", label="absolute")
    ax[3].legend(loc="upper left")
    ax[3].set_ylabel("joint work [J]")
    ax[3].set_xlabel("time [s]")
    s = result.summary
    fig.suptitle(
        f"biped in mud, {s['foot']} feet: {s['distance [m]']:.2f} m, "
        f"{s['energy_per_step [J]']:.2f} J/step, sinking {1e3 * s['mean_sinking [m]']:.1f} mm, "
        f"max suction {s['max_suction [N]']:.1f} N" + (" (fell)" if s["fell"] else ""),
        fontsize=9,
    )
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def save_strip(frames: list[NDArray[np.uint8]], path: Path) -> Path | None:
    """Save RGB frames side by side as one PNG; the path, or None without frames."""
    if not frames:
        return None
    plt = require_matplotlib()

    plt.imsave(path, np.concatenate(frames, axis=1))
    return path
