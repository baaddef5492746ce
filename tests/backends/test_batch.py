"""BatchedMud: N feet with their own muds, states and motions equal N separate MudTerrains."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from _backend_support import terrain_forces, wandering_path

import mudrft
from mudrft._validation import MudrftError
from mudrft.backends.batch import BatchedMud, batched_channel_parameters
from mudrft.parameters.base import Mud, MudParameters

# Same arithmetic as the reference up to operation order and vectorized libm calls (a few
# ulp per operation); forces are compared relative to the largest force of each foot, with
# 1e-11 of it (~10^5 ulp) as the bound: rounding stays far below, a wrong term far above.
RTOL = 1e-11
N = 4
DT = 1e-3


def _backends():
    out = ["numpy"]
    for mod, name in (("numba", "numba"), ("jax", "jax")):
        try:
            __import__(mod)
            out.append(name)
        except ImportError:
            pass
    return out


def _muds():
    return [mudrft.paper_mud(w) for w in (0.25, 0.3, 0.38, 0.45)]


def _paths(n_steps=250):
    paths = [wandering_path(n_steps, DT, seed=10 + i) for i in range(N)]
    pos = np.stack([p for p, _ in paths], axis=1)  # (steps, N, 3)
    vel = np.stack([v for _, v in paths], axis=1)
    return pos, vel


def _reference(foot, muds, pos, vel):
    return np.stack(
        [
            terrain_forces(mudrft.MudTerrain(m), foot, pos[:, i], vel[:, i], DT)[0]
            for i, m in enumerate(muds)
        ],
        axis=1,
    )


@pytest.mark.parametrize("backend", _backends())
@pytest.mark.parametrize(
    "foot", [mudrft.feet.Flat(), mudrft.feet.SemiSphere()], ids=lambda f: f.name
)
def test_batched_feet_with_own_muds_match_separate_terrains(foot, backend):
    muds = _muds()
    pos, vel = _paths()
    ref = _reference(foot, muds, pos, vel)
    sim = BatchedMud(muds, foot, N, position=pos[0], backend=backend)
    got = np.stack([sim.step(pos[k], vel[k], DT).copy() for k in range(1, len(pos))])
    for i in range(N):
        scale = np.abs(ref[:, i]).max()
        assert scale > 1.0
        np.testing.assert_allclose(got[:, i], ref[:, i], rtol=0, atol=RTOL * scale)
    # depth and stress of the last step are exposed
    np.testing.assert_allclose(sim.depth, np.maximum(-pos[-1, :, 2], 0.0), atol=1e-15)
    assert sim.stress.shape == (N, 3)


def test_mud_with_array_fields_equals_list_of_muds():
    muds = _muds()
    vert = MudParameters.stack([m.vertical for m in muds])
    hor = MudParameters.stack([m.horizontal for m in muds])
    arr_mud = Mud(vert, hor)
    a = batched_channel_parameters(arr_mud, N)
    b = batched_channel_parameters(muds, N)
    assert a.alpha.shape == (N, 3)
    for k in ("alpha", "lam", "k_a", "sigma_y"):
        np.testing.assert_array_equal(getattr(a, k), getattr(b, k))
    pos, vel = _paths(60)
    s1 = BatchedMud(arr_mud, mudrft.feet.Flat(), N, position=pos[0])
    s2 = BatchedMud(muds, mudrft.feet.Flat(), N, position=pos[0])
    for k in range(1, len(pos)):
        np.testing.assert_array_equal(s1.step(pos[k], vel[k], DT), s2.step(pos[k], vel[k], DT))


def test_shared_mud_broadcasts_and_equals_per_foot_copies():
    mud = mudrft.paper_mud(0.3)
    pos, vel = _paths(80)
    shared = BatchedMud(mud, mudrft.feet.SemiCylinder(), N, position=pos[0])
    copies = BatchedMud([mud] * N, mudrft.feet.SemiCylinder(), N, position=pos[0])
    assert shared.params.alpha.shape == (3,)
    for k in range(1, len(pos)):
        np.testing.assert_array_equal(
            shared.step(pos[k], vel[k], DT), copies.step(pos[k], vel[k], DT)
        )


def test_mesh_foot_and_generic_foot_paths():
    """A mesh foot (vectorized surface rule) and a foot subclass (generic contact_force path)."""

    class MyFlat(mudrft.feet.Flat):
        """A subclass: not recognised by the fast rules, so the foot's own contact_force runs."""

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        mesh = mudrft.feet.SemiSphere().to_mesh(resolution=6)
    muds = _muds()
    pos, vel = _paths(120)
    for foot in (mesh, MyFlat()):
        ref = _reference(foot, muds, pos, vel)
        sim = BatchedMud(muds, foot, N, position=pos[0])
        got = np.stack([sim.step(pos[k], vel[k], DT).copy() for k in range(1, len(pos))])
        np.testing.assert_allclose(got, ref, rtol=0, atol=RTOL * np.abs(ref).max())


def test_batched_mud_rejects_bad_input():
    mud = mudrft.paper_mud(0.25)
    foot = mudrft.feet.Flat()
    with pytest.raises(MudrftError, match="n must be"):
        BatchedMud(mud, foot, 0)
    with pytest.raises(MudrftError, match="list of n = 3"):
        BatchedMud([mud, mud], foot, 3)
    with pytest.raises(MudrftError, match="backend"):
        BatchedMud(mud, foot, 2, backend="cuda")
    with pytest.raises(MudrftError, match="shape"):
        p = mud.vertical.replace(alpha=np.array([1e4, 2e4, 3e4]))
        BatchedMud(Mud(p, mud.horizontal), foot, 2)
    sim = BatchedMud(mud, foot, 2)
    with pytest.raises(MudrftError, match=r"position must have shape \(2, 3\)"):
        sim.step(np.zeros((3, 3)), np.zeros((2, 3)), DT)
    with pytest.raises(MudrftError, match="finite"):
        sim.step(np.full((2, 3), np.nan), np.zeros((2, 3)), DT)
    with pytest.raises(MudrftError, match="dt"):
        sim.step(np.zeros((2, 3)), np.zeros((2, 3)), -1.0)


def test_numba_multithreaded_loop_equals_numpy_backend():
    """Batches from PARALLEL_MIN feet on run the threaded numba loop; compare with numpy."""
    pytest.importorskip("numba")
    from mudrft.backends.numba import PARALLEL_MIN

    n = PARALLEL_MIN
    rng = np.random.default_rng(4)
    muds = [mudrft.paper_mud(w) for w in rng.uniform(0.25, 0.45, n)]
    foot = mudrft.feet.SemiCylinder()
    pos0 = np.column_stack([rng.uniform(-0.01, 0.01, (n, 2)), rng.uniform(-0.002, 0.002, n)])
    vel = rng.normal(scale=0.05, size=(n, 3))
    a = BatchedMud(muds, foot, n, position=pos0, backend="numba")
    b = BatchedMud(muds, foot, n, position=pos0)
    pos = pos0.copy()
    for _ in range(20):
        pos = pos + vel * DT
        fa, fb = a.step(pos, vel, DT), b.step(pos, vel, DT)
        np.testing.assert_allclose(fa, fb, rtol=0, atol=RTOL * max(np.abs(fb).max(), 1.0))
    assert np.abs(fb).max() > 1.0


@pytest.mark.parametrize(
    "foot",
    [mudrft.feet.Flat(), mudrft.feet.SemiSphere(), mudrft.feet.MorphingFoot()],
    ids=lambda f: f.name,
)
@pytest.mark.parametrize("as_list", [False, True], ids=["mud", "list"])
def test_one_foot_on_numpy_takes_the_float_path_and_equals_the_array_path(foot, as_list):
    """A batch of one foot (numpy) steps MudTerrain's float path (docs/performance.md); it
    gives the array path's forces, stresses and depths: foot 0 of a batch of two on the same
    motion, to the batch tolerance."""
    mud = mudrft.paper_mud(0.25)
    pos, vel = wandering_path(250, DT, seed=3)
    one = BatchedMud([mud] if as_list else mud, foot, 1, position=pos[0])
    assert one._one is not None  # the float path was taken
    two = BatchedMud(mud, foot, 2, position=np.stack([pos[0], pos[0]]))
    assert two._one is None
    got, want = [], []
    for k in range(1, len(pos)):
        f1 = one.step(pos[k], vel[k], DT)
        f2 = two.step(np.stack([pos[k], pos[k]]), np.stack([vel[k], vel[k]]), DT)
        assert f1.shape == (1, 3) and one.stress.shape == (1, 3) and one.depth.shape == (1,)
        np.testing.assert_allclose(one.stress[0], two.stress[0], rtol=1e-11, atol=1e-6)
        np.testing.assert_allclose(one.depth[0], two.depth[0], rtol=0, atol=1e-15)
        got.append(f1[0].copy())
        want.append(f2[0].copy())
    got, want = np.array(got), np.array(want)
    scale = np.abs(want).max()
    assert scale > 1.0
    np.testing.assert_allclose(got, want, rtol=0, atol=RTOL * scale)
