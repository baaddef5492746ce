"""Files written by the mudrft command: never replaced without --force, all or nothing.

Every test goes through ``mudrft.cli.main`` only, so that each can be run against an
older command line as well.
"""

from __future__ import annotations

import importlib
import json
import os
import signal
import subprocess
import sys
import time
from contextlib import contextmanager
from pathlib import Path

import pytest

import mudrft
from mudrft.cli import main

FAST = ("--dt", "0.004", "--quiet")  # a coarse, quiet gait cycle: the command is tested


def run(capsys, *args):
    code = main([str(a) for a in args])
    out = capsys.readouterr()
    return code, out.out, out.err


def listing(path):
    """Every file and directory under ``path``, hidden ones included."""
    return sorted(str(p.relative_to(path)) for p in path.rglob("*"))


def one_line_error(code, err, *needles):
    assert code == 2, err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    for needle in needles:
        assert needle in err, err


@pytest.fixture
def plot_fails(monkeypatch):
    def broken(self, **kw):
        raise mudrft.MudrftError("the figure could not be drawn")

    monkeypatch.setattr(mudrft.simulation.Result, "plot", broken)


# --------------------------------------------------------------------------------------
# --force
# --------------------------------------------------------------------------------------
def test_simulate_refuses_to_overwrite_an_existing_plot(tmp_path, capsys):
    pytest.importorskip("matplotlib")  # --plot needs the extra "plot"
    fig = tmp_path / "fig.png"
    fig.write_bytes(b"my figure")
    code, _, err = run(
        capsys, "simulate", "--foot", "flat", *FAST, "--out", tmp_path / "run.csv", "--plot", fig
    )
    one_line_error(code, err, "--plot", "--force")
    assert fig.read_bytes() == b"my figure"
    assert listing(tmp_path) == ["fig.png"]  # and no run.csv either


def test_simulate_force_replaces_both_outputs(tmp_path, capsys):
    pytest.importorskip("matplotlib")  # --plot needs the extra "plot"
    out, fig = tmp_path / "run.csv", tmp_path / "fig.png"
    out.write_text("old")
    fig.write_bytes(b"old")
    code, stdout, _ = run(
        capsys, "simulate", "--foot", "flat", *FAST, "--out", out, "--plot", fig, "--force"
    )
    assert code == 0 and f"wrote {out}" in stdout and f"wrote {fig}" in stdout
    assert out.read_text().startswith("time [s]") and fig.read_bytes()[:4] == b"\x89PNG"
    assert listing(tmp_path) == ["fig.png", "run.csv"]


def test_bench_refuses_to_overwrite_an_existing_json(tmp_path, capsys, monkeypatch):
    from mudrft.cli.bench import load_harness

    harness = load_harness()  # the checkout's benchmarks/harness, as `mudrft bench` loads it
    monkeypatch.setattr(harness, "run_benchmarks", lambda **kw: {"speed": 1.0})
    monkeypatch.setattr(harness, "summary_lines", lambda res: ["fast"])
    target = tmp_path / "bench.json"
    target.write_text("keep me")
    code, _, err = run(capsys, "bench", "--quick", "--json", target)
    one_line_error(code, err, "--json", "--force")
    assert target.read_text() == "keep me"
    code, out, _ = run(capsys, "bench", "--quick", "--json", target, "--force", "--quiet")
    assert code == 0 and "fast" in out
    assert json.loads(target.read_text()) == {"speed": 1.0}
    assert listing(tmp_path) == ["bench.json"]


def test_calibrate_takes_force_and_still_accepts_overwrite_with_a_warning(tmp_path, capsys):
    data = tmp_path / "log.csv"
    mudrft.calibration.save_intrusion_csv(mudrft.calibration.example_dataset("vertical"), data)
    out = tmp_path / "fit.json"
    out.write_text("{}")
    common = ("calibrate", data, "--groups", "alpha", "--quiet", "--out", out)
    code, _, err = run(capsys, *common)
    one_line_error(code, err, "--force")
    assert out.read_text() == "{}"
    assert run(capsys, *common, "--force")[0] == 0
    assert json.loads(out.read_text())["free"] == ["alpha"]
    out.write_text("{}")
    code, _, err = run(capsys, *common, "--overwrite")
    assert code == 0 and "--overwrite is deprecated" in err and "--force" in err
    assert json.loads(out.read_text())["free"] == ["alpha"]


# --------------------------------------------------------------------------------------
# all or nothing
# --------------------------------------------------------------------------------------
def test_simulate_whose_plot_fails_leaves_no_csv(tmp_path, capsys, plot_fails):
    pytest.importorskip("matplotlib")  # --plot needs the extra "plot"
    code, _, err = run(
        capsys,
        *("simulate", "--foot", "flat", *FAST),
        *("--out", tmp_path / "run.csv", "--plot", tmp_path / "fig.png"),
    )
    one_line_error(code, err, "could not be drawn")
    assert listing(tmp_path) == []


def test_simulate_whose_plot_fails_keeps_the_old_csv_under_force(tmp_path, capsys, plot_fails):
    out = tmp_path / "run.csv"
    out.write_text("the previous run")
    code, _, _ = run(
        capsys,
        *("simulate", "--foot", "flat", *FAST, "--force"),
        *("--out", out, "--plot", tmp_path / "fig.png"),
    )
    assert code == 2 and out.read_text() == "the previous run"
    assert listing(tmp_path) == ["run.csv"]


def test_calibrate_whose_plot_fails_leaves_no_json(tmp_path, capsys, monkeypatch):
    pytest.importorskip("matplotlib")  # --plot needs the extra "plot"

    def broken(self, **kw):
        raise mudrft.MudrftError("the figure could not be drawn")

    monkeypatch.setattr(mudrft.calibration.FitResult, "plot", broken)
    data = tmp_path / "in" / "log.csv"
    data.parent.mkdir()
    mudrft.calibration.save_intrusion_csv(mudrft.calibration.example_dataset("vertical"), data)
    outdir = tmp_path / "out"
    outdir.mkdir()
    code, _, err = run(
        capsys,
        *("calibrate", data, "--groups", "alpha", "--quiet"),
        *("--out", outdir / "fit.json", "--plot", outdir / "fit.png"),
    )
    one_line_error(code, err, "could not be drawn")
    assert listing(outdir) == []


def test_failed_walk_leaves_no_directory(tmp_path, capsys, monkeypatch):
    pytest.importorskip("mujoco")
    import mudrft.integrations.walk as W

    def broken(*args, **kw):
        raise mudrft.MudrftError("the biped could not be built")

    monkeypatch.setattr(W, "walk", broken)
    out = tmp_path / "runs" / "walk1"
    code, _, err = run(capsys, "walk", "--out", out, "--seconds", "0.1", "--quiet")
    one_line_error(code, err, "could not be built")
    assert listing(tmp_path) == []


def test_failed_compare_leaves_no_directory(tmp_path, capsys, monkeypatch):
    C = importlib.import_module("mudrft.baselines.compare")

    real = C.compare
    calls = []

    def fails_second_time(*args, **kw):
        calls.append(1)
        if len(calls) > 1:
            raise mudrft.MudrftError("the gait run failed")
        return real(*args, **kw)

    monkeypatch.setattr(C, "compare", fails_second_time)
    out = tmp_path / "cmp"
    code, _, err = run(
        capsys,
        *("compare", "--out", out, "--depth", "0.01", "--hold", "0.05", "--quiet"),
        "--no-figures",  # the failure path, with or without matplotlib
    )
    one_line_error(code, err, "gait run failed")
    assert listing(tmp_path) == []


def test_failed_compare_keeps_an_existing_directory_and_its_files(tmp_path, capsys, monkeypatch):
    C = importlib.import_module("mudrft.baselines.compare")

    def broken(*args, **kw):
        raise mudrft.MudrftError("the plate run failed")

    monkeypatch.setattr(C, "compare", broken)
    (tmp_path / "notes.txt").write_text("mine")
    (tmp_path / "compare.csv").write_text("old results")
    code, _, _ = run(capsys, "compare", "--out", tmp_path, "--force", "--quiet")
    assert code == 2
    assert listing(tmp_path) == ["compare.csv", "notes.txt"]
    assert (tmp_path / "compare.csv").read_text() == "old results"


def test_failed_reproduce_leaves_nothing(tmp_path, capsys, monkeypatch):
    import mudrft.reproduce as R

    def half_done(out, **kw):
        Path(out).mkdir(parents=True, exist_ok=True)
        (Path(out) / "summary.csv").write_text("foot\n")
        raise mudrft.MudrftError("a run failed")

    monkeypatch.setattr(R, "reproduce", half_done)
    out = tmp_path / "results"
    code, _, err = run(capsys, "reproduce", "--out", out, "--no-figures", "--quiet")
    one_line_error(code, err, "a run failed")
    assert listing(tmp_path) == []


@pytest.mark.skipif(not hasattr(signal, "SIGTERM") or os.name == "nt", reason="POSIX signals")
def test_a_terminated_reproduce_leaves_nothing(tmp_path):
    """SIGTERM (a batch system's time limit, ``kill``, ``timeout``) mid-run: exit status
    143, one line, and neither the output directory nor a temporary file stays behind."""
    out = tmp_path / "results"
    code = (  # SIGTERM as a terminal's process has it, whatever this test process inherited
        "import signal, sys, mudrft.cli; signal.signal(signal.SIGTERM, signal.SIG_DFL); "
        f"sys.exit(mudrft.cli.main(['reproduce', '--out', {str(out)!r}, '--no-figures']))"
    )
    src = str(Path(mudrft.__file__).resolve().parents[1])
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([src, os.environ.get("PYTHONPATH", "")])}
    proc = subprocess.Popen(
        [sys.executable, "-c", code], env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE
    )
    try:
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline and proc.poll() is None:
            if out.is_dir() and any(out.iterdir()):  # the staging directory: it is running
                break
            time.sleep(0.01)
        assert proc.poll() is None, "reproduce ended before it could be terminated"
        proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:  # pragma: no cover - only when the test fails
            proc.kill()
            proc.wait()
    assert proc.returncode == 143, err
    assert err.decode().strip().splitlines()[-1] == "mudrft reproduce: terminated"
    assert listing(tmp_path) == []


@pytest.mark.skipif(not hasattr(signal, "SIGTERM") or os.name == "nt", reason="POSIX signals")
@pytest.mark.parametrize(
    ("where", "signame", "status", "last_line"),
    [
        ("staging directory", "SIGTERM", 143, "terminated"),
        ("temporary file", "SIGTERM", 143, "terminated"),
        ("staging directory", "SIGINT", 130, "interrupted"),
    ],
)
def test_a_signal_while_an_output_is_created_leaves_nothing(
    tmp_path, capsys, monkeypatch, where, signame, status, last_line
):
    """A signal delivered between creating an output's temporary name and registering it
    for cleanup (the moment the test above waits for, so a busy machine hits it): it is
    held until the name is registered, then the run unwinds and removes it."""
    import tempfile

    import mudrft.io.atomic as atomic

    def then_terminated(make):
        def made(*args, **kwargs):
            result = make(*args, **kwargs)
            os.kill(os.getpid(), getattr(signal, signame))  # it exists, not yet registered
            return result

        return made

    monkeypatch.setattr(atomic.tempfile, "mkdtemp", then_terminated(tempfile.mkdtemp))
    if where == "staging directory":
        args = ["reproduce", "--out", tmp_path / "results", "--no-figures", "--quiet"]
    else:
        args = ["simulate", "--foot", "flat", *FAST, "--out", tmp_path / "run.csv"]
    # as in a terminal: a background job (as in CI) starts with SIGINT ignored
    with _default_signal_handlers():
        code, _, err = run(capsys, *args)
    assert code == status and err.strip().splitlines()[-1].endswith(f": {last_line}"), err
    assert listing(tmp_path) == []


def test_a_signal_that_cuts_the_cleanup_short_still_leaves_nothing(tmp_path, capsys, monkeypatch):
    """A signal at the first instruction of ``Outputs.__exit__``, before its cleanup began:
    the command's signal context removes what that ``with`` block did not."""
    import mudrft.cli._common as common

    def cut_short(self, *exc_info):
        raise common.Terminated

    monkeypatch.setattr(common.Outputs, "__exit__", cut_short)
    out = tmp_path / "results"
    with _default_signal_handlers():
        code, _, err = run(capsys, "reproduce", "--out", out, "--no-figures", "--quiet")
    assert code == 143 and err.strip().endswith("mudrft reproduce: terminated"), err
    assert listing(tmp_path) == []


@pytest.mark.skipif(not hasattr(signal, "SIGTERM") or os.name == "nt", reason="POSIX signals")
@pytest.mark.parametrize(("signame", "status"), [("SIGTERM", 143), ("SIGINT", 130)])
def test_a_signal_python_swallows_still_ends_the_command(
    tmp_path, capsys, monkeypatch, signame, status
):
    """A signal whose handler runs inside ``__del__`` (or a weakref callback, as an import's
    module lock has): Python ignores the handler's exception and goes on. The command must
    not then finish and write its outputs: it ends with the signal's status, leaving
    nothing, and says so in one line (no "Exception ignored" report)."""
    import mudrft.simulation

    seen = {"ran": False, "went_on": False}

    class Signals:
        def __del__(self):
            seen["ran"] = True
            signal.raise_signal(getattr(signal, signame))  # its handler raises in here
            seen["went_on"] = True  # not reached: the handler's exception ended __del__

    simulate = mudrft.simulation.simulate

    def simulated(*args, **kwargs):
        Signals()  # collected at once, mid-run
        return simulate(*args, **kwargs)

    monkeypatch.setattr(mudrft.simulation, "simulate", simulated)
    reports = []  # what reaches Python's "Exception ignored" report (stderr)
    monkeypatch.setattr(sys, "unraisablehook", reports.append)
    with _default_signal_handlers():
        code, _, err = run(capsys, "simulate", "--foot", "flat", *FAST, "--out", tmp_path / "r.csv")
    assert seen == {"ran": True, "went_on": False}  # the situation under test did arise
    assert code == status, err
    assert reports == [] and err.count("\n") == 1, err
    assert listing(tmp_path) == []


@contextmanager
def _default_signal_handlers():
    before = {sig: signal.getsignal(sig) for sig in (signal.SIGINT, signal.SIGTERM)}
    signal.signal(signal.SIGINT, signal.default_int_handler)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    try:
        yield
    finally:
        for sig, handler in before.items():
            signal.signal(sig, handler)


@pytest.mark.skipif(not hasattr(signal, "SIGTERM") or os.name == "nt", reason="POSIX signals")
def test_an_ignored_signal_stays_ignored(tmp_path, capsys, monkeypatch):
    """A background job (``mudrft ... &`` in a script) ignores SIGINT: the command keeps it so."""
    import tempfile

    import mudrft.io.atomic as atomic

    make = tempfile.mkdtemp

    def made(*args, **kwargs):
        result = make(*args, **kwargs)
        os.kill(os.getpid(), signal.SIGINT)
        return result

    monkeypatch.setattr(atomic.tempfile, "mkdtemp", made)
    before = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        code, _, err = run(capsys, "simulate", "--foot", "flat", *FAST, "--out", tmp_path / "r.csv")
        assert signal.getsignal(signal.SIGINT) is signal.SIG_IGN  # and is left so
    finally:
        signal.signal(signal.SIGINT, before)
    assert code == 0, err
    assert listing(tmp_path) == ["r.csv"]


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="named pipes")
def test_force_refuses_a_pipe_and_writes_through_a_link(tmp_path, capsys):
    """``--force`` replaced a named pipe (as root, /dev/null) and a symbolic link by a file."""
    import stat

    pipe, real, link = tmp_path / "pipe.csv", tmp_path / "real.csv", tmp_path / "link.csv"
    os.mkfifo(pipe)
    real.write_text("old")
    link.symlink_to(real)
    code, _, err = run(capsys, "simulate", "--foot", "flat", *FAST, "--out", pipe, "--force")
    one_line_error(code, err, "--out", "not a regular file")
    assert stat.S_ISFIFO(os.lstat(pipe).st_mode)
    code, _, err = run(capsys, "simulate", "--foot", "flat", *FAST, "--out", link, "--force")
    assert code == 0, err
    assert link.is_symlink() and real.read_text().startswith("time [s]")
    assert listing(tmp_path) == ["link.csv", "pipe.csv", "real.csv"]


def test_compare_out_under_a_file_is_a_one_line_error(tmp_path, capsys):
    (tmp_path / "file").write_text("")
    code, _, err = run(capsys, "compare", "--out", tmp_path / "file" / "x", "--no-figures")
    one_line_error(code, err, "is a file, not a directory")
    code, _, err = run(capsys, "walk", "--out", tmp_path / "file" / "x", "--seconds", "0.1")
    one_line_error(code, err)
    assert listing(tmp_path) == ["file"]


def test_outputs_under_a_file_or_in_a_missing_directory(tmp_path, capsys):
    (tmp_path / "file").write_text("")
    for out, needle in [
        (tmp_path / "file" / "r.csv", "not a directory"),
        (tmp_path / "no" / "r.csv", "does not exist"),
    ]:
        code, _, err = run(capsys, "simulate", "--foot", "flat", *FAST, "--out", out)
        one_line_error(code, err, "--out", needle)
    assert listing(tmp_path) == ["file"]


def test_simulate_never_writes_over_its_input_mesh(tmp_path, capsys):
    stl = tmp_path / "foot.stl"
    stl.write_text("solid my_foot\nendsolid my_foot\n")
    before = stl.read_bytes()
    code, _, err = run(capsys, "simulate", "--foot", stl, "--out", stl, "--force")
    one_line_error(code, err, "--foot")
    assert stl.read_bytes() == before


def test_successful_commands_leave_no_temporary_files(tmp_path, capsys):
    code, _, _ = run(
        capsys,
        "compare",
        "--out",
        tmp_path / "a" / "b",
        "--depth",
        "0.01",
        "--hold",
        "0.05",
        "--quiet",
        "--no-figures",
    )
    assert code == 0
    assert listing(tmp_path) == ["a", "a/b", "a/b/compare.csv", "a/b/compare_summary.csv"]


# --------------------------------------------------------------------------------------
# figure formats and file modes
# --------------------------------------------------------------------------------------
@pytest.mark.parametrize("command", ["simulate", "calibrate"])
def test_a_plot_name_matplotlib_cannot_write_is_refused_before_any_work(
    tmp_path, capsys, monkeypatch, command
):
    """A --plot suffix that is no figure format is a one-line error naming --plot and the
    formats, raised before the simulation or the fit runs (it used to end the whole run in
    a matplotlib traceback)."""
    pytest.importorskip("matplotlib")  # --plot needs the extra "plot"
    ran = []
    monkeypatch.setattr(mudrft.simulation, "simulate", lambda *a, **k: ran.append(1))
    monkeypatch.setattr(mudrft.calibration.fit, "calibrate", lambda *a, **k: ran.append(1))
    if command == "simulate":
        args = ["simulate", "--foot", "flat", *FAST, "--out", tmp_path / "run.csv"]
    else:
        data = tmp_path / "in" / "log.csv"
        data.parent.mkdir()
        mudrft.calibration.save_intrusion_csv(mudrft.calibration.example_dataset("vertical"), data)
        args = ["calibrate", data, "--quiet", "--out", tmp_path / "fit.json"]
    before = listing(tmp_path)
    for name in ("fig.txt", "fig"):
        code, _, err = run(capsys, *args, "--plot", tmp_path / name)
        one_line_error(code, err, "--plot", ".png", ".pdf")
    assert ran == []
    assert listing(tmp_path) == before


def test_output_files_get_the_mode_of_a_new_file(tmp_path, capsys):
    """Outputs are written under a private temporary name, then moved: they must end with
    the permissions the umask gives a new file, not the temporary file's 0600."""
    old = os.umask(0o022)
    try:
        code, _, _ = run(capsys, "simulate", "--foot", "flat", *FAST, "--out", tmp_path / "a.csv")
        os.umask(0o027)
        code2, _, _ = run(capsys, "simulate", "--foot", "flat", *FAST, "--out", tmp_path / "b.csv")
    finally:
        os.umask(old)
    assert code == code2 == 0
    assert (tmp_path / "a.csv").stat().st_mode & 0o777 == 0o644
    assert (tmp_path / "b.csv").stat().st_mode & 0o777 == 0o640


def test_a_nested_command_leaves_the_outer_commands_outputs_alone(tmp_path):
    """The signal context kept one process-wide list: a nested command's end discarded the
    outer command's outputs and the outer one then failed in list.remove."""
    from mudrft.cli._common import Outputs, signals_as_exceptions

    with signals_as_exceptions(), Outputs(force=False) as outer:
        outer.file("--out", tmp_path / "outer.txt").write_text("x")
        with signals_as_exceptions(), Outputs(force=False) as inner:
            inner.file("--out", tmp_path / "inner.txt").write_text("y")
    assert listing(tmp_path) == ["inner.txt", "outer.txt"]


def test_a_command_in_a_thread_keeps_its_outputs_when_the_main_threads_ends(tmp_path):
    """Signal bookkeeping belongs to the main thread. A command in another thread (a
    notebook's worker, a GUI) had its outputs discarded by the end of the main thread's
    command, then failed in list.remove, leaving its temporary file."""
    import threading

    from mudrft.cli._common import Outputs, signals_as_exceptions

    entered, main_done, errors = threading.Event(), threading.Event(), []

    def worker():
        try:
            with Outputs(force=False) as o:
                o.file("--out", tmp_path / "worker.txt").write_text("w")
                entered.set()
                main_done.wait(10)
        except Exception as exc:  # pragma: no cover - only when the test fails
            errors.append(exc)

    thread = threading.Thread(target=worker)
    thread.start()
    entered.wait(10)
    with signals_as_exceptions():  # the main thread runs a command and ends it meanwhile
        pass
    main_done.set()
    thread.join(10)
    assert errors == [] and listing(tmp_path) == ["worker.txt"]


@pytest.mark.parametrize("where", ["same file system", "another file system"])
def test_a_link_in_an_output_directory_to_another_directory_is_written_through(tmp_path, where):
    """A rename cannot reach a link's target on another file system (EXDEV): the commit
    failed halfway, one output written. Each such output is now copied beside its target
    before any output is moved."""
    import tempfile

    from mudrft.cli._common import Outputs

    if where == "same file system":
        elsewhere = tmp_path / "elsewhere"
        elsewhere.mkdir()
    else:
        shm = Path("/dev/shm")
        if not shm.is_dir() or shm.stat().st_dev == tmp_path.stat().st_dev:
            pytest.skip("no second file system (/dev/shm) here")
        elsewhere = Path(tempfile.mkdtemp(dir=shm))
    try:
        out = tmp_path / "out"
        out.mkdir()
        (elsewhere / "b.txt").write_text("old b")
        (out / "b.txt").symlink_to(elsewhere / "b.txt")
        with Outputs(force=True) as o:
            stage = o.directory("--dir", out, ["a.txt", "b.txt"])
            (stage / "a.txt").write_text("a")
            (stage / "b.txt").write_text("new b")
        assert (out / "b.txt").is_symlink() and (elsewhere / "b.txt").read_text() == "new b"
        assert listing(out) == ["a.txt", "b.txt"] and listing(elsewhere) == ["b.txt"]
    finally:
        if where != "same file system":
            import shutil

            shutil.rmtree(elsewhere, ignore_errors=True)


def test_a_symbolic_link_loop_is_refused(tmp_path, capsys):
    (tmp_path / "a.csv").symlink_to(tmp_path / "b.csv")
    (tmp_path / "b.csv").symlink_to(tmp_path / "a.csv")
    code, _, err = run(capsys, "simulate", "--foot", "flat", *FAST, "--out", tmp_path / "a.csv")
    one_line_error(code, err, "--out", "symbolic link that loops")
    assert (tmp_path / "a.csv").is_symlink()
