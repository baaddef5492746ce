"""A fuzz of the command line: each mistake found there is one line naming the option.

Every test goes through ``mudrft.cli.main`` only.
"""

from __future__ import annotations

from importlib import resources

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
