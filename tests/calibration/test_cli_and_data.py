"""The ``mudrft calibrate`` command and the shipped synthetic example files."""

from __future__ import annotations

import argparse
import json
from importlib import resources

import numpy as np
import pytest

import mudrft
from mudrft.calibration import EXAMPLE_FILES, example_dataset, load_parameters, synthetic_dataset
from mudrft.calibration.synthetic import EXAMPLE_SETTINGS
from mudrft.cli import main as mudrft_main
from mudrft.cli.calibrate import add_parser, run


def main(argv):
    """``mudrft calibrate ARGV...``."""
    return mudrft_main(["calibrate", *argv])


def _example_path(direction="vertical", w=0.25):
    return str(resources.files("mudrft") / "data" / EXAMPLE_FILES[(direction, w)])


def test_cli_fits_writes_json_and_reports_progress(tmp_path, capsys):
    out = tmp_path / "fit.json"
    rc = main(
        [_example_path(), "--direction", "vertical", "--groups", "b", "th", "--out", str(out)]
    )
    assert rc == 0
    cap = capsys.readouterr()
    stages = [ln for ln in cap.err.splitlines() if ln.startswith("calibrate: stage")]
    # one progress line per stage: intrusion, relaxation (the groups have no suction
    # parameter, so no retraction stage), joint
    assert [ln.split()[2] for ln in stages] == ["intrusion", "relaxation", "joint"]
    assert "synthetic" in cap.out and "alpha" in cap.out
    data = json.loads(out.read_text())
    assert data["free"] == ["alpha", "n", "lam", "eta_m", "eta_inf", "gamma_dot_c"]
    assert isinstance(load_parameters(out), mudrft.MudParameters)


def test_cli_refuses_to_overwrite_and_reports_bad_files(tmp_path, capsys):
    out = tmp_path / "fit.json"
    out.write_text("{}")
    assert main([_example_path(), "--out", str(out), "--quiet"]) == 2
    assert "exists" in capsys.readouterr().err
    assert out.read_text() == "{}"
    bad = tmp_path / "bad.csv"
    bad.write_text("time [s],depth [furlong],stress [Pa]\n0,0,0\n")
    assert main([str(bad), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert str(bad) in err and "line 1, column 2" in err and "Traceback" not in err
    # the output may not name an input file
    assert main([str(bad), "--out", str(bad), "--force", "--quiet"]) == 2
    assert "input file" in capsys.readouterr().err


def test_cli_force_log_with_area(tmp_path, capsys):
    ds = example_dataset("vertical")
    area = 0.0025
    lines = ["trial,time [s],depth [mm],Fz [N]"]
    for tr in ds:
        lines += [
            f"{tr.name},{float(t)!r},{float(1e3 * q)!r},{float(s * area)!r}"
            for t, q, s in zip(tr.time, tr.depth, tr.stress, strict=True)
        ]
    p = tmp_path / "force.csv"
    p.write_text("\n".join(lines) + "\n")
    assert main([str(p), "--groups", "alpha", "--quiet"]) == 2  # no area: error
    assert "area" in capsys.readouterr().err
    out = tmp_path / "f.json"
    assert (
        main([str(p), "--area", str(area), "--groups", "alpha", "--quiet", "--out", str(out)]) == 0
    )


def test_add_parser_wires_into_a_parent_parser():
    parent = argparse.ArgumentParser(prog="mudrft")
    sub = parent.add_subparsers(dest="command")
    add_parser(sub)
    args = parent.parse_args(
        [
            "calibrate",
            "a.csv",
            "--direction",
            "horizontal",
            "--area",
            "0.01",
            "--length",
            "0.04",
            "--groups",
            "b",
            "s",
        ]
    )
    assert args.func is run and args.data == ["a.csv"] and args.area == "0.01"  # units later
    assert args.groups == ["b", "s"] and args.length == "0.04"


# --------------------------------------------------------------------------------------
# example files
# --------------------------------------------------------------------------------------
@pytest.mark.parametrize("key", sorted(EXAMPLE_FILES))
def test_example_files_are_labelled_synthetic_and_regenerable(key):
    direction, w = key
    ds = example_dataset(direction, water_content=w)
    assert ds.synthetic and ds.direction == direction
    text = open(_example_path(direction, w), encoding="utf-8").read()
    assert text.startswith("# synthetic:")
    assert 300 <= text.count("\n") <= 700  # "a few hundred rows"
    s = EXAMPLE_SETTINGS
    ref = synthetic_dataset(
        mudrft.paper_parameters(w, direction),
        speeds=s["speeds"],
        noise=s["noise"],
        seed=s["seed"],
        depth=s["depth"],
        hold=s["hold"],
        dt=s["dt"],
        direction=direction,
    )
    for a, b in zip(ds, ref, strict=True):
        # the files keep 6 significant digits
        np.testing.assert_allclose(a.time, b.time, rtol=1e-5, atol=1e-9)
        np.testing.assert_allclose(a.stress, b.stress, rtol=1e-5, atol=1e-3)


def test_synthetic_dataset_noise_level_and_seed():
    p = mudrft.paper_parameters(0.25)
    a = synthetic_dataset(p, speeds=(0.02,), noise=0.02, seed=1, dt=0.01)
    b = synthetic_dataset(p, speeds=(0.02,), noise=0.02, seed=1, dt=0.01)
    clean = synthetic_dataset(p, speeds=(0.02,), noise=0.0, dt=0.01)
    np.testing.assert_array_equal(a[0].stress, b[0].stress)  # same seed, same data
    r = a[0].stress - clean[0].stress
    # Gaussian noise of 2 % of the range: the sample std of 450 draws is within 15 %
    # of it (about 4.5 standard errors of a standard deviation)
    assert np.std(r) == pytest.approx(0.02 * np.ptp(clean[0].stress), rel=0.15)


@pytest.mark.filterwarnings("default::mudrft._validation.CalibrationWarning")  # shown as lines
def test_cli_calibration_warnings_are_one_line_each_and_survive_quiet(
    tmp_path, capsys, monkeypatch
):
    """With --quiet the thinning warning read 'mudrft calibrate: warning: calibrate:
    warning: ...'; without it, it came as a plain progress note."""
    import mudrft.calibration._problem as options

    longest = max(len(t) for t in example_dataset("vertical").trials)
    monkeypatch.setattr(options, "FIT_SAMPLES", longest // 2 + 1)  # thinned by 2
    log = tmp_path / "log.csv"
    name = EXAMPLE_FILES[("vertical", 0.25)]
    log.write_bytes(resources.files("mudrft.data").joinpath(name).read_bytes())
    for quiet in (["--quiet"], []):
        assert mudrft_main(["calibrate", str(log), "--groups", "b", *quiet]) in (0, 1)
        err = capsys.readouterr().err
        warned = [line for line in err.splitlines() if "warning" in line]
        assert warned == [
            f"mudrft calibrate: warning: the longest trial has {longest} samples; fitting "
            f"every 2nd sample (about {longest // 2} per trial, decision D104) to keep the "
            "fit to minutes; pass decimate=1 (CLI: --decimate 1) to fit every sample"
        ], err


@pytest.mark.filterwarnings("default::mudrft._validation.CalibrationWarning")  # shown as lines
def test_strict_makes_a_fit_that_does_not_describe_the_data_exit_1_with_the_warning(
    tmp_path, capsys
):
    """A fit that 'does not describe the data' exits 0, so a script could not fail
    on it; --strict makes a warning exit status 1 with its message. The default is
    unchanged, and the outputs are written as without --strict."""
    rng = np.random.default_rng(0)
    t = np.linspace(0.0, 1.0, 41)
    depth = 0.06 * np.minimum(t, 1.0 - t)
    stress = np.abs(rng.normal(0.0, 2000.0, t.size)) + 100.0 * (depth > 0)  # noise
    log = tmp_path / "noise.csv"
    rows = "".join(f"{a},{b},{c}\n" for a, b, c in zip(t, depth, stress, strict=True))
    log.write_text("time [s],depth [m],stress [Pa]\n" + rows)
    poor = "the model does not describe these data (relative RMSE above 25 %); check the units"
    common = ["calibrate", str(log), "--groups", "b", "--quiet"]
    assert mudrft_main([*common, "--out", str(tmp_path / "a.json")]) == 0
    err = capsys.readouterr().err
    assert f"mudrft calibrate: warning: {poor}" in err and "error" not in err
    assert mudrft_main([*common, "--strict", "--out", str(tmp_path / "b.json")]) == 1
    out, err = capsys.readouterr()
    last = err.splitlines()[-1]
    assert last.startswith(f"mudrft calibrate: error: --strict: the command warned: {poor}")
    assert (tmp_path / "b.json").exists() and "wrote" in out
    example = ["calibrate", _example_path(), "--groups", "b", "--quiet", "--strict"]
    assert mudrft_main(example) == 0  # a fit that describes its data passes
    assert capsys.readouterr().err == ""


# --------------------------------------------------------------------------------------
# a log as a lab's logger writes it (issue 39)
# --------------------------------------------------------------------------------------
def _lab_log(path, names, *, sep="\t"):
    """A 20 mm/s plate test of the paper's W = 25 % mud, as a logger writes it: a force in N
    on a 40 x 40 mm plate, depth in mm, a column mudrft does not read, tab-separated."""
    truth = mudrft.paper_parameters(0.25)
    (tr,) = synthetic_dataset(
        truth, speeds=(0.02,), noise=0.005, dt=0.02, hold=0.5, characteristic_length=0.04
    )
    rows = "".join(
        f"{t:.3f}{sep}{1e3 * q:.4f}{sep}{s * 0.0016:.5f}{sep}21.5\n"
        for t, q, s in zip(tr.time, tr.depth, tr.stress, strict=True)
    )
    path.write_text(sep.join(names) + "\n" + rows)
    return truth


def _alpha(path):
    return json.loads(path.read_text())["parameters"]["alpha"]


def test_a_tab_separated_lab_log_calibrates_with_columns_and_units_on_the_options(tmp_path, capsys):
    fit = ["--groups", "alpha", "--quiet", "--length", "40mm"]
    truth = _lab_log(tmp_path / "lab.txt", ("Time (s)", "Depth (mm)", "Force (N)", "Temp (C)"))
    assert main([str(tmp_path / "lab.txt"), "--area", "1600mm^2", *fit, "--out", str(tmp_path / "a.json")]) == 0  # fmt: skip
    german = tmp_path / "de.txt"
    _lab_log(german, ("Zeit (s)", "Weg (mm)", "Kraft (N)", "Temperatur (C)"))
    assert main([str(german), "--area", "1600mm^2", *fit]) == 2
    err = capsys.readouterr().err
    assert "no time column" in err and "--columns time=NAME" in err
    columns = 'time="Zeit (s)",depth="Weg (mm)",force="Kraft (N)"'
    out = tmp_path / "b.json"
    assert (
        main([str(german), "--columns", columns, "--area", "0.0016", *fit, "--out", str(out)]) == 0
    )
    # the same numbers in SI (1600 mm^2 is 0.0016 m^2 to round-off)
    assert _alpha(out) == pytest.approx(_alpha(tmp_path / "a.json"), rel=1e-9)
    assert _alpha(out) == pytest.approx(truth.alpha, rel=0.02)
