"""A field of mud in MJX: each robot of a vmapped batch on its own drawn field, in one
compiled call, following the CPU coupling on the same field (issue 42)."""

from __future__ import annotations

import numpy as np
import pytest

import mudrft

pytest.importorskip("mujoco")
pytest.importorskip("jax")
pytest.importorskip("numba")
import jax

from mudrft.integrations import mjx as mm
from mudrft.integrations.mjx._lazy import x64_context
from mudrft.integrations.mujoco import attach

from .conftest import box_foot_model, mujoco

if not mm.available():
    pytest.skip("mujoco-mjx is not installed (extra 'mjx')", allow_module_level=True)

FIELD = mudrft.MudField(
    {"firm": 0.25, "soft": 0.4, "rock": "rigid"}, ["firm soft", "rock firm"],
    cell_size=0.04, origin=(-0.04, -0.04), border=0.02,
)  # fmt: skip
DRAWS = [FIELD.randomized(seed, water_content=(0.25, 0.45), layout=True) for seed in range(4)]


@pytest.mark.slow  # compiles MJX for tens of seconds: CI runs it as its own step
def test_each_robot_steps_on_its_own_field_as_the_cpu_coupling_does():
    """Four box feet sliding at 0.3 m/s across their fields' borders, each on its own
    draw, vmapped in one compiled rollout (float64), against the compiled CPU coupling on
    the same draw: positions to 1e-6 m over 0.3 s (the CPU couplings of numpy and numba
    part by 1e-6 in 0.5 s, D68a); a second set of draws reuses the compilation."""
    model = box_foot_model(height=0.002)
    cpu = []
    for f in DRAWS:
        d = mujoco.MjData(model)
        d.qvel[:2] = [0.3, 0.2]
        c = attach(model, "foot", f)
        c.reset(d)
        for _ in range(300):
            mujoco.mj_step(model, d)
        cpu.append(d.qpos.copy())
        c.detach()
    with x64_context(True):
        coupling = mm.attach(model, "foot", FIELD)
        d0 = mujoco.MjData(model)
        d0.qvel[:2] = [0.3, 0.2]
        dx = coupling.put_data(d0)
        batch = jax.tree_util.tree_map(lambda a: np.stack([a] * len(DRAWS)), dx)
        fields = [np.stack(a) for a in zip(*(coupling.field_arrays(f) for f in DRAWS), strict=True)]  # fmt: skip
        states = jax.vmap(coupling.init)(batch)

        def one(d, s, field):
            def body(carry, _):
                d, s, out = coupling.step(*carry, field=field)
                return (d, s), out.depth

            return jax.lax.scan(body, (d, s), None, length=300)

        run = mm.jit(jax.vmap(one))
        (out_d, _), _ = run(batch, states, tuple(fields))
        got = np.asarray(out_d.qpos)
        assert np.abs(got - np.array(cpu)).max() < 1e-6
        assert np.ptp(got[:, 2]) > 1e-4  # the fields differ, and so do the sinkings
        again = [FIELD.randomized(seed, layout=True) for seed in range(4, 8)]
        fields = [np.stack(a) for a in zip(*(coupling.field_arrays(f) for f in again), strict=True)]  # fmt: skip
        run(batch, states, tuple(fields))
        assert run._cache_size() == 1


def test_field_arrays_refuses_another_shape_and_uneven_ground():
    with x64_context(False):
        coupling = mm.attach(box_foot_model(), "foot", FIELD)
        with pytest.raises(mudrft.MudrftError, match=r"field must have the attached field's shape"):
            coupling.field_arrays(mudrft.MudField({"m": 0.3}, ["m"]))
        with pytest.raises(mudrft.MudrftError, match="needs a coupling attached to a MudField"):
            mm.attach(box_foot_model(), "foot", mudrft.paper_mud(0.3)).field_arrays()
        uneven = mudrft.MudField({"m": 0.3}, ["m"], heights=[[0.0, 0.01], [0.0, 0.01]])
        with pytest.raises(mudrft.MudrftError, match="on a level surface only"):
            mm.attach(box_foot_model(), "foot", uneven)
        hilly = mudrft.MudField(
            FIELD.regions, ["firm soft", "rock firm"], cell_size=0.04, origin=(-0.04, -0.04),
            border=0.02, heights=[[0.0, 0.01], [0.0, 0.01]],
        )  # fmt: skip
        with pytest.raises(mudrft.MudrftError, match="on a level surface only"):
            coupling.field_arrays(hilly)
