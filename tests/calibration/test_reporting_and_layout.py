"""How a fit reports (logging and progress, never print) and what calibration may import."""

from __future__ import annotations

import ast
import logging
from pathlib import Path

import pytest

import mudrft
from mudrft._validation import MudrftError
from mudrft.calibration import calibrate, synthetic_dataset

SRC = Path(mudrft.__file__).parent


@pytest.fixture(scope="module")
def small_data():
    p = mudrft.paper_parameters(0.25, "vertical")
    return synthetic_dataset(p, speeds=(0.02,), noise=0.01, seed=1, dt=0.02)


def test_notes_go_to_the_calibration_logger(small_data, caplog, capsys):
    with caplog.at_level(logging.INFO, logger="mudrft.calibration"):
        calibrate(small_data, groups="alpha", phases=False)
    notes = [r.getMessage() for r in caplog.records if r.name == "mudrft.calibration"]
    assert notes[0].startswith("calibrate: 1 trial(s)")
    assert any(n.startswith("calibrate: stage joint") for n in notes)
    assert notes[-1].startswith("calibrate: done")
    out = capsys.readouterr()
    assert out.out == "" and out.err == ""  # nothing printed without progress=True


def test_progress_callable_receives_each_line_and_true_reports_percentages(small_data, caplog):
    lines: list[str] = []
    calibrate(small_data, groups="b", progress=lines.append)
    assert all(isinstance(s, str) for s in lines)
    assert [s.split()[2] for s in lines if s.startswith("calibrate: stage")] == [
        "intrusion",
        "joint",
    ]
    with caplog.at_level(logging.INFO, logger="mudrft"):
        calibrate(small_data, groups="alpha", phases=False, progress=True)
    pct = [r.getMessage() for r in caplog.records if r.name == "mudrft.progress"]
    assert pct and pct[-1].strip() == "calibrate: 100 %"


def test_bad_progress_is_refused(small_data):
    with pytest.raises(MudrftError, match="progress must be True, False, None or a callable"):
        calibrate(small_data, progress="loud")


def _imports(path: Path) -> set[str]:
    """Absolute names of the mudrft modules a source file imports."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    package = ".".join(path.relative_to(SRC.parent).with_suffix("").parts[:-1])
    names = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom):
            base = package.split(".")
            if node.level:
                base = base[: len(base) - node.level + 1]
                names.add(".".join([*base, node.module or ""]).rstrip("."))
            else:
                names.add(node.module or "")
        elif isinstance(node, ast.Import):
            names.update(a.name for a in node.names)
    return {n for n in names if n.startswith("mudrft")}


@pytest.mark.parametrize("package", ["calibration", "io"])
def test_imports_point_down(package):
    """Calibration and io never import the backends, the integrations or the CLI."""
    forbidden = ("mudrft.backends", "mudrft.integrations", "mudrft.cli")
    for path in sorted((SRC / package).glob("*.py")):
        if path.name == "cli.py":
            continue  # the calibrate subcommand is CLI code
        bad = [n for n in _imports(path) if n.startswith(forbidden)]
        assert not bad, (path.name, bad)


@pytest.mark.parametrize("package", ["calibration", "io"])
def test_modules_are_rooms_a_newcomer_can_hold_in_mind(package):
    for path in sorted((SRC / package).glob("*.py")):
        n = len(path.read_text(encoding="utf-8").splitlines())
        assert n <= 500, (path.name, n)
