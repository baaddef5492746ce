r"""Prescribed motions of the foot's tip: the paper's plate tests E1-E4 and a gait cycle."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ._validation import (
    MudrftError,
    PlausibilityWarning,
    check_choice,
    check_finite,
    check_increasing,
    check_samples,
    nonnegative_number,
    number_in_range,
    positive_number,
    warn_implausible,
    warn_plausibility,
)

__all__ = [
    "FOOT_HEIGHT", "GAIT_SPEEDS", "MIN_GAIT_STEPS", "STANCE_DEPTH", "STRIDE_LENGTH",
    "BuriedFootWarning", "Trajectory", "check_unburied", "gait", "plate_intrusion",
]  # fmt: skip

#: The paper's gait speeds [m/s] (Sec. IV-A).
GAIT_SPEEDS = {"slow": 0.13, "medium": 0.20, "fast": 0.26}
#: Stride length of :func:`gait` [m]: one cycle lasts STRIDE_LENGTH / speed (decision D10).
STRIDE_LENGTH = 0.13
#: Height of the paper's three fixed feet, :math:`h_F` = 26 mm (Sec. IV-A) [m].
FOOT_HEIGHT = 0.026
#: Deepest tip depth of :func:`gait` [m] (decision D10): within :data:`FOOT_HEIGHT`, as the
#: closed forms (12)-(14) assume a foot that is not buried.
STANCE_DEPTH = 0.02
#: Fewest steps of ``dt`` :func:`gait` accepts in one cycle [-].
MIN_GAIT_STEPS = 20


class BuriedFootWarning(PlausibilityWarning):
    """A foot was pushed deeper than its own height: the mud closes over its top, which the
    model does not describe (decision D26)."""


def check_unburied(
    foot: str, height: float, depth: float, *, how: str, strict: bool, hint: str | None = None,
) -> None:  # fmt: skip
    """Warn (:class:`BuriedFootWarning`), or raise under ``strict``, when the deepest tip
    ``depth`` [m] exceeds the foot's ``height`` [m]; the other arguments word the message."""
    if not depth > height * (1 + 1e-9):
        return
    if hint is None:
        hint = f"; keep the tip within the foot's height (mudrft.gait's stance: {STANCE_DEPTH} m)"
    message = (
        f"{how} {depth:.3g} m deep, deeper than the {foot} foot is tall ({height:.3g} m): the "
        "mud closes over it, and the model gives the force of the foot alone, without the "
        f"mud on its top or on the leg (decision D26){hint}"
    )
    if strict:
        raise MudrftError(f"strict: {message}")
    warn_plausibility(message, BuriedFootWarning)


def _check_velocity(t: np.ndarray, p: np.ndarray, v: np.ndarray) -> None:
    """Warn when the velocity [m/s] is not the rate of the position [m] (a flipped sign, mm/s):
    each step's mean velocity must lie between its ends', up to a quarter of the extent."""
    dt, dp = np.diff(t)[:, None], np.diff(p, axis=0)
    lo, hi = np.minimum(v[:-1], v[1:]) * dt, np.maximum(v[:-1], v[1:]) * dt
    off = np.maximum(lo - dp, 0.0) + np.maximum(dp - hi, 0.0)
    # in the air (z >= 0 at both ends) a path may jump
    off = off[(p[:-1, 2] < 0.0) | (p[1:, 2] < 0.0)].sum(axis=0)  # per axis [m]
    axis = int(np.argmax(off))
    extent = float(np.ptp(p, axis=0).max())
    if off[axis] > max(0.25 * extent, 1e-6):
        warn_plausibility(
            f"Trajectory: the velocity is not the rate of the position: along {'xyz'[axis]} "
            f"they disagree by {off[axis]:.3g} m over a path that spans {extent:.3g} m; "
            "velocity must be d(position)/dt in m/s (Trajectory.from_positions computes it)"
        )


@dataclass(frozen=True, eq=False)
class Trajectory:
    """Path of the foot tip in the world frame: strictly increasing ``time`` (n,) [s],
    ``position`` (n, 3) [m] (z < 0 below the mud surface), ``velocity`` (n, 3) [m/s], a
    ``name`` and the protocol's ``meta`` (plate angle [rad], direction, ...)."""

    time: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    name: str = "trajectory"
    meta: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        t = check_increasing("time", self.time)
        p = check_finite("position", self.position)
        v = check_finite("velocity", self.velocity)
        if t.size < 2:
            raise MudrftError(f"time must have at least 2 samples, got {t.size}")
        for name, a in (("position", p), ("velocity", v)):
            if a.shape != (t.size, 3):
                raise MudrftError(
                    f"{name} must have shape ({t.size}, 3) to match time, got {a.shape}"
                )
        if not isinstance(self.name, str):
            raise MudrftError(f"name must be a string, got {self.name!r}")
        if not isinstance(self.meta, dict):
            raise MudrftError(f"meta must be a dict, got {type(self.meta).__name__}")
        for name, value in (("time", t), ("position", p), ("velocity", v)):
            object.__setattr__(self, name, value)
        _check_velocity(t, p, v)

    def __repr__(self) -> str:
        return (
            f"Trajectory(name={self.name!r}, samples={self.time.size}, "
            f"duration={self.time[-1] - self.time[0]:.4g} s, "
            f"lowest_z={float(self.position[:, 2].min()):.4g} m)"
        )

    @classmethod
    def from_positions(cls, time: np.ndarray, position: np.ndarray, **kw: object) -> Trajectory:
        """A trajectory of positions [m] at ``time`` [s]; the velocity of sample k is the rate
        over the step that ends there [m/s] (sample 0 takes the first step's)."""
        t, p = check_increasing("time", time), check_finite("position", position)
        if p.shape != (t.size, 3):
            raise MudrftError(f"position must have shape ({t.size}, 3), got {p.shape}")
        rate = np.diff(p, axis=0) / np.diff(t)[:, None]
        v = np.concatenate([rate[:1], rate]) if rate.size else np.zeros_like(p)
        return cls(time=t, position=p, velocity=v, **kw)  # type: ignore[arg-type]

    @property
    def depth(self) -> np.ndarray:
        """Tip depth below the mud surface [m], >= 0."""
        return np.maximum(-self.position[:, 2], 0.0)

    @property
    def duration(self) -> float:
        """Duration [s]."""
        return float(self.time[-1] - self.time[0])

    def __len__(self) -> int:
        return int(self.time.size)


def plate_intrusion(
    depth: float = 0.03, speed: float = 0.02, hold: float = 1.0, angle: float = 0.0,
    direction: str = "vertical", *, dt: float = 1e-3, rest: float = 0.5,
) -> Trajectory:  # fmt: skip
    """The paper's plate test (E1-E4, Sec. IV-A): intrude, hold, retract at the same speed.

    Parameters
    ----------
    depth, speed : float
        Intrusion displacement [m] (vertical: below the surface; horizontal: travel) and
        speed, also of the retraction [m/s].
    hold : float
        Time at rest between intrusion and retraction [s].
    angle : float
        Penetration angle of the plate [rad], 0 to pi/2: between plate normal and motion.
    direction : {"vertical", "horizontal"}
        Vertical (along -z) or horizontal (along +x) intrusion.
    dt : float, keyword-only
        Sample spacing [s].
    rest : float, keyword-only
        Time at rest after the retraction [s].

    Returns
    -------
    Trajectory
        With ``meta`` holding the protocol and the intrusion ``"displacement"`` [m].

    Examples
    --------
    >>> tr = plate_intrusion(depth=0.03, speed=0.02, hold=1.0)
    >>> round(float(tr.depth.max()), 4), round(tr.duration, 3)
    (0.03, 4.5)
    """
    depth = positive_number("depth", depth, unit="m")
    speed = positive_number("speed", speed, unit="m/s")
    dt = positive_number("dt", dt, unit="s")
    hold = nonnegative_number("hold", hold, unit="s")
    rest = nonnegative_number("rest", rest, unit="s")
    angle = number_in_range("angle", angle, 0.0, np.pi / 2, unit="rad")  # fmt: skip
    check_choice("direction", direction, ("vertical", "horizontal"))
    warn_implausible(
        "plate_intrusion: a depth of", depth, (0.0, 1.0), unit="m", hint="depth is in metres (30 mm = 0.03)"
    )  # fmt: skip
    t_in = depth / speed
    t_total = 2 * t_in + hold + rest
    what = f"plate_intrusion: a {t_total:.3g} s test at dt = {float(dt):g} s"
    check_samples(what, t_total / dt + 1, hint="use a larger dt")
    n = int(np.ceil(t_total / dt)) + 1
    t = np.linspace(0.0, t_total, n)
    t = np.unique(np.concatenate([t, [t_in, t_in + hold, 2 * t_in + hold]]))
    out = np.maximum(depth - speed * (t - t_in - hold), 0.0)
    q = np.select([t < t_in, t < t_in + hold], [speed * t, depth], out)
    # each sample carries the rate of the step that ends there
    qd = np.select([t <= t_in, t <= t_in + hold, t <= 2 * t_in + hold], [speed, 0.0, -speed], 0.0)
    pos, vel = np.zeros((t.size, 3)), np.zeros((t.size, 3))
    if direction == "vertical":
        pos[:, 2], vel[:, 2] = -q, -qd
    else:
        pos[:, 0], vel[:, 0] = q, qd
    meta = {
        "angle": float(angle), "direction": direction, "depth": float(depth),
        "speed": float(speed), "hold": float(hold), "t_retract": float(t_in + hold),
        "displacement": q,
    }  # fmt: skip
    name = f"plate {direction} intrusion"
    return Trajectory(time=t, position=pos, velocity=vel, name=name, meta=meta)


def gait(
    speed: float = 0.2, *, depth: float = STANCE_DEPTH, stride: float = STRIDE_LENGTH,
    slip: float = 0.3, sway: float = 0.15, lift: float = 0.02, dt: float = 1e-3,
) -> Trajectory:  # fmt: skip
    r"""One stepping cycle of the foot tip at a gait speed (half stance, half swing).

    The paper gives the gait speeds but not the foot path (decision D10). The cycle lasts
    :math:`T=S/v` (stride over speed); with phase :math:`s=t/T` the tip sinks to depth
    :math:`D` along :math:`d=\tfrac{D}{2}(1-\cos 2\pi s)` in the stance
    (:math:`s\le\tfrac12`), is pulled out and lifted to :math:`h` along
    :math:`z=-D+\tfrac{D+h}{2}(1-\cos 2\pi(s-\tfrac12))` in the swing, and slips forward
    and sways sideways, :math:`x=\rho S(1-\cos\pi s)/2`, :math:`y=\rho_y S\sin(\pi s)/2`.

    Parameters
    ----------
    speed : float
        Gait speed [m/s].
    depth, stride : float, keyword-only
        Deepest tip depth and stride length [m].
    slip, sway : float, keyword-only
        Forward slip and lateral sway as fractions of the stride [-].
    lift : float, keyword-only
        Height of the tip above the surface at the end of the swing [m].
    dt : float, keyword-only
        Sample spacing [s]; at most :math:`T/20` (:data:`MIN_GAIT_STEPS`).

    Examples
    --------
    >>> tr = gait(speed=0.2)
    >>> round(tr.duration, 3), round(float(tr.depth.max()), 4)
    (0.65, 0.02)
    """
    speed = positive_number("speed", speed, unit="m/s")
    depth = positive_number("depth", depth, unit="m")
    stride = positive_number("stride", stride, unit="m")
    dt = positive_number("dt", dt, unit="s")
    slip, sway = (number_in_range(n, v, 0.0, 1.0) for n, v in (("slip", slip), ("sway", sway)))  # fmt: skip
    lift = nonnegative_number("lift", lift, unit="m")
    for what, value, plausible, unit, hint in (
        ("a stance depth of", depth, (0.0, 1.0), "m", "depth is in metres (20 mm = 0.02)"),
        ("a lift of", lift, (0.0, 1.0), "m", "lift is in metres (10 mm = 0.01)"),
        ("a stride of", stride, (0.0, 5.0), "m", "stride is in metres (130 mm = 0.13)"),
        ("a speed of", speed, (0.0, 10.0), "m/s", "speed is in m/s (200 mm/s = 0.2)"),
    ):
        warn_implausible(f"gait: {what}", value, plausible, unit=unit, hint=hint)
    T = stride / speed
    cycle = f"one {T:.3g} s cycle (stride {float(stride):g} m / speed {float(speed):g} m/s)"
    faster = "use a larger dt or a higher speed"
    check_samples(f"gait: {cycle} at dt = {float(dt):g} s", T / dt + 1, hint=faster)
    if not T / dt >= MIN_GAIT_STEPS:
        raise MudrftError(
            f"gait: dt = {float(dt):g} s cuts {cycle} into {T / dt:.3g} steps; at least "
            f"{MIN_GAIT_STEPS} are needed: use dt <= {T / MIN_GAIT_STEPS:.3g} s or a lower speed"
        )
    n = int(np.ceil(T / dt)) + 1
    t = np.linspace(0.0, T, n)
    s = t / T
    z = np.where(
        s <= 0.5,
        -0.5 * depth * (1 - np.cos(2 * np.pi * s)),
        -depth + 0.5 * (depth + lift) * (1 - np.cos(2 * np.pi * (s - 0.5))),
    )
    x = 0.5 * slip * stride * (1 - np.cos(np.pi * s))
    y = 0.5 * sway * stride * np.sin(np.pi * s)
    meta = {"speed": float(speed), "period": T, "depth": float(depth), "stride": float(stride)}
    path = np.stack([x, y, z], 1)
    return Trajectory.from_positions(t, path, name=f"gait {speed:g} m/s", meta=meta)
