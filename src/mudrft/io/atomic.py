"""Writing files atomically: staged in a private directory beside the target, then moved
into place; a failure leaves nothing, an existing file is replaced only with
``overwrite=True``, and what a killed run staged is removed by the next run."""

from __future__ import annotations

import json
import math
import os
import re
import shutil
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from .._progress import logger
from .._validation import MudrftError

Content = bytes | bytearray | memoryview | str | Callable[[Path], object]

#: Staging names: this version's (``.mudrft-PID-XXXXXXXX.tmp``), and those of mudrft 0.1.
_STAGED = re.compile(r"\.mudrft-(?P<pid>\d+)-[a-z0-9_]+\.tmp")
_LEGACY = re.compile(r"\.mudrft-[a-z0-9_]{8}\.tmp|\..+\.[0-9a-f]{12}\.tmp(\.[A-Za-z0-9]+)?")
#: When this process started [s since the epoch]: newer staging may belong to a live run.
_STARTED = time.time()


def regular_target(path: str | os.PathLike[str], option: str = "path") -> Path:
    """The file that writing ``path`` replaces (a symbolic link's target); refuses a pipe,
    a device or a socket. ``option`` names the output in the message (``"--out"``)."""
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


def _alive(pid: int) -> bool:
    """Whether process ``pid`` runs on this machine (unknown on Windows: taken as yes)."""
    if os.name == "nt" or pid == os.getpid():
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except OSError:  # another user's process
        return True
    return True


def remove_stale_staging(directory: str | os.PathLike[str]) -> list[Path]:
    """Remove the staging of mudrft runs in ``directory`` that are older than this
    process and whose process no longer runs; return what was removed."""
    removed: list[Path] = []
    try:
        entries = list(os.scandir(directory))
    except OSError:
        return removed
    for entry in entries:
        staged = _STAGED.fullmatch(entry.name)
        if not (staged or _LEGACY.fullmatch(entry.name)):
            continue
        try:
            if entry.stat(follow_symlinks=False).st_mtime >= _STARTED:
                continue
            if staged and _alive(int(staged["pid"])):
                continue
            if entry.is_dir(follow_symlinks=False):
                shutil.rmtree(entry.path)
            else:
                os.unlink(entry.path)
        except OSError:  # gone meanwhile, or not ours to remove
            continue
        removed.append(Path(entry.path))
    if removed:
        logger.info(
            "removed %d staging file(s) left by a killed run: %s",
            len(removed), ", ".join(p.name for p in removed),
        )  # fmt: skip
    return removed


def staging_directory(directory: str | os.PathLike[str]) -> Path:
    """A new private directory in ``directory`` to stage outputs in (stale ones of killed
    runs removed first); :class:`OSError` if ``directory`` is not writable."""
    remove_stale_staging(directory)
    prefix = f".mudrft-{os.getpid()}-"
    return Path(tempfile.mkdtemp(prefix=prefix, suffix=".tmp", dir=directory))


def move_into_place(staged: Path, target: Path, *, overwrite: bool, option: str) -> None:
    """Move ``staged`` to ``target`` in one step; without ``overwrite`` only if ``target``
    does not exist (else :class:`MudrftError`)."""
    if overwrite:
        os.replace(staged, target)
        return
    try:
        os.link(staged, target)
    except OSError as exc:  # FileExistsError, or no hard links here: check, then move
        if isinstance(exc, FileExistsError) or os.path.lexists(target):
            raise MudrftError(f"{target}: file exists; pass {option} to replace it") from None
        os.replace(staged, target)


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
        The data (a str is written as UTF-8), or a function that writes the path it is
        given (e.g. with h5py).
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
        written; nothing is left behind.

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
    if not overwrite and os.path.lexists(p):  # early, before any work
        raise MudrftError(f"{p}: file exists; pass {option} to replace it")
    stage = None
    try:
        stage = staging_directory(p.parent)
        staged = stage / p.name
        if callable(content):
            content(staged)
        else:
            with open(staged, "wb") as fh:
                fh.write(content.encode("utf-8") if isinstance(content, str) else content)
                fh.flush()
                os.fsync(fh.fileno())
        move_into_place(staged, p, overwrite=overwrite, option=option)
    except OSError as exc:
        raise MudrftError(f"{p}: cannot be written ({exc.strerror or exc})") from exc
    finally:
        if stage is not None:
            shutil.rmtree(stage, ignore_errors=True)
    return p


def finite_or_none(obj: Any) -> Any:
    """``obj`` with every NaN or infinite number (nested in dicts, lists) replaced by None."""
    if isinstance(obj, dict):
        return {k: finite_or_none(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [finite_or_none(v) for v in obj]
    if obj is None or isinstance(obj, (int, str)):  # bool is an int
        return obj
    try:
        value = float(obj)  # also numpy numbers
    except (TypeError, ValueError):
        return obj  # json.dumps names what it cannot write
    return value if math.isfinite(value) else None


def json_text(obj: Any, *, indent: int | None = 2) -> str:
    r"""Standard JSON for ``obj`` ending in a newline, every NaN or infinite number written
    as ``null`` (:func:`finite_or_none`); ``indent`` as :func:`json.dumps`.

    Examples
    --------
    >>> json_text({"energy [J]": float("nan"), "steps": 0}, indent=None)
    '{"energy [J]": null, "steps": 0}\n'
    """
    return json.dumps(finite_or_none(obj), indent=indent, allow_nan=False) + "\n"
