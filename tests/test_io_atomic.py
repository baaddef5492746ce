"""Writing files: every writer is atomic (a failure leaves nothing behind) and never
replaces an existing file without the caller's permission."""

from __future__ import annotations

import os
import stat
from pathlib import Path

import numpy as np
import pytest

from mudrft._validation import MudrftError
from mudrft.io import IntrusionDataset, Trial, atomic_write, save_intrusion_csv
from mudrft.io import atomic as atomic_module


def _dataset(n: int = 5) -> IntrusionDataset:
    t = np.linspace(0.0, 1.0, n)
    return IntrusionDataset((Trial(t, 0.02 * t, 1e3 * t, name="a"),))


def _fit_to_json(ds: IntrusionDataset, p: Path, **kw: bool) -> Path:
    """A FitResult (made from a minimal dict, no fit needed) saved as JSON."""
    import mudrft
    from mudrft.calibration import FitResult
    from mudrft.calibration._problem import FIT_PARAMETERS

    data = {
        "parameters": mudrft.paper_parameters(0.25).as_dict(),
        "free": [],
        "standard_error": dict.fromkeys(FIT_PARAMETERS),
        "relative_standard_error": dict.fromkeys(FIT_PARAMETERS),
        "confidence_interval": {k: [None, None] for k in FIT_PARAMETERS},
        "confidence_level": 0.95,
        "correlation": {"parameters": [], "matrix": []},
        "identifiability": dict.fromkeys(FIT_PARAMETERS, "fixed"),
        "relative_rmse": 0.0,
        "trial_relative_rmse": [],
        "noise": 0.0,
        "status": "converged",
        "direction": "vertical",
    }
    return FitResult.from_dict(data).to_json(p, **kw)


def _hdf5(ds: IntrusionDataset, p: Path, **kw: bool) -> Path:
    pytest.importorskip("h5py")
    from mudrft.io import save_intrusion_hdf5

    return save_intrusion_hdf5(ds, p, **kw)


#: Every writer of mudrft.io and of the calibration, as (dataset, path, **options) -> Path.
WRITERS = {
    "save_intrusion_csv": lambda ds, p, **kw: save_intrusion_csv(ds, p, **kw),
    "IntrusionDataset.to_csv": lambda ds, p, **kw: ds.to_csv(p, **kw),
    "save_intrusion_hdf5": _hdf5,
    "FitResult.to_json": _fit_to_json,
}


def _listing(d: Path) -> list[str]:
    return sorted(os.listdir(d))


@pytest.mark.parametrize("writer", sorted(WRITERS))
def test_existing_file_is_never_overwritten_without_the_flag(tmp_path, writer):
    write = WRITERS[writer]
    p = tmp_path / "out.dat"
    p.write_bytes(b"precious user data\n")
    before = (p.read_bytes(), os.stat(p).st_mtime_ns)
    with pytest.raises(MudrftError, match=r"exists.*overwrite=True"):
        write(_dataset(), p)
    assert (p.read_bytes(), os.stat(p).st_mtime_ns) == before
    assert _listing(tmp_path) == ["out.dat"]  # no temporary file left
    assert write(_dataset(), p, overwrite=True) == p
    assert p.read_bytes() != b"precious user data\n"
    assert _listing(tmp_path) == ["out.dat"]


@pytest.mark.parametrize("writer", sorted(WRITERS))
def test_new_file_is_written_with_nothing_else(tmp_path, writer):
    p = WRITERS[writer](_dataset(), tmp_path / "new.dat")
    assert p.stat().st_size > 0
    assert _listing(tmp_path) == ["new.dat"]


def test_failed_write_leaves_no_file(tmp_path):
    def half_then_fail(tmp: Path) -> None:
        tmp.write_bytes(b"half a file")
        raise RuntimeError("disk on fire")

    with pytest.raises(RuntimeError, match="disk on fire"):
        atomic_write(tmp_path / "x.csv", half_then_fail)
    assert _listing(tmp_path) == []


def test_failed_overwrite_keeps_the_old_file(tmp_path):
    p = tmp_path / "x.csv"
    p.write_text("old\n")

    def fail(tmp: Path) -> None:
        tmp.write_text("new but broken")
        raise OSError(28, "No space left on device")

    with pytest.raises(MudrftError, match=r"x\.csv: cannot be written \(No space left"):
        atomic_write(p, fail, overwrite=True)
    assert p.read_text() == "old\n"
    assert _listing(tmp_path) == ["x.csv"]


def test_failed_move_into_place_leaves_nothing(tmp_path, monkeypatch):
    def no_replace(src: object, dst: object) -> None:
        raise PermissionError(13, "Permission denied")

    monkeypatch.setattr(atomic_module.os, "replace", no_replace)
    p = tmp_path / "x.csv"
    p.write_text("old\n")
    with pytest.raises(MudrftError, match="cannot be written"):
        save_intrusion_csv(_dataset(), p, overwrite=True)
    assert p.read_text() == "old\n"
    assert _listing(tmp_path) == ["x.csv"]


def test_write_into_a_missing_directory_fails_cleanly(tmp_path):
    with pytest.raises(MudrftError, match="cannot be written"):
        save_intrusion_csv(_dataset(), tmp_path / "no" / "such" / "dir.csv")
    assert _listing(tmp_path) == []


def test_data_that_cannot_be_written_leave_no_file(tmp_path):
    t = np.linspace(0.0, 1.0, 4)
    mixed = IntrusionDataset(
        (
            Trial(t, 0.01 * t, t, name="a", characteristic_length=0.05),
            Trial(t, 0.01 * t, t, name="b", characteristic_length=0.04),
        )
    )
    with pytest.raises(MudrftError, match="one characteristic length"):
        save_intrusion_csv(mixed, tmp_path / "m.csv")
    assert _listing(tmp_path) == []


def test_file_that_appears_during_the_write_is_not_overwritten(tmp_path):
    """Another program creates the target while mudrft writes: its file wins, mudrft
    refuses (the final move cannot replace a file without the flag)."""
    p = tmp_path / "race.csv"

    def write_while_someone_else_does(tmp: Path) -> None:
        tmp.write_text("ours\n")
        p.write_text("theirs\n")

    with pytest.raises(MudrftError, match="exists"):
        atomic_write(p, write_while_someone_else_does)
    assert p.read_text() == "theirs\n"
    assert _listing(tmp_path) == ["race.csv"]


def test_directory_and_bad_content_are_refused(tmp_path):
    with pytest.raises(MudrftError, match="is a directory"):
        atomic_write(tmp_path, b"x", overwrite=True)
    with pytest.raises(MudrftError, match="content must be bytes, str or a callable"):
        atomic_write(tmp_path / "a", 3)  # type: ignore[arg-type]
    assert _listing(tmp_path) == []


def test_written_file_has_the_usual_permissions(tmp_path):
    """The temporary file is created like open() would create the target (umask applies),
    not with a temporary file's private mode."""
    ref = tmp_path / "ref"
    ref.write_text("x")
    p = atomic_write(tmp_path / "a.txt", "x")
    assert stat.S_IMODE(p.stat().st_mode) == stat.S_IMODE(ref.stat().st_mode)


def test_text_is_utf8_and_option_is_named(tmp_path):
    p = atomic_write(tmp_path / "u.txt", "σ [Pa]\n")
    assert p.read_bytes() == "σ [Pa]\n".encode()
    with pytest.raises(MudrftError, match="pass --force to replace it"):
        atomic_write(p, "again", option="--force")


def test_json_text_writes_undefined_numbers_as_null():
    """Standard JSON: NaN and infinities (numpy's too) become null, nested anywhere."""
    import json

    from mudrft.io import json_text

    obj = {"a": float("nan"), "b": [1.0, np.inf, np.float64(2.5)], "c": {"d": -np.inf}, "e": True}
    text = json_text(obj)
    back = json.loads(text, parse_constant=lambda c: pytest.fail(f"non-standard JSON: {c}"))
    assert back == {"a": None, "b": [1.0, None, 2.5], "c": {"d": None}, "e": True}
    assert text.endswith("\n")


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="named pipes")
def test_a_pipe_is_refused_even_with_overwrite(tmp_path):
    """An atomic write replaces the name by a file: a named pipe (or, as root, /dev/null)
    became a regular file that its reader never saw."""
    pipe = tmp_path / "pipe.csv"
    os.mkfifo(pipe)
    with pytest.raises(MudrftError, match=r"not a regular file \(a pipe, a device"):
        atomic_write(pipe, "data\n", overwrite=True)
    assert stat.S_ISFIFO(os.lstat(pipe).st_mode) and sorted(os.listdir(tmp_path)) == ["pipe.csv"]


def test_a_symbolic_link_is_written_through(tmp_path):
    """``overwrite=True`` on a link replaces the file it names; the link stays a link."""
    real, link = tmp_path / "real.csv", tmp_path / "link.csv"
    real.write_text("old\n")
    link.symlink_to(real)
    with pytest.raises(MudrftError, match="exists"):
        atomic_write(link, "new\n")
    assert atomic_write(link, "new\n", overwrite=True) == real
    assert link.is_symlink() and real.read_text() == "new\n"
    assert sorted(os.listdir(tmp_path)) == ["link.csv", "real.csv"]


# -- staging left by a killed run (issue 43) ---------------------------------------------
def _dead_pid() -> int:
    import subprocess
    import sys

    proc = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"], text=True,
                          capture_output=True, check=True)  # fmt: skip
    return int(proc.stdout)


def _age(path: Path, seconds: float = 60.0) -> Path:
    old = atomic_module._STARTED - seconds
    os.utime(path, (old, old))
    return path


def test_stale_staging_of_dead_runs_is_removed_and_nothing_else(tmp_path):
    dead, mine = _dead_pid(), os.getpid()
    stale_dir = tmp_path / f".mudrft-{dead}-abcd_123.tmp"
    stale_dir.mkdir()
    (stale_dir / "run.csv").write_text("half")
    (tmp_path / ".mudrft-k2j4_x9a.tmp").mkdir()  # mudrft 0.1's names, without the process
    (tmp_path / ".fit.0123456789ab.tmp.json").write_text("half")
    (tmp_path / ".log.csv.0123456789ab.tmp").write_text("half")
    stale = sorted(tmp_path.iterdir())
    (tmp_path / f".mudrft-{mine}-live1234.tmp").mkdir()  # a run still going (this process)
    (tmp_path / ".mudrft-settings").mkdir()
    (tmp_path / ".fit.json").write_text("{}")
    (tmp_path / "notes.tmp").write_text("")
    kept = sorted(set(tmp_path.iterdir()) - set(stale))
    for p in [*stale, *kept]:
        _age(p)
    (tmp_path / f".mudrft-{dead}-newer123.tmp").mkdir()  # made after this process started
    assert sorted(atomic_module.remove_stale_staging(tmp_path)) == stale
    assert _listing(tmp_path) == sorted([p.name for p in kept] + [f".mudrft-{dead}-newer123.tmp"])
    assert atomic_module.remove_stale_staging(tmp_path / "missing") == []


def test_the_next_write_removes_the_staging_of_a_killed_one(tmp_path):
    stale = tmp_path / f".mudrft-{_dead_pid()}-abcd1234.tmp"
    stale.mkdir()
    (stale / "out.csv").write_text("half")
    _age(stale)
    save_intrusion_csv(_dataset(), tmp_path / "out.csv")
    assert _listing(tmp_path) == ["out.csv"]


def test_a_command_killed_outright_is_cleaned_up_by_the_next_run(tmp_path):
    """``kill -9`` mid-run leaves the staging directory; the next run into the same
    directory (a new process) removes it."""
    import signal
    import subprocess
    import sys

    if os.name == "nt":
        pytest.skip("POSIX signals")
    import mudrft

    src = str(Path(mudrft.__file__).resolve().parents[1])
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([src, os.environ.get("PYTHONPATH", "")])}
    out = tmp_path / "run.csv"
    killed = (
        "import os, signal, sys; from mudrft.cli._common import Outputs; "
        "Outputs(force=False).file('--out', sys.argv[1]).write_text('half'); "
        "os.kill(os.getpid(), signal.SIGKILL)"
    )
    proc = subprocess.run([sys.executable, "-c", killed, str(out)], env=env, check=False)
    assert proc.returncode == -signal.SIGKILL
    (left,) = os.listdir(tmp_path)
    assert left.startswith(".mudrft-")
    command = [sys.executable, "-m", "mudrft", "simulate", "--foot", "flat", "--dt", "0.004"]
    proc = subprocess.run([*command, "--out", str(out)], env=env, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert _listing(tmp_path) == ["run.csv"]
    assert f"removed 1 staging file(s) left by a killed run: {left}" in proc.stderr
