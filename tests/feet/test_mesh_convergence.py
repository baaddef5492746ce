"""Mesh integration against the closed forms; invariance and symmetry of the element rule."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from mudrft.feet import Flat, Foot, MeshFoot, SemiCylinder, SemiSphere
from mudrft.feet.closed_form import semisphere_forces

S = np.array([1.3e3, 0.7e3, 2.1e3])
S_ISO = np.array([1.3e3, 1.3e3, 2.1e3])  # sx = sy: the sphere's mesh and closed form agree (D23)


def _stress(foot) -> np.ndarray:
    return S_ISO if foot.trailing else S


@pytest.mark.parametrize("resolution", [1, 3])
@pytest.mark.parametrize("depth", [0.0, 0.004, 0.0173, 0.026, 0.05])
def test_flat_mesh_is_exact(resolution: int, depth: float) -> None:
    foot = Flat()
    mesh = foot.to_mesh(resolution=resolution)
    for h in (0.0, 0.4, 1.2, math.pi / 2):
        # planar faces: the clipped integral is exact up to round-off
        np.testing.assert_allclose(
            mesh.resultant(depth, S, h), foot.resultant(depth, S, h), rtol=1e-12, atol=1e-12
        )


def _errors(foot, depth: float, stress: np.ndarray, heading: float, levels) -> np.ndarray:
    ref = foot.resultant(depth, stress, heading)
    return np.array(
        [
            np.abs(foot.to_mesh(resolution=n).resultant(depth, stress, heading) - ref) / np.abs(ref)
            for n in levels
        ]
    )


@pytest.mark.parametrize("foot", [SemiCylinder(), SemiSphere()], ids=lambda f: f.name)
def test_mesh_converges_to_closed_form_at_second_order(foot) -> None:
    """Inscribed polyhedra: error ~ h^2. At depth = height every ring is whole, so the
    observed order log2(e_n / e_2n) is clean: 2 within 0.1 (measured 1.99-2.00)."""
    levels = (8, 16, 32)
    e = _errors(foot, foot.height, _stress(foot), 0.4, levels)
    rate = np.log2(e[:-1] / e[1:])
    assert np.all(np.abs(rate - 2.0) < 0.1), rate
    assert np.all(e[-1] < 2e-3)


@pytest.mark.parametrize("foot", [SemiCylinder(), SemiSphere()], ids=lambda f: f.name)
@pytest.mark.parametrize("depth", [0.0031, 0.0113, 0.0197])
def test_mesh_converges_at_depths_cutting_facets(foot, depth: float) -> None:
    """Where the surface cuts facets the error oscillates with the mesh (measured factors of
    up to 4 around C/n^2), so the check is a second-order envelope: with K the largest
    e_n n^2 of the two coarsest levels, e_n n^2 <= 1.5 K on the finer ones (a first-order
    error would exceed it by a factor 8/1.5 at n = 64)."""
    levels = np.array([8, 16, 32, 64])
    e = _errors(foot, depth, _stress(foot), 0.9, levels)
    scaled = e * levels[:, None] ** 2
    assert np.all(scaled[2:] <= 1.5 * scaled[:2].max(axis=0)), scaled
    assert np.all(e[-1] < 3e-3)


def test_sphere_mesh_with_unequal_stresses_uses_their_mean() -> None:
    """D23: per-face stress on the sphere gives (sx + sy)/2 in both components, where the
    printed derivation uses sx in F_x and sy in F_y; F_z is unaffected."""
    mesh = SemiSphere().to_mesh(resolution=64)
    s = np.array([2e3, 0.5e3, 1e3])
    mean = semisphere_forces(0.02, [1.25e3, 1.25e3, 1e3], 0.7, radius=0.045, height=0.026)
    # resolution 64: second-order mesh error ~ 1e-4 (test above), so 5e-4 relative
    np.testing.assert_allclose(mesh.resultant(0.02, s, 0.7), mean, rtol=5e-4)
    printed_rule = SemiSphere().resultant(0.02, s, 0.7)
    assert abs(printed_rule[0] - mean[0]) > 0.1 * mean[0]  # a real difference: 20 % here


@pytest.mark.parametrize("foot", [Flat(), SemiCylinder(), SemiSphere()], ids=lambda f: f.name)
def test_mesh_projected_areas_and_lc_match_closed_form(foot) -> None:
    mesh = foot.to_mesh(resolution=48)
    d = np.array([0.006, 0.019, 0.03])
    # second-order geometry at resolution 48: ~1e-3 of the curved areas (1e-12 flat)
    np.testing.assert_allclose(mesh.projected_areas(d), foot.projected_areas(d), rtol=2e-3)
    assert mesh.characteristic_length == pytest.approx(foot.characteristic_length, rel=2e-3)
    assert mesh.height == pytest.approx(foot.height, rel=1e-12)


def test_flat_mesh_rotated_90_degrees_is_the_swapped_flat_foot() -> None:
    posed = Flat(length=0.08, width=0.065).posed(
        Rotation.from_euler("z", 90, degrees=True), resolution=2
    )
    swapped = Flat(length=0.065, width=0.08)
    for h in (0.0, 0.5, math.pi / 2):
        np.testing.assert_allclose(
            posed.resultant(0.012, S, h), swapped.resultant(0.012, S, h), rtol=1e-12, atol=1e-12
        )


@settings(max_examples=30, deadline=None)
@given(
    beta=st.floats(-math.pi, math.pi),
    heading=st.floats(-math.pi, math.pi),
    depth=st.floats(0.001, 0.06),
    trailing=st.booleans(),
)
def test_invariant_under_rotation_about_z(lumpy_mesh, beta, heading, depth, trailing) -> None:
    """Rotating foot and motion about z by beta rotates the force: the mud's one horizontal
    stress (sx = sy, measured along the motion) makes the rule isotropic (D9)."""
    v, f = lumpy_mesh
    foot = MeshFoot(v, f, trailing=trailing)
    rz = Rotation.from_euler("z", beta).as_matrix()
    turned = foot.posed(rz)
    s = np.array([1.5e3, 1.5e3, 1e3])
    f1 = rz @ foot.force(depth, s, heading)
    f2 = turned.force(depth, s, heading + beta)
    np.testing.assert_allclose(f2, f1, rtol=1e-9, atol=1e-9 * np.abs(f1).max())


def test_quarter_turn_swaps_the_channels(lumpy_mesh) -> None:
    """A 90 degree turn about z maps the x channel onto y: swap sx and sy (any sx, sy)."""
    v, f = lumpy_mesh
    foot = MeshFoot(v, f)
    rz = Rotation.from_euler("z", 90, degrees=True).as_matrix()
    turned = foot.posed(rz)
    for h in (0.2, 1.0, 1.4):
        f1 = rz @ foot.force(0.02, [2e3, 0.5e3, 1e3], h)
        # walls that faced x face y after the turn: sx and sy change places
        f2 = turned.force(0.02, [0.5e3, 2e3, 1e3], h + math.pi / 2)
        np.testing.assert_allclose(f2, f1, rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize("trailing", [False, True])
def test_mirror_symmetry(lumpy_mesh, trailing: bool) -> None:
    """Mirroring foot and motion in x (heading -> pi - heading) mirrors the force."""
    v, f = lumpy_mesh
    foot = MeshFoot(v, f, trailing=trailing)
    mirrored = MeshFoot(v * [-1, 1, 1], f[:, ::-1], trailing=trailing)
    for h in (0.3, 1.2, 2.5, -2.0):
        s = np.array([1.8e3, 0.9e3, 1e3])
        f1 = foot.force(0.025, s, h)
        f2 = mirrored.force(0.025, s, math.pi - h)
        np.testing.assert_allclose(f2, f1 * [-1, 1, 1], rtol=1e-9, atol=1e-12)


@pytest.mark.parametrize("foot", [Flat(), SemiCylinder(), SemiSphere()], ids=lambda f: f.name)
def test_symmetric_mesh_vector_rule_equals_folded_closed_form(foot) -> None:
    """On mirror-symmetric feet the direct vector rule (MeshFoot.force) agrees with the
    first-quadrant folding of Foot.force in every quadrant."""
    mesh = foot.to_mesh(resolution=24)
    h = np.linspace(-math.pi, math.pi, 25)
    sy = 1.4e3 if foot.trailing else 0.6e3
    s = np.stack([np.full(h.size, 1.4e3), np.full(h.size, sy), np.full(h.size, 1e3)], -1)
    direct = mesh.force(0.017, s, h)
    folded = Foot.force_unchecked(mesh, 0.017, s, h)  # base rule: fold, resultant, unfold
    np.testing.assert_allclose(direct, folded, rtol=1e-10, atol=1e-12)
    # and both agree with the closed form at mesh accuracy (resolution 24: ~4e-3)
    np.testing.assert_allclose(direct, foot.force(0.017, s, h), rtol=6e-3, atol=1e-3)


@pytest.mark.parametrize("foot", [Flat(), SemiCylinder(), SemiSphere()], ids=lambda f: f.name)
def test_mesh_follows_the_heading_rule_for_every_sign_of_the_stresses(foot) -> None:
    """The element rule and the closed forms' heading rule (D9) are one linear law: the mesh
    equals the folded rule for stresses that resist or pull (suction), and is continuous
    where the motion crosses an axis."""
    mesh = foot.to_mesh(resolution=24)
    eps = 1e-7
    axes = np.arange(-4, 5) * 0.5 * math.pi
    h = np.concatenate([np.linspace(-math.pi, math.pi, 25), axes - eps, axes + eps])
    signs = np.array([[1, 1], [1, -1], [-1, 1], [-1, -1]], float)
    for sgn in signs:
        s = np.broadcast_to([1.4e3 * sgn[0], 0.6e3 * sgn[1], 1e3], (h.size, 3))
        direct = mesh.force(0.017, s, h)
        folded = Foot.force_unchecked(mesh, 0.017, s, h)
        np.testing.assert_allclose(direct, folded, rtol=1e-10, atol=1e-12)
        # continuous across each axis: the force moves by O(eps), not by a wall's shear
        below = mesh.force(0.017, s[: axes.size], axes - eps)
        above = mesh.force(0.017, s[: axes.size], axes + eps)
        np.testing.assert_allclose(below, above, rtol=0, atol=1e-4)
        if not foot.trailing:  # the printed sphere form differs when sigma_x != sigma_y (D22)
            np.testing.assert_allclose(direct, foot.force(0.017, s, h), rtol=6e-3, atol=1e-3)


@settings(max_examples=30, deadline=None)
@given(
    heading=st.floats(-2 * math.pi, 2 * math.pi),
    depth=st.floats(0.002, 0.06),
    sx=st.floats(10, 5e3),
    sy=st.floats(10, 5e3),
    trailing=st.booleans(),
)
def test_forces_oppose_the_motion(lumpy_mesh, heading, depth, sx, sy, trailing) -> None:
    v, f = lumpy_mesh
    foot = MeshFoot(v, f, trailing=trailing)
    c, s = math.cos(heading), math.sin(heading)
    force = foot.force(depth, [sx, sy, 0.0], heading)  # stresses resisting the motion
    assert force[0] * c + force[1] * s < 0


@pytest.mark.parametrize("radius, height", [(0.045, 0.026), (0.045, 0.045), (0.02, 0.005)])
def test_curved_meshes_and_characteristic_lengths_end_at_the_one_rim_angle(radius, height):
    """theta_H = acos(1 - H/R) is written once (meshgen.rim_angle): the meshes' rims and the
    characteristic lengths of D27 (top cross-sections) are read at it."""
    from mudrft._validation import MudrftError
    from mudrft.feet.meshgen import rim_angle, semicylinder_mesh, semisphere_mesh
    from mudrft.feet.shapes import SemiCylinder, SemiSphere

    th = rim_angle(radius, height)
    half = radius * np.sin(th)  # half the top cross-section's width [m]
    v, _ = semicylinder_mesh(radius, 0.065, height, resolution=6)
    assert np.isclose(np.abs(v[:, 1]).max(), half, rtol=1e-12)
    v, _ = semisphere_mesh(radius, height, resolution=6)
    assert np.isclose(np.hypot(v[:, 0], v[:, 1]).max(), half, rtol=1e-12)
    assert SemiCylinder(radius=radius, height=height).characteristic_length == pytest.approx(
        np.sqrt(2 * half * 0.065)
    )
    assert SemiSphere(radius=radius, height=height).characteristic_length == pytest.approx(
        np.sqrt(np.pi) * half
    )
    with pytest.raises(MudrftError, match="height must be <= radius"):
        rim_angle(radius, 1.5 * radius)
