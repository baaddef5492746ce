"""What the README and the guide say in words and numbers holds for the code.

test_snippets.py runs the pages' Python blocks and test_commands.py checks their command
lines; this file checks the prose around them where it names a set of things (the extras,
the metrics) or quotes a number the code computes, so that a change of the code that makes
the page wrong breaks a test instead of misleading a reader (decision D147).
"""

from __future__ import annotations

import re
import tomllib
from pathlib import Path

import numpy as np
import pytest

import mudrft
from mudrft.cli import main

REPO = Path(__file__).resolve().parents[2]
README = REPO / "README.md"
GETTING_STARTED = REPO / "docs" / "getting-started.md"
FORCES = REPO / "docs" / "guide" / "forces.md"


def _extras_table(page: Path) -> set[str]:
    """The extras named in the first cells of the page's ``| extra | for |`` table."""
    lines = page.read_text(encoding="utf-8").splitlines()
    start = lines.index("| extra | for |")
    names: set[str] = set()
    for line in lines[start + 2 :]:
        if not line.startswith("|"):
            break
        names |= set(re.findall(r"`([^`]+)`", line.split("|")[1]))
    return names


@pytest.mark.parametrize("page", [README, GETTING_STARTED], ids=lambda p: p.name)
def test_the_extras_table_lists_every_extra(page):
    """getting-started's table lacked mjx, rl, rl-train and sweep; the README's, docs."""
    pyproject = tomllib.loads((REPO / "pyproject.toml").read_text(encoding="utf-8"))
    extras = set(pyproject["project"]["optional-dependencies"]) - {"all", "test", "dev"}
    assert _extras_table(page) == extras


def _metric_names(line: str) -> set[str]:
    line = line.replace("impulse_x/y/z", "impulse_x impulse_y impulse_z")
    return set(re.findall(r"[a-z]+(?:_[a-z]+)+|energy", line))


def test_the_pages_that_list_the_metrics_list_them_all():
    """The README's, getting-started's and the forces guide's lists of ``Result.metrics()``
    ended at ``sinking`` (now ``max_depth``): ``suction_ratio`` [-] was missing. A list that
    elides some (``...``) names the first and the last."""
    keys = list(
        mudrft.simulate(mudrft.feet.Flat(), mudrft.paper_mud(0.25), mudrft.gait(0.26)).metrics()
    )
    lines = [
        line
        for page in (README, GETTING_STARTED, FORCES)
        for line in page.read_text(encoding="utf-8").splitlines()
        if "peak_support" in line and "max_suction" in line and "max_depth" in line
    ]
    assert len(lines) >= 4
    for line in lines:
        named = _metric_names(line)
        wanted = {keys[0], keys[-1]} if "..." in line else set(keys)
        assert wanted <= named, (line, sorted(wanted - named))


def test_the_explicit_time_step_limit_quoted_in_the_mujoco_guide():
    """The guide said 'about 0.5 ms for a 0.3 kg foot'; the flat foot's limit is 0.59 ms."""
    pytest.importorskip("mujoco")
    from mudrft.integrations.mujoco import stability_limits

    text = (REPO / "docs" / "guide" / "mujoco.md").read_text(encoding="utf-8")
    quoted = float(re.search(r"about ([\d.]+) ms for a 0\.3 kg flat foot 20 mm deep", text)[1])
    limit = stability_limits(mudrft.feet.Flat(), mudrft.paper_mud(0.25), mass=0.3, depth=0.02)
    assert round(limit["dt_viscous"] * 1e3, 1) == quoted


def test_the_semi_sphere_mesh_numbers_quoted_in_compare_feet():
    """'matches the closed form's peak support to 0.1 % and its horizontal impulse J_x to
    0.1 % (-18.94 against -18.96 N s at 0.2 m/s, W = 25 %)', with the page's mesh."""
    text = " ".join(
        (REPO / "docs" / "guide" / "compare-feet.md").read_text(encoding="utf-8").split()
    )
    m = re.search(
        r"peak support to ([\d.]+) % and its horizontal impulse \$J_x\$ to ([\d.]+) % "
        r"\(([-\d.]+) against ([-\d.]+) N s at 0\.2 m/s, W = 25 %\)",
        text,
    )
    assert m, "the sentence moved: update this test with it"
    sphere = mudrft.feet.SemiSphere(radius=0.045)
    mud, gait = mudrft.paper_mud(0.25), mudrft.gait(0.2)
    exact = mudrft.simulate(sphere, mud, gait).metrics()
    mesh = mudrft.simulate(sphere.to_mesh(resolution=24), mud, gait).metrics()
    assert abs(mesh["peak_support"] / exact["peak_support"] - 1) < float(m[1]) / 100
    assert abs(mesh["impulse_x"] / exact["impulse_x"] - 1) < float(m[2]) / 100
    assert np.round([mesh["impulse_x"], exact["impulse_x"]], 2).tolist() == [
        float(m[3]),
        float(m[4]),
    ]


def test_a_value_that_is_not_a_number_shows_the_usage_above_the_error_line(capsys, tmp_path):
    """The README: a value that is not a number shows the command's usage, then ends in the
    line ``mudrft COMMAND: error: ...``, exit status 2; a value the command checks is one
    line alone."""
    out = str(tmp_path / "run.csv")
    with pytest.raises(SystemExit) as exit_:
        main(["simulate", "--foot", "flat", "--speed", "abc", "--out", out])
    err = capsys.readouterr().err.splitlines()
    assert exit_.value.code == 2 and err[0].startswith("usage: mudrft simulate")
    assert err[-1] == "mudrft simulate: error: argument --speed: invalid float value: 'abc'"
    assert main(["simulate", "--foot", "flat", "--speed", "inf", "--out", out]) == 2
    assert len(capsys.readouterr().err.splitlines()) == 1
    assert not list(tmp_path.iterdir())
