"""Snapshots, copies and pickles of the stateful stepper BatchedMud.

A planner saves the mud where the robot is, rolls out candidate futures and goes back. The
continuation after a restore, a copy or a pickle must be the original's, bit for bit, and a
rollout must not change the snapshot or the live stepper it was taken from.
"""

from __future__ import annotations

import copy
import importlib.util
import pickle

import numpy as np
import pytest
from _backend_support import wandering_path

import mudrft
from mudrft._validation import MudrftError
from mudrft.backends import BatchedMud

MUD = mudrft.paper_mud(0.3)
FOOT = mudrft.feet.SemiSphere()
DT = 1e-3
POS, VEL = wandering_path(300, DT, seed=7)  # enters, wanders, leaves and re-enters
K = 120  # the snapshot is taken after K - 1 steps, in the mud

COPIES = {
    "copy": copy.copy,
    "deepcopy": copy.deepcopy,
    "pickle": lambda obj: pickle.loads(pickle.dumps(obj)),
}


def _installed(*names):
    return [n for n in names if n in ("python", "numpy") or importlib.util.find_spec(n)]


def _steps(sim, k0, k1, n=None):
    """Forces of steps k0..k1-1 of the path (tiled over n feet for a batch)."""
    out = []
    for k in range(k0, k1):
        p, v = POS[k], VEL[k]
        if n is not None:
            p, v = np.tile(p, (n, 1)), np.tile(v, (n, 1))
        out.append(np.array(sim.step(p, v, DT)))
    return np.array(out)


def _one(backend):
    """One foot: the single-foot stepper (a batch of one)."""
    return BatchedMud(MUD, FOOT, 1, position=POS[0], backend=backend), None


def _batch(backend, n=3, foot=FOOT):
    return BatchedMud(MUD, foot, n, position=POS[0], backend=backend), n


STEPPERS = [
    *(pytest.param(_one, b, id=f"one-{b}") for b in _installed("numba")),
    *(pytest.param(_batch, b, id=f"batch-{b}") for b in _installed("numpy", "numba", "jax")),
    # one foot on numpy steps on Python floats (its own state format inside)
    pytest.param(lambda b: _batch(b, n=1), "numpy", id="batch-numpy-one"),
]


@pytest.mark.parametrize("how", COPIES)
@pytest.mark.parametrize(("make", "backend"), STEPPERS)
def test_a_copy_continues_as_the_original_and_does_not_share_its_state(make, backend, how):
    # before: a deep copy or pickle of a numba stepper returned the force of the copy
    # time at every step (its output view still showed the original's array), a shallow
    # copy stepped the original's state, the JAX BatchedMud could not be pickled at all
    sim, n = make(backend)
    ref, _ = make(backend)
    _steps(sim, 1, K, n)
    expected = np.concatenate([_steps(ref, 1, K, n)[-1:], _steps(ref, K, len(POS), n)])
    twin = COPIES[how](sim)
    np.testing.assert_array_equal(_steps(twin, K, len(POS), n), expected[1:])
    # the original was not moved by its copy's steps
    np.testing.assert_array_equal(_steps(sim, K, len(POS), n), expected[1:])


@pytest.mark.parametrize(("make", "backend"), STEPPERS)
def test_restore_gives_a_bit_identical_continuation_and_rollouts_leave_the_snapshot(make, backend):
    sim, n = make(backend)
    _steps(sim, 1, K, n)
    snap = sim.snapshot()
    kept = copy.deepcopy(tuple(np.array(leaf) for leaf in _leaves(snap)))
    first = _steps(sim, K, len(POS), n)
    # a rollout from a copy of the live stepper, then from the restored one, then again
    _steps(copy.copy(sim), K, K + 50, n)
    sim.restore(snap)
    np.testing.assert_array_equal(_steps(sim, K, len(POS), n), first)
    sim.restore(snap)
    np.testing.assert_array_equal(_steps(sim, K, len(POS), n), first)
    for a, b in zip(_leaves(snap), kept, strict=True):
        np.testing.assert_array_equal(a, b)
    # read-only: a user's in-place change cannot corrupt it either
    arrays = [leaf for leaf in _leaves(snap) if isinstance(leaf, np.ndarray)]
    assert arrays and not any(a.flags.writeable for a in arrays)


def test_the_last_step_is_in_the_snapshot_and_comes_back_with_restore():
    for backend in _installed("numpy", "numba", "jax"):
        sim, n = _batch(backend)
        f = _steps(sim, 1, K, n)[-1]
        snap = sim.snapshot()
        np.testing.assert_array_equal(snap.force, f)
        out = (sim.force.copy(), sim.stress.copy(), sim.depth.copy())
        _steps(sim, K, K + 30, n)
        sim.restore(snap)
        for a, b in zip((sim.force, sim.stress, sim.depth), out, strict=True):
            np.testing.assert_array_equal(a, b)
    ff, _ = _one("numba")
    f = _steps(ff, 1, K)[-1]
    np.testing.assert_array_equal(ff.snapshot().force, f)
    np.testing.assert_array_equal(ff.snapshot().depth, ff.depth)


@pytest.mark.parametrize("backend", _installed("numba", "jax"))
def test_a_snapshot_restores_on_every_backend_and_steps_on_in_mud_terrain(backend):
    sim, n = _batch("numpy")
    _steps(sim, 1, K, n)
    snap = sim.snapshot()
    reference = _steps(sim, K, K + 40, n)
    other, _ = _batch(backend)
    other.restore(snap)
    scale = np.abs(reference).max()
    np.testing.assert_allclose(_steps(other, K, K + 40, n), reference, rtol=0, atol=1e-11 * scale)
    terrain = mudrft.MudTerrain(MUD)
    _state, out = terrain.step(
        FOOT, snap.state, np.tile(POS[K], (n, 1)), np.tile(VEL[K], (n, 1)), DT
    )
    np.testing.assert_array_equal(out.force, reference[0])


def test_a_morphing_foot_batch_restores_its_mechanism_state():
    foot = mudrft.feet.MorphingFoot()
    sim, n = _batch("numpy", n=2, foot=foot)
    _steps(sim, 1, K, n)
    snap = sim.snapshot()
    assert snap.state.foot is not None
    first = _steps(sim, K, K + 60, n)
    sim.restore(snap)
    np.testing.assert_array_equal(_steps(sim, K, K + 60, n), first)


def test_restore_refuses_a_snapshot_of_another_stepper():
    batch, _ = _batch("numpy", n=2)
    with pytest.raises(
        MudrftError, match=r"shape \(3,\).*got state arrays of shape\(s\) \[\(2,\)\]"
    ):
        _batch("numpy", n=3)[0].restore(batch.snapshot())
    with pytest.raises(MudrftError, match=r"snapshot must be what BatchedMud\.snapshot"):
        batch.restore(batch)


def _leaves(tree):
    if isinstance(tree, tuple):
        return [leaf for v in tree for leaf in _leaves(v)]
    return [] if tree is None else [tree]


@pytest.mark.parametrize("backend", _installed("numpy", "numba", "jax"))
def test_one_foot_snapshot_seeds_a_batch_of_candidate_futures(backend):
    # the live foot is a batch of one; 5 candidate velocities are rolled out together from
    # its snapshot and agree with each candidate rolled out alone from the same snapshot
    live, _ = _one("numba")
    _steps(live, 1, K)
    snap = live.snapshot()
    gains = np.linspace(0.6, 1.4, 5)
    batch, _ = _batch(backend, n=5)
    batch.restore(snap)
    np.testing.assert_array_equal(batch.force, np.tile(snap.force, (5, 1)))
    together = [
        batch.step(POS[k] + 0.0 * gains[:, None], VEL[k] * gains[:, None], DT)
        for k in range(K, K + 30)
    ]
    for i, g in enumerate(gains):
        live.restore(snap)
        alone = [live.step(POS[k], VEL[k] * g, DT)[0] for k in range(K, K + 30)]
        scale = np.abs(alone).max()
        np.testing.assert_allclose(np.array(together)[:, i], alone, rtol=0, atol=1e-11 * scale)
