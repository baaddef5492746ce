"""The mudrft command: output, files, and one-line errors for user mistakes."""

from __future__ import annotations

import numpy as np
import pytest

from mudrft.cli import main


def run(capsys, *args):
    code = main(list(args))
    out = capsys.readouterr()
    return code, out.out, out.err


def test_params_lists_both_tables(capsys):
    code, out, _ = run(capsys, "params")
    assert code == 0
    assert "Table S1" in out and "Table S2" in out
    assert out.count("%") >= 6 and "violates" in out


def test_help_lists_the_stable_commands(capsys):
    with pytest.raises(SystemExit):
        main(["--help"])
    out = capsys.readouterr().out
    for cmd in ("params", "simulate", "reproduce"):
        assert cmd in out


def test_simulate_writes_run_csv_and_refuses_to_overwrite(tmp_path, capsys):
    out = tmp_path / "run.csv"
    code, _stdout, _ = run(
        capsys,
        "simulate",
        "--foot",
        "flat",
        "--water-content",
        "0.25",
        "--speed",
        "0.2",
        "--out",
        str(out),
    )
    assert code == 0 and out.exists()
    assert out.read_text().splitlines()[0] == "time [s],x [m],y [m],z [m],Fx [N],Fy [N],Fz [N]"
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    assert data.shape[1] == 7 and np.all(np.isfinite(data))
    before = out.read_bytes()
    code, _, err = run(capsys, "simulate", "--foot", "flat", "--out", str(out))
    assert code == 2 and "--force" in err and "Traceback" not in err
    assert out.read_bytes() == before


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["simulate", "--foot", "banana", "--out", "x.csv"], "foot"),
        (["simulate", "--foot", "flat", "--speed", "0", "--out", "x.csv"], "speed"),
        (["simulate", "--foot", "flat", "--speed", "-1", "--out", "x.csv"], "speed"),
        (
            ["simulate", "--foot", "flat", "--water-content", "0.9", "--out", "x.csv"],
            "water_content",
        ),
    ],
)
def test_simulate_bad_input_is_one_line(tmp_path, capsys, monkeypatch, args, needle):
    monkeypatch.chdir(tmp_path)
    code, _, err = run(capsys, *args)
    assert code == 2
    assert needle in err and "Traceback" not in err and err.count("\n") == 1


def test_reproduce_refuses_existing_results_and_unwritable_dirs(tmp_path, capsys):
    (tmp_path / "summary.csv").write_text("keep me")
    code, _, err = run(capsys, "reproduce", "--out", str(tmp_path))
    assert code == 2 and "--force" in err
    assert (tmp_path / "summary.csv").read_text() == "keep me"
    blocker = tmp_path / "file"
    blocker.write_text("")
    code, _, err = run(capsys, "reproduce", "--out", str(blocker))
    assert code == 2 and "not a directory" in err
