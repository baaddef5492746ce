r"""A fast single-foot path for per-step coupling (MuJoCo, a controller loop).

:class:`FastMudFoot` is :class:`mudrft.MudTerrain` with one closed-form foot, advanced one
step at a time: the one terrain step (:func:`mudrft.terrains.mud.mud_step`) and the foot's
closed form (:func:`mudrft.feet.closed_form.closed_form_force`), compiled on floats by the
numba backend when numba is installed (about 2 microseconds a step), else run on Python
floats as :func:`mudrft._specialize.on_floats` rewrites them (about 6 microseconds). The
tests check that it gives the same forces as ``MudTerrain`` + the foot (decision D73).

Supported feet: :class:`~mudrft.feet.Flat`, :class:`~mudrft.feet.SemiCylinder`,
:class:`~mudrft.feet.SemiSphere` (rigid, axis-aligned). Other feet raise
:class:`~mudrft.MudrftError`; use :class:`mudrft.MudTerrain` for them.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from typing import Any, cast

import numpy as np
from numpy.typing import ArrayLike, NDArray

from .._specialize import on_floats
from .._validation import MudrftError, check_choice, check_finite
from ..feet.base import Foot
from ..feet.closed_form import closed_form_force
from ..feet.shapes import Flat, SemiCylinder, SemiSphere
from ..parameters.base import Mud
from ..terrains import MudTerrain
from ..terrains.mud import MudState, mud_step
from ._snapshot import Restorable, Snapshot, check_snapshot, frozen, map_leaves
from .batch import as_mud_terrain

__all__ = ["FastMudFoot", "foot_geometry"]


def foot_geometry(foot: Foot) -> tuple[int, tuple[float, float, float]]:
    """``(kind, (g0, g1, g2))`` of a closed-form foot for the compiled paths [m].

    Raises
    ------
    MudrftError
        For a foot without a closed form (mesh feet, the morphing foot).
    """

    if type(foot) not in (Flat, SemiCylinder, SemiSphere):
        raise MudrftError(
            "foot must be a closed-form foot (mudrft.feet.Flat, SemiCylinder or SemiSphere), "
            f"got {type(foot).__name__}; use mudrft.MudTerrain for other feet"
        )
    kind, g0, g1, g2 = cast("Flat | SemiCylinder | SemiSphere", foot).kernel_geometry
    return kind, (g0, g1, g2)


class FastMudFoot(Restorable):
    """One closed-form foot in mud, stepped on floats (see module docstring).

    Parameters
    ----------
    foot : Flat, SemiCylinder or SemiSphere
        The foot.
    mud : Mud or MudTerrain
        The mud (a MudTerrain brings its own options; the keywords below are then an error).
    position : array_like, shape (3,), keyword-only
        Initial tip position [m].
    characteristic_length : float or None, keyword-only
        :math:`L_c` [m]; default the foot's.
    acceleration, reset_on_exit, xi0, heading_speed, thixotropy, clock : keyword-only
        As :class:`mudrft.MudTerrain`.
    backend : {"auto", "numba", "python"}, keyword-only
        ``"auto"`` uses numba when it can be imported.

    Attributes
    ----------
    backend : str
        The path in use: ``"numba"`` or ``"python"``.
    stress : ndarray (3,)
        Channel stresses of the last step [Pa].
    depth : float
        Tip depth after the last step [m].

    Examples
    --------
    >>> import mudrft
    >>> ff = FastMudFoot(mudrft.feet.Flat(), mudrft.paper_mud(0.25), backend="python")
    >>> f = ff.step((0.0, 0.0, -0.001), (0.0, 0.0, -0.02), 1e-3)
    >>> bool(f[2] > 0)
    True
    """

    def __init__(
        self,
        foot: Flat | SemiCylinder | SemiSphere,
        mud: Mud | MudTerrain,
        *,
        position: ArrayLike = (0.0, 0.0, 0.0),
        backend: str = "auto",
        **options: Any,
    ) -> None:
        check_choice("backend", backend, ("auto", "numba", "python"))
        kind, geom = foot_geometry(foot)
        terrain = as_mud_terrain(mud, **options)
        if any(np.ndim(v) for v in terrain.constants[0] + terrain.constants[1]):
            raise MudrftError(
                "mud must hold one parameter set per direction (scalar fields) for a single "
                "foot, got array fields; use BatchedMud for batches"
            )
        self.foot, self.terrain, self.mud = foot, terrain, terrain.mud
        if backend == "auto":
            from .numba import available

            backend = "numba" if available() else "python"
        self.backend = backend
        if backend == "numba":
            from .numba import N_STATE, compiled_fast_foot, config_row, constant_row

            self._fast = compiled_fast_foot()
            self._c = constant_row(*terrain.constants).reshape(1, -1)
            # work rows: state, output (force, stress, depth), options (cfg then geometry)
            self._w = np.zeros((3, N_STATE))
            self._w[2, :11] = (*config_row(terrain, foot), kind, *geom)
            self._bind(self._w)
        else:  # the specialized one terrain step and closed form, options read once
            t = terrain
            self._mud_step = on_floats(mud_step)
            self._constants = terrain.constants
            self._force = on_floats(closed_form_force)
            self._geom = (kind, *geom)
            self._options = (
                t.length(foot), t.kappa, t.xi0, t.reset_on_exit, t.heading_speed, 1.0,
                t.quasi_static, t.restart,
            )  # fmt: skip
        self.reset(position)

    def reset(self, position: ArrayLike) -> None:
        """Put the foot above undisturbed mud with its tip at ``position`` (3,) [m]."""
        pos = check_finite("position", position)
        if pos.shape != (3,):
            raise MudrftError(f"position must have shape (3,) [m], got shape {pos.shape}")
        self._channels = self.terrain.initial_state(self.foot, pos).channels
        self._stress: NDArray[np.float64] | tuple[float, ...] = np.zeros(3)
        self._depth = max(-float(pos[2]), 0.0)
        if self.backend == "numba":
            from .numba import state_rows

            self._w[0] = state_rows(self._channels)[0]
            self._w[1] = 0.0
            self._w[1, 6] = self._depth

    def _bind(self, w: NDArray[np.float64]) -> None:
        """Use the work array ``w`` (numba), and views of it made once (a slice per step
        costs 0.2 us). A copy of the array needs views of its own: views copied with it
        still showed the old array, so a deep copy returned the force of the copy time."""
        self._w, self._out, self._force_view = w, w[1:2], w[1, :3]

    # -- snapshots (decision D143) ----------------------------------------------------------
    def snapshot(self) -> Snapshot:
        """The foot's state after the last step, a copy to :meth:`restore` later (D143).

        Returns
        -------
        Snapshot
            The mud under the foot (Python floats), and the force [N], stresses [Pa] and
            depth [m] of the last step; no later step changes it.
        """
        if self.backend == "numba":
            from .numba import channels_of_rows

            ch = channels_of_rows(self._w[0])
            force, stress = self._w[1, :3], self._w[1, 3:6]
        else:
            ch = self._channels
            stress = np.array(self._stress, dtype=float)
            f = self._force(*self._geom, self._depth, *stress.tolist(), ch.heading)
            force = np.array(f, dtype=float) * ch.in_mud  # what the step returned
        state = MudState(channels=map_leaves(float, ch), foot=None)
        return Snapshot(state, frozen(force), frozen(stress), float(self.depth))

    def restore(self, snapshot: Snapshot) -> None:
        """Put the foot back into the state of ``snapshot`` (from :meth:`snapshot` of this
        foot, or of another ``FastMudFoot`` with the same foot and mud); the steps after it
        are those that followed the snapshot, bit for bit (D143)."""
        ch = map_leaves(float, check_snapshot(snapshot, (), "FastMudFoot"))
        stress, depth = np.array(snapshot.stress, dtype=float), float(snapshot.depth)
        if self.backend == "numba":
            from .numba import state_rows

            w = self._w.copy()  # a fresh array: a copy of this foot must not share it
            w[0] = state_rows(ch)[0]
            w[1] = 0.0
            w[1, :3], w[1, 3:6], w[1, 6] = snapshot.force, stress, depth
            self._bind(w)
        self._channels, self._stress, self._depth = ch, tuple(stress.tolist()), depth

    def _init_args(self) -> tuple[tuple[Any, ...], dict[str, Any]]:
        return (self.foot, self.terrain), {"backend": self.backend}

    def step(self, position: ArrayLike, velocity: ArrayLike, dt: float) -> NDArray[np.float64]:
        """Advance by ``dt`` to a tip at ``position`` moving at ``velocity``; return the force.

        Parameters
        ----------
        position : sequence of 3 float
            Tip position at the end of the step [m].
        velocity : sequence of 3 float
            Tip velocity [m/s].
        dt : float
            Step [s], > 0.

        Returns
        -------
        ndarray, shape (3,)
            Force of the mud on the foot, world frame [N].
        """
        # Python floats: numba unboxes them much faster than numpy scalars
        p_in: Any = position.tolist() if type(position) is np.ndarray else position
        v_in: Any = velocity.tolist() if type(velocity) is np.ndarray else velocity
        try:
            x, y, z = p_in
            vx, vy, vz = v_in
            step = float(dt)
        except (TypeError, ValueError):
            raise MudrftError(
                f"position and velocity must have 3 components, got shapes "
                f"{np.shape(position)} and {np.shape(velocity)}"
            ) from None
        if self.backend == "numba":
            try:
                code = self._fast(self._c, self._w, x, y, z, vx, vy, vz, step)
            except TypeError:  # no matching signature: not real numbers
                raise self._not_numbers(p_in, v_in) from None
            if code == 0:
                return self._force_view.copy()  # type: ignore[no-any-return]
            if code == 2:
                raise MudrftError(
                    "the step produced a non-finite force; check the parameters and dt"
                )
            raise MudrftError(
                f"position and velocity must be finite and dt > 0 s, got position "
                f"{[float(v) for v in (x, y, z)]}, velocity {[float(v) for v in (vx, vy, vz)]}, "
                f"dt {step!r}"
            )
        try:
            px, py, pz = float(x), float(y), float(z)
            ux, uy, uz = float(vx), float(vy), float(vz)
        except (TypeError, ValueError):
            raise self._not_numbers(p_in, v_in) from None
        # the check of the numba kernel (one sum, no tuples made)
        if not (step > 0.0 and math.isfinite(step) and math.isfinite(px + py + pz + ux + uy + uz)):
            raise MudrftError(
                f"position and velocity must be finite and dt > 0 s, got position "
                f"{[px, py, pz]}, velocity {[ux, uy, uz]}, dt {dt!r}"
            )
        # the one terrain step and the foot's closed form, on Python floats
        ch, sx, sy, sz, depth = self._mud_step(
            self._constants, self._channels, px, py, pz, ux, uy, uz, step, *self._options
        )
        fx, fy, fz = self._force(*self._geom, depth, sx, sy, sz, ch.heading)
        if not (math.isfinite(fx) and math.isfinite(fy) and math.isfinite(fz)):
            raise MudrftError("the step produced a non-finite force; check the parameters and dt")
        inside = ch.in_mud
        force = np.empty(3)  # filled item by item: half the time of np.array((...))
        force[0], force[1], force[2] = fx * inside, fy * inside, fz * inside
        self._channels, self._stress, self._depth = ch, (sx, sy, sz), depth
        return force

    @staticmethod
    def _not_numbers(position: Iterable[object], velocity: Iterable[object]) -> MudrftError:
        return MudrftError(
            f"position and velocity must be real numbers [m], [m/s], got {list(position)!r} "
            f"and {list(velocity)!r}"
        )

    @property
    def stress(self) -> NDArray[np.float64]:
        """Channel stresses (sx, sy, sz) of the last step [Pa]."""
        if self.backend == "numba":
            return self._out[0, 3:6].copy()  # type: ignore[no-any-return]
        return np.array(self._stress, dtype=float)

    @property
    def depth(self) -> float:
        """Tip depth after the last step [m]."""
        return float(self._out[0, 6]) if self.backend == "numba" else self._depth

    def __repr__(self) -> str:
        return f"FastMudFoot(foot={self.foot!r}, mud={self.mud!r}, backend={self.backend!r})"
