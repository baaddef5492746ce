"""The element rule of mudrft.feet.surface: clipping, local frame, eq. (6), wrench, JAX."""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from mudrft.constitutive.laws import f_n, f_n_extended, f_t, f_t_extended
from mudrft.feet import Flat, SemiSphere
from mudrft.feet.surface import (
    clip_below,
    element_forces,
    integrate_triangles,
    integrate_wrench,
    prepare_triangles,
)

EXACT = 1e-12  # closed-form geometry in double precision: only round-off (~1e-16) remains


def clip_reference(tri: np.ndarray, d: float) -> tuple[float, np.ndarray]:
    """Sutherland-Hodgman clip of one triangle by z < d; polygon area and centroid.

    Strict: a facet lying in the surface plane (z == d everywhere) has no depth and is out,
    the convention of ``clip_below`` (the boundary has measure zero for any other facet).
    """
    poly = []
    for i in range(3):
        a, b = tri[i], tri[(i + 1) % 3]
        ina, inb = a[2] < d, b[2] < d
        if ina:
            poly.append(a)
        if ina != inb:
            t = (d - a[2]) / (b[2] - a[2])
            poly.append(a + t * (b - a))
    if len(poly) < 3:
        return 0.0, tri.mean(0)
    p0 = poly[0]
    area, cen = 0.0, np.zeros(3)
    for i in range(1, len(poly) - 1):  # fan: triangles of a convex polygon
        ai = 0.5 * np.linalg.norm(np.cross(poly[i] - p0, poly[i + 1] - p0))
        area += ai
        cen += ai * (p0 + poly[i] + poly[i + 1]) / 3
    return area, cen / area if area > 0 else tri.mean(0)


@settings(max_examples=50, deadline=None)
@given(seed=st.integers(0, 2**20), d=st.floats(-0.2, 1.2))
@example(seed=0, d=0.5)  # the horizontal facet lies exactly in the surface plane
def test_clipping_is_exact(seed: int, d: float) -> None:
    rng = np.random.default_rng(seed)
    tri = rng.uniform(0, 1, (6, 3, 3))
    tri[1, 1, 2] = tri[1, 0, 2]  # two vertices at the same height
    tri[2, :, 2] = 0.5  # a horizontal facet
    area, cen = clip_below(prepare_triangles(tri), d)
    for k in range(len(tri)):
        a_ref, c_ref = clip_reference(tri[k], d)
        assert area[k] == pytest.approx(a_ref, rel=EXACT, abs=EXACT)
        if a_ref > 1e-9:  # centroid defined (tiny slivers: round-off in the reference)
            np.testing.assert_allclose(cen[k], c_ref, rtol=1e-9, atol=1e-9)


def test_clip_below_gives_the_submerged_centroid() -> None:
    tri = np.array([[[0, 0, 0], [1, 0, 1], [-1, 0, 1]]], dtype=float)
    area, cen = clip_below(prepare_triangles(tri), 0.6)
    # submerged triangle of height 0.6: centroid at z = 0.4, 0.2 below the surface
    np.testing.assert_allclose(area, [0.36])
    np.testing.assert_allclose(0.6 - cen[:, 2], [0.2])


class LocalFrame(NamedTuple):
    e1: np.ndarray
    e2: np.ndarray
    e3: np.ndarray
    psi1: np.ndarray
    psi2: np.ndarray
    varphi: np.ndarray


def local_frame(normals: np.ndarray, heading: float) -> LocalFrame:
    """The paper's local plate frame (Sec. II-C) and angles of eq. (6), for unit normals (m, 3):
    e1 = n x e3 / |.|, e2 = e3 x e1 the horizontal normal, psi1 from -e_z, psi2 from e2 to
    the motion, varphi the azimuth of e2; e1, e2 zero for horizontal facets."""
    n = np.asarray(normals)
    r = np.hypot(n[:, 0], n[:, 1])
    safe = np.where(r > 0, r, 1.0)
    nx, ny = np.where(r > 0, n[:, 0] / safe, 0.0), np.where(r > 0, n[:, 1] / safe, 0.0)
    zero = np.zeros_like(r)
    ux, uy = math.cos(heading), math.sin(heading)
    return LocalFrame(
        e1=np.stack([ny, -nx, zero], axis=-1),
        e2=np.stack([nx, ny, zero], axis=-1),
        e3=np.stack([zero, zero, zero + 1.0], axis=-1),
        psi1=np.arctan2(r, -n[:, 2]),
        psi2=np.arctan2(nx * uy - ny * ux, nx * ux + ny * uy),
        varphi=np.arctan2(ny, nx),
    )


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 2**20), heading=st.floats(-2 * math.pi, 2 * math.pi))
def test_local_frame_and_angles(seed: int, heading: float) -> None:
    rng = np.random.default_rng(seed)
    n = rng.normal(size=(20, 3))
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    fr = local_frame(n, heading)
    np.testing.assert_allclose(np.einsum("ij,ij->i", fr.e1, fr.e2), 0, atol=EXACT)
    np.testing.assert_allclose(np.linalg.norm(fr.e1, axis=1), 1, rtol=EXACT)
    # e1 = n x e3 / |n x e3| as in Sec. II-C, e2 = e3 x e1 is the horizontal normal
    ne3 = np.cross(n, [0, 0, 1])
    np.testing.assert_allclose(fr.e1, ne3 / np.linalg.norm(ne3, axis=1, keepdims=True), atol=EXACT)
    np.testing.assert_allclose(fr.e2, np.cross(fr.e3, fr.e1), atol=EXACT)
    np.testing.assert_allclose(np.cos(fr.psi1), -n[:, 2], atol=EXACT)
    u = np.array([math.cos(heading), math.sin(heading), 0.0])
    np.testing.assert_allclose(np.cos(fr.psi2), fr.e2 @ u, atol=EXACT)
    np.testing.assert_allclose(np.sin(fr.psi2), -(fr.e1 @ u), atol=EXACT)
    np.testing.assert_allclose(np.arctan2(fr.e2[:, 1], fr.e2[:, 0]), fr.varphi, atol=EXACT)


def _single(normal: np.ndarray) -> np.ndarray:
    """A unit-area triangle with the given outward normal, centred below z = 0.5."""
    n = normal / np.linalg.norm(normal)
    a = np.cross(n, [0.3, 0.5, 0.7])
    a /= np.linalg.norm(a)
    b = np.cross(n, a)
    s = math.sqrt(2.0)  # legs of length sqrt(2): area 1
    p0 = np.array([0.0, 0.0, 0.2])
    return np.array([[p0, p0 + s * a, p0 + s * b]])


@settings(max_examples=40, deadline=None)
@given(seed=st.integers(0, 2**20), heading=st.floats(-math.pi, math.pi), trailing=st.booleans())
def test_element_force_is_eq6_with_the_paper_factors(
    seed: int, heading: float, trailing: bool
) -> None:
    """Erratum E24: the element force equals eq. (6) with dF_y = -(sn sin + st cos) dS_h,
    with the per-face stress of D22 (stresses measured along the motion)."""
    rng = np.random.default_rng(seed)
    n = rng.normal(size=3)
    tri = _single(n)
    prep = prepare_triangles(tri)
    s = rng.uniform(-3.0, 3.0, 3)
    df, _ = element_forces(prep, 10.0, s, heading, trailing=trailing)  # fully submerged
    fr = local_frame(prep.normal, heading)
    nn = prep.normal[0]
    r = math.hypot(nn[0], nn[1])
    psi1, psi2, vphi = float(fr.psi1[0]), float(fr.psi2[0]), float(fr.varphi[0])
    c2, s2 = math.cos(vphi) ** 2, math.sin(vphi) ** 2
    sig_x = sig_y = s[0] * c2 + s[1] * s2  # per-face stress (D22)
    lead = math.cos(psi2) > 1e-9 or (abs(math.cos(psi2)) <= 1e-9 and math.sin(psi2) > 0)
    if trailing:
        fn, ft = f_n_extended(psi2), f_t_extended(psi2)
    else:  # leading facets only, sign of the tangential part from sin(psi2)
        fn, ft = f_n(psi2) * lead, math.copysign(f_t(psi2), math.sin(psi2)) * lead
    dsh = r * 1.0  # projected area of the unit facet
    ex = (-fn * sig_x * math.cos(vphi) + ft * sig_x * math.sin(vphi)) * dsh
    ey = -(fn * sig_y * math.sin(vphi) + ft * sig_y * math.cos(vphi)) * dsh
    ez = (f_n(psi1) * math.cos(psi1) + f_t(psi1) * math.sin(psi1)) * s[2] if nn[2] < -1e-9 else 0.0
    np.testing.assert_allclose(df[0], [ex, ey, ez], rtol=1e-10, atol=1e-12)


def test_printed_eq6_sign_of_dFy_would_push_along_the_motion() -> None:
    """E24: a facet facing +y, motion +y: printed dF_y = +sn sin(varphi) aids the motion."""
    tri = _single(np.array([0.0, 1.0, 0.0]))
    df, _ = element_forces(prepare_triangles(tri), 10.0, [0.0, 1.0, 0.0], math.pi / 2)
    sn, vphi = 1.0 * f_n(0.0), math.pi / 2
    printed_dfy = sn * math.sin(vphi)
    assert printed_dfy > 0 and df[0, 1] == pytest.approx(-printed_dfy)


def test_vertical_walls_carry_no_vertical_force() -> None:
    """D21: psi1 = pi/2 walls (f_t = 1) would add sz per area; they are excluded."""
    tilt = 1e-13  # round-off sized tilt of a wall
    wall = _single(np.array([1.0, 0.0, -tilt]))
    f = integrate_triangles(wall, 10.0, [0.0, 0.0, 1.0], 0.0)
    assert f[2] == 0.0
    steep = _single(np.array([1.0, 0.0, -0.01]))
    psi1 = math.acos(0.01 / math.hypot(1.0, 0.01))  # 0.57 deg from vertical: counts fully
    assert integrate_triangles(steep, 10.0, [0.0, 0.0, 1.0], 0.0)[2] == pytest.approx(
        f_n(psi1) * math.cos(psi1) + f_t(psi1) * math.sin(psi1), rel=1e-12
    )


def test_wrench_moment_and_center_of_pressure() -> None:
    tri = SemiSphere().to_mesh(resolution=8).triangles
    s, h, d = [1.5e3, 0.5e3, 2e3], 0.6, 0.018
    w0 = integrate_wrench(tri, d, s, h, trailing=True)
    p = np.array([0.01, -0.02, 0.03])
    wp = integrate_wrench(tri, d, s, h, point=p, trailing=True)
    np.testing.assert_allclose(wp.force, w0.force, rtol=EXACT)
    # transfer of moments: M_p = M_0 - p x F
    np.testing.assert_allclose(wp.moment, w0.moment - np.cross(p, w0.force), rtol=1e-10, atol=1e-14)
    np.testing.assert_allclose(wp.center_of_pressure, w0.center_of_pressure, atol=1e-12)
    # about the center of pressure only a couple along F remains (central axis)
    cop = w0.center_of_pressure
    m_cop = w0.moment - np.cross(cop, w0.force)
    scale = np.linalg.norm(w0.moment) * np.linalg.norm(w0.force)
    assert np.linalg.norm(np.cross(m_cop, w0.force)) <= 1e-12 * scale  # round-off only


def test_center_of_pressure_of_flat_foot() -> None:
    foot = Flat().to_mesh(resolution=4)
    # vertical load: uniform pressure on the sole, center of the sole
    np.testing.assert_allclose(
        foot.center_of_pressure(0.01, [0, 0, 1e3], 0.0), [0, 0, 0], atol=1e-12
    )
    # pure x load at heading 0: uniform pressure on the +x face, half-way down the wet part
    cop = foot.center_of_pressure(0.01, [1e3, 0, 0], 0.0)
    np.testing.assert_allclose(cop, [0.0325, 0.0, 0.005], atol=1e-12)


def test_batch_broadcasting_matches_loop() -> None:
    tri = SemiSphere().to_mesh(resolution=6).triangles
    rng = np.random.default_rng(1)
    d = rng.uniform(0, 0.03, 7)
    s = rng.uniform(-2e3, 2e3, (7, 3))
    h = rng.uniform(-4, 4, 7)
    batch = integrate_triangles(tri, d, s, h, trailing=True)
    loop = [integrate_triangles(tri, d[i], s[i], h[i], trailing=True) for i in range(7)]
    np.testing.assert_allclose(batch, loop, rtol=1e-12, atol=1e-14)
    # a batch of posed feet: triangles (N, m, 3, 3) with one depth each
    stack = np.stack([tri, tri[:, :, [1, 0, 2]][:, ::-1]])  # the second mirrored in x <-> y
    out = integrate_triangles(stack, d[:2], s[:2], h[:2], trailing=True)
    np.testing.assert_allclose(out[0], loop[0], rtol=1e-12, atol=1e-14)
    alone = integrate_triangles(stack[1], d[1], s[1], h[1], trailing=True)
    np.testing.assert_allclose(out[1], alone, rtol=1e-12, atol=1e-14)


@pytest.mark.slow
def test_runs_under_jax() -> None:
    jax = pytest.importorskip("jax")
    jnp = jax.numpy
    tri = SemiSphere().to_mesh(resolution=6).triangles
    d, s, h = (
        np.array([0.005, 0.02]),
        np.array([[1e3, 2e3, 3e3], [-1e3, 1e3, 1e3]]),
        np.array([0.3, 2.2]),
    )
    ref = integrate_wrench(tri, d, s, h, trailing=True)
    got = integrate_wrench(
        jnp.asarray(tri), jnp.asarray(d), jnp.asarray(s), jnp.asarray(h), trailing=True, xp=jnp
    )
    for a, b in zip(ref, got, strict=True):
        # jax computes in float32 by default: ~1e-6 relative on sums of ~1e3 terms
        np.testing.assert_allclose(np.asarray(b), a, rtol=2e-5, atol=1e-6 * np.abs(a).max())
    grad = jax.grad(
        lambda dd: integrate_triangles(
            jnp.asarray(tri), dd, jnp.asarray(s[0]), 0.3, trailing=True, xp=jnp
        )[2]
    )(0.01)
    assert np.isfinite(float(grad)) and float(grad) > 0  # deeper: more support


def test_tilted_flat_foot_counts_the_wall_that_faces_down() -> None:
    """D21 caveat: eq. (6) gives a wall tilted by any angle below the horizontal the full
    f_t(psi1) sin(psi1) ~ 1 weight, so a flat foot tilted by 0.01 deg about x adds the
    W x z wall that now faces down: F_z jumps from L W sz to (L W + W z) sz."""
    from scipy.spatial.transform import Rotation

    foot = Flat()
    tilted = foot.posed(Rotation.from_euler("x", 0.01, degrees=True), resolution=1)
    z, sz = 0.02, 1e4
    fz = tilted.resultant(z, [0.0, 0.0, sz], 0.0)[2]
    # cos(1.7e-4 rad) and the 1.4e-5 m lift of the tilted sole: ~1e-5 relative
    assert fz == pytest.approx((foot.length * foot.width + foot.width * z) * sz, rel=1e-4)
