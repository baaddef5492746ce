r"""The mud walker: the project's planar biped in mud, its observation, reward and end, and
``mudrft/MudWalker-v0`` on the CPU (:class:`MudWalkerEnv`).

One definition, with ``xp`` = numpy or ``jax.numpy``, for :class:`MudWalkerEnv` (one robot,
MuJoCo on the CPU with the CPU coupling) and :class:`~mudrft.envs.MudWalkerVectorEnv`
(many, MJX).
The robot is :func:`mudrft.integrations.walk.biped_model` (10 kg, hip, knee and ankle PD
servos) with MuJoCo's contacts off: the bed under the mud is the coupling's (D67).

*Action* (6,) in [-1, 1]: joint targets of the servos, ``stand + action_scale * action``
[rad] (hips, knees, ankles; left then right), clipped to the servos' ranges.

*Observation* (23,) float32 (``observe="privileged"``), or its first 17 entries, what the
robot senses of itself (``observe="proprioceptive"``):

====== =====================================================================
0-7    torso height above its start [m], torso pitch [rad], six joint angles [rad]
8-16   the nine joint velocities [m/s, rad/s], clipped to +-10
17-18  sinking of each foot (depth of its lowest point) [cm]
19-22  mud force on each foot, (F_x, F_z) over the robot's weight [-] (suction: F_z < 0)
====== =====================================================================

*Reward* per control step: forward speed of the torso [m/s] times
``forward_reward_weight``, minus ``ctrl_cost_weight`` times the squared action, plus
``healthy_reward`` while healthy (Gymnasium's Walker2d recipe).

*End*: the torso sinks below 60 % of its start height, pitches past 1 rad, or the state
is not finite (``info["unstable"]``); truncation at 1000 control steps.
"""

from __future__ import annotations

import difflib
import importlib.util
import os
from collections.abc import Mapping
from dataclasses import dataclass, fields
from typing import TYPE_CHECKING, Any

import gymnasium
import numpy as np
from numpy.typing import NDArray

import mudrft

from .._typing import ArrayLike, Namespace, XpArray
from .._validation import (
    MudrftError,
    check_choice,
    check_finite,
    check_number,
    nonnegative_number,
    positive_int,
    positive_number,
    set_number,
)

if TYPE_CHECKING:
    import mujoco

    from ..feet.base import Foot
    from ..parameters.base import Mud

__all__ = [
    "ACTION_SIZE", "FEET", "MAX_CONTROL_PERIOD", "NOT_RUNNING", "OBS_SIZE", "OBS_SIZES",
    "MudWalkerEnv", "WalkerConfig", "WalkerLayout", "check_action", "check_reset", "healthy",
    "make_walker", "observation", "reward", "walker_config", "walker_layout",
]  # fmt: skip

#: Foot shapes by name (the paper's feet that both couplings support).
FEET = ("flat", "semi-cylinder", "semi-sphere")
OBS_SIZE = 23
#: The observation's length by ``observe``.
OBS_SIZES = {"privileged": OBS_SIZE, "proprioceptive": 17}
#: Longest time one action may be held, ``frame_skip * dt`` [s]: the walker falls sooner.
MAX_CONTROL_PERIOD = 1.0
ACTION_SIZE = 6


@dataclass(frozen=True)
class WalkerConfig:
    """Options of the mud walker, validated here once.

    ``foot``: ``"flat"``, ``"semi-cylinder"``, ``"semi-sphere"`` or a mudrft foot;
    ``water_content`` [-] of the paper's mud; ``dt`` the physics step [s]; ``frame_skip``
    physics steps per control step; ``forward_reward_weight``, ``ctrl_cost_weight``,
    ``healthy_reward`` the reward terms; ``action_scale`` the joint target range about the
    standing pose [rad]; ``reset_noise_scale`` the half-width of the reset noise on joint
    angles [rad] and velocities; ``bottom`` the depth of the rigid bed under the mud [m];
    ``field`` a :class:`~mudrft.MudField` (or the path of its TOML spec) in place of the
    one mud of ``water_content``, its rigid cells boxes MuJoCo's contact holds the feet on
    (:func:`~mudrft.integrations.mujoco.add_rigid_cells`); ``randomize`` the keywords of
    :meth:`~mudrft.MudField.randomized`, a new draw of the field at each reset (from the
    reset's seed); ``observe`` ``"privileged"`` or ``"proprioceptive"`` (the module
    docstring); ``ground`` ``"mud"``, or ``"rigid"``: MuJoCo's contact with a floor at the
    surface and no mud (to train a policy for comparison).
    """

    foot: str | Foot = "flat"
    water_content: float = 0.25
    dt: float = 2e-3
    frame_skip: int = 10
    forward_reward_weight: float = 1.0
    ctrl_cost_weight: float = 1e-3
    healthy_reward: float = 1.0
    action_scale: float = 0.5
    reset_noise_scale: float = 5e-3
    bottom: float = 0.15
    field: Any = None
    randomize: Any = None
    observe: str = "privileged"
    ground: str = "mud"

    def __post_init__(self) -> None:
        if isinstance(self.foot, str):
            if self.foot not in FEET:
                raise MudrftError(f"foot must be one of {FEET} or a mudrft foot, got {self.foot!r}")
        elif not hasattr(self.foot, "contact_force"):
            raise MudrftError(f"foot must be a name or a mudrft foot, got {self.foot!r}")
        w = check_number("water_content", check_finite("water_content", self.water_content))
        mudrft.paper_mud(w)  # a water content the paper's tables cover
        object.__setattr__(self, "dt", positive_number("dt", self.dt, unit="s"))
        if self.dt > 5e-3:
            raise MudrftError(f"dt must be <= 0.005 s for the walker, got {self.dt!r}")
        fs = positive_int("frame_skip", self.frame_skip)
        if fs * self.dt > MAX_CONTROL_PERIOD:
            raise MudrftError(
                f"frame_skip must hold an action for at most {MAX_CONTROL_PERIOD:g} s "
                f"(frame_skip * dt; the walker falls sooner), got {fs!r} steps of {self.dt!r} s"
            )
        for name in ("forward_reward_weight", "ctrl_cost_weight", "healthy_reward"):
            set_number(self, name, getattr(self, name))
        object.__setattr__(self, "action_scale", positive_number("action_scale", self.action_scale, unit="rad"))  # fmt: skip
        object.__setattr__(self, "reset_noise_scale", nonnegative_number("reset_noise_scale", self.reset_noise_scale, unit="rad"))  # fmt: skip
        object.__setattr__(self, "bottom", positive_number("bottom", self.bottom, unit="m"))
        check_choice("observe", self.observe, OBS_SIZES)
        check_choice("ground", self.ground, ("mud", "rigid"))
        f = self.field
        if f is not None and not isinstance(f, mudrft.MudField):
            if not isinstance(f, str | os.PathLike):
                raise MudrftError(f"field must be a MudField or the path of its TOML spec, got {f!r}")  # fmt: skip
            object.__setattr__(self, "field", mudrft.MudField.from_toml(f))
        if self.randomize is not None:
            if not isinstance(self.randomize, Mapping):
                raise MudrftError(f"randomize must be a mapping of MudField.randomized's keywords, got {self.randomize!r}")  # fmt: skip
            self.mud_field.randomized(0, **self.randomize)  # its keywords, checked now
        if self.ground == "rigid" and (self.field is not None or self.randomize is not None):
            raise MudrftError("ground='rigid' has no mud: field and randomize must be None")

    @property
    def mud_field(self) -> mudrft.MudField:
        """The field: :attr:`field`, or the one mud of :attr:`water_content` everywhere."""
        if self.field is not None:
            return self.field  # type: ignore[no-any-return]
        return mudrft.MudField({"mud": self.mud}, ["mud"], cell_size=1.0, border=1.0)

    @property
    def foot_object(self) -> Foot:
        """The mudrft foot."""
        return mudrft.feet.by_name(self.foot) if isinstance(self.foot, str) else self.foot

    @property
    def mud(self) -> Mud:
        """The paper's mud at :attr:`water_content`."""
        return mudrft.paper_mud(float(self.water_content))


def walker_config(options: dict[str, Any], *, own: tuple[str, ...] = ()) -> WalkerConfig:
    """``WalkerConfig(**options)``; an unknown option is named with the known ones and
    ``own``, the environment's own keywords."""
    known = list(dict.fromkeys([*own, *(f.name for f in fields(WalkerConfig))]))
    for key in options:
        if key not in known:
            near = difflib.get_close_matches(str(key), known, n=1)
            hint = f" (did you mean {near[0]!r}?)" if near else ""
            raise MudrftError(f"{key}: not an option of the mud walker{hint}; expected one of {', '.join(known)}")  # fmt: skip
    return WalkerConfig(**options)


@dataclass(frozen=True, eq=False)
class WalkerLayout:
    """The walker's MuJoCo model and where things are in it (numpy, made once)."""

    model: mujoco.MjModel
    qpos0: np.ndarray  # standing pose, soles 1 mm above the mud
    ctrl0: np.ndarray  # standing servo targets [rad]
    ctrl_low: np.ndarray
    ctrl_high: np.ndarray
    joint_qadr: np.ndarray
    joint_dadr: np.ndarray
    rootx: int
    rootz: int
    pitch: int
    torso: int
    torso_z0: float  # torso height at the start [m]
    weight: float  # [N]
    bodies: tuple[str, str]


def walker_layout(cfg: WalkerConfig) -> WalkerLayout:
    """Build the biped for ``cfg`` (contacts off: the bed is the coupling's, D67; a field
    with rigid regions: the feet touch the boxes of its rigid cells; on rigid ground, the
    bed is at the surface and MuJoCo's contact holds the feet)."""
    from ..integrations.mujoco import _mujoco
    from ..integrations.walk import BIPED_FEET, GaitController, biped_model

    mj = _mujoco()
    rigid = cfg.ground == "mud" and cfg.field is not None and cfg.field.has_rigid
    model = biped_model(
        None, bottom=float(cfg.bottom), timestep=float(cfg.dt), field=cfg.field if rigid else None
    )
    if cfg.ground == "rigid":
        model.geom_pos[model.geom("bottom").id, 2] = 0.0
    elif not rigid:  # rigid cells: the feet's contact with their boxes (add_rigid_cells)
        model.opt.disableflags |= int(mj.mjtDisableBit.mjDSBL_CONTACT)
    data = mj.MjData(model)
    gait = GaitController(model)
    gait.initial_pose(data)
    jq, torso = gait._qadr, int(model.body("torso").id)
    qadr = {n: int(model.jnt_qposadr[model.joint(n).id]) for n in ("rootx", "rootz")}
    return WalkerLayout(
        model=model, qpos0=np.array(data.qpos), ctrl0=np.array(data.qpos[jq]),
        ctrl_low=np.array(model.actuator_ctrlrange[:, 0]),
        ctrl_high=np.array(model.actuator_ctrlrange[:, 1]), joint_qadr=jq, joint_dadr=gait._dadr,
        rootx=qadr["rootx"], rootz=qadr["rootz"], pitch=gait._pitch, torso=torso,
        torso_z0=float(data.xpos[torso, 2]),
        weight=float(np.sum(model.body_mass) * -model.opt.gravity[2]),
        bodies=tuple(BIPED_FEET),  # type: ignore[arg-type]
    )  # fmt: skip


def check_reset(seed: object, options: object) -> int | None:
    """``reset``'s ``seed`` (None or an integer >= 0) as a Python int; no ``options`` (the
    mud and the foot are set when the environment is made)."""
    if options:
        raise MudrftError(
            f"options: reset takes none (the foot, the mud and the other options are set "
            f"when the environment is made), got {options!r}"
        )
    if seed is None:
        return None
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise MudrftError(f"seed must be None or an integer >= 0, got {seed!r}")
    return int(seed)


#: Why ``step`` is refused in each phase of an environment but "running".
NOT_RUNNING = {
    "new": "call reset() before step()",
    "ended": "the episode has terminated: call reset() before step()",
    "closed": "the environment is closed: make a new one",
}


class _CpuEnv(gymnasium.Env):  # type: ignore[misc]
    """What the CPU environments share: the phase (``"new"``, then ``"running"``,
    ``"ended"`` when terminated, or ``"closed"``) and a field drawn anew at each reset."""

    coupling: Any
    field: mudrft.MudField | None
    _depth: np.ndarray  # each foot's sinking [m] in the last step
    _force: np.ndarray  # each foot's mud force [N] in the last step
    _phase = "new"

    def _begin_reset(self, seed: object, options: dict[str, Any] | None) -> Any:
        """Check ``reset``'s arguments, refuse a closed environment and seed
        ``np_random``; a curriculum's next field, ``options={"field": f}``, else None."""
        given = None
        if isinstance(options, dict) and set(options) == {"field"}:
            given, options = options["field"], None
            if given is not None and self.field is None:
                raise MudrftError(
                    "options={'field': ...} needs an environment made with field= or randomize="
                )
        seed = check_reset(seed, options)
        if self._phase == "closed":
            raise MudrftError(NOT_RUNNING["closed"])
        gymnasium.Env.reset(self, seed=seed)
        return given

    def _draw_field(self, given: Any, base: mudrft.MudField, randomize: Any, model: Any) -> None:
        """Step the mud on ``given``, else on a draw of ``base`` with ``randomize``'s
        keywords (where given), its rigid cells' boxes in ``model`` following it."""
        if given is None and randomize is None:
            return
        self.field = given or base.randomized(self.np_random, **randomize)
        self.coupling.use_field(self.field)
        if base.has_rigid:
            from ..integrations.mujoco import set_rigid_cells

            set_rigid_cells(model, self.field)

    def _check_running(self) -> None:
        if self._phase != "running":  # before reset the robot lay at the origin, the mud unset
            raise MudrftError(NOT_RUNNING[self._phase])

    def _info(self, x0: float, x1: float, seconds: float, unstable: bool) -> dict[str, Any]:
        """A step's ``info``: the robot's move from ``x0`` to ``x1`` [m] in ``seconds``
        [s], and each foot's sinking and mud force."""
        return {
            "x_position": x1,
            "x_velocity": (x1 - x0) / seconds,
            "sinking [m]": self._depth.copy(),
            "mud_force [N]": self._force.copy(),
            "unstable": unstable,
        }

    def close(self) -> None:
        """Release the mud coupling's hold on MuJoCo's step; the environment steps no more."""
        self._phase = "closed"
        if self.coupling is not None:
            self.coupling.detach()


def check_action(action: ArrayLike, shape: tuple[int, ...]) -> np.ndarray:
    """The action as a finite float array of exactly ``shape``."""
    if np.iscomplexobj(action):  # numpy would drop the imaginary part with a warning
        raise MudrftError(f"action must be real numbers of shape {shape}, got complex values")
    try:
        a = np.asarray(action, dtype=float)
    except (TypeError, ValueError):
        raise MudrftError(f"action must be numbers of shape {shape}, got {action!r}") from None
    if a.shape != shape:
        raise MudrftError(f"action must have shape {shape}, got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise MudrftError("action must be finite, got NaN or inf")
    return a


def controls(lay: WalkerLayout, action: XpArray, scale: float, xp: Namespace = np) -> XpArray:
    """Servo targets [rad] of an action in [-1, 1] (clipped to the servos' ranges)."""
    a = xp.clip(action, -1.0, 1.0)
    return xp.clip(lay.ctrl0 + scale * a, lay.ctrl_low, lay.ctrl_high)


def observation(
    lay: WalkerLayout, qpos: XpArray, qvel: XpArray, depth: XpArray, force: XpArray,
    xp: Namespace = np, *, observe: str = "privileged",
) -> XpArray:  # fmt: skip
    """The observation (..., 23) of the module docstring from the state and the mud's
    last contact: ``depth`` (..., 2) [m], ``force`` (..., 2, 3) [N]; (..., 17) for
    ``observe="proprioceptive"``."""
    z = qpos[..., lay.rootz : lay.rootz + 1] - lay.qpos0[lay.rootz]
    pitch = qpos[..., lay.pitch : lay.pitch + 1]
    parts = [z, pitch, qpos[..., lay.joint_qadr], xp.clip(qvel, -10.0, 10.0)]
    if observe == "privileged":
        f = force[..., :, (0, 2)] / lay.weight
        parts += [depth / 0.01, f.reshape(*f.shape[:-2], 4)]
    return xp.concatenate(parts, axis=-1)


def healthy(lay: WalkerLayout, qpos: XpArray, xp: Namespace = np) -> XpArray:
    """True while the torso is above 60 % of its start height, pitched less than 1 rad,
    and the state is finite."""
    height = lay.torso_z0 + (qpos[..., lay.rootz] - lay.qpos0[lay.rootz])
    ok = (height > 0.6 * lay.torso_z0) & (xp.abs(qpos[..., lay.pitch]) < 1.0)
    return ok & xp.all(xp.isfinite(qpos), axis=-1)


def reward(
    cfg: WalkerConfig, x_before: XpArray, x_after: XpArray, action: XpArray, alive: XpArray,
    xp: Namespace = np,
) -> XpArray:  # fmt: skip
    """Forward speed times its weight, minus the control cost, plus the healthy reward."""
    speed = (x_after - x_before) / (cfg.dt * cfg.frame_skip)
    cost = cfg.ctrl_cost_weight * xp.sum(xp.clip(action, -1.0, 1.0) ** 2, axis=-1)
    return cfg.forward_reward_weight * speed - cost + cfg.healthy_reward * alive


class MudWalkerEnv(_CpuEnv):
    """The planar biped walking in mud (Gymnasium ``Env``; id ``mudrft/MudWalker-v0``).

    ``backend`` is the CPU coupling's (``"auto"`` or ``"numba"``: the compiled one);
    ``render_mode="rgb_array"`` renders the side camera offscreen (OpenGL needed); the
    other ``options`` are :class:`~mudrft.envs.walker.WalkerConfig`'s (field, observation,
    ground). ``info`` holds each foot's sinking and mud force.

    >>> import gymnasium, mudrft.envs
    >>> env = gymnasium.make("mudrft/MudWalker-v0", foot="semi-sphere", water_content=0.35)
    >>> obs, info = env.reset(seed=0)
    >>> obs.shape
    (23,)
    """

    metadata = {"render_modes": ["rgb_array"], "render_fps": 50}  # noqa: RUF012 (Gymnasium's attribute)

    def __init__(
        self, *, backend: str = "auto", render_mode: str | None = None, **options: Any
    ) -> None:
        from ..integrations.mujoco import _mujoco, attach

        if render_mode not in (None, "rgb_array"):
            raise MudrftError(
                f"render_mode must be None or 'rgb_array' ('human' through gymnasium.make), "
                f"got {render_mode!r}"
            )
        self.config = cfg = walker_config(options, own=("backend", "render_mode"))
        self.layout = walker_layout(cfg)
        self.render_mode = render_mode
        self.metadata = {**self.metadata, "render_fps": round(1.0 / (cfg.dt * cfg.frame_skip))}
        self._mj = _mujoco()
        m = self.layout.model
        self.data = self._mj.MjData(m)
        fielded = cfg.field is not None or cfg.randomize is not None
        self.field = self.base_field = cfg.mud_field if fielded else None
        self.coupling = None if cfg.ground == "rigid" else attach(
            m, list(self.layout.bodies), self.base_field or cfg.mud, feet=cfg.foot_object,
            bottom=cfg.bottom, backend=backend,
        )  # fmt: skip
        box = gymnasium.spaces.Box
        self.action_space = box(-1.0, 1.0, (ACTION_SIZE,), dtype=np.float32)
        self.observation_space = box(-np.inf, np.inf, (OBS_SIZES[cfg.observe],), dtype=np.float32)
        self._renderer: mujoco.Renderer | None = None
        self._depth, self._force = np.zeros(2), np.zeros((2, 3))

    def _obs(self) -> NDArray[np.float32]:
        d = self.data
        o = observation(
            self.layout, d.qpos, d.qvel, self._depth, self._force, observe=self.config.observe
        )
        return np.asarray(o, dtype=np.float32)

    def reset(
        self, *, seed: int | None = None, options: dict[str, Any] | None = None
    ) -> tuple[NDArray[np.float32], dict[str, Any]]:
        """Stand the biped 1 mm above the mud, with uniform noise on joints and velocities;
        the field is ``options={"field": f}`` (a curriculum's next, of the shape of the
        environment's), else drawn anew with ``randomize`` from ``seed``."""
        given = self._begin_reset(seed, options)
        lay, d, mj = self.layout, self.data, self._mj
        mj.mj_resetData(lay.model, d)
        noise = self.config.reset_noise_scale
        d.qpos[:] = lay.qpos0
        d.qpos[lay.joint_qadr] += self.np_random.uniform(-noise, noise, ACTION_SIZE)
        d.qvel[:] = self.np_random.uniform(-noise, noise, lay.model.nv)
        d.ctrl[:] = lay.ctrl0
        mj.mj_forward(lay.model, d)
        if self.base_field is not None:
            self._draw_field(given, self.base_field, self.config.randomize, lay.model)
        if self.coupling is not None:
            self.coupling.reset(d)
        self._depth, self._force = np.zeros(2), np.zeros((2, 3))
        self._phase = "running"
        return self._obs(), {"x_position": float(d.qpos[lay.rootx]), "field": self.field}

    def step(
        self, action: ArrayLike
    ) -> tuple[NDArray[np.float32], float, bool, bool, dict[str, Any]]:
        """One control step: ``frame_skip`` physics steps with the mud; an unstable step
        terminates the episode with ``info["unstable"] = True``."""
        lay, cfg, d, mj = self.layout, self.config, self.data, self._mj
        self._check_running()
        a = check_action(action, (ACTION_SIZE,))
        x0 = float(d.qpos[lay.rootx])
        d.ctrl[:] = controls(lay, a, cfg.action_scale)
        bad = [int(w) for w in (mj.mjtWarning.mjWARN_BADQPOS, mj.mjtWarning.mjWARN_BADQVEL,
                                mj.mjtWarning.mjWARN_BADQACC)]  # fmt: skip
        warned = int(d.warning.number[bad].sum())
        try:
            if self.coupling is None:  # rigid ground: MuJoCo's contact alone
                mj.mj_step(lay.model, d, nstep=cfg.frame_skip)
            else:
                out = self.coupling.step(d, cfg.frame_skip)
                self._depth, self._force = np.array(out.depth), np.array(out.force)
            unstable = int(d.warning.number[bad].sum()) > warned or not (
                np.isfinite(d.qpos).all() and np.isfinite(d.qvel).all()
            )
        except MudrftError:  # the coupling refused a diverged state
            unstable = True
        if unstable:  # keep the observation finite
            d.qpos[:] = np.nan_to_num(d.qpos)
            d.qvel[:] = 0.0
        ok = not unstable and bool(healthy(lay, d.qpos))
        self._phase = "running" if ok else "ended"
        x1 = float(d.qpos[lay.rootx])
        r = float(reward(cfg, x0, x1, a, float(ok)))
        return self._obs(), r, not ok, False, self._info(x0, x1, cfg.dt * cfg.frame_skip, unstable)

    def render(self) -> np.ndarray | None:
        """An RGB image of the side camera (``render_mode="rgb_array"``), else None."""
        if self.render_mode != "rgb_array":
            return None
        if self._renderer is None:
            from ..integrations.walk import _renderer

            self._renderer = _renderer(self.layout.model)
            if self._renderer is None:
                raise MudrftError(
                    "rendering needs OpenGL: set MUJOCO_GL=egl (or osmesa) before mujoco is "
                    "imported"
                )
        self._renderer.update_scene(self.data, camera="side")
        return np.asarray(self._renderer.render())

    def close(self) -> None:
        """Release the offscreen renderer, if one was made, and the mud coupling's hold on
        MuJoCo's step; the environment steps no more."""
        super().close()
        if self._renderer is not None:
            self._renderer.close()
            self._renderer = None


def make_walker(*, render_mode: str | None = None, **options: Any) -> gymnasium.Env:
    """The registered entry point: :class:`MudWalkerEnv`, or with ``render_mode="human"``
    its frames in a window (Gymnasium's ``HumanRendering``, which needs pygame)."""
    if render_mode != "human":
        return MudWalkerEnv(render_mode=render_mode, **options)
    if importlib.util.find_spec("pygame") is None:
        raise MudrftError(
            "render_mode='human' shows the frames with pygame, which is not installed: "
            "pip install pygame (Gymnasium's extra 'classic-control' has it), or use "
            "render_mode='rgb_array'"
        )
    return gymnasium.wrappers.HumanRendering(MudWalkerEnv(render_mode="rgb_array", **options))
