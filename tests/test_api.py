"""The public names DESIGN.md promises, used exactly as written there."""

from __future__ import annotations

import importlib

import numpy as np
import pytest

import mudrft


def test_simulate_stays_callable_after_submodules_are_imported():
    for mod in (
        "mudrft.simulation",
        "mudrft.reproduce",
        "mudrft.cli",
        "mudrft.backends.batch",
        "mudrft.integrations.mujoco",
        "mudrft.calibration",
    ):
        importlib.import_module(mod)
    assert callable(mudrft.simulate) and callable(mudrft.calibrate)


def test_parameters_contract():
    mud = mudrft.paper_mud(water_content=0.25)
    assert isinstance(mud.vertical, mudrft.MudParameters) and isinstance(
        mud.horizontal, mudrft.MudParameters
    )
    p = mudrft.paper_parameters(water_content=0.25, direction="vertical")
    for field in (
        "alpha",
        "n",
        "lam",
        "eta_m",
        "eta_inf",
        "gamma_dot_c",
        "tau_build",
        "tau_leak",
        "epsilon",
        "sigma_y",
    ):
        assert isinstance(getattr(p, field), float)
    import dataclasses

    with pytest.raises(dataclasses.FrozenInstanceError):
        p.alpha = 1.0  # type: ignore[misc]


@pytest.mark.parametrize(
    "foot",
    [
        mudrft.feet.Flat(length=0.08, width=0.065),
        mudrft.feet.SemiCylinder(radius=0.045, width=0.065),
        mudrft.feet.SemiSphere(radius=0.045),
        mudrft.feet.MorphingFoot(),
    ],
    ids=lambda f: f.name,
)
def test_feet_contract(foot):
    f = foot.resultant(0.02, (5e3, 3e3, 2e4), 0.3)
    assert isinstance(f, np.ndarray) and f.shape == (3,) and np.all(f > 0)
    result = mudrft.simulate(foot, mudrft.paper_mud(0.25), mudrft.gait(speed=0.2))
    assert result.force.shape == (len(result.time), 3)
    assert set(result.metrics()) >= {
        "peak_support",
        "max_suction",
        "impulse_x",
        "impulse_y",
        "impulse_z",
        "energy",
        "max_depth",
    }
    assert result.metrics()["max_depth"] == pytest.approx(0.02)  # the gait's stance depth


def test_mesh_foot_contract(tmp_path):
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float) * 0.05
    faces = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    foot = mudrft.feet.MeshFoot(v, faces)
    assert foot.resultant(0.01, (1e3, 1e3, 1e4), 0.0).shape == (3,)
    stl = tmp_path / "foot.stl"
    stl.write_text(
        "solid t\n"
        + "".join(
            "facet normal 0 0 0\nouter loop\n"
            + "".join(f"vertex {x} {y} {z}\n" for x, y, z in v[f])
            + "endloop\nendfacet\n"
            for f in faces
        )
        + "endsolid t\n"
    )
    assert mudrft.feet.MeshFoot.from_file(stl).resultant(0.01, (1e3, 1e3, 1e4), 0.0).shape == (3,)


def test_protocols_and_terrains():
    tr = mudrft.plate_intrusion(depth=0.03, speed=0.02, hold=1.0, angle=0.0, direction="vertical")
    assert tr.depth.max() == pytest.approx(0.03)
    foot = mudrft.feet.Flat()
    for terrain in (
        mudrft.terrains.GranularRFT(),
        mudrft.terrains.LinearStiffness(),
        mudrft.terrains.MaxwellMud(),
        mudrft.terrains.RigidGround(),
    ):
        res = mudrft.simulate(
            foot, terrain, mudrft.plate_intrusion(depth=0.01, speed=0.02, hold=0.2)
        )
        assert np.all(np.isfinite(res.force)) and res.force[:, 2].max() > 0


def test_calibrate_contract():
    data = mudrft.calibration.example_dataset("vertical")
    fit = mudrft.calibrate(data, direction="vertical")
    assert isinstance(fit.parameters, mudrft.MudParameters)
