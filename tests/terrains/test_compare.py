"""The terrain loop, the comparison and its outputs (Figs. S5, S6)."""

from __future__ import annotations

import csv
import logging

import numpy as np
import pytest

import mudrft
from mudrft import MudrftError
from mudrft.baselines import (
    CSV_COLUMNS,
    GranularRFT,
    LinearStiffness,
    MaxwellMud,
    RigidGround,
    compare,
    default_terrains,
    run_terrain,
    summarize,
    write_csv,
)
from mudrft.terrains import Terrain

REFERENCE = {
    "plate": lambda: mudrft.plate_intrusion(hold=0.3),
    "gait-slow": lambda: mudrft.gait(0.13),
    "gait-medium": lambda: mudrft.gait(0.2),
    "gait-fast": lambda: mudrft.gait(0.26),
}


def test_every_terrain_implements_the_protocol_with_no_arguments():
    import mudrft.terrains as T

    for cls in (
        T.GranularRFT,
        T.GranularRFT3D,
        T.LinearStiffness,
        T.MaxwellMud,
        T.RigidGround,
        T.Mud,
    ):
        t = cls()
        assert isinstance(t, Terrain) and isinstance(t.name, str)


def event_samples(tr: mudrft.Trajectory) -> np.ndarray:
    """Samples next to kinematic events: v_z changes sign (or to/from 0), entry and exit.

    A |v_z| below 1e-12 m/s counts as 0: the gaits reach their lowest point with a
    rounding residue (v_z = -1.2e-17 m/s at the bottom of gait(0.13)), where granular RFT's
    leading ramp (D53) already switches the bottom off, one sample before the sign flips.
    """
    vz = tr.velocity[:, 2]
    sz = np.sign(np.where(np.abs(vz) < 1e-12, 0.0, vz))
    inside = tr.depth > 0
    ev = np.zeros(len(tr), bool)
    ev[1:] |= sz[1:] != sz[:-1]
    ev[1:] |= inside[1:] != inside[:-1]
    ev[0] = True
    near = ev.copy()
    for k in (1, 2):  # the jump may land one or two samples after the event
        near[k:] |= ev[:-k]
    return near


@pytest.mark.parametrize("traj", list(REFERENCE))
def test_forces_are_finite_and_continuous_between_kinematic_events(box, traj):
    tr = REFERENCE[traj]()
    near = event_samples(tr)
    assert near.sum() < 0.05 * len(tr)  # events are a handful of samples
    for name, terrain in default_terrains().items():
        h = run_terrain(terrain, box, tr)
        assert np.all(np.isfinite(h.force)), name
        jump = np.abs(np.diff(h.force, axis=0)).max(axis=1)
        scale = np.abs(h.force).max()
        # away from events a 1 ms step moves the force by < 5 % of its peak (smooth inputs
        # give <= 2.5 %: the fastest, the Maxwell suction filter at 60 rad/s, moves
        # 0.54 omega dt sigma_Y A per step); at events (velocity or contact switches)
        # jumps stay bounded by the force range
        assert jump[~near[1:]].max() <= 0.05 * scale, (name, traj)
        assert jump.max() <= 1.01 * 2 * scale, (name, traj)


def test_compare_runs_every_terrain_on_the_same_motion(box):
    tr = mudrft.gait(0.26)
    out = compare(box, tr, [GranularRFT(), LinearStiffness(), MaxwellMud(), RigidGround()])
    assert list(out) == ["granular-rft", "linear", "maxwell", "rigid"]
    for name, h in out.items():
        np.testing.assert_array_equal(h.time, tr.time)
        ref = run_terrain(
            {
                "granular-rft": GranularRFT(),
                "linear": LinearStiffness(),
                "maxwell": MaxwellMud(),
                "rigid": RigidGround(),
            }[name],
            box,
            tr,
        )
        # the same steps; numpy 1.26's SIMD loops may round an element by an ulp
        # differently with the array's alignment (1.1e-16 N seen): 1e-12 of the peak
        peak = np.abs(ref.force).max()
        np.testing.assert_allclose(h.force, ref.force, rtol=0, atol=1e-12 * peak)
    with pytest.raises(MudrftError, match="unique"):
        compare(box, tr, [LinearStiffness(), LinearStiffness()])


def test_figure_s6_claims_hold(box):
    """Supplementary Sec. III-D: sand drops to zero on retraction, mud shows suction and a
    hysteresis loop, the linear model has neither."""
    tr = mudrft.plate_intrusion(depth=0.02, dt=2e-3)  # the 50 mm box is never buried
    out = compare(
        box, tr, {"mud": mudrft.terrains.Mud(), "sand": GranularRFT(), "linear": LinearStiffness()}
    )
    up = tr.velocity[:, 2] > 0
    assert np.all(out["sand"].force[up, 2] == 0.0)
    assert out["mud"].force[up, 2].min() < -0.2 * out["mud"].force[:, 2].max()  # suction
    rows = {r["terrain"]: r for r in summarize(out)}
    assert rows["mud"]["energy [J]"] > 0.1  # dissipative loop
    # elastic: the loop encloses no area; the trapezoid rule misses at most half a step of
    # power F v dt / 2 at each of the four velocity corners
    fmax = out["linear"].force[:, 2].max()
    assert abs(rows["linear"]["energy [J]"]) <= 4 * 0.5 * fmax * 0.02 * 2e-3


def test_csv_round_trip(box, tmp_path):
    tr = mudrft.gait(0.26)
    out = compare(box, tr, [LinearStiffness(), MaxwellMud()])
    p = write_csv({"gait": out}, tmp_path / "compare.csv")
    with p.open() as fh:
        rows = list(csv.reader(fh))
    assert tuple(rows[0]) == CSV_COLUMNS
    assert len(rows) == 1 + 2 * len(tr)
    fz = np.array([float(r[CSV_COLUMNS.index("Fz [N]")]) for r in rows[1:] if r[1] == "maxwell"])
    np.testing.assert_allclose(
        fz, out["maxwell"].force[:, 2], rtol=1e-5, atol=1e-9
    )  # 6 significant digits
    with pytest.raises(MudrftError, match="exists"):
        write_csv(out, p)


def test_command_writes_csv_summary_and_figures(box, tmp_path):
    pytest.importorskip("matplotlib")
    from mudrft.cli.compare import write_comparison

    paths = write_comparison(box, tmp_path / "cmp", depth=0.01, hold=0.1, quiet=True)
    for p in paths.values():
        assert p.exists() and p.stat().st_size > 0
    with paths["summary"].open() as fh:
        rows = list(csv.DictReader(fh))
    assert {(r["trajectory"], r["terrain"]) for r in rows} == {
        (t, n)
        for t in ("plate", "gait")
        for n in ("mud", "granular-rft", "granular-rft3d", "linear", "maxwell", "rigid")
    }
    with pytest.raises(MudrftError, match="exists"):
        write_comparison(box, tmp_path / "cmp", depth=0.01, hold=0.1, quiet=True, figures=False)


def test_command_line_rejects_bad_input(tmp_path, capsys):
    from mudrft.cli import main

    assert main(["compare", "--out", str(tmp_path / "x"), "--speed", "-1"]) == 2
    assert "speed" in capsys.readouterr().err


def test_run_terrain_rejects_non_terrains(box):
    with pytest.raises(MudrftError, match="terrain must have"):
        run_terrain(object(), box, mudrft.gait())
    with pytest.raises(MudrftError, match="trajectory"):
        run_terrain(LinearStiffness(), box, "gait")


def test_compare_reports_progress_through_the_mudrft_logger_not_print(box, capsys, caplog):
    tr = mudrft.gait(0.26)
    seen = []
    compare(box, tr, [LinearStiffness(), RigidGround()], progress=seen.append)
    assert seen == [0.5, 1.0]  # a callable gets the share of terrains run
    with caplog.at_level(logging.INFO, logger="mudrft"):
        compare(box, tr, [LinearStiffness(), RigidGround()], progress=True)
    lines = [r.getMessage() for r in caplog.records if r.name == "mudrft.progress"]
    assert lines[-1].strip() == f"compare on {tr.name}: 100 %"
    compare(box, tr, [LinearStiffness()])
    assert capsys.readouterr().out == ""  # the library never prints


def test_compare_takes_terrain_names_objects_and_muds_mixed(box):
    # a terramechanics researcher's walkthrough: switching terrains by name, the
    # names of default_terrains; before, a name failed with "terrain names must be unique,
    # got ['str', 'str']" or "terrain must have initial_state() and step(), got str"
    plate = mudrft.plate_intrusion(depth=0.01, hold=0.0, dt=2e-3)
    sand = GranularRFT(zeta=0.464e6, name="poppy-cp")
    out = compare(box, plate, ["mud", "granular-rft", sand], water_content=0.45)
    assert list(out) == ["mud", "granular-rft", "poppy-cp"]
    ref = run_terrain(mudrft.terrains.MudTerrain(mudrft.paper_mud(0.45)), box, plate)
    np.testing.assert_array_equal(out["mud"].force, ref.force)
    np.testing.assert_array_equal(
        out["granular-rft"].force, run_terrain(GranularRFT(), box, plate).force
    )
    both = compare(box, plate, {"W=25": mudrft.paper_mud(0.25), "sand": "granular-rft"})
    np.testing.assert_array_equal(both["sand"].force, out["granular-rft"].force)
    assert both["W=25"].force[:, 2].max() > 0


def test_compare_names_what_is_wrong_with_a_terrain(box):
    plate = mudrft.plate_intrusion(depth=0.01, hold=0.0, dt=2e-3)
    names = r"\['mud', 'granular-rft', 'granular-rft3d', 'linear', 'maxwell', 'rigid'\]"
    with pytest.raises(
        MudrftError, match=rf"terrains\[1\] must be a terrain .*{names}, got 'sand'"
    ):
        compare(box, plate, ["mud", "sand"])
    with pytest.raises(MudrftError, match=r"got the string 'linear' \(write \['linear'\]"):
        compare(box, plate, "linear")
    with pytest.raises(MudrftError, match=r"terrains\[0\] must be a terrain object, got the class"):
        compare(box, plate, [GranularRFT])
    with pytest.raises(MudrftError, match=r"terrains\['a'\] must be a terrain.*got float 3.0"):
        compare(box, plate, {"a": 3.0})
    # simulate takes objects: a name or a class says what to write
    with pytest.raises(MudrftError, match=r"got the string 'granular-rft': write the terrain"):
        mudrft.simulate(box, "granular-rft", plate)
    with pytest.raises(MudrftError, match=r"got the class GranularRFT \(write GranularRFT\(\)"):
        mudrft.simulate(box, GranularRFT, plate)


def test_figure_s6_draws_any_subset_and_does_not_claim_w25(box):
    """A terramechanics researcher's walkthrough: ``mudrft compare --terrains
    granular-rft,linear`` ran and then failed on the figure ('histories must include
    ['mud', 'granular-rft']'), and panel (a) labelled the mud 'W = 25 %' at any water
    content."""
    pytest.importorskip("matplotlib")
    import matplotlib.pyplot as plt

    from mudrft.baselines.plots import plot_s6

    plate = mudrft.plate_intrusion(depth=0.01, hold=0.0, dt=2e-3)
    fig = plot_s6(compare(box, plate, [GranularRFT(), LinearStiffness()]))
    try:
        labels = [a.get_legend_handles_labels()[1] for a in fig.axes]
        assert labels[0] == ["sand (granular RFT)"]
        assert labels[1] == ["linear stiffness (Godon 2022)"]
    finally:
        plt.close(fig)
    fig = plot_s6(
        compare(box, plate, ["mud", "granular-rft", "granular-rft3d"], water_content=0.45)
    )
    try:
        a = fig.axes[0].get_legend_handles_labels()[1]
        assert a == ["mud (this model)", "sand (granular RFT)", "sand (3D-RFT)"]
        assert not any("25 %" in t for t in a)
    finally:
        plt.close(fig)
