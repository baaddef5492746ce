r"""Batched evaluation: one call advances N independent feet in mud.

:class:`BatchedMud` holds N feet of one shape, each with its own mud parameters, state,
pose and velocity, and advances them together::

    sim = BatchedMud(mud, mudrft.feet.Flat(), n=10_000)
    forces = sim.step(position, velocity, dt)        # (N, 3) in, (N, 3) [N] out

It computes what :class:`mudrft.MudTerrain` computes for a batch (same channels, entry
points, reset on exit, heading; the tests compare them), arranged for speed (decision D71):
the parameters are validated and turned into per-channel constants once, the state lives
in preallocated arrays, the inputs are checked once per call, the foot's vectorized force
rule is called without re-validation, and no Python loop runs over feet or facets.

Backends:

``"numpy"`` (default)
    Fused numpy (:func:`mudrft.backends.kernels.fused_step`); any foot.
``"numba"``
    The scalar kernels compiled by numba, with a loop over feet in compiled code
    (multi-threaded from :data:`~mudrft.backends.numba_kernels.PARALLEL_MIN` feet on);
    closed-form feet (flat, semi-cylinder, semi-sphere).
``"jax"``
    :func:`mudrft.backends.jax.terrain_step` compiled with :func:`jax.jit`; closed-form and
    mesh feet; the state stays on the JAX device (GPU if JAX has one).

Per-foot parameters: give a :class:`~mudrft.parameters.base.Mud` whose parameter fields are
arrays of shape (N,), or a list of N muds (stacked with
:meth:`~mudrft.parameters.base.MudParameters.stack`).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from .._validation import MudrftError, check_choice, check_finite, check_positive
from ..constitutive.state import ChannelState
from ..parameters.base import Mud, MudParameters
from ..terrain import channel_parameters
from . import kernels
from ._options import terrain_options

__all__ = ["BACKENDS", "BatchedMud", "batched_channel_parameters"]

#: Backends of :class:`BatchedMud`.
BACKENDS = ("numpy", "numba", "jax")


def batched_channel_parameters(mud: Mud | Sequence[Mud], n: int) -> MudParameters:
    """Channel parameters (x, y, z) for N feet: fields of shape (3,) if shared, else (N, 3).

    Parameters
    ----------
    mud : Mud or sequence of Mud
        One mud for all feet (its fields scalars or arrays of shape (N,)), or N muds.
    n : int
        Number of feet.

    Returns
    -------
    MudParameters
        Validated, with a trailing channel axis of 3.

    Examples
    --------
    >>> import mudrft
    >>> muds = [mudrft.paper_mud(w) for w in (0.25, 0.3, 0.35)]
    >>> batched_channel_parameters(muds, 3).alpha.shape
    (3, 3)
    """
    if isinstance(mud, Mud):
        p = channel_parameters(mud)
    elif (
        isinstance(mud, Sequence)
        and not isinstance(mud, str)
        and all(isinstance(m, Mud) for m in mud)
    ):
        if len(mud) != n:
            raise MudrftError(
                f"mud must be one Mud or a list of n = {n} muds, got a list of {len(mud)}"
            )
        vert = MudParameters.stack([m.vertical for m in mud])
        hor = MudParameters.stack([m.horizontal for m in mud])
        p = channel_parameters(Mud(vert, hor, name=f"{n} muds"))
    else:
        raise MudrftError(
            f"mud must be a Mud (mudrft.paper_mud) or a list of Mud, got {type(mud).__name__}"
        )
    shape = p.shape
    if shape not in ((3,), (n, 3)):
        raise MudrftError(
            f"mud parameters must be scalars or arrays of shape ({n},) for n = {n} feet, got "
            f"channel parameters of shape {shape}"
        )
    return p


class BatchedMud:
    """N feet of one shape in mud, advanced together (see module docstring).

    Parameters
    ----------
    mud : Mud, sequence of Mud, or MudTerrain
        The mud of every foot: one shared Mud, a Mud with array fields of shape (N,), a list
        of N muds, or a :class:`mudrft.MudTerrain` (its mud and options are used).
    foot : Foot
        The foot shape shared by the batch.
    n : int
        Number of feet N.
    position : array_like, shape (N, 3) or (3,), keyword-only
        Initial tip positions [m]; default (0, 0, 0) (on the surface).
    characteristic_length : float or None, keyword-only
        :math:`L_c` [m]; default the foot's.
    acceleration, reset_on_exit, xi0, heading_speed : keyword-only
        As :class:`mudrft.MudTerrain` (ignored when ``mud`` is a MudTerrain).
    backend : {"numpy", "numba", "jax"}, keyword-only
        Kernel (see module docstring). Default "numpy".

    Attributes
    ----------
    n : int
        Number of feet.
    params : MudParameters
        Channel parameters, fields of shape (3,) or (N, 3).
    force, stress : ndarray (N, 3)
        Force [N] and channel stresses [Pa] of the last step.
    depth : ndarray (N,)
        Tip depths [m] after the last step.

    Examples
    --------
    >>> import numpy as np, mudrft
    >>> sim = BatchedMud(mudrft.paper_mud(0.25), mudrft.feet.Flat(), 4)
    >>> pos = np.zeros((4, 3)); vel = np.zeros((4, 3)); vel[:, 2] = -0.02
    >>> for k in range(1, 6):
    ...     pos[:, 2] = -0.02 * k * 1e-3
    ...     f = sim.step(pos, vel, 1e-3)
    >>> f.shape, bool(np.all(f[:, 2] > 0))
    ((4, 3), True)
    """

    def __init__(
        self,
        mud: Any,
        foot: Any,
        n: int,
        *,
        position: Any = None,
        characteristic_length: float | None = None,
        acceleration: bool = True,
        reset_on_exit: bool = True,
        xi0: float = 0.0,
        heading_speed: float = 1e-6,
        backend: str = "numpy",
    ) -> None:
        from ..feet.base import Foot

        if isinstance(n, bool) or not isinstance(n, int | np.integer) or n < 1:
            raise MudrftError(f"n must be an integer >= 1 (number of feet), got {n!r}")
        if not isinstance(foot, Foot):
            raise MudrftError(
                f"foot must be a mudrft foot (mudrft.feet.Flat(), ...), got {type(foot).__name__}"
            )
        self.backend = check_choice("backend", backend, BACKENDS)
        mud, opts = terrain_options(
            mud, foot, characteristic_length=characteristic_length, acceleration=acceleration,
            reset_on_exit=reset_on_exit, xi0=xi0, heading_speed=heading_speed,
        )
        self.n = int(n)
        self.foot = foot
        self.params = batched_channel_parameters(mud, self.n)
        self.characteristic_length = opts.characteristic_length
        self.acceleration = opts.acceleration
        self.reset_on_exit = opts.reset_on_exit
        self.xi0 = opts.xi0
        self.heading_speed = opts.heading_speed
        self._consts = kernels.channel_constants(self.params)
        self._kappa = 1.0 if self.acceleration else 0.0
        self._setup_backend()
        self.reset(np.zeros(3) if position is None else position)

    # -- set-up ---------------------------------------------------------------------------
    def _setup_backend(self) -> None:
        from .forces import force_function

        if self.backend == "numpy":
            self._force_fn = force_function(self.foot)
        elif self.backend == "numba":
            from .fast import foot_geometry
            from .numba_kernels import PARALLEL_MIN, compiled

            kind, geom = foot_geometry(self.foot)
            self._geom = np.asarray(geom, dtype=float)
            self._cfg = np.array(
                [
                    kind,
                    self.characteristic_length,
                    self._kappa,
                    self.xi0,
                    1.0 if self.reset_on_exit else 0.0,
                    self.heading_speed,
                ]
            )
            self._c = np.ascontiguousarray(kernels.constant_rows(self._consts).ravel())
            name = "batch_step" if self.n >= PARALLEL_MIN else "batch_step_serial"
            self._nb_step = compiled()[name]
        else:
            from . import jax as mjax

            fn = force_function(self.foot, xp=mjax.safe_namespace())
            if fn is None:
                raise MudrftError(
                    f"backend 'jax' supports the flat, semi-cylinder, semi-sphere and mesh feet, "
                    f"got {type(self.foot).__name__}; use backend='numpy'"
                )
            self._jax_setup(mjax, fn)

    def _jax_setup(self, mjax: Any, fn: Any) -> None:
        jax = mjax.enable_x64()
        jp = mjax.to_jax(self.params)
        opts = {
            "force_fn": fn,
            "characteristic_length": self.characteristic_length,
            "acceleration": self.acceleration,
            "reset_on_exit": self.reset_on_exit,
            "xi0": self.xi0,
            "heading_speed": self.heading_speed,
        }

        def one(st: Any, pos: Any, vel: Any, dt: Any) -> Any:
            return mjax.terrain_step(jp, st, pos, vel, dt, **opts)

        self._jax_step = jax.jit(one)
        self._mjax = mjax

    # -- state ----------------------------------------------------------------------------
    def _inputs(self, name: str, value: Any) -> np.ndarray:
        a = check_finite(name, value)
        if a.shape == (3,):
            a = np.broadcast_to(a, (self.n, 3))
        if a.shape != (self.n, 3):
            raise MudrftError(f"{name} must have shape ({self.n}, 3) or (3,), got shape {a.shape}")
        return a

    def reset(self, position: Any) -> None:
        """Put every foot above undisturbed mud with its tip at ``position`` (N, 3) or (3,) [m]."""
        pos = self._inputs("position", position)
        n, lc = self.n, self.characteristic_length
        depth = np.maximum(-pos[:, 2], 0.0)
        self.force = np.zeros((n, 3))
        self.stress = np.zeros((n, 3))
        self.depth = depth.copy()
        if self.backend == "numba":
            st = np.zeros((n, kernels.N_STATE))
            st[:, 2:15:5] = self.xi0
            st[:, 10] = depth / lc
            st[:, 11] = depth / lc
            st[:, 15:17] = pos[:, :2]
            st[:, 18] = depth > 0
            self._st = st.ravel()
            self._out = np.zeros(n * kernels.N_OUT)
            return
        g = np.zeros((n, 3))
        g[:, 2] = depth / lc
        z = np.zeros((n, 3))
        ch = ChannelState(
            gamma=g, gamma_w=g.copy(), xi=z + self.xi0, s_th=z.copy(), sigma_s=z.copy()
        )
        if self.backend == "jax":
            self._jst = self._mjax.initial_terrain_state(pos, lc, xi0=self.xi0)
            return
        self._ch = ch
        self._entry = pos[:, :2].copy()
        self._heading = np.zeros(n)
        self._in_mud = depth > 0
        self._foot_state = self.foot.initial_foot_state()

    # -- stepping -------------------------------------------------------------------------
    def step(self, position: Any, velocity: Any, dt: float) -> np.ndarray:
        """Advance every foot by ``dt`` and return the forces of the mud on them.

        Parameters
        ----------
        position : array_like, shape (N, 3)
            Tip positions at the end of the step [m] (world frame, z up, surface z = 0).
        velocity : array_like, shape (N, 3)
            Tip velocities [m/s].
        dt : float
            Step [s], > 0.

        Returns
        -------
        ndarray, shape (N, 3)
            Forces [N] (world frame; also in :attr:`force`).
        """
        pos = self._inputs("position", position)
        vel = self._inputs("velocity", velocity)
        dt = float(check_positive("dt", dt, unit="s"))
        if self.backend == "numba":
            self._nb_step(
                self._c,
                self._st,
                self._out,
                self._geom,
                self._cfg,
                np.ascontiguousarray(pos),
                np.ascontiguousarray(vel),
                dt,
            )
            out = self._out.reshape(self.n, kernels.N_OUT)
            self.force = out[:, 0:3].copy()
            self.stress = out[:, 3:6].copy()
            self.depth = out[:, 6].copy()
        elif self.backend == "jax":
            self._jst, (f, s, d) = self._jax_step(self._jst, pos, vel, dt)
            self.force, self.stress, self.depth = np.asarray(f), np.asarray(s), np.asarray(d)
        else:
            self._step_numpy(pos, vel, dt)
        if not np.all(np.isfinite(self.force)):
            raise MudrftError(
                "the batched step produced non-finite forces; check the parameters and dt"
            )
        return self.force

    def _step_numpy(self, pos: np.ndarray, vel: np.ndarray, dt: float) -> None:
        lc = self.characteristic_length
        depth = np.maximum(-pos[:, 2], 0.0)
        in_mud = depth > 0
        ch = self._ch
        entry = self._entry
        if self.reset_on_exit:
            fresh = ~self._in_mud
            if fresh.any():
                f3 = fresh[:, None]
                ch = ChannelState(
                    gamma=np.where(f3, 0.0, ch.gamma),
                    gamma_w=np.where(f3, 0.0, ch.gamma_w),
                    xi=np.where(f3, self.xi0, ch.xi),
                    s_th=np.where(f3, 0.0, ch.s_th),
                    sigma_s=np.where(f3, 0.0, ch.sigma_s),
                )
                entry = np.where(f3, pos[:, :2] - vel[:, :2] * dt, entry)
        gamma = np.empty((self.n, 3))
        np.subtract(pos[:, :2], entry, out=gamma[:, :2])
        gamma[:, :2] /= lc
        np.divide(depth, lc, out=gamma[:, 2])
        gdot = np.empty((self.n, 3))
        np.divide(vel[:, :2], lc, out=gdot[:, :2])
        np.divide(np.where(in_mud | self._in_mud, -vel[:, 2], 0.0), lc, out=gdot[:, 2])
        hs = np.hypot(vel[:, 0], vel[:, 1])
        heading = np.where(hs > self.heading_speed, np.arctan2(vel[:, 1], vel[:, 0]), self._heading)
        seal3: Any
        if self._force_fn is None:
            seal = np.asarray(self.foot.seal_factor(self._foot_state), dtype=float)
            seal3 = np.ones((self.n, 3))
            seal3[:, 2] = seal
        else:
            seal3 = 1.0
        ch, total = kernels.fused_step(self._consts, ch, gamma, gdot, dt, seal3, self._kappa)
        stress = np.where(in_mud[:, None], total, 0.0)
        if self._force_fn is None:
            self._foot_state, force = self.foot.contact_force(
                self._foot_state, depth, stress, heading, dt
            )
        else:
            force = self._force_fn(depth, stress, heading)
        self.force = np.where(in_mud[:, None], force, 0.0)
        self.stress = stress
        self.depth = depth
        self._ch, self._entry, self._heading, self._in_mud = ch, entry, heading, in_mud

    def __repr__(self) -> str:
        return f"BatchedMud(n={self.n}, foot={self.foot!r}, backend={self.backend!r})"
