r"""A small planar biped walking in mud, the ``mudrft walk`` command, and what a walk returns
and writes: its tables, the CSV files, the plot, the images.

The biped (``assets/biped.xml``, 10 kg) has a torso on a planarizing boom and two legs
with hip, knee and ankle pitch joints driven by torque-limited PD servos;
:func:`biped_model` gives its feet the simulated foot's shape (visual and rigid bed only).
:class:`GaitController` (D69) tracks a periodic gait: each ankle follows a stance line or a
swing arc relative to the hip, the foot kept level. The biped falls only if its legs fold
(torso below half its start height) or the torso pitches past 1 rad.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from .._validation import MudrftError, check_nonnegative, check_positive, check_samples, plain
from ..plotting import require_matplotlib
from ..trajectories import BuriedFootWarning, check_unburied
from .mujoco import _mujoco  # imports MuJoCo on first call

if TYPE_CHECKING:
    import mujoco

    from ..feet.base import Foot
    from ..parameters.base import Mud
    from ..terrains import MudTerrain
    from ..terrains.field import MudField

__all__ = [
    "ANKLE_HEIGHT",
    "BIPED_FEET",
    "MAX_DT",
    "STEP_COLUMNS",
    "WALK_COLUMNS",
    "GaitController",
    "WalkResult",
    "biped_model",
    "biped_path",
    "plot_walk",
    "save_strip",
    "walk",
]

#: Names of the biped's foot bodies (and of their geoms).
BIPED_FEET = ("left_foot", "right_foot")
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
#: Leg segment lengths of the biped: thigh, shank [m].
THIGH, SHANK = 0.2, 0.2
#: The largest physics time step the biped walks stably at [s].
MAX_DT = 0.01
#: The fewest physics steps a walking step may span (``step_time / dt``): the servos
#: track the gait's joint targets, which a step of a handful of samples does not describe.
MIN_STEP_SAMPLES = 20
_JOINTS = ("left_hip", "left_knee", "left_ankle", "right_hip", "right_knee", "right_ankle")


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
    for k in range(int(step[-1])):  # the last step may be cut short
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


def biped_path() -> Path:
    """Path of the biped's MJCF file."""
    return Path(str(resources.files("mudrft.integrations") / "assets" / "biped.xml"))


def biped_model(
    foot: Foot | None = None,
    *,
    bottom: float = 0.15,
    surface: float = 0.0,
    timestep: float = 1e-3,
    field: MudField | None = None,
) -> mujoco.MjModel:
    """The biped as a ``mujoco.MjModel``, with feet shaped like ``foot``.

    Parameters
    ----------
    foot : Foot or None
        A mudrft foot; when it has a surface mesh (``to_mesh()`` or ``vertices`` and
        ``faces``), the foot geoms become that mesh, tip at the sole. Otherwise the box
        feet stay.
    bottom : float, keyword-only
        Depth of the rigid bed (plane) below the mud surface [m].
    surface : float, keyword-only
        Height of the mud surface [m].
    timestep : float, keyword-only
        Physics time step [s].
    field : MudField or None, keyword-only
        A field with rigid regions: a box under each of its cells
        (:func:`~mudrft.integrations.mujoco.add_rigid_cells`), the rigid ones colliding
        with the feet, and the bed no longer a MuJoCo contact (the coupling's ``bottom=``
        carries the feet there).
    """
    mj = _mujoco()
    check_positive("bottom", bottom, unit="m")
    check_positive("timestep", timestep, unit="s")
    rigid = field if field is not None and field.has_rigid else None  # boxes under its cells
    spec = mj.MjSpec.from_file(str(biped_path()))
    spec.option.timestep = float(timestep)
    for g in spec.geoms:
        if g.name == "bottom":
            g.pos = [0.0, 0.0, float(surface) - float(bottom)]
            if rigid is not None:
                g.conaffinity = 0  # the coupling's bottom= is the bed
        elif g.name == "mud_surface":
            g.pos = [0.0, 0.0, float(surface)]
    mesh = _foot_mesh(foot)
    if mesh is not None:
        verts, faces = mesh
        m = spec.add_mesh()
        m.name = "foot_mesh"
        m.uservert = np.asarray(verts, dtype=float).ravel().tolist()
        m.userface = np.asarray(faces, dtype=int).ravel().tolist()
        for g in spec.geoms:
            if g.name in BIPED_FEET:
                g.type = mj.mjtGeom.mjGEOM_MESH
                g.meshname = "foot_mesh"
                g.pos = [0.0, 0.0, -ANKLE_HEIGHT]
    if rigid is not None:
        from .mujoco.rigid import add_rigid_cells, set_rigid_cells

        add_rigid_cells(spec, rigid, surface=float(surface))
    model = spec.compile()
    if rigid is not None:
        set_rigid_cells(model, rigid)
    return model


def _foot_mesh(foot: Foot | None) -> tuple[np.ndarray, np.ndarray] | None:
    if foot is None:
        return None
    try:
        # duck-typed: a closed form's MeshFoot, or a foot that has vertices and faces itself
        mf: Any = foot.to_mesh(resolution=8) if hasattr(foot, "to_mesh") else foot
        v, f = np.asarray(mf.vertices, dtype=float), np.asarray(mf.faces, dtype=int)
    except (AttributeError, TypeError, MudrftError):
        return None
    if v.ndim != 2 or v.shape[1] != 3 or f.ndim != 2 or f.shape[1] != 3 or len(f) < 4:
        return None
    return v, f


def _leg_ik(x: float, z: float) -> tuple[float, float]:
    """Hip and knee angles [rad] that put the ankle at (x, z) [m] relative to the hip."""
    r2 = x * x + z * z
    c2 = (r2 - THIGH**2 - SHANK**2) / (2 * THIGH * SHANK)
    q2 = math.acos(min(max(c2, -1.0), 1.0))
    phi = math.atan2(-x, -z)
    q1 = phi - math.atan2(SHANK * math.sin(q2), THIGH + SHANK * math.cos(q2))
    return q1, q2


def _ease(a: float, b: float, s: float, start: float, end: float) -> float:
    """From ``a`` to ``b`` along a smoothstep as ``s`` goes from ``start`` to ``end``."""
    u = min(max((s - start) / (end - start), 0.0), 1.0)
    return a + (b - a) * (u * u * (3 - 2 * u))


@dataclass
class GaitController:
    """Joint PD tracking of a periodic stepping gait (decision D69).

    Parameters
    ----------
    model : mujoco.MjModel
        The biped (:func:`biped_model`).
    speed : float
        Walking speed command [m/s]: step length = ``speed * step_time``.
    step_time : float
        Duration of one step (one leg's swing) [s].
    hip_height : float
        Height of the hip above the ankle of a foot standing on the mud surface [m].
    lift : float
        Height of the swing foot's sole above the mud surface at the top of the swing [m].
    surface : float
        Height of the mud surface [m].
    ramp_steps : int
        Steps over which the step length ramps up from 0.
    """

    model: mujoco.MjModel
    speed: float = 0.1
    step_time: float = 1.0
    hip_height: float = 0.33
    lift: float = 0.06
    surface: float = 0.0
    ramp_steps: int = 2
    phases: tuple[float, float, float, float, float] = (0.1, 0.4, 0.6, 0.85, 0.95)

    def __post_init__(self) -> None:
        check_nonnegative("speed", self.speed, unit="m/s")
        check_positive("step_time", self.step_time, unit="s")
        check_positive("hip_height", self.hip_height, unit="m")
        check_nonnegative("lift", self.lift, unit="m")
        if self.hip_height >= THIGH + SHANK:
            raise MudrftError(
                f"hip_height must be < {THIGH + SHANK} m (leg length), got {self.hip_height!r}"
            )
        m = self.model
        ids = [m.joint(n).id for n in _JOINTS]
        self._qadr = np.array([m.jnt_qposadr[i] for i in ids])
        self._dadr = np.array([m.jnt_dofadr[i] for i in ids])
        self._pitch = int(m.jnt_qposadr[m.joint("rooty").id])
        self._hip_body = int(m.body("left_thigh").id)
        self._foot_bodies = (int(m.body("left_foot").id), int(m.body("right_foot").id))
        self._lo, self._hi = m.actuator_ctrlrange[:, 0].copy(), m.actuator_ctrlrange[:, 1].copy()
        self.reset()

    def reset(self) -> None:
        """Start standing, both ankles under the hip."""
        self._start = [0.0, 0.0]
        self._z0 = [0.0, 0.0]
        self._step = -1

    def step_length(self, k: int) -> float:
        """Length of step ``k`` [m] (ramped up over ``ramp_steps``)."""
        full = self.speed * self.step_time
        return full * min(1.0, (k + 1) / (self.ramp_steps + 1)) if self.ramp_steps > 0 else full

    def targets(
        self, t: float, pitch: float, hip_z: float, ankle_z: tuple[float, float]
    ) -> tuple[np.ndarray, int, int]:
        """Joint targets [rad] at time ``t`` [s], the gait step index and the stance leg (0 left).

        ``pitch``: torso pitch [rad]; ``hip_z``: hip height [m]; ``ankle_z``: ankle heights [m].
        Heights are held relative to the mud surface: the stance leg extends as its foot sinks,
        and the swing foot rises to ``lift`` above the surface and lands on it.
        """
        k = int(t // self.step_time)
        s = t / self.step_time - k
        stance = k % 2  # step 0: right leg swings, left leg stands
        if k != self._step:  # new step: remember where each ankle starts
            if self._step >= 0:  # each ankle ends the last step where the gait put it
                end = 0.5 * self.step_length(self._step)
                self._start = [-end if leg == self._step % 2 else end for leg in (0, 1)]
            self._z0 = list(ankle_z)
            self._step = k
        half = 0.5 * self.step_length(k)
        land = self.surface + ANKLE_HEIGHT
        top = land + self.lift
        q = np.empty(6)
        for leg in (0, 1):
            x0 = self._start[leg]
            if leg == stance:
                x = x0 + (-half - x0) * s
                z = ankle_z[leg] - (land + self.hip_height)  # the hip over a standing foot
            else:
                # weight shift, slow pull-out, forward swing, set-down (fractions of the step)
                p = self.phases
                x = _ease(x0, half, s, p[1], p[3])
                if s < p[2]:
                    z = _ease(self._z0[leg], top, s, p[0], p[2]) - hip_z
                else:
                    z = _ease(top, land, s, p[2], p[4]) - hip_z
            r = math.hypot(x, z)
            if r > 0.99 * (THIGH + SHANK):  # keep the knee bent
                x, z = x * 0.99 * (THIGH + SHANK) / r, z * 0.99 * (THIGH + SHANK) / r
            q1, q2 = _leg_ik(x, z)
            q[3 * leg : 3 * leg + 3] = (q1, q2, -(q1 + q2) - pitch)
        return q, k, stance

    def __call__(self, data: mujoco.MjData) -> tuple[int, int]:
        """Write joint targets into ``data.ctrl`` (the servos); returns (step index, stance leg)."""
        pitch = float(data.qpos[self._pitch])
        hip_z = float(data.xpos[self._hip_body, 2])
        left, right = (float(data.xpos[b, 2]) for b in self._foot_bodies)
        q_des, k, stance = self.targets(float(data.time), pitch, hip_z, (left, right))
        data.ctrl[:] = np.clip(q_des, self._lo, self._hi)
        return k, stance

    def initial_pose(
        self, data: mujoco.MjData, *, surface: float = 0.0, clearance: float = 0.001
    ) -> None:
        """Set a standing pose with both soles ``clearance`` above the mud surface [m]."""
        q1, q2 = _leg_ik(0.0, -self.hip_height)
        data.qpos[:] = 0.0
        data.qvel[:] = 0.0
        data.qpos[self._qadr] = [q1, q2, -(q1 + q2)] * 2
        z0 = float(self.model.body("torso").pos[2])
        data.qpos[int(self.model.jnt_qposadr[self.model.joint("rootz").id])] = (
            surface + clearance + self.hip_height + ANKLE_HEIGHT - z0
        )
        _mujoco().mj_forward(self.model, data)


def walk(
    foot: Foot,
    mud: Mud | MudTerrain,
    *,
    seconds: float = 10.0,
    dt: float = 1e-3,
    speed: float = 0.1,
    step_time: float = 1.0,
    bottom: float = 0.15,
    backend: str = "auto",
    frames: int = 0,
    progress: Callable[[float], None] | None = None,
    strict: bool = False,
    **removed: object,
) -> WalkResult:
    """Walk the biped in mud for ``seconds``; its energy, sinking and suction (:class:`WalkResult`).

    Parameters
    ----------
    foot : Foot
        The foot on both legs (any mudrft foot, including ``MorphingFoot``).
    mud : Mud or MudTerrain
        The mud.
    seconds : float, keyword-only
        Simulated time [s], at least one physics step ``dt``.
    dt : float, keyword-only
        Physics time step [s].
    speed : float, keyword-only
        Walking speed command [m/s].
    step_time : float, keyword-only
        Duration of a step [s], at least :data:`MIN_STEP_SAMPLES` physics steps.
    bottom : float, keyword-only
        Depth of the rigid bed under the mud [m].
    backend : {"auto", "numba"}, keyword-only
        The coupling's backend: the compiled one (D68a) either way.
    frames : int, keyword-only
        Number of offscreen images to render along the walk (needs a working OpenGL, e.g.
        ``MUJOCO_GL=egl``; silently none when rendering fails).
    progress : callable or None, keyword-only
        Called with the fraction done, about 20 times.
    strict : bool, keyword-only
        Raise a :class:`~mudrft.MudrftError` instead of warning
        (:class:`~mudrft.trajectories.BuriedFootWarning`, once a run) when a foot sinks
        deeper than it is tall.
    """
    from .mujoco import attach
    from .mujoco.options import check_removed

    check_removed("walk", removed)
    mj = _mujoco()
    check_positive("seconds", seconds, unit="s")
    check_positive("dt", dt, unit="s")
    if dt > MAX_DT:
        raise MudrftError(f"dt must be <= {MAX_DT} s for the biped, got {plain(dt)}")
    check_positive("step_time", step_time, unit="s")
    if step_time < MIN_STEP_SAMPLES * dt:
        raise MudrftError(
            f"step_time must span at least {MIN_STEP_SAMPLES} physics steps (>= "
            f"{plain(MIN_STEP_SAMPLES * dt)} s at dt = {plain(dt)} s), got {plain(step_time)} s"
        )
    if seconds < dt:  # no step to walk
        raise MudrftError(
            f"seconds must be at least one physics step (dt = {plain(dt)} s), got {plain(seconds)} s"
        )
    check_samples(
        f"walk: {float(seconds):g} s at dt = {float(dt):g} s",
        seconds / dt,
        hint="use a larger dt or fewer seconds",
    )
    n = round(seconds / dt)
    model = biped_model(foot, bottom=bottom, timestep=dt)
    data = mj.MjData(model)
    ctrl = GaitController(model, speed=speed, step_time=step_time)
    ctrl.initial_pose(data)
    coupling = attach(model, list(BIPED_FEET), mud, feet=foot, backend=backend)
    coupling.reset(data)
    torso = model.body("torso").id
    x_start, z_start = data.xpos[torso, (0, 2)].tolist()
    rows = np.zeros((n, len(WALK_COLUMNS)))
    renderer = _renderer(model) if frames > 0 else None
    marks = set(np.linspace(0, n - 1, frames).astype(int).tolist())  # the frames' steps
    images: list[np.ndarray] = []
    energy = abs_energy = 0.0
    fell = False
    every = max(n // 20, 1)
    k = 0
    # the walk warns of a buried foot once, after the run (strict refuses): not the coupling
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", BuriedFootWarning)
        for k in range(n):
            step, _stance = ctrl(data)
            out = coupling.step(data)
            # joint torques times joint velocities, joint by joint (D69)
            pj = data.actuator_force * data.qvel[ctrl._dadr]
            power = float(pj.sum())
            energy += float(np.maximum(pj, 0.0).sum()) * dt
            abs_energy += float(np.abs(pj).sum()) * dt
            x, z = data.xpos[torso, (0, 2)].tolist()
            pitch = float(data.qpos[ctrl._pitch])
            rows[k, :4] = data.time, x, z, pitch
            rows[k, 4:6] = out.depth[:2]
            rows[k, 6:10] = out.force[:2, (0, 2)].ravel()  # left Fx, Fz, right Fx, Fz
            rows[k, 10:] = power, energy, abs_energy, out.tip[0, 0], out.tip[1, 0], step
            if renderer is not None and k in marks:
                renderer.update_scene(data, camera="side")
                images.append(renderer.render().copy())
            if not (math.isfinite(z) and math.isfinite(x)) or z < 0.5 * z_start or abs(pitch) > 1.0:
                fell = True
                break
            if progress is not None and k % every == 0:
                progress(k / n)
    rows = rows[: k + 1]
    table = {c: rows[:, i] for i, c in enumerate(WALK_COLUMNS)}
    deepest = float(np.nanmax(rows[:, 4:6])) if rows.size else 0.0
    check_unburied(
        getattr(foot, "name", type(foot).__name__),
        float(getattr(foot, "height", math.inf)),
        deepest,
        how="walk: a foot sank",
        strict=bool(strict),
        hint="; a firmer mud (lower water content) or a larger foot keeps it within its height",
    )
    weight = float(np.sum(model.body_mass) * -model.opt.gravity[2])
    max_suction = float(max(0.0, -min(table["left_Fz [N]"].min(), table["right_Fz [N]"].min())))
    steps = _per_step(table)
    n_steps = len(steps["step"])

    def mean(column: str) -> float:  # over the complete gait steps, NaN without one
        return float(np.mean(steps[column])) if n_steps else math.nan

    x_end = table["x [m]"][-1]
    summary = {
        "fell": bool(fell),
        "distance [m]": float(x_end - x_start) if math.isfinite(x_end) else math.nan,
        "energy_per_step [J]": mean("energy [J]"),
        "absolute_work_per_step [J]": mean("absolute_work [J]"),
        "mean_slip [m]": mean("slip [m]"),
        "shank_in_mud_steps": int(np.sum(steps["shank_in_mud"])),
        "weight [N]": weight,
        "mean_sinking [m]": mean("sinking [m]"),
        "max_suction [N]": max_suction,
        "max_suction_over_weight": max_suction / weight,
        "steps": n_steps,
        "seconds": float(table["time [s]"][-1]),
        "dt [s]": float(dt),
        "speed_command [m/s]": float(speed),
        "step_time [s]": float(step_time),
        "mean_speed [m/s]": float((x_end - x_start) / max(table["time [s]"][-1], 1e-12)),
        "min_torso_height [m]": float(table["z [m]"].min()),
        "foot": getattr(foot, "name", type(foot).__name__),
        "bottom [m]": float(bottom),
    }
    if renderer is not None:
        renderer.close()
    return WalkResult(table=table, steps=steps, summary=summary, frames=images)
