"""The training examples in their smoke settings: examples/train_mud_walker.py (PPO on
fields of mud and on rigid ground, compared on held-out fields, issue 42) and
examples/train_mud_walker_brax.py (Brax's PPO on the MJX walker; extra ``rl-brax``)."""

from __future__ import annotations

import csv
import importlib.util
import json
from pathlib import Path

import pytest

pytest.importorskip("mujoco")
pytest.importorskip("numba")

EXAMPLE = Path(__file__).parents[2] / "examples" / "train_mud_walker.py"
SMOKE = ["--steps", "256", "--eval-every", "128", "--eval-episodes", "1", "--episode-steps", "20"]


def _example():
    spec = importlib.util.spec_from_file_location("train_mud_walker", EXAMPLE)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.filterwarnings("ignore::DeprecationWarning")  # torch's and SB3's own
@pytest.mark.filterwarnings("ignore::UserWarning")
def test_the_smoke_setting_trains_both_policies_and_compares_them(tmp_path, capsys, monkeypatch):
    pytest.importorskip("stable_baselines3")
    import tempfile

    scratch = tmp_path / "tmp"  # SB3's default logger made a folder in the temp directory
    scratch.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(scratch))
    ex = _example()
    out = tmp_path / "out"
    assert ex.main(["--out", str(out), *SMOKE]) == 0
    assert [p.name for p in scratch.iterdir() if p.name.startswith("SB3-")] == []  # (torch caches)
    tmp_path = out
    rows = list(csv.DictReader((tmp_path / "results.csv").open()))
    assert [r["trained_on"] for r in rows] == ["mud", "rigid"]
    for r in rows:
        assert 0.0 <= float(r["success_rate"]) <= 1.0
        assert float(r["sinking_per_step [mm]"]) > 0.0  # evaluated in the mud, both of them
    curve = list(csv.DictReader((tmp_path / "curves.csv").open()))
    assert [int(c["steps"]) for c in curve] == [128, 256] * 2  # one PPO rollout an evaluation
    run = json.loads((tmp_path / "run.json").read_text())
    assert run["wall_time [s]"] > 0 and "CPUs" in run["machine"]
    assert (tmp_path / "curves.png").stat().st_size > 1000
    assert "| mud |" in capsys.readouterr().out
    with pytest.raises(SystemExit):  # no overwrite without --force
        ex.main(["--out", str(tmp_path), *SMOKE])


BRAX_EXAMPLE = EXAMPLE.with_name("train_mud_walker_brax.py")
BRAX_SMOKE = ["--steps", "640", "--num-envs", "8", "--episode-steps", "20", "--evals", "2"]


@pytest.mark.slow  # Brax's PPO and the MJX walker compile for about a minute on a CPU
@pytest.mark.filterwarnings("ignore::DeprecationWarning")
def test_the_brax_example_trains_the_mjx_walker(tmp_path):
    pytest.importorskip("brax")
    pytest.importorskip("mujoco.mjx")
    spec = importlib.util.spec_from_file_location("train_mud_walker_brax", BRAX_EXAMPLE)
    ex = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(ex)
    assert ex.main(["--out", str(tmp_path), *BRAX_SMOKE]) == 0
    curve = list(csv.DictReader((tmp_path / "curves.csv").open()))
    assert [int(c["steps"]) for c in curve] == [0, 640]  # an evaluation before and after
    for c in curve:  # an episode of 20 control steps: at most 20 x (1 + 5 x speed)
        assert 0.0 < float(c["eval_return"]) < 20 * (1 + 5 * 2.0)
        assert abs(float(c["eval_forward_speed [m/s]"])) < 2.0
    run = json.loads((tmp_path / "run.json").read_text())
    assert run["wall_time [s]"] > 0 and run["device"].startswith("cpu")
    with pytest.raises(SystemExit):  # no overwrite without --force
        ex.main(["--out", str(tmp_path), *BRAX_SMOKE])
