"""A foot of the MuJoCo coupling that sinks past its own height warns once (D26)."""

from __future__ import annotations

import warnings

import pytest

import mudrft

pytest.importorskip("mujoco")
from mudrft.trajectories import BuriedFootWarning

from ._reference import attach, attach_batch
from .conftest import box_foot_model, mujoco

#: A 20 x 20 x 10 mm box of 5 kg in the wettest mud: it sinks past its 10 mm within 0.1 s.
SMALL = (0.01, 0.01, 0.005)
WET = mudrft.paper_mud(0.45)


def _buried(record: list[warnings.WarningMessage]) -> list[str]:
    return [str(w.message) for w in record if issubclass(w.category, BuriedFootWarning)]


def _run(step, calls: int) -> list[str]:
    with warnings.catch_warnings(record=True) as record:
        warnings.simplefilter("always")
        for _ in range(calls):
            step()
    return _buried(record)


@pytest.mark.parametrize("backend", ["numpy", "numba"])
def test_a_foot_sunk_past_its_height_warns_once(backend):
    """Over 100 calls of 10 steps the box sinks far past its height and warns once,
    naming the body, the depth, its height and what to do; not again after reset (an
    environment resets every episode)."""
    model = box_foot_model(mass=5.0, half=SMALL)
    data = mujoco.MjData(model)
    coupling = attach(model, "foot", WET, backend=backend)
    coupling.reset(data)
    caught = _run(lambda: coupling.step(data, 10), 100)
    assert len(caught) == 1, caught
    assert coupling.last.depth[0] > 0.05  # five times the foot's height
    msg = caught[0]
    assert "body 'foot' sank" in msg and "the Flat foot is tall (0.01 m)" in msg
    assert "bottom=" in msg and "firmer mud" in msg
    mujoco.mj_resetData(model, data)
    coupling.reset(data)
    assert _run(lambda: coupling.advance(data, 10), 100) == []
    assert coupling.last.depth[0] > 0.05  # buried again, quietly


def test_plain_mj_step_warns_when_last_is_read():
    """With the compiled coupling inside ``mj_step``, reading ``last`` checks (once)."""
    model = box_foot_model(mass=5.0, half=SMALL)
    data = mujoco.MjData(model)
    coupling = attach(model, "foot", WET)
    assert coupling.backend == "numba"
    coupling.reset(data)

    def step() -> None:
        for _ in range(10):
            mujoco.mj_step(model, data)
        assert coupling.last is not None

    assert len(_run(step, 100)) == 1


def test_a_batch_warns_once_a_foot_naming_a_robot():
    """Two robots sinking warn once for their one foot, naming the robot that sank first."""
    model = box_foot_model(mass=5.0, half=SMALL)
    datas = [mujoco.MjData(model) for _ in range(2)]
    datas[1].qpos[2] += 1.0  # robot 1 falls 1 m onto the mud (0.45 s), robot 0 lies on it
    coupling = attach_batch(model, "foot", WET, n=2, backend="numpy")
    coupling.reset(datas)
    caught = _run(lambda: coupling.step(datas, 10), 100)
    assert len(caught) == 1, caught
    assert "body 'foot' of robot 0 sank" in caught[0]
    assert min(coupling.last.depth[:, 0]) > 0.01  # both sank past the foot's height


@pytest.mark.parametrize("backend", ["numpy", "numba"])
def test_a_foot_within_its_height_never_warns(backend):
    """The paper's 26 mm box foot (1.5 kg) rests in the mud well within its height."""
    model = box_foot_model()
    data = mujoco.MjData(model)
    coupling = attach(model, "foot", mudrft.paper_mud(0.25), backend=backend)
    coupling.reset(data)
    assert _run(lambda: coupling.step(data, 10), 100) == []
    assert 0.0 < coupling.last.depth[0] < 0.026
