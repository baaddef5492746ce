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
            depths=(),
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
    assert cyl.mudrft.startswith("gait: suction +25 %, s_c/s_f = 0.67")
    assert "Energy in the gait +25 %" in cyl.mudrft
    assert cyl.short == "+25 %, s_c/s_f 0.67"
    assert flat.mudrft.startswith("gait: suction -17 %")  # 50 N against 60 N


def test_the_morphing_percentages_need_158_together_and_are_judged_on_the_suction():
    """-57 % and -32 % are the walking tests' (Fig. 13): each is judged on its own, within
    +-10 points, in the gait or the load-carrying stance; the cells say that together they
    need s_c/s_f = 1.58 and that the energies are not compared."""
    cells = _morphing_cells(40.8, 1.0)  # 32 % below the flat foot's 60 N, 2 % above 40 N
    assert cells["morphing-vs-flat"].verdict == "agrees"
    assert cells["morphing-vs-semi-cylinder"].verdict == "differs"
    for c in cells.values():
        assert "Both percentages together need s_c/s_f = 1.58" in c.mudrft
        assert "not compared" in c.mudrft
    assert "load-carrying" not in cells["morphing-vs-flat"].mudrft  # not run here


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
    for verdict in ("agrees", "partly", "differs", "not evaluated"):
        assert f"*{verdict}*" in how
    for tolerance in ("+-10 points", "100 +- 25 %", "below 15 %", "below 30 %"):
        assert tolerance in how
    assert "kPa" in how and "(9)-(14) here" in how  # units and the equation numbers


def test_no_column_of_the_reports_tables_is_named_twice(small_report):
    """The matrix's header was '| claim | paper | paper | paper-restart | ...': the paper's
    value and the headline reading had the same name."""
    headers = [
        ln
        for ln in small_report.splitlines()
        if ln.startswith("| claim |") and "the paper says" in ln
    ]
    assert len(headers) == 2
    for header in headers:
        names = [x.strip() for x in header.strip("|").split("|")]
        assert len(names) == len(set(names)), names
        assert "the paper says" in names
    assert "paper (headline)" in headers[1]


def test_the_report_gives_every_csv_column_with_its_unit(small_report):
    from mudrft.reproduce import SUMMARY_COLUMNS
    from mudrft.reproduce.report import CLAIMS_COLUMNS, DEPTHS_COLUMNS

    files = small_report.split("## Files")[1]
    for col in (*SUMMARY_COLUMNS, *CLAIMS_COLUMNS, *DEPTHS_COLUMNS):
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
