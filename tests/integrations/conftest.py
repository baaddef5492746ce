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

    Two findings of the suite appear only from a MuJoCo release on
    (measured): the 2 ms walk's suction spike from 3.5 (3.3.6 and 3.4.0 converge)."""
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


_LEG = """<mujoco><option timestep="{dt}" gravity="0 0 -3.639" integrator="{integrator}"/><worldbody>
  <body name="base" pos="0 0 0.25"><freejoint/>
    <geom type="box" size="0.05 0.05 0.03" mass="1.6363"/>
    <body name="thigh" pos="0 0 -0.05"><joint type="hinge" axis="-0.6071 -0.1164 0.7860"/>
      <geom type="capsule" fromto="0 0 0 0 0 -0.1" size="0.015" mass="0.9067"/>
      <body name="shank" pos="0 0 -0.1"><joint type="hinge" axis="0.0360 0.0251 0.9990"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.1" size="0.012" mass="0.3930"/>
        <body name="foot" pos="0 0 -0.11"><joint type="hinge" axis="0.9038 -0.3401 0.2597"/>
          <geom name="sole" type="box" size="0.03 0.04 0.01" mass="0.3554"/>
        </body></body></body></body></worldbody></mujoco>"""


def thrown_leg(dt: float = 0.002, integrator: str = "implicitfast") -> tuple[object, object]:
    """A random leg of the search of D150 (seed 387), model and data: a free base, hinges on
    random axes, a box foot ("sole") 5 mm into the mud, thrown at up to 18 rad/s."""
    model = mujoco.MjModel.from_xml_string(_LEG.format(dt=dt, integrator=integrator))
    data = mujoco.MjData(model)
    data.qvel[:9] = [6.1017, 4.246, -1.0, 1.6234, 5.7705, 4.2251, -1.4605, -1.5018, 1.6873]
    mujoco.mj_forward(model, data)
    data.qpos[2] -= data.geom_xpos[model.geom("sole").id][2] - 0.005
    mujoco.mj_forward(model, data)
    return model, data
