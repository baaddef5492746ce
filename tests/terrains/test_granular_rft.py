"""Granular RFT (Li et al. 2013; 3D extension of Treers et al. 2021)."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

import mudrft
from mudrft import MudrftError
from mudrft._validation import PlausibilityWarning
from mudrft.baselines import GranularRFT, li2013_alpha, rft_forces, run_terrain, treers_weights
from mudrft.feet.meshgen import semisphere_mesh
from mudrft.terrains import GranularRFT3D
from mudrft.terrains.granular_rft import GRANULAR_MEDIA, _group_weights, _prepare, horizontal_share

# Li, Zhang & Goldman (Science 2013), generic first-order Fourier coefficients, typed
# here from the publication (not imported from mudrft) so the hand computation below
# is independent of the implementation.
LI = {
    "A00": 0.206,
    "A10": 0.169,
    "B11": 0.212,
    "B01": 0.358,
    "Bm11": 0.055,
    "C11": -0.124,
    "C01": 0.253,
    "Cm11": 0.007,
    "D10": 0.088,
}


def alpha_by_hand(beta: float, gamma: float) -> tuple[float, float]:
    """Li et al.'s Fourier series sum_{m=-1..1, n=0..1} written out term by term."""
    az = (
        LI["A00"]
        + LI["A10"] * math.cos(2 * beta)
        + LI["B01"] * math.sin(gamma)
        + LI["B11"] * math.sin(2 * beta + gamma)
        + LI["Bm11"] * math.sin(-2 * beta + gamma)
    )
    ax = (
        LI["C01"] * math.cos(gamma)
        + LI["C11"] * math.cos(2 * beta + gamma)
        + LI["Cm11"] * math.cos(-2 * beta + gamma)
        + LI["D10"] * math.sin(2 * beta)
    )
    return ax, az


# (beta, gamma) points: horizontal plate pushed down, 45 deg plate and motion, a steep plate
# pulled up and forward, a vertical plate dragged horizontally, a plate moving down-back
ANGLES = [
    (0.0, math.pi / 2),
    (math.pi / 4, math.pi / 4),
    (-math.pi / 4, math.pi / 3),
    (math.pi / 3, -math.pi / 6),
    (math.pi / 2 - 1e-9, 0.0),
    (math.pi / 6, math.pi / 2),
]


@pytest.mark.parametrize(("beta", "gamma"), ANGLES)
def test_generic_alpha_matches_the_published_fourier_series(beta, gamma):
    ax, az = li2013_alpha(beta, gamma)
    ax0, az0 = alpha_by_hand(beta, gamma)
    # same series, different code: agreement to rounding (1e-12 absolute on O(1) values)
    assert float(ax) == pytest.approx(ax0, abs=1e-12)
    assert float(az) == pytest.approx(az0, abs=1e-12)


def test_published_landmarks_of_the_generic_fit():
    # vertical penetration of a horizontal plate: the generic fit is normalised to 1 there,
    # and by left-right symmetry it has no horizontal component
    ax, az = li2013_alpha(0.0, math.pi / 2)
    assert float(az) == pytest.approx(1.000, abs=1e-12)
    assert float(ax) == pytest.approx(0.0, abs=1e-12)
    # vertical plate dragged horizontally: drag C01 - C11 - Cm11, lift A00 - A10 (by hand)
    ax, az = li2013_alpha(math.pi / 2, 0.0)
    assert float(ax) == pytest.approx(0.253 + 0.124 - 0.007, abs=1e-12)
    assert float(az) == pytest.approx(0.206 - 0.169, abs=1e-12)
    # pulling a horizontal plate straight up: alpha_z = A00 + A10 - B01 - B11 - Bm11 < 0
    assert float(li2013_alpha(0.0, -math.pi / 2)[1]) == pytest.approx(-0.25, abs=1e-12)


def _plate(
    beta: float,
    gamma: float,
    extension: str,
    zeta: float = 2e5,
    depth: float = 0.02,
    area: float = 1e-3,
):
    """One plate element with attack angle beta moving at intrusion angle gamma in the x-z plane."""
    n = np.array([[math.sin(beta), 0.0, -math.cos(beta)]])
    v = np.array([math.cos(gamma), 0.0, -math.sin(gamma)])
    return rft_forces(n, [depth], [area], v, zeta=zeta, extension=extension)


@pytest.mark.parametrize("extension", ["treers2021", "planar"])
@pytest.mark.parametrize(("beta", "gamma"), ANGLES)
def test_plate_force_is_zeta_alpha_depth_area(beta, gamma, extension):
    zeta, depth, area = 2e5, 0.02, 1e-3
    f = _plate(beta, gamma, extension, zeta, depth, area)
    ax, az = alpha_by_hand(beta, gamma)
    leading = math.sin(beta + gamma) > 0  # n . v for this plate and velocity
    expected = np.array([-ax, 0.0, az]) * zeta * depth * area if leading else np.zeros(3)
    # in-plane motion: both extensions reduce to 2D RFT (f1 = 0, f23 = 1); rounding only
    np.testing.assert_allclose(f, expected, rtol=1e-10, atol=1e-12)


def test_trailing_plate_carries_nothing():
    # plate facing down, moving up and back: trailing, so no force at all (no suction)
    assert np.all(_plate(0.3, -1.0, "treers2021") == 0.0)


def test_treers_weights_limits_and_monotonic():
    u = np.linspace(0.0, 1.0, 101)
    f1, f23 = treers_weights(u, u)
    assert f1[0] == pytest.approx(0.0, abs=1e-15) and f1[-1] == pytest.approx(1.0, abs=1e-15)
    assert f23[0] == pytest.approx(0.0, abs=1e-15) and f23[-1] == pytest.approx(1.0, abs=1e-15)
    assert np.all(np.diff(f1) > 0) and np.all(np.diff(f23) > 0)


unit3 = st.tuples(*[st.floats(-1, 1, allow_nan=False)] * 3).filter(
    lambda v: 0.2 < np.linalg.norm(v)
)


@settings(max_examples=40, deadline=None)
@given(n=unit3, v=unit3, yaw=st.floats(-math.pi, math.pi))
@example(n=(1.0, 0.0, 0.0), v=(1.27e-25, 1.0, 0.0), yaw=1.0)  # n.v ~ 1e-25: rounding flips its sign
@example(n=(1.0, 0.0, 5.128761427363178e-277), v=(-1.43e-189, 0.75, 1.0), yaw=1.0)
# |n_h| = 4e-12 moving straight down, and |v_h| = 5e-10 on a flat facet: found by 20,000
# random examples; below 1e-9 the facet's horizontal direction was the world x axis
@example(n=(0.0, 1e-12, -0.25), v=(0.0, 0.0, -1.0), yaw=1.0)
@example(n=(0.0, 0.0, 1.0), v=(0.0, 4.889658737509672e-10, 1.0), yaw=1.0)
def test_rft_is_invariant_under_rotation_about_the_vertical(n, v, yaw):
    n = np.array(n) / np.linalg.norm(n)
    v = np.array(v) / np.linalg.norm(v)
    c, s = math.cos(yaw), math.sin(yaw)
    R = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    f = rft_forces([n], [0.01], [1e-3], v, zeta=1e5)
    fr = rft_forces([R @ n], [0.01], [1e-3], R @ v, zeta=1e5)
    # rotating foot and motion about z rotates the force; rounding only
    np.testing.assert_allclose(fr, R @ f, atol=1e-12)


@pytest.mark.parametrize("edge", [1 - 1e-3, 1 - 2e-3])
def test_a_nearly_flat_facet_moves_the_force_continuously_across_the_horizontal_band(edge):
    """Treers et al.'s switch at |n_z| = 1 - 1e-3 (frame from the motion above it, from the
    normal below) made the force jump by 3 % under a tilt of 1e-9; across either edge of the
    band where the two frames are mixed (horizontal_share) it now moves by a tiny amount."""
    v = np.array([1.0, 0.0, -1.0]) / math.sqrt(2)

    def force(nz):
        n = [0.0, math.sqrt(1 - nz * nz), -nz]  # tilted toward +y, moving along +x and down
        return rft_forces([n], [0.01], [1e-3], v, zeta=1e5)

    above, below = force(edge + 1e-9), force(edge - 1e-9)
    assert np.linalg.norm(above - below) < 1e-6 * np.linalg.norm(above)
    # and the frames do differ there: the band mixes two different forces
    assert np.linalg.norm(force(1 - 1e-3) - force(1 - 2e-3)) > 1e-2 * np.linalg.norm(above)


def test_horizontal_share_is_the_sharp_rule_outside_its_band():
    nz = np.array([-1.0, 0.9995, -(1 - 1e-3), 1 - 2e-3, 0.99, 0.0])
    np.testing.assert_array_equal(horizontal_share(nz), [1.0, 1.0, 1.0, 0.0, 0.0, 0.0])
    inside = np.linspace(1 - 2e-3, 1 - 1e-3, 7)[1:-1]
    assert np.all(np.diff(horizontal_share(inside)) > 0)
    assert np.all((horizontal_share(inside) > 0) & (horizontal_share(inside) < 1))


@settings(max_examples=40, deadline=None)
@given(n=unit3, v=unit3)
def test_only_leading_submerged_elements_carry_force(n, v):
    n = np.array(n) / np.linalg.norm(n)
    v = np.array(v) / np.linalg.norm(v)
    f = rft_forces([n, n], [0.01, -0.01], [1e-3, 1e-3], v, per_element=True)
    assert np.all(f[1] == 0.0)  # above the surface
    if n @ v <= 0:
        assert np.all(f[0] == 0.0)  # trailing


def plate_force_by_hand(trajectory, zeta, area):
    """Horizontal plate pushed down: F_z = zeta * depth * area, as alpha_z(0, pi/2) = 1."""
    down = trajectory.velocity[:, 2] < 0
    hold = trajectory.velocity[:, 2] == 0
    return np.where(down | hold, zeta * trajectory.depth * area, 0.0)


def test_vertical_plate_test_matches_hand_formula_and_has_no_suction(box):
    tr = mudrft.plate_intrusion(depth=0.02, dt=2e-3)  # 20 mm: the 50 mm box is never buried
    h = run_terrain(GranularRFT(), box, tr)
    expected = plate_force_by_hand(tr, GranularRFT().zeta, box.length * box.width)
    # sides are edge-on (not leading) and the top stays above the surface: exact to rounding
    np.testing.assert_allclose(h.force[:, 2], expected, rtol=1e-10, atol=1e-9)
    # alpha_x(0, pi/2) = 0 by symmetry; cos(pi/2) leaves ~1e-17 of rounding
    np.testing.assert_allclose(h.force[:, :2], 0.0, atol=1e-12)
    assert np.all(h.force[:, 2] >= 0.0)  # no suction
    retract = tr.velocity[:, 2] > 0
    assert np.all(h.force[retract, 2] == 0.0)  # "dropped to zero immediately" (Fig. S6a)


def test_at_rest_the_last_direction_is_kept(box):
    tr = mudrft.plate_intrusion(depth=0.02, hold=0.5, dt=2e-3)
    h = run_terrain(GranularRFT(), box, tr)
    hold = tr.velocity[:, 2] == 0
    hold &= tr.depth > 0
    # a standing foot stays supported at the full intrusion force (decision D52)
    np.testing.assert_allclose(
        h.force[hold, 2], GranularRFT().zeta * 0.02 * box.length * box.width, rtol=1e-12
    )


@pytest.mark.parametrize("speed", [0.13, 0.2, 0.26])
def test_bottom_never_pulls_on_the_gait(box, speed):
    tr = mudrft.gait(speed)
    el = box.elements()
    bottom = el.normals[:, 2] < -0.5
    for i in range(0, len(tr), 7):
        d = -(tr.position[i, 2] + el.centroids[:, 2])
        v = tr.velocity[i]
        if np.linalg.norm(v) == 0:
            continue
        f = rft_forces(el.normals, d, el.areas, v, per_element=True)
        assert np.all(f[bottom, 2] >= 0.0)
        if v[2] > 0:  # pulling out: the bottom is trailing and carries nothing
            assert np.all(f[bottom] == 0.0)


def test_fast_integration_matches_element_sum(box):
    tr = mudrft.gait(0.2)
    rft = GranularRFT()
    h = run_terrain(rft, box, tr)
    el = box.elements()
    for i in range(1, len(tr), 37):
        d = -(tr.position[i, 2] + el.centroids[:, 2])
        ref = rft_forces(el.normals, d, el.areas, tr.velocity[i], zeta=rft.zeta)
        # prefix-sum integration vs direct sum: rounding on forces of O(10) N
        np.testing.assert_allclose(h.force[i], ref, atol=1e-9)


def test_batch_equals_single_steps(box):
    rft = GranularRFT()
    pos = np.array([[0.0, 0.0, -0.01], [0.01, 0.0, -0.02], [0.0, 0.0, 0.01]])
    vel = np.array([[0.1, 0.05, -0.1], [0.0, 0.0, 0.1], [0.0, 0.0, -0.1]])
    s = rft.initial_state(box, pos)
    _, out = rft.step(box, s, pos, vel, 1e-3)
    for k in range(3):
        _, o = rft.step(box, rft.initial_state(box, pos[k]), pos[k], vel[k], 1e-3)
        np.testing.assert_allclose(out.force[k], o.force, atol=1e-12)


def test_named_media_and_errors(box):
    assert GranularRFT.medium("poppy-cp").zeta == GRANULAR_MEDIA["poppy-cp"]
    with pytest.raises(MudrftError, match="zeta"):
        GranularRFT(zeta=-1.0)
    with pytest.raises(MudrftError, match="extension"):
        GranularRFT(extension="4d")
    with pytest.raises(MudrftError, match="normals"):
        rft_forces([[0, 0, -1]], [0.01, 0.02], [1e-3], [0, 0, -1])
    with pytest.raises(MudrftError, match="velocity"):
        GranularRFT().step(
            box, GranularRFT().initial_state(box, np.zeros(3)), np.zeros(3), np.zeros(2), 1e-3
        )


def test_on_the_library_flat_foot():
    feet = pytest.importorskip("mudrft.feet")
    foot = feet.Flat()
    tr = mudrft.plate_intrusion(depth=0.02, dt=2e-3)  # shallower than the foot's 26 mm height
    h = run_terrain(GranularRFT(), foot, tr)
    area = foot.projected_areas(0.01)[2]
    expected = plate_force_by_hand(tr, GranularRFT().zeta, area)
    # the mesh's bottom facets sum to the footprint; rounding only
    np.testing.assert_allclose(h.force[:, 2], expected, rtol=1e-9, atol=1e-9)


def test_a_facet_tangent_to_the_motion_moves_the_force_continuously():
    """A wall tilted by 1e-9 rad so that it leads changes the force by a tiny amount (D53);
    the sharp rule (leading_width=0) keeps the old all-or-nothing switch for reference."""
    n_flat = np.array([[0.0, 0.0, -1.0]])
    n_tilt = np.array([[math.sin(1e-9), 0.0, -math.cos(1e-9)]])
    v = np.array([1.0, 0.0, 0.0])
    f0 = rft_forces(n_flat, [0.02], [5e-3], v)
    f1 = rft_forces(n_tilt, [0.02], [5e-3], v)
    full = np.abs(rft_forces(np.array([[1.0, 0.0, 0.0]]), [0.02], [5e-3], v)).max()
    # n.v = 1e-9 -> weight 1e-6 of a fully leading facet's force (the ramp is 1e-3 wide)
    assert np.all(np.abs(f1 - f0) <= 2e-6 * full)
    sharp0 = rft_forces(n_flat, [0.02], [5e-3], v, leading_width=0.0)
    sharp1 = rft_forces(n_tilt, [0.02], [5e-3], v, leading_width=0.0)
    assert np.abs(sharp1 - sharp0).max() > 0.1 * full  # the switch the ramp removes


@settings(max_examples=40, deadline=None)
@given(tilt=st.floats(-0.01, 0.01), eps=st.floats(-1e-9, 1e-9))
def test_rft_force_is_lipschitz_in_the_facet_tilt(tilt, eps):
    """|dF| <= |f| * |d(n.v)| / width: the ramp bounds how fast a facet switches on."""

    def force(a):
        n = np.array([[math.sin(a), 0.0, -math.cos(a)]])
        return rft_forces(n, [0.02], [5e-3], [1.0, 0.0, 0.0])

    full = np.abs(rft_forces(np.array([[1.0, 0.0, 0.0]]), [0.02], [5e-3], [1.0, 0.0, 0.0])).max()
    bound = 10 * full * abs(eps) / 1e-3 + 1e-9 * full
    assert np.abs(force(tilt + eps) - force(tilt)).max() <= bound


# --- a terramechanics researcher's walkthrough: units as RFT papers print them ---

#: Li et al.'s (2013) fit for loosely packed poppy seeds as tabulated [N/cm^3] (D50).
POPPY_LP_N_PER_CM3 = dict(
    A00=0.051,
    A10=0.047,
    B01=0.083,
    B11=0.053,
    Bm11=0.020,
    C01=0.057,
    C11=-0.026,
    Cm11=0.0,
    D10=0.025,
)


def test_zeta_given_in_n_per_cm3_warns_and_si_does_not():
    # 0.254 "N/m^3" is 1e6 times too small a medium: the plate test read 4e-5 N, silently
    with pytest.warns(PlausibilityWarning, match=r"zeta is 0.254 N/m\^3.*N/cm\^3"):
        GranularRFT(zeta=0.254)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        GranularRFT(zeta=0.254e6)
        GranularRFT.medium("poppy-cp")


def test_a_mediums_own_fit_in_n_per_cm3_is_kept_exactly(box):
    from mudrft.baselines import FourierCoefficients

    lp = FourierCoefficients(**POPPY_LP_N_PER_CM3)
    rft = GranularRFT.from_coefficients(lp, unit="N/cm^3")
    assert rft.zeta == pytest.approx(0.254e6, rel=1e-12)  # A00 + A10 + B01 + B11 + Bm11
    beta, gamma = np.meshgrid(np.linspace(-1.5, 1.5, 7), np.linspace(-1.5, 1.5, 7))
    ax, az = rft.alpha(beta, gamma)  # [N/m^3]
    ax_ref, az_ref = lp.alpha(beta, gamma)  # [N/cm^3], the published series
    np.testing.assert_allclose(ax, 1e6 * ax_ref, rtol=1e-12, atol=1e-6)
    np.testing.assert_allclose(az, 1e6 * az_ref, rtol=1e-12, atol=1e-6)
    # the plate test: F_z = 0.254 N/cm^3 * depth * area, in SI
    tr = mudrft.plate_intrusion(depth=0.02, dt=2e-3)
    h = run_terrain(rft, box, tr)
    assert h.force[:, 2].max() == pytest.approx(0.254e6 * 0.02 * box.length * box.width, rel=1e-9)
    # the same table given as the dimensionless fit was multiplied by zeta once more: warns
    with pytest.warns(PlausibilityWarning, match=r"not normalised.*from_coefficients"):
        GranularRFT(coefficients=lp)


def test_from_coefficients_rejects_what_it_cannot_scale():
    from mudrft.baselines import FourierCoefficients

    flat = dict(POPPY_LP_N_PER_CM3, A00=-0.254)  # alpha_z(0, pi/2) = -0.051
    with pytest.raises(MudrftError, match=r"alpha_z\(0, pi/2\).*> 0, got -0.051 N/cm\^3"):
        GranularRFT.from_coefficients(FourierCoefficients(**flat))
    with pytest.raises(
        MudrftError, match=r"unit for stress per depth must be one of .*got .psi/in."
    ):
        GranularRFT.from_coefficients(FourierCoefficients(**POPPY_LP_N_PER_CM3), unit="psi/in")
    with pytest.raises(MudrftError, match="takes its scale from the coefficients, got zeta="):
        GranularRFT.from_coefficients(FourierCoefficients(**POPPY_LP_N_PER_CM3), zeta=1e5)


def _tilted_mesh_foot() -> mudrft.feet.MeshFoot:
    """A semi-sphere mesh tilted off every axis: each facet has its own normal."""
    mesh = mudrft.feet.MeshFoot(*semisphere_mesh(0.045, 0.045, resolution=6))
    return mesh.posed(Rotation.from_rotvec([0.1, 0.2, 0.3]))


@pytest.mark.parametrize("terrain", [GranularRFT(), GranularRFT3D()], ids=lambda t: t.name)
@pytest.mark.parametrize("which", ["tilted mesh", "flat"])
def test_the_step_equals_every_groups_response_weighted_by_depth(terrain, which):
    """A step evaluates the submerged groups of facets only and reuses their responses while
    the direction repeats; its force is the depth-weighted sum over all of the foot's groups,
    each evaluated afresh (the step before that saving), to 1e-12 of the largest force. The
    path: a gait (a new direction each step), then straight down and a hold (one direction:
    groups join the cached ones as they sink), three feet at once at staggered depths."""
    foot = _tilted_mesh_foot() if which == "tilted mesh" else mudrft.feet.Flat()
    gait = mudrft.gait(0.2, dt=5e-3)
    plate = mudrft.plate_intrusion(depth=0.03, speed=0.05, hold=0.05, dt=5e-3)
    one = np.concatenate([gait.position, plate.position])
    vel = np.concatenate([gait.velocity, plate.velocity])
    pos = one[:, None, :] + np.array([[0.0, 0.0, 0.0], [0.0, 0.0, -0.004], [0.0, 0.0, 0.03]])
    vel = np.repeat(vel[:, None, :], 3, axis=1)
    pr = _prepare(foot.elements())
    state = terrain.initial_state(foot, pos[0])
    direction = np.array([0.0, 0.0, -1.0])
    forces, every = [], []
    for k in range(1, len(pos)):
        state, out = terrain.step(foot, state, pos[k], vel[k], 5e-3)
        speed = np.linalg.norm(vel[k, 0])
        direction = vel[k, 0] / speed if speed > terrain.rest_speed else direction
        unit = terrain._unit_forces(pr.normals, direction)  # every group, (k, 3)
        w = _group_weights(pr, -pos[k, :, 2])  # (3, k) [m^3]
        forces.append(out.force)
        every.append(terrain.scale * np.einsum("bk,kc->bc", w, unit))
    every_a = np.array(every)
    assert np.abs(every_a[:, 0, 2]).max() > 1.0  # the foot sank and was held [N]
    np.testing.assert_allclose(forces, every_a, rtol=0, atol=1e-12 * np.abs(every_a).max())
