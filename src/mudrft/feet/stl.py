"""Dependency-free reader and writer for STL files (ASCII and binary).

Binary STL: an 80-byte header, a little-endian uint32 triangle count, then 50 bytes per
triangle (normal, three vertices as float32, a uint16 attribute). A file is read as binary
when its size is exactly ``84 + 50 * count`` (some binary files start with ``solid`` too);
otherwise as ASCII (``solid``, then per facet ``facet ... vertex x y z`` three times ``...
endfacet``, then ``endsolid``: a file without it is refused as truncated). Stored normals are
ignored: the winding gives the normal.
"""

from __future__ import annotations

import io
import math
import os
import struct
from array import array
from typing import BinaryIO

import numpy as np

from .._typing import ArrayLike
from .._validation import MudrftError, check_finite, check_memory

__all__ = ["facet_bound", "read_stl", "write_stl"]

#: The shortest text an ASCII facet can take [bytes]: a ``facet`` line (6 with its newline)
#: and three ``vertex x y z`` lines of one-digit numbers (13 each); ``outer loop``,
#: ``endloop`` and ``endfacet`` only add to it. A file of ``size`` bytes holds at most
#: ``size // 45 + 1`` facets, which bounds the memory reading it takes before it is parsed.
ASCII_FACET_MIN_BYTES = 45

#: Memory reading an STL file takes per facet [bytes] (measured: 131 for a binary file, its
#: 50-byte records and the float64 triangles; 75 for an ASCII one, parsed line by line).
READ_BYTES_PER_FACET = 144

_BINARY_DTYPE = np.dtype([("normal", "<f4", (3,)), ("v", "<f4", (3, 3)), ("attr", "<u2")])


def read_stl(path: str | os.PathLike[str]) -> np.ndarray:
    """Read an STL file into a triangle array.

    The file's size bounds its facet count (:func:`facet_bound`); the memory the reading takes
    is checked against :func:`mudrft._validation.memory_limit` before the file is parsed.

    Parameters
    ----------
    path : str or path-like
        STL file (ASCII or binary), in the file's own length unit.

    Returns
    -------
    ndarray, shape (m, 3, 3)
        Triangle vertices (float64).

    Raises
    ------
    MudrftError
        If the file cannot be opened, is truncated or malformed, holds no triangle, or would
        need more memory than the limit.
    """
    p = os.fspath(path)
    count, binary = _facet_bound(p)
    check_memory(
        f"reading the STL file {p!r} ({'' if binary else 'up to '}{count} facets)",
        count * READ_BYTES_PER_FACET,
        hint="simplify the mesh (a foot needs a few thousand facets)",
    )
    try:
        with open(p, "rb") as fh:
            if binary:
                if count == 0:
                    raise MudrftError(f"the STL file {p!r} contains no triangles")
                rec = np.fromfile(fh, dtype=_BINARY_DTYPE, count=count, offset=84)
                return _finite(rec["v"].astype(np.float64), p)
            return _read_ascii(fh, p)
    except OSError as exc:
        raise MudrftError(f"could not read the STL file {p!r}: {exc.strerror or exc}") from exc


def facet_bound(path: str | os.PathLike[str]) -> int:
    """The most facets the STL file at ``path`` can hold, from its size alone.

    Exact for a binary file (its header's count); for an ASCII file the size over
    :data:`ASCII_FACET_MIN_BYTES`, the shortest text a facet can take.
    """
    return _facet_bound(os.fspath(path))[0]


def _facet_bound(path: str) -> tuple[int, bool]:
    """``(facets, binary)``: the facet count (exact if binary, an upper bound if ASCII)."""
    try:
        with open(path, "rb") as fh:
            head = fh.read(84)
            size = os.fstat(fh.fileno()).st_size
    except OSError as exc:
        raise MudrftError(f"could not read the STL file {path!r}: {exc.strerror or exc}") from exc
    if len(head) == 84:
        (count,) = struct.unpack_from("<I", head, 80)
        if size == 84 + 50 * count:
            return int(count), True
    return size // ASCII_FACET_MIN_BYTES + 1, False


def _finite(tri: np.ndarray, path: str) -> np.ndarray:
    if not np.all(np.isfinite(tri)):
        raise MudrftError(f"the STL file {path!r} has NaN or infinite vertex coordinates")
    return tri


def _read_ascii(fh: BinaryIO, path: str) -> np.ndarray:
    """Parse ``solid / facet / vertex x y z (three) / endfacet / endsolid`` line by line into
    a float array, so that memory stays near the triangles' own 72 bytes a facet.

    Each ``facet`` line starts a facet, which must hold exactly three ``vertex`` lines; the
    last solid must end with ``endsolid`` (a file cut short on a facet boundary has none).
    Several solids in one file are read as one mesh.
    """
    text = io.TextIOWrapper(fh, encoding="ascii", newline=None)
    coords = array("d")
    facet = nvert = lineno = loose = 0  # facets so far, vertices in the current one, line,
    started = open_solid = in_facet = False  # first line of a vertex outside any facet
    try:
        for lineno, line in enumerate(text, start=1):
            parts = line.split()
            if not parts:
                continue
            key = parts[0].lower()
            if not started and not key.startswith("solid"):
                raise MudrftError(
                    f"the STL file {path!r} is not an STL file (no 'solid' header, bad binary size)"
                )
            started = True
            if key == "vertex":
                coords.extend(_vertex(parts, path, lineno))
                if in_facet:
                    nvert += 1
                else:
                    loose = loose or lineno  # reported once every vertex is checked
            elif key in ("facet", "endfacet", "endsolid"):
                if in_facet and nvert != 3:
                    raise _vertex_count(path, facet, nvert, lineno)
                in_facet = key == "facet"
                if key == "facet":
                    if not open_solid:
                        raise MudrftError(
                            f"the STL file {path!r} has a facet after 'endsolid' (line {lineno})"
                        )
                    facet, nvert = facet + 1, 0
                elif key == "endsolid":
                    open_solid = False
            elif key.startswith("solid"):  # "solid name" (or "solidname")
                open_solid = True
    except UnicodeDecodeError as exc:
        raise MudrftError(
            f"the STL file {path!r} is neither a valid binary STL (size does not match the "
            "triangle count) nor ASCII text"
        ) from exc
    finally:
        text.detach()  # leave the binary file to its owner
    if in_facet and nvert > 3:
        raise _vertex_count(path, facet, nvert, lineno)
    if open_solid:
        where = f"after facet {facet}"
        if in_facet and nvert < 3:
            where = (
                f"inside facet {facet}, after {nvert} of its 3 vertices (a vertex count not a "
                "multiple of 3)"
            )
        raise MudrftError(
            f"the STL file {path!r} looks truncated: it ends {where}, with no 'endsolid' line"
        )
    if loose:
        raise MudrftError(
            f"the STL file {path!r} has a vertex outside any facet (line {loose}); each "
            "'facet' line starts a facet of 3 'vertex' lines"
        )
    if not coords:
        raise MudrftError(f"the STL file {path!r} contains no triangles")
    return np.frombuffer(coords, dtype=np.float64).reshape(-1, 3, 3)


def _vertex(parts: list[str], path: str, lineno: int) -> tuple[float, float, float]:
    """The coordinates of a ``vertex x y z`` line, finite, or an error naming the line."""
    if len(parts) != 4:
        raise MudrftError(
            f"the STL file {path!r} has a malformed vertex line (line {lineno}): "
            f"{' '.join(parts)!r}"
        )
    try:
        x, y, z = (float(c) for c in parts[1:])
    except ValueError as exc:
        raise MudrftError(
            f"the STL file {path!r} has a non-numeric vertex coordinate (line {lineno}): {exc}"
        ) from exc
    if not (math.isfinite(x) and math.isfinite(y) and math.isfinite(z)):
        raise MudrftError(
            f"the STL file {path!r} has NaN or infinite vertex coordinates (line {lineno})"
        )
    return x, y, z


def _vertex_count(path: str, facet: int, nvert: int, lineno: int) -> MudrftError:
    return MudrftError(
        f"the STL file {path!r} has {nvert} vertices in facet {facet} (ending on line "
        f"{lineno}); a facet must have exactly 3 (triangulate quads and polygons first)"
    )


def write_stl(
    path: str | os.PathLike[str],
    triangles: ArrayLike,
    *,
    binary: bool = True,
    overwrite: bool = False,
) -> None:
    """Write triangles to an STL file.

    Parameters
    ----------
    path : str or path-like
        Output file; an existing file is kept unless ``overwrite=True``.
    triangles : array_like, shape (m, 3, 3)
        Triangle vertices (in the unit the file should carry, usually m or mm).
    binary : bool, optional
        Binary (float32, compact) or ASCII (full double precision in text).
    overwrite : bool, optional
        Replace an existing file.
    """
    tri = check_finite("triangles", triangles)
    if tri.ndim != 3 or tri.shape[1:] != (3, 3) or tri.shape[0] == 0:
        raise MudrftError(f"triangles must have shape (m, 3, 3) with m >= 1, got shape {tri.shape}")
    p = os.fspath(path)
    if os.path.exists(p) and not overwrite:
        raise MudrftError(f"path {p!r} exists; pass overwrite=True to replace it")
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    ln = np.linalg.norm(n, axis=1, keepdims=True)
    n = np.divide(n, ln, out=np.zeros_like(n), where=ln > 0)
    if binary:
        rec = np.zeros(tri.shape[0], dtype=_BINARY_DTYPE)
        rec["normal"], rec["v"] = n, tri
        header = b"mudrft binary STL".ljust(80, b" ")
        with open(p, "wb") as fh:
            fh.write(header + struct.pack("<I", tri.shape[0]) + rec.tobytes())
        return
    lines = ["solid mudrft"]
    for t, nn in zip(tri.tolist(), n.tolist(), strict=True):
        lines.append(f"  facet normal {nn[0]!r} {nn[1]!r} {nn[2]!r}")
        lines.append("    outer loop")
        lines.extend(f"      vertex {x!r} {y!r} {z!r}" for x, y, z in t)
        lines.append("    endloop")
        lines.append("  endfacet")
    lines.append("endsolid mudrft")
    with open(p, "w", encoding="ascii") as fh:
        fh.write("\n".join(lines) + "\n")
