r"""How many triangles an OBJ or PLY file holds, found before it is parsed (decision D102).

:meth:`mudrft.feet.mesh.MeshFoot.from_file` reads OBJ and PLY through the optional
``trimesh``, which parses a whole file at once. So that the memory this takes is checked
before it is allocated, as for STL (:func:`mudrft.feet.stl.facet_bound`), these functions
count the triangles without building any array:

* **OBJ**: the file is read line by line; a face line ``f a b c ...`` of ``k`` vertices
  becomes ``k - 2`` triangles (a fan, as trimesh triangulates it).
* **PLY**: the header gives the vertex and face counts. In an ASCII file the face lines are
  read like an OBJ's; in a binary file the bytes after the vertices bound the number of
  vertex indices, ``(bytes - faces * count size) / index size``, exact for a file of
  triangles (the usual layout) and an upper bound otherwise.

A file these functions cannot make sense of gets the bound of its size alone (every two bytes
a triangle); trimesh then reports what is wrong with it.
"""

from __future__ import annotations

import os

__all__ = ["BYTES_PER_FILE_BYTE", "reading_memory", "triangle_bound"]

#: Memory trimesh takes per byte of a text mesh file while parsing it [bytes] (measured
#: about 6 for OBJ, 15 for ASCII PLY, 11 for binary PLY; decision D102).
BYTES_PER_FILE_BYTE = 16

#: Largest header a PLY file may have before it is taken as malformed [bytes].
_PLY_HEADER_MAX = 1 << 20

_PLY_SIZES = {
    "char": 1, "int8": 1, "uchar": 1, "uint8": 1, "short": 2, "int16": 2, "ushort": 2,
    "uint16": 2, "int": 4, "int32": 4, "uint": 4, "uint32": 4, "float": 4, "float32": 4,
    "double": 8, "float64": 8,
}  # fmt: skip


def triangle_bound(path: str, ext: str) -> int:
    """The most triangles the OBJ or PLY file at ``path`` holds (see the module docstring).

    Parameters
    ----------
    path : str
        The mesh file.
    ext : str
        Its extension, ``".obj"`` or ``".ply"`` (lower case).

    Returns
    -------
    int
        An upper bound on the triangles (exact for OBJ, ASCII PLY and binary PLY of
        triangles).
    """
    size = os.path.getsize(path)
    with open(path, "rb") as fh:
        count = _obj_triangles(fh) if ext == ".obj" else _ply_triangles(fh, size)
    return size // 2 + 1 if count is None else count


def reading_memory(path: str, ext: str, bytes_per_triangle: float) -> tuple[float, int]:
    """``(bytes, triangles)``: the memory reading the file and building its foot takes.

    The parse (:data:`BYTES_PER_FILE_BYTE` times the file's size) plus the foot's
    ``bytes_per_triangle`` for each triangle of :func:`triangle_bound`.
    """
    tri = triangle_bound(path, ext)
    return os.path.getsize(path) * BYTES_PER_FILE_BYTE + tri * bytes_per_triangle, tri


def _obj_triangles(fh) -> int:  # type: ignore[no-untyped-def]
    tri = 0
    for line in fh:
        if line[:2] in (b"f ", b"f\t"):
            tri += max(len(line.split()) - 3, 0)
    return tri


def _ply_triangles(fh, size: int) -> int | None:  # type: ignore[no-untyped-def]
    if fh.readline(16).strip() != b"ply":
        return None
    fmt = None
    elements: list[list] = []  # [name, count, [property, ...]]
    while fh.tell() < _PLY_HEADER_MAX:
        words = fh.readline(4096).split()
        if not words or words[0] in (b"comment", b"obj_info"):
            continue
        if words[0] == b"end_header":
            break
        try:
            if words[0] == b"format":
                fmt = words[1].decode("ascii")
            elif words[0] == b"element":
                elements.append([words[1], int(words[2]), []])
            elif words[0] == b"property":
                elements[-1][2].append([w.decode("ascii") for w in words[1:]])
        except (IndexError, ValueError, UnicodeDecodeError):
            return None
    else:
        return None
    faces = [e for e in elements if e[0] == b"face"]
    if not faces or faces[0][1] < 0:
        return None
    if fmt == "ascii":
        return _ply_ascii_triangles(fh, elements)
    return _ply_binary_triangles(elements, size - fh.tell())


def _ply_ascii_triangles(fh, elements: list[list]) -> int | None:  # type: ignore[no-untyped-def]
    tri = 0
    for name, count, _ in elements:
        for _ in range(count):
            line = fh.readline()
            if not line:
                return tri if name == b"face" else None
            if name == b"face":
                words = line.split()
                try:
                    tri += max(int(words[0]) - 2, 0) if words else 0
                except ValueError:
                    return None
        if name == b"face":
            return tri
    return None


def _ply_binary_triangles(elements: list[list], body: int) -> int | None:
    before = 0  # bytes of the elements before the faces, where their records are fixed
    for name, count, props in elements:
        if name == b"face":
            break
        if any(p[0] == "list" for p in props):
            before = 0  # a list in another element: its bytes are unknown, take none
            break
        before += count * sum(_PLY_SIZES.get(p[0], 1) for p in props)
    face = next(e for e in elements if e[0] == b"face")
    lists = [p for p in face[2] if p[0] == "list" and len(p) >= 3]
    if not lists:
        return None
    count_size, index_size = _PLY_SIZES.get(lists[0][1], 1), _PLY_SIZES.get(lists[0][2], 1)
    indices = max(body - before - face[1] * count_size, 0) // index_size
    return max(indices - 2 * face[1], face[1])
