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


def _on_cpu(model, draws, start_data, steps=300):
    """The compiled CPU coupling's qpos after ``steps`` steps from ``start_data()`` on
    each field of ``draws`` (n, nq)."""
    out = []
    for f in draws:
        d = start_data()
        c = attach(model, "foot", f)
        c.reset(d)
        for _ in range(steps):
            mujoco.mj_step(model, d)
        out.append(d.qpos.copy())
        c.detach()
    return np.array(out)


@pytest.mark.slow  # compiles MJX for tens of seconds: CI runs it as its own step
def test_each_robot_steps_on_its_own_field_as_the_cpu_coupling_does():
    """Four box feet sliding at 0.3 m/s across their fields' borders, each on its own
    draw, vmapped in one compiled rollout (float64), against the compiled CPU coupling on
    the same draw: positions to 1e-6 m over 0.3 s (the CPU couplings of numpy and numba
    part by 1e-6 in 0.5 s, D68a); a second set of draws reuses the compilation."""
    model = box_foot_model(height=0.002)

    def start_data():
        d = mujoco.MjData(model)
        d.qvel[:2] = [0.3, 0.2]
        return d

    cpu = _on_cpu(model, DRAWS, start_data)
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
        assert np.abs(got - cpu).max() < 1e-6
        assert np.ptp(got[:, 2]) > 1e-4  # the fields differ, and so do the sinkings
        again = [FIELD.randomized(seed, layout=True) for seed in range(4, 8)]
        fields = [np.stack(a) for a in zip(*(coupling.field_arrays(f) for f in again), strict=True)]  # fmt: skip
        run(batch, states, tuple(fields))
        assert run._cache_size() == 1


def test_field_arrays_refuses_another_shape():
    with x64_context(False):
        coupling = mm.attach(box_foot_model(), "foot", FIELD)
        with pytest.raises(mudrft.MudrftError, match=r"field must have the attached field's shape"):
            coupling.field_arrays(mudrft.MudField({"m": 0.3}, ["m"]))
        with pytest.raises(mudrft.MudrftError, match="needs a coupling attached to a MudField"):
            mm.attach(box_foot_model(), "foot", mudrft.paper_mud(0.3)).field_arrays()
        hilly = mudrft.MudField(
            FIELD.regions, ["firm soft", "rock firm"], cell_size=0.04, origin=(-0.04, -0.04),
            border=0.02, heights=[[0.0, 0.01], [0.0, 0.01]],
        )  # fmt: skip
        with pytest.raises(mudrft.MudrftError, match=r"\(1, 1\) heights, got .* \(2, 2\) heights"):
            coupling.field_arrays(hilly)


BUMPY = mudrft.MudField(
    {"firm": 0.25, "soft": 0.4}, ["firm soft", "soft firm"], cell_size=0.05,
    origin=(-0.05, -0.05), border=0.02,
    heights=0.004 * np.random.default_rng(7).standard_normal((6, 6)),
)  # fmt: skip


@pytest.mark.slow  # compiles MJX for tens of seconds: CI runs it as its own step
def test_on_uneven_ground_mjx_steps_as_the_cpu_coupling_does():
    """Three box feet dropped onto random bumps (4 mm standard deviation on a 20 mm grid)
    and sliding at 0.3 m/s, each on its own draw of the mud, vmapped in one compiled
    rollout (float64), against the compiled CPU coupling on the same draw: positions and
    orientations to 1e-6 over 0.3 s (D175: both turn each foot onto the tangent plane under
    it); the draws keep the heights, and the bumps tilt the feet (> 1 degree)."""
    model = box_foot_model(height=0.002)
    draws = [BUMPY.randomized(seed, water_content=(0.25, 0.45)) for seed in range(3)]
    start = BUMPY.height(0.0, 0.0)[0] + 0.011

    def start_data():
        d = mujoco.MjData(model)
        d.qpos[2], d.qvel[:2] = start, [0.3, 0.2]
        return d

    cpu = _on_cpu(model, draws, start_data)
    with x64_context(True):
        coupling = mm.attach(model, "foot", BUMPY)
        dx = coupling.put_data(start_data())
        batch = jax.tree_util.tree_map(lambda a: np.stack([a] * len(draws)), dx)
        fields = tuple(np.stack(a) for a in zip(*(coupling.field_arrays(f) for f in draws), strict=True))  # fmt: skip
        states = jax.vmap(lambda d, f: coupling.init(d, field=f))(batch, fields)

        def one(d, s, field):
            def body(carry, _):
                d, s, out = coupling.step(*carry, field=field)
                return (d, s), out.depth

            return jax.lax.scan(body, (d, s), None, length=300)

        (out_d, _), depth = mm.jit(jax.vmap(one))(batch, states, fields)
        got = np.asarray(out_d.qpos)
    assert np.abs(got - cpu).max() < 1e-6
    tilt = np.degrees(2 * np.arccos(np.clip(np.abs(cpu[:, 3]), 0.0, 1.0)))
    assert tilt.max() > 1.0 and np.asarray(depth).max() > 1e-3


@pytest.mark.slow  # compiles MJX (its box-box contact too) for tens of seconds
def test_rigid_cells_hold_a_foot_in_mjx_as_on_the_cpu():
    """The field's rigid cells as boxes (``add_rigid_cells``, ``set_rigid_cells`` before
    the model goes to MJX): a box foot dropped on the rock comes to rest on it by MJX's
    contact, with no mud force, as it does on the CPU by MuJoCo's; one dropped on the mud
    beside it, in the same vmapped rollout, sinks into the mud as on the CPU (to 1e-6 m).

    How deep each engine's soft contact lets the box into the rock is MuJoCo's, not the
    coupling's: MuJoCo 4.0 and its MJX agree to 1e-8 m, MuJoCo 3.3.6's C box-box contact
    rests 0.11 mm deeper than its MJX. So each is held to within 0.5 mm of the rock's top."""
    from mudrft.integrations.mujoco import add_rigid_cells, set_rigid_cells

    field = mudrft.MudField({"mud": 0.35, "rock": "rigid"}, ["rock mud"], cell_size=0.2, origin=(-0.1, -0.1))  # fmt: skip
    spec = mujoco.MjSpec.from_string("""<mujoco><worldbody><body name="foot" pos="0 0 0.02">
      <freejoint/><geom type="box" size="0.03 0.04 0.01" mass="3"/></body></worldbody></mujoco>""")  # fmt: skip
    add_rigid_cells(spec, field)
    model = spec.compile()
    set_rigid_cells(model, field)
    starts = (0.0, 0.3)  # over the rock, over the mud

    def start_data(x):
        d = mujoco.MjData(model)
        d.qpos[0] = x
        return d

    cpu, cpu_force = [], []
    for x in starts:
        d = start_data(x)
        c = attach(model, "foot", field)
        c.reset(d)
        mujoco.mj_step(model, d, nstep=300)
        cpu.append(d.qpos.copy())
        cpu_force.append(c.last.force[0].copy())
        c.detach()
    cpu = np.array(cpu)
    assert np.all(cpu_force[0] == 0.0) and cpu_force[1][2] > 0.0
    with x64_context(True):
        coupling = mm.attach(model, "foot", field)
        datas = [coupling.put_data(start_data(x)) for x in starts]
        batch = jax.tree_util.tree_map(lambda *a: np.stack(a), *datas)
        states = jax.vmap(coupling.init)(batch)

        def one(d, s):
            def body(carry, _):
                d, s, out = coupling.step(*carry)
                return (d, s), out.force

            return jax.lax.scan(body, (d, s), None, length=300)

        (out_d, _), force = mm.jit(jax.vmap(one))(batch, states)
        got, force = np.asarray(out_d.qpos), np.asarray(force)
    rock, mud = 0, 1
    assert np.all(force[rock] == 0.0) and force[mud, -1, 0, 2] > 0.0  # (robot, step, foot, xyz)
    assert np.abs(got[mud] - cpu[mud]).max() < 1e-6
    top = 0.0 + 0.01  # the rock's top is the surface; the foot's center 10 mm above it
    assert abs(got[rock, 2] - top) < 5e-4 and abs(cpu[rock, 2] - top) < 5e-4
    assert np.abs(np.asarray(out_d.qvel)[rock]).max() < 1e-3  # at rest on it
    assert cpu[mud, 2] < top - 2e-3  # it sank into the mud
