"""3D-RFT of Agarwal, Goldman & Kamrin (PNAS 2023): hand computations, cap, symmetry, errors."""

from __future__ import annotations

import math
import warnings
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import mudrft
from mudrft import MudrftError
from mudrft._validation import PlausibilityWarning
from mudrft.baselines import run_terrain
from mudrft.feet.base import Foot, SurfaceElements
from mudrft.terrains import GranularRFT, GranularRFT3D
from mudrft.terrains.granular_rft import rft_forces
from mudrft.terrains.granular_rft3d import (
    PolynomialCoefficients,
    agarwal_generic_alpha,
    agarwal_xi,
    rft3d_alpha,
    rft3d_forces,
)

# The paper's coefficients c_i^k (k = 1..20), typed here again (not imported) so the hand
# computation is independent of the implementation; read from public implementations (D91).
C1 = [0.00212, -0.02320, -0.20890, -0.43083, -0.00259, 0.48872, -0.00415, 0.07204, -0.02750,
      -0.08772, 0.01992, -0.45961, 0.40799, -0.10107, -0.06576, 0.05664, -0.09269, 0.01892,
      0.01033, 0.15120]  # fmt: skip
C2 = [-0.06796, -0.10941, 0.04725, -0.06914, -0.05835, -0.65880, -0.11985, -0.25739, -0.26834,
      0.02692, -0.00736, 0.63758, 0.08997, 0.21069, 0.04748, 0.20406, 0.18519, 0.04934, 0.13527,
      -0.33207]  # fmt: skip
C3 = [-0.02634, -0.03436, 0.45256, 0.00835, 0.02553, -1.31290, -0.05532, 0.06790, -0.16404,
      0.02287, 0.02927, 0.95406, -0.00131, -0.11028, 0.01487, -0.02730, 0.10911, -0.04097,
      0.07881, -0.27519]  # fmt: skip


def terms_by_hand(x1: float, x2: float, x3: float) -> list[float]:
    """The paper's 20 monomials T_k, written out in the paper's order."""
    return [1, x1, x2, x3, x1**2, x2**2, x3**2, x1 * x2, x2 * x3, x3 * x1, x1**3, x2**3, x3**3,
            x1 * x2**2, x2 * x1**2, x2 * x3**2, x3 * x2**2, x3 * x1**2, x1 * x3**2,
            x1 * x2 * x3]  # fmt: skip


def xi_by_hand(rho_c: float, mu: float, g: float = 9.81) -> float:
    return rho_c * g * (894 * mu**3 - 386 * mu**2 + 89 * mu)


def alpha_local_by_hand(beta: float, gamma: float, psi: float) -> tuple[float, float, float]:
    """(alpha_r, alpha_theta, alpha_z) of the paper's generic response, term by term."""
    x1 = math.sin(gamma)
    x2 = math.cos(beta)
    x3 = math.cos(psi) * math.cos(gamma) * math.sin(beta) + math.sin(gamma) * math.cos(beta)
    t = terms_by_hand(x1, x2, x3)
    f1, f2, f3 = (sum(c * tk for c, tk in zip(cs, t, strict=True)) for cs in (C1, C2, C3))
    return (
        f1 * math.sin(beta) * math.cos(psi) + f2 * math.cos(gamma),
        f1 * math.sin(beta) * math.sin(psi),
        -f1 * math.cos(beta) - f2 * math.sin(gamma) - f3,
    )


def facet_force_by_hand(n, v, depth, area, rho_c, mu_int, mu_surf):
    """The paper's recipe for one facet, in its local frame (r, theta, z), step by step."""
    n = np.asarray(n, float) / np.linalg.norm(n)
    v = np.asarray(v, float) / np.linalg.norm(v)
    if n @ v <= 0 or depth <= 0:
        return np.zeros(3)  # only submerged leading facets carry force
    z = np.array([0.0, 0.0, 1.0])
    vh = v - (v @ z) * z
    nh = n - (n @ z) * z
    if np.linalg.norm(vh) > 0:
        r = vh / np.linalg.norm(vh)
    elif np.linalg.norm(nh) > 0:
        r = nh / np.linalg.norm(nh)
    else:
        r = np.array([1.0, 0.0, 0.0])
    th = np.cross(z, r)
    nr, nz = n @ r, n @ z
    # beta: tilt of the facet, signed as in the paper's frame
    if nr >= 0 and nz >= 0:
        beta = -math.acos(nz)
    elif nr >= 0:
        beta = math.pi - math.acos(nz)
    elif nz >= 0:
        beta = math.acos(nz)
    else:
        beta = -math.pi + math.acos(nz)
    gamma = math.acos(np.clip(v @ r, -1, 1)) * (1 if v @ z <= 0 else -1)
    nr0 = nh / np.linalg.norm(nh) if np.linalg.norm(nh) > 0 else np.zeros(3)
    psi = math.atan((nr0 @ th) / (nr0 @ r)) if nr0 @ r != 0 else 0.0
    a_r, a_th, a_z = alpha_local_by_hand(beta, gamma, psi)
    a = a_r * r + a_th * th + a_z * z
    a_n = (a @ n) * n
    a_t = a - a_n
    cap = min(mu_surf * np.linalg.norm(a_n) / np.linalg.norm(a_t), 1.0)
    alpha = xi_by_hand(rho_c, mu_int) * (a_n + cap * a_t)
    return alpha * depth * area


def _u(*c: float) -> list[float]:
    return list(np.array(c) / np.linalg.norm(c))


S45 = math.sqrt(0.5)
# (outward normal, direction of motion): plate pushed down; 45-degree facet pushed down (cap
# active) and dragged forward; a facet facing up-forward dragged forward (beta < 0); a facet
# leading while moving up (gamma < 0); a twisted facet (psi != 0); a general 3D case
FACETS = [
    ([0, 0, -1], [0, 0, -1]),
    ([S45, 0, -S45], [0, 0, -1]),
    ([S45, 0, -S45], [1, 0, 0]),
    (_u(math.sin(1.0), 0, math.cos(1.0)), [1, 0, 0]),
    (_u(math.sin(1.2), 0, -math.cos(1.2)), _u(math.cos(0.5), 0, math.sin(0.5))),
    (_u(0.5 * math.cos(0.7), 0.5 * math.sin(0.7), -math.sqrt(0.75)), _u(math.cos(0.3), 0, -0.3)),
    (_u(0.2, -0.6, -0.77), _u(0.3, 0.5, -0.8)),
    (_u(-0.4, 0.3, -0.5), _u(-0.2, 0.1, -0.9)),
]


class OneFacet(Foot):
    """A foot made of one facet at the tip (for the terrain on single facets)."""

    name = "one-facet"

    def __init__(self, normal: Any, area: float) -> None:
        self.normal, self.area = np.asarray(normal, float), area

    @property
    def characteristic_length(self) -> float:
        return 0.05

    @property
    def height(self) -> float:
        return 0.0

    def elements(self) -> SurfaceElements:
        return SurfaceElements(np.zeros((1, 3)), self.normal[None, :], np.array([self.area]))

    def projected_areas(self, depth: Any) -> np.ndarray:
        d = np.asarray(depth, float)
        return np.stack([np.zeros_like(d), np.zeros_like(d), np.where(d > 0, self.area, 0.0)], -1)

    def resultant(self, depth: Any, stress: Any, heading: Any) -> np.ndarray:
        return self.projected_areas(depth) * np.asarray(stress, float)


@pytest.mark.parametrize(("n", "v"), FACETS)
def test_single_facets_equal_the_papers_formulas_by_hand(n, v):
    depth, area = 0.02, 1e-3
    t = GranularRFT3D()
    expected = facet_force_by_hand(n, v, depth, area, t.rho_c, t.mu_int, t.mu_surf)
    assert np.abs(expected).max() > 1e-2  # every case leads and carries force
    f = rft3d_forces([n], [depth], [area], v, xi_n=t.xi_n, mu_surf=t.mu_surf)
    # the same formulas in the frame-free form (D90): agreement to rounding
    np.testing.assert_allclose(f, expected, rtol=1e-9, atol=1e-12)
    foot = OneFacet(n, area)
    _, out = t.step(foot, t.initial_state(foot, [0, 0, -depth]), [0, 0, -depth], v, 1e-3)
    # the terrain groups facets by normals rounded to 1e-9 (prefix-sum integration)
    np.testing.assert_allclose(out.force, expected, rtol=1e-7, atol=1e-12)


def test_local_frame_response_is_the_printed_polynomial():
    for beta, gamma, psi in [(0.3, 0.9, 0.2), (-1.1, -0.4, -0.8), (1.5, 0.0, 1.2)]:
        got = [float(a) for a in agarwal_generic_alpha(beta, gamma, psi)]
        np.testing.assert_allclose(got, alpha_local_by_hand(beta, gamma, psi), atol=1e-14)


def test_material_constant_from_density_and_internal_friction():
    assert float(agarwal_xi(1310.0, 0.21)) == pytest.approx(xi_by_hand(1310.0, 0.21), rel=1e-14)
    assert GranularRFT3D(rho_c=1600.0, mu_int=0.6).xi_n == pytest.approx(
        1600 * 9.81 * (894 * 0.216 - 386 * 0.36 + 89 * 0.6), rel=1e-14
    )


def test_flat_plate_pushed_down_is_the_plate_constant_times_area_times_depth(box):
    t = GranularRFT3D()
    # by hand: x1 = x2 = x3 = 1, so alpha_z = -(sum c1 + sum c2 + sum c3) = 0.87574 (D92)
    az = -(sum(C1) + sum(C2) + sum(C3))
    assert az == pytest.approx(0.87574, abs=1e-12)
    assert t.plate_constant == pytest.approx(az * xi_by_hand(t.rho_c, t.mu_int), rel=1e-13)
    tr = mudrft.plate_intrusion(depth=0.02, hold=0.2, dt=2e-3)  # the box is 50 mm high
    h = run_terrain(t, box, tr)
    area = box.length * box.width
    loaded = tr.velocity[:, 2] <= 0  # down, and the hold keeps the last direction (D52)
    expected = np.where(loaded, t.plate_constant * area * tr.depth, 0.0)
    np.testing.assert_allclose(h.force[:, 2], expected, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(h.force[:, :2], 0.0, atol=1e-12)
    # the material constant alone is 1 / 0.87574 = 1.142 times too stiff for a plate
    deepest = int(np.argmax(tr.depth))
    assert h.force[deepest, 2] / (t.xi_n * area * tr.depth[deepest]) == pytest.approx(0.87574)


@pytest.mark.parametrize(
    ("n", "v", "mu", "active"),
    [
        ([0, 0, -1], [0, 0, -1], 0.0, False),  # no tangential part on a plate pushed down
        ([S45, 0, -S45], [0, 0, -1], 0.4, True),  # |a_t| / |a_n| = 0.632
        ([S45, 0, -S45], [0, 0, -1], 0.7, False),
        ([1, 0, 0], [1, 0, 0], 0.3, True),  # face-on wall: |a_t| / |a_n| = 0.388
        ([1, 0, 0], [1, 0, 0], 0.4, False),
    ],
)
def test_friction_cap_acts_only_where_shear_exceeds_mu_surf_times_normal(n, v, mu, active):
    free = rft3d_alpha([n], v)[0]
    capped = rft3d_alpha([n], v, mu_surf=mu)[0]
    nn = np.asarray(n, float)
    a_n, c_n = (free @ nn) * nn, (capped @ nn) * nn
    a_t, c_t = free - a_n, capped - c_n
    np.testing.assert_allclose(c_n, a_n, atol=1e-15)  # the normal part is never changed
    assert (np.linalg.norm(a_t) > mu * np.linalg.norm(a_n)) == active
    if active:
        assert np.linalg.norm(c_t) == pytest.approx(mu * np.linalg.norm(a_n), rel=1e-12)
        np.testing.assert_allclose(np.cross(c_t, a_t), 0.0, atol=1e-15)  # same direction
    else:
        np.testing.assert_allclose(capped, free, atol=1e-15)


unit3 = st.tuples(*[st.floats(-1, 1, allow_nan=False)] * 3).filter(
    lambda v: 0.2 < np.linalg.norm(v)
)


@settings(max_examples=60, deadline=None, derandomize=True)
@given(n=unit3, v=unit3, mu=st.floats(0.0, 1.0))
def test_capped_shear_never_exceeds_mu_surf_times_normal(n, v, mu):
    a = rft3d_alpha([n], v, mu_surf=mu)[0]
    nn = np.array(n) / np.linalg.norm(n)
    a_n = (a @ nn) * nn
    assert np.linalg.norm(a - a_n) <= mu * np.linalg.norm(a_n) * (1 + 1e-12) + 1e-15


@settings(max_examples=60, deadline=None, derandomize=True)
@given(n=unit3, v=unit3, yaw=st.floats(-math.pi, math.pi))
def test_rft3d_is_invariant_under_rotation_about_the_vertical(n, v, yaw):
    c, s = math.cos(yaw), math.sin(yaw)
    R = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    n, v = np.array(n), np.array(v)
    kw = {"xi_n": 1e5, "mu_surf": 0.4}
    f = rft3d_forces([n], [0.01], [1e-3], v, **kw)
    fr = rft3d_forces([R @ n], [0.01], [1e-3], R @ v, **kw)
    # rotating facet and motion about z rotates the force; rounding only (forces of O(1) N)
    np.testing.assert_allclose(fr, R @ f, atol=1e-11)


def test_face_on_wall_is_the_mean_of_the_fits_two_ends_and_continuous_in_tilt():
    """D93: beta = +pi/2 and -pi/2 are the same vertical wall, but the fit gives two values."""
    up = np.array(alpha_local_by_hand(-math.pi / 2, 0.0, 0.0))  # n_z >= 0 reading
    down = np.array(alpha_local_by_hand(math.pi / 2, 0.0, 0.0))  # n_z < 0 reading
    assert abs(up[0] - down[0]) > 0.03  # -0.2294 against -0.1919: the fit's seam
    v = [1.0, 0.0, 0.0]
    wall = rft3d_alpha([[1, 0, 0]], v)[0]
    np.testing.assert_allclose(wall, 0.5 * (up + down), atol=1e-14)  # r = x, z = z here
    for eps in (1e-9, -1e-9):
        tilted = rft3d_alpha([[math.cos(eps), 0, math.sin(eps)]], v)[0]
        assert np.abs(tilted - wall).max() < 1e-6  # n_z = 1e-9: weight moves by 5e-7
    sharp = [rft3d_alpha([[1, 0, eps]], v, wall_width=0.0)[0] for eps in (1e-9, -1e-9)]
    assert np.abs(sharp[0] - sharp[1]).max() > 0.03  # the seam the blend removes


def test_a_facet_tangent_to_the_motion_switches_on_continuously():
    """The leading ramp of granular RFT (D53): a flat foot dragged along x, tilted by 1e-9."""
    kw = {"xi_n": 1e5, "mu_surf": 0.4}
    v = [1.0, 0.0, 0.0]
    f0 = rft3d_forces([[0, 0, -1]], [0.02], [5e-3], v, **kw)
    f1 = rft3d_forces([[math.sin(1e-9), 0, -math.cos(1e-9)]], [0.02], [5e-3], v, **kw)
    full = np.abs(rft3d_forces([[1, 0, 0]], [0.02], [5e-3], v, **kw)).max()
    assert np.all(f0 == 0.0) and np.abs(f1 - f0).max() <= 2e-6 * full


def test_trailing_and_emerged_facets_carry_nothing_so_no_suction(box):
    f = rft3d_forces([[0, 0, -1]] * 2, [0.02, -0.01], [1e-3] * 2, [0.3, 0, 1], xi_n=1e5, mu_surf=1)
    assert np.all(f == 0.0)
    tr = mudrft.plate_intrusion(depth=0.02, dt=2e-3)
    h = run_terrain(GranularRFT3D(), box, tr)
    assert np.all(h.force[tr.velocity[:, 2] > 0, 2] == 0.0)


def test_fast_integration_matches_element_sum_and_batch_matches_single(box):
    t = GranularRFT3D()
    tr = mudrft.gait(0.2)
    h = run_terrain(t, box, tr)
    el = box.elements()
    for i in range(1, len(tr), 37):
        d = -(tr.position[i, 2] + el.centroids[:, 2])
        ref = rft3d_forces(el.normals, d, el.areas, tr.velocity[i], xi_n=t.xi_n, mu_surf=0.4)
        np.testing.assert_allclose(h.force[i], ref, atol=1e-9)  # rounding on O(10) N
    pos = np.array([[0.0, 0.0, -0.01], [0.01, 0.0, -0.02], [0.0, 0.0, 0.01]])
    vel = np.array([[0.1, 0.05, -0.1], [0.0, 0.0, 0.1], [0.0, 0.0, -0.1]])
    _, out = t.step(box, t.initial_state(box, pos), pos, vel, 1e-3)
    for k in range(3):
        _, o = t.step(box, t.initial_state(box, pos[k]), pos[k], vel[k], 1e-3)
        np.testing.assert_allclose(out.force[k], o.force, atol=1e-12)


# Numbers quoted in docs/model.md (section 8, "Where the two granular models differ"):
# force per unit depth and area on one facet, in units of each model's own plate constant
# (zeta for GranularRFT, 0.87574 xi_n for GranularRFT3D with mu_surf = 0.4).
DOC_NUMBERS = {
    "face-on wall dragged along its normal": ([1, 0, 0], [1, 0, 0], (-0.370, 0.037), (-0.241, 0.093)),
    "45-degree facet pushed straight down": ([S45, 0, -S45], [0, 0, -1], (-0.219, 0.564), (-0.359, 0.838)),
    "45-degree facet dragged forward": ([S45, 0, -S45], [1, 0, 0], (-0.341, 0.363), (-0.446, 0.319)),
    "45-degree facet facing up dragged forward": ([S45, 0, S45], [1, 0, 0], (-0.165, 0.049), (-0.176, -0.102)),
}  # fmt: skip


@pytest.mark.parametrize("case", list(DOC_NUMBERS))
def test_the_comparison_numbers_in_the_docs(case):
    n, v, li, agarwal = DOC_NUMBERS[case]
    rft = rft_forces([n], [1.0], [1.0], v, zeta=1.0)
    t = GranularRFT3D()
    a = rft3d_forces([n], [1.0], [1.0], v, xi_n=1.0, mu_surf=t.mu_surf) * t.xi_n / t.plate_constant
    np.testing.assert_allclose(rft[[0, 2]], li, atol=5e-4)
    np.testing.assert_allclose(a[[0, 2]], agarwal, atol=5e-4)
    assert rft[1] == pytest.approx(0.0, abs=1e-12) and a[1] == pytest.approx(0.0, abs=1e-12)


def test_default_media_of_the_two_models_and_their_plate_constants():
    assert GranularRFT().zeta == pytest.approx(2.54e5)
    assert GranularRFT3D().plate_constant == pytest.approx(1.1194e5, rel=1e-4)


def test_bad_options_are_rejected_with_clear_messages(box):
    for kw, match in [
        ({"rho_c": -1.0}, r"rho_c must be > 0 kg/m\^3, got -1.0"),
        ({"rho_c": float("nan")}, "rho_c must be finite"),
        ({"mu_int": 0.0}, r"mu_int must lie in \[1e-06, 2.0\], got 0.0"),
        ({"mu_surf": -0.1}, r"mu_surf must lie in \[0.0, 1000.0\], got -0.1"),
        ({"gravity": 0.0}, "gravity must be > 0"),
        ({"rest_speed": -1.0}, "rest_speed must be > 0"),
        ({"leading_width": 2.0}, "leading_width must lie in"),
        ({"wall_width": -1e-3}, "wall_width must lie in"),
        ({"coefficients": "li2013"}, "coefficients must be a PolynomialCoefficients, got str"),
        ({"name": ""}, "name must be a non-empty string"),
    ]:
        with pytest.raises(MudrftError, match=match):
            GranularRFT3D(**kw)
    with pytest.raises(MudrftError, match=r"c2 must hold 20 coefficients, got shape \(19,\)"):
        PolynomialCoefficients(c1=tuple(C1), c2=tuple(C2[:-1]), c3=tuple(C3))
    t = GranularRFT3D()
    s = t.initial_state(box, np.zeros(3))
    with pytest.raises(MudrftError, match="velocity must have the shape of position"):
        t.step(box, s, np.zeros(3), np.zeros(2), 1e-3)
    with pytest.raises(MudrftError, match="dt must be finite and > 0"):
        t.step(box, s, np.zeros(3), np.zeros(3), 0.0)
    with pytest.raises(MudrftError, match="position must be finite"):
        t.step(box, s, [0, 0, np.nan], np.zeros(3), 1e-3)
    with pytest.raises(
        MudrftError, match=r"normals \(m, 3\), areas \(m,\) and depths \(\.\.\., m\) must agree"
    ):
        rft3d_forces([[0, 0, -1]], [0.01, 0.02], [1e-3], [0, 0, -1], xi_n=1e5, mu_surf=0.4)
    with pytest.raises(MudrftError, match="direction must be nonzero"):
        rft3d_forces([[0, 0, -1]], [0.01], [1e-3], [0, 0, 0], xi_n=1e5, mu_surf=0.4)
    with pytest.raises(MudrftError, match="xi_n must be > 0"):
        rft3d_forces([[0, 0, -1]], [0.01], [1e-3], [0, 0, -1], xi_n=0.0, mu_surf=0.4)
    # a negative area is refused as by rft_forces (it would turn the element's force round)
    with pytest.raises(MudrftError, match=r"areas must be >= 0 m\^2"):
        rft3d_forces([[0, 0, -1]], [0.01], [-1e-3], [0, 0, -1], xi_n=1e5, mu_surf=0.4)


def test_use_registers_the_citation():
    GranularRFT3D()
    assert "agarwal2023rft3d" in mudrft.citations(bibtex=False)


def test_density_in_g_per_cm3_and_friction_in_degrees_warn():
    # a terramechanics researcher's walkthrough: 1.31 (g/cm^3) gave a medium 1000x
    # too soft and 22 (degrees) a cap that never acts, both silently
    with pytest.warns(PlausibilityWarning, match=r"rho_c is 1.31 kg/m\^3.*g/cm\^3"):
        GranularRFT3D(rho_c=1.31)
    with pytest.warns(PlausibilityWarning, match=r"mu_surf = 22 looks like a friction angle"):
        GranularRFT3D(mu_surf=22.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        GranularRFT3D(rho_c=1600.0, mu_int=0.6, mu_surf=0.5)
        GranularRFT3D(mu_surf=1e3)  # the cap turned off


def test_an_internal_friction_angle_in_degrees_is_told_it_is_a_coefficient():
    with pytest.raises(MudrftError, match=r"mu_int must lie in .*got 30.0: mu_int is the internal"):
        GranularRFT3D(mu_int=30)


def test_both_rfts_weight_each_element_by_depth_and_area_in_one_place(monkeypatch):
    """dF = k max(z, 0) A alpha is written once (granular_rft._element_forces): 2D RFT and
    3D-RFT both scale their unit responses by it; replacing it changes both."""
    from mudrft.terrains import granular_rft, granular_rft3d
    from mudrft.terrains.granular_rft import _element_forces

    n = np.array([[0.0, 0.0, -1.0], [0.6, 0.0, -0.8], [0.0, 1.0, 0.0]])
    a = np.array([1e-4, 2e-4, 3e-4])
    d = np.array([0.02, -0.01, 0.03])
    v = np.array([0.3, 0.0, -1.0])
    kw3 = dict(xi_n=1e5, mu_surf=0.4)
    each = rft3d_forces(n, d, a, v, per_element=True, **kw3)
    assert np.all(each[1] == 0.0)  # above the surface: no force
    np.testing.assert_allclose(rft3d_forces(n, 2 * d, a, v, **kw3), 2 * each.sum(0))
    np.testing.assert_allclose(
        rft_forces(n, d, a, v, zeta=1e5, per_element=True).sum(0), rft_forces(n, d, a, v, zeta=1e5)
    )
    calls = []

    def spy(*args, **kwargs):
        calls.append(args[0])
        return _element_forces(*args, **kwargs)

    monkeypatch.setattr(granular_rft, "_element_forces", spy)
    monkeypatch.setattr(granular_rft3d, "_element_forces", spy)
    rft_forces(n, d, a, v, zeta=2.5e5)
    rft3d_forces(n, d, a, v, **kw3)
    assert calls == [2.5e5, 1e5]
