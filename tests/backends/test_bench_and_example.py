"""The benchmark's roofline arithmetic, its CLI checks, and the JAX calibration example.

The harness lives in the checkout's ``benchmarks/harness``; it is loaded the way
``mudrft bench`` loads it. No assertion here is on wall time.
"""

from __future__ import annotations

import argparse
import runpy
import sys
from pathlib import Path

import pytest

from mudrft._validation import MudrftError
from mudrft.cli import bench as bench_cli

REPO = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def harness():
    """The benchmark harness, loaded from the checkout as ``mudrft bench`` does."""
    return bench_cli.load_harness()


def _fake_results(ns_channel: float) -> dict:
    return {
        "limits": {"copy_GBps": 10.0, "matmul_GFLOPs": 100.0},
        "constitutive": {"numpy_batch_ns_per_channel": ns_channel},
        "mesh": {"1e5": {"numpy_ns_per_facet": 5.0}},
        "batch": {"numpy": {"100000": {"us_per_foot": 1.0}}},
    }


def test_roofline_limit_is_the_slower_of_memory_and_compute(harness):
    w = harness.ROOFLINE["channel_step"]
    t_mem = w["bytes"] / 10e9 * 1e9  # ns at 10 GB/s
    t_cpu = w["flops"] / 100e9 * 1e9  # ns at 100 GFLOP/s
    limit = max(t_mem, t_cpu)
    r = harness.roofline(_fake_results(ns_channel=2 * limit))["channel_step"]
    assert r["limit_ns"] == pytest.approx(limit, rel=1e-12)
    assert r["bound"] == ("memory" if t_mem >= t_cpu else "compute")
    assert r["ratio_to_limit"]["numpy"] == pytest.approx(0.5, rel=1e-12)
    foot = harness.roofline(_fake_results(1.0))["foot_step"]
    assert foot["measured_ns"]["numpy"] == pytest.approx(1000.0)


def test_harness_is_loaded_from_the_checkout_not_the_package(harness):
    assert Path(harness.__file__).resolve() == REPO / "benchmarks" / "harness" / "__init__.py"
    assert bench_cli.load_harness() is harness  # once per process
    assert callable(harness.run_benchmarks) and callable(harness.summary_lines)


def test_bench_without_a_checkout_fails_in_one_line_naming_what_to_do(tmp_path, monkeypatch):
    monkeypatch.delitem(sys.modules, bench_cli.HARNESS_MODULE, raising=False)
    monkeypatch.setattr(bench_cli, "harness_path", lambda: tmp_path / "benchmarks" / "harness")
    with pytest.raises(MudrftError, match="source checkout") as info:
        bench_cli.load_harness()
    message = str(info.value)
    assert "\n" not in message and "pip install -e" in message
    assert bench_cli.HARNESS_MODULE not in sys.modules


def test_bench_refuses_a_json_path_in_a_missing_directory(tmp_path):
    args = argparse.Namespace(
        quick=True, json=str(tmp_path / "nope" / "out.json"), quiet=True, force=False
    )
    with pytest.raises(MudrftError, match="does not exist"):
        bench_cli.run(args)


def test_bench_parser_has_quick_and_json():
    parser = argparse.ArgumentParser()
    sub = parser.add_subparsers()
    bench_cli.add_parser(sub)
    ns = parser.parse_args(["bench", "--quick", "--json", "x.json", "--force"])
    assert ns.quick and ns.json == "x.json" and ns.force and ns.func is bench_cli.run


def test_jax_gradient_calibration_example_recovers_alpha_and_eta_inf(capsys):
    """Round trip: the example's L-BFGS-B with JAX gradients recovers the synthetic truth."""
    pytest.importorskip("jax")
    script = REPO / "examples" / "jax_gradient_calibration.py"
    mod = runpy.run_path(str(script))
    assert mod["main"]() == 0  # main returns 0 only within 2 % (alpha) and 5 % (eta_inf)
    assert "recovered" in capsys.readouterr().out
