"""Patches of mud and rigid ground under a MuJoCo model (:class:`~mudrft.terrains.field.MudField`):
each foot feels the region under it, a border blends continuously, and crossing one never
gives a free foot energy."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import mudrft
from mudrft._validation import MudrftError
from mudrft.terrains.field import MudField

pytest.importorskip("mujoco")
pytest.importorskip("numba")
from ._reference import attach
from .conftest import box_foot_model, energy_rise, kinematic_foot_model, mujoco

with warnings.catch_warnings():  # W = 15 % lies outside the paper's table: extrapolated
    warnings.simplefilter("ignore")
    FIRM = mudrft.paper_mud(0.15, extrapolate=True)
SOFT = mudrft.paper_mud(0.35)
BORDER = 0.05


def _field(to: str) -> MudField:
    """Firm mud for x < 0, ``to`` (soft mud or rigid ground) for x > 0."""
    regions = {"firm": FIRM, "soft": SOFT, "rigid": "rigid"}
    return MudField(regions, [f"firm {to}"], cell_size=1.0, origin=(-1.0, -0.5), border=BORDER)


def test_a_one_region_field_steps_as_the_mud_to_the_bit():
    runs = []
    for mud in (SOFT, MudField({"soft": SOFT}, ["soft"])):
        model = box_foot_model(height=0.005)
        data = mujoco.MjData(model)
        data.qvel[0] = 0.2
        coupling = attach(model, "foot", mud)
        coupling.reset(data)
        for _ in range(400):
            mujoco.mj_step(model, data)
        runs.append(np.concatenate([data.qpos, data.qvel, coupling.last.force[0]]))
    assert np.array_equal(runs[0], runs[1])


@pytest.mark.parametrize(("y", "share", "mud"), [(-0.4, 1.0, FIRM), (0.4, 1.0, SOFT), (0.0, 0.5, FIRM)])  # fmt: skip
def test_a_foot_feels_the_region_under_it(y, share, mud):
    """A kinematic foot along the gait (in x and z) inside one region feels that mud
    exactly as MudTerrain does; near the border of mud and rigid ground (y = 0: half of
    each; the gait strays 10 mm in y), the mud's share of it."""
    tr = mudrft.gait(speed=0.2)
    dt = float(tr.time[1] - tr.time[0])
    model = kinematic_foot_model(dt=dt)
    data = mujoco.MjData(model)
    regions = {"firm": FIRM, "soft": SOFT, "rigid": "rigid"}
    cells = ["firm", "rigid" if share < 1 else "soft"]  # rows: y < 0, then y > 0
    field = MudField(regions, cells, cell_size=1.0, origin=(-0.5, -1.0), border=BORDER)
    coupling = attach(model, "foot", field)
    terrain, foot = mudrft.MudTerrain(mud), mudrft.feet.Flat()
    at = tr.position + np.array([0.0, y, 0.0])
    state = terrain.initial_state(foot, tr.position[0])
    data.qpos[:] = at[0]
    coupling.reset(data)
    got, want = [], []
    for k in range(1, len(tr)):
        data.qpos[:], data.qvel[:] = at[k], tr.velocity[k]
        mujoco.mj_forward(model, data)
        got.append(coupling.apply(data).explicit_force[0])
        state, out = terrain.step(foot, state, tr.position[k], tr.velocity[k], dt)
        want.append(field.blend(*at[k, :2])[0] * out.force)
    got, want = np.array(got), np.array(want)
    assert np.abs(want[:, 2]).max() > 20  # the foot carries load
    assert field.blend(*at[0, :2])[0] == share
    np.testing.assert_allclose(got, want, rtol=1e-9, atol=1e-9 * np.abs(want).max())


def test_the_force_changes_smoothly_across_a_border():
    """A foot dragged 10 mm deep at 0.5 m/s from firm into soft mud: the horizontal force
    moves from firm's to soft's over the border (50 mm, 100 steps of 1 ms), not in one
    step; no step changes it by more than a twentieth of the whole change."""
    model = kinematic_foot_model(dt=1e-3)
    data = mujoco.MjData(model)
    coupling = attach(model, "foot", _field("soft"))
    start = np.array([-0.1, 0.0, -0.01])  # the sole 10 mm deep
    data.qpos[:] = start
    coupling.reset(data)
    fx = []
    for k in range(1, 401):
        data.qpos[:], data.qvel[:] = start + np.array([5e-4 * k, 0.0, 0.0]), [0.5, 0.0, 0.0]
        mujoco.mj_forward(model, data)
        fx.append(coupling.apply(data).explicit_force[0, 0])
    fx = np.array(fx)
    whole = abs(fx[150] - fx[-1])  # x = -25 mm (firm, steady) and +100 mm (soft)
    assert whole > 1.0
    assert np.abs(np.diff(fx[150:])).max() < whole / 20


@settings(max_examples=4, deadline=None)
@given(angle=st.floats(-70.0, 70.0), speed=st.floats(0.3, 1.0))
@pytest.mark.parametrize("dt", [1e-3, 2e-3])
@pytest.mark.parametrize("to", ["soft", "rigid"])
def test_a_free_foot_crossing_a_border_gains_no_energy(to, dt, angle, speed):
    """A free box foot (isotropic inertia, so MuJoCo's step alone keeps its energy) lands
    at ``speed`` [m/s] ``angle`` [deg] off the border's normal, 20 mm before the border
    from firm mud into soft mud or onto rigid ground (a floor box, MuJoCo's contact):
    its mechanical energy never rises above the start."""
    floor = '<geom type="box" size="1 1 0.5" pos="1 0 -0.5"/>' if to == "rigid" else ""
    xml = f"""<mujoco><option timestep="{dt}"/><worldbody>{floor}
      <body name="foot" pos="-0.02 0 0.012"><freejoint/>
        <inertial pos="0 0 0" mass="1.0" diaginertia="6e-4 6e-4 6e-4"/>
        <geom type="box" size="0.03 0.04 0.01" mass="0"/></body></worldbody></mujoco>"""
    model = mujoco.MjModel.from_xml_string(xml)
    data = mujoco.MjData(model)
    field = _field(to)
    coupling = attach(model, "foot", field, floor="keep")
    coupling.reset(data)
    a = np.radians(angle)
    data.qvel[:3] = [speed * np.cos(a), speed * np.sin(a), -0.2]
    before = field.blend(*data.qpos[:2])
    rise, e0 = energy_rise(model, data, lambda: mujoco.mj_step(model, data), int(0.4 / dt))
    after = field.blend(*data.qpos[:2])
    assert not (before[0] == after[0] and np.array_equal(before[1], after[1]))  # it moved on
    assert rise <= 1e-12 * e0


def test_the_removed_numpy_coupling_is_refused_by_name():
    from mudrft.integrations.mujoco import attach as mudrft_attach

    model = box_foot_model()
    with pytest.raises(
        MudrftError, match=r"'auto' or 'numba', got 'numpy' \(the numpy coupling was removed"
    ):
        mudrft_attach(model, "foot", _field("soft"), backend="numpy")


def test_each_robot_steps_on_its_own_drawn_field():
    """Two robots of a batch, each on its own draw of one field (``use_field``), step as
    two single couplings on those fields, to the bit."""
    from ._reference import attach_batch

    field = MudField({"a": 0.25, "b": 0.35, "r": "rigid"}, ["a b", "b r"], cell_size=0.05)
    draws = [field.randomized(seed, water_content=(0.25, 0.45), layout=True) for seed in (1, 2)]
    assert not np.array_equal(draws[0].arrays()[2], draws[1].arrays()[2])

    def run(datas, coupling):
        for d in datas:
            d.qvel[:2] = [0.3, 0.1]
        coupling.reset(datas)
        for _ in range(300):
            for d in datas:
                mujoco.mj_step(coupling.model, d)
        return np.array([np.concatenate([d.qpos, d.qvel]) for d in datas])

    model = box_foot_model(height=0.002)
    batch = attach_batch(model, "foot", field, n=2)
    for i, f in enumerate(draws):
        batch.use_field(f, robot=i)
    together = run([mujoco.MjData(model) for _ in range(2)], batch)
    for i, f in enumerate(draws):
        one = run([mujoco.MjData(model)], attach(box_foot_model(height=0.002), "foot", f))
        np.testing.assert_array_equal(together[i], one[0])
    with pytest.raises(MudrftError, match=r"field must have the coupling's shape: \(2, 2\) cells"):
        batch.use_field(MudField({"a": 0.3}, ["a a a"], cell_size=0.05))
    with pytest.raises(MudrftError, match=r"robot must be None or an index in \[0, 2\)"):
        batch.use_field(field, robot=2)


def test_rigid_cells_are_boxes_that_collide_where_the_field_is_rigid():
    """``add_rigid_cells`` puts a box under each cell, the edge cells reaching beyond the
    grid as the field's nearest-cell rule does; ``set_rigid_cells`` makes the rigid ones
    collide. A box foot dropped on the rock rests on it by MuJoCo's contact (within 1 mm of
    the surface, no mud force); dropped on the mud, 0.3 m away, it sinks into the mud."""
    from mudrft.integrations.mujoco import add_rigid_cells, set_rigid_cells

    field = MudField({"mud": SOFT, "rock": "rigid"}, ["rock mud"], cell_size=0.2, origin=(-0.1, -0.1))  # fmt: skip
    depth = {}
    for x in (0.0, 0.3):
        spec = mujoco.MjSpec.from_string(f"""<mujoco><worldbody><body name="foot" pos="{x} 0 0.02">
          <freejoint/><geom type="box" size="0.03 0.04 0.01" mass="3"/></body></worldbody></mujoco>""")  # fmt: skip
        add_rigid_cells(spec, field)
        model = spec.compile()
        assert set_rigid_cells(model, field) == 1
        data = mujoco.MjData(model)
        coupling = attach(model, "foot", field)
        coupling.reset(data)
        mujoco.mj_step(model, data, nstep=500)
        depth[x] = float(coupling.last.depth[0])
        if x == 0.0:
            assert data.ncon > 0 and np.all(coupling.last.force == 0.0)
    assert depth[0.0] < 1e-3 and depth[0.3] > 2e-3
    far = mujoco.MjModel.from_xml_string("<mujoco><worldbody/></mujoco>")
    with pytest.raises(MudrftError, match=r"no box for cell \(0, 0\) of the field"):
        set_rigid_cells(far, field)
