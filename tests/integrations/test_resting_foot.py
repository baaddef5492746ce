"""A foot that comes to rest in the mud settles: no period-two oscillation (D119).

Found by a walkthrough with a robot of one's own: after a sideways motion a resting
foot kept alternating its force step by step. The swing was the suction switch
:math:`H_\\nu` of eq. (1), which turns within :math:`\\nu L_c` (about 0.5 mm/s) of rest:
the secant of D63 spanned the velocity change of the last mud wrench alone (0.15-0.23 m/s
for the calf below, whose mud wrench its actuator cancels), so its slope was a fiftieth of
the switch's and each implicit step jumped across the switch (D119). Before D119 the
calf's horizontal force alternated by +-1.47 N (3.0 N from one step to the next), the
box's vertical force by +-0.25 N at 5 ms and +-0.29 N at 10 ms (0.5 and 0.6 N step to
step); with the secant toward rest, 2.5e-4 N and 4e-5 N (step to step 5e-4 and 2e-3 N).

The criterion is the period-two amplitude of the applied force over the last steps, half
the difference between the means of the even and the odd steps (a steady force or a slow
creep gives 0), and the largest change from one step to the next: both bounded well
below the force's own scale (0.1 % of the calf's 22 N support, 0.3 % of the box's 2.9 N
weight), at least ten times above what the settled foot shows and ten times below what
the oscillation gave.
"""

from __future__ import annotations

import importlib.util

import numpy as np
import pytest

import mudrft

pytest.importorskip("mujoco")
from ._reference import attach
from .conftest import box_foot_model, mujoco

MUD = mudrft.paper_mud(0.25)

BACKENDS = [
    "numpy",
    pytest.param(
        "numba",
        marks=pytest.mark.skipif(
            importlib.util.find_spec("numba") is None, reason="numba not installed"
        ),
    ),
]

#: The guide's leg (docs/guide/mujoco.md): a 2 kg hip on a vertical slide, a 0.25 kg calf
#: on a hinged knee held by a position actuator (kp 20 N m/rad), a 3 cm sphere foot.
CALF = """<mujoco><option timestep="0.002"/><worldbody>
  <geom name="floor" type="plane" size="2 2 0.1" pos="0 0 -0.2"/>
  <body name="hip" pos="0 0 0.2"><joint type="slide" axis="0 0 1"/>
    <geom type="box" size="0.05 0.05 0.02" mass="2"/>
    <body name="calf" pos="0 0 -0.1"><joint name="knee" type="hinge" axis="0 1 0"/>
      <geom name="shin" type="capsule" fromto="0 0 0 0 0 -0.06" size="0.012" mass="0.2"/>
      <geom name="toe" type="sphere" pos="0 0 -0.07" size="0.03" mass="0.05"/>
    </body></body></worldbody>
  <actuator><position joint="knee" kp="20"/></actuator></mujoco>"""


def period_two(force: np.ndarray) -> float:
    """Amplitude of the period-two part of a force sampled every step [N]: half the
    difference between the means of the even and the odd samples."""
    n = len(force) - len(force) % 2
    return float(abs(force[:n:2].mean() - force[1:n:2].mean()) / 2)


@pytest.mark.parametrize("backend", BACKENDS)
def test_a_calf_at_rest_after_a_sideways_motion_settles(backend):
    """1 s standing, the knee commanded to 0.3 rad for 0.3 s and back: 2.7 s later the foot
    rests 13 mm deep, held sideways by the mud against the actuator (about -6 N). Before
    D119 its horizontal force alternated by +-1.5 N every step for as long as it was run."""
    model = mujoco.MjModel.from_xml_string(CALF)
    data = mujoco.MjData(model)
    coupling = attach(model, "calf", MUD, backend=backend)
    coupling.reset(data)
    force = []
    for target, steps in ((0.0, 500), (0.3, 150), (0.0, 1350)):
        data.ctrl[0] = target
        for _ in range(steps):
            force.append(coupling.step(data).force[0].copy())
    fx = np.array(force)[-500:, 0]  # the last second
    assert np.abs(fx).mean() > 1.0  # the mud holds the foot against the actuator
    assert period_two(fx) < 0.02
    assert np.abs(np.diff(fx)).max() < 0.05


@pytest.mark.parametrize("backend", BACKENDS)
@pytest.mark.parametrize("dt", [5e-3, 1e-2])
def test_a_free_box_foot_at_rest_settles_at_large_steps(backend, dt):
    """A free 0.3 kg box foot set down on the mud sliding at 0.2 m/s comes to rest within
    0.1 s; over its last 0.5 of 3 s its vertical force is its weight, steady. Before D119
    it alternated by +-0.2-0.3 N about the weight at 5 and 10 ms."""
    model = box_foot_model(mass=0.3, dt=dt)
    data = mujoco.MjData(model)
    coupling = attach(model, "foot", MUD, backend=backend)
    coupling.reset(data)
    data.qvel[0] = 0.2
    steps = round(3.0 / dt)
    fz = np.array([coupling.step(data).force[0, 2] for _ in range(steps)])[-round(0.5 / dt) :]
    weight = 0.3 * 9.81
    assert fz.mean() == pytest.approx(weight, rel=1e-3)
    assert period_two(fz) < 0.01
    assert np.abs(np.diff(fz)).max() < 0.02
