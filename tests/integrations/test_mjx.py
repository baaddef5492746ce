"""The MJX coupling (mudrft.integrations.mjx) follows the CPU coupling, stays stable and
differentiates (decision D81).

The equivalence runs in float64 (the JAX backend's precision, D70) and, with a looser
tolerance, in float32 (MJX's default). Its floor is the model, not the port: the elastic
law alpha gamma^n with n = 0.12 turns displacements of round-off size into stresses of
hundreds of Pa, and the heading rule feeds them into the horizontal force (D68a). MJX
computes the foot's pose with its own quaternion arithmetic, so the lateral displacement
of the planar biped's feet is 1e-17 m instead of exactly 0; two CPU couplings that differ
only by the order of a few sums (numpy and numba) already part by 2e-6 in 0.5 s.
"""

from __future__ import annotations

import numpy as np
import pytest

import mudrft

pytest.importorskip("mujoco")
pytest.importorskip("jax")
import jax

from mudrft.integrations import mjx as mm
from mudrft.integrations.mjx._lazy import x64_context
from mudrft.integrations.walk import BIPED_FEET, GaitController, biped_model

from ._reference import attach
from .conftest import mujoco

if not mm.available():
    pytest.skip("mujoco-mjx is not installed (extra 'mjx')", allow_module_level=True)

MUD = mudrft.paper_mud(0.25)
DT = 2e-3  # [s], the largest step the CPU coupling's walk tests use
# float64 / float32: max |q_mjx - q_cpu| over the joint positions [m, rad] and max |depth
# difference| of the feet [m] over 0.5 s standing at dt = 2 ms (measured 2.1e-5 / 1.5e-6
# and 2.4e-5 / 6.1e-6; at 1 ms 4e-6 / 8e-7 and 2e-5 / 5e-6; the feet sink 7-8 mm)
TOL = {"float64": (5e-5, 5e-6), "float32": (1e-4, 2e-5)}


def _standing_biped():
    """The biped standing on the mud with its servos holding the pose; contacts off (the
    bed is 0.15 m down, never reached), so MJX compiles no collision."""
    m = biped_model(timestep=DT)
    m.opt.disableflags |= int(mujoco.mjtDisableBit.mjDSBL_CONTACT)
    d = mujoco.MjData(m)
    ctrl = GaitController(m)
    ctrl.initial_pose(d)
    ctrl(d)
    return m, d


@pytest.fixture(scope="module")
def cpu_reference():
    """0.5 s of the standing biped with the CPU coupling: joint positions and depths."""
    m, d = _standing_biped()
    cpu = attach(m, list(BIPED_FEET), MUD, backend="numpy")
    cpu.reset(d)
    q, depth = [], []
    for _ in range(250):
        out = cpu.step(d)
        q.append(d.qpos.copy())
        depth.append(out.depth.copy())
    return np.array(q), np.array(depth)


@pytest.mark.slow
@pytest.mark.parametrize("dtype", ["float64", "float32"])
def test_mjx_follows_the_cpu_coupling_and_stays_stable(cpu_reference, dtype):
    """0.5 s against the CPU coupling within TOL; in float32 (the default of MJX and of
    the vector environment) on to 10 s: finite, settled, no chatter."""
    q_cpu, depth_cpu = cpu_reference
    with x64_context(dtype == "float64"):
        m, d = _standing_biped()
        coupling = mm.attach(m, list(BIPED_FEET), MUD)
        dx = coupling.put_data(d)
        assert dx.qpos.dtype == np.dtype(dtype)
        state = mm.jit(coupling.init)(dx)
        dx, state, out = coupling.rollout(dx, state, 250)
        dq = np.abs(np.asarray(dx.qpos) - q_cpu[-1]).max()
        dd = np.abs(np.asarray(out.depth) - depth_cpu).max()
        assert dq < TOL[dtype][0] and dd < TOL[dtype][1], (dq, dd)
        assert np.asarray(out.depth)[-1].min() > 5e-3  # it did sink into the mud
        if dtype == "float64":
            return
        for _ in range(19):  # on to 10 s with the same compiled rollout
            dx, state, out = coupling.rollout(dx, state, 250)
            assert bool(np.all(out.finite))
        depth = np.asarray(out.depth[-1])
        assert np.all(np.isfinite(np.asarray(dx.qpos)))
        assert np.all((depth > 5e-3) & (depth < 0.03)), depth  # settled, not sinking away
        assert float(np.abs(np.asarray(dx.qvel)).max()) < 0.05  # at rest, no chatter


@pytest.mark.slow  # compiles MJX for tens of seconds: CI runs it as its own step
def test_gradient_through_a_rollout_equals_finite_differences():
    """d(height after 40 ms)/d(initial sink speed) of a free foot shot into the mud:
    reverse mode through MJX, the mud and the implicit step, against central differences."""
    with x64_context(True):
        xml = """<mujoco><option timestep="0.001"/><worldbody>
          <body name="foot" pos="0 0 0.015"><freejoint/>
          <geom type="box" size="0.0325 0.04 0.013" mass="0.5"/></body></worldbody></mujoco>"""
        m = mujoco.MjModel.from_xml_string(xml)
        d = mujoco.MjData(m)
        d.qvel[:] = [0.05, 0.0, -0.2, 0.0, 0.5, 0.0]  # sinking, sliding and pitching
        mujoco.mj_forward(m, d)
        coupling = mm.attach(m, "foot", MUD)
        d0 = coupling.put_data(d)
        st0 = mm.jit(coupling.init)(d0)

        def height(vz):
            def body(carry, _):
                dd, st = carry
                dd, st, _out = coupling.step(dd, st)
                return (dd, st), None

            start = d0.replace(qvel=d0.qvel.at[2].set(vz))
            (dd, _), _ = jax.lax.scan(body, (start, st0), None, length=40)
            return dd.qpos[2]

        value_and_grad = mm.jit(jax.value_and_grad(height))  # one compiled program
        value, grad = value_and_grad(-0.2)
        h = 1e-6
        fd = (value_and_grad(-0.2 + h)[0] - value_and_grad(-0.2 - h)[0]) / (2 * h)
        assert float(value) < 0.013  # the foot is in the mud (it started at 0.015 m)
        assert abs(float(grad) - float(fd)) < 1e-6 * abs(float(fd)), (grad, fd)  # 2e-8 measured


#: A release that gains energy without the bound of D62c (D62b; a random search with the
#: numpy coupling, 2026-11-23): the semi-sphere, 0.71 kg, tilted, spinning at 65 rad/s,
#: 4.9 mm above the mud, under 8.4 m/s^2 of gravity, W = 25 %, quasi-static evaluation.
_ROLLING = {
    "euler": (32.479, -52.317, -37.824),
    "qvel": (0.9685, -0.9551, 0.3541, -59.0519, 26.9782, -4.7474),
    "mass": 0.70627,
    "gravity": 8.4453,
}


def _rolling_shadow_rise(*, bound: bool) -> tuple[float, float]:
    """Largest rise of the energy MuJoCo's Euler step conserves (kinetic + gravitational +
    dt/2 m g.v, see tests/integrations/test_passivity.py) over 0.15 s of the rolling
    release on MJX in float64 [J], and its start [J]."""
    from mudrft.integrations.mjx import physics

    r, dt, inertia = _ROLLING, 1e-3, 2e-4
    xml = f"""<mujoco><option timestep="{dt}" gravity="0 0 {-r["gravity"]}"/><worldbody>
      <body name="foot" pos="0 0 0.5"><freejoint/>
      <inertial pos="0 0 0" mass="{r["mass"]}" diaginertia="{inertia} {inertia} {inertia}"/>
      </body></worldbody></mujoco>"""
    m = mujoco.MjModel.from_xml_string(xml)
    d = mujoco.MjData(m)
    terrain = mudrft.MudTerrain(mudrft.paper_mud(0.25), thixotropy="quasi-static")
    foot = mudrft.feet.SemiSphere()
    q = np.zeros(4)
    mujoco.mju_euler2Quat(q, np.radians(r["euler"]), "xyz")
    d.qpos[3:7] = q
    mujoco.mj_forward(m, d)
    probe = attach(m, "foot", terrain, feet=foot, backend="numpy")
    R = d.xmat[1].reshape(3, 3)
    lowest = (d.xpos[1] + probe.bodies[0].triangles.reshape(-1, 3) @ R.T)[:, 2].min()
    d.qpos[2] += 0.00488 - lowest
    d.qvel[:] = r["qvel"]
    mujoco.mj_forward(m, d)

    def shadow(qpos, qvel):
        g = -r["gravity"]
        kinetic = 0.5 * r["mass"] * (qvel[:3] @ qvel[:3]) + 0.5 * inertia * (qvel[3:] @ qvel[3:])
        return kinetic - r["mass"] * g * qpos[2] + 0.5 * dt * r["mass"] * g * qvel[2]

    with x64_context(True):
        coupling = mm.attach(m, "foot", terrain, feet=foot)
        d0 = coupling.put_data(d)
        st0 = coupling.init(d0)
        if not bound:
            st0 = st0._replace(tank=st0.tank + 1e9)  # a tank that never runs dry

        def body(carry, _):
            dd, st = carry
            dd, st, _out = coupling.step(dd, st)
            if not bound:
                st = st._replace(tank=st.tank + 1e9)
            return (dd, st), (dd.qpos, dd.qvel)

        _, (qpos, qvel) = mm.jit(lambda: jax.lax.scan(body, (d0, st0), None, length=150))()
        energy = np.array([float(shadow(a, b)) for a, b in zip(qpos, qvel, strict=True)])
    start = float(shadow(np.asarray(d.qpos), np.asarray(d.qvel)))
    assert physics.MjxMudState._fields[-1] == "tank"
    return float(energy.max() - start), start


@pytest.mark.slow  # compiles MJX for tens of seconds: CI runs it as its own step
def test_mjx_keeps_the_passivity_bound():
    """D62c on MJX: the rolling release gains nothing with the bound (tolerance: round-off
    in float64). The release gained energy under the old direction-split horizontal law;
    the CPU coupling's passivity tests cover the unbounded law in any direction."""
    rise, start = _rolling_shadow_rise(bound=True)
    assert rise <= 1e-9 * (1.0 + start)


def test_mjx_refuses_rk4_and_implicit_and_names_what_it_runs():
    """The MJX coupling runs one scheme, under Euler or implicitfast: RK4 held the wrench
    over four stages (a light spinning foot gained energy) and MJX has no 'implicit'."""
    from .conftest import box_foot_model

    for integrator in ("RK4", "IMPLICIT"):
        m = box_foot_model()
        m.opt.integrator = getattr(mujoco.mjtIntegrator, f"mjINT_{integrator}")
        with pytest.raises(
            mudrft.MudrftError, match=f"'Euler' or 'implicitfast'.*mjINT_{integrator}"
        ):
            mm.attach(m, "foot", MUD)


@pytest.fixture(scope="module")
def foot_batch():
    """Three free box feet, soles 8 mm in the mud, in float32 (MJX's default), and their
    first step, vmapped and compiled once: the first foot sinks at 0.2 m/s, the second has
    NaN velocities, the third is thrown in at 1e6 m/s."""
    xml = """<mujoco><option timestep="0.001"/><worldbody>
      <body name="foot" pos="0 0 0.005"><freejoint/>
      <geom type="box" size="0.0325 0.04 0.013" mass="0.5"/></body></worldbody></mujoco>"""
    with x64_context(False):
        coupling = mm.attach(mujoco.MjModel.from_xml_string(xml), "foot", MUD)
        d = coupling.put_data()
        qvel = np.zeros((3, 6), dtype=np.float32)
        qvel[:, 2] = [-0.2, np.nan, -1e6]
        # numpy on the host: jax.numpy would compile a kernel per field of mjx.Data
        batch = jax.tree_util.tree_map(lambda a: np.stack([a] * 3), d).replace(qvel=qvel)

    @mm.jit
    def first_step(d):
        st = jax.vmap(coupling.init)(d)
        return st, *jax.vmap(coupling.step)(d, st)

    return coupling, batch, first_step


@pytest.mark.slow  # compiles MJX for tens of seconds: CI runs it as its own step
def test_an_unstable_robot_in_a_batch_is_flagged_and_its_mud_held(foot_batch):
    """Issue 43: a NaN in qvel, or a body thrown in at -1e6 m/s, turned the whole state into
    NaN without a word. The foot with NaN velocities and the one beyond MAX_SPEED are
    flagged, keep their mud state and get no wrench; the sound one steps."""
    from mudrft.integrations.mjx.physics import MAX_SPEED

    assert MAX_SPEED < 1e6
    _, batch, first_step = foot_batch
    with x64_context(False):
        st0, d1, st1, out = first_step(batch)
    np.testing.assert_array_equal(out.unstable, [False, True, True])
    assert float(out.force[0, 0, 2]) > 0.0 and np.all(np.isfinite(np.asarray(d1.qpos[0])))
    for field in (out.force, out.torque, out.explicit_force):
        assert np.all(np.asarray(field)[1:] == 0.0)
    for before, after in zip(jax.tree_util.tree_leaves(st0), jax.tree_util.tree_leaves(st1), strict=True):  # fmt: skip
        after = np.asarray(after)
        assert np.all(np.isfinite(after))
        np.testing.assert_array_equal(after[1:], np.asarray(before)[1:])  # held
    np.testing.assert_array_equal(st1.has_prev, [1.0, 0.0, 0.0])  # the sound one stepped


@pytest.mark.slow  # compiles MJX for tens of seconds: CI runs it as its own step
def test_a_float32_robot_after_the_switch_to_float64_is_told_what_happened(foot_batch):
    """A robot made in float32, stepped after mudrft.backends.jax switched the
    process to float64 (its first call does, D70): the rollout's scan refused its carry
    ('carry[1].foot_xy has type float32[1,2] but ... float64'), and the vector environment
    failed on 'lax.add requires arguments to have the same dtypes, got int32, int64'. Now
    a MudrftError says what happened and what to do; in float32 it still runs."""
    coupling, batch, first_step = foot_batch
    with x64_context(False):
        st0 = first_step(batch)[0]
    one = jax.tree_util.tree_map(lambda a: np.asarray(a)[0], (batch, st0))  # on the host
    assert one[0].qpos.dtype == np.float32
    with x64_context(True), pytest.raises(mudrft.MudrftError, match="d is float32 but JAX now"):
        coupling.rollout(*one, 3)
    with x64_context(False):
        _, _, st, out = first_step(batch)
    assert st.foot_xy.dtype == np.float32 and float(out.depth[0, 0]) > 0.005


@pytest.mark.slow  # compiles MJX for tens of seconds: CI runs it as its own step
def test_an_mjx_sphere_foot_is_a_full_ball_whatever_the_calf_tilt():
    """Issue 41: a sphere foot is a ball, the same from every angle. MJX modelled it as a
    hemisphere fixed to the calf, so its support changed with the calf's tilt. A calf
    whose ball's center stands 10 mm above the mud's surface, upright, pitched 40 degrees
    and rolled 80 degrees about that center: the same depth and force in every pose."""
    xml = """<mujoco><option timestep="0.001"/><worldbody>
      <body name="calf" pos="0 0 0.11"><freejoint/>
      <geom type="capsule" fromto="0 0 0 0 0 0.1" size="0.01" contype="0" conaffinity="0"
       mass="0.3"/>
      <geom name="ball" type="sphere" pos="0 0 -0.1" size="0.02" mass="0.2"/>
      </body></worldbody></mujoco>"""
    m = mujoco.MjModel.from_xml_string(xml)
    center = np.array([0.0, 0.0, 0.01])
    with x64_context(True):
        coupling = mm.attach(m, "calf", MUD)
        assert coupling.bodies[0].ball
        datas = []
        for euler in ((0.0, 0.0, 0.0), (0.0, 40.0, 0.0), (80.0, 0.0, 0.0)):
            d = mujoco.MjData(m)
            q = np.zeros(4)
            mujoco.mju_euler2Quat(q, np.radians(euler), "xyz")
            R = np.zeros(9)
            mujoco.mju_quat2Mat(R, q)
            d.qpos[:3] = center + R.reshape(3, 3) @ [0.0, 0.0, 0.1]
            d.qpos[3:7] = q
            mujoco.mj_forward(m, d)
            assert d.geom_xpos[1] == pytest.approx(center, abs=1e-12)
            datas.append(coupling.put_data(d))
        batch = jax.tree_util.tree_map(lambda *a: np.stack(a), *datas)

        @mm.jit
        def first_step(d):
            st = jax.vmap(coupling.init)(d)
            return jax.vmap(coupling.step)(d, st)[2]

        out = first_step(batch)
    depth, force = np.asarray(out.depth)[:, 0], np.asarray(out.explicit_force)[:, 0]
    np.testing.assert_allclose(depth, 0.02 - center[2], atol=1e-12)  # radius 0.02 m
    assert force[0, 2] > 0.0
    np.testing.assert_allclose(force, np.broadcast_to(force[0], force.shape), rtol=1e-9, atol=1e-9)
