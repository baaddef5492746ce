"""Running sweeps: values equal to mudrft.simulate, the labelled layout, failures recorded,
a store that refuses to be overwritten, a killed sweep resumed without recomputing, and a
real dask.distributed cluster of two worker processes giving the serial run's results.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import mudrft
from mudrft._validation import MudrftError
from mudrft.sweep import SweepWarning, evaluate, load_spec

pytest.importorskip("xarray")
pytest.importorskip("zarr")
pytest.importorskip("distributed")

SRC = Path(mudrft.__file__).resolve().parents[1]

SPEC = {
    "sweep": {"metrics": ["peak_support", "max_suction", "energy"], "points_per_task": 2},
    "foot": {"kind": ["flat", "semi-sphere"], "width": [0.05, 0.065]},
    "mud": {"water_content": [0.25, 0.35]},
    "motion": {"speed": 0.2},
}


@pytest.fixture(scope="module")
def serial():
    """The spec's sweep, run serially in memory (its semi-sphere points fail: no width)."""
    with pytest.warns(SweepWarning, match="4 of 8 points of the sweep failed"):
        return mudrft.sweep(SPEC, scheduler="serial")


def same(a, b):
    for name in a.data_vars:
        x, y = a[name].values, b[name].values
        assert np.array_equal(x, y, equal_nan=x.dtype.kind == "f"), name
    for name in a.coords:
        assert np.array_equal(a[name].values, b[name].values), name


def test_values_equal_simulate_and_the_result_is_labelled(serial):
    ds = serial
    assert ds["peak_support"].dims == ("foot", "width", "water_content")
    assert list(ds.data_vars) == ["peak_support", "max_suction", "energy", "error"]
    assert ds["peak_support"].attrs["units"] == "N" and ds["energy"].attrs["units"] == "J"
    assert ds["width"].attrs["units"] == "m" and ds["width"].attrs["section"] == "foot"
    assert float(ds["speed"]) == 0.2 and ds["speed"].attrs["units"] == "m/s"  # fixed: a scalar
    assert ds.attrs["mudrft_version"] == mudrft.__version__
    assert "Tables S1 (vertical) and S2" in ds.attrs["parameter_sources"]
    assert load_spec(SPEC).identity() == ds.attrs["spec_identity"]
    assert ds.attrs["complete"] == 1
    foot = mudrft.feet.Flat(width=0.065)
    ref = mudrft.simulate(foot, mudrft.paper_mud(0.35), mudrft.gait(0.2)).metrics()
    got = ds.sel(foot="flat", width=0.065, water_content=0.35)
    for m in ("peak_support", "max_suction", "energy"):
        assert float(got[m]) == ref[m]


def test_a_point_that_raises_is_recorded_and_the_rest_completes(serial, monkeypatch):
    # a bad combination: the semi-sphere has no width
    bad = serial.sel(foot="semi-sphere")
    assert np.isnan(bad["peak_support"].values).all()
    assert all("no parameter 'width'" in e for e in bad["error"].values.ravel())
    assert serial.attrs["failed_points"] == 4
    ok = serial.sel(foot="flat")
    assert np.isfinite(ok["peak_support"].values).all() and (ok["error"].values == "").all()
    # any exception inside the physics is recorded the same way
    real = evaluate.evaluate_point

    def flaky(context, point, **kw):
        if point.get("water_content") == 0.35 and point.get("width") == 0.05:
            raise ZeroDivisionError("boom")
        return real(context, point, **kw)

    monkeypatch.setattr(evaluate, "evaluate_point", flaky)
    spec = {**SPEC, "foot": {"kind": "flat", "width": [0.05, 0.065]}}
    with pytest.warns(SweepWarning, match="1 of 4 points"):
        ds = mudrft.sweep(spec, scheduler="serial")
    assert ds["error"].sel(width=0.05, water_content=0.35).item() == "ZeroDivisionError: boom"
    assert np.isnan(ds["peak_support"].sel(width=0.05, water_content=0.35))
    assert np.isfinite(ds["peak_support"].sel(width=0.05, water_content=0.25))
    assert ds.attrs["failed_points"] == 1


def test_store_is_never_replaced_without_asking(tmp_path):
    spec = {"foot": {"kind": "flat"}, "motion": {"speed": [0.2]}, "sweep": {"metrics": ["max_depth"]}}  # fmt: skip
    store = tmp_path / "s.zarr"
    first = mudrft.sweep(spec, store=store, scheduler="serial")
    with pytest.raises(MudrftError, match="exists; pass resume=True"):
        mudrft.sweep(spec, store=store, scheduler="serial")
    other = {**spec, "motion": {"speed": [0.3]}}
    with pytest.raises(MudrftError, match="made from another spec"):
        mudrft.sweep(other, store=store, scheduler="serial", resume=True)
    again = mudrft.sweep(spec, store=store, scheduler="serial", resume=True)  # nothing to do
    same(first, again)
    assert mudrft.sweep(other, store=store, scheduler="serial", overwrite=True)["speed"] == 0.3
    plain = tmp_path / "mine"
    plain.mkdir()
    with pytest.raises(MudrftError, match="not a mudrft sweep store; refusing"):
        mudrft.sweep(spec, store=plain, scheduler="serial", overwrite=True)
    assert plain.is_dir()
    same(mudrft.sweep.load_result(store), mudrft.sweep(other, scheduler="serial"))


def test_a_sweep_that_cannot_start_leaves_no_store(tmp_path):
    """An unreachable scheduler fails before any chunk: the store this call made is removed,
    so running again needs no --force (a failed run leaves nothing behind)."""
    import dask

    spec = {"foot": {"kind": "flat"}, "motion": {"speed": [0.2]}, "sweep": {"metrics": ["max_depth"]}}  # fmt: skip
    store = tmp_path / "s.zarr"
    with dask.config.set({"distributed.comm.timeouts.connect": "1s"}), pytest.raises(OSError):
        mudrft.sweep(spec, store=store, scheduler="tcp://127.0.0.1:9")
    assert list(tmp_path.iterdir()) == []
    assert mudrft.sweep(spec, store=store, scheduler="serial")["max_depth"].notnull().all()


def test_a_sweep_that_fails_after_a_chunk_keeps_its_store_for_resume(tmp_path, monkeypatch):
    """A failure after the first chunk keeps the store (resume continues it)."""
    spec = {**SPEC, "foot": {"kind": "flat", "width": [0.05, 0.065]}}
    store = tmp_path / "s.zarr"
    real = evaluate.evaluate_chunk
    calls = []

    def second_fails(context, points):
        calls.append(1)
        if len(calls) == 2:
            raise KeyboardInterrupt
        return real(context, points)

    monkeypatch.setattr("mudrft.sweep.run.evaluate_chunk", second_fails)
    with pytest.raises(KeyboardInterrupt):
        mudrft.sweep(spec, store=store, scheduler="serial")
    assert store.is_dir()
    monkeypatch.setattr("mudrft.sweep.run.evaluate_chunk", real)
    ds = mudrft.sweep(spec, store=store, scheduler="serial", resume=True)
    same(ds, mudrft.sweep(spec, scheduler="serial"))


KILL_SPEC = """
[sweep]
metrics = ["max_suction"]
points_per_task = 2
[foot]
kind = "flat"
width = [0.05, 0.055, 0.06, 0.065, 0.07, 0.075]
[mud]
water_content = [0.25, 0.35]
[motion]
speed = 0.2
dt = 2e-4
"""


def created(store):
    """Whether the store is made whole (its last attribute written)."""
    try:
        return "arrays" in json.loads((store / "zarr.json").read_text())["attributes"]
    except (OSError, ValueError, KeyError):
        return False


def test_a_killed_sweep_resumes_without_recomputing_finished_chunks(tmp_path, monkeypatch):
    (tmp_path / "spec.toml").write_text(KILL_SPEC)
    spec = load_spec(tmp_path / "spec.toml")
    store = tmp_path / "s.zarr"
    code = (  # each point takes at least 0.2 s, so the sweep cannot end between two polls
        "import time, mudrft\n"
        "from mudrft.sweep import evaluate\n"
        "point = evaluate.evaluate_point\n"
        "evaluate.evaluate_point = lambda *a, **k: (time.sleep(0.2), point(*a, **k))[1]\n"
        f"mudrft.sweep({str(tmp_path / 'spec.toml')!r}, store={str(store)!r}, scheduler='serial')\n"
    )
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(SRC), os.environ.get("PYTHONPATH", "")])}  # fmt: skip
    proc = subprocess.Popen([sys.executable, "-c", code], env=env)
    import zarr

    from mudrft.sweep.store import chunk_status

    def done_chunks(group, spec):
        return chunk_status(group)[0]

    try:
        deadline = time.monotonic() + 120
        done = np.zeros(spec.n_chunks, dtype=bool)
        while time.monotonic() < deadline and proc.poll() is None:
            if created(store):
                done = done_chunks(zarr.open_group(str(store), mode="r"), spec)
                if done.sum() >= 2:
                    break
            time.sleep(0.02)
        proc.send_signal(signal.SIGKILL)  # no cleanup: as a lost machine or `kill -9`
    finally:
        proc.wait(timeout=30)
    done = done_chunks(zarr.open_group(str(store), mode="r"), spec)
    assert 2 <= done.sum() < spec.n_chunks, "the sweep finished before it could be killed"
    before = np.asarray(zarr.open_group(str(store), mode="r")["max_suction"][...])

    calls = []
    real = evaluate.evaluate_point

    def counting(context, point, **kw):
        calls.append(point)
        return real(context, point, **kw)

    monkeypatch.setattr(evaluate, "evaluate_point", counting)
    ds = mudrft.sweep(tmp_path / "spec.toml", store=store, scheduler="serial", resume=True)
    missing = [i for i in range(spec.n_chunks) if not done[i]]
    expected = [p for i in missing for p in spec.chunk_points(i)]
    assert calls == expected  # exactly the unfinished chunks' points, once each
    after = ds["max_suction"].values
    for i in np.flatnonzero(done):  # finished chunks kept as they were
        sl = spec.chunk_slices(i)
        assert np.array_equal(after[sl], before[sl])
    assert np.isfinite(after).all() and ds.attrs["complete"] == 1
    foot = mudrft.feet.Flat(width=0.075)
    ref = mudrft.simulate(foot, mudrft.paper_mud(0.35), mudrft.gait(0.2, dt=2e-4)).metrics()
    assert float(ds["max_suction"].sel(width=0.075, water_content=0.35)) == ref["max_suction"]


def test_two_worker_processes_on_a_local_cluster_give_the_serial_results(
    serial, tmp_path, monkeypatch
):
    import distributed
    from distributed import Client, LocalCluster, get_task_stream

    small = {**SPEC, "foot": {"kind": "flat", "width": [0.05]}, "mud": {"water_content": 0.25}}
    with (
        LocalCluster(
            n_workers=2, processes=True, threads_per_worker=1, dashboard_address=":0"
        ) as cluster,
        Client(cluster) as client,
    ):
        with get_task_stream(client) as stream, pytest.warns(SweepWarning):
            ds = mudrft.sweep(SPEC, client=client, store=tmp_path / "d.zarr")
        # a running cluster by its address, as `--scheduler tcp://...` does
        by_address = mudrft.sweep(small, scheduler=cluster.scheduler_address)

        # the default: a local cluster of single-thread worker processes (here the one above)
        made = {}

        class Local:
            def __init__(self, **kw):
                made.update(kw)

            def __enter__(self):
                return cluster

            def __exit__(self, *exc):
                return False

        monkeypatch.setattr(distributed, "LocalCluster", Local)
        default = mudrft.sweep(small, workers=2)
        # with no options, a sweep whose points left outlast a cluster's start-up moves
        # there after its second chunk (the first pays the warm-up)
        monkeypatch.setattr("mudrft.sweep.run.CLUSTER_START_S", 0.0)
        monkeypatch.setattr(os, "cpu_count", lambda: 2)
        handed, to_cluster = [], mudrft.sweep.run._run_dask

        def spy(client, spec, context, pending, done):  # what the cluster is given
            handed.append(list(pending))
            return to_cluster(client, spec, context, pending, done)

        # (counted here, not in a task stream, which may also list a task of the sweeps
        # above that the scheduler reports late)
        monkeypatch.setattr("mudrft.sweep.run._run_dask", spy)
        with pytest.warns(SweepWarning):
            switched = mudrft.sweep(SPEC)
    tasks = [t for t in stream.data if "evaluate_chunk" in str(t["key"])]
    assert len(tasks) == load_spec(SPEC).n_chunks == 4
    assert len({t["worker"] for t in tasks}) == 2  # both processes ran chunks
    same(ds, serial)
    assert made["n_workers"] == 2 and made["threads_per_worker"] == 1 and made["processes"]
    same(switched, serial)
    assert [len(p) for p in handed] == [2]  # the last two of four chunks
    reference = serial.sel(foot="flat", width=[0.05], water_content=0.25)
    for other in (by_address, default):
        assert np.array_equal(other["max_suction"].values, reference["max_suction"].values)


def test_walk_metrics_are_read_from_the_walk_summary(monkeypatch):
    # the MuJoCo walk itself is tested in tests/integrations; here, that a sweep passes the
    # motion parameters on and reads every walking metric from the summary's keys
    pytest.importorskip("mujoco")
    from mudrft.integrations import walk as W
    from mudrft.sweep.catalog import METRICS

    seen = {}

    def fake_walk(foot, mud, **kw):
        seen.update(kw, foot=foot.name)
        summary = {m.key: float(i) for i, m in enumerate(METRICS["walk"].values())}
        return W.WalkResult(table={}, steps={}, summary=summary)

    monkeypatch.setattr(W, "walk", fake_walk)
    spec = {"foot": {"kind": "flat"}, "motion": {"kind": "walk", "seconds": [2.0], "speed": 0.1}}
    ds = mudrft.sweep(spec, scheduler="serial")
    assert seen == {"seconds": 2.0, "speed": 0.1, "foot": "flat"}
    assert [ds[m].item() for m in METRICS["walk"]] == list(range(len(METRICS["walk"])))
    assert ds["distance"].attrs["units"] == "m" and (ds["error"].values == "").all()


def test_failed_points_are_warned_about_with_the_first_error(serial):
    """A combination wrong for every point (a semi-cylinder lower than its height) gave an
    all-NaN result without a word; some failed points are warned about too."""
    spec = {"foot": {"kind": "semi-cylinder", "radius": 0.01}, "motion": {"speed": [0.13, 0.2]}}
    with pytest.warns(SweepWarning, match=r"every point of the sweep failed \(2\); the first error: MudrftError: height must be <= radius"):  # fmt: skip
        ds = mudrft.sweep(spec, scheduler="serial")
    assert ds.attrs["failed_points"] == 2
    spec = {**SPEC, "mud": {"water_content": 0.25}, "foot": {"kind": ["flat", "semi-sphere"], "width": 0.05}}  # fmt: skip
    with pytest.warns(SweepWarning, match=r"1 of 2 points of the sweep failed \(NaN metrics; each error in 'error'\); the first error: MudrftError: the semi-sphere foot has no parameter 'width'"):  # fmt: skip
        mudrft.sweep(spec, scheduler="serial")


def test_a_small_sweep_runs_in_this_process_by_default(monkeypatch):
    """A sweep quicker than a cluster's start-up starts none (it ran 10-15 s on a local
    cluster against 3-6 s serially)."""
    import distributed

    def no_cluster(**kw):
        raise AssertionError("a local cluster was started for a small sweep")

    monkeypatch.setattr(distributed, "LocalCluster", no_cluster)
    monkeypatch.setattr(os, "cpu_count", lambda: 2)
    small = {**SPEC, "foot": {"kind": "flat", "width": [0.05]}, "mud": {"water_content": [0.25, 0.35]}}  # fmt: skip
    ds = mudrft.sweep(small)
    assert np.isfinite(ds["max_suction"].values).all()


def test_resume_without_a_store_is_refused():
    spec = {"foot": {"kind": "flat"}, "motion": {"speed": [0.2]}, "sweep": {"metrics": ["max_depth"]}}  # fmt: skip
    with pytest.raises(MudrftError, match=r"resume needs the store"):
        mudrft.sweep(spec, scheduler="serial", resume=True)


def test_a_sweep_called_while_a_worker_imports_the_script_names_the_main_guard(
    tmp_path, monkeypatch
):
    """D116: a worker process imports the driver's script; an unguarded top-level call ran
    the sweep again there and failed with "store exists", a store the user never made."""
    import multiprocessing

    monkeypatch.setattr(multiprocessing.current_process(), "_inheriting", True, raising=False)
    with pytest.raises(MudrftError, match=r"importing the script.*if __name__ == \"__main__\""):
        mudrft.sweep(SPEC, store=tmp_path / "s.zarr", scheduler="serial")
    assert not (tmp_path / "s.zarr").exists()


def test_a_local_cluster_that_does_not_start_is_one_error_naming_the_main_guard(
    tmp_path, monkeypatch
):
    """D116: distributed says only "Nanny failed to start."; the store made for the run is
    removed and the error says what to do."""
    import distributed

    def failing(**kw):
        raise RuntimeError("Nanny failed to start.")

    monkeypatch.setattr(distributed, "LocalCluster", failing)
    with pytest.raises(
        MudrftError,
        match=r"could not start its 2 worker process\(es\) \(Nanny failed to start\.\); "
        r"most often because .*if __name__ == \"__main__\".*scheduler='serial'",
    ):
        mudrft.sweep(SPEC, store=tmp_path / "s.zarr", workers=2)
    assert not (tmp_path / "s.zarr").exists()


def _distributed_version() -> tuple[int, int]:
    import distributed

    major, minor = distributed.__version__.split(".")[:2]
    return int(major), int(minor)


@pytest.mark.skipif(
    _distributed_version() < (2026, 7),
    reason="distributed before 2026.7 restarts a worker that fails to start until the "
    "script is interrupted (each restart prints the error); measured on 2024.8-2026.3",
)
def test_an_unguarded_script_fails_with_the_main_guard_in_driver_and_worker(tmp_path):
    """The script of the README without ``if __name__ == "__main__":``, run for real."""
    script = tmp_path / "unguarded.py"
    script.write_text(
        "import mudrft\n"
        "mudrft.sweep({'foot': {'kind': 'flat'}, 'motion': {'speed': [0.2]}},\n"
        "             store='s.zarr', workers=1)\n"
    )
    env = {**os.environ, "PYTHONPATH": str(SRC)}
    run = subprocess.run(
        [sys.executable, str(script)], cwd=tmp_path, env=env, capture_output=True, text=True,
        timeout=240,
    )  # fmt: skip
    assert run.returncode == 1
    last = run.stderr.strip().splitlines()[-1]
    assert last.startswith("mudrft._validation.MudrftError: the local Dask cluster could not")
    assert 'if __name__ == "__main__"' in last
    assert "while a new worker process was importing the script" in run.stderr  # the worker
    assert "exists" not in run.stderr and not (tmp_path / "s.zarr").exists()
