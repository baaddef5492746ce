"""The coupling's step under MuJoCo's RK4 (docs/model.md D150): the other forces'
acceleration read from MuJoCo, a free foot's wrench held in its body frame, a chain's in
the world frame, the user's ``qfrc_applied`` left alone, both backends alike."""

from __future__ import annotations

import numpy as np
import pytest

import mudrft

pytest.importorskip("mujoco")
from mudrft.integrations.mujoco import attach, rk4
from mudrft.integrations.mujoco.kinematics import com_twist

from .conftest import energy_rise, mujoco, thrown_leg


def test_the_twist_acceleration_is_the_derivative_of_the_twist():
    """J qacc + Jdot qvel of a spinning leg's foot equals the twist's rate of change:
    Richardson's extrapolation of its change over RK4 steps of 1 and 2 us (error second
    order in the step, relative 1e-6)."""
    rng = np.random.default_rng(1)
    qvel = rng.normal(size=9) * 20

    def rate(dt: float):
        model, data = thrown_leg(dt=dt)
        data.qvel[:] = qvel
        mujoco.mj_forward(model, data)
        foot = np.array([model.body("foot").id])
        root = int(model.body_rootid[foot[0]])
        ends = []
        for k in range(2):
            if k:
                mujoco.mj_step(model, data)
                mujoco.mj_forward(model, data)
            ends.append(com_twist(data.cvel[foot[0]], data.subtree_com[root], data.xipos[foot[0]]))
        return (ends[1] - ends[0]) / dt

    fd1, fd2 = rate(1e-6), rate(2e-6)
    model, data = thrown_leg(dt=1e-6)
    data.qvel[:] = qvel
    mujoco.mj_forward(model, data)
    acc = rk4.twist_acceleration(model, [data], np.array([model.body("foot").id]))[0, 0]
    assert np.abs(acc).max() > 100.0
    assert 2 * fd1 - fd2 == pytest.approx(acc, rel=1e-6, abs=1e-6 * np.abs(acc).max())


def test_free_bodies_are_those_one_free_joint_moves():
    """A free body and what is welded to it; not a body on a hinge, nor its welded child."""
    model = mujoco.MjModel.from_xml_string(
        """<mujoco><worldbody>
        <body name="puck"><freejoint/><geom type="cylinder" size="0.03 0.01" mass="0.2"/>
          <body name="weight" pos="0 0 0.02"><geom type="sphere" size="0.01" mass="0.05"/>
            <body name="flap"><joint type="hinge"/><geom type="box" size="0.01 0.01 0.01"/>
              <body name="tip" pos="0.02 0 0"><geom type="sphere" size="0.005"/></body>
        </body></body></body>
        <body name="wall" pos="1 0 0"><geom type="box" size="0.1 0.1 0.1"/></body>
        </worldbody></mujoco>"""
    )
    names = ["puck", "weight", "flap", "tip", "wall"]
    ids = np.array([model.body(n).id for n in names])
    assert rk4.free_bodies(model, ids).tolist() == [True, True, False, False, False]


def test_step_under_rk4_leaves_the_users_applied_forces():
    """``qfrc_applied`` holds the free foot's wrench for the step only; afterwards it is the
    user's, bit for bit, and ``xfrc_applied`` shows the mud's wrench as under Euler."""
    model = mujoco.MjModel.from_xml_string(
        """<mujoco><option timestep="0.002" integrator="RK4"/><worldbody>
        <body name="foot" pos="0 0 0.01"><freejoint/>
        <geom type="box" size="0.0325 0.04 0.013" mass="0.5"/></body></worldbody></mujoco>"""
    )
    data = mujoco.MjData(model)
    coupling = attach(model, "foot", mudrft.paper_mud(0.25), backend="numpy")
    coupling.reset(data)
    user = np.array([0.1, -0.2, 0.3, 1e-3, 2e-3, -3e-3])
    data.qfrc_applied[:] = user
    for _ in range(50):
        out = coupling.step(data)
    assert out.depth[0] > 0
    assert data.qfrc_applied.tolist() == user.tolist()
    assert data.xfrc_applied[1].tolist() == [*out.force[0], *out.torque[0]]


def test_both_backends_step_alike_under_rk4():
    """The compiled kernel takes the acceleration read from MuJoCo as the numpy coupling
    does: the same leg, the same forces (1e-9 of the largest)."""
    pytest.importorskip("numba")
    forces = {}
    for backend in ("numpy", "numba"):
        model, data = thrown_leg()
        coupling = attach(model, "foot", mudrft.paper_mud(0.35), backend=backend)
        coupling.reset(data)
        forces[backend] = np.array([coupling.step(data).force[0] for _ in range(100)])
    peak = np.abs(forces["numpy"]).max()
    assert peak > 10.0
    np.testing.assert_allclose(forces["numba"], forces["numpy"], rtol=0, atol=1e-9 * peak)


def _leg_rise():
    """Largest energy rise of the leg in the mud for 0.3 s [J], of the leg without mud, and
    the start [J]."""
    model, data = thrown_leg()
    coupling = attach(model, "foot", mudrft.paper_mud(0.35), backend="numpy")
    coupling.reset(data)
    rise, e0 = energy_rise(model, data, lambda: coupling.step(data), 150)
    model, data = thrown_leg()
    control, _ = energy_rise(model, data, lambda: mujoco.mj_step(model, data), 150)
    return rise, control, e0


def test_a_leg_under_rk4_gains_no_energy_beyond_mujoco_alone():
    """A foot in a chain keeps ``xfrc_applied`` (D150): the leg loses energy in the mud (a
    search of 1,200 such legs at 1-5 ms: none rose 1 % of 1 + E0 above its control)."""
    rise, control, e0 = _leg_rise()
    assert rise <= control + 0.01 * (1 + e0), (rise, control, e0)


def test_a_legs_wrench_held_as_a_generalized_force_makes_it_diverge(monkeypatch):
    """Why a chain keeps ``xfrc_applied``: with the foot's wrench held as the generalized
    force J^T w over the stages (the free body's rule), this leg diverges: on MuJoCo 4.0
    its energy rises to 1.3e38 J at 0.26 s (where MuJoCo resets the state), on 3.3.6 and
    3.17 MuJoCo reports bad accelerations at the second step (another leg of the search
    gained 1.3 J of 76 J on 4.0)."""
    monkeypatch.setattr(rk4, "free_bodies", lambda model, ids: np.ones(len(ids), dtype=bool))
    try:
        rise, control, e0 = _leg_rise()
    except mudrft.MudrftError as exc:
        assert "diverged" in str(exc)
    else:
        assert rise > 1e6 * (1 + e0), (rise, control, e0)
