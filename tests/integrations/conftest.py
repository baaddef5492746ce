"""Small MuJoCo models shared by the coupling tests (skipped without mujoco)."""

from __future__ import annotations

import numpy as np

try:  # the test modules skip themselves without mujoco (pytest.importorskip)
    import mujoco
except ImportError:  # pragma: no cover - depends on the environment
    mujoco = None

G = 9.81  # MuJoCo's default gravity [m/s^2]


def mujoco_at_least(major: int, minor: int) -> bool:
    """Whether the installed MuJoCo is ``major.minor`` or later (False without MuJoCo).

    Two failures the suite documents as strict xfails appear only from a MuJoCo release on
    (measured, D149): the 2 ms walk's suction spike from 3.5 (3.3.6 and 3.4.0 converge),
    the RK4 energy gain from 4.0 (3.3.6, 3.10 and 3.17 lose energy)."""
    if mujoco is None:
        return False
    parts = [int(p) for p in mujoco.__version__.split(".")[:2]]
    return (parts[0], parts[1]) >= (major, minor)


def box_foot_model(
    *,
    mass: float = 1.5,
    half: tuple[float, float, float] = (0.0325, 0.04, 0.013),
    dt: float = 1e-3,
    height: float = 0.0,
) -> object:
    """A free box foot (65 x 80 x 26 mm by default) whose sole is ``height`` above z = 0."""
    hx, hy, hz = half
    xml = f"""<mujoco><option timestep="{dt}"/><worldbody>
      <body name="foot" pos="0 0 {hz + height}"><freejoint/>
        <geom type="box" size="{hx} {hy} {hz}" mass="{mass}"/></body></worldbody></mujoco>"""
    return mujoco.MjModel.from_xml_string(xml)


def kinematic_foot_model(*, yaw: float = 0.0, dt: float = 1e-3) -> object:
    """A box foot on x, y, z slide joints (driven kinematically), yawed by ``yaw`` [rad]."""
    c, s = np.cos(yaw / 2), np.sin(yaw / 2)
    xml = f"""<mujoco><option timestep="{dt}" gravity="0 0 0"/><worldbody>
      <body name="foot" pos="0 0 0.013" quat="{c} 0 0 {s}">
        <joint name="x" type="slide" axis="{np.cos(yaw)} {-np.sin(yaw)} 0"/>
        <joint name="y" type="slide" axis="{np.sin(yaw)} {np.cos(yaw)} 0"/>
        <joint name="z" type="slide" axis="0 0 1"/>
        <geom type="box" size="0.0325 0.04 0.013" mass="0.5"/></body></worldbody></mujoco>"""
    return mujoco.MjModel.from_xml_string(xml)


def mechanical_energy(model: object, data: object) -> float:
    """Kinetic + gravitational potential energy of the whole model [J] (MuJoCo's own)."""
    model.opt.enableflags |= int(mujoco.mjtEnableBit.mjENBL_ENERGY)  # type: ignore[attr-defined]
    mujoco.mj_forward(model, data)
    return float(data.energy[0] + data.energy[1])  # type: ignore[attr-defined]


def energy_rise(model: object, data: object, step: object, steps: int) -> tuple[float, float]:
    """Largest rise of :func:`mechanical_energy` above its start over ``steps`` calls of
    ``step()`` [J], and the start [J]."""
    e0 = mechanical_energy(model, data)
    rise = -np.inf
    for _ in range(steps):
        step()  # type: ignore[operator]
        rise = max(rise, mechanical_energy(model, data) - e0)
    return float(rise), e0
