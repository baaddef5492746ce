"""The compiled coupling (backend="numba", D68a) equals the numpy coupling and stays passive."""

from __future__ import annotations

import numpy as np
import pytest

import mudrft

pytest.importorskip("mujoco")
from mudrft.integrations.walk import BIPED_FEET, GaitController, biped_model

from ._reference import attach
from .conftest import mechanical_energy, mujoco, thrown_leg

MUD = mudrft.paper_mud(0.25)
_MESH = mudrft.feet.SemiSphere().to_mesh(resolution=8)  # a mesh foot of 512 facets


# the biped's feet reach their 26 mm height at heel strike: buried, as warned
@pytest.mark.filterwarnings("ignore::mudrft.trajectories.BuriedFootWarning")
@pytest.mark.parametrize("foot", ["flat", "semi-cylinder", "semi-sphere", "mesh", "morphing"])
def test_compiled_coupling_equals_numpy_along_a_walk(foot):
    """Over a 2 s walk of the biped (dt = 2 ms), the compiled coupling writes the numpy
    coupling's wrench for the same motion to 1e-9 of the step's largest component.

    The walk is simulated with the compiled coupling; each step its MjData state is copied
    into a second MjData driven through the numpy coupling. (Two closed-loop runs drift
    apart: the elastic law alpha gamma^n, n = 0.12, turns the 1e-16 round-off of the
    planar biped's lateral displacement into stresses of up to a few hundred Pa, D68a.)
    Measured: 7e-16 (closed forms), 7e-14 (the 512-facet mesh: its facets are summed in
    another order).
    """
    f = _MESH if foot == "mesh" else mudrft.feet.by_name(foot)
    dt = 2e-3
    model = biped_model(f, timestep=dt)
    data, twin = mujoco.MjData(model), mujoco.MjData(model)
    ctrl = GaitController(model)
    ctrl.initial_pose(data)
    ctrl.initial_pose(twin)
    fast = attach(model, list(BIPED_FEET), MUD, feet=f, backend="numba")
    ref = attach(model, list(BIPED_FEET), MUD, feet=f)
    fast.reset(data)
    ref.reset(twin)
    worst, support = 0.0, 0.0
    for _ in range(round(2.0 / dt)):
        ctrl(data)
        mujoco.mj_step1(model, data)
        a = fast.apply(data)
        twin.qpos[:], twin.qvel[:], twin.ctrl[:] = data.qpos, data.qvel, data.ctrl
        twin.act[:], twin.time = data.act, data.time
        mujoco.mj_step1(model, twin)
        b = ref.apply(twin)
        mujoco.mj_step2(model, data)
        wa = np.concatenate([a.force, a.torque], axis=None)
        wb = np.concatenate([b.force, b.torque], axis=None)
        scale = max(np.abs(wb).max(), 1e-9)
        worst = max(worst, float(np.abs(wa - wb).max() / scale))
        support = max(support, float(b.force[:, 2].max()))
        for name in ("depth", "stress", "point", "velocity"):
            # round-off relative to each quantity's scale, in its unit (m, m/s, Pa): the two
            # couplings sum in other orders, and 1,000 steps of a walk carry it along (a
            # channel velocity of 2e-6 m/s differed by 4e-12 m/s, 1e-11 of the foot's speed)
            tol = 1e-11 * max(1.0, float(np.abs(getattr(b, name)).max()))
            np.testing.assert_allclose(getattr(a, name), getattr(b, name), rtol=1e-9, atol=tol)
    assert support > 100.0  # the biped stood in the mud
    assert data.qpos[0] > 0.03  # and walked
    assert worst < 1e-9


@pytest.mark.filterwarnings("ignore::mudrft.trajectories.BuriedFootWarning")  # thrown deep
def test_a_compiled_coupling_applied_once_then_stepped_equals_numpy():
    """``apply`` on the first step, ``step`` after it: the compiled coupling kept the first
    step's flag (no last step: the acceleration estimate is gravity alone) for as long as
    it ran, and the thrown leg's foot force differed from the numpy coupling's by up to
    938 N (largest 615 N) within 0.4 s. Now alike to 1e-9 of the largest force
    (measured 7e-12)."""
    forces = {}
    for backend in ("numpy", "numba"):
        model, data = thrown_leg(integrator="implicitfast")
        coupling = attach(model, "foot", MUD, backend=backend)
        coupling.reset(data)
        mujoco.mj_step1(model, data)
        coupling.apply(data)
        mujoco.mj_step2(model, data)
        forces[backend] = np.array([coupling.step(data).force[0] for _ in range(200)])
    peak = np.abs(forces["numpy"]).max()
    assert peak > 10.0
    np.testing.assert_allclose(forces["numba"], forces["numpy"], rtol=0, atol=1e-9 * peak)


@pytest.mark.parametrize("foot", ["flat", "morphing"])
@pytest.mark.parametrize("dt", [1e-3, 2e-3])
def test_compiled_biped_with_actuators_off_is_passive_for_ten_seconds(dt, foot):
    """The biped, servos off, falls limp into the mud: 10 s without NaN, and its mechanical
    energy (kinetic, gravity, the boom's pitch spring) never rises above its start."""
    f = mudrft.feet.by_name(foot)
    model = biped_model(f, timestep=dt)
    model.actuator_gainprm[:] = 0.0
    model.actuator_biasprm[:] = 0.0
    data = mujoco.MjData(model)
    GaitController(model).initial_pose(data)
    coupling = attach(model, list(BIPED_FEET), MUD, feet=f, backend="numba")
    coupling.reset(data)
    e0 = mechanical_energy(model, data)
    rise = -np.inf
    for _ in range(round(10.0 / dt)):
        out = coupling.step(data)
        rise = max(rise, mechanical_energy(model, data) - e0)
    assert np.all(np.isfinite(data.qpos)) and np.all(np.isfinite(out.force))
    assert out.depth.max() > 0.005  # it sank into the mud
    assert rise <= 1e-9 * abs(e0)


@pytest.mark.parametrize("backend", ["numba", "numpy"])
def test_advance_is_step_without_the_contact_and_last_is_read_when_asked(backend):
    """``advance`` moves the robot exactly as ``step`` does; ``last`` after it is the contact
    ``step`` returns for the same steps, built from the newest step whenever it is read
    (never a stale one), for one robot and for a batch of two."""
    from ._reference import attach_batch

    model = biped_model(mudrft.feet.Flat())
    ctrl = GaitController(model)
    datas = [mujoco.MjData(model) for _ in range(4)]
    pair_b = [mujoco.MjData(model), mujoco.MjData(model)]
    for d in (*datas, *pair_b):
        ctrl.initial_pose(d)
    kw = {"feet": mudrft.feet.Flat(), "backend": backend}
    one_a, one_b = (attach(model, list(BIPED_FEET), MUD, **kw) for _ in range(2))
    two_a, two_b = (attach_batch(model, list(BIPED_FEET), MUD, n=2, **kw) for _ in range(2))
    one_a.reset(datas[0])
    one_b.reset(datas[1])
    two_a.reset(datas[2:])
    two_b.reset(pair_b)
    reads = 0
    for k in range(300):
        for d in (*datas, *pair_b):
            ctrl(d)
        one_a.advance(datas[0])
        want = one_b.step(datas[1])
        two_a.advance(datas[2:])
        want2 = two_b.step(pair_b)
        if k % 37 == 0 or k == 299:  # read now and then: each read is of the newest step
            reads += 1
            for got, ref in ((one_a.last, want), (two_a.last, want2)):
                assert got is not None
                for name in got._fields:
                    np.testing.assert_array_equal(getattr(got, name), getattr(ref, name))
    np.testing.assert_array_equal(datas[0].qpos, datas[1].qpos)
    np.testing.assert_array_equal(datas[2].qpos, pair_b[0].qpos)
    assert want.depth.max() > 0.0 and reads == 10
    held = one_a.last
    one_a.advance(datas[0], 5)
    assert one_a.last is not held  # a kept contact is not changed by later steps
    assert not np.array_equal(held.tip, one_a.last.tip)


def test_the_first_compilation_says_so_on_the_logger(caplog, monkeypatch):
    """The first reset of a numba coupling compiles for about 15 s; it was silent."""
    from types import SimpleNamespace

    from mudrft.integrations.mujoco import callback as backend

    made = []
    monkeypatch.setattr(backend, "_CALLBACK", [None])
    monkeypatch.setattr(backend, "jit_callback", lambda f: made.append(1) or SimpleNamespace(ctypes="cb"))  # fmt: skip
    with caplog.at_level("INFO", logger="mudrft"):
        assert backend.callback() == "cb"
    assert "compiling the MuJoCo coupling with numba" in caplog.text
    assert "compiled the MuJoCo coupling in" in caplog.text
    caplog.clear()
    with caplog.at_level("INFO", logger="mudrft"):
        assert backend.callback() == "cb"
    assert caplog.text == "" and made == [1]
