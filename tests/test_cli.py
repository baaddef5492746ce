"""The mudrft command: output, files, and one-line errors for user mistakes."""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import warnings

import numpy as np
import pytest

import mudrft
from mudrft.cli import main


def run(capsys, *args):
    code = main(list(args))
    out = capsys.readouterr()
    return code, out.out, out.err


def test_params_lists_both_tables(capsys):
    code, out, _ = run(capsys, "params")
    assert code == 0
    assert "Table S1" in out and "Table S2" in out
    assert out.count("%") >= 6 and "violates" in out


def test_help_lists_the_stable_commands(capsys):
    with pytest.raises(SystemExit):
        main(["--help"])
    out = capsys.readouterr().out
    for cmd in ("params", "simulate", "reproduce"):
        assert cmd in out


def test_simulate_writes_run_csv_and_refuses_to_overwrite(tmp_path, capsys):
    out = tmp_path / "run.csv"
    code, _stdout, _ = run(
        capsys,
        "simulate",
        "--foot",
        "flat",
        "--water-content",
        "0.25",
        "--speed",
        "0.2",
        "--out",
        str(out),
    )
    assert code == 0 and out.exists()
    assert out.read_text().splitlines()[0] == "time [s],x [m],y [m],z [m],Fx [N],Fy [N],Fz [N]"
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    assert data.shape[1] == 7 and np.all(np.isfinite(data))
    before = out.read_bytes()
    code, _, err = run(capsys, "simulate", "--foot", "flat", "--out", str(out))
    assert code == 2 and "--force" in err and "Traceback" not in err
    assert out.read_bytes() == before


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["simulate", "--foot", "banana", "--out", "x.csv"], "foot"),
        (["simulate", "--foot", "flat", "--speed", "0", "--out", "x.csv"], "speed"),
        (["simulate", "--foot", "flat", "--speed", "-1", "--out", "x.csv"], "speed"),
        (
            ["simulate", "--foot", "flat", "--water-content", "0.9", "--out", "x.csv"],
            "--water-content",
        ),
    ],
)
def test_simulate_bad_input_is_one_line(tmp_path, capsys, monkeypatch, args, needle):
    monkeypatch.chdir(tmp_path)
    code, _, err = run(capsys, *args)
    assert code == 2
    assert needle in err and "Traceback" not in err and err.count("\n") == 1


def test_reproduce_refuses_existing_results_and_unwritable_dirs(tmp_path, capsys):
    (tmp_path / "summary.csv").write_text("keep me")
    # --no-figures: the refusal does not depend on the extra "plot"
    code, _, err = run(capsys, "reproduce", "--out", str(tmp_path), "--no-figures")
    assert code == 2 and "--force" in err
    assert (tmp_path / "summary.csv").read_text() == "keep me"
    blocker = tmp_path / "file"
    blocker.write_text("")
    code, _, err = run(capsys, "reproduce", "--out", str(blocker), "--no-figures")
    assert code == 2 and "not a directory" in err


@pytest.mark.parametrize("command", ["reproduce", "compare"])
def test_figures_without_matplotlib_name_the_extra_and_the_way_around(
    tmp_path, capsys, monkeypatch, command
):
    """A core-only install (``pip install mudrft``): the figures need the extra, and the
    message says both ways out; nothing is written."""
    monkeypatch.setitem(sys.modules, "matplotlib", None)  # import matplotlib -> ImportError
    out = tmp_path / "out"
    code, _, err = run(capsys, command, "--out", str(out), "--quiet")
    assert code == 2 and err.count("\n") == 1, err
    assert "pip install 'mudrft[plot]', or pass --no-figures" in err
    assert not out.exists()


# --------------------------------------------------------------------------------------
# help, extras, logging, messages
# --------------------------------------------------------------------------------------
def help_of(capsys, *command):
    with pytest.raises(SystemExit) as exc:
        main([*command, "--help"])
    assert exc.value.code == 0
    return capsys.readouterr().out


def test_help_lists_every_subcommand(capsys):
    out = help_of(capsys)
    for cmd in ("params", "simulate", "reproduce", "calibrate", "compare", "walk", "bench"):
        assert f"\n    {cmd}" in out


@pytest.mark.parametrize("command", ["params", "simulate", "reproduce"])
def test_subcommands_have_a_description(capsys, command):
    out = help_of(capsys, command)
    _, _, rest = out.partition("\n\n")
    description = rest.split("\n\n")[0]
    assert not description.startswith(("options:", "positional")) and len(description) > 80


@pytest.mark.parametrize(
    ("command", "needle"),
    [
        ("walk", "(default: 0.25)"),
        ("walk", "(default: 10.0)"),
        ("simulate", "(default: 0.2)"),
        ("compare", "(default: mudrft-compare)"),
        ("bench", "--force"),
        ("calibrate", "(default: 0.95)"),
    ],
)
def test_help_shows_defaults(capsys, command, needle):
    assert needle in " ".join(help_of(capsys, command).split())


def test_every_subcommand_has_the_house_help_layout_and_one_quiet_flag():
    """Subcommands register through cli._parser.add_subcommand (one place for the help
    layout) and take --quiet from add_run_options (issue 12: it was written once per command)."""
    from mudrft.cli import COMMANDS, build_parser
    from mudrft.cli._parser import HelpFormatter

    parser = build_parser()
    (sub,) = (a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    assert set(sub.choices) == set(COMMANDS)
    for name, command in sub.choices.items():
        assert command.formatter_class is HelpFormatter, name
        quiet = [a for a in command._actions if "--quiet" in a.option_strings]
        assert name == "params" or (len(quiet) == 1 and quiet[0].default is False), name


def test_the_evaluation_options_are_the_same_in_every_command_that_has_them():
    """--thixotropy and --clock come from one add_evaluation_options (they were written out
    in simulate and calibrate alike); the commands differ only in what --thixotropy does."""
    from mudrft.cli import build_parser

    parser = build_parser()
    (sub,) = (a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    seen = {}
    for name, command in sub.choices.items():
        options = {o: a for a in command._actions for o in a.option_strings}
        if "--thixotropy" in options:
            thixotropy, clock = options["--thixotropy"], options["--clock"]
            seen[name] = (
                tuple(thixotropy.choices),
                thixotropy.default,
                tuple(clock.choices),
                clock.default,
                clock.help,
            )
    assert {"simulate", "calibrate"} <= set(seen)
    assert len(set(seen.values())) == 1, seen


def test_compare_help_is_plain_text(capsys):
    out = help_of(capsys, "compare")
    for rest in (":func:", ":data:", ":mod:", "``"):
        assert rest not in out


def test_calibrate_help_hides_the_deprecated_overwrite(capsys):
    out = help_of(capsys, "calibrate")
    assert "--force" in out and "--overwrite" not in out


def test_walk_without_mujoco_is_listed_and_fails_in_one_line(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "mujoco", None)  # import mujoco -> ImportError
    assert "walk" in help_of(capsys)
    out = tmp_path / "w"
    code, _, err = run(capsys, "walk", "--out", str(out), "--seconds", "0.1")
    assert code == 2 and "pip install 'mudrft[mujoco]'" in err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert not out.exists()


def test_plot_without_matplotlib_fails_before_simulating(tmp_path, capsys, monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    out = tmp_path / "run.csv"
    code, _, err = run(
        capsys, "simulate", "--foot", "flat", "--out", str(out), "--plot", str(tmp_path / "f.png")
    )
    assert code == 2 and "mudrft[plot]" in err and err.count("\n") == 1
    assert list(tmp_path.iterdir()) == []


def test_errors_show_plain_numbers_not_numpy_reprs(tmp_path, capsys, monkeypatch):
    import mudrft.feet

    def bad_foot(name, **options):
        raise mudrft.MudrftError(f"foot size must be > 0 m, got {np.float64(-1.5)!r}")

    monkeypatch.setattr(mudrft.feet, "by_name", bad_foot)  # the command imports it as it runs
    code, _, err = run(capsys, "simulate", "--foot", "x", "--out", str(tmp_path / "r.csv"))
    assert code == 2 and "got -1.5" in err and "np." not in err


def test_option_errors_name_the_option(tmp_path, capsys):
    for args, needle in [
        (
            ["simulate", "--foot", "flat", "--dt", "nan"],
            "--dt must be a finite number [s], got nan",
        ),
        (["simulate", "--foot", "flat", "--depth", "-1"], "--depth must be > 0 m, got -1"),
        (["simulate", "--foot", "flat", "--water-content", "0.9"], "pass --extrapolate"),
        (["compare", "--speed", "inf", "--no-figures"], "--speed must be a finite number"),
    ]:
        code, _, err = run(capsys, *args, "--out", str(tmp_path / "o"))
        assert code == 2 and needle in err and err.count("\n") == 1, err
    assert list(tmp_path.iterdir()) == []


def test_notes_and_progress_go_to_stderr_and_quiet_silences_them(tmp_path, capsys):
    code, out, err = run(
        capsys, "simulate", "--foot", "flat", "--dt", "0.004", "--out", str(tmp_path / "a.csv")
    )
    assert code == 0 and "simulating flat foot" in err and "%" in err
    assert out.startswith("wrote ") and "peak_support" in out and "simulating" not in out
    code, out, err = run(
        capsys,
        *("simulate", "--foot", "flat", "--dt", "0.004", "--quiet"),
        *("--out", str(tmp_path / "b.csv")),
    )
    assert code == 0 and err == "" and "peak_support" in out


def test_the_command_leaves_logging_as_it_found_it(tmp_path, capsys):
    import logging

    log = logging.getLogger("mudrft")
    before = (list(log.handlers), log.level)
    run(capsys, "simulate", "--foot", "flat", "--dt", "0.004", "--out", str(tmp_path / "a.csv"))
    assert (list(log.handlers), log.level) == before


def test_a_root_handler_does_not_print_the_commands_lines_twice(tmp_path, capsys):
    """`mudrft bench` printed 'INFO:mudrft:  robots, MJX with mud, N=1: done' after each
    line once MJX had logged through the root logger (an implicit logging.basicConfig):
    the command's lines reached stderr twice. Its own handler is the one that prints."""
    import logging

    root = logging.getLogger()
    extra = logging.StreamHandler(sys.stderr)  # what logging.basicConfig() adds
    root.addHandler(extra)
    try:
        code, _, err = run(
            capsys, "simulate", "--foot", "flat", "--dt", "0.004", "--out", str(tmp_path / "a.csv")
        )
    finally:
        root.removeHandler(extra)
    lines = err.splitlines()
    assert code == 0 and any("simulating flat foot" in line for line in lines)
    assert len(lines) == len(set(lines)), err
    assert logging.getLogger("mudrft").propagate  # restored for the library's users


def test_entry_point_and_python_dash_m(tmp_path):
    from importlib.metadata import entry_points

    (ep,) = entry_points(group="console_scripts", name="mudrft")
    assert ep.value == "mudrft.cli:main" and ep.load() is main
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    proc = subprocess.run(
        [sys.executable, "-m", "mudrft", "params"],
        capture_output=True,
        text=True,
        env=env,
        cwd=tmp_path,
        check=False,
    )
    assert proc.returncode == 0 and "Table S1" in proc.stdout


@pytest.mark.parametrize("command", ["simulate", "compare", "walk"])
def test_every_command_that_takes_a_foot_file_takes_its_unit(command):
    """--unit, which the mesh warning recommends, exists wherever --foot takes a file (it
    was missing from compare and walk, so the advice failed there)."""
    from mudrft.cli import build_parser

    parser = build_parser()
    required = {"simulate": ["--out", "x.csv"], "walk": ["--out", "x"], "compare": []}[command]
    args = parser.parse_args([command, "--foot", "foot.stl", "--unit", "mm", *required])
    assert args.unit == "mm" and args.foot == "foot.stl" and args.trailing is None
    assert parser.parse_args([command, "--foot", "foot.stl", "--trailing", *required]).trailing
    assert parser.parse_args([command, "--foot", "foot.obj", "--up", "y", *required]).up == "y"


def test_simulate_trailing_lets_a_dome_mesh_resist_with_its_trailing_facets(tmp_path, capsys):
    """A dome mesh of one's own matches SemiSphere only with trailing facets (D23); the
    command line could not ask for them. --trailing is for mesh files only."""
    import trimesh

    import mudrft
    from mudrft.feet.meshgen import semisphere_mesh

    v, f = semisphere_mesh(0.045, 0.026, resolution=12)
    trimesh.Trimesh(v, f, process=False).export(tmp_path / "dome.stl")
    drag = {}
    for trailing in (False, True):
        out = tmp_path / f"run{trailing}.csv"
        extra = ["--trailing"] if trailing else []
        args = ["simulate", "--foot", str(tmp_path / "dome.stl"), "--out", str(out), *extra]
        assert run(capsys, *args, "--quiet")[0] == 0
        drag[trailing] = np.abs(np.loadtxt(out, delimiter=",", skiprows=1)[:, 4]).max()
    sphere = mudrft.simulate(mudrft.feet.SemiSphere(), mudrft.paper_mud(0.25), mudrft.gait(0.2))
    closed_form = np.abs(sphere.force[:, 0]).max()
    assert abs(drag[True] / closed_form - 1) < abs(drag[False] / closed_form - 1)
    code, _, err = run(capsys, "simulate", "--foot", "flat", "--trailing", "--out", "x.csv")
    assert code == 2
    assert "trailing (CLI: --trailing) applies to mesh files only" in err


@pytest.mark.parametrize(
    ("args", "line"),
    [
        (
            ["simulate", "--foot", "flat", "--speeed", "0.2", "--out", "x.csv"],
            "mudrft simulate: error: unrecognized option '--speeed'; did you mean '--speed'? "
            "(mudrft simulate --help lists the options)",
        ),
        (
            ["calibrate", "log.csv", "--directon", "vertical"],
            "mudrft calibrate: error: unrecognized option '--directon'; did you mean "
            "'--direction'? (mudrft calibrate --help lists the options)",
        ),
        (
            ["simulate", "--foot", "flat", "--out", "x.csv", "extra"],
            "mudrft simulate: error: unrecognized argument 'extra' "
            "(mudrft simulate --help lists the options)",
        ),
    ],
)
def test_a_mistyped_option_is_one_line_naming_the_command_and_the_closest_option(
    tmp_path, capsys, monkeypatch, args, line
):
    """A new user's typo: argparse answered with the top-level usage and
    'mudrft: error: unrecognized arguments: --speeed 0.2' (not the command, no hint),
    though every other mistake is one line 'mudrft COMMAND: error: ...'."""
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as exc:
        main(args)
    err = capsys.readouterr().err
    assert exc.value.code == 2
    assert err == line + "\n"
    assert not (tmp_path / "x.csv").exists()


@pytest.mark.parametrize(
    ("args", "line"),
    [
        (
            ["reproduc", "--out", "x"],
            "mudrft: error: unrecognized command 'reproduc'; did you mean 'reproduce'? "
            "(mudrft --help lists the commands)",
        ),
        (["flat"], "mudrft: error: unrecognized command 'flat' (mudrft --help lists the commands)"),
        (
            ["--versoin"],
            "mudrft: error: unrecognized option '--versoin'; did you mean '--version'? "
            "(mudrft --help lists the commands and options)",
        ),
        (
            ["--foo"],
            "mudrft: error: unrecognized option '--foo' "
            "(mudrft --help lists the commands and options)",
        ),
        (
            ["--quiet", "simulate", "--foot", "flat", "--out", "x.csv"],
            "mudrft simulate: error: option '--quiet' goes after the command: mudrft simulate "
            "... --quiet (mudrft simulate --help lists the options)",
        ),
        (
            ["--force"],
            "mudrft: error: unrecognized option '--force'; a command's options go after it: "
            "mudrft COMMAND --force (mudrft --help lists the commands and options)",
        ),
    ],
)
def test_a_mistyped_command_or_top_level_option_is_one_line_naming_the_closest(
    tmp_path, capsys, monkeypatch, args, line
):
    """'mudrft reproduc' answered with argparse's usage and 'argument COMMAND: invalid
    choice: ... (choose from ...)', and 'mudrft --foo' with the usage and 'unrecognized
    arguments': the walls removed from a command's options. A command's own
    option before the command was 'unrecognized', with "did you mean '--quiet'?"."""
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as exc:
        main(args)
    assert exc.value.code == 2
    assert capsys.readouterr().err == line + "\n"
    assert list(tmp_path.iterdir()) == []


def _parameter_file(path, params):
    import json

    path.write_text(json.dumps({"direction": params.direction, **params.as_dict()}))
    return str(path)


def test_simulate_takes_calibrated_parameter_files(tmp_path, capsys):
    """A user who ran 'mudrft calibrate --out fit.json' could not simulate with the fit:
    simulate knew only the paper's rows."""
    import mudrft

    v35 = mudrft.paper_parameters(0.35, "vertical")
    fit = _parameter_file(tmp_path / "fit_v.json", v35)
    out = tmp_path / "run.csv"
    code, stdout, _ = run(
        capsys, "simulate", "--foot", "flat", "--vertical", fit, "--out", str(out), "--quiet"
    )
    assert code == 0, stdout
    mud = mudrft.Mud(vertical=v35, horizontal=mudrft.paper_parameters(0.25, "horizontal"))
    expected = mudrft.simulate(mudrft.feet.by_name("flat"), mud, mudrft.gait(0.2))
    table = np.loadtxt(out, delimiter=",", skiprows=1)
    np.testing.assert_allclose(table[:, 4:], expected.force, rtol=1e-6, atol=1e-9)
    paper = mudrft.simulate(mudrft.feet.by_name("flat"), mudrft.paper_mud(0.25), mudrft.gait(0.2))
    assert not np.allclose(table[:, 6], paper.force[:, 2], rtol=1e-3)


def test_compare_takes_a_calibrated_parameter_file_for_the_mud_only(tmp_path, capsys):
    """``mudrft compare --vertical FIT.json`` runs the mud model on the fit; the
    baselines keep their defaults (D59)."""
    import csv

    import mudrft

    fit = _parameter_file(tmp_path / "fit.json", mudrft.paper_parameters(0.45, "vertical"))
    rows = {}
    for name, extra in (("paper", []), ("fit", ["--vertical", fit])):
        out = tmp_path / name
        args = ["compare", "--out", str(out), "--no-figures", "--quiet", *extra]
        assert run(capsys, *args)[0] == 0
        with (out / "compare_summary.csv").open() as fh:
            rows[name] = {(r["trajectory"], r["terrain"]): r for r in csv.DictReader(fh)}
    for key, paper in rows["paper"].items():
        same = rows["fit"][key]["peak_support [N]"] == paper["peak_support [N]"]
        assert same == (key[1] != "mud"), key
    assert float(rows["fit"][("plate", "mud")]["peak_support [N]"]) < float(
        rows["paper"][("plate", "mud")]["peak_support [N]"]
    )


@pytest.mark.parametrize(
    ("option", "which", "message"),
    [
        ("--vertical", "h", "--vertical: {path!r} holds a horizontal parameter set, expected a "
         "vertical one (were --vertical and --horizontal swapped?)"),
        ("--horizontal", "missing", "--horizontal: {path}: no such file"),
    ],
)  # fmt: skip
def test_simulate_parameter_file_mistakes_name_the_option(
    tmp_path, capsys, monkeypatch, option, which, message
):
    import mudrft

    monkeypatch.chdir(tmp_path)
    path = "missing.json"
    if which == "h":
        path = _parameter_file(tmp_path / "h.json", mudrft.paper_parameters(0.25, "horizontal"))
    code, _, err = run(capsys, "simulate", "--foot", "flat", option, path, "--out", "x.csv")
    assert code == 2
    assert err == f"mudrft simulate: error: {message.format(path=path)}\n"
    assert not (tmp_path / "x.csv").exists()


def test_simulate_prints_each_metric_with_its_unit(tmp_path, capsys):
    """The metrics came as 'peak_support 92.79', 'impulse_x -20.2': a new user could not
    tell N from N s from J without the README."""
    code, out, _ = run(
        capsys, "simulate", "--foot", "flat", "--out", str(tmp_path / "r.csv"), "--quiet"
    )
    assert code == 0
    units = {line.split()[0]: line.split()[2:] for line in out.splitlines()[1:]}
    assert units == {
        "peak_support": ["N"],
        "max_suction": ["N"],
        "impulse_x": ["N", "s"],
        "impulse_y": ["N", "s"],
        "impulse_z": ["N", "s"],
        "energy": ["J"],
        "max_depth": ["m"],
        "suction_ratio": ["-"],
    }


def test_simulate_load_sinks_to_the_static_depth_and_prints_it(tmp_path, capsys):
    """--load presses the foot with a ramped weight for 30 s (D13: it creeps to the static
    depth; measured 3e-4 short for the flat foot under 49 N), and prints both depths."""
    out = tmp_path / "load.csv"
    code, stdout, _ = run(capsys, "simulate", "--foot", "flat", "--load", "49", "--out", str(out))
    assert code == 0
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    static = mudrft.static_sinking(mudrft.feet.Flat(), mudrft.paper_mud(0.25), 49.0)
    assert data[-1, 0] == pytest.approx(30.0)
    assert -data[-1, 3] == pytest.approx(static, rel=1e-3)
    assert data[-1, 6] == pytest.approx(49.0, rel=1e-3)  # the mud carries the weight
    assert f"static sinking {static: .6g} m" in stdout
    final = float(next(x for x in stdout.splitlines() if x.split()[0] == "sinking").split()[1])
    assert final == pytest.approx(-data[-1, 3], rel=1e-5)  # the settled depth, in m


@pytest.mark.parametrize(
    ("args", "needle"),
    [
        (["--load", "49", "--speed", "0.2"], "--speed sets the gait, which --load replaces"),
        (["--load", "49", "--path", "p.csv"], "--path moves the foot and --load presses it"),
        (["--ramp", "1"], "--ramp applies to --load only"),
        (["--duration", "5"], "--duration applies to --load only"),
        (["--load", "-3"], "--load must be > 0 N, got -3"),
        (["--load", "49", "--ramp", "-1"], "--ramp must be >= 0 s"),
    ],
)
def test_simulate_motion_options_that_do_not_go_together(tmp_path, capsys, args, needle):
    out = tmp_path / "x.csv"
    code, _, err = run(capsys, "simulate", "--foot", "flat", *args, "--out", str(out))
    assert code == 2 and needle in err and err.count("\n") == 1, err
    assert not out.exists()


def test_compare_runs_your_own_granular_medium_and_only_the_terrains_named(tmp_path, capsys):
    """A terramechanics researcher's walkthrough: ``--terrains`` picks the terrains and
    ``--zeta``/``--rho-c``/``--mu-int``/``--mu-surf`` describe the sand; before, compare ran
    every terrain with the default media only."""
    import csv

    import mudrft
    from mudrft.baselines import compare, summarize

    out = tmp_path / "sand"
    args = ["compare", "--out", str(out), "--no-figures", "--quiet", "--depth", "0.01"]
    args += ["--hold", "0.1", "--terrains", "granular-rft,granular-rft3d", "--zeta", "0.9e6"]
    args += ["--rho-c", "1600", "--mu-int", "0.4", "--mu-surf", "0.3"]
    assert run(capsys, *args)[0] == 0
    with (out / "compare_summary.csv").open() as fh:
        rows = {(r["trajectory"], r["terrain"]): r for r in csv.DictReader(fh)}
    assert sorted(rows) == [
        (t, n) for t in ("gait", "plate") for n in ("granular-rft", "granular-rft3d")
    ]
    terrains = [
        mudrft.terrains.GranularRFT(zeta=0.9e6),
        mudrft.terrains.GranularRFT3D(rho_c=1600, mu_int=0.4, mu_surf=0.3),
    ]
    foot = mudrft.feet.by_name("flat")
    expected = summarize(compare(foot, mudrft.plate_intrusion(depth=0.01, hold=0.1), terrains))
    for row in expected:
        got = float(rows[("plate", row["terrain"])]["peak_support [N]"])
        assert got == pytest.approx(row["peak_support [N]"], rel=1e-5)
    # the plate: zeta * depth * area for the 80 x 65 mm flat foot
    assert float(rows[("plate", "granular-rft")]["peak_support [N]"]) == pytest.approx(
        0.9e6 * 0.01 * 0.08 * 0.065, rel=1e-5
    )


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--terrains", "sand"], "--terrains must name one or more of mud, granular-rft"),
        (["--terrains", "mud,mud"], "--terrains must name each terrain once, got 'mud,mud'"),
        (["--terrains", "mud", "--zeta", "2e5"], "--zeta describes granular-rft, which --terrains leaves out"),
        (["--rho-c", "-1"], "--rho-c must be > 0 kg/m^3, got -1"),
        (["--depth", "30"], "--depth must be at most 1 m (it is in metres: 30 mm is 0.03), got 30 m"),
    ],
)  # fmt: skip
def test_compare_terrain_option_mistakes_name_the_option(tmp_path, capsys, extra, message):
    code, _, err = run(capsys, "compare", "--out", str(tmp_path / "x"), "--no-figures", *extra)
    assert code == 2
    assert message in err
    assert not (tmp_path / "x").exists()


def test_compare_warns_on_sand_coefficients_in_n_per_cm3(tmp_path, capsys):
    args = ["compare", "--out", str(tmp_path / "x"), "--no-figures", "--quiet"]
    args += ["--terrains", "granular-rft", "--zeta", "0.254", "--depth", "0.005", "--hold", "0"]
    with warnings.catch_warnings():  # the suite makes PlausibilityWarning an error
        warnings.simplefilter("always")
        code, _, err = run(capsys, *args)
    assert code == 0
    assert "compare: warning: GranularRFT: zeta is 0.254 N/m^3" in err and "N/cm^3" in err


def test_compare_figures_of_a_subset_of_terrains(tmp_path, capsys):
    """``--terrains rigid`` (or any subset without mud and sand) wrote no figure: the S6
    figure needed mud and granular RFT and the gait figure left rigid ground out."""
    pytest.importorskip("matplotlib")
    out = tmp_path / "rigid"
    args = ["compare", "--out", str(out), "--quiet", "--terrains", "rigid"]
    assert run(capsys, *args, "--depth", "0.005", "--hold", "0")[0] == 0
    assert (out / "compare_s6.png").stat().st_size > 0
    assert (out / "compare_gait.png").stat().st_size > 0


def test_simulate_runs_a_baseline_terrain_with_your_own_medium(tmp_path, capsys):
    """``mudrft simulate --terrain granular-rft --zeta ...``: before, simulate ran the
    mud only, so a terramechanics researcher could not put the same gait on sand here."""
    import mudrft

    out = tmp_path / "sand.csv"
    args = ["simulate", "--foot", "flat", "--terrain", "granular-rft", "--zeta", "0.9e6"]
    code, stdout, _ = run(capsys, *args, "--out", str(out), "--quiet")
    assert code == 0 and "peak_support" in stdout
    expected = mudrft.simulate(
        mudrft.feet.by_name("flat"), mudrft.terrains.GranularRFT(zeta=0.9e6), mudrft.gait(0.2)
    )
    table = np.loadtxt(out, delimiter=",", skiprows=1)
    np.testing.assert_allclose(table[:, 4:], expected.force, rtol=1e-6, atol=1e-9)


@pytest.mark.parametrize(
    ("extra", "message"),
    [
        (["--terrain", "sand"], "--terrain must name one of mud, granular-rft"),
        (["--terrain", "mud,linear"], "--terrain must name one terrain, got 'mud,linear'"),
        (["--zeta", "2e5"], "--zeta describes granular-rft, which --terrain leaves out"),
        (["--terrain", "linear", "--thixotropy", "quasi-static"],
         "--thixotropy describes the mud, but --terrain is 'linear'"),
        (["--terrain", "rigid", "--water-content", "0.35"],
         "--water-content describes the mud, but --terrain is 'rigid'"),
        (["--terrain", "maxwell", "--clock", "retraction"],
         "--clock describes the mud, but --terrain is 'maxwell'"),
        (["--terrain", "rigid", "--labels", "text"],
         "--labels describes the mud, but --terrain is 'rigid'"),
        (["--terrain", "linear", "--extrapolate"],
         "--extrapolate describes the mud, but --terrain is 'linear'"),
        (["--terrain", "granular-rft3d", "--mu-surf", "-0.1"], "--mu-surf must be >= 0, got -0.1"),
    ],
)  # fmt: skip
def test_simulate_terrain_option_mistakes_name_the_option(tmp_path, capsys, extra, message):
    out = tmp_path / "x.csv"
    code, _, err = run(capsys, "simulate", "--foot", "flat", "--out", str(out), *extra)
    assert code == 2
    assert message in err
    assert not out.exists()


#: What ``mudrft --help`` may not import: the physics, the library's edges, heavy packages.
HEAVY = (
    "mudrft.parameters", "mudrft.constitutive", "mudrft.feet", "mudrft.terrains",
    "mudrft.simulation", "mudrft.plate", "mudrft.trajectories", "mudrft.calibration",
    "mudrft.baselines", "mudrft.reproduce", "mudrft.integrations", "mudrft.backends",
    "mudrft.io.dataset", "mudrft.sweep.run", "scipy", "trimesh", "matplotlib",
)  # fmt: skip


@pytest.mark.parametrize(
    "command", ["", "params", "simulate", "reproduce", "calibrate", "compare", "walk", "bench"]
)
def test_help_parses_before_it_imports_the_physics(command):
    """``mudrft --help`` (and each command's) imports the command line only (issue 40)."""
    words = [command, "--help"] if command else ["--help"]
    code = (
        "import sys\nfrom mudrft.cli import main\n"
        f"try:\n    main({words!r})\nexcept SystemExit:\n    pass\n"
        f"print([m for m in sys.modules if m.split('.')[0] in ('scipy', 'trimesh', 'matplotlib')"
        f" or m.startswith({HEAVY!r})], file=sys.stderr)"
    )
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(sys.path)}
    proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
    assert proc.returncode == 0 and "usage: mudrft" in proc.stdout, proc.stderr
    assert proc.stderr.strip().splitlines()[-1] == "[]", proc.stderr


def test_the_help_texts_constants_are_the_librarys():
    """Written in the command line so that ``--help`` needs no physics."""
    from mudrft.baselines.compare import TERRAIN_NAMES
    from mudrft.cli import _terrain, simulate
    from mudrft.trajectories import STANCE_DEPTH

    assert _terrain.TERRAIN_NAMES == TERRAIN_NAMES
    assert simulate.STANCE_DEPTH == STANCE_DEPTH
    assert simulate.GAIT_SPEED == mudrft.gait().meta["speed"]


# ---------------------------------------------------------------------------------------
# one default gait, and a foot deeper than its height (issue 38)
# ---------------------------------------------------------------------------------------
def test_simulate_and_compare_give_the_same_support_and_suction_by_default(tmp_path, capsys):
    """simulate's gait was 20 mm deep and compare's 30 mm: the same foot printed 116/144 N
    in one and 164/204 N in the other. Both take mudrft.trajectories.STANCE_DEPTH now."""
    import csv

    code, out, _ = run(capsys, "simulate", "--foot", "flat", "--out", str(tmp_path / "r.csv"))
    assert code == 0
    printed = {line.split()[0]: float(line.split()[1]) for line in out.splitlines()[1:]}
    code, _, _ = run(
        capsys, "compare", "--foot", "flat", "--terrains", "mud", "--no-figures",
        "--out", str(tmp_path / "c"), "--quiet",
    )  # fmt: skip
    assert code == 0
    with open(tmp_path / "c" / "compare_summary.csv", newline="") as fh:
        (row,) = [r for r in csv.DictReader(fh) if r["trajectory"] == "gait"]
    for name in ("peak_support", "max_suction"):
        assert float(row[f"{name} [N]"]) == pytest.approx(printed[name], rel=1e-5), name
    assert printed["max_depth"] == pytest.approx(0.02)


@pytest.mark.parametrize("command", ["simulate", "compare"])
def test_a_30_mm_gait_of_a_26_mm_foot_warns_and_fails_under_strict(tmp_path, capsys, command):
    out = str(tmp_path / ("r.csv" if command == "simulate" else "c"))
    args = [command, "--foot", "flat", "--depth", "0.03", "--out", out, "--quiet"]
    if command == "compare":
        args += ["--terrains", "mud", "--no-figures"]
    with warnings.catch_warnings():  # the suite makes PlausibilityWarning an error
        warnings.simplefilter("always")
        code, _, err = run(capsys, *args)
    assert code == 0
    assert "warning:" in err and "deeper than the flat foot is tall (0.026 m)" in err
    assert err.count("deeper than the flat foot") == (1 if command == "simulate" else 2)
    code, _, err = run(capsys, *args, "--force", "--strict")
    assert code == 2 and "strict: " in err and "Traceback" not in err
    out2 = str(tmp_path / ("s.csv" if command == "simulate" else "d"))
    code, _, err = run(capsys, *[out2 if a == out else a for a in args], "--strict")
    assert code == 2 and not os.path.exists(out2)  # nothing written


def test_simulate_help_points_to_the_guide_page_on_which_evaluation_to_use(capsys):
    from pathlib import Path

    with pytest.raises(SystemExit):
        main(["simulate", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "docs/guide/evaluations.md" in text and "--strict" in text
    docs = Path(__file__).resolve().parents[1] / "docs" / "guide"
    page = (docs / "evaluations.md").read_text()
    assert page.startswith("# Which evaluation to use")
    assert "evaluations" in (docs / "index.md").read_text().split()
