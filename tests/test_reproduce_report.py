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


def _morphing_cells(morph_suction, morph_energy):
    """The two morphing-vs cells of the headline on made-up numbers [N, J]."""
    from mudrft.reproduce import FEET, HEADLINE, evaluate

    numbers = {
        "flat": {"peak_ns": 3.0, "min_ns": -3.0, "max_suction": 60.0, "energy": 2.0},
        "semi-cylinder": {"peak_ns": 2.0, "min_ns": -2.0, "max_suction": 40.0, "energy": 2.0},
        "semi-sphere": {"peak_ns": 1.0, "min_ns": -1.0, "max_suction": 20.0, "energy": 2.0},
        "morphing": {"peak_support": 100.0, "max_suction": morph_suction, "energy": morph_energy},
    }
    cells = evaluate(
        HEADLINE,
        lambda foot, speed, row: numbers[foot],
        lambda foot, row: 0.01,
        feet=list(FEET),
        speeds=[0.2],
        rows=[0.25],
    )
    return {c.claim: c for c in cells if c.claim.startswith("morphing-vs")}


def test_a_morphing_foot_worse_than_a_fixed_one_is_a_plus_not_a_double_minus():
    """'suction -{reduction} %' printed 'suction --25 %' for a morphing foot with more
    suction than the semi-cylinder."""
    cells = _morphing_cells(50.0, 2.5)  # 25 % more suction and energy than the semi-cylinder
    cyl, flat = cells["morphing-vs-semi-cylinder"], cells["morphing-vs-flat"]
    assert "--" not in cyl.mudrft + cyl.short + flat.mudrft + flat.short
    assert cyl.mudrft.startswith("suction +25 %, energy +25 %")
    assert cyl.short.startswith("+25 % / +25 %")
    assert flat.mudrft.startswith("suction -17 %, energy +25 %")  # 50 N against 60 N


def test_what_matching_one_percentage_does_to_the_other_is_said_with_its_direction():
    """s_c/s_f = 40/60: matching -57 % leaves 17.2 N, 71 % below the flat foot's 60 N;
    matching -32 % leaves 40.8 N, 2 % above the semi-cylinder's 40 N (printed before as
    'the semi-cylinder reduction -2 %')."""
    cells = _morphing_cells(10.0, 1.0)
    assert "suction 71 % below the flat foot's (the paper: 32 % below)" in (
        cells["morphing-vs-semi-cylinder"].mudrft
    )
    assert "suction 2 % above the semi-cylinder's (the paper: 57 % below)" in (
        cells["morphing-vs-flat"].mudrft
    )


def test_the_headline_cites_the_figures_that_state_25_percent():
    """Figs. 9 and 12 state W = 25 % in their captions; Fig. 11's caption states none."""
    from mudrft.reproduce import HEADLINE

    cited = HEADLINE.derivation.split("stated at '25 %' (")[1].split(")")[0]
    assert re.findall(r"\d+", cited) == ["9", "12"]


@pytest.fixture(scope="module")
def small_report(tmp_path_factory):
    out = tmp_path_factory.mktemp("small")
    reproduce(out, quiet=True, **SMALL)
    return (out / "report.md").read_text()


def test_the_report_says_what_a_reading_and_each_verdict_are(small_report):
    """report.md used 'reading', 'agrees', 'partly' and the tolerances without saying what
    they are, or that the headline was fixed before its verdicts were seen (docs/model.md
    said it)."""
    how = small_report.split("## How to read this report")[1].split("\n## ")[0]
    assert "A *reading* fixes each choice" in how
    assert "before any of its verdicts was computed" in how
    for verdict in ("agrees", "partly", "differs", "inconsistent in the paper", "not evaluated"):
        assert f"*{verdict}*" in how
    for tolerance in ("+-10 points", "100 +- 25 %", "below 15 %", "below 30 %"):
        assert tolerance in how
    assert "kPa" in how and "(9)-(14) here" in how  # units and the equation numbers


def test_no_column_of_the_reports_tables_is_named_twice(small_report):
    """The matrix's header was '| claim | paper | paper | paper-restart | ...': the paper's
    value and the headline reading had the same name."""
    headers = [ln for ln in small_report.splitlines() if ln.startswith("| claim |")]
    assert len(headers) == 2
    for header in headers:
        names = [x.strip() for x in header.strip("|").split("|")]
        assert len(names) == len(set(names)), names
        assert "the paper says" in names
    assert "paper (headline)" in headers[1]


def test_the_report_gives_every_csv_column_with_its_unit(small_report):
    from mudrft.reproduce import SUMMARY_COLUMNS
    from mudrft.reproduce.report import CLAIMS_COLUMNS

    files = small_report.split("## Files")[1]
    for col in (*SUMMARY_COLUMNS, *CLAIMS_COLUMNS):
        assert f"`{col}`" in files, col
    for unitless in ("water_content", "suction_ratio", "normalized_suction_ratio"):
        assert f"`{unitless}` [-]" in files


def test_every_figure_says_its_speed_and_water_content(tmp_path, monkeypatch):
    """Figs. 10, 12 and 13 did not say at which speed (and Figs. 10, 13 at which water
    content) they were drawn."""
    pytest.importorskip("matplotlib")
    import matplotlib.figure

    from mudrft.reproduce.runner import FIGURES

    texts: dict[str, str] = {}
    save = matplotlib.figure.Figure.savefig

    def record(fig, fname, *args, **kwargs):
        parts = [fig.get_suptitle(), *(ax.get_title() for ax in fig.axes)]
        texts[str(fname).rsplit("/", 1)[-1]] = " ".join(parts)
        return save(fig, fname, *args, **kwargs)

    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", record)
    reproduce(
        tmp_path,
        feet=("flat", "morphing"),
        speeds=(0.13, 0.2),
        water_contents=(0.25, 0.35),
        readings=READINGS[:1],
        quiet=True,
    )
    assert tuple(texts) == FIGURES
    for name, text in texts.items():
        assert "0.2 m/s" in text and "W = 25 %" in text, (name, text)
