"""The morphing foot in the mud model: balance at every step, modes, suction, sinking, batches.

Runs use the paper's W = 25 % mud. Tolerances: the column balance is solved to 1e-10 N,
so 1e-8 N is checked; batch and scalar runs do the same floating-point operations per
element, so they agree to 1e-9 relative (a margin over round-off in the vectorized
reductions).
"""

from __future__ import annotations

import numpy as np
import pytest

import mudrft
from mudrft.feet import Flat, MorphingFoot, SemiCylinder, SemiSphere
from mudrft.simulation import LoadControl, simulate
from mudrft.terrains import MudTerrain

BALANCE_TOL = 1e-8  # [N], see module docstring
MUD = mudrft.paper_mud(0.25)


def run_states(foot, trajectory):
    """Step MudTerrain by hand, keeping the foot state, stress and force of every step."""
    ter = MudTerrain(MUD)
    st = ter.initial_state(foot, trajectory.position[0])
    rows = []
    for k in range(1, len(trajectory)):
        seal = float(foot.seal_factor(st.foot))
        st, out = ter.step(
            foot,
            st,
            trajectory.position[k],
            trajectory.velocity[k],
            trajectory.time[k] - trajectory.time[k - 1],
        )
        rows.append(
            (
                float(out.depth),
                float(out.stress[2]),
                float(st.foot.deflection),
                float(out.force[2]),
                seal,
            )
        )
    return np.array(rows)


@pytest.fixture(scope="module")
def gait_rows():
    return run_states(MorphingFoot(), mudrft.gait(0.2))


@pytest.fixture(scope="module")
def plunge():
    return mudrft.plate_intrusion(depth=0.03, speed=0.02, hold=1.0, dt=2e-3)


def check_balance(foot, rows):
    checked = 0
    for depth, sz, delta, fz, _ in rows:
        if depth <= 0:
            assert delta == 0.0 and fz == 0.0
            continue
        spring = float(foot.spring.force(delta))
        # the reported force is the mud force at the balanced deflection
        assert fz == pytest.approx(
            sz * float(foot.effective_area(depth, delta)), rel=1e-12, abs=1e-12
        )
        if delta == 0.0:
            assert fz <= BALANCE_TOL  # column on its extension stop: the mud does not push
        elif delta == foot.stroke:
            assert fz >= spring - BALANCE_TOL  # on the compression stop
        else:
            assert abs(spring - fz) <= BALANCE_TOL
            checked += 1
    return checked


def test_balance_holds_at_every_step_of_a_gait(gait_rows):
    interior = check_balance(MorphingFoot(), gait_rows)
    assert interior > 10  # the pads pass through partial spread, not only the stops
    d = gait_rows[:, 2]
    assert d.max() == MorphingFoot().stroke and d[-1] == 0.0  # spreads, then curls up again


def test_balance_holds_at_every_step_of_an_intrusion_retraction(plunge):
    foot = MorphingFoot()
    rows = run_states(foot, plunge)
    assert check_balance(foot, rows) > 5


def test_pads_curl_and_break_the_seal_on_retraction(gait_rows):
    depth, sz, delta, _, seal = gait_rows.T
    retract = (sz < 0) & (depth > 0)
    assert retract.any()
    assert np.all(delta[retract] == 0.0)  # suction never compresses the column
    assert seal[retract][5:].max() < 1e-3  # after the curl the seal is broken
    assert seal[depth == 0][-1] == 1.0  # and is restored out of the mud


def test_modes_sink_in_order_under_the_same_load():
    # Fig. S4b: expanded sinks least, retracted most, morphing close to expanded;
    # a 49 N load (half a 10 kg biped) settled by mudrft.simulate's LoadControl
    load = LoadControl(weight=49.0, duration=2.0, dt=2e-3)
    sink = {}
    for mode in ("expanded", "morphing", "retracted"):
        res = simulate(MorphingFoot(mode=mode), MUD, load)
        assert abs(res.velocity[-1, 2]) < 1e-3  # settled (m/s)
        sink[mode] = res.depth[-1]
    assert sink["expanded"] <= sink["morphing"] + 1e-9
    assert sink["morphing"] < sink["retracted"]
    assert sink["retracted"] > 1.5 * sink["expanded"]


@pytest.mark.parametrize("which", ["gait", "plunge"])
def test_morphing_has_less_suction_than_expanded(which, plunge):
    tr = mudrft.gait(0.2) if which == "gait" else plunge
    m = {
        mode: simulate(MorphingFoot(mode=mode), MUD, tr).metrics()
        for mode in ("morphing", "expanded")
    }
    assert m["morphing"]["max_suction"] < 0.75 * m["expanded"]["max_suction"]
    # with the same support: the pads are spread while intruding in both modes
    assert m["morphing"]["peak_support"] == pytest.approx(m["expanded"]["peak_support"], rel=1e-3)
    assert m["morphing"]["energy"] < m["expanded"]["energy"]


def test_seal_break_lowers_suction_in_a_slow_retraction(plunge):
    broken = simulate(MorphingFoot(), MUD, plunge).metrics()["max_suction"]
    kept = simulate(MorphingFoot(seal_length=1e3), MUD, plunge).metrics()["max_suction"]
    assert broken < 0.8 * kept


def test_paper_claim_morphing_suction_fraction_is_far_below_fixed_feet():
    # Sec. IV-B: fixed feet suction ~100 % of their support, morphing ~40 %
    tr = mudrft.gait(0.2)
    ratio = {
        f.name: simulate(f, MUD, tr).metrics()["suction_ratio"]
        for f in (Flat(), SemiCylinder(), SemiSphere(), MorphingFoot())
    }
    fixed = min(v for k, v in ratio.items() if k != "morphing")
    assert ratio["morphing"] < 0.6 * fixed
    assert 0.2 < ratio["morphing"] < 0.6  # the paper's 40 % within a factor 1.5 either way


def test_batch_terrain_step_equals_scalar_steps():
    foot = MorphingFoot()
    trs = [mudrft.gait(0.2, depth=d, dt=2e-3) for d in (0.015, 0.03, 0.045)]
    n = min(len(t) for t in trs)
    pos = np.stack([t.position[:n] for t in trs], axis=1)
    vel = np.stack([t.velocity[:n] for t in trs], axis=1)
    time = trs[0].time[:n]
    ter = MudTerrain(MUD)
    st = ter.initial_state(foot, pos[0])
    fb = np.zeros((n, 3, 3))
    for k in range(1, n):
        st, out = ter.step(foot, st, pos[k], vel[k], time[k] - time[k - 1])
        fb[k] = out.force
    for i in range(3):
        st = ter.initial_state(foot, pos[0, i])
        for k in range(1, n):
            st, out = ter.step(foot, st, pos[k, i], vel[k, i], time[k] - time[k - 1])
            np.testing.assert_allclose(out.force, fb[k, i], rtol=1e-9, atol=1e-9)


def test_simulate_by_name_and_csv(tmp_path):
    res = simulate(mudrft.feet.by_name("morphing"), MUD, mudrft.gait(0.2, dt=2e-3))
    assert res.foot == "morphing" and res.areas is not None
    assert np.all(np.isfinite(res.force))
    p = res.to_csv(tmp_path / "run.csv")
    data = np.loadtxt(p, delimiter=",", skiprows=1)
    np.testing.assert_allclose(data[:, 4:], res.force, rtol=1e-8, atol=1e-9)


# ---------------------------------------------------------------------------------------
# the pad-curl delay (D35)
# ---------------------------------------------------------------------------------------
#: The morphing foot's gait at 0.2 m/s on the W = 25 % mud under each evaluation, computed
#: by mudrft before the pad-curl delay existed (commit 0780bab): peak support [N], max
#: suction [N], energy [J] and the sum of |F| over the samples [N].
BEFORE_THE_DELAY = {
    "quasi-static": (80.70013730442608, 10.395629494024877, 1.7786983220340353, 27693.25569611258),
    "ode": (157.53988952166347, 39.59519568436661, 3.3639901380816903, 44123.48921518316),
}


@pytest.mark.parametrize("thixotropy", list(BEFORE_THE_DELAY))
def test_a_zero_pad_curl_delay_is_the_former_behaviour_exactly(thixotropy):
    """The delay's default, 0, lets the pads curl the moment the retraction begins, as
    mudrft did before it had the parameter: the same numbers, recorded before the delay
    existed (numpy 2.4, numba 0.68), to 1e-14 relative: bit for bit there, while numpy 1.24
    rounds one of them a unit in the last place differently."""
    assert MorphingFoot().curl_delay == 0.0
    res = simulate(MorphingFoot(), MudTerrain(MUD, thixotropy=thixotropy), mudrft.gait(0.2))
    m = res.metrics()
    got = (m["peak_support"], m["max_suction"], m["energy"], float(np.abs(res.force).sum()))
    np.testing.assert_allclose(got, BEFORE_THE_DELAY[thixotropy], rtol=1e-14, atol=0.0)


def test_the_pad_curl_delay_holds_the_pads_spread_for_its_time_into_the_retraction():
    """Held: the deflection does not fall (the pads do not curl) while the retraction is
    younger than the delay; then they curl, and the seal breaks later than without it."""
    gait, delay = mudrft.gait(0.2), 0.05
    rows0 = run_states(MorphingFoot(), gait)
    rows = run_states(MorphingFoot(curl_delay=delay), gait)
    deepest = int(np.argmax(rows[:, 0]))  # the retraction begins after this step
    dt = float(gait.time[1] - gait.time[0])
    held = slice(deepest + 1, deepest + 1 + int(delay / dt) - 1)
    assert np.all(np.diff(rows[deepest : held.stop, 2]) >= 0)  # no curl while held
    assert rows0[held, 2].min() < rows[held, 2].min()  # without the delay they curl there
    assert np.all(rows[held, 4] == 1.0)  # the seal holds
    assert rows[held.stop + 20, 2] < rows[held.stop - 1, 2]  # then they curl
    np.testing.assert_array_equal(rows[: deepest + 1], rows0[: deepest + 1])  # intrusion alike


def test_the_pad_curl_delay_is_the_same_compiled_and_stepped():
    """simulate runs the compiled rows (terrains.rows), MudTerrain.step the foot's Python
    path: the delay is carried in both."""
    foot, gait = MorphingFoot(curl_delay=0.055), mudrft.gait(0.2)
    res = simulate(foot, MUD, gait)
    stepped = run_states(foot, gait)
    np.testing.assert_allclose(res.force[1:, 2], stepped[:, 3], rtol=0, atol=1e-9)
    assert (
        res.metrics()["max_suction"]
        > 2 * simulate(MorphingFoot(), MUD, gait).metrics()["max_suction"]
    )


def test_the_pad_curl_delay_is_a_checked_parameter_of_the_foot():
    foot = MorphingFoot(curl_delay=0.05)
    assert foot.as_dict()["curl_delay"] == 0.05 and foot != MorphingFoot()
    assert foot.replace(mode="expanded").curl_delay == 0.05
    assert foot.replace(curl_delay=0.0) == MorphingFoot()
    assert "curl_delay=0.05 s" in repr(foot)
    with pytest.raises(mudrft.MudrftError, match="curl_delay must be >= 0"):
        MorphingFoot(curl_delay=-0.01)
