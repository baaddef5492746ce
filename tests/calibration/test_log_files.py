"""CSV intrusion logs: what a fuzz of the file inputs found read wrong without a word.

Each test fails on the code before the fix: a log written by mudrft that did not read
back (6 significant digits), a trial named "#1" that vanished as a comment, metadata
given twice where the last silently won, the same file merged twice, a characteristic
length in mm read as metres, and the ``synthetic`` flag set by any mention of the word.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from mudrft import MudrftError
from mudrft._validation import PlausibilityWarning
from mudrft.cli import main
from mudrft.io import IntrusionDataset, Trial, load_dataset, load_intrusion_csv, save_intrusion_csv

HEADER = "trial,time [s],depth [m],stress [Pa]\n"
ROWS = "a,0,0,0\na,0.1,0.002,500\na,0.2,0.004,900\na,0.3,0.002,-100\n"


def write(tmp_path, text, name="log.csv"):
    p = tmp_path / name
    p.write_text(text)
    return p


def quiet_load(p, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a correct file reads without a warning
        return load_intrusion_csv(p, **kw)


def test_a_written_log_reads_back_to_the_same_numbers(tmp_path):
    """%.6g merged the samples of a 20 kHz log after 10 s (time must increase strictly),
    absolute timestamps and stresses 1 mPa apart."""
    t = 10.0 + np.arange(200) / 20_000
    fast = Trial(t, 1e-3 * (t - 9.9), 123_456.789 + 1e-3 * np.arange(200), name="fast")
    clock = Trial(1.7e9 + np.arange(5.0), [0, 1e-3, 2e-3, 1e-3, 0], [0, 1, 2, 3, 4], name="abs")
    ds = IntrusionDataset((fast, clock))
    back = quiet_load(save_intrusion_csv(ds, tmp_path / "x.csv"))
    for a, b in zip(ds.trials, back.trials, strict=True):
        assert a.name == b.name
        for k in ("time", "depth", "stress"):
            np.testing.assert_array_equal(getattr(a, k), getattr(b, k))


@pytest.mark.parametrize("name", ["#1", "a, b", ' "quoted" '])
def test_a_trial_name_the_csv_could_misread_survives(tmp_path, name):
    """A trial named "#1" was written as comment lines and vanished on reading."""
    tr = Trial([0.0, 0.1, 0.2], [0.0, 2e-3, 0.0], [0.0, 500.0, -50.0], name=name)
    other = Trial([0.0, 0.1, 0.2], [0.0, 3e-3, 0.0], [0.0, 700.0, -60.0], name="other")
    back = quiet_load(save_intrusion_csv(IntrusionDataset((tr, other)), tmp_path / "x.csv"))
    assert [t.name for t in back.trials] == [name.strip(), "other"]
    np.testing.assert_array_equal(back.trials[0].stress, tr.stress)


def test_a_note_of_several_lines_reads_back(tmp_path):
    tr = Trial([0.0, 0.1, 0.2], [0.0, 2e-3, 0.0], [0.0, 500.0, -50.0])
    ds = IntrusionDataset((tr,), notes=("rig 2\nplate B",))
    back = quiet_load(save_intrusion_csv(ds, tmp_path / "x.csv"))
    assert back.notes[:2] == ("rig 2", "plate B")


@pytest.mark.parametrize(
    ("first", "again"),
    [
        ("# characteristic_length [m]: 0.05", "# characteristic_length [m]: 0.04"),
        ("# area [m^2]: 0.002", "# area [m^2]: 0.003"),
        ("# direction: vertical", "# direction: horizontal"),
    ],
)
def test_metadata_given_twice_differently_is_refused(tmp_path, first, again):
    """The last value used to win, also from a line after the data."""
    p = write(tmp_path, f"{first}\n{HEADER}{ROWS}{again}\n")
    with pytest.raises(MudrftError, match=r"line 7: .* is given again.*after line 1 gave"):
        load_intrusion_csv(p)


def test_metadata_repeated_with_the_same_value_is_fine(tmp_path):
    p = write(tmp_path, f"# area [m^2]: 0.002\n# area [mm^2]: 2000\n{HEADER}{ROWS}")
    assert len(quiet_load(p).trials) == 1


def test_the_same_file_twice_is_refused(tmp_path, capsys):
    """Merged, its data counted twice in a fit; the message names the argument for the
    library and for the command line."""
    p = write(tmp_path, HEADER + ROWS)
    with pytest.raises(MudrftError, match=r"path \(CLI: data\) names the same file twice"):
        load_dataset([p, tmp_path / "." / "log.csv"])
    out = tmp_path / "fit.json"
    assert main(["calibrate", str(p), str(tmp_path / "." / "log.csv"), "--out", str(out)]) == 2
    assert "(CLI: data) names the same file twice" in capsys.readouterr().err
    assert not out.exists()


@pytest.mark.parametrize("line", ["# characteristic_length: 50", "# characteristic_length [m]: 50"])
def test_a_characteristic_length_in_mm_read_as_metres_warns(tmp_path, line):
    """50 (mm) read as 50 m fitted alpha 33 times too large, 'converged'."""
    p = write(tmp_path, f"{line}\n{HEADER}{ROWS}")
    with pytest.warns(PlausibilityWarning, match=r"characteristic_length.*50.*\(50 mm is 0.05\)"):
        load_intrusion_csv(p)


def test_a_characteristic_length_argument_in_mm_warns():
    with pytest.warns(PlausibilityWarning, match="characteristic_length"):
        Trial([0.0, 0.1], [0.0, 1e-3], [0.0, 1.0], characteristic_length=50)


def test_an_area_in_cm2_read_as_m2_warns(tmp_path):
    p = write(tmp_path, "trial,time [s],depth [m],Fz [kN]\n" + ROWS)
    with pytest.warns(PlausibilityWarning, match=r"plate area is .*20"):
        load_intrusion_csv(p, area=20.0)


def test_a_depth_positive_only_by_noise_warns_of_a_flipped_sign():
    """One +1 µm sample slipped past the refusal of a never-positive depth."""
    depth = [0.0, -0.01, -0.02, 1e-6]
    with pytest.warns(PlausibilityWarning, match="sign flipped"):
        Trial([0.0, 0.1, 0.2, 0.3], depth, [0.0, 1.0, 2.0, 3.0])


@pytest.mark.parametrize(
    ("note", "synthetic"),
    [
        ("synthetic: generated by mudrft", True),
        ("synthetic: yes", True),
        ("synthetic: no", False),
        ("synthetic: false", False),
        ("not synthetic: measured on rig 2", False),
        ("compared with a synthetic data set", False),
    ],
)
def test_the_synthetic_flag_is_what_the_file_says(tmp_path, note, synthetic):
    p = write(tmp_path, f"# {note}\n{HEADER}{ROWS}")
    assert quiet_load(p).synthetic is synthetic


@pytest.mark.parametrize("sep", [";", "\t"])
def test_a_log_separated_by_semicolons_or_tabs_reads_as_one_with_commas(tmp_path, sep):
    """Refused before (issue 39): the delimiter is the header's most frequent of comma, tab
    and semicolon; with semicolons or tabs, a number may have a decimal comma."""
    commas = quiet_load(write(tmp_path, HEADER + ROWS, "c.csv"))
    text = (HEADER + ROWS).replace(",", sep)
    for decimal in (".", ","):
        other = quiet_load(write(tmp_path, text.replace(".", decimal), "s.csv"))
        for a, b in zip(commas.trials, other.trials, strict=True):
            for k in ("time", "depth", "stress"):
                np.testing.assert_array_equal(getattr(a, k), getattr(b, k))


def test_a_decimal_comma_in_a_comma_separated_file_is_a_field_count_error(tmp_path):
    p = write(tmp_path, HEADER + ROWS.replace("0.002", "0,002"))
    with pytest.raises(MudrftError, match=r"line 3: expected 4 comma-separated fields"):
        load_intrusion_csv(p)


def test_old_mac_line_endings_read_as_lines(tmp_path):
    """A file with \\r alone ended in the csv module's 'new-line character seen' error."""
    p = tmp_path / "mac.csv"
    p.write_bytes((HEADER + ROWS).replace("\n", "\r").encode())
    np.testing.assert_array_equal(quiet_load(p).trials[0].stress, [0, 500, 900, -100])


def test_logs_of_two_directions_are_refused_naming_both_files(tmp_path):
    v = write(tmp_path, "# direction: vertical\n" + HEADER + ROWS, "v.csv")
    h = write(tmp_path, "# direction: horizontal\n" + HEADER + ROWS, "h.csv")
    with pytest.raises(
        MudrftError, match=r"horizontal dataset \(.*h\.csv\) into a vertical one \(.*v\.csv\)"
    ):
        load_dataset([v, h])


def test_a_stress_of_the_opposite_sign_warns():
    """A log with the stress sign flipped fitted and reported 'converged'."""
    t = np.linspace(0.0, 1.0, 11)
    depth = 0.02 * np.minimum(t, 1.0 - t)
    with pytest.warns(
        PlausibilityWarning, match="stress is mostly negative while the plate intrudes"
    ):
        Trial(t, depth, -1e4 * depth)


@pytest.mark.parametrize(
    "header",
    ["time (ms),depth (mm),stress (kPa)", "Time in ms,Depth in mm,Stress in kPa"],
)
def test_units_in_parentheses_or_after_in_are_read(tmp_path, header):
    """'time (s)' read as a column named 'time (s)' (issue 39)."""
    p = write(tmp_path, f"{header}\n0,0,0\n100,2,0.5\n200,4,0.9\n")
    tr = quiet_load(p).trials[0]
    np.testing.assert_allclose(tr.time, [0.0, 0.1, 0.2], rtol=1e-12)
    np.testing.assert_allclose(tr.depth, [0.0, 0.002, 0.004], rtol=1e-12)
    np.testing.assert_allclose(tr.stress, [0.0, 500.0, 900.0], rtol=1e-12)


def test_logs_of_different_areas_merge_and_read_back(tmp_path):
    """Each file's '# area' note was written again, and the merged CSV was refused on
    reading ('area is given again'); the two default-named trials merged into one."""
    a = write(
        tmp_path,
        "# area [m^2]: 0.0025\n# synthetic: yes\ntime [s],depth [m],Fz [N]\n0,0,0\n0.1,0.002,10\n",
        "a.csv",
    )
    b = write(
        tmp_path, "# area [m^2]: 0.004\ntime [s],depth [m],Fz [N]\n0,0,0\n0.1,0.002,10\n", "b.csv"
    )
    merged = load_dataset([a, b])
    assert [t.name for t in merged.trials] == ["trial", "trial (2)"]
    back = quiet_load(save_intrusion_csv(merged, tmp_path / "m.csv"))
    for x, y in zip(merged.trials, back.trials, strict=True):
        np.testing.assert_array_equal(x.stress, y.stress)
    assert back.synthetic


def test_trials_of_one_name_are_refused_by_the_csv_writer(tmp_path):
    tr = Trial([0.0, 0.1], [0.0, 1e-3], [0.0, 1.0])
    with pytest.raises(MudrftError, match=r"several trials are named \['trial'\]"):
        save_intrusion_csv(IntrusionDataset((tr, tr)), tmp_path / "x.csv")


def test_a_note_line_that_looks_like_metadata_is_not_read_as_it(tmp_path):
    tr = Trial([0.0, 0.1, 0.2], [0.0, 2e-3, 0.0], [0.0, 500.0, -50.0])
    notes = ("run 3\ncharacteristic_length: 0.1", "run 4\narea: 5", "direction: vertical\nkept")
    back = quiet_load(save_intrusion_csv(IntrusionDataset((tr,), notes=notes), tmp_path / "n.csv"))
    assert back.notes[:3] == ("run 3", "run 4", "kept") and "area" not in back.meta


def test_the_synthetic_flag_survives_an_hdf5_round_trip(tmp_path):
    pytest.importorskip("h5py")
    from mudrft.io import save_intrusion_hdf5

    p = write(tmp_path, f"# source: rig B\n# synthetic: yes\n{HEADER}{ROWS}")
    back = load_dataset(save_intrusion_hdf5(quiet_load(p), tmp_path / "x.h5"))
    assert back.synthetic


# -- times in the wrong unit ------------------------------------------------------------
def _ramp_log(rate_hz: float, speed: float, *, time_scale: float = 1.0, unit: str = "s") -> str:
    """A hold, an intrusion to 20 mm at ``speed`` [m/s], a hold: sampled at ``rate_hz``, its
    times multiplied by ``time_scale`` and labelled ``unit``; a little depth noise."""
    t = np.arange(0.0, 0.02 / speed + 0.2, 1.0 / rate_hz)
    depth = np.clip(speed * (t - 0.1), 0.0, 0.02)
    depth = depth + 1e-5 * np.random.default_rng(0).standard_normal(t.size) * (depth > 0)
    stress = 2e4 * np.sqrt(np.clip(depth, 0.0, None) / 0.02)
    columns = np.column_stack([t * time_scale, depth, stress]).tolist()
    rows = "".join(f"{a!r},{d!r},{s!r}\n" for a, d, s in columns)
    return f"time [{unit}],depth [m],stress [Pa]\n" + rows


def test_the_intrusion_speed_ignores_holds_and_noise():
    from mudrft.io.dataset import intrusion_speed

    t = np.linspace(0.0, 1.0, 1001)
    depth = np.clip(0.05 * (t - 0.3), 0.0, 0.02)  # 0.05 m/s from 0.3 s, held from 0.7 s
    noisy = depth + 2e-5 * np.random.default_rng(1).standard_normal(t.size)
    assert intrusion_speed(t, depth) == pytest.approx(0.05, rel=0.01)
    assert intrusion_speed(t, noisy) == pytest.approx(0.05, rel=0.05)
    assert intrusion_speed(t, -depth) == 0.0  # never deeper than its start


@pytest.mark.parametrize("rate_hz", [1_000.0, 20_000.0])
def test_times_logged_in_ms_and_labelled_s_warn(tmp_path, rate_hz):
    """The paper's 0.13 m/s logged in ms and read as s ran at 0.13 mm/s: a fit of a test a
    thousand times slower, with no word."""
    p = write(tmp_path, _ramp_log(rate_hz, 0.13, time_scale=1e3))
    with pytest.warns(
        PlausibilityWarning, match=r"runs at 0.00013 m/s, less than 0.001.*'time \[ms\]'"
    ):
        load_intrusion_csv(p)
    stated = write(tmp_path, _ramp_log(rate_hz, 0.13, time_scale=1e3, unit="ms"), "ms.csv")
    assert quiet_load(stated).trials[0].time[-1] == pytest.approx(0.02 / 0.13 + 0.2, abs=1e-3)


def test_times_in_s_labelled_ms_warn(tmp_path):
    p = write(tmp_path, _ramp_log(1_000.0, 0.13, unit="ms"))
    with pytest.warns(
        PlausibilityWarning, match=r"runs at 130 m/s, more than 20 m/s.*'time \[s\]'"
    ):
        load_intrusion_csv(p)


def test_times_in_us_labelled_ms_point_to_us(tmp_path):
    p = write(tmp_path, _ramp_log(1_000.0, 0.13, time_scale=1e6, unit="ms"))
    with pytest.warns(PlausibilityWarning, match=r"\(read as ms\); .*'time \[us\]'"):
        load_intrusion_csv(p)


@pytest.mark.parametrize(("rate_hz", "speed"), [(1_000.0, 5e-4), (10.0, 0.05), (200.0, 2.0)])
def test_plausible_slow_or_fast_tests_read_quietly(tmp_path, rate_hz, speed):
    """A slow test sampled fast, a test sampled slowly but fast enough, a fast foot."""
    quiet_load(write(tmp_path, _ramp_log(rate_hz, speed)))


@pytest.mark.parametrize(
    ("header", "message"),
    [
        (
            "time [ms],position [mm],load [N]",
            "no depth column; name it 'depth' or 'displacement', with its unit (e.g. "
            "'depth [mm]'), or name it with columns={'depth': 'NAME'} (CLI: --columns "
            "depth=NAME); got ['time [ms]', 'position [mm]', 'load [N]']",
        ),
        (
            "Zeit [ms],depth [mm],force [N]",
            "no time column; name it 'time' or 't', with its unit (e.g. 'time [ms]'), or "
            "name it with columns={'time': 'NAME'} (CLI: --columns time=NAME); got "
            "['Zeit [ms]', 'depth [mm]', 'force [N]']",
        ),
        (
            "time [ms],depth [mm],load [N]",
            "needs a stress or a force column; name it 'stress' or 'sigma' (e.g. "
            "'stress [Pa]'), or 'Fz', 'force' or 'F' (e.g. 'force [N]'), or name it with "
            "columns={'force': 'NAME'} (CLI: --columns force=NAME); got "
            "['time [ms]', 'depth [mm]', 'load [N]']",
        ),
    ],
)
def test_a_column_with_its_rigs_own_name_is_told_the_names_mudrft_reads(tmp_path, header, message):
    """A new user's rig logs 'position [mm]' and 'load [N]': the error said only
    "expected e.g. 'depth [m]'", not which names are read, nor that the unit in the
    header may stay as the rig logs it."""
    p = write(tmp_path, f"{header}\n0,0,0\n100,2,10\n")
    with pytest.raises(MudrftError) as exc:
        load_intrusion_csv(p, area=0.0025)
    assert str(exc.value) == f"{p}: line 1: {message}"


# -- columns as the logger wrote them (issue 39) ----------------------------------------------
LAB = "Zeit (ms)\tPosition (mm)\tLoad (N)\tpos\n0\t0\t0\t0\n100\t2\t0.8\t2\n200\t4\t1.44\t4\n"


def test_a_column_mapping_names_the_columns_a_logger_calls_otherwise(tmp_path):
    p = write(tmp_path, LAB, "lab.txt")
    with pytest.raises(MudrftError, match=r"no time column; .*columns=\{'time': 'NAME'\}"):
        load_intrusion_csv(p, area=0.0016)
    mapping = {"time": "zeit (ms)", "depth": "Position (mm)", "force": "Load (N)"}
    tr = quiet_load(p, area=0.0016, columns=mapping).trials[0]
    np.testing.assert_allclose(tr.time, [0.0, 0.1, 0.2], rtol=1e-12)
    np.testing.assert_allclose(tr.depth, [0.0, 0.002, 0.004], rtol=1e-12)
    np.testing.assert_allclose(tr.stress, [0.0, 500.0, 900.0], rtol=1e-12)
    # a column without a unit takes the one given with the mapping
    units = {**mapping, "depth": "pos [mm]"}
    np.testing.assert_array_equal(
        quiet_load(p, area=0.0016, columns=units).trials[0].depth, tr.depth
    )
    via = load_dataset(p, area=0.0016, columns=mapping)  # the same through load_dataset
    np.testing.assert_array_equal(via.trials[0].stress, tr.stress)


@pytest.mark.parametrize(
    ("columns", "message"),
    [
        (
            {"time": "Time (s)"},
            r"columns maps time to 'Time \(s\)', but no column is named so; "
            r"the columns are \['Zeit \(ms\)'",
        ),
        ({"speed": "Load (N)"}, r"columns must map roles, of \['depth', 'force', .*got 'speed'"),
        ({"time": "Zeit (ms)", "depth": "Zeit (ms)"}, r"maps both time and depth to 'Zeit \(ms\)'"),
        ({"depth": "pos"}, r"column 'pos' has no unit; write it as 'pos \[m\]'"),
        ({"time": "Zeit (ms)", "force": "Load (N)"}, r"no depth column"),
    ],
)
def test_a_column_mapping_that_does_not_fit_the_file_is_named(tmp_path, columns, message):
    p = write(tmp_path, LAB, "lab.txt")
    with pytest.raises(MudrftError, match=message):
        load_intrusion_csv(p, area=0.0016, columns=columns)


def test_an_hdf5_log_takes_a_column_mapping(tmp_path):
    h5py = pytest.importorskip("h5py")
    p = tmp_path / "lab.h5"
    with h5py.File(p, "w") as fh:
        fh["Zeit (ms)"] = [0.0, 100.0, 200.0]
        fh["Weg (mm)"] = [0.0, 2.0, 4.0]
        fh["stress [kPa]"] = [0.0, 0.5, 0.9]
    tr = load_dataset(p, columns={"time": "Zeit (ms)", "depth": "Weg (mm)"}).trials[0]
    np.testing.assert_allclose(tr.depth, [0.0, 0.002, 0.004], rtol=1e-12)
    np.testing.assert_allclose(tr.time, [0.0, 0.1, 0.2], rtol=1e-12)


# -- the last silent inputs of a log (issue 43) -----------------------------------------------
@pytest.mark.parametrize("value", ["5000", "0"])
def test_a_stress_of_one_value_throughout_is_refused(tmp_path, value):
    """numpy's 'zero-size array to reduction operation' came out of mudrft calibrate."""
    rows = "".join(f"{0.1 * k:.1f},{0.002 * min(k, 8 - k)},{value}\n" for k in range(9))
    p = write(tmp_path, "time [s],depth [m],stress [Pa]\n" + rows)
    said = rf"log.csv: line 2, column 'stress \[Pa\]': trial 'trial': stress is {value}.0 Pa in every sample"  # fmt: skip
    with pytest.raises(MudrftError, match=said):
        load_intrusion_csv(p)


def test_a_cli_calibration_of_a_constant_stress_is_one_line(tmp_path, capsys):
    rows = "".join(f"{0.1 * k:.1f},{0.002 * min(k, 8 - k)},5000\n" for k in range(9))
    p = write(tmp_path, "time [s],depth [m],stress [Pa]\n" + rows)
    assert main(["calibrate", str(p), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "stress is 5000.0 Pa in every sample" in err


def test_a_log_in_kpa_labelled_pa_warns(tmp_path):
    """It fitted sigma_y = 7.2 Pa, a thousand times too soft, without a word (issue 43)."""
    p = write(
        tmp_path, HEADER + ROWS.replace("500", "0.5").replace("900", "0.9").replace("-100", "-0.1")
    )
    with pytest.warns(PlausibilityWarning, match=r"peaks at 0.9 Pa, less than 100 Pa.*'stress \[kPa\]'"):  # fmt: skip
        load_intrusion_csv(p)


def test_a_trials_speed_is_its_rate_in_the_mud_not_its_largest_step():
    """An approach from 5 mm above the surface in one step, 0.02 mm of depth noise at
    500 Hz, a hold and a retraction: 'the largest rate' labelled a 10 mm/s trial
    1.25e+03 mm/s (issue 39)."""
    t = np.arange(0.0, 7.0, 0.002)
    depth = np.where(t < 3.0, 0.01 * t, np.maximum(0.03 - 0.01 * (t - 4.0), 0.0))
    depth = np.where((t >= 3.0) & (t < 4.0), 0.03, depth)
    depth[:1] = -0.005  # the plate above the surface, then at it
    noisy = depth + 2e-5 * np.random.default_rng(4).standard_normal(t.size)
    stress = 2e4 * np.sqrt(np.clip(depth, 0.0, None) / 0.03) + 1.0
    tr = Trial(t, noisy, stress)
    assert tr.speed == pytest.approx(0.01, rel=0.01)
    assert "speed=0.01 m/s" in repr(tr)
