"""A foot's own path from a CSV file: ``mudrft.io.load_path_csv`` and ``simulate --path``."""

from __future__ import annotations

import numpy as np
import pytest

import mudrft
from mudrft._validation import MudrftError, PlausibilityWarning
from mudrft.cli import main
from mudrft.io import load_path_csv
from mudrft.trajectories import Trajectory


def write(tmp_path, text, name="tip.csv"):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_units_are_converted_and_absent_coordinates_are_zero(tmp_path):
    path = write(
        tmp_path,
        "# tip of the front-left foot\ntime [ms],x [mm],z [cm],note\n"
        "0,0,0.5,a\n100,1,-1,b\n250,3,-2,c\n",
    )
    tr = load_path_csv(path)
    assert isinstance(tr, Trajectory) and tr.name == "tip.csv"
    np.testing.assert_allclose(tr.time, [0.0, 0.1, 0.25])
    np.testing.assert_allclose(tr.position, [[0, 0, 0.005], [0.001, 0, -0.01], [0.003, 0, -0.02]])
    # each sample's velocity is the rate of the step that ends there (from_positions)
    np.testing.assert_allclose(tr.velocity[2], [0.002 / 0.15, 0.0, -0.01 / 0.15])


def test_a_depth_column_is_the_negative_of_z(tmp_path):
    tr = load_path_csv(write(tmp_path, "t,depth [mm]\n0,0\n1,20\n2,0\n"))
    np.testing.assert_allclose(tr.position[:, 2], [0.0, -0.02, 0.0])


def test_simulate_output_reads_back_as_the_path_it_ran(tmp_path):
    """The CSV of Result.to_csv (9 significant digits) is the path it ran; with the
    velocity of from_positions, as any sampled path gets it, it runs as that path does.
    Tolerance: the CSV's round-off (about 1e-11 m a position over a 1 ms step) moves the
    forces by up to 8e-5 N where the rate dependence is steep (measured); 1e-3 N against
    forces of up to 200 N."""
    gait = mudrft.gait(0.2)
    res = mudrft.simulate(mudrft.feet.Flat(), mudrft.paper_mud(0.25), gait)
    tr = load_path_csv(res.to_csv(tmp_path / "run.csv"))
    np.testing.assert_allclose(tr.time, gait.time, rtol=1e-8, atol=1e-12)
    np.testing.assert_allclose(tr.position, gait.position, rtol=1e-8, atol=1e-12)
    again = mudrft.simulate(mudrft.feet.Flat(), mudrft.paper_mud(0.25), tr)
    direct = mudrft.simulate(
        mudrft.feet.Flat(),
        mudrft.paper_mud(0.25),
        Trajectory.from_positions(gait.time, gait.position),
    )
    np.testing.assert_allclose(again.force, direct.force, rtol=0, atol=1e-3)


@pytest.mark.parametrize(
    ("text", "needles"),
    [
        ("time [s],x [m]\n0,0\n1,0\n", ("no z (or depth) column", "line 1")),
        ("x [m],z [m]\n0,0\n1,-1\n", ("no time column",)),
        ("time [s],z [m],depth [m]\n0,0,0\n1,-1,1\n", ("both give the tip's height",)),
        ("t [s],time [s],z [m]\n0,0,0\n1,1,-1\n", ("two columns give the time",)),
        ("time [s],z [m]\n0,0\n", ("1 data row", "at least 2")),
        ("time [s],z [m]\n0,0\n1,-0.01\n1,-0.02\n", ("line 4", "does not exceed")),
        ("time [s],z [furlong]\n0,0\n1,-1\n", ("line 1, column 2", "furlong")),
        ("time [s],z [m]\n0,0\n1,deep\n", ("line 3, column 2", "'deep'")),
        ("time [s];z [m]\n0;0\n", ("1 data row",)),
    ],
)
def test_mistakes_name_the_file_and_the_place(tmp_path, text, needles):
    path = write(tmp_path, text)
    with pytest.raises(MudrftError) as info:
        load_path_csv(path)
    message = str(info.value)
    assert message.startswith(str(path))
    for needle in needles:
        assert needle in message, message


def test_a_path_that_never_enters_the_mud_warns(tmp_path):
    with pytest.warns(PlausibilityWarning, match="never goes below the mud surface"):
        load_path_csv(write(tmp_path, "time [s],z [mm]\n0,0\n1,20\n2,0\n"))


def test_simulate_runs_a_path_and_refuses_it_with_gait_options(tmp_path, capsys):
    path = write(tmp_path, "time [ms],z [mm]\n0,5\n200,-20\n400,5\n")
    out = tmp_path / "run.csv"
    assert main(["simulate", "--foot", "flat", "--path", str(path), "--out", str(out)]) == 0
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    # resampled at --dt (1 ms), the path's 0.4 s; at 20 mm deep the mud pushes up
    assert data.shape == (401, 7)
    assert data[:, 3].min() == pytest.approx(-0.02) and data[:, 6].max() > 0
    capsys.readouterr()
    before = path.read_bytes()
    for extra, needle in (
        (["--speed", "0.2", "--out", str(tmp_path / "b.csv")], "--path replaces"),
        (["--out", str(path), "--force"], "is the --path file"),
    ):
        code = main(["simulate", "--foot", "flat", "--path", str(path), *extra])
        err = capsys.readouterr().err
        assert code == 2 and needle in err and err.count("\n") == 1, err
    assert path.read_bytes() == before and not (tmp_path / "b.csv").exists()


def test_measured_forces_are_kept_in_newtons(tmp_path):
    tr = load_path_csv(write(tmp_path, "time [s],z [mm],Fz [kN],Fx [mN]\n0,0,0,5\n1,-20,0.1,-5\n"))
    assert set(tr.meta["measured_force"]) == {"Fx", "Fz"}
    np.testing.assert_allclose(tr.meta["measured_force"]["Fz"], [0.0, 100.0])
    np.testing.assert_allclose(tr.meta["measured_force"]["Fx"], [0.005, -0.005])
    assert "measured_force" not in load_path_csv(write(tmp_path, "t,z\n0,0\n1,-0.01\n")).meta


def test_simulate_path_compares_with_the_forces_the_file_measured(tmp_path, capsys):
    """The relative RMSE of the paper's Table II, per force column of the file: the run that
    wrote the file predicts it within 0.5 % (measured 0.04-0.26 %: the file's velocities
    are step rates, the gait's analytic), another foot does not (12-31 %)."""
    measured = tmp_path / "flat.csv"
    assert main(["simulate", "--foot", "flat", "--out", str(measured), "--quiet"]) == 0
    errors = {}
    for foot in ("flat", "semi-sphere"):
        capsys.readouterr()
        out = tmp_path / f"{foot}.run.csv"
        assert main(["simulate", "--foot", foot, "--path", str(measured), "--out", str(out)]) == 0
        lines = [ln.split() for ln in capsys.readouterr().out.splitlines() if "rel_rmse" in ln]
        errors[foot] = {ln[0]: float(ln[1]) for ln in lines}
        assert set(errors[foot]) == {"rel_rmse_Fx", "rel_rmse_Fy", "rel_rmse_Fz"}
    assert max(errors["flat"].values()) < 0.005
    assert min(errors["semi-sphere"].values()) > 0.05
    constant = write(tmp_path, "time [s],z [mm],Fz [N]\n0,0,1\n0.2,-20,1\n0.4,0,1\n")
    capsys.readouterr()
    assert (
        main(["simulate", "--foot", "flat", "--path", str(constant), "--out", str(out) + "2"]) == 0
    )
    assert "rel_rmse_Fz     not defined: measured must not be constant" in capsys.readouterr().out
