r"""A fast single-foot path for per-step coupling (MuJoCo, a controller loop).

:class:`FastMudFoot` is :class:`mudrft.MudTerrain` with one closed-form foot, advanced one
step at a time on Python floats: the constitutive step of the three channels
(:func:`mudrft.backends.kernels.scalar_channel_step`) and the foot's closed form
(:func:`mudrft.backends.kernels.scalar_foot_force`), compiled with numba when it is
installed, else run as plain Python with the ``math`` module. A step costs about a
microsecond with numba and about 15 microseconds without, instead of the hundreds of
microseconds that the array code spends on small-array overhead (``mudrft bench`` measures
it; docs/performance.md). The tests check that it gives the same forces as
``MudTerrain`` + the foot (decision D73).

Supported feet: :class:`~mudrft.feet.Flat`, :class:`~mudrft.feet.SemiCylinder`,
:class:`~mudrft.feet.SemiSphere` (rigid, axis-aligned). Other feet raise
:class:`~mudrft.MudrftError`; use :class:`mudrft.MudTerrain` for them.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from .._validation import MudrftError, check_choice, check_finite
from ..parameters.base import Mud
from ..terrain import MudTerrain, channel_parameters
from . import kernels
from ._options import terrain_options

__all__ = ["FastMudFoot", "foot_geometry"]


def foot_geometry(foot: Any) -> tuple[int, tuple[float, float, float]]:
    """Kind code and dimensions of a closed-form foot for the scalar kernels.

    Parameters
    ----------
    foot : Flat, SemiCylinder or SemiSphere
        The foot.

    Returns
    -------
    kind : int
        0 flat, 1 semi-cylinder, 2 semi-sphere.
    geom : tuple of 3 float
        (L, W, H), (R, W, H) or (R, H, 0) [m].

    Examples
    --------
    >>> import mudrft
    >>> foot_geometry(mudrft.feet.Flat())
    (0, (0.08, 0.065, 0.026))
    """
    from ..feet.closed_form import Flat, SemiCylinder, SemiSphere

    if type(foot) is Flat:
        return 0, (foot.length, foot.width, foot.height)
    if type(foot) is SemiCylinder:
        return 1, (foot.radius, foot.width, foot.height)
    if type(foot) is SemiSphere:
        return 2, (foot.radius, foot.height, 0.0)
    raise MudrftError(
        "foot must be a closed-form foot (mudrft.feet.Flat, SemiCylinder or SemiSphere) for the "
        f"fast path, got {type(foot).__name__}; use mudrft.MudTerrain for other feet"
    )


def _numba_available() -> bool:
    from .numba_kernels import available

    return available()


class FastMudFoot:
    """One closed-form foot in mud, stepped on floats (see module docstring).

    Parameters
    ----------
    foot : Flat, SemiCylinder or SemiSphere
        The foot.
    mud : Mud or MudTerrain
        The mud (a MudTerrain brings its options, which then override the keywords below).
    position : array_like, shape (3,), keyword-only
        Initial tip position [m].
    characteristic_length : float or None, keyword-only
        :math:`L_c` [m]; default the foot's.
    acceleration, reset_on_exit, xi0, heading_speed : keyword-only
        As :class:`mudrft.MudTerrain`.
    backend : {"auto", "numba", "python"}, keyword-only
        ``"auto"`` uses numba when it can be imported.

    Attributes
    ----------
    backend : str
        The kernel in use: ``"numba"`` or ``"python"``.
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
        foot: Any,
        mud: Mud | MudTerrain,
        *,
        position: Any = (0.0, 0.0, 0.0),
        characteristic_length: float | None = None,
        acceleration: bool = True,
        reset_on_exit: bool = True,
        xi0: float = 0.0,
        heading_speed: float = 1e-6,
        backend: str = "auto",
    ) -> None:
        check_choice("backend", backend, ("auto", "numba", "python"))
        kind, geom = foot_geometry(foot)
        mud, opts = terrain_options(
            mud, foot, characteristic_length=characteristic_length, acceleration=acceleration,
            reset_on_exit=reset_on_exit, xi0=xi0, heading_speed=heading_speed,
        )
        if not isinstance(mud, Mud):
            raise MudrftError(f"mud must be a Mud or a MudTerrain, got {type(mud).__name__}")
        params = channel_parameters(mud)
        if params.shape != (3,):
            raise MudrftError(
                f"mud must hold one parameter set per direction (scalar fields) for a single foot, "
                f"got channel parameters of shape {params.shape}; use BatchedMud for batches"
            )
        self.foot = foot
        self.mud = mud
        self.characteristic_length = opts.characteristic_length
        self.acceleration = opts.acceleration
        self.reset_on_exit = opts.reset_on_exit
        self.xi0 = opts.xi0
        self.heading_speed = opts.heading_speed
        if backend == "auto":
            backend = "numba" if _numba_available() else "python"
        self.backend = backend
        consts = kernels.constant_rows(kernels.channel_constants(params)).ravel()
        work = [0.0] * kernels.N_WORK
        work[kernels.W_GEOM : kernels.W_GEOM + 3] = geom
        work[kernels.W_CFG : kernels.W_STATE] = (
            float(kind),
            self.characteristic_length,
            1.0 if self.acceleration else 0.0,
            self.xi0,
            1.0 if self.reset_on_exit else 0.0,
            self.heading_speed,
        )
        if backend == "numba":
            from .numba_kernels import compiled

            self._kernel = compiled()["fast_foot_step"]
            self._c: Any = np.ascontiguousarray(consts, dtype=float)
            self._w: Any = np.array(work, dtype=float)
            self._fview = self._w[kernels.W_OUT : kernels.W_OUT + 3]
        else:
            self._kernel = kernels.fast_foot_step
            self._c = [float(v) for v in consts]
            self._w = work
        self.reset(position)

    def reset(self, position: Any) -> None:
        """Put the foot above undisturbed mud with its tip at ``position`` (3,) [m]."""
        pos = check_finite("position", position)
        if pos.shape != (3,):
            raise MudrftError(f"position must have shape (3,), got shape {pos.shape}")
        depth = max(-float(pos[2]), 0.0)
        g = depth / self.characteristic_length
        st = [0.0] * kernels.N_STATE
        for k in range(3):
            st[5 * k + 2] = self.xi0
        st[10] = g
        st[11] = g
        st[15], st[16] = float(pos[0]), float(pos[1])
        st[18] = 1.0 if depth > 0 else 0.0
        w = self._w
        for k in range(kernels.N_STATE):
            w[kernels.W_STATE + k] = st[k]
        for k in range(kernels.N_OUT):
            w[kernels.W_OUT + k] = 0.0
        w[kernels.W_OUT + 6] = depth

    def step(self, position: Any, velocity: Any, dt: float) -> np.ndarray:
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
        numba = self.backend == "numba"
        pos: Any
        vel: Any
        if numba and type(position) is np.ndarray and type(velocity) is np.ndarray:
            pos, vel = position, velocity
            ok = pos.shape == (3,) and vel.shape == (3,)
        else:
            pos = tuple(map(float, position))
            vel = tuple(map(float, velocity))
            ok = len(pos) == 3 and len(vel) == 3
        if not ok:
            raise MudrftError(
                f"position and velocity must have 3 components, got {np.shape(position)} and "
                f"{np.shape(velocity)}"
            )
        code = self._kernel(self._c, self._w, pos, vel, float(dt))
        if code == 1:
            raise MudrftError(
                f"position and velocity must be finite and dt > 0 s, got position {list(pos)!r}, "
                f"velocity {list(vel)!r}, dt {dt!r}"
            )
        if code == 2:
            raise MudrftError("the step produced a non-finite force; check the parameters and dt")
        if numba:
            return self._fview.copy()  # type: ignore[no-any-return]
        w, o = self._w, kernels.W_OUT
        return np.array((w[o], w[o + 1], w[o + 2]))

    @property
    def stress(self) -> np.ndarray:
        """Channel stresses (sx, sy, sz) of the last step [Pa]."""
        o = kernels.W_OUT
        return np.array(self._w[o + 3 : o + 6], dtype=float)

    @property
    def depth(self) -> float:
        """Tip depth after the last step [m]."""
        return float(self._w[kernels.W_OUT + 6])

    def __repr__(self) -> str:
        return f"FastMudFoot(foot={self.foot!r}, mud={self.mud!r}, backend={self.backend!r})"
