"""Synthetic intrusion logs made by mudrft's own model plus noise, not measured: every
dataset made here says so in its notes (the shipped CSVs in a ``# synthetic:`` line)."""

from __future__ import annotations

import os
from collections.abc import Sequence
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from .._validation import (
    MudrftError,
    check_choice,
    check_nonnegative,
    check_number,
    check_positive,
    check_samples,
    nonnegative_number,
    positive_number,
)
from ..io import IntrusionDataset, Trial, load_intrusion_csv, save_intrusion_csv
from ..io._build import DIRECTIONS
from ..parameters.base import MudParameters
from ..parameters.registry import paper_parameters
from ..plate import DEFAULT_PLATE_LENGTH, plate_response
from ..trajectories import Trajectory, plate_intrusion

#: Shipped example files: (direction, water content) -> file name in ``mudrft/data``.
EXAMPLE_FILES: dict[tuple[str, float], str] = {
    ("vertical", 0.25): "synthetic_plate_vertical_w25.csv",
    ("vertical", 0.35): "synthetic_plate_vertical_w35.csv",
    ("horizontal", 0.25): "synthetic_plate_horizontal_w25.csv",
}

#: Settings with which the example files were generated (see examples/make_calibration_figures.py).
EXAMPLE_SETTINGS: dict[str, Any] = dict(
    speeds=(0.01, 0.02, 0.04), depth=0.03, hold=1.0, dt=0.025, noise=0.01, seed=2026
)


def synthetic_dataset(
    params: MudParameters,
    speeds: Sequence[float] = (0.01, 0.02, 0.04),
    noise: float = 0.01,
    seed: int | None = 0,
    *,
    depth: float = 0.03,
    hold: float = 1.5,
    dt: float = 0.01,
    rest: float = 0.0,
    characteristic_length: float = DEFAULT_PLATE_LENGTH,
    direction: str | None = None,
    acceleration: bool | None = None,
    thixotropy: str = "ode",
    clock: str = "contact",
    approach: float = 0.0,
    tare: float = 0.0,
    stress_noise: float = 0.0,
    depth_noise: float = 0.0,
    offset: float = 0.0,
) -> IntrusionDataset:
    """Plate tests simulated with known parameters plus noise (synthetic data).

    One trial per speed: intrude to ``depth``, hold, retract at the same speed
    (:func:`mudrft.plate_intrusion`); with ``approach`` or ``tare`` > 0 (vertical tests) the
    plate starts and ends above the surface, as a lab logger records it.

    Parameters
    ----------
    params : MudParameters
        The true parameters (SI).
    speeds : sequence of float
        Intrusion speeds [m/s], one trial each.
    noise : float
        Relative noise level [-] (0.01 = 1 % of the stress range).
    seed : int or None
        Seed of the noise generator.
    depth, hold, dt, rest : float, keyword-only
        Intrusion displacement [m], hold time at the deepest point [s], sample spacing [s]
        (the model is stepped exactly between samples), time logged after the retraction [s].
    characteristic_length : float, keyword-only
        Plate characteristic length [m] (decision D1).
    direction : {"vertical", "horizontal"}, optional, keyword-only
        Test direction; default ``params.direction`` or vertical.
    acceleration : bool or None, keyword-only
        Keep the acceleration term (decision D6); None keeps it in the ODE.
    thixotropy, clock : str, keyword-only
        Evaluation of the model (decision D15), as :class:`mudrft.MudTerrain`.
    approach, tare : float, keyword-only
        Height above the surface the plate starts from and retracts to [m], and time at rest
        there before the approach [s].
    stress_noise, depth_noise : float, keyword-only
        Standard deviations of the force sensor's noise, as a stress [Pa], and of the depth
        sensor's [m].
    offset : float, keyword-only
        The force sensor's reading at zero force, as a stress [Pa] (an untared sensor).

    Returns
    -------
    IntrusionDataset
        With ``synthetic`` notes and the true parameters in ``meta["true_parameters"]``.

    Examples
    --------
    >>> import mudrft
    >>> ds = synthetic_dataset(mudrft.paper_parameters(0.25), speeds=(0.02,), dt=0.05)
    >>> ds.synthetic, len(ds), round(ds[0].speed, 3)
    (True, 1, 0.02)
    """
    if not isinstance(params, MudParameters) or params.shape != ():
        raise MudrftError(f"params must be a single MudParameters, got {params!r}")
    sp = check_positive("speeds", speeds, unit="m/s")
    if sp.ndim != 1 or sp.size == 0:
        raise MudrftError(f"speeds must be a non-empty list of speeds [m/s], got {speeds!r}")
    check_nonnegative("noise", noise)
    sd_stress = nonnegative_number("stress_noise", stress_noise, unit="Pa")
    sd_depth = nonnegative_number("depth_noise", depth_noise, unit="m")
    offset = check_number("offset", offset, unit="Pa")
    default = params.direction or "vertical"
    d = check_choice("direction", default if direction is None else direction, DIRECTIONS)
    lab = nonnegative_number("approach", approach, unit="m") > 0 or (
        nonnegative_number("tare", tare, unit="s") > 0
    )
    if lab and d != "vertical":
        raise MudrftError(
            "approach and tare apply to vertical tests (a plate that starts above the mud); "
            f"this one is {d}"
        )
    if seed is not None and (isinstance(seed, bool) or not isinstance(seed, int | np.integer)):
        raise MudrftError(f"seed must be an integer or None, got {seed!r}")
    rng = np.random.default_rng(seed)
    trials = []
    for v in sp:
        if lab:
            tr, logged = _lab_path(float(v), depth, hold, dt, rest, float(approach), float(tare))
        else:
            tr = plate_intrusion(
                depth=depth, speed=float(v), hold=hold, direction=d, dt=dt, rest=rest
            )
            logged = np.arange(tr.time.size)
        res = plate_response(
            tr,
            params,
            characteristic_length=characteristic_length,
            acceleration=acceleration,
            thixotropy=thixotropy,
            clock=clock,
        )
        true = res.stress[logged]
        span = float(np.ptp(true))
        sd = float(np.hypot(float(noise) * span, sd_stress))
        # drawn only when asked for: the shipped examples keep their noise
        depth_error = rng.normal(0.0, sd_depth, logged.size) if sd_depth > 0 else 0.0
        trials.append(
            Trial(
                tr.time[logged],
                res.displacement[logged] + depth_error,
                true + offset + rng.normal(0.0, sd, logged.size),
                name=f"v{1e3 * v:g}mm_s",
                characteristic_length=characteristic_length,
                meta={"speed": float(v), "noise": sd},
            )
        )
    w = params.water_content
    label = params.source or "given parameters"
    notes: tuple[str, ...] = (
        f"synthetic: generated by mudrft's own model ({label}) with Gaussian noise of "
        f"{100 * float(noise):g} % of each trial's stress range; NOT measured data",
        f"generator: mudrft.calibration.synthetic_dataset(seed={seed}, depth={depth} m, "
        f"hold={hold} s, dt={dt} s, speeds={[float(x) for x in sp]} m/s)",
    )
    if lab or sd_stress or sd_depth or offset:
        notes += (
            f"generator (lab log): approach={approach} m, tare={tare} s, stress_noise="
            f"{sd_stress} Pa, depth_noise={sd_depth} m, offset={offset} Pa",
        )
    meta = {"synthetic": "yes", "true_parameters": params.as_dict(), "water_content": w}
    return IntrusionDataset(tuple(trials), direction=d, source="synthetic", notes=notes, meta=meta)


def _lab_path(
    speed: float, depth: float, hold: float, dt: float, rest: float, approach: float, tare: float
) -> tuple[Trajectory, NDArray[np.intp]]:
    """A vertical plate test as a logger samples it (every ``dt`` [s], plus the path's
    corners) and the indices of the logged samples in it (arguments in SI)."""
    depth, dt = positive_number("depth", depth, unit="m"), positive_number("dt", dt, unit="s")
    hold, rest = (nonnegative_number(k, v, unit="s") for k, v in (("hold", hold), ("rest", rest)))
    t_in = depth / speed
    t_air = approach / speed
    corners = np.cumsum([0.0, tare, t_air, t_in, hold, t_in, t_air, rest])
    heights = np.array([approach, approach, 0.0, -depth, -depth, 0.0, approach, approach])
    check_samples(
        f"synthetic_dataset: a {corners[-1]:.3g} s test at dt = {dt:g} s",
        corners[-1] / dt + 1,
        hint="use a larger dt",
    )
    n = int(np.floor(corners[-1] / dt + 1e-9)) + 1
    grid = dt * np.arange(n)
    t = np.union1d(grid, corners[corners <= grid[-1]])
    z = np.interp(t, corners, heights)
    logged = np.searchsorted(t, grid)
    traj = Trajectory.from_positions(
        t,
        np.column_stack([np.zeros_like(t), np.zeros_like(t), z]),
        name="plate vertical intrusion (logged)",
        meta={"direction": "vertical", "displacement": -z},
    )
    return traj, logged


def example_dataset(
    direction: str = "vertical", *, water_content: float = 0.25
) -> IntrusionDataset:
    """A small synthetic example log shipped with mudrft (three speeds, 1 % noise), made
    by :func:`synthetic_dataset` from the paper's parameters with :data:`EXAMPLE_SETTINGS`,
    for a test ``direction`` ("vertical" or "horizontal") and ``water_content`` 0.25 (both
    directions) or 0.35 (vertical only) [-].

    Examples
    --------
    >>> ds = example_dataset("vertical")
    >>> ds.synthetic, len(ds)
    (True, 3)
    """
    check_choice("direction", direction, DIRECTIONS)
    key = (direction, float(water_content))
    if key not in EXAMPLE_FILES:
        raise MudrftError(
            f"no example file for direction={direction!r}, water_content="
            f"{water_content!r}; available: {sorted(EXAMPLE_FILES)}"
        )
    ref = resources.files("mudrft") / "data" / EXAMPLE_FILES[key]
    with resources.as_file(ref) as path:
        return load_intrusion_csv(path)


def write_example_files(directory: str | os.PathLike, *, overwrite: bool = False) -> list[Path]:
    """(Re)generate the shipped example CSVs (:data:`EXAMPLE_FILES`) in ``directory``;
    return the files written."""
    out = []
    for (direction, w), name in EXAMPLE_FILES.items():
        ds = synthetic_dataset(
            paper_parameters(w, direction), direction=direction, **EXAMPLE_SETTINGS
        )
        out.append(save_intrusion_csv(ds, Path(os.fspath(directory)) / name, overwrite=overwrite))
    return out
