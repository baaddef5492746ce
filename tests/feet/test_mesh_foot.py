"""MeshFoot: validation of bad meshes, frame, pose, files (STL/OBJ/PLY) and by_name."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import mudrft.feet as feet
from mudrft._validation import MudrftError
from mudrft.feet import Flat, MeshFoot, MeshWarning, SemiCylinder, SemiSphere, by_name

S = np.array([1.2e3, 0.8e3, 2e3])


def write_stl(path, triangles, *, binary: bool = True) -> None:
    """Triangles (m, 3, 3) as an STL file, written by trimesh."""
    import trimesh

    tri = np.asarray(triangles, dtype=float)
    faces = np.arange(3 * len(tri)).reshape(-1, 3)
    mesh = trimesh.Trimesh(tri.reshape(-1, 3), faces, process=False)
    mesh.export(path, file_type="stl" if binary else "stl_ascii")


@pytest.fixture(scope="module")
def cyl() -> MeshFoot:
    return SemiCylinder().to_mesh(resolution=6)


def _same(a: MeshFoot, b: MeshFoot, rtol: float = 1e-12) -> None:
    for d, h in ((0.004, 0.0), (0.013, 0.7), (0.03, math.pi / 2)):
        np.testing.assert_allclose(
            a.resultant(d, S, h), b.resultant(d, S, h), rtol=rtol, atol=1e-12
        )


# -- validation ------------------------------------------------------------------------------
def test_bad_vertices_and_faces(cyl: MeshFoot) -> None:
    v, f = cyl.vertices.copy(), cyl.faces
    v[3, 1] = np.nan
    with pytest.raises(MudrftError, match="vertices must be finite"):
        MeshFoot(v, f)
    with pytest.raises(MudrftError, match=r"vertices must have shape \(n, 3\)"):
        MeshFoot(cyl.vertices[:, :2], f)
    with pytest.raises(MudrftError, match="faces must index vertices"):
        MeshFoot(cyl.vertices, np.vstack([f, [[0, 1, len(cyl.vertices)]]]))
    with pytest.raises(MudrftError, match="faces must index vertices"):
        MeshFoot(cyl.vertices, np.vstack([f, [[0, -1, 2]]]))
    with pytest.raises(MudrftError, match="integer vertex indices"):
        MeshFoot(cyl.vertices, f + 0.5)
    with pytest.raises(MudrftError, match=r"triangulate"):
        MeshFoot(cyl.vertices, np.zeros((4, 4), int))
    with pytest.raises(MudrftError, match="at least one triangle"):
        MeshFoot(cyl.vertices, np.zeros((0, 3), int))
    with pytest.raises(MudrftError, match="zero size"):
        MeshFoot(np.zeros((3, 3)), [[0, 1, 2]])
    with pytest.raises(MudrftError, match="every facet has zero area"):
        MeshFoot([[0, 0, 0], [0.01, 0, 0], [0.02, 0, 0]], [[0, 1, 2]])  # collinear
    with pytest.raises(MudrftError, match="trailing must be"):
        MeshFoot(cyl.vertices, f, trailing="yes")


def test_float_faces_with_integer_values_are_accepted(cyl: MeshFoot) -> None:
    _same(MeshFoot(cyl.vertices, cyl.faces.astype(float)), cyl)


def test_zero_area_facets_are_dropped_with_a_warning(cyl: MeshFoot) -> None:
    f = np.vstack([cyl.faces, [[0, 0, 1]], [[2, 2, 2]]])  # repeated vertices: zero area
    with pytest.warns(MeshWarning, match="dropped 2 zero-area"):
        m = MeshFoot(cyl.vertices, f)
    assert m.dropped == 2 and len(m) == len(cyl)
    _same(m, cyl)


def test_inward_winding_is_flipped(cyl: MeshFoot) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # closed meshes raise no warning
        m = MeshFoot(cyl.vertices, cyl.faces[:, ::-1])
    assert m.flipped and not cyl.flipped and m.closed
    _same(m, cyl)


def test_inconsistent_winding_is_an_error(cyl: MeshFoot) -> None:
    f = cyl.faces.copy()
    f[5] = f[5, ::-1]
    with pytest.raises(MudrftError, match="consistently wound"):
        MeshFoot(cyl.vertices, f)


def test_open_mesh_is_accepted_with_a_warning() -> None:
    sole = [[0, 0, 0], [0.065, 0, 0], [0.065, 0.08, 0], [0, 0.08, 0]]
    with pytest.warns(MeshWarning, match="open"):
        plate = MeshFoot(sole, [[0, 2, 1], [0, 3, 2]])
    assert not plate.closed and plate.height == 0.0
    # a thin plate: only the sole, which carries L W sz as the flat foot does
    np.testing.assert_allclose(plate.resultant(0.01, S, 0.3)[2], Flat().resultant(0.01, S, 0.3)[2])


def test_stl_triangle_soup_is_welded_and_closed(cyl: MeshFoot, tmp_path) -> None:
    soup = cyl.triangles.reshape(-1, 3)
    faces = np.arange(soup.shape[0]).reshape(-1, 3)
    m = MeshFoot(soup, faces)  # every vertex repeated per facet: still closed
    assert m.closed
    _same(m, cyl)


# -- frame and pose --------------------------------------------------------------------------
def test_tip_is_moved_to_the_origin(cyl: MeshFoot) -> None:
    off = np.array([0.3, -0.1, 0.25])
    m = MeshFoot(cyl.vertices + off, cyl.faces)
    np.testing.assert_allclose(m.shift, -off, atol=1e-15)
    np.testing.assert_allclose(m.vertices, cyl.vertices, atol=1e-15)
    _same(m, cyl)


def test_posed_accepts_matrix_and_scipy_rotation(cyl: MeshFoot) -> None:
    rot = Rotation.from_euler("xyz", [0.3, -0.2, 1.0])
    a, b = cyl.posed(rot), cyl.posed(rot.as_matrix())
    _same(a, b)
    assert a.vertices[:, 2].min() == 0.0 and a.trailing == cyl.trailing and a.name == cyl.name
    # a rotation about z keeps the height; a tilt changes it
    assert cyl.posed(Rotation.from_euler("z", 0.7)).height == pytest.approx(cyl.height)
    assert a.height > cyl.height
    with pytest.raises(MudrftError, match="proper rotation"):
        cyl.posed(np.diag([1.0, 1.0, -1.0]))
    with pytest.raises(MudrftError, match="3x3 matrix"):
        cyl.posed(np.eye(2))


def test_upside_down_semisphere_rests_on_its_flat_top() -> None:
    """Turned over, the cap presses with its flat top: F_z = pi (R sin theta_H)^2 sz."""
    foot = SemiSphere()
    flipped = foot.posed(Rotation.from_euler("x", math.pi), resolution=16)
    area = math.pi * (foot.characteristic_length / math.sqrt(math.pi)) ** 2
    # polygonal rim of 64 segments: area ratio sin(2 pi/64)/(2 pi/64) = 0.9984, so 2e-3
    assert flipped.resultant(0.001, [0, 0, 1.0], 0.0)[2] == pytest.approx(area, rel=2e-3)


def test_elements_and_closed_form_elements() -> None:
    el = SemiSphere().elements()
    assert el.centroids.shape == el.normals.shape == (len(el), 3)
    np.testing.assert_allclose(np.linalg.norm(el.normals, axis=1), 1.0, rtol=1e-12)
    # total area of the cap plus its top disk, second-order accurate at resolution 48
    r, h = 0.045, 0.026
    rim = math.sqrt(h * (2 * r - h))
    assert el.areas.sum() == pytest.approx(2 * math.pi * r * h + math.pi * rim**2, rel=1e-3)


def test_closed_form_center_of_pressure_on_the_axis() -> None:
    cop = SemiCylinder().center_of_pressure(np.array([0.01, 0.02]), [0.0, 0.0, 1e3], 0.0)
    assert cop.shape == (2, 3)
    np.testing.assert_allclose(cop[:, :2], 0.0, atol=1e-12)  # symmetric load


# -- files -----------------------------------------------------------------------------------
@pytest.mark.parametrize("binary", [True, False])
def test_stl_round_trip(cyl: MeshFoot, tmp_path, binary: bool) -> None:
    path = tmp_path / "foot.stl"
    write_stl(path, cyl.triangles * 1e3, binary=binary)  # in mm, as CAD exports
    back = MeshFoot.from_file(path, unit="mm")
    assert back.name == "foot" and back.closed
    # binary STL stores float32: ~1e-7 relative on the coordinates, so 1e-5 on forces
    _same(back, cyl, rtol=1e-5 if binary else 1e-12)


@pytest.mark.parametrize("ext", [".obj", ".ply"])
def test_obj_and_ply_through_trimesh(cyl: MeshFoot, tmp_path, ext: str) -> None:
    import trimesh

    path = tmp_path / f"foot{ext}"
    trimesh.Trimesh(cyl.vertices, cyl.faces, process=False).export(path)
    _same(MeshFoot.from_file(path), cyl, rtol=1e-6)  # text formats may round to ~8 digits


def test_bad_files(tmp_path) -> None:
    with pytest.raises(MudrftError, match=r"one of \['.stl', '.obj', '.ply'\]"):
        MeshFoot.from_file(tmp_path / "foot.step")
    with pytest.raises(MudrftError, match="no such file"):
        MeshFoot.from_file(tmp_path / "missing.stl")
    garbage = tmp_path / "garbage.stl"
    garbage.write_bytes(bytes(range(256)) * 3)
    with pytest.raises(MudrftError, match="neither a binary STL"):
        MeshFoot.from_file(garbage)
    cut = tmp_path / "cut.stl"
    cut.write_text("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n")
    with pytest.raises(MudrftError, match="looks truncated"):
        MeshFoot.from_file(cut)
    nan = tmp_path / "nan.stl"
    nan.write_text(
        "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 nan\n"
        "vertex 0 1 0\nendloop\nendfacet\nendsolid x\n"
    )
    with pytest.raises(MudrftError, match="NaN or infinite"):
        MeshFoot.from_file(nan)
    empty = tmp_path / "empty.stl"
    empty.write_bytes(b"\0" * 80 + (0).to_bytes(4, "little"))
    with pytest.raises(MudrftError, match="no triangles"):
        MeshFoot.from_file(empty)
    bad_obj = tmp_path / "bad.ply"
    bad_obj.write_text("not a ply file at all")
    with pytest.raises(MudrftError, match=r"could not read|no triangles"):
        MeshFoot.from_file(bad_obj)
    with pytest.raises(MudrftError, match="unit for length"):
        MeshFoot.from_file(garbage, unit="furlong")


# -- names -----------------------------------------------------------------------------------
def test_by_name(tmp_path) -> None:
    assert by_name("flat") == Flat() and by_name("semi-cylinder") == SemiCylinder()
    assert by_name("semi-sphere") == SemiSphere()
    path = tmp_path / "paper_flat.stl"
    write_stl(path, Flat().to_mesh(resolution=1).triangles)
    m = by_name(str(path))
    assert isinstance(m, MeshFoot) and m.name == "paper_flat"
    np.testing.assert_allclose(m.resultant(0.01, S, 0.5), Flat().resultant(0.01, S, 0.5), rtol=1e-6)
    with pytest.raises(MudrftError, match="foot must be one of"):
        by_name("hoof")


def test_morphing_is_lazy() -> None:
    pytest.importorskip("mudrft.feet.morphing")
    assert feet.MorphingFoot.__name__ == "MorphingFoot"
    assert isinstance(by_name("morphing"), feet.MorphingFoot)


def test_unknown_attribute() -> None:
    with pytest.raises(AttributeError, match="no attribute 'Hoof'"):
        feet.Hoof  # noqa: B018
