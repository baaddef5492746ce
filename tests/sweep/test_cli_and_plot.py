"""``mudrft sweep``: outputs, resume and force, one-line errors; maps and sensitivity."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import mudrft
from mudrft.cli import main
from mudrft.sweep import SweepSpec, load_spec, plot_maps, sensitivity
from mudrft.sweep.run import SweepWarning

xr = pytest.importorskip("xarray")
pytest.importorskip("zarr")
pytest.importorskip("matplotlib")

SPEC = """
[sweep]
metrics = ["max_suction", "peak_support"]
[foot]
kind = "flat"
width = [0.05, 0.065]
[mud]
water_content = [0.25, 0.35]
[motion]
speed = [0.2, 0.26]
[plot]
metrics = ["max_suction"]
"""


def run(capsys, *args):
    code = main(list(args))
    out = capsys.readouterr()
    return code, out.out, out.err


def test_sweep_writes_store_table_and_maps_and_never_overwrites(tmp_path, capsys):
    (tmp_path / "s.toml").write_text(SPEC)
    out = tmp_path / "maps"
    args = ("sweep", str(tmp_path / "s.toml"), "--out", str(out), "--scheduler", "serial")
    code, stdout, err = run(capsys, *args, "--plot")
    assert code == 0, err
    assert sorted(p.name for p in out.iterdir()) == ["max_suction.png", "points.csv", "sweep.zarr"]
    assert "8 points, 0 failed" in stdout and "  sweep: 100 %" in err
    rows = (out / "points.csv").read_text().splitlines()
    assert rows[0] == (
        "width [m],water_content,speed [m/s],foot,max_suction [N],peak_support [N],error"
    )
    assert len(rows) == 9
    ds = mudrft.sweep.load_result(out / "sweep.zarr")
    assert float(ds.max_suction.sel(width=0.05, water_content=0.25, speed=0.2)) > 0
    # an existing store: one line naming both ways on
    code, _, err = run(capsys, *args)
    assert code == 2 and err.strip().endswith("pass --resume to continue it or --force to start again")  # fmt: skip
    # --resume keeps the store, but points.csv exists: --force replaces the derived files
    code, _, err = run(capsys, *args, "--resume")
    assert code == 2 and "points.csv' exists; pass --force" in err
    code, stdout, _ = run(capsys, *args, "--resume", "--force", "--quiet")
    assert code == 0 and "wrote" in stdout
    assert not [p for p in out.iterdir() if p.name.startswith(".")]  # no temporary files left


def test_sweep_errors_are_one_line(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text('[foot]\nkind = "flat"\nradius = 0.04\n')
    code, _, err = run(capsys, "sweep", str(bad), "--out", str(tmp_path / "o"))
    assert code == 2 and err.count("\n") == 1
    assert "mudrft sweep: error: [foot] radius: not a parameter of the flat foot" in err
    assert not (tmp_path / "o").exists()  # nothing made before the spec is good
    (tmp_path / "s.toml").write_text(SPEC)
    code, _, err = run(capsys, "sweep", str(tmp_path / "s.toml"), "--out", str(tmp_path / "o"), "--workers", "0")  # fmt: skip
    assert code == 2 and "workers (CLI: --workers) must be an integer >= 1, got 0" in err
    assert not (tmp_path / "o").exists()


def test_help_lists_sweep(capsys):
    with pytest.raises(SystemExit):
        main(["--help"])
    assert "sweep" in capsys.readouterr().out


def _grid() -> xr.Dataset:
    a, b, c = np.array([1.0, 2.0, 3.0]), np.array([10.0, 20.0]), np.array(["x", "y"])
    m = a[:, None, None] * 2 + b[None, :, None] * 0.1 + (c == "y")[None, None, :] * 0.01
    m[0, 0, 0] = np.nan  # a failed point
    return xr.Dataset(
        {"m": (("a", "b", "c"), m), "error": (("a", "b", "c"), np.full(m.shape, ""))},
        coords={"a": a, "b": b, "c": c},
    )


def test_grid_maps_one_panel_per_value_of_the_third_parameter():
    import matplotlib.pyplot as plt

    fig = plot_maps(_grid(), "m")
    try:
        panels = [ax for ax in fig.axes if ax.get_title().startswith("c = ")]
        assert [ax.get_title() for ax in panels] == ["c = x", "c = y"]
        assert panels[0].get_xlabel() == "a" and panels[0].get_ylabel() == "b"
    finally:
        plt.close(fig)
    with pytest.raises(mudrft.MudrftError, match="metric must be one of m, got 'q'"):
        plot_maps(_grid(), "q")
    with pytest.raises(mudrft.MudrftError, match="x must be a swept parameter"):
        plot_maps(_grid(), "m", x="z")


def test_map_titles_carry_the_units_of_the_values_they_name():
    # a panel read 'speed = 0.13' with the unit only in the axis labels of other plots
    import matplotlib.pyplot as plt

    grid = _grid()
    grid["a"].attrs["units"] = "m/s"
    grid["c"].attrs["units"] = "-"
    fig = plot_maps(grid, "m", x="b", y="c", panels="a")
    try:
        titles = [ax.get_title() for ax in fig.axes if ax.get_title()]
        assert titles == ["a = 1 m/s", "a = 2 m/s", "a = 3 m/s"]
    finally:
        plt.close(fig)
    deeper = grid.expand_dims(d=[0.02, 0.03])
    deeper["d"].attrs["units"] = "m"
    fig = plot_maps(deeper, "m", x="b", y="a", panels="c")  # d held at its first value
    try:
        assert "at d = 0.02 m" in fig.get_suptitle()
        assert [ax.get_title() for ax in fig.axes if ax.get_title()] == ["c = x", "c = y"]
    finally:
        plt.close(fig)


def test_sensitivity_ranks_parameters():
    grid = _grid()
    grid["m"][0, 0, 0] = 2.0 + 1.0  # no failed point: the main effects' spreads are exact
    ranked = sensitivity(grid, "m")
    assert [name for name, _ in ranked] == ["a", "b", "c"]  # also the foot kind, a string
    assert [v for _, v in ranked] == pytest.approx([4.0, 1.0, 0.01])
    assert all(np.isfinite(v) for _, v in sensitivity(_grid(), "m"))  # failed points skipped
    rng = np.random.default_rng(0)
    p, q = rng.uniform(size=50), rng.uniform(size=50)
    ds = xr.Dataset(
        {"m": ("point", -3 * p + 0.2 * q)},
        coords={"point": np.arange(50), "p": ("point", p), "q": ("point", q)},
    )
    ranked = sensitivity(ds, "m")
    assert ranked[0][0] == "p" and ranked[0][1] < -0.9 and abs(ranked[1][1]) < 0.5
    import matplotlib.pyplot as plt

    plt.close(plot_maps(ds, "m", x="p", y="q"))


def test_warnings_at_points_are_reported_once_per_message():
    spec = load_spec(
        {
            "sweep": {"metrics": ["max_depth"]},
            "foot": {"kind": "flat"},
            "mud": {"water_content": [0.46, 0.47], "extrapolate": True},
        }
    )
    assert isinstance(spec, SweepSpec)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        ds = mudrft.sweep(spec, scheduler="serial")
    mine = [w for w in caught if issubclass(w.category, SweepWarning)]
    assert len(mine) == 2 and all("extrapolated" in str(w.message) for w in mine)
    assert np.isfinite(ds["max_depth"].values).all()


def test_sensitivity_example_runs_on_a_small_sample(tmp_path, capsys):
    import runpy
    from pathlib import Path

    path = Path(__file__).resolve().parents[2] / "examples" / "sweep_sensitivity.py"
    example = runpy.run_path(str(path), run_name="sweep_sensitivity")
    figure = tmp_path / "s.png"
    ranked = example["main"](["--n", "8", "--serial", "--out", str(figure)])
    assert sorted(name for name, _ in ranked) == sorted(f"{k}_scale" for k in example["FACTORS"])
    assert figure.stat().st_size > 0 and "Spearman" in capsys.readouterr().out


def test_a_sweep_with_failed_points_exits_with_1_and_says_how_many(tmp_path, capsys):
    """Failed points are recorded, not fatal; but the command says how many, even under
    --quiet, and exits with 1 (it exited with 0 unless every point failed)."""
    spec = SPEC.replace('kind = "flat"', 'kind = ["flat", "semi-sphere"]')
    spec = spec.replace("water_content = [0.25, 0.35]", "water_content = 0.25")
    spec = spec.replace("speed = [0.2, 0.26]", "speed = 0.2")
    (tmp_path / "s.toml").write_text(spec)
    args = ("sweep", str(tmp_path / "s.toml"), "--out", str(tmp_path / "o"), "--quiet")
    code, stdout, err = run(capsys, *args, "--scheduler", "serial")
    assert code == 1, err
    assert "4 points, 2 failed" in stdout
    assert err.strip().endswith(f"mudrft sweep: error: 2 of 4 points failed (NaN metrics; each error in the 'error' column of {tmp_path / 'o' / 'points.csv'})")  # fmt: skip
    assert (tmp_path / "o" / "points.csv").read_text().count("has no parameter 'width'") == 2


def test_a_value_out_of_range_is_refused_before_anything_runs(tmp_path, capsys):
    # width = [0.05, -0.01] ran, half the points failed, and --quiet exited 0 saying nothing
    (tmp_path / "s.toml").write_text(SPEC.replace("width = [0.05, 0.065]", "width = [0.05, -0.01]"))  # fmt: skip
    code, _, err = run(capsys, "sweep", str(tmp_path / "s.toml"), "--out", str(tmp_path / "o"), "--quiet")  # fmt: skip
    assert code == 2 and err.strip() == "mudrft sweep: error: [foot] width must be > 0 [m], got -0.01"  # fmt: skip
    assert not (tmp_path / "o").exists()
