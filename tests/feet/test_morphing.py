"""The morphing foot's mechanism: kinematics, springs, forces and the column balance (D30-D37).

No mud dynamics here (see test_morphing_mud.py): stresses are given. Tolerances: the
kinematics are closed forms evaluated in double precision, so joint distances hold to
1e-12 m; the balance solver stops at |R| <= 1e-10 N, so 1e-8 N leaves margin.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from mudrft._validation import MudrftError
from mudrft.feet import MorphingFoot, by_name
from mudrft.feet.morphing import MorphingFootGeometry, TwoStageSpring, pads

BALANCE_TOL = 1e-8  # [N]; the solver converges to 1e-10 N (see module docstring)
FOOT = MorphingFoot()
G = FOOT.geometry
S = FOOT.spring


def pad_area_independent(length: float) -> float:
    """Trapezoid area from the pivot to ``length`` along a pad, from the dataclass fields."""
    w_at = G.pad_inner_width + (G.pad_outer_width - G.pad_inner_width) * length / G.pad_length
    return 0.5 * length * (G.pad_inner_width + w_at)


# -- kinematics ---------------------------------------------------------------------------------
def test_defaults_are_the_documented_reconstruction():
    # D30: 8 pads, ~96 mm across when spread, full spread under about a quarter of a
    # 10 kg biped's weight; these numbers are stated in docs/model.md
    assert G.n_pads == 8
    spread_diameter = 2 * (G.base_radius + G.pad_length * math.cos(G.expanded_angle))
    assert 0.080 <= spread_diameter <= 0.100
    full = float(FOOT.rigid_ground(FOOT.stroke).force)
    assert 0.1 * 98.1 < full < 0.35 * 98.1
    assert by_name("morphing") == FOOT


def test_linkage_joints_keep_their_lengths():
    for dl in np.linspace(0.0, FOOT.stroke, 9):
        p = FOOT.linkage_points(dl)
        assert np.linalg.norm(p["C"] - p["A"]) == pytest.approx(G.crank_length, abs=1e-12)
        assert np.linalg.norm(p["B"] - p["C"]) == pytest.approx(G.coupler_length, abs=1e-12)
        assert np.linalg.norm(p["P"] - p["A"]) == pytest.approx(G.pad_length, abs=1e-12)
        # the upper pole moves down by exactly the deflection
        assert p["B"][1] == pytest.approx(FOOT.linkage_points(0.0)["B"][1] - dl, abs=1e-12)


def test_pad_angle_monotone_and_nearly_linear_in_deflection():
    d = np.linspace(0.0, FOOT.stroke, 2001)
    th = FOOT.pad_angle(d)
    assert th[0] == pytest.approx(G.retracted_angle, abs=1e-9)
    assert th[-1] == pytest.approx(G.expanded_angle, abs=1e-9)
    assert np.all(np.diff(th) < 0)
    # Fig. S3a: "the foot deflection is linear with the deformation angle"; the slider-crank
    # departs from its chord by at most 2 deg (about 3 % of the 70 deg travel)
    chord = th[0] + (th[-1] - th[0]) * d / d[-1]
    assert np.degrees(np.abs(th - chord)).max() < 2.0


def test_inverse_kinematics_round_trip():
    d = np.linspace(0.0, FOOT.stroke, 50)
    np.testing.assert_allclose(FOOT.deflection_at(FOOT.pad_angle(d)), d, atol=1e-12)


def test_footprint_area_increases_with_deflection():
    d = np.linspace(0.0, FOOT.stroke, 400)
    a = FOOT.footprint_area(d)
    assert np.all(np.diff(a) > 0)
    for depth in (0.003, 0.006, 0.015, 0.03, 0.06):  # submerged footprint at any depth
        assert np.all(np.diff(FOOT.footprint_area(d, depth)) >= 0)
    spread = math.pi * G.base_radius**2 + G.n_pads * pad_area_independent(G.pad_length) * math.cos(
        G.expanded_angle
    )
    assert a[-1] == pytest.approx(spread, rel=1e-12)


@given(depth=st.floats(0.0, 0.08), d1=st.floats(0.0, 1.0), d2=st.floats(0.0, 1.0))
@settings(max_examples=40, deadline=None)
def test_submerged_pad_area_grows_as_pads_spread(depth, d1, d2):
    # spreading (more deflection) lowers every pad point, so no part of a pad leaves the mud
    lo, hi = sorted((d1 * FOOT.stroke, d2 * FOOT.stroke))
    th_lo, th_hi = FOOT.pad_angle(lo), FOOT.pad_angle(hi)
    assert pads.submerged_length(G, depth, th_hi) >= pads.submerged_length(G, depth, th_lo) - 1e-15


# -- springs ------------------------------------------------------------------------------------
def test_spring_is_continuous_across_the_two_stages():
    knee = S.knee_deflection
    eps = 1e-12
    left, right = float(S.force(knee - eps)), float(S.force(knee + eps))
    assert abs(right - left) < 1e-8  # slope <= 6000 N/m times 2e-12 m
    assert float(S.force(knee)) == pytest.approx(S.soft_stiffness * S.soft_travel, rel=1e-12)
    # deflection under a force is continuous too, and inverts the force law
    f = np.linspace(0.0, float(FOOT.rigid_ground(FOOT.stroke).force), 500)
    d = S.deflection(f)
    assert np.all(np.diff(d) > 0)
    np.testing.assert_allclose(S.force(d), f, rtol=1e-12, atol=1e-12)
    fk = S.knee_force
    assert abs(float(S.deflection(fk + 1e-9)) - float(S.deflection(fk - 1e-9))) < 1e-11


def test_rigid_ground_has_two_stiffness_regions():
    # Fig. S3b: soft region (both springs in series) then hard region (hard spring alone)
    d = np.linspace(0.0, FOOT.stroke, 1001)
    r = FOOT.rigid_ground(d)
    slope = np.diff(r.force) / np.diff(d)
    soft = d[1:] < S.knee_deflection
    hard = d[:-1] > S.knee_deflection
    series = S.soft_stiffness * S.hard_stiffness / (S.soft_stiffness + S.hard_stiffness)
    np.testing.assert_allclose(slope[soft], series, rtol=1e-9)
    np.testing.assert_allclose(slope[hard], S.hard_stiffness, rtol=1e-9)
    assert set(np.unique(r.stiffness)) == {series, S.hard_stiffness}
    np.testing.assert_array_equal(r.pad_angle, FOOT.pad_angle(d))


# -- forces -------------------------------------------------------------------------------------
def test_expanded_vertical_force_is_the_plate_rule_on_base_and_pads():
    foot = MorphingFoot(mode="expanded")
    sz = 1.7e4
    th = G.expanded_angle
    rule = math.cos(th) ** 2 * math.cos(th) + math.sin(th) ** 2 * math.sin(th)  # f_n cos + f_t sin
    depth = 0.05  # pads fully under the surface
    want = sz * (math.pi * G.base_radius**2 + G.n_pads * pad_area_independent(G.pad_length) * rule)
    assert foot.resultant(depth, [0.0, 0.0, sz], 0.3)[2] == pytest.approx(want, rel=1e-12)


def test_retracted_pads_count_only_below_the_surface():
    foot = MorphingFoot(mode="retracted")
    th = G.retracted_angle
    rule = math.cos(th) ** 3 + math.sin(th) ** 3
    for depth in (0.002, 0.015, 0.03):
        length = min(max((depth - G.pivot_height) / math.sin(th), 0.0), G.pad_length)
        want = 1e4 * (math.pi * G.base_radius**2 + G.n_pads * pad_area_independent(length) * rule)
        assert foot.resultant(depth, [0.0, 0.0, 1e4], 0.0)[2] == pytest.approx(want, rel=1e-12)


def test_horizontal_forces_are_symmetric_and_odd():
    foot = MorphingFoot(mode="expanded")
    s = [2e3, 2e3, 0.0]
    fx = foot.resultant(0.02, s, 0.0)
    fy = foot.resultant(0.02, s, math.pi / 2)
    assert fx[0] == pytest.approx(fy[1], rel=1e-12)  # 8-fold symmetry: x and y alike
    assert fx[1] == 0.0 and fy[0] == pytest.approx(0.0, abs=1e-12)
    # world-frame force flips with the motion (decision D9): stresses along the motion
    f1 = foot.force(0.02, [2e3, 1e3, 5e3], 0.4)
    f2 = foot.force(0.02, [2e3, 1e3, 5e3], 0.4 + math.pi)
    np.testing.assert_allclose(f2, f1 * [-1, -1, 1], rtol=1e-12)
    assert f1[0] < 0 and f1[1] < 0  # resisting motion toward +x, +y


def test_zero_depth_gives_zero_force():
    np.testing.assert_array_equal(FOOT.resultant(0.0, [1e3, 1e3, 1e3], 0.2), 0.0)


# -- the column balance ---------------------------------------------------------------------------
def balance_ok(foot, depth, sz, delta):
    r = foot.residual(delta, depth, sz)
    if delta <= 0.0:
        return r >= -BALANCE_TOL  # stop at 0: the mud does not compress the column
    if delta >= foot.stroke:
        return r <= BALANCE_TOL  # stop at the stroke: the mud pushes harder than the springs
    return abs(r) <= BALANCE_TOL


@given(
    depth=st.floats(0.0, 0.08),
    sz=st.floats(-6e4, 6e4),
    prev=st.floats(0.0, 1.0),
)
@settings(max_examples=50, deadline=None)
def test_equilibrium_satisfies_the_balance(depth, sz, prev):
    delta = float(FOOT.equilibrium(depth, sz, previous=prev * FOOT.stroke))
    assert 0.0 <= delta <= FOOT.stroke
    assert balance_ok(FOOT, depth, sz, delta)


def test_suction_leaves_the_column_unloaded():
    assert float(FOOT.equilibrium(0.02, -5e3, previous=FOOT.stroke)) == 0.0


def test_unique_root_where_the_residual_is_monotone():
    # D34: with the pads wholly out of the mud (depth <= pivot height) or wholly in it,
    # F_s(delta)/A_z(delta) is strictly increasing, so R = F_s - sz*A_z has one root for
    # every sz > 0, whatever the previous deflection
    d = np.linspace(1e-7, FOOT.stroke, 3000)
    th = FOOT.pad_angle(d)
    full = G.pivot_height + G.pad_length
    for depth in (0.001, G.pivot_height, full, full + 0.02):
        ratio = S.force(d) / pads.vertical_area(FOOT.geometry, depth, th)
        assert np.all(np.diff(ratio) > 0), depth
        for sz in np.linspace(100.0, 6e4, 7):
            roots = {
                round(float(FOOT.equilibrium(depth, sz, previous=p)), 12)
                for p in (0.0, 0.004, FOOT.stroke)
            }
            assert len(roots) == 1


def test_snap_through_is_resolved_by_continuation():
    # pads dipping into the surface catch more mud as they spread: at 10 mm and 4.2 kPa the
    # residual has three roots; loading from curled stays on the lowest, unloading from
    # spread on the highest (the overdamped column), and both are balanced
    depth, sz = 0.010, 4200.0
    grid = np.linspace(0.0, FOOT.stroke, 4001)
    r = FOOT.residual(grid, depth, sz)
    crossings = np.flatnonzero(np.diff(np.sign(r)) != 0)
    assert crossings.size == 3
    low = float(FOOT.equilibrium(depth, sz, previous=0.0))
    high = float(FOOT.equilibrium(depth, sz, previous=FOOT.stroke))
    assert low < grid[crossings[1]] < high
    assert balance_ok(FOOT, depth, sz, low) and balance_ok(FOOT, depth, sz, high)
    # the loading branch is what the stateless resultant uses
    fz = FOOT.resultant(depth, [0.0, 0.0, sz], 0.0)[2]
    assert fz == pytest.approx(float(S.force(low)), abs=BALANCE_TOL)


@pytest.mark.parametrize("few", [0, 10**9], ids=["find_root", "floats"])
def test_batch_equals_scalar(monkeypatch, few):
    # with one solver for every call (few=0: find_root; huge: the float path), a batch gives bit for
    # bit the deflections of single calls; the default threshold is checked below
    from mudrft.feet.morphing import equilibrium

    monkeypatch.setattr(equilibrium, "_FEW", few)
    rng = np.random.default_rng(3)
    depth = rng.uniform(0.0, 0.05, 64)
    sz = rng.uniform(-2e4, 4e4, 64)
    prev = rng.uniform(0.0, FOOT.stroke, 64)
    batch = FOOT.equilibrium(depth, sz, previous=prev)
    single = [
        float(FOOT.equilibrium(a, b, previous=c)) for a, b, c in zip(depth, sz, prev, strict=True)
    ]
    np.testing.assert_allclose(batch, single, rtol=0, atol=1e-15)
    stress = np.stack([sz * 0.3, sz * 0.1, sz], axis=-1)
    heads = rng.uniform(0.0, math.pi / 2, 64)
    fb = FOOT.resultant(depth, stress, heads)
    fs = np.array([FOOT.resultant(a, b, c) for a, b, c in zip(depth, stress, heads, strict=True)])
    np.testing.assert_allclose(fb, fs, rtol=1e-12, atol=1e-12)


def test_locked_modes_ignore_the_load():
    for mode, want in (("expanded", FOOT.stroke), ("retracted", 0.0)):
        foot = MorphingFoot(mode=mode)
        st0 = foot.initial_foot_state()
        st1, _ = foot.contact_force(st0, 0.02, np.array([0.0, 0.0, 3e4]), 0.0, 1e-3)
        assert float(st1.deflection) == want
        assert float(foot.seal_factor(st1)) == 1.0
        # and the state-free force equals the stepped one
        np.testing.assert_allclose(
            foot.contact_force(st0, 0.02, [1e3, 2e3, 3e4], 0.5, 1e-3)[1],
            foot.force(0.02, [1e3, 2e3, 3e4], 0.5),
            rtol=1e-14,
        )


def test_seal_factor_drops_as_pads_curl_from_their_most_spread():
    st = FOOT.initial_foot_state()
    assert float(FOOT.seal_factor(st)) == 1.0
    st, _ = FOOT.contact_force(st, 0.02, [0.0, 0.0, 4e4], 0.0, 1e-3)  # pressed: spread
    assert float(st.deflection) == FOOT.stroke and float(FOOT.seal_factor(st)) == 1.0
    st, _ = FOOT.contact_force(st, 0.02, [0.0, 0.0, -4e3], 0.0, 1e-3)  # suction: curls up
    lift = G.pad_length * (math.sin(G.retracted_angle) - math.sin(G.expanded_angle))
    assert float(FOOT.seal_factor(st)) == pytest.approx(1 - math.tanh(lift / FOOT.seal_length))
    assert float(FOOT.seal_factor(st)) < 1e-6
    st, _ = FOOT.contact_force(st, 0.0, [0.0, 0.0, 0.0], 0.0, 1e-3)  # out of the mud: reset
    assert float(FOOT.seal_factor(st)) == 1.0


def test_overrides_and_replace():
    f = MorphingFoot(pad_length=0.05, hard_stiffness=12000.0)
    assert f.geometry.pad_length == 0.05 and f.spring.hard_stiffness == 12000.0
    g = f.replace(mode="expanded", soft_stiffness=400.0)
    assert (
        g.mode == "expanded" and g.spring.soft_stiffness == 400.0 and g.geometry.pad_length == 0.05
    )
    assert (
        MorphingFoot(MorphingFootGeometry(pad_length=0.05), TwoStageSpring(hard_stiffness=12000.0))
        == f
    )
    # a longer pad spreads wider and raises L_c (D36)
    assert f.characteristic_length > FOOT.characteristic_length


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"mode": "folded"}, "mode must be one of"),
        ({"pad_lenght": 0.03}, "unknown MorphingFoot parameter"),
        ({"soft_stiffness": -1.0}, "soft_stiffness must be > 0"),
        ({"hard_stiffness": 100.0}, "hard_stiffness must be >= soft_stiffness"),
        ({"soft_travel": 0.02}, "bottom out within the stroke"),
        ({"coupler_length": 0.005}, "coupler_length"),
        ({"expanded_angle": 1.4}, "retracted_angle must exceed"),
        ({"n_pads": 0}, "n_pads"),
        # the pivots of ten 10 mm pads do not fit around the 14 mm base (tangent decagon)
        ({"n_pads": 10}, r"n_pads = 10 pads .* overlap at their pivots.* <= .* = 0\.0091 m"),
        # a million pads hung every force evaluation (found by the sweep fuzz)
        ({"n_pads": 10**6, "pad_inner_width": 1e-6}, "n_pads must be at most 100"),
        ({"seal_length": 0.0}, "seal_length must be > 0"),
        ({"column_radius": 0.02}, "column_radius must be <="),
    ],
)
def test_bad_parameters_raise(kwargs, match):
    with pytest.raises(MudrftError, match=match):
        MorphingFoot(**kwargs)


def test_pads_that_just_fit_around_the_base_are_a_foot():
    """Nine 10 mm pads fit the 14 mm base (2 r tan(pi/9) = 10.2 mm), and so do twelve pads of
    the width that tiles it exactly."""
    assert MorphingFoot(n_pads=9).geometry.n_pads == 9
    width = 2 * 0.014 * math.tan(math.pi / 12)
    foot = MorphingFoot(n_pads=12, pad_inner_width=width)
    assert foot.resultant(0.01, [0.0, 0.0, 1e3], 0.0)[2] > 0


def test_bad_inputs_raise():
    with pytest.raises(MudrftError, match="heading must lie in"):
        FOOT.resultant(0.01, [0.0, 0.0, 1.0], 2.0)
    with pytest.raises(MudrftError, match="depth must be >= 0"):
        FOOT.resultant(-0.01, [0.0, 0.0, 1.0], 0.0)
    with pytest.raises(MudrftError, match="stress must have shape"):
        FOOT.resultant(0.01, [0.0, 1.0], 0.0)
    with pytest.raises(MudrftError, match="deflection must lie in"):
        FOOT.pad_angle(0.05)
    with pytest.raises(MudrftError, match="sz must be finite"):
        FOOT.equilibrium(0.01, np.nan)


def test_drawing_helpers_are_consistent():
    corners = FOOT.pad_corners(FOOT.stroke)
    assert corners.shape == (8, 4, 3)
    rim = np.linalg.norm(corners[:, 2:, :2].mean(axis=1), axis=-1)
    np.testing.assert_allclose(
        rim, G.base_radius + G.pad_length * math.cos(G.expanded_angle), rtol=1e-12
    )
    el = FOOT.elements(FOOT.stroke)
    walls = (
        2
        * math.pi
        * (G.base_radius * G.pivot_height + G.column_radius * (G.height - G.pivot_height))
    )
    np.testing.assert_allclose(  # base disk, its rim and the column, both faces of 8 pads (D159)
        el.areas.sum(),
        math.pi * G.base_radius**2 + walls + 2 * 8 * pad_area_independent(G.pad_length),
        rtol=1e-12,
    )
    np.testing.assert_allclose(np.linalg.norm(el.normals, axis=1), 1.0, rtol=1e-12)
    cop = FOOT.center_of_pressure(0.03, [0.0, 0.0, 1e4], 0.0)
    assert cop[0] == 0.0 and cop[1] == 0.0 and 0.0 <= cop[2] <= 0.03


# -- the package and its root finder ------------------------------------------------------------
def test_package_keeps_the_names_of_the_former_module():
    import mudrft.feet
    import mudrft.feet.morphing as pkg

    former = (
        "MODES",
        "MorphingFoot",
        "MorphingFootGeometry",
        "MorphingState",
        "RigidGroundResponse",
        "TwoStageSpring",
    )
    assert set(former) <= set(pkg.__all__)
    assert mudrft.feet.MorphingFoot is pkg.MorphingFoot
    assert pkg.MODES == ("morphing", "expanded", "retracted")
    assert isinstance(FOOT.initial_foot_state(), pkg.MorphingState)
    assert isinstance(FOOT.rigid_ground(0.0), pkg.RigidGroundResponse)


def test_old_scipy_takes_the_float_path_with_the_same_roots(monkeypatch):
    # SciPy < 1.15 has no scipy.optimize.elementwise.find_root; every element then takes the
    # float path (the same scan, bisection). Same brackets, so the same roots: both stop at
    # |R| <= 1e-10 N and |dR/d(delta)| >= 600 N/m at these roots, so they agree to 1e-12 m
    from mudrft.feet.morphing import equilibrium

    rng = np.random.default_rng(3)
    depth = rng.uniform(0.0, 0.05, 64)
    sz = rng.uniform(-2e4, 4e4, 64)
    prev = rng.uniform(0.0, FOOT.stroke, 64)
    vectorized = FOOT.equilibrium(depth, sz, previous=prev)
    monkeypatch.setattr(equilibrium, "find_root", None)
    fallback = FOOT.equilibrium(depth, sz, previous=prev)
    np.testing.assert_allclose(fallback, vectorized, rtol=0, atol=1e-12)
    for a, b, c in zip(depth, sz, fallback, strict=True):
        assert balance_ok(FOOT, a, b, c)
    # the snap-through keeps its hysteresis: loading stays below the middle root, unloading above
    grid = np.linspace(0.0, FOOT.stroke, 4001)
    crossings = np.flatnonzero(np.diff(np.sign(FOOT.residual(grid, 0.010, 4200.0))) != 0)
    low = float(FOOT.equilibrium(0.010, 4200.0, previous=0.0))
    high = float(FOOT.equilibrium(0.010, 4200.0, previous=FOOT.stroke))
    assert low < grid[crossings[1]] < high
    assert balance_ok(FOOT, 0.010, 4200.0, low) and balance_ok(FOOT, 0.010, 4200.0, high)


def test_a_single_foot_takes_the_float_path_and_a_batch_find_root(monkeypatch):
    # find_root has ~2 ms of fixed cost a call, so up to _FEW moving elements take the float
    # path one by one (balanced_deflection_on_floats, which the compiled coupling runs). Same
    # brackets and tolerances, so both stop within |R| <= 1e-10 N of the same root:
    # |dR/d(delta)| >= 600 N/m at these roots, so they agree to 1e-12 m, and the forces to
    # 1e-10 relative
    from mudrft.feet.morphing import equilibrium

    if equilibrium.find_root is None:  # pragma: no cover - SciPy < 1.15: the float path only
        pytest.skip("scipy.optimize.elementwise.find_root needs SciPy >= 1.15")
    calls = []

    def spy(f, init, **kw):
        calls.append(init[0].size)
        return find_root(f, init, **kw)

    find_root = equilibrium.find_root
    monkeypatch.setattr(equilibrium, "find_root", spy)
    rng = np.random.default_rng(5)
    depth = rng.uniform(0.0, 0.03, 64)
    sz = rng.uniform(500.0, 1.2e4, 64)
    prev = rng.uniform(0.0, FOOT.stroke, 64)
    batch = FOOT.equilibrium(depth, sz, previous=prev)
    assert len(calls) == 1 and calls[0] > equilibrium._FEW  # one find_root for the batch
    single = np.array(
        [float(FOOT.equilibrium(a, b, previous=c)) for a, b, c in zip(depth, sz, prev, strict=True)]
    )
    assert len(calls) == 1  # and none for the single feet
    assert np.count_nonzero((single > 0) & (single < FOOT.stroke)) > equilibrium._FEW
    np.testing.assert_allclose(batch, single, rtol=0, atol=1e-12)
    np.testing.assert_allclose(
        sz * FOOT.effective_area(depth, batch), sz * FOOT.effective_area(depth, single), rtol=1e-10
    )
    for a, b, c in zip(depth, sz, single, strict=True):
        assert balance_ok(FOOT, a, b, c)


def test_forces_at_the_balanced_deflection_are_the_resultant_and_it_checks_the_deflection():
    # forces_at is resultant with the deflection given instead of balanced: at the column's
    # own balance (equilibrium loaded from rest, D34) the two agree exactly; spreading the
    # pads (a larger deflection) only adds footprint in the mud, so the vertical force
    # grows once the pads reach the mud (at 4 mm only the base plate is in it)
    depth = np.array([0.004, 0.01, 0.02])
    stress = np.array([[900.0, 700.0, 4000.0], [1500.0, 1200.0, 9000.0], [0.0, 0.0, 15000.0]])
    heading = np.array([0.0, 0.3, 1.0])
    delta = FOOT.equilibrium(depth, stress[:, 2])
    np.testing.assert_array_equal(
        FOOT.forces_at(depth, stress, heading, delta), FOOT.resultant(depth, stress, heading)
    )
    curled = FOOT.forces_at(depth, stress, heading, 0.0)
    spread = FOOT.forces_at(depth, stress, heading, FOOT.stroke)
    assert spread[0, 2] == pytest.approx(curled[0, 2], rel=1e-12)
    assert np.all(spread[1:, 2] > 1.5 * curled[1:, 2])
    with pytest.raises(MudrftError, match="deflection"):
        FOOT.forces_at(0.01, [0.0, 0.0, 1e4], 0.0, 2 * FOOT.stroke)


def test_posed_is_refused_with_the_reason_and_where_a_tilted_morphing_foot_is_posed():
    """`foot.posed(rotation)` is listed as what every foot has; the morphing foot answered
    AttributeError. Its pads move, so it has no rotated mesh: a clear refusal."""
    from scipy.spatial.transform import Rotation

    with pytest.raises(MudrftError, match=r"posed\(rotation\).*pads open and curl.*D60a"):
        MorphingFoot().posed(Rotation.from_euler("y", 10, degrees=True))
