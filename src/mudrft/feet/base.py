r"""The foot interface shared by closed-form feet, mesh feet and the morphing foot.

A foot's frame has its origin at its lowest point (the *tip*), z up; ``depth`` [m] >= 0 is
the tip's below the mud surface. Channel stresses [Pa]: :math:`\sigma_z>0` support,
horizontal ones positive when they resist the motion. Forces: the mud's on the foot [N].
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np

from .._typing import ArrayLike, FloatArray, Namespace, XpArray
from .._validation import (
    MudrftError,
    check_broadcast,
    check_finite,
    check_in_range,
    check_nonnegative,
    warn_implausible,
)

__all__ = [
    "CHUNK", "Foot", "SurfaceElements", "check_depth_stress", "check_resultant_inputs",
    "first_quadrant", "fold_heading", "in_chunks", "magnitudes", "projection_weights",
    "unfold_forces", "world_force"
]  # fmt: skip


#: Facet evaluations per vectorized chunk of samples x facets (bounded memory).
CHUNK = 1 << 16


def in_chunks(fn: Callable[..., Any], n_facets: int, *rows: np.ndarray) -> Any:
    """``fn(*rows)`` over the leading axis of ``rows``, about :data:`CHUNK` facet evaluations
    (``n_facets`` a row) at a time; ``fn`` returns an array, or a named tuple of arrays.

    >>> in_chunks(lambda d: d[:, None] * np.ones(3), 1 << 15, np.arange(5.0)).shape
    (5, 3)
    """
    n, step = rows[0].shape[0], max(1, CHUNK // max(int(n_facets), 1))
    if n <= step:
        return fn(*rows)
    parts = [fn(*(r[i : i + step] for r in rows)) for i in range(0, n, step)]
    if isinstance(parts[0], tuple):
        return type(parts[0])(*(np.concatenate(p, axis=0) for p in zip(*parts, strict=True)))
    return np.concatenate(parts, axis=0)


@dataclass(frozen=True, eq=False)
class SurfaceElements:
    """Surface elements of a foot in its frame: ``centroids`` (m, 3) [m], outward unit
    ``normals`` (m, 3) [-] and ``areas`` (m,) [m^2]."""

    centroids: np.ndarray
    normals: np.ndarray
    areas: np.ndarray

    def __len__(self) -> int:
        return int(self.areas.shape[0])


STRESS_BATCH = "stress (its last axis, 3, aside)"


def first_quadrant(
    stress: ArrayLike, heading: ArrayLike
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Reduce a world heading to the first quadrant, as the paper's closed forms expect.

    Parameters
    ----------
    stress : array_like, shape (..., 3)
        Channel stresses [Pa], positive when they resist the motion.
    heading : array_like
        World heading of the horizontal motion [rad], broadcasting to the batch shape.

    Returns
    -------
    tuple
        ``(stress_q, phi, signs)``: the stresses (a copy), the folded heading [rad] and the
        signs (sx, sy) that map first-quadrant forces back to the world (D9).
    """
    s, h = _check_stress(stress), check_finite("heading", heading)
    if check_broadcast(**{STRESS_BATCH: s.shape[:-1]}, heading=h.shape) != s.shape[:-1]:
        raise MudrftError(
            f"heading (shape {h.shape}) must broadcast to stress's batch shape {s.shape[:-1]}"
        )
    signs = np.stack([np.where(np.cos(h) < 0, -1.0, 1.0), np.where(np.sin(h) < 0, -1.0, 1.0)], -1)
    return s.copy(), fold_heading(h), signs


def _check_stress(stress: ArrayLike) -> FloatArray:
    s = check_finite("stress", stress)
    if s.shape[-1:] != (3,):
        raise MudrftError(f"stress must have shape (..., 3) [Pa], got shape {s.shape}")
    return s


#: A tip depth beyond this [m] and this many foot heights warns (mm read as m?).
PLAUSIBLE_DEPTH = 1.0
PLAUSIBLE_DEPTH_HEIGHTS = 10.0


def check_depth_stress(
    depth: ArrayLike, stress: ArrayLike, *, height: float
) -> tuple[FloatArray, FloatArray]:
    """A tip depth [m] (>= 0) and channel stresses (..., 3) [Pa] given to a foot of ``height``
    [m], validated, as float arrays; an implausibly deep tip warns."""
    d = check_nonnegative("depth", depth, unit="m")
    if d.size:
        limit = max(PLAUSIBLE_DEPTH, PLAUSIBLE_DEPTH_HEIGHTS * float(height))
        warn_implausible(
            "foot: a tip depth of", float(d.max()), (0.0, limit), unit="m",
            hint="depth is in metres (20 mm = 0.02)",
        )  # fmt: skip
    return d, _check_stress(stress)


def check_resultant_inputs(
    depth: ArrayLike, stress: ArrayLike, heading: ArrayLike, *, height: float
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The arguments of :meth:`Foot.resultant` (depth [m], stress (..., 3) [Pa], heading in
    [0, pi/2] [rad]) for a foot of ``height`` [m], validated, as float arrays."""
    d, s = check_depth_stress(depth, stress, height=height)
    h = check_in_range("heading", heading, 0.0, 0.5 * np.pi, unit="rad")
    batch_shape(d, s, h)
    return d, s, h


def batch_shape(
    depth: np.ndarray, stress: np.ndarray, heading: np.ndarray, **more: tuple[int, ...]
) -> tuple[int, ...]:
    """The batch shape of depth [m], stress (..., 3) [Pa], heading [rad] and any ``more``
    named shapes, or an error that names each shape."""
    return check_broadcast(
        depth=depth.shape, **{STRESS_BATCH: stress.shape[:-1]}, heading=heading.shape, **more
    )


def fold_heading(heading: XpArray, xp: Namespace = np) -> XpArray:
    """The world heading folded into the first quadrant, :math:`[0,\\pi/2]` [rad] (D9)."""
    return xp.arctan2(xp.abs(xp.sin(heading)), xp.abs(xp.cos(heading)))


def world_force(
    coefficients: tuple[XpArray, XpArray, XpArray, XpArray, XpArray], sx: XpArray, sy: XpArray,
    sz: XpArray, heading: XpArray, xp: Namespace = np,
) -> tuple[XpArray, XpArray, XpArray]:  # fmt: skip
    r"""The heading rule (D9): world force [N] from a closed form's coefficients
    ``(a_x, b_x, b_y, a_y, a_z)`` [m^2] at the folded heading (:func:`fold_heading`), signed
    stresses [Pa] and the world ``heading`` [rad] (sgn 0 = +1):

    .. math:: F_x=-\operatorname{sgn}(\cos h)\,(a_x\sigma_x+b_x\sigma_y),\quad
              F_y=-\operatorname{sgn}(\sin h)\,(a_y\sigma_y+b_y\sigma_x),\quad F_z=a_z\sigma_z
    """
    ax, bx, by, ay, az = coefficients
    cx, cy = xp.where(xp.cos(heading) < 0.0, -1.0, 1.0), xp.where(xp.sin(heading) < 0.0, -1.0, 1.0)
    return -cx * (ax * sx + bx * sy), -cy * (ay * sy + by * sx), az * sz


def projection_weights(normals: np.ndarray) -> np.ndarray:
    r"""Area projected along x, y and z per unit area [-] (m, 3) of elements of unit ``normals``
    (m, 3): half of :math:`|n_x|` and :math:`|n_y|` (seen from one side), :math:`\max(-n_z,0)`."""
    n = normals
    return np.stack(
        [0.5 * np.abs(n[:, 0]), 0.5 * np.abs(n[:, 1]), np.clip(-n[:, 2], 0.0, None)], axis=-1
    )


def magnitudes(coefficients: tuple[XpArray, ...], stress: XpArray, xp: Namespace = np) -> XpArray:
    """First-quadrant magnitudes (Fx, Fy, Fz) [N] (..., 3) from the coefficients
    ``(a_x, b_x, b_y, a_y, a_z)`` [m^2] of a linear form and stresses (..., 3) [Pa]."""
    ax, bx, by, ay, az = coefficients
    s = xp.asarray(stress)
    sx, sy, sz = s[..., 0], s[..., 1], s[..., 2]
    return xp.stack(xp.broadcast_arrays(ax * sx + bx * sy, by * sx + ay * sy, az * sz), axis=-1)


def unfold_forces(
    magnitudes: Callable[[FloatArray, FloatArray], FloatArray],
    stress: ArrayLike,
    heading: ArrayLike,
) -> FloatArray:
    r"""World forces (..., 3) [N] for any heading [rad] from first-quadrant ``magnitudes``
    (stresses (..., 2, 3), folded headings (..., 1)): the linear form's coefficients read off
    unit stresses, then :func:`world_force`; ``stress`` (..., 3) [Pa]."""
    s, h = np.asarray(stress, dtype=float), np.asarray(heading, dtype=float)
    shape = np.broadcast_shapes(s.shape[:-1], h.shape)
    units = np.zeros((*shape, 2, 3))
    units[..., [0, 1], [0, 1]] = 1.0  # unit sx, then unit sy
    units[..., :, 2] = np.broadcast_to(s[..., 2], shape)[..., None]
    phi = np.broadcast_to(fold_heading(h), shape)[..., None]
    m = np.asarray(magnitudes(units, phi), dtype=float)
    coeffs = (m[..., 0, 0], m[..., 1, 0], m[..., 0, 1], m[..., 1, 1], 1.0)
    fx, fy, _ = world_force(coeffs, s[..., 0], s[..., 1], 0.0, h)
    return np.stack(np.broadcast_arrays(fx, fy, m[..., 0, 2]), axis=-1)


class Foot(ABC):
    """Abstract foot: subclasses implement :meth:`resultant` (and usually :meth:`elements`),
    and have a ``name`` (str), a ``characteristic_length`` :math:`L_c` [m] that makes
    displacements dimensionless, and a ``height`` above the tip [m]."""

    name: str = "foot"
    #: whether :meth:`force_components` gives the world force element-wise on any ``xp``
    elementwise: ClassVar[bool] = False

    @property
    @abstractmethod
    def characteristic_length(self) -> float:
        """Characteristic length :math:`L_c` [m]."""

    @property
    @abstractmethod
    def height(self) -> float:
        """Height of the foot above its tip [m]."""

    @abstractmethod
    def resultant(self, depth: ArrayLike, stress: ArrayLike, heading: ArrayLike) -> FloatArray:
        """Paper-style resultant force magnitudes (Fx, Fy, Fz) [N], shape (..., 3).

        Parameters
        ----------
        depth : float or array
            Tip depth [m], >= 0.
        stress : array_like, shape (..., 3)
            Uniform channel stresses (sx, sy, sz) [Pa], positive when resisting the motion.
        heading : float or array
            Horizontal heading of the motion from the x axis [rad], in [0, pi/2].
        """

    def projected_areas(self, depth: ArrayLike) -> FloatArray:
        """Areas of the submerged part projected along x, y and z [m^2], shape (..., 3), at
        tip ``depth`` [m], to normalise forces into stresses (paper Figs. 10-12)."""
        d = check_nonnegative("depth", depth, unit="m")
        el = self.elements()
        z, weights = el.centroids[:, 2], el.areas[:, None] * projection_weights(el.normals)
        wetted = in_chunks(lambda dd: (z[None, :] <= dd[:, None]) @ weights, len(z), d.reshape(-1))
        return wetted.reshape((*d.shape, 3))

    def elements(self) -> SurfaceElements:
        """Surface elements of the whole foot in its own frame (tip at the origin)."""
        raise MudrftError(f"{type(self).__name__} does not provide surface elements")

    def force(self, depth: ArrayLike, stress: ArrayLike, heading: ArrayLike) -> FloatArray:
        """World-frame force of the mud on the foot [N] (..., 3): arguments as :meth:`resultant`,
        with signed stresses [Pa] and any world heading [rad]."""
        d, s = check_depth_stress(depth, stress, height=self.height)
        h = check_finite("heading", heading)
        batch_shape(d, s, h)
        return self.force_unchecked(d, s, h)

    def force_unchecked(
        self, depth: np.ndarray, stress: np.ndarray, heading: np.ndarray
    ) -> np.ndarray:
        """:meth:`force` without input validation, for inner loops (arrays already checked)."""
        d = np.asarray(depth, dtype=float)
        return unfold_forces(lambda su, ph: self.resultant(d[..., None], su, ph), stress, heading)

    def force_components(
        self, depth: XpArray, sx: XpArray, sy: XpArray, sz: XpArray, heading: XpArray,
        xp: Namespace = np,
    ) -> tuple[XpArray, XpArray, XpArray]:  # fmt: skip
        """World force ``(F_x, F_y, F_z)`` [N] element-wise, for feet with ``elementwise``;
        parameters as :meth:`force`, the stresses split into channels [Pa]."""
        raise MudrftError(f"{type(self).__name__} has no element-wise force rule")

    def force_array(
        self, depth: XpArray, stress: XpArray, heading: XpArray, xp: Namespace = np
    ) -> XpArray:
        """:meth:`force_components` with the stresses (..., 3) [Pa] split and the world force
        stacked (..., 3) [N]; no validation, no dtype conversion."""
        s = xp.asarray(stress)
        f = self.force_components(
            xp.asarray(depth), s[..., 0], s[..., 1], s[..., 2], xp.asarray(heading), xp=xp
        )
        return xp.stack(xp.broadcast_arrays(*f), axis=-1)

    def initial_foot_state(self) -> Any:
        """Internal state of the foot mechanism (``None`` for rigid feet)."""
        return None

    def seal_factor(self, foot_state: Any) -> Any:
        """Factor in [0, 1] multiplying the cavity sealing state (1 for rigid feet) [-]."""
        return 1.0

    def contact_force(
        self, foot_state: Any, depth: np.ndarray, stress: np.ndarray, heading: np.ndarray,
        dt: float, *, retraction: Any = 0.0,
    ) -> tuple[Any, np.ndarray]:  # fmt: skip
        """Advance the foot's internal state; return ``(foot_state, force)`` [N] (rigid feet:
        :meth:`force`); ``retraction``: time since the retraction began [s]."""
        return foot_state, self.force_unchecked(depth, stress, heading)

    def center_of_pressure(
        self, depth: ArrayLike, stress: ArrayLike, heading: ArrayLike
    ) -> FloatArray:
        """Point of application of the mud force in the foot frame [m], shape (..., 3);
        by default on the foot axis, half-way up the submerged height."""
        d = np.minimum(np.asarray(depth, dtype=float), self.height)
        return np.stack([np.zeros_like(d), np.zeros_like(d), 0.5 * d], axis=-1)

    def __repr__(self) -> str:
        return f"{type(self).__name__}(name={self.name!r})"
