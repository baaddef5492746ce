"""A store that knows what it holds: damaged chunks are named (or masked on request) when
read, recomputed on resume whatever their ``done`` flag says, and a store whose metadata is
gone is refused with how to start again. Before, a chunk of random bytes raised zarr's
``RuntimeError: Zstd decompression error`` and a removed chunk read as fill values silently.
"""

from __future__ import annotations

import json
import shutil

import numpy as np
import pytest

import mudrft
from mudrft._validation import MudrftError
from mudrft.cli import main
from mudrft.sweep import load_result, load_spec

pytest.importorskip("xarray")
pytest.importorskip("zarr")

SPEC = {
    "sweep": {"metrics": ["max_suction", "max_depth"], "points_per_task": 2},
    "foot": {"kind": "flat", "width": [0.05, 0.06, 0.065]},
    "mud": {"water_content": [0.25, 0.35]},
    "motion": {"speed": 0.2},
}
CHUNK = 1  # the damaged chunk: width = 0.06, both water contents
FILE = "max_suction/c/1/0"  # its max_suction chunk file (chunk grid index (1, 0))


@pytest.fixture(scope="module")
def undamaged(tmp_path_factory):
    store = tmp_path_factory.mktemp("sweep") / "s.zarr"
    return store, mudrft.sweep(SPEC, store=store, scheduler="serial")


@pytest.fixture
def store(undamaged, tmp_path):
    copy = tmp_path / "s.zarr"
    shutil.copytree(undamaged[0], copy)
    return copy


def damage(path, how):
    rng = np.random.default_rng(0)
    data = bytearray(path.read_bytes())
    if how == "random bytes":
        path.write_bytes(rng.integers(0, 256, len(data), dtype=np.uint8).tobytes())
    elif how == "truncated":
        path.write_bytes(b"")
    elif how in ("3 flipped bytes", "3 flipped bytes at the end"):
        start = 0 if how == "3 flipped bytes" else len(data) - 3
        for k in range(start, start + 3):
            data[k] ^= 0x5A
        path.write_bytes(bytes(data))
    else:  # removed, its done flags kept
        path.unlink()


HOW = ["random bytes", "truncated", "3 flipped bytes", "3 flipped bytes at the end", "removed"]


@pytest.mark.parametrize("how", HOW)
def test_a_damaged_chunk_is_named_masked_on_request_and_recomputed_on_resume(store, undamaged, how):  # fmt: skip
    ref = undamaged[1]
    damage(store / FILE, how)
    with pytest.raises(MudrftError) as info:
        load_result(store)
    message = str(info.value)
    assert message.startswith(f"store {str(store)!r} is damaged: 1 of 3 chunks cannot be trusted: chunk 1 (width = 0.06, water_content = 0.25..0.35): ")  # fmt: skip
    assert "resume=True (CLI: --resume) recomputes them" in message
    masked = load_result(store, on_damage="mask")
    bad = masked.sel(width=0.06)
    assert np.isnan(bad["max_suction"]).all() and np.isnan(bad["max_depth"]).all()
    assert all(e.startswith("damaged: chunk 1 of the store") for e in bad["error"].values)
    assert (bad["done"] == 0).all() and masked.attrs["damaged_chunks"] == [CHUNK]
    good = masked.sel(width=[0.05, 0.065])
    assert np.array_equal(good["max_suction"], ref["max_suction"].sel(width=[0.05, 0.065]))
    resumed = mudrft.sweep(SPEC, store=store, scheduler="serial", resume=True)
    for name in ref.data_vars:
        assert np.array_equal(resumed[name].values, ref[name].values), name
    assert "damaged_chunks" not in load_result(store).attrs


def test_resume_recomputes_only_the_damaged_chunk(store, monkeypatch):
    from mudrft.sweep import evaluate

    damage(store / "max_depth/c/2/0", "random bytes")  # chunk 2: width = 0.065
    calls = []
    real = evaluate.evaluate_point
    monkeypatch.setattr(evaluate, "evaluate_point", lambda c, p, **kw: calls.append(p) or real(c, p, **kw))  # fmt: skip
    mudrft.sweep(SPEC, store=store, scheduler="serial", resume=True)
    assert calls == load_spec(SPEC).chunk_points(2)


def test_a_missing_done_flag_of_a_completed_store_is_damage(store):
    (store / "done/c/0/0").unlink()
    with pytest.raises(MudrftError, match=r"chunk 0 \(width = 0.05, .*\): its done flags are missing"):  # fmt: skip
        load_result(store)


def test_a_store_without_its_root_or_array_metadata_is_refused_saying_how_to_start_again(
    store, tmp_path
):
    shutil.copytree(store, tmp_path / "t.zarr")
    (store / "max_depth" / "zarr.json").unlink()
    for call in (lambda: load_result(store), lambda: mudrft.sweep(SPEC, store=store, resume=True)):  # fmt: skip
        with pytest.raises(MudrftError, match=r"the metadata of its array 'max_depth' \(max_depth/zarr.json\) is gone or unreadable, so the store cannot be read or resumed; start again with overwrite=True \(CLI: --force\)"):  # fmt: skip
            call()
    assert mudrft.sweep(SPEC, store=store, scheduler="serial", overwrite=True).attrs["complete"] == 1  # fmt: skip
    root = tmp_path / "t.zarr"
    (root / "zarr.json").unlink()
    with pytest.raises(MudrftError, match=r"has no readable zarr.json: .* if it was a sweep, remove the directory and run the sweep again"):  # fmt: skip
        load_result(root)
    with pytest.raises(MudrftError, match="not a mudrft sweep store; refusing to replace it"):
        mudrft.sweep(SPEC, store=root, overwrite=True)


def test_a_store_of_the_first_format_or_half_made_is_refused(store):
    meta = json.loads((store / "zarr.json").read_text())
    meta["attributes"]["mudrft_sweep_format"] = 1
    (store / "zarr.json").write_text(json.dumps(meta))
    with pytest.raises(MudrftError, match=r"store format 1 .* no chunk checksums .* overwrite=True"):  # fmt: skip
        load_result(store)
    with pytest.raises(MudrftError, match="on_damage must be 'raise' or 'mask', got 'skip'"):
        load_result(store, on_damage="skip")
    meta["attributes"]["mudrft_sweep_format"] = 2
    del meta["attributes"]["arrays"]  # a kill while the store was made: written last
    (store / "zarr.json").write_text(json.dumps(meta))
    with pytest.raises(MudrftError, match=r"was not completely created .* overwrite=True"):
        mudrft.sweep(SPEC, store=store, resume=True)


def test_the_command_line_names_the_damage_and_resume_repairs_it(tmp_path, capsys):
    spec = tmp_path / "s.toml"
    spec.write_text(
        '[sweep]\nmetrics = ["max_depth"]\npoints_per_task = 1\n[foot]\nkind = "flat"\n'
        "width = [0.05, 0.06]\n[motion]\nspeed = 0.2\n"
    )
    out = tmp_path / "o"
    args = ["sweep", str(spec), "--out", str(out), "--scheduler", "serial", "--quiet"]
    assert main(args) == 0
    damage(out / "sweep.zarr" / "max_depth" / "c" / "1", "random bytes")
    assert main([*args, "--force"]) == 0  # starts again
    damage(out / "sweep.zarr" / "max_depth" / "c" / "1", "truncated")
    capsys.readouterr()
    assert main([*args, "--resume", "--force"]) == 0
    err = capsys.readouterr().err
    assert "1 damaged chunk(s)" in err and "chunk 1: max_depth does not decode" in err
    assert np.isfinite(load_result(out / "sweep.zarr")["max_depth"]).all()
