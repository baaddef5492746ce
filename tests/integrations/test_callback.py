"""The compiled coupling runs inside MuJoCo's step (``mjcb_passive``): plain ``mj_step``,
``mj_forward`` and ``mujoco.rollout`` see the mud; several models share the callback; a
user's compiled callback is chained, a Python one refused."""

from __future__ import annotations

import ctypes
import gc
import weakref

import numpy as np
import pytest

import mudrft
from mudrft import MudrftError

pytest.importorskip("mujoco")
from ._reference import attach
from .conftest import box_foot_model, mujoco

MUD = mudrft.paper_mud(0.25)


@pytest.fixture(autouse=True)
def _no_callback_left():
    """Each test starts and ends without a passive callback set."""
    mujoco.set_mjcb_passive(None)
    yield
    mujoco.set_mjcb_passive(None)


def _sliding_foot(mass: float = 1.5, mud: mudrft.Mud = MUD):
    """A box foot landing with a sideways and spinning motion: model, data, coupling."""
    model = box_foot_model(mass=mass, height=0.002)
    data = mujoco.MjData(model)
    data.qvel[:] = [0.3, -0.1, -0.2, 0.5, -0.3, 2.0]
    coupling = attach(model, "foot", mud, backend="numba")
    coupling.reset(data)
    return model, data, coupling


def test_plain_mj_step_forward_and_rollout_step_the_mud_as_coupling_step_does():
    """The same trajectory, bit for bit, from ``coupling.step``, from ``mj_step`` with
    ``mj_forward`` called twice between steps (a repeated call does not step the mud on),
    and from ``mujoco.rollout``."""
    from mujoco import rollout

    model_a, data_a, coupling_a = _sliding_foot()
    coupling_a.step(data_a, 300)
    model_b, data_b, coupling_b = _sliding_foot()
    for _ in range(300):
        mujoco.mj_step(model_b, data_b)
        mujoco.mj_forward(model_b, data_b)
        mujoco.mj_forward(model_b, data_b)
    model_c, data_c, _ = _sliding_foot()
    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    start = np.zeros(mujoco.mj_stateSize(model_c, spec))
    mujoco.mj_getState(model_c, data_c, start, spec)
    states, _ = rollout.rollout(model_c, data_c, start[None], nstep=300)
    qpos_c = states[0, -1, 1 : 1 + model_c.nq]  # the state: time, then qpos
    assert coupling_a.last.depth[0] > 0.001  # landed in the mud and sank
    np.testing.assert_array_equal(data_a.qpos, data_b.qpos)
    np.testing.assert_array_equal(data_a.qpos, qpos_c)
    mujoco.mj_forward(model_a, data_a)  # last: the wrench over the step ahead, as b's
    for name in ("force", "torque", "depth"):
        np.testing.assert_array_equal(getattr(coupling_a.last, name), getattr(coupling_b.last, name))  # fmt: skip


def test_two_models_in_one_process_each_step_their_own_mud():
    """Two models (feet of 1.5 and 3 kg, W = 25 % and 35 %) stepped in turn with plain
    ``mj_step`` end where each ends stepped alone."""
    wet = mudrft.paper_mud(0.35)
    alone = []
    for mass, mud in ((1.5, MUD), (3.0, wet)):
        model, data, _ = _sliding_foot(mass, mud)
        mujoco.mj_step(model, data, 200)
        alone.append(data.qpos.copy())
    (m1, d1, _), (m2, d2, _) = _sliding_foot(1.5, MUD), _sliding_foot(3.0, wet)
    for _ in range(200):
        mujoco.mj_step(m1, d1)
        mujoco.mj_step(m2, d2)
    np.testing.assert_array_equal(d1.qpos, alone[0])
    np.testing.assert_array_equal(d2.qpos, alone[1])
    assert abs(alone[0][2] - alone[1][2]) > 5e-4  # the two runs differ: the test can fail


def test_a_compiled_user_callback_is_chained_and_a_python_one_refused():
    """A ctypes callback set before ``reset`` still runs once per step after the mud's; a
    Python callable cannot be called from compiled code, so ``reset`` says so."""
    calls = []
    user = ctypes.CFUNCTYPE(None, ctypes.c_void_p, ctypes.c_void_p)(lambda m, d: calls.append(d))
    mujoco.set_mjcb_passive(user)
    model, data, coupling = _sliding_foot()
    before = len(calls)  # reset's mj_forward called it too
    mujoco.mj_step(model, data, 10)
    assert len(calls) == before + 10
    assert np.any(data.xfrc_applied[1] != 0.0)  # the mud acted too
    mujoco.set_mjcb_passive(lambda m, d: None)
    with pytest.raises(MudrftError, match=r"mjcb_passive is a Python callable"):
        coupling.reset(data)


def test_a_callback_replaced_after_reset_is_named_at_the_next_step():
    _, data, coupling = _sliding_foot()
    coupling.step(data, 5)
    mujoco.set_mjcb_passive(None)
    with pytest.raises(MudrftError, match=r"set_mjcb_passive was called after reset"):
        coupling.step(data)
    coupling.reset(data)  # reinstalls it
    coupling.step(data, 5)


def test_a_coupling_let_go_keeps_its_mud_until_detached():
    """A coupling nobody holds still steps its MjData in plain ``mj_step`` (the mud does
    not vanish mid-run when Python collects it); ``detach`` takes the mud out."""
    model, data, coupling = _sliding_foot()
    coupling.step(data, 50)
    held = weakref.ref(coupling)
    del coupling
    gc.collect()
    data.xfrc_applied[:] = 0.0
    mujoco.mj_step(model, data, 5)
    assert np.any(data.xfrc_applied[1] != 0.0) and held() is not None
    held().detach()
    gc.collect()
    assert held() is None  # detached, nothing holds it any more
    data.xfrc_applied[:] = 0.0
    mujoco.mj_step(model, data, 50)
    np.testing.assert_array_equal(data.xfrc_applied, 0.0)


def test_without_mujocos_library_attach_says_why(monkeypatch):
    """The coupling calls MuJoCo's C library; where it cannot be found, ``attach`` says
    so, whichever backend is named."""
    from mudrft.integrations.mujoco import backend

    def missing():
        raise ImportError("the MuJoCo library was not found in /nowhere")

    monkeypatch.setattr(backend, "mujoco_functions", missing)
    model = box_foot_model()
    with pytest.raises(MudrftError, match=r"MuJoCo's own library, which was not found"):
        attach(model, "foot", MUD)
    with pytest.raises(MudrftError, match=r"MuJoCo's own library, which was not found"):
        attach(model, "foot", MUD, backend="numba")
