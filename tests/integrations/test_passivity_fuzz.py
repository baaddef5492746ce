"""A passivity search of the MuJoCo coupling, kept as tests: free bodies of every geom and
foot kind, in any pose, spinning up to 100 rad/s, on both backends, never gain energy from
the mud; and what the search found (docs/model.md, D65 and "A passivity search")."""

from __future__ import annotations

import numpy as np
import pytest

import mudrft

pytest.importorskip("mujoco")
from ._reference import attach
from .conftest import energy_rise, mechanical_energy, mujoco

# feet thrown, spun and dropped deep on purpose: their burial warning is not what is tested
pytestmark = pytest.mark.filterwarnings("ignore::mudrft.trajectories.BuriedFootWarning")

GEOMS = ("box", "sphere", "capsule", "cylinder", "mesh")
FEET = ("flat", "semi-cylinder", "semi-sphere", "morphing", "mesh-foot")
BACKENDS = ("numpy", "numba")


def _backend(backend: str) -> str:
    if backend == "numba":
        pytest.importorskip("numba")
    return backend


def _geom(kind: str, s: float) -> str:
    """A foot geom of size ``s`` [m] whose centre is 1 cm below the body's frame origin."""
    if kind == "box":
        return f'<geom type="box" size="{s} {1.2 * s} {0.4 * s}" pos="0 0 -0.01"/>'
    if kind == "sphere":
        return f'<geom type="sphere" size="{s}" pos="0 0 -0.01"/>'
    if kind in ("capsule", "cylinder"):
        return f'<geom type="{kind}" size="{0.6 * s} {s}" zaxis="1 0 0" pos="0 0 -0.01"/>'
    return '<geom type="mesh" mesh="sole" pos="0 0 -0.01"/>'


def _foot(kind: str):
    if kind in mudrft.feet.NAMES:  # flat, semi-cylinder, semi-sphere, morphing
        return mudrft.feet.by_name(kind)
    return mudrft.feet.SemiSphere().to_mesh(resolution=6)


def _release(kind: str, backend: str, seed: int, *, integrator: str | None = None):
    """A random free release (deterministic in ``seed``) without gravity.

    Isotropic inertia with the centre of mass at the frame origin, so that MuJoCo's Euler
    step alone conserves the body's energy at any spin (D62b); any orientation (upside
    down, on edge), lowest point 5 mm deep to 15 mm above the mud, moving at up to 2 m/s
    (downwards at 0.2 m/s at least)
    and spinning at up to 100 rad/s about any axis; 0.05-20 kg, dt 0.5-5 ms, Euler or
    implicitfast (or ``integrator``), W = 25/35/45 %, the ODE or the quasi-static
    evaluation, with or without a rigid bottom.
    """
    rng = np.random.default_rng(seed)
    mass = float(np.exp(rng.uniform(np.log(0.05), np.log(20.0))))
    s = float(rng.uniform(0.02, 0.04))
    inertia = mass * (rng.uniform(0.2, 1.5) * s) ** 2
    dt = float(rng.choice([5e-4, 1e-3, 2e-3, 5e-3]))
    integrator = str(rng.choice(["Euler", "implicitfast"])) if integrator is None else integrator
    quat = rng.normal(size=4)
    drop = rng.uniform(-0.005, 0.015)
    vel = rng.normal(size=3)
    vel *= rng.uniform(0.0, 2.0) / np.linalg.norm(vel)
    vel[2] = -abs(vel[2]) - 0.2  # into the mud, whatever else it does
    spin = rng.normal(size=3)
    spin *= rng.uniform(0.0, 100.0) / np.linalg.norm(spin)
    w = float(rng.choice([0.25, 0.35, 0.45]))
    quasi = bool(rng.random() < 0.5)
    bottom = float(rng.uniform(0.003, 0.03)) if rng.random() < 0.4 else None
    sole = rng.normal(size=(14, 3)) * [s, 1.2 * s, 0.6 * s]
    asset = '<asset><mesh name="sole" vertex="' + " ".join(map(str, sole.ravel())) + '"/></asset>'
    geom = _geom(kind, s) if kind in GEOMS else ""
    xml = f"""<mujoco><option timestep="{dt}" gravity="0 0 0" integrator="{integrator}"/>
      {asset}<worldbody><body name="foot" pos="0.3 -0.2 0.5"><freejoint/>
      <inertial pos="0 0 0" mass="{mass}" diaginertia="{inertia} {inertia} {inertia}"/>
      {geom}</body></worldbody></mujoco>"""
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    mud = mudrft.paper_mud(w)
    terrain = mudrft.MudTerrain(mud, thixotropy="quasi-static") if quasi else mud
    feet = None if kind in GEOMS else _foot(kind)
    coupling = attach(model, "foot", terrain, feet=feet, bottom=bottom, backend=backend)
    data.qpos[3:7] = quat / np.linalg.norm(quat)
    mujoco.mj_forward(model, data)
    R = data.xmat[1].reshape(3, 3)
    lowest = (data.xpos[1] + coupling.bodies[0].triangles.reshape(-1, 3) @ R.T)[:, 2].min()
    data.qpos[2] += drop - lowest
    data.qvel[:3] = vel
    data.qvel[3:6] = R.T @ spin  # a free joint's spin: body frame
    coupling.reset(data)
    return model, data, coupling


def _rise(model, data, coupling, seconds: float) -> tuple[float, float, int]:
    """Largest rise of kinetic + gravitational energy above its start [J], the start [J],
    and the steps with the foot in the mud."""
    e0 = mechanical_energy(model, data)
    rise, wet = -np.inf, 0
    for _ in range(round(seconds / model.opt.timestep)):
        out = coupling.step(data)
        wet += int(out.depth[0] > 0)
        rise = max(rise, mechanical_energy(model, data) - e0)
    return float(rise), e0, wet


#: Two releases of each kind and backend
SEEDS = (1, 2)


@pytest.mark.parametrize("seed", SEEDS)
@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("kind", GEOMS + FEET)
def test_a_free_body_of_any_kind_never_gains_energy_from_the_mud(kind, backend, seed):
    """Gravity off: the energy is kinetic only and MuJoCo's step conserves it without mud,
    so any rise is the coupling's. Tolerance 1e-9 of the start (round-off: the search's
    largest rise over 12,000 such releases was 2e-15 of the start, D62c)."""
    model, data, coupling = _release(kind, _backend(backend), seed)
    rise, e0, wet = _rise(model, data, coupling, 0.15)
    assert wet > 0  # the release met the mud
    assert rise <= 1e-9 * e0 + 1e-12, (rise, e0)


# -- D65: the compiled coupling's odometry read the wrong float of the mud state ------------


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_foot_yawing_in_the_mud_is_not_displaced_on_either_backend(backend):
    """A sphere 1 cm deep spinning about the vertical through its tip, 3.6 m from the world
    origin, has no horizontal displacement, so no horizontal force (D65).

    The compiled coupling took the vertical channel's suction stress (float 18 of the state
    row, in_mud before the quasi-static clocks moved it to float 24) for the flag; while
    the foot had no suction it restarted the tip's foot-frame position from the turned
    world position every step: 3.6 m x 2 mrad = 7 mm a step of spurious sliding."""
    xml = """<mujoco><option timestep="0.001" gravity="0 0 0"/><worldbody>
      <body name="foot" pos="3 -2 0.02"><joint name="yaw" type="hinge" axis="0 0 1"/>
        <geom type="sphere" size="0.03" mass="0.3"/></body></worldbody></mujoco>"""
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    coupling = attach(model, "foot", mudrft.paper_mud(0.25), backend=_backend(backend))
    coupling.reset(data)
    for k in range(200):
        data.qpos[0] = 2.0 * k * 1e-3
        data.qvel[0] = 2.0
        mujoco.mj_forward(model, data)
        out = coupling.apply(data)
        assert np.abs(out.force[0, :2]).max() < 1e-9  # round-off only
    assert out.force[0, 2] > 0


def _sphere_release(backend: str, *, mud: bool = True) -> tuple[float, float]:
    """The release the search found (seed 1087 of its sphere class): a 0.18 kg sphere
    whose centre of mass is 27 mm below its frame origin, tilted, sliding at 1.9 m/s and
    spinning at 54 rad/s, 1.6 mm above W = 35 % mud (quasi-static), 0.3 s at 1 ms. Largest
    rise of its energy [J] (or, ``mud=False``, of the same release without mud), start [J]."""
    xml = """<mujoco><option timestep="0.001" integrator="implicitfast"/><worldbody>
      <body name="foot" pos="0 0 0.5"><freejoint/>
      <geom type="sphere" size="0.0232" pos="0 0 -0.0272" mass="0.182"/></body>
      </worldbody></mujoco>"""
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    terrain = mudrft.MudTerrain(mudrft.paper_mud(0.35), thixotropy="quasi-static")
    coupling = attach(model, "foot", terrain, backend=_backend(backend))
    quat = np.array([-0.3147, -0.7875, 0.1420, 0.5105])
    data.qpos[3:7] = quat / np.linalg.norm(quat)
    mujoco.mj_forward(model, data)
    R = data.xmat[1].reshape(3, 3)
    lowest = (data.xpos[1] + coupling.bodies[0].triangles.reshape(-1, 3) @ R.T)[:, 2].min()
    data.qpos[2] += 0.0016 - lowest
    data.qvel[:3] = (0.467, -1.7996, 0.6248)
    data.qvel[3:6] = R.T @ np.array([20.59, -5.327, 49.72])
    coupling.reset(data)
    step = (lambda: coupling.step(data)) if mud else (lambda: mujoco.mj_step(model, data))
    return energy_rise(model, data, step, 300)


@pytest.mark.parametrize("backend", BACKENDS)
def test_the_sphere_the_search_found_gains_nothing_beyond_mujoco_alone(backend):
    """With the odometry above, the compiled coupling pushed this sphere sideways while it
    yawed in the mud and it gained 6.2 mJ of its 0.23 J (13 mJ under Euler); the numpy
    coupling gained nothing. Its centre of mass is off its frame origin, so MuJoCo alone
    moves its energy (0.46 mJ at the start of the flight): the rise with mud may not exceed
    the rise without it (tolerance round-off)."""
    rise, e0 = _sphere_release(backend)
    control, _ = _sphere_release(backend, mud=False)
    assert rise <= control + 1e-9 * e0, (rise, control, e0)


# -- a light foot spinning fast --------------------------------------------------------------


def _spinning_flat_foot(backend: str):
    """Seed 5738 of the passivity search: a free 1 kg flat foot of small isotropic inertia
    (5.1e-6 kg m^2) spinning at 76 rad/s, 6 mm deep, at dt = 5 ms without gravity, under
    implicitfast (under RK4, which the coupling refuses, the held wrench gained 0.26 J)."""
    xml = """<mujoco><option timestep="0.005" gravity="0 0 0" integrator="implicitfast"/>
      <worldbody><body name="foot" pos="0 0 0.5"><freejoint/>
      <inertial pos="0 0 0" mass="1.0256" diaginertia="5.11e-6 5.11e-6 5.11e-6"/></body>
      </worldbody></mujoco>"""
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    terrain = mudrft.MudTerrain(mudrft.paper_mud(0.35), acceleration=False)
    coupling = attach(model, "foot", terrain, feet=mudrft.feet.Flat(), backend=backend)
    quat = np.array([0.5931, 0.1947, 0.1002, 0.7748])
    data.qpos[3:7] = quat / np.linalg.norm(quat)
    mujoco.mj_forward(model, data)
    R = data.xmat[1].reshape(3, 3)
    lowest = (data.xpos[1] + coupling.bodies[0].triangles.reshape(-1, 3) @ R.T)[:, 2].min()
    data.qpos[2] += -0.00597 - lowest
    data.qvel[:3] = (-1.915, -0.0804, -1.3872)
    data.qvel[3:6] = R.T @ np.array([37.80, 1.663, 66.43])
    coupling.reset(data)
    return model, data, coupling


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_light_free_flat_foot_spinning_fast_gains_no_energy(backend):
    """The release that gained energy under RK4: under implicitfast the energy
    never rises (tolerance round-off)."""
    model, data, coupling = _spinning_flat_foot(_backend(backend))
    rise, e0, wet = _rise(model, data, coupling, 0.3)
    assert wet > 0
    assert rise <= 1e-9 * e0, (rise, e0)
