"""Dependency-free reader and writer for STL files (ASCII and binary).

Binary STL: an 80-byte header, a little-endian uint32 triangle count, then 50 bytes per
triangle (normal, three vertices as float32, a uint16 attribute). A file is read as binary
when its size is exactly ``84 + 50 * count`` (some binary files start with ``solid`` too);
otherwise as ASCII (``facet ... vertex x y z ... endfacet``). Stored normals are ignored:
the winding gives the normal.
"""

from __future__ import annotations

import os
import struct
from typing import Any

import numpy as np

from .._validation import MudrftError, check_finite

__all__ = ["read_stl", "write_stl"]

_BINARY_DTYPE = np.dtype([("normal", "<f4", (3,)), ("v", "<f4", (3, 3)), ("attr", "<u2")])


def read_stl(path: str | os.PathLike[str]) -> np.ndarray:
    """Read an STL file into a triangle array.

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
        If the file cannot be opened, is truncated or malformed, or holds no triangle.
    """
    p = os.fspath(path)
    try:
        with open(p, "rb") as fh:
            data = fh.read()
    except OSError as exc:
        raise MudrftError(f"could not read the STL file {p!r}: {exc.strerror or exc}") from exc
    if len(data) >= 84:
        (count,) = struct.unpack_from("<I", data, 80)
        if len(data) == 84 + 50 * count:
            if count == 0:
                raise MudrftError(f"the STL file {p!r} contains no triangles")
            rec = np.frombuffer(data, dtype=_BINARY_DTYPE, count=count, offset=84)
            return _finite(rec["v"].astype(np.float64), p)
    return _read_ascii(data, p)


def _finite(tri: np.ndarray, path: str) -> np.ndarray:
    if not np.all(np.isfinite(tri)):
        raise MudrftError(f"the STL file {path!r} has NaN or infinite vertex coordinates")
    return tri


def _read_ascii(data: bytes, path: str) -> np.ndarray:
    try:
        text = data.decode("ascii")
    except UnicodeDecodeError as exc:
        raise MudrftError(
            f"the STL file {path!r} is neither a valid binary STL (size does not match the "
            "triangle count) nor ASCII text"
        ) from exc
    if not text.lstrip().lower().startswith("solid"):
        raise MudrftError(
            f"the STL file {path!r} is not an STL file (no 'solid' header, bad binary size)"
        )
    coords: list[str] = []
    for line in text.splitlines():
        parts = line.split()
        if parts and parts[0].lower() == "vertex":
            if len(parts) != 4:
                raise MudrftError(
                    f"the STL file {path!r} has a malformed vertex line: {line.strip()!r}"
                )
            coords.extend(parts[1:])
    if not coords:
        raise MudrftError(f"the STL file {path!r} contains no triangles")
    try:
        arr = np.array([float(c) for c in coords])
    except ValueError as exc:
        raise MudrftError(
            f"the STL file {path!r} has a non-numeric vertex coordinate: {exc}"
        ) from exc
    if arr.size % 9:
        raise MudrftError(
            f"the STL file {path!r} has {arr.size // 3} vertices, "
            "not a multiple of 3 (truncated facet?)"
        )
    return _finite(arr.reshape(-1, 3, 3), path)


def write_stl(
    path: str | os.PathLike[str], triangles: Any, *, binary: bool = True, overwrite: bool = False
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
