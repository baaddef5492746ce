"""mudrft reproduce: the pinned summary.csv, figures, report and refusal to overwrite."""

from __future__ import annotations

import csv
import logging

import pytest

from mudrft._validation import MudrftError
from mudrft.reproduce import FEET, SUMMARY_COLUMNS, read_summary, reproduce

PINNED = [
    "foot",
    "speed [m/s]",
    "water_content",
    "peak_support [N]",
    "max_suction [N]",
    "impulse_x [N s]",
    "impulse_y [N s]",
    "impulse_z [N s]",
    "energy [J]",
    "sinking [m]",
]


@pytest.fixture(scope="module")
def full_run(tmp_path_factory):
    pytest.importorskip("matplotlib")  # the full run draws the figures
    out = tmp_path_factory.mktemp("reproduce")
    rows = reproduce(out, quiet=True)
    return out, rows


def test_summary_has_the_pinned_columns_and_every_combination(full_run):
    out, rows = full_run
    with open(out / "summary.csv", newline="") as fh:
        header = next(csv.reader(fh))
    assert header[: len(PINNED)] == PINNED
    assert tuple(header) == SUMMARY_COLUMNS
    back = read_summary(out / "summary.csv")
    assert len(back) == len(rows) == 4 * 3 * 3
    assert {r["foot"] for r in back} == set(FEET)
    assert {r["speed [m/s]"] for r in back} == {0.13, 0.2, 0.26}
    assert {r["water_content"] for r in back} == {0.25, 0.35, 0.45}
    for r in back:
        assert r["max_suction [N]"] >= 0 and r["energy [J]"] >= 0 and r["sinking [m]"] > 0


def test_figures_and_report(full_run):
    out, _ = full_run
    for name in (
        "fig09_forces.png",
        "fig10_normalized.png",
        "fig12_hysteresis.png",
        "fig13_suction_energy.png",
    ):
        assert (out / name).stat().st_size > 10_000
    report = (out / "report.md").read_text()
    for claim in ("largest suction", "40 %", "57 %", "water content", "speed", "sinks least"):
        assert claim in report
    assert "claims agree" in report and ("differs" in report or "agrees" in report)


def test_refuses_to_overwrite_without_force(full_run):
    out, _ = full_run
    before = (out / "summary.csv").read_bytes()
    with pytest.raises(MudrftError, match="--force"):
        reproduce(out, quiet=True)
    assert (out / "summary.csv").read_bytes() == before


def test_subset_and_force(tmp_path, caplog):
    with caplog.at_level(logging.INFO, logger="mudrft"):
        rows = reproduce(
            tmp_path, feet=("flat",), speeds=(0.2,), water_contents=(0.25,), figures=False
        )
    assert len(rows) == 1
    assert "[ 1/1]" in caplog.text  # progress is shown, through the mudrft logger
    rows = reproduce(
        tmp_path,
        force=True,
        feet=("semi-sphere",),
        speeds=(0.13,),
        water_contents=(0.35,),
        figures=False,
        quiet=True,
    )
    assert rows[0]["foot"] == "semi-sphere"
    with pytest.raises(MudrftError, match="speeds"):
        reproduce(tmp_path / "x", speeds=(0.0,), quiet=True)
