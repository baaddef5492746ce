"""Mesh files through trimesh: truncated and malformed files, inward open meshes, units,
memory bounded before parsing, complex vertices, the example foot shipped with mudrft.

Each file mistake is refused with a MudrftError that names the file; a truncated ASCII STL
is never read as part of a foot.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
import trimesh

import mudrft
from mudrft._validation import MudrftError
from mudrft.feet import Flat, MeshFoot, MeshWarning, SemiSphere
from mudrft.feet.meshfile import BYTES_PER_FACET, BYTES_PER_FILE_BYTE
from mudrft.sweep.spec import load_spec
from mudrft.units import parse_unit

#: A downward-facing sole (80 x 65 mm): faces [0, 2, 1], [0, 3, 2] point down.
SOLE = [[0, 0, 0], [0.065, 0, 0], [0.065, 0.08, 0], [0, 0.08, 0]]


def write_stl(path, triangles, *, binary: bool = True) -> None:
    """Triangles (m, 3, 3) as an STL file, written by trimesh."""
    tri = np.asarray(triangles, dtype=float)
    faces = np.arange(3 * len(tri)).reshape(-1, 3)
    mesh = trimesh.Trimesh(tri.reshape(-1, 3), faces, process=False)
    mesh.export(path, file_type="stl" if binary else "stl_ascii")


def facet_text(tri, *, vertices: int = 3) -> str:
    """One ASCII STL facet with its first ``vertices`` corners (cycling for more than 3)."""
    corners = [np.asarray(tri).tolist()[k % 3] for k in range(vertices)]
    rows = "".join(f"vertex {x!r} {y!r} {z!r}\n" for x, y, z in corners)
    return f"facet normal 0 0 0\nouter loop\n{rows}endloop\nendfacet\n"


@pytest.fixture
def box_text() -> str:
    """The paper's flat foot (12 facets) as ASCII STL text."""
    tri = Flat().to_mesh(resolution=1).triangles
    return "solid box\n" + "".join(facet_text(t) for t in tri) + "endsolid box\n"


def boundary(path, match: str, **kw) -> None:
    with pytest.raises(MudrftError, match=match) as info:
        MeshFoot.from_file(path, **kw)
    assert str(path) in str(info.value), f"the message does not name the file: {info.value}"


# -- 1. truncated files and facets of other than three vertices ------------------------------
def test_a_truncated_ascii_stl_is_refused_not_read_as_part_of_a_foot(tmp_path, box_text):
    whole = tmp_path / "box.stl"
    whole.write_text(box_text)
    assert len(MeshFoot.from_file(whole)) == 12
    ends = [m.end() for m in re.finditer("endfacet\n", box_text)]
    for name, cut in (("half", ends[5]), ("cut", ends[5] + 60)):  # on a facet, inside one
        path = tmp_path / f"{name}.stl"
        path.write_text(box_text[:cut])
        boundary(path, r"looks truncated: an ASCII STL ends with an 'endsolid' line")
    empty = tmp_path / "empty.stl"
    empty.write_text("solid nothing\nendsolid nothing\n")
    # trimesh 5 reads no triangles, trimesh 4 fails: refused either way
    boundary(empty, r"(contains no triangles|could not read).*\(an ASCII STL is a 'solid' line")


@pytest.mark.parametrize("count", [4, 2])
def test_an_ascii_facet_must_have_three_vertices(tmp_path, count):
    tri = Flat().to_mesh(resolution=1).triangles
    body = facet_text(tri[0]) + facet_text(tri[1], vertices=count) + facet_text(tri[2])
    path = tmp_path / "quad.stl"
    path.write_text(f"solid q\n{body}endsolid q\n")
    boundary(path, r"could not read the mesh file .*facets of exactly 3 'vertex' lines")


def test_ascii_stl_variants_that_stay_valid(tmp_path, box_text):
    """CRLF line ends, capital keywords and several solids in one file are all read."""
    crlf = tmp_path / "crlf.stl"
    crlf.write_bytes(box_text.upper().replace("\n", "\r\n").encode())
    two = tmp_path / "two.stl"
    head, tail = box_text.split("endfacet\n", 1)
    two.write_text(head + "endfacet\nendsolid a\nsolid b\n" + tail)
    for path in (crlf, two):
        assert len(MeshFoot.from_file(path)) == 12


def test_a_file_that_is_no_stl_is_named_so(tmp_path):
    garbage = tmp_path / "garbage.stl"
    garbage.write_bytes(bytes(range(256)) * 3)
    boundary(garbage, r"neither a binary STL \(its size, 768 bytes, does not match")
    text = tmp_path / "text.stl"
    text.write_text("hello world\n")
    boundary(text, "nor an ASCII STL")


# -- 2. an open mesh whose normals point inward ----------------------------------------------
def test_a_mesh_with_no_downward_facing_area_is_refused():
    with pytest.raises(MudrftError, match=r"plan area is 0 m\^2.*normals may point inward"):
        MeshFoot(SOLE, [[0, 1, 2], [0, 2, 3]])  # the sole wound upward: no bottom
    with pytest.warns(MeshWarning, match="open"):
        plate = MeshFoot(SOLE, [[0, 2, 1], [0, 3, 2]])  # wound downward: a valid plate
    assert plate.characteristic_length == pytest.approx(np.sqrt(0.065 * 0.08))
    with pytest.raises(MudrftError, match="no facet facing down"):
        plate.posed([[1, 0, 0], [0, 0, -1], [0, 1, 0]])  # turned on edge: no bottom left


def test_an_inward_open_mesh_file_is_refused_naming_the_file(tmp_path):
    path = tmp_path / "inward.stl"
    write_stl(path, np.asarray(SOLE, float)[[[0, 1, 2], [0, 2, 3]]])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", MeshWarning)
        boundary(path, "normals may point inward")


# -- 3. units and paths that are not strings -------------------------------------------------
@pytest.mark.parametrize("unit", [None, 1e-3, 1, True])
def test_a_unit_that_is_not_a_string_is_named(tmp_path, unit):
    path = tmp_path / "foot.stl"
    write_stl(path, Flat().to_mesh(resolution=1).triangles)
    with pytest.raises(MudrftError, match=r"unit must be .* such as 'm' or 'mm'"):
        MeshFoot.from_file(path, unit=unit)
    with pytest.raises(MudrftError, match=r"unit for length must be a unit string"):
        parse_unit("length", unit)
    with pytest.raises(MudrftError, match=r'\[foot\] unit must be .* such as "m" or "mm"'):
        load_spec({"foot": {"kind": str(path), "unit": unit}})


@pytest.mark.parametrize("path", [None, 3, b"foot.stl"])
def test_a_path_that_is_not_a_path_is_named(path):
    with pytest.raises(MudrftError, match="path must be the path of a mesh file"):
        MeshFoot.from_file(path)


# -- 4. memory is checked before trimesh parses the file -------------------------------------
def _never_parsed(monkeypatch) -> None:
    def never(*args, **kwargs):
        raise AssertionError("trimesh was asked to parse a file over the memory limit")

    monkeypatch.setattr(trimesh, "load", never)
    monkeypatch.setattr(trimesh.exchange.stl, "load_stl", never)


def test_a_binary_stl_is_refused_from_its_header_count_before_it_is_read(tmp_path, monkeypatch):
    path = tmp_path / "box.stl"
    write_stl(path, Flat().to_mesh(resolution=1).triangles)
    _never_parsed(monkeypatch)
    monkeypatch.setenv("MUDRFT_MEMORY_LIMIT", str(12 * BYTES_PER_FACET - 1))
    boundary(path, r"reading the STL file .* \(12 facets\) would need")
    monkeypatch.setenv("MUDRFT_MEMORY_LIMIT", str(12 * BYTES_PER_FACET))  # fits: parsed
    boundary(path, "AssertionError: trimesh was asked to parse")  # the fake's error, wrapped


@pytest.mark.parametrize("suffix", [".stl", ".obj", ".ply"])
def test_other_files_are_refused_from_their_size_before_they_are_parsed(
    tmp_path, monkeypatch, suffix
):
    path = tmp_path / f"box{suffix}"
    box = Flat().to_mesh(resolution=1)
    kind = "stl_ascii" if suffix == ".stl" else suffix[1:]
    trimesh.Trimesh(box.vertices, box.faces, process=False).export(path, file_type=kind)
    size = path.stat().st_size
    _never_parsed(monkeypatch)
    monkeypatch.setenv("MUDRFT_MEMORY_LIMIT", str(size * BYTES_PER_FILE_BYTE - 1))
    boundary(path, rf"reading the mesh file .* \({size} bytes\) would need")


def _box_mesh(quads: bool) -> tuple[np.ndarray, list[list[int]]]:
    """The paper's flat foot as vertices and faces: 12 triangles, or 6 quads."""
    v = np.array([[x, y, z] for z in (0, 0.026) for y in (0, 0.08) for x in (0, 0.065)])
    quad = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]]
    if quads:
        return v, quad
    return v, [t for q in quad for t in ([q[0], q[1], q[2]], [q[0], q[2], q[3]])]


def _write_ply(path, v, faces, *, binary: bool, index: str = "int") -> None:
    import struct

    head = [
        "ply", f"format {'binary_little_endian' if binary else 'ascii'} 1.0", "comment box",
        f"element vertex {len(v)}", "property float x", "property float y", "property float z",
        f"element face {len(faces)}", f"property list uchar {index} vertex_indices", "end_header",
    ]  # fmt: skip
    code = {"int": "i", "ushort": "H"}[index]
    with open(path, "wb") as fh:
        fh.write(("\n".join(head) + "\n").encode())
        for p in v:
            fh.write(struct.pack("<3f", *p) if binary else f"{p[0]} {p[1]} {p[2]}\n".encode())
        for f in faces:
            row = (len(f), *f)
            fh.write(
                struct.pack(f"<B{len(f)}{code}", *row)
                if binary
                else (" ".join(map(str, row)) + "\n").encode()
            )


@pytest.mark.parametrize("fmt", ["obj", "ply-ascii", "ply-binary", "ply-binary-ushort"])
@pytest.mark.parametrize("quads", [False, True])
def test_obj_and_ply_of_triangles_or_quads_make_the_same_foot(tmp_path, fmt, quads):
    """12 triangles either way (trimesh splits a quad in two)."""
    v, faces = _box_mesh(quads)
    path = tmp_path / f"box.{fmt[:3]}"
    if fmt == "obj":
        rows = [f"v {x} {y} {z}" for x, y, z in v] + [
            "f " + " ".join(str(i + 1) for i in f) for f in faces
        ]
        path.write_text("# box\n" + "\n".join(rows) + "\n")
    else:
        _write_ply(
            path, v, faces, binary=fmt != "ply-ascii", index="ushort" if "ushort" in fmt else "int"
        )
    foot = MeshFoot.from_file(path)
    assert foot.faces.shape == (12, 3) and foot.closed
    assert foot.height == pytest.approx(0.026, rel=1e-6)


# -- 5. messages that name the file and the fault --------------------------------------------
def test_mesh_errors_from_a_file_name_the_file(tmp_path):
    tri = Flat().to_mesh(resolution=1).triangles.copy()
    tri[3] = tri[3][::-1]
    wound = tmp_path / "wound.stl"
    write_stl(wound, tri)
    boundary(wound, "consistently wound")
    line = tmp_path / "line.stl"
    write_stl(line, np.array([[[0, 0, 0], [0.01, 0, 0], [0.02, 0, 0]]]))
    boundary(line, "no non-degenerate facet: every facet has zero area")
    nan = tmp_path / "nan.obj"
    nan.write_text("v 0 0 0\nv 0.01 0 nan\nv 0 0.01 0\nf 1 2 3\n")
    boundary(nan, r"NaN or infinite vertex coordinates \(vertex 1")


def test_an_all_degenerate_stl_says_it_has_no_facet(tmp_path):
    path = tmp_path / "point.stl"
    write_stl(path, np.zeros((2, 3, 3)))
    boundary(path, "no non-degenerate facet")


def test_a_directory_is_not_called_missing(tmp_path):
    (tmp_path / "x.stl").mkdir()
    with pytest.raises(MudrftError, match="which is a directory"):
        MeshFoot.from_file(tmp_path / "x.stl")


def test_a_ply_without_a_property_names_it_and_the_file(tmp_path):
    path = tmp_path / "bad.ply"
    path.write_text(
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float y\nproperty float z\n"
        "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0\n1 0\n0 1\n3 0 1 2\n"
    )
    boundary(path, r"lacks the property or element 'x' \(a PLY mesh needs")


@pytest.mark.parametrize("up", ["y", "-y", "x", "-x", "-z"])
def test_a_file_with_another_up_axis_is_stood_up(tmp_path, up):
    # a Y-up export (Blender's OBJ default) was taken as it lay: the foot's length stood
    # vertical. up= turns the file's up axis to +z: the same foot as the z-up file
    from mudrft.feet.mesh import UP_AXES

    dome = SemiSphere().to_mesh(resolution=6)  # no symmetry that hides a wrong turn
    turn = np.array(UP_AXES[up], float)  # file -> z up, so z up -> file is its transpose
    write_stl(tmp_path / "z.stl", dome.triangles, binary=False)
    write_stl(tmp_path / "f.stl", dome.triangles @ turn, binary=False)
    assert np.allclose(turn @ np.array({"x": [1, 0, 0], "y": [0, 1, 0], "-x": [-1, 0, 0],
                                        "-y": [0, -1, 0], "-z": [0, 0, -1]}[up]), [0, 0, 1])  # fmt: skip
    upright = MeshFoot.from_file(tmp_path / "z.stl")
    lying = MeshFoot.from_file(tmp_path / "f.stl")
    stood = MeshFoot.from_file(tmp_path / "f.stl", up=up)
    assert stood.height == pytest.approx(upright.height, abs=1e-12)
    for d in (0.005, 0.01, 0.02):
        np.testing.assert_allclose(stood.projected_areas(d), upright.projected_areas(d), atol=1e-12)
    assert not np.allclose(lying.projected_areas(0.01), upright.projected_areas(0.01), rtol=0.05)


def test_up_is_checked_and_is_for_mesh_files_only(tmp_path):
    from mudrft.feet import by_name

    write_stl(tmp_path / "z.stl", Flat().to_mesh(resolution=1).triangles)
    with pytest.raises(MudrftError, match=r"up must be the file's up axis, one of .*got 'Y'"):
        MeshFoot.from_file(tmp_path / "z.stl", up="Y")
    with pytest.raises(MudrftError, match=r"up \(CLI: --up\) applies to mesh files only"):
        by_name("flat", up="y")
    assert by_name(str(tmp_path / "z.stl"), up="z").height == pytest.approx(0.026, abs=1e-9)


# -- 6. complex vertices (issue 43), a million facets, the example foot ----------------------
def test_complex_vertices_are_refused():
    box = Flat().to_mesh(resolution=1)
    with pytest.raises(MudrftError, match=r"vertices must be real coordinates \[m\], got complex"):
        MeshFoot(box.vertices + 1e-3j, box.faces)
    with pytest.raises(MudrftError, match="got complex numbers"):
        MeshFoot(box.vertices.astype(complex), box.faces)  # even with no imaginary part


def test_the_weld_merges_exact_matches_as_numpy_unique_does():
    from mudrft.feet.meshfile import weld

    rng = np.random.default_rng(3)
    points = rng.integers(0, 4, (500, 3)).astype(float) * 0.01  # many exact repeats
    distinct, inverse = weld(points)
    expected = np.unique(points, axis=0)
    np.testing.assert_array_equal(distinct, expected)
    np.testing.assert_array_equal(distinct[inverse], points)


def test_the_example_foot_ships_with_mudrft_and_loads_as_the_readme_shows():
    path = mudrft.data_path("foot.stl")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a closed mesh of a plausible size: no warning
        foot = MeshFoot.from_file(path, unit="mm")
    assert foot.name == "foot" and foot.closed and len(foot) == 288
    assert foot.height == pytest.approx(0.026, rel=1e-6)
    stress = [0.0, 0.0, 2e3]  # the support of the paper's semi-sphere, to the mesh's resolution
    expected = SemiSphere().resultant(0.02, stress, 0.0)[2]
    assert foot.resultant(0.02, stress, 0.0)[2] == pytest.approx(expected, rel=0.02)
    with pytest.raises(MudrftError, match=r"name must be a file shipped with mudrft, one of"):
        mudrft.data_path("hoof.stl")


def test_import_mudrft_loads_neither_scipy_sparse_nor_trimesh():
    code = (
        "import sys, mudrft, mudrft.feet; mudrft.feet.MeshFoot; "
        "print(sorted(m for m in ('scipy.sparse', 'trimesh') if m in sys.modules))"
    )
    src = str(Path(mudrft.__file__).resolve().parents[1])  # this checkout's mudrft
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([src, os.environ.get("PYTHONPATH", "")])}
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True, env=env
    )
    assert out.stdout.strip() == "[]"
