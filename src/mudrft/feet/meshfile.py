"""Mesh files (STL, OBJ, PLY) read through trimesh, their memory bounded before parsing
(a binary STL's from the facet count in its header, any other file's from its size)."""

from __future__ import annotations

import os
from typing import TYPE_CHECKING, cast

import numpy as np

from .._validation import MudrftError, check_memory

if TYPE_CHECKING:
    import trimesh

__all__ = ["BYTES_PER_FACET", "BYTES_PER_FILE_BYTE", "FORMATS", "read_mesh", "weld"]

#: File formats :func:`read_mesh` reads.
FORMATS = (".stl", ".obj", ".ply")
#: Memory reading a binary STL and building its foot take per facet [bytes].
BYTES_PER_FACET = 640
#: The same per byte of any other file [bytes] (a triangle takes at least about 10 bytes).
BYTES_PER_FILE_BYTE = 64

SIMPLIFY = (
    "simplify the mesh (a foot needs a few thousand facets; e.g. trimesh's "
    "simplify_quadric_decimation)"
)
_HINTS = {
    ".stl": " (an ASCII STL is a 'solid' line, facets of exactly 3 'vertex' lines, and an "
    "'endsolid' line)",
    ".ply": " (a PLY mesh needs an element 'vertex' with the properties x, y and z, and an "
    "element 'face' with the list property vertex_indices)",
    ".obj": "",
}


def _stl_facets(path: str, size: int) -> int | None:
    """The facet count of a binary STL, None for an ASCII one; an error for a file that is
    neither, or an ASCII STL cut short."""
    with open(path, "rb") as fh:
        head = fh.read(84)
        fh.seek(max(0, size - 256))
        tail = fh.read().strip().splitlines()
    if len(head) == 84:
        count = int(np.frombuffer(head, "<u4", 1, 80)[0])
        if size == 84 + 50 * count:
            return count
    if not head.lstrip().lower().startswith(b"solid"):
        raise MudrftError(
            f"the mesh file {path!r} is neither a binary STL (its size, {size} bytes, does not "
            "match the facet count in its header) nor an ASCII STL (which begins 'solid')"
        )
    last = tail[-1].strip() if tail else b""
    if not last.lower().startswith(b"endsolid"):
        raise MudrftError(
            f"the mesh file {path!r} looks truncated: an ASCII STL ends with an 'endsolid' "
            f"line, and its last line is {last.decode('ascii', 'replace')[:40]!r}"
        )
    return None


def weld(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The distinct rows of ``points`` (n, 3), sorted, and each row's index among them
    (faster than ``numpy.unique(points, axis=0)``, and -0.0 equals 0.0)."""
    order = np.lexsort(points.T[::-1])
    ordered = points[order]
    new = np.empty(len(ordered), dtype=bool)
    new[:1] = True
    np.any(ordered[1:] != ordered[:-1], axis=1, out=new[1:])
    inverse = np.empty(len(ordered), dtype=np.intp)
    inverse[order] = np.cumsum(new) - 1
    return ordered[new], inverse


def read_mesh(path: str) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (n, 3) [the file's unit] and faces (m, 3) of the mesh file ``path``; errors
    name the file."""
    ext = os.path.splitext(path)[1].lower()
    try:
        size = os.path.getsize(path)
        facets = _stl_facets(path, size) if ext == ".stl" else None
    except OSError as exc:
        raise MudrftError(f"could not read the mesh file {path!r}: {exc.strerror}") from exc
    if facets is not None:
        what, nbytes = f"reading the STL file {path!r} ({facets} facets)", facets * BYTES_PER_FACET
    else:
        what, nbytes = f"reading the mesh file {path!r} ({size} bytes)", size * BYTES_PER_FILE_BYTE
    check_memory(what, nbytes, hint=SIMPLIFY)
    import trimesh  # heavy (0.5 s): imported when a file is read

    try:
        if facets is not None:  # trimesh's reader alone: a Trimesh would triple the memory
            with open(path, "rb") as fh:
                arrays = trimesh.exchange.stl.load_stl(fh)
            v = arrays.get("vertices", np.zeros((0, 3)))  # none in a file of 0 facets
            f = arrays.get("faces", np.zeros((0, 3), dtype=int))
        else:  # force="mesh": one Trimesh (a scene is concatenated); process=False: as written
            mesh = cast("trimesh.Trimesh", trimesh.load(path, force="mesh", process=False))
            v, f = np.asarray(mesh.vertices), np.asarray(mesh.faces)
    except Exception as exc:  # trimesh raises many exception types on bad files
        why = f"{type(exc).__name__}: {exc}"
        if isinstance(exc, KeyError) and exc.args:  # a property looked up by name
            why = f"it lacks the property or element {exc.args[0]!r}"
        raise MudrftError(f"could not read the mesh file {path!r}: {why}{_HINTS[ext]}") from exc
    if v.ndim != 2 or v.shape[0] == 0 or f.ndim != 2 or f.shape[0] == 0:
        raise MudrftError(f"the mesh file {path!r} contains no triangles{_HINTS[ext]}")
    if not np.all(np.isfinite(v)):
        i = int(np.argmax(~np.isfinite(v).all(axis=1)))
        raise MudrftError(
            f"the mesh file {path!r} has NaN or infinite vertex coordinates (vertex {i}: "
            f"{v[i].tolist()})"
        )
    if ext == ".stl":
        v, inverse = weld(v)
        f = inverse[f]
    return np.asarray(v, dtype=np.float64), f
