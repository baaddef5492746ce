"""Atomic, overwrite-safe writing of files: the one way mudrft writes a file it produces.

:func:`atomic_write` writes to a temporary file in the target's directory, then moves it
into place in one step. A reader never sees a half-written file, a failure leaves
nothing behind (no temporary file, no truncated target), and an existing file is never
replaced unless the caller passes ``overwrite=True``, even if it appears while the data
are being written.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import uuid
from collections.abc import Callable
from pathlib import Path
from typing import Any

from .._validation import MudrftError

__all__ = ["atomic_write", "json_text", "regular_target"]

Content = bytes | bytearray | memoryview | str | Callable[[Path], object]


def _exists_error(p: Path, option: str) -> MudrftError:
    return MudrftError(f"{p}: file exists; pass {option} to replace it")


def regular_target(path: str | os.PathLike[str], option: str = "path") -> Path:
    """The file that writing ``path`` replaces: a symbolic link's target (the link stays a
    link), ``path`` itself otherwise.

    Refuses a pipe, a device or a socket: an atomic write replaces the name by a regular
    file, which would turn ``/dev/null`` into a file (as root, destroying the device) and a
    named pipe into a file its reader never sees.

    Parameters
    ----------
    path : str or path-like
        The output's name.
    option : str
        How the caller's API names the output, for the message (``"--out"``, ``"path"``).
    """
    p = Path(os.fspath(path))
    if p.is_symlink():
        p = Path(os.path.realpath(p))
        if p.is_symlink():  # realpath stops where links loop
            raise MudrftError(
                f"{option} {str(path)!r} is a symbolic link that loops (through {str(p)!r}); "
                "name a file"
            )
    if p.exists() and not (p.is_file() or p.is_dir()):
        raise MudrftError(
            f"{option} {str(path)!r} is not a regular file (a pipe, a device or a socket); "
            "mudrft writes its outputs atomically, as new files: name a file"
        )
    return p


def _temporary(p: Path) -> tuple[Path, int]:
    """A new empty file next to ``p`` (same directory, so the final move is atomic), opened
    for writing; created with the default permissions (the umask applies)."""
    for _ in range(100):
        tmp = p.with_name(f".{p.name}.{uuid.uuid4().hex[:12]}.tmp")
        try:
            return tmp, os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o666)
        except FileExistsError:  # pragma: no cover - a 48-bit random name collided
            continue
    raise FileExistsError(f"no free temporary name next to {p}")  # pragma: no cover


def _fill(tmp: Path, fd: int, content: Content) -> None:
    """Write ``content`` to the temporary file (flushed to disk for bytes and text)."""
    if callable(content):
        os.close(fd)
        content(tmp)
        return
    data = content.encode("utf-8") if isinstance(content, str) else bytes(content)
    with os.fdopen(fd, "wb") as fh:
        fh.write(data)
        fh.flush()
        os.fsync(fh.fileno())


def _move_into_place(tmp: Path, p: Path, *, overwrite: bool, option: str) -> None:
    """Move the finished temporary file to ``p``; without ``overwrite`` only if ``p`` does
    not exist at that moment (a hard link fails on an existing name, atomically)."""
    if overwrite:
        os.replace(tmp, p)
        return
    try:
        os.link(tmp, p)
    except FileExistsError:
        raise _exists_error(p, option) from None
    except OSError:  # hard links not supported here: check, then move
        if os.path.lexists(p):
            raise _exists_error(p, option) from None
        os.replace(tmp, p)


def atomic_write(
    path: str | os.PathLike[str],
    content: Content,
    *,
    overwrite: bool = False,
    option: str = "overwrite=True",
) -> Path:
    """Write a file atomically; never replace an existing file unless ``overwrite=True``.

    Parameters
    ----------
    path : str or path-like
        The file to write.
    content : bytes, str or callable
        The data (a str is written as UTF-8), or a function that writes the file whose
        path it is given (e.g. with h5py); it must write that path, not another.
    overwrite : bool, keyword-only
        Replace ``path`` if it exists (default: refuse).
    option : str, keyword-only
        How the caller's API spells the permission to replace, named in the error
        (``"overwrite=True"``, ``"--force"``, ...).

    Returns
    -------
    Path
        The file written.

    Raises
    ------
    MudrftError
        If ``path`` exists and ``overwrite`` is false, names a directory, or cannot be
        written. Nothing is left behind: neither a temporary file nor a partial target.

    Examples
    --------
    >>> import tempfile, os
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = atomic_write(os.path.join(d, "a.txt"), "first\\n")
    ...     try:
    ...         atomic_write(p, "second\\n")
    ...     except MudrftError as exc:
    ...         print("refused:", "file exists" in str(exc))
    ...     print(p.read_text().strip(), sorted(os.listdir(d)))
    refused: True
    first ['a.txt']
    """
    p = regular_target(path)
    if not (callable(content) or isinstance(content, (bytes, bytearray, memoryview, str))):
        raise MudrftError(
            f"content must be bytes, str or a callable that writes a path, got "
            f"{type(content).__name__}"
        )
    if p.is_dir():
        raise MudrftError(f"{p}: is a directory, expected a file name")
    if not overwrite and os.path.lexists(p):
        raise _exists_error(p, option)  # early, before any work
    tmp: Path | None = None
    try:
        tmp, fd = _temporary(p)
        _fill(tmp, fd, content)
        _move_into_place(tmp, p, overwrite=overwrite, option=option)
    except OSError as exc:
        raise MudrftError(f"{p}: cannot be written ({exc.strerror or exc})") from exc
    finally:
        if tmp is not None:
            with contextlib.suppress(OSError):  # gone already once moved into place
                os.unlink(tmp)
    return p


def _finite_or_none(obj: Any) -> Any:
    if isinstance(obj, dict):
        return {k: _finite_or_none(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_finite_or_none(v) for v in obj]
    if isinstance(obj, bool) or obj is None or isinstance(obj, (int, str)):
        return obj
    try:
        value = float(obj)  # also numpy numbers
    except (TypeError, ValueError):
        return obj  # json.dumps names what it cannot write
    return value if math.isfinite(value) else None


def json_text(obj: Any, *, indent: int | None = 2) -> str:
    r"""Standard JSON for ``obj``, every NaN or infinite number written as ``null``.

    Python's :func:`json.dumps` writes ``NaN`` and ``Infinity`` by default, which is not
    JSON: strict parsers (JavaScript's ``JSON.parse``, ``json.loads`` with
    ``parse_constant``) reject the file. mudrft's summaries mark an undefined number (a
    metric of a walk without a complete step) as NaN in Python and ``null`` on disk.

    Parameters
    ----------
    obj : dict, list or number
        Nested dicts and lists of numbers (numpy numbers too), strings, booleans and None.
    indent : int or None, keyword-only
        As :func:`json.dumps`.

    Returns
    -------
    str
        The JSON text, ending in a newline.

    Examples
    --------
    >>> json_text({"energy [J]": float("nan"), "steps": 0}, indent=None)
    '{"energy [J]": null, "steps": 0}\n'
    """
    return json.dumps(_finite_or_none(obj), indent=indent, allow_nan=False) + "\n"
