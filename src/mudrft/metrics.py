r"""The paper's metrics on force histories (Sec. IV-B, Table II, Figs. 10-13).

All functions take sampled histories (time [s], force [N], depth [m]) and integrate with
the trapezoidal rule, exact for the piecewise-linear signals between samples.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
from numpy.typing import ArrayLike

from ._typing import FloatArray, FloatOrArray
from ._validation import MudrftError, check_finite, check_increasing, check_shape

__all__ = [
    "Metrics", "cycle_metrics", "energy", "impulse", "max_suction", "normalized_stress",
    "peak_support", "relative_rmse", "sinking_depth",
]  # fmt: skip


class Metrics(dict[str, float]):
    """The metrics of a run (:meth:`mudrft.Result.metrics`), a dict; ``["sinking"]`` of a
    prescribed motion gives ``max_depth`` with a :class:`DeprecationWarning`."""

    def __missing__(self, key: str) -> float:
        if key == "sinking" and "max_depth" in self:
            warnings.warn(
                "metrics()['sinking'] of a prescribed motion is its deepest depth, "
                "metrics()['max_depth']; 'sinking' is the settled depth under a load "
                "(LoadControl)",
                DeprecationWarning,
                stacklevel=2,
            )
            return self["max_depth"]
        raise KeyError(key)


def _trapz(y: FloatArray, x: FloatArray) -> FloatOrArray:
    """Trapezoidal integral of ``y`` (samples along axis 0) over ``x``, as
    ``numpy.trapezoid`` (numpy >= 2.0) computes it."""
    dx = np.diff(x).reshape((-1,) + (1,) * (np.ndim(y) - 1))
    out: FloatOrArray = (dx * (y[1:] + y[:-1]) / 2.0).sum(axis=0)
    return out


def _history(name: str, value: ArrayLike) -> FloatArray:
    arr = check_shape(name, value, (None,))
    if arr.size == 0:
        raise MudrftError(f"{name} must hold at least one sample, got an empty array")
    return arr


def _forces(name: str, value: ArrayLike, samples: int) -> FloatArray:
    """A finite force (or velocity) history of ``samples`` samples, shape (n,) or (n, 3)."""
    if samples == 0:
        raise MudrftError("time must hold at least one sample, got an empty array")
    arr = check_finite(name, value)
    if arr.ndim not in (1, 2) or arr.shape[0] != samples or arr.shape[1:] not in ((), (3,)):
        raise MudrftError(
            f"{name} must have shape ({samples},) or ({samples}, 3) to match time, "
            f"got shape {arr.shape}"
        )
    return arr


def relative_rmse(predicted: ArrayLike, measured: ArrayLike) -> float:
    r"""Relative root-mean-square error [-] of ``predicted`` against ``measured``, 1-D
    histories on the same samples [any unit] (Table II, in %); normalised as decision D12:

    .. math:: e=\frac{\sqrt{\tfrac1N\sum_k(\hat F_k-F_k)^2}}{\max_k F_k-\min_k F_k}

    >>> round(relative_rmse([0.0, 1.0, 2.0], [0.0, 1.0, 3.0]), 6)
    0.19245
    """
    p, m = check_finite("predicted", predicted), check_finite("measured", measured)
    if p.shape != m.shape or p.ndim != 1 or p.size < 2:
        raise MudrftError(
            f"predicted and measured must be 1-D with the same length >= 2, got shapes {p.shape} and {m.shape}"
        )
    with np.errstate(over="ignore"):  # a range beyond the largest float is refused below
        span = float(m.max() - m.min())
        if span <= 0:
            raise MudrftError("measured must not be constant: its range normalises the error")
        rel = (p - m) / span
    if not (math.isfinite(span) and np.all(np.isfinite(rel))):
        raise MudrftError(
            f"predicted and measured must differ by less than the largest float, got a range "
            f"of {span!r}"
        )
    return float(np.sqrt(np.mean(rel * rel)))


def impulse(time: ArrayLike, force: ArrayLike) -> FloatArray:
    r"""Impulse per axis :math:`\int F\,dt` [N s] of ``force`` (n,) or (n, 3) [N] at the
    increasing ``time`` (n,) [s].

    >>> impulse([0.0, 1.0, 2.0], [[0, 0, 0], [1, 2, 3], [0, 0, 0]])
    array([1., 2., 3.])
    """
    t = check_increasing("time", time)
    f = _forces("force", force, t.size)
    return np.asarray(_trapz(f, t))


def max_suction(force_z: ArrayLike) -> float:
    """Maximum suction: magnitude (>= 0) of the most negative vertical force ``force_z``
    (n,) [N] (``result.force[:, 2]``).

    >>> max_suction([1.0, -3.0, 2.0]), max_suction([1.0, 2.0])
    (3.0, 0.0)
    """
    f = _history("force_z", force_z)
    return float(max(0.0, -float(np.min(f))))


def peak_support(force_z: ArrayLike) -> float:
    """Largest upward vertical force of ``force_z`` (n,) [N], 0 if never positive."""
    if np.asarray(force_z).dtype == bool:  # a mask (force > 0) given for the force
        raise MudrftError("force_z must be the vertical force [N], got a boolean array")
    f = _history("force_z", force_z)
    return float(max(0.0, float(np.max(f))))


def energy(time: ArrayLike, force: ArrayLike, velocity: ArrayLike) -> float:
    r"""Work the foot does against the mud, :math:`W=-\int \mathbf F\cdot\mathbf v\,dt` [J].

    ``force`` is the force of the mud on the foot [N]; ``velocity[k]`` [m/s] is the rate over
    the step that ends at ``time[k]`` [s] (decision D13b), so
    :math:`W=-\sum_k \tfrac12(\mathbf F_{k-1}+\mathbf F_k)\cdot\mathbf v_k\,\Delta t_k`.

    >>> # a constant 10 N resisting a 1 m/s motion for 2 s costs 20 J
    >>> energy([0.0, 2.0], [[-10, 0, 0], [-10, 0, 0]], [[1, 0, 0], [1, 0, 0]])
    20.0
    """
    t = check_increasing("time", time)
    f, v = _forces("force", force, t.size), check_finite("velocity", velocity)
    if v.shape != f.shape:
        raise MudrftError(f"velocity must have the shape of force {f.shape}, got shape {v.shape}")
    mean_force = 0.5 * (f[1:] + f[:-1])
    work = (mean_force * v[1:]).sum(axis=-1) if f.ndim == 2 else mean_force * v[1:]
    return float(-(work * np.diff(t)).sum()) + 0.0  # + 0.0: no work reads 0.0, not -0.0


def sinking_depth(depth: ArrayLike, *, final: bool = False) -> float:
    """The deepest tip ``depth`` (n,) [m] (``result.depth``), or the last with ``final=True``
    (under load control, the equilibrium sinking of Fig. 12)."""
    if not isinstance(final, (bool, np.bool_)):  # final="no" is true
        raise MudrftError(f"final must be True or False, got {final!r}")
    d = _history("depth", depth)
    if np.any(d < 0):
        raise MudrftError(
            f"depth must be >= 0 m (the depth below the surface, result.depth), got "
            f"{float(d.min())!r} m: was the tip's z given instead?"
        )
    return float(d[-1] if final else d.max())


def cycle_metrics(
    time: FloatArray, force: FloatArray, velocity: FloatArray, depth: FloatArray, *, load: bool
) -> Metrics:
    """The paper's metrics of one run from unchecked histories, as a :class:`~mudrft.Result`
    holds them: ``time`` [s], ``force`` [N] and ``velocity`` [m/s] (n, 3), ``depth`` [m].

    Returns ``peak_support`` [N], ``max_suction`` [N] (>= 0), ``impulse_x``, ``impulse_y``,
    ``impulse_z`` [N s], ``energy`` [J] (work of the foot against the terrain),
    ``max_depth`` [m], ``suction_ratio`` [-]; with ``load`` (a :class:`~mudrft.LoadControl`
    run) also ``sinking`` [m], the settled depth.
    """
    imp = impulse(time, force)
    peak, suction = peak_support(force[:, 2]), max_suction(force[:, 2])
    out = Metrics(
        peak_support=peak, max_suction=suction,
        impulse_x=float(imp[0]), impulse_y=float(imp[1]), impulse_z=float(imp[2]),
        energy=energy(time, force, velocity), max_depth=sinking_depth(depth),
        suction_ratio=suction / peak if peak > 0 else 0.0,
    )  # fmt: skip
    if load:
        out["sinking"] = sinking_depth(depth, final=True)
    return out


def normalized_stress(force: ArrayLike, areas: ArrayLike) -> FloatArray:
    r"""Force (n, 3) [N] divided by the matching cross-section ``areas`` (n, 3) [m^2], as in
    Figs. 10-12 [Pa]: :math:`\bar\sigma_i=F_i/A_i`, zero where the area is zero."""
    f, a = check_finite("force", force), check_finite("areas", areas)
    if f.shape != a.shape:
        raise MudrftError(f"force and areas must have the same shape, got {f.shape} and {a.shape}")
    if np.any(a < 0):
        raise MudrftError(f"areas must be >= 0 m^2, got {float(a.min())!r} m^2")
    safe = np.where(a > 0, a, 1.0)
    return np.where(a > 0, f / safe, 0.0)
