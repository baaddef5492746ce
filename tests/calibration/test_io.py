"""Loading intrusion logs: units, trials, metadata, and malformed files (never a traceback,
never a modified input)."""

from __future__ import annotations

import os
import tempfile
import warnings
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from mudrft._validation import MudrftError, PlausibilityWarning
from mudrft.io import (
    IntrusionDataset,
    Trial,
    load_dataset,
    load_intrusion_csv,
    load_intrusion_hdf5,
    save_intrusion_csv,
    save_intrusion_hdf5,
)


def _write(tmp: Path, text: str | bytes, name: str = "log.csv") -> Path:
    p = tmp / name
    if isinstance(text, bytes):
        p.write_bytes(text)
    else:
        p.write_text(text, encoding="utf-8")
    return p


def _fingerprint(p: Path) -> tuple[bytes, int]:
    return p.read_bytes(), os.stat(p).st_mtime_ns


# --------------------------------------------------------------------------------------
# well-formed files
# --------------------------------------------------------------------------------------
def test_units_are_converted_to_si(tmp_path):
    text = (
        "# direction: vertical\ntime [ms],depth [mm],stress [kPa]\n0,0,0\n250,5,1.5\n500,10,2.25\n"
    )
    ds = load_intrusion_csv(_write(tmp_path, text))
    tr = ds[0]
    # exact conversions by powers of ten (compare to 1e-12 relative: float rounding only)
    np.testing.assert_allclose(tr.time, [0.0, 0.25, 0.5], rtol=1e-12)
    np.testing.assert_allclose(tr.depth, [0.0, 0.005, 0.010], rtol=1e-12)
    np.testing.assert_allclose(tr.stress, [0.0, 1500.0, 2250.0], rtol=1e-12)
    assert ds.direction == "vertical"


def test_mpa_and_seconds(tmp_path):
    ds = load_intrusion_csv(
        _write(tmp_path, "t [s],displacement [m],sigma [MPa]\n0,0,0\n1,0.01,0.02\n")
    )
    np.testing.assert_allclose(ds[0].stress, [0.0, 2.0e4], rtol=1e-12)


def test_force_needs_an_area_and_is_divided_by_it(tmp_path):
    p = _write(tmp_path, "time [s],depth [m],Fz [N]\n0,0,0\n1,0.01,5\n2,0.02,7.5\n")
    with pytest.raises(MudrftError, match="area"):
        load_intrusion_csv(p)
    ds = load_intrusion_csv(p, area=0.0025)
    np.testing.assert_allclose(ds[0].stress, [0.0, 2000.0, 3000.0], rtol=1e-12)
    # the area can also come from the header (in cm^2)
    p2 = _write(
        tmp_path, "# area [cm^2]: 25\ntime [s],depth [m],force [kN]\n0,0,0\n1,0.01,0.005\n", "h.csv"
    )
    np.testing.assert_allclose(load_intrusion_csv(p2)[0].stress, [0.0, 2000.0], rtol=1e-12)


def test_characteristic_length_sets_gamma(tmp_path):
    text = "# characteristic_length [mm]: 40\ntime [s],depth [mm],stress [Pa]\n0,0,0\n1,10,5000\n"
    p = _write(tmp_path, text)
    assert load_intrusion_csv(p)[0].gamma[-1] == pytest.approx(0.25, rel=1e-12)
    # the argument overrides the header
    assert load_intrusion_csv(p, characteristic_length=0.05)[0].gamma[-1] == pytest.approx(0.2)


def test_trial_column_splits_trials_in_order_of_appearance(tmp_path):
    text = (
        "trial,time [s],depth [m],stress [kPa]\n"
        "slow,0,0,0\nslow,1,0.01,10\nfast,0,0,0\nfast,0.5,0.01,20\nslow,2,0.02,15\n"
    )
    ds = load_intrusion_csv(_write(tmp_path, text))
    assert [t.name for t in ds] == ["slow", "fast"]
    np.testing.assert_allclose(ds[0].time, [0.0, 1.0, 2.0])
    np.testing.assert_allclose(ds[1].stress, [0.0, 20e3])
    # trial speeds follow the depth and time columns
    assert ds.speeds == pytest.approx([0.01, 0.02])


def test_csv_round_trip(tmp_path):
    rng = np.random.default_rng(0)
    t = np.linspace(0, 1, 11)
    tr1 = Trial(t, 0.03 * t, 1e4 * rng.random(11), name="a")
    tr2 = Trial(t, 0.02 * t, 1e4 * rng.random(11), name="b")
    ds = IntrusionDataset((tr1, tr2), direction="horizontal", notes=("synthetic: test data",))
    p = save_intrusion_csv(ds, tmp_path / "rt.csv")
    back = load_intrusion_csv(p)
    assert back.direction == "horizontal" and back.synthetic
    for a, b in zip(ds, back, strict=True):
        # the writer keeps 6 significant digits
        np.testing.assert_allclose(b.stress, a.stress, rtol=1e-5)
        np.testing.assert_allclose(b.depth, a.depth, rtol=1e-5)
        assert a.name == b.name


def test_writers_never_overwrite(tmp_path):
    ds = IntrusionDataset.from_arrays([0.0, 1.0], [0.0, 0.01], [0.0, 1000.0])
    p = _write(tmp_path, "precious user data\n")
    before = _fingerprint(p)
    with pytest.raises(MudrftError, match="exists"):
        save_intrusion_csv(ds, p)
    assert _fingerprint(p) == before
    save_intrusion_csv(ds, p, overwrite=True)
    assert load_intrusion_csv(p)[0].stress[-1] == 1000.0


def test_hdf5_round_trip_and_unit_attributes(tmp_path):
    h5py = pytest.importorskip("h5py")
    t = np.linspace(0, 1, 5)
    trials = (Trial(t, 0.02 * t, 100 * t, name="v10mm/s"), Trial(t, 0.03 * t, 90 * t, name="b"))
    ds = IntrusionDataset(trials, notes=("synthetic: yes",))
    p = save_intrusion_hdf5(ds, tmp_path / "d.h5")
    back = load_dataset(p)
    np.testing.assert_allclose(back[0].stress, ds[0].stress, rtol=1e-15)
    assert back.synthetic
    # the labels as they were (the groups are '000_v10mm_s', '001_b': ordered, no '/')
    assert [tr.name for tr in back.trials] == ["v10mm/s", "b"]
    # a bare dataset name with a unit attribute, and a force with an area attribute
    q = tmp_path / "u.h5"
    with h5py.File(q, "w") as fh:
        fh.attrs["area"] = 0.01
        fh.create_dataset("time", data=[0.0, 100.0, 200.0]).attrs["unit"] = "ms"
        fh.create_dataset("depth [mm]", data=[0.0, 1.0, 2.0])
        fh.create_dataset("Fz [N]", data=[0.0, 10.0, 20.0])
    tr = load_intrusion_hdf5(q)[0]
    np.testing.assert_allclose(tr.time, [0.0, 0.1, 0.2], rtol=1e-12)
    np.testing.assert_allclose(tr.stress, [0.0, 1000.0, 2000.0], rtol=1e-12)


def test_hdf5_errors_name_the_file(tmp_path):
    h5py = pytest.importorskip("h5py")
    q = tmp_path / "bad.h5"
    with h5py.File(q, "w") as fh:
        fh.create_dataset("time [s]", data=[0.0, 1.0])
        fh.create_dataset("depth [parsec]", data=[0.0, 1.0])
        fh.create_dataset("stress [Pa]", data=[0.0, 1.0])
    with pytest.raises(MudrftError, match=r"bad\.h5.*depth \[parsec\]"):
        load_intrusion_hdf5(q)
    with pytest.raises(MudrftError, match="not a readable HDF5"):
        load_intrusion_hdf5(_write(tmp_path, "time [s]\n", "fake.h5"))


# --------------------------------------------------------------------------------------
# malformed files: a precise MudrftError naming the file (and line/column), input unchanged
# --------------------------------------------------------------------------------------
GOOD_HEADER = "time [s],depth [m],stress [Pa]\n"
MALFORMED = {
    "empty": ("", "no header"),
    "comments only": ("# nothing here\n", "no header"),
    "header only": (GOOD_HEADER, "no data rows"),
    "unknown unit": (
        "time [fortnight],depth [m],stress [Pa]\n0,0,0\n",
        "line 1, column 1.*fortnight",
    ),
    "missing unit": ("time,depth [m],stress [Pa]\n0,0,0\n", "line 1, column 1.*no unit"),
    "no depth": ("time [s],stress [Pa]\n0,0\n", "line 1.*no depth column"),
    "no stress": ("time [s],depth [m]\n0,0\n", "stress.*or a force column"),
    "text in cell": (
        GOOD_HEADER + "0,0,0\n1,abc,2\n",
        r"line 3, column 2 \('depth \[m\]'\).*'abc'",
    ),
    "empty cell": (GOOD_HEADER + "0,0,0\n1,,2\n", "line 3, column 2.*empty cell"),
    "nan": (GOOD_HEADER + "0,0,0\n1,0.01,nan\n", "line 3, column 3.*not finite"),
    "inf": (GOOD_HEADER + "0,0,0\n1,0.01,-inf\n", "line 3, column 3.*not finite"),
    "overflow": (
        "time [s],depth [m],stress [MPa]\n0,0,0\n1,0.01,1e305\n",
        "line 3, column 3.*overflow",
    ),
    "too few fields": (GOOD_HEADER + "0,0,0\n1,0.01\n", "line 3: expected 3"),
    "too many fields": (GOOD_HEADER + "0,0,0,9\n", "line 2: expected 3"),
    "time backwards": (
        GOOD_HEADER + "0,0,0\n1,0.01,5\n0.5,0.02,6\n",
        r"line 4, column 'time \[s\]'.*increase",
    ),
    "repeated time": (GOOD_HEADER + "0,0,0\n0,0.01,5\n", "line 3.*increase"),
    "one sample": (GOOD_HEADER + "0,0,0\n", "line 2.*at least 2"),
    "duplicate column": (
        "time [s],depth [m],depth [mm],stress [Pa]\n0,0,0,0\n",
        "column 3.*two columns",
    ),
    "bad quote": ('time [s],depth [m],stress [Pa]\n0,"0,0\n', "line 2.*malformed CSV"),
    "bad direction": ("# direction: sideways\n" + GOOD_HEADER + "0,0,0\n", "line 1.*direction"),
    "negative length": (
        "# characteristic_length [m]: -1\n" + GOOD_HEADER + "0,0,0\n",
        "line 1.*characteristic_length",
    ),
    "Fz horizontal": (
        "# direction: horizontal\ntime [s],depth [m],Fz [N]\n0,0,0\n1,0.1,1\n",
        "line 2.*'Fz'",
    ),
    "empty trial": (
        "trial,time [s],depth [m],stress [Pa]\na,0,0,0\n,1,0.01,1\n",
        "line 3.*empty trial",
    ),
    "NUL byte": (b"time [s],depth [m],stress [Pa]\n0,0\x00,0\n", "line 2.*NUL"),
    "latin-1": ("time [s],depth [m],stress [Pa]\n# caf\xe9\n".encode("latin-1"), "line 2.*UTF-8"),
}


@pytest.mark.parametrize("case", sorted(MALFORMED))
def test_malformed_file_raises_precise_error_and_is_untouched(tmp_path, case):
    content, pattern = MALFORMED[case]
    p = _write(tmp_path, content)
    before = _fingerprint(p)
    with pytest.raises(MudrftError) as info:
        load_intrusion_csv(p)
    msg = str(info.value)
    assert msg.startswith(str(p)), msg
    assert __import__("re").search(pattern, msg), msg
    assert _fingerprint(p) == before


def test_missing_file_and_directory(tmp_path):
    with pytest.raises(MudrftError, match="no such file"):
        load_intrusion_csv(tmp_path / "absent.csv")
    with pytest.raises(MudrftError, match="is a directory"):
        load_intrusion_csv(tmp_path)


_CSV_CHARS = st.sampled_from(
    [
        *"0123456789.,-+e#[]\n \"'",
        "nan",
        "inf",
        "time [s]",
        "depth [mm]",
        "stress [kPa]",
        "Fz [N]",
        "trial",
        ",",
        "\n",
        "ms",
    ]
)


def _check_file(content: bytes) -> None:
    with tempfile.TemporaryDirectory() as d:
        p = Path(d) / "fuzz.csv"
        p.write_bytes(content)
        before = _fingerprint(p)
        # a corrupted number can make a valid but suspicious log (a 1 m depth, a stress of
        # the wrong sign): a PlausibilityWarning is an answer, not a traceback
        with warnings.catch_warnings(record=True) as said:
            warnings.simplefilter("always")
            try:
                ds = load_intrusion_csv(p, area=0.01)
            except MudrftError as exc:
                assert str(exc).startswith(str(p)), str(exc)
            else:
                # anything accepted is a valid dataset in SI
                assert all(
                    np.all(np.isfinite(t.stress)) and np.all(np.diff(t.time) > 0) for t in ds
                )
        assert all(issubclass(w.category, PlausibilityWarning) for w in said), [
            str(w.message) for w in said
        ]
        assert _fingerprint(p) == before


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(_CSV_CHARS, max_size=80).map("".join))
def test_fuzzed_csv_text_never_tracebacks(text):
    _check_file((GOOD_HEADER + text).encode("utf-8"))


@settings(max_examples=30, deadline=None)
@given(st.binary(max_size=200))
def test_fuzzed_bytes_never_traceback(data):
    _check_file(data)


@settings(max_examples=30, deadline=None)
@given(st.integers(min_value=0, max_value=200), st.text(max_size=5))
def test_corrupted_valid_file_never_tracebacks(pos, junk):
    good = GOOD_HEADER + "".join(f"{0.1 * k:.2f},{0.001 * k:.4f},{100 * k}\n" for k in range(12))
    pos = min(pos, len(good))
    _check_file((good[:pos] + junk + good[pos + len(junk) :]).encode("utf-8"))


def test_a_direction_that_overrides_the_files_is_said(tmp_path, caplog):
    """direction= still wins over the file's '# direction:' (documented), but no longer
    silently: a warning names the file, both directions and where the file says it."""
    import logging

    from mudrft.calibration import example_dataset, save_intrusion_csv
    from mudrft.io import load_dataset

    path = tmp_path / "h.csv"
    save_intrusion_csv(example_dataset("horizontal"), path)
    with caplog.at_level(logging.WARNING, logger="mudrft"):
        same = load_dataset(path, direction="horizontal")
    assert same.direction == "horizontal" and not caplog.records
    with caplog.at_level(logging.WARNING, logger="mudrft"):
        ds = load_dataset(path, direction="vertical")
    assert ds.direction == "vertical"
    (record,) = caplog.records
    assert (
        "h.csv" in record.getMessage()
        and "overrides the file's 'horizontal'" in record.getMessage()
    )


def test_a_log_whose_depth_is_never_positive_is_refused(tmp_path):
    """A log recorded with the opposite sign (every depth <= 0) is an error that names the
    column and says what to do; it used to be fitted to the parameter bounds, exit 0."""
    from mudrft.calibration import example_dataset, save_intrusion_csv
    from mudrft.io import load_dataset

    path = tmp_path / "v.csv"
    save_intrusion_csv(example_dataset("vertical"), path)
    lines = path.read_text().splitlines()
    head = next(i for i, line in enumerate(lines) if not line.startswith("#"))
    cols = lines[head].split(",")
    k = next(i for i, c in enumerate(cols) if c.strip().lower().startswith("depth"))
    flipped = lines[: head + 1]
    for line in lines[head + 1 :]:
        cells = line.split(",")
        cells[k] = str(-float(cells[k]))
        flipped.append(",".join(cells))
    bad = tmp_path / "negative.csv"
    bad.write_text("\n".join(flipped) + "\n")
    load_dataset(path)  # the original loads
    with pytest.raises(
        MudrftError, match=r"negative.csv.*'depth \[m\]'.*never positive.*flip its sign"
    ):
        load_dataset(bad)
