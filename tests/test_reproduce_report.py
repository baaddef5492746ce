"""mudrft reproduce as a reviewer reads it: outputs it must not replace, progress that names
the runs, report.md readable without docs/model.md, figures that say their conditions, and
the numbers docs/model.md quotes from the run (D140-D142)."""

from __future__ import annotations

import logging
import re

import pytest

from mudrft._validation import MudrftError
from mudrft.reproduce import READINGS, reproduce

SMALL = {"feet": ("flat",), "speeds": (0.2,), "water_contents": (0.25,), "figures": False}


@pytest.mark.parametrize("name", ["report.md", "claims.csv"])
def test_an_existing_output_other_than_summary_is_not_replaced_without_force(tmp_path, name):
    """The library call checked summary.csv only: a report.md of one's own was replaced."""
    (tmp_path / name).write_text("mine")
    with pytest.raises(MudrftError, match=rf"{re.escape(name)}.*--force"):
        reproduce(tmp_path, quiet=True, **SMALL)
    assert (tmp_path / name).read_text() == "mine"
    assert not (tmp_path / "summary.csv").exists()
    reproduce(tmp_path, force=True, quiet=True, **SMALL)
    assert (tmp_path / name).read_text() != "mine"


def test_a_figure_name_is_free_when_no_figures_are_written(tmp_path):
    (tmp_path / "fig09_forces.png").write_text("mine")
    reproduce(tmp_path, quiet=True, **SMALL)
    assert (tmp_path / "fig09_forces.png").read_text() == "mine"


def test_progress_names_a_shared_run_by_the_first_reading_that_needs_it(tmp_path, caplog):
    """The headline's flat-foot run at W = 25 % is also the text-labels reading's '15 %' run;
    progress named it by the last reading ('paper-text-labels ... W = 15 %'), so the
    headline's own run never showed."""
    readings = (READINGS[0], next(r for r in READINGS if r.key == "paper-text-labels"))
    with caplog.at_level(logging.INFO, logger="mudrft"):
        reproduce(
            tmp_path,
            feet=("flat",),
            speeds=(0.2,),
            water_contents=(0.25, 0.35),
            readings=readings,
            figures=False,
        )
    lines = [r.getMessage() for r in caplog.records if r.getMessage().startswith("[")]
    assert len(lines) == 2  # two rows, each run once
    assert re.search(r"\] paper +flat +0\.20 m/s +W = 25 %", lines[0]), lines
    assert re.search(r"\] paper +flat +0\.20 m/s +W = 35 %", lines[1]), lines
