"""A fuzz of the command line: each mistake found there is one line naming the option.

Every test goes through ``mudrft.cli.main`` only.
"""

from __future__ import annotations

from importlib import resources

import pytest

from mudrft.cli import main

FAST = ("--dt", "0.004", "--quiet")  # a coarse, quiet gait cycle: the command is tested
SPEC = """
[foot]
kind = "flat"
[mud]
water_content = 0.25
[motion]
speed = [0.2, 0.26]
"""


def run(capsys, *args):
    code = main([str(a) for a in args])
    out = capsys.readouterr()
    return code, out.out, out.err


def one_line_error(code, err, *needles):
    assert code == 2, err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    for needle in needles:
        assert needle in err, err


def example_log():
    return resources.files("mudrft") / "data" / "synthetic_plate_vertical_w25.csv"


# --------------------------------------------------------------------------------------
# an empty output name (an unset shell variable) is not the current directory
# --------------------------------------------------------------------------------------
def test_empty_out_file_is_refused(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code, _, err = run(capsys, "simulate", "--foot", "flat", "--out", "", *FAST)
    one_line_error(code, err, "--out", "empty")
    assert list(tmp_path.iterdir()) == []


def test_empty_out_directory_is_refused(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    code, _, err = run(capsys, "compare", "--out", "", "--no-figures", "--quiet")
    one_line_error(code, err, "--out", "empty")
    assert list(tmp_path.iterdir()) == []


# --------------------------------------------------------------------------------------
# errors name the command line's options, not the library's keywords
# --------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("args", "needles"),
    [
        (("--confidence", "95"), ("--confidence", "0.95")),
        (("--confidence", "0"), ("--confidence",)),
        (("--length", "0"), ("--length",)),
        (("--area", "-1"), ("--area",)),
        (("--area", "16furlong^2"), ("--area", "unit for area must be one of")),
        (("--length", "forty mm"), ("--length", "a number with an optional unit", "40mm")),
        (("--columns", "time"), ("--columns must be ROLE=NAME pairs", "'time'")),
        (("--columns", "speed=v"), ("--columns", "ROLE one of time, depth")),
        (("--columns", "time=a,time=b"), ("--columns names the time twice",)),
        (("--starts", "0"), ("--starts",)),
        (("--decimate", "0"), ("--decimate",)),
        (("--clock", "retraction"), ("--clock retraction", "--thixotropy quasi-static")),
    ],
)
def test_calibrate_option_errors_name_the_option(tmp_path, capsys, args, needles):
    out = tmp_path / "fit.json"
    code, _, err = run(capsys, "calibrate", example_log(), "--out", out, "--quiet", *args)
    one_line_error(code, err, *needles)
    assert list(tmp_path.iterdir()) == []


def test_simulate_clock_without_quasi_static_names_the_options(tmp_path, capsys):
    args = ("simulate", "--foot", "flat", "--out", tmp_path / "run.csv", "--clock", "retraction")
    code, _, err = run(capsys, *args, *FAST)
    one_line_error(code, err, "--clock retraction", "--thixotropy quasi-static")
    assert list(tmp_path.iterdir()) == []


def test_compare_negative_hold_names_the_option(tmp_path, capsys):
    out = tmp_path / "cmp"
    code, _, err = run(capsys, "compare", "--out", out, "--hold", "-1", "--no-figures")
    one_line_error(code, err, "--hold", ">= 0 s")
    assert not out.exists()


@pytest.mark.parametrize(
    ("args", "needles"),
    [
        (("--speed", "-1"), ("--speed", ">= 0 m/s")),
        (("--dt", "0.02"), ("--dt", "0.01 s")),
        (("--step-time", "1e-6"), ("--step-time", "at least 20 time steps", "0.02 s")),
    ],
)
def test_walk_option_errors_name_the_option(tmp_path, capsys, args, needles):
    pytest.importorskip("mujoco")
    pytest.importorskip("matplotlib")
    out = tmp_path / "w"
    code, _, err = run(
        capsys, "walk", "--out", out, "--seconds", "0.05", "--no-render", "--quiet", *args
    )
    one_line_error(code, err, *needles)
    assert not out.exists()


# --------------------------------------------------------------------------------------
# mudrft sweep
# --------------------------------------------------------------------------------------
@pytest.mark.parametrize("address", ["bogus", "localhost:notaport", ""])
def test_sweep_bad_scheduler_address_is_one_line(tmp_path, capsys, address):
    for module in ("dask", "distributed", "xarray", "zarr"):
        pytest.importorskip(module)
    (tmp_path / "s.toml").write_text(SPEC)
    out = tmp_path / "o"
    code, _, err = run(
        capsys, "sweep", tmp_path / "s.toml", "--out", out, "--scheduler", address, "--quiet"
    )
    one_line_error(code, err, "--scheduler")
    assert not out.exists()


def test_sweep_never_replaces_its_spec(tmp_path, capsys):
    for module in ("xarray", "zarr"):
        pytest.importorskip(module)
    spec = tmp_path / "points.csv"  # a spec under the name of the table the sweep writes
    spec.write_text(SPEC)
    args = ("sweep", spec, "--out", tmp_path, "--scheduler", "serial", "--force", "--quiet")
    code, _, err = run(capsys, *args)
    one_line_error(code, err, "--out", "spec")
    assert spec.read_text() == SPEC
    assert sorted(p.name for p in tmp_path.iterdir()) == ["points.csv"]


def test_a_missing_foot_file_names_the_foot_option(tmp_path, capsys):
    """'path must be an existing mesh file' named the reader's argument, not --foot."""
    out = tmp_path / "r.csv"
    code, _, err = run(capsys, "simulate", "--foot", tmp_path / "missing.stl", "--out", out)
    one_line_error(code, err, "--foot", "missing.stl", "no such mesh file")
    assert not out.exists()


def test_sweep_out_inside_a_store_is_refused(tmp_path, capsys):
    """--out DIR/sweep.zarr wrote sweep.zarr, points.csv and maps inside the store."""
    for module in ("xarray", "zarr"):
        pytest.importorskip(module)
    spec = tmp_path / "spec.toml"
    spec.write_text(SPEC)
    for out in (tmp_path / "sweep.zarr", tmp_path / "sweep.zarr" / "more"):
        code, _, err = run(capsys, "sweep", spec, "--out", out, "--scheduler", "serial", "--quiet")
        one_line_error(code, err, "--out", "is a sweep store", "give the directory that holds it")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["spec.toml"]


def test_a_library_warning_through_logging_has_the_command_prefix(tmp_path, capsys):
    """A warning the library logs (not a Python warning) was printed bare; the CLI promises
    'mudrft COMMAND: warning: ...' for every warning of the library."""
    log = tmp_path / "v.csv"
    log.write_text(
        "# direction: vertical\ntime [s],depth [m],stress [Pa]\n"
        "0,0,0\n0.1,0.002,500\n0.2,0.004,900\n0.3,0.002,-100\n"
    )
    code, _, err = run(
        capsys, "calibrate", log, "--direction", "horizontal", "--out", tmp_path / "f.json"
    )
    lines = [line for line in err.splitlines() if "overrides the file's" in line]
    assert len(lines) == 1 and lines[0].startswith("mudrft calibrate: warning: "), err
    assert code == 2 and not (tmp_path / "f.json").exists()  # 4 samples: too few to fit
