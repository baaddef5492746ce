r"""The column in balance with the mud, and the seal broken by curling pads (D32, D34, D35).

The deflection :math:`\delta` solves :math:`R(\delta)=F_s(\delta)-\sigma_zA_z(d,
\theta(\delta))=0` on :math:`[0,\delta_{max}]`, the end stops as complementarity: from the
previous deflection the column moves with the net force to the first root or stop (D34),
bracketed by a scan over 33 nodes, refined to :math:`|R|\le10^{-10}` N by bisection on
floats (up to 16 moving elements) or SciPy's ``find_root``.
"""

from __future__ import annotations

import dataclasses
import functools
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..._typing import Namespace, XpArray
from ..._validation import MudrftError, plain
from ..._xp import pyfloat
from .linkage import Linkage, MorphingRow, pad_angle
from .pads import morphing_force, vertical_area
from .springs import TwoStageSpring, spring_force

if TYPE_CHECKING:
    from .linkage import MorphingFootGeometry


def _find_root() -> Any:
    """SciPy's ``find_root`` (SciPy >= 1.15) or None, imported on first use (tests set it)."""
    if "find_root" not in globals():
        try:
            from scipy.optimize.elementwise import find_root
        except ImportError:  # pragma: no cover - exercised by the tests through monkeypatching
            find_root = None
        globals()["find_root"] = find_root
    return globals()["find_root"]


def __getattr__(name: str) -> Any:
    if name == "find_root":
        return _find_root()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


__all__ = [
    "MorphingState", "balanced_deflection", "balanced_deflection_on_floats", "column_residual",
    "contact_on_floats", "held_deflection", "linkage_row", "seal_factor", "track_most_spread"
]  # fmt: skip

_GRID = 33  # nodes of the coarse bracketing grid over the stroke (D34)
_FTOL = 1e-10  # force balance tolerance [N]
_XTOL = 1e-15  # bracket width at which the refinement stops [m]
_FEW = 16  # up to this many moving elements take the float path one by one, more find_root [-]
_BISECTIONS = 64  # cap on the halvings of a bracket on floats (39 take 0.37 mm to 1e-15 m)


class MorphingState(NamedTuple):
    """Internal state of a morphing foot (scalars or arrays of one batch shape): column
    ``deflection`` [m], ``pad_angle`` [rad] and ``most_spread``, the smallest pad angle of
    the current contact [rad] (seal memory, D35)."""

    deflection: NDArray[np.float64]
    pad_angle: NDArray[np.float64]
    most_spread: NDArray[np.float64]


def column_residual(
    g: MorphingFootGeometry | MorphingRow, pole_top: XpArray, branch: XpArray,
    spring: TwoStageSpring | MorphingRow, deflection: XpArray, depth: XpArray, sz: XpArray,
    xp: Namespace = np,
) -> XpArray:  # fmt: skip
    r"""Balance residual :math:`R` [N] (D32), element-wise: ``g`` and ``spring`` by attribute
    (dataclasses or a :class:`~.linkage.MorphingRow`), ``pole_top`` [m] and ``branch`` of the
    linkage; deflection [m], depth [m], vertical stress [Pa]."""
    theta = pad_angle(g, pole_top, branch, deflection, xp=xp)
    return spring_force(spring, deflection, xp=xp) - sz * vertical_area(g, depth, theta, xp=xp)


@functools.lru_cache(maxsize=64)
def linkage_row(
    linkage: Linkage, spring: TwoStageSpring, seal_length: float = 1.0, lock: float = -1.0,
    curl_delay: float = 0.0,
) -> MorphingRow:  # fmt: skip
    """The :class:`~.linkage.MorphingRow` of a :class:`~.linkage.Linkage` and a
    :class:`~.springs.TwoStageSpring` (seal length [m], locked deflection [m] or -1,
    pad-curl delay [s]); cached, for :func:`balanced_deflection` on floats."""
    # every field of the geometry (a field the row lacks fails below, instead of vanishing)
    values = dataclasses.asdict(linkage.geometry)
    values.update({k: getattr(linkage, k) for k in ("pole_top", "stroke", "branch")})
    knees = ("series_stiffness", "hard_stiffness", "knee_deflection", "knee_force")
    values.update({k: getattr(spring, k) for k in knees})
    values.update(seal_length=seal_length, lock=lock, curl_delay=curl_delay)
    return MorphingRow(**{k: float(v) for k, v in values.items()})


def balanced_deflection(
    depth: ArrayLike, sz: ArrayLike, *, previous: ArrayLike, linkage: Linkage,
    spring: TwoStageSpring,
) -> NDArray[np.float64]:  # fmt: skip
    """Column deflection [m] in balance with the mud from ``previous`` [m] (D34), unchecked:
    tip depth [m] >= 0, vertical stress [Pa]; the result has the broadcast shape."""
    d, s, p = np.broadcast_arrays(
        np.asarray(depth, float), np.asarray(sz, float), np.asarray(previous, float)
    )
    shape = d.shape
    d, s = d.ravel(), s.ravel()
    stroke = linkage.stroke
    p = np.clip(p.ravel(), 0.0, stroke)
    out = p.copy()
    f = functools.partial(
        column_residual, linkage.geometry, linkage.pole_top, linkage.branch, spring
    )
    r_p = f(p, d, s)
    moving = _moving(r_p, p, stroke)
    count = int(np.count_nonzero(moving))
    if count > _FEW and _find_root() is not None:
        out[moving] = _move(f, d[moving], s[moving], p[moving], r_p[moving], stroke)
    elif count:
        row = linkage_row(linkage, spring)
        seen: dict[tuple[float, float, float], float] = {}  # the coupling's nudged copies
        for i in np.flatnonzero(moving):
            key = (float(d[i]), float(s[i]), float(p[i]))
            if key not in seen:
                seen[key] = balanced_deflection_on_floats(row, *key)
            out[i] = seen[key]
    return out.reshape(shape)


def _moving(r_p: XpArray, p: XpArray, stroke: XpArray, xp: Namespace = np) -> XpArray:
    """Whether the column moves from ``p`` [m] (residual ``r_p`` [N] there): not balanced,
    and not pushed against the stop it rests on (D34)."""
    return ((r_p < 0.0) & (p < stroke)) | ((r_p > 0.0) & (p > 0.0))


def _node(k: XpArray, up: XpArray, stroke: XpArray, xp: Namespace = np) -> XpArray:
    """The ``k``-th of the 33 nodes [m] in the direction of motion (``up``: from 0), the
    values of ``np.linspace(0, stroke, 33)`` bit for bit."""
    j = xp.where(up, k, _GRID - 1 - k)
    return xp.where(j == _GRID - 1, stroke, j * (stroke / (_GRID - 1)))


def _scan_node(
    up: XpArray, p: XpArray, x: XpArray, r: XpArray, lo: XpArray, flo: XpArray, hi: XpArray,
    fhi: XpArray, found: XpArray, xp: Namespace = np,
) -> tuple[XpArray, XpArray, XpArray, XpArray, XpArray]:  # fmt: skip
    """One node ``x`` [m] (residual ``r`` [N]) of the scan from ``p`` [m] (D34), element-wise:
    beyond ``p`` (``up``: compressing), a node where R keeps its sign is the near end of the
    bracket, the first where it changes the far end. Returns ``(lo, flo, hi, fhi, found)``.
    """
    beyond = xp.where(found, False, xp.where(up, x > p, x < p))
    hit = beyond & xp.where(up, r >= 0.0, r <= 0.0)
    to_hi = beyond & (hit == up)  # compressing: the root's far side; extending: the near end
    to_lo = beyond & (hit != up)
    lo, flo = xp.where(to_lo, x, lo), xp.where(to_lo, r, flo)
    hi, fhi = xp.where(to_hi, x, hi), xp.where(to_hi, r, fhi)
    return lo, flo, hi, fhi, found | hit


def _settle(
    up: XpArray, found: XpArray, lo: XpArray, flo: XpArray, hi: XpArray, fhi: XpArray,
    stroke: XpArray, xp: Namespace = np,
) -> tuple[XpArray, XpArray]:  # fmt: skip
    """The deflection [m] of a finished scan (a stop if no root was found, else a bracket end
    that balances), and whether the bracket is open, to be refined (R(lo) < 0 < R(hi))."""
    x = xp.where(found, xp.where(fhi == 0.0, hi, lo), xp.where(up, stroke, 0.0))
    return x, found & (flo != 0.0) & (fhi != 0.0)


def _move(
    f: Callable[..., NDArray[np.float64]], d: NDArray[np.float64], s: NDArray[np.float64],
    p: NDArray[np.float64], r_p: NDArray[np.float64], stroke: float,
) -> NDArray[np.float64]:  # fmt: skip
    """The moving elements of a batch, ``f`` the residual [N] of (deflection, depth, sz): the
    scan on arrays, then ``find_root`` in one call."""
    nodes = np.linspace(0.0, stroke, _GRID)
    r_n = f(nodes[None, :], d[:, None], s[:, None])
    up = r_p < 0.0
    r_n = np.where(up[:, None], r_n, r_n[:, ::-1])  # in the direction of motion
    lo, flo, hi, fhi, found = p, r_p, p, r_p, np.zeros(d.size, dtype=bool)
    for k in range(_GRID):
        x, r = _node(k, up, stroke), r_n[:, k]
        lo, flo, hi, fhi, found = _scan_node(up, p, x, r, lo, flo, hi, fhi, found)
        if found.all():
            break  # the remaining nodes change nothing
    out, open_ = _settle(up, found, lo, flo, hi, fhi, stroke)
    if not np.any(open_):
        return np.asarray(out)

    a, b, dd, ss = lo[open_], hi[open_], d[open_], s[open_]
    tol = {"xatol": _XTOL, "xrtol": 0.0, "fatol": _FTOL, "frtol": 0.0}
    res = _find_root()(f, (a, b), args=(dd, ss), tolerances=tol)
    if not np.all(res.success):
        bad = int(np.flatnonzero(~res.success)[0])
        raise MudrftError(
            "the column balance did not converge: expected a root of R in "
            f"[{plain(a[bad])}, {plain(b[bad])}] m at depth {plain(dd[bad])} m and sz "
            f"{plain(ss[bad])} Pa, got scipy status {int(res.status[bad])}"
        )
    out[open_] = res.x
    return np.asarray(out)


def seal_factor(
    pad_angle: ArrayLike, most_spread: ArrayLike, pad_length: float, seal_length: float,
    xp: Namespace = np,
) -> XpArray:  # fmt: skip
    r"""Seal factor :math:`1-\tanh(g/g_s)` [-], :math:`g=\ell(\sin\theta-\sin\theta_m)` (D35).

    ``pad_angle`` :math:`\theta` and ``most_spread`` :math:`\theta_m` [rad], ``pad_length``
    :math:`\ell` and ``seal_length`` :math:`g_s` [m]; 1 while the pads are at their most spread.

    >>> float(seal_factor(0.5, 0.5, pad_length=0.034, seal_length=0.002))
    1.0
    """
    lift = xp.maximum(pad_length * (xp.sin(pad_angle) - xp.sin(most_spread)), 0.0)
    return 1.0 - xp.tanh(lift / seal_length)


def track_most_spread(
    depth: XpArray, pad_angle: XpArray, most_spread: XpArray, xp: Namespace = np
) -> XpArray:
    """Seal memory after a step: the smallest pad angle [rad] of the contact, reset to
    ``pad_angle`` [rad] out of the mud (``depth`` [m] 0) (D35)."""
    return xp.where(depth > 0.0, xp.minimum(most_spread, pad_angle), pad_angle)


def held_deflection(
    deflection: XpArray, previous: XpArray, retraction: XpArray, curl_delay: float,
    xp: Namespace = np,
) -> XpArray:  # fmt: skip
    r"""The deflection [m] after the pad-curl delay (D35): for the first ``curl_delay`` [s] of a
    retraction (``retraction``: :math:`t-t_w` [s], or 0) the column may not extend from
    ``previous`` [m]; else ``deflection``, the step's balance [m].

    >>> float(held_deflection(0.004, 0.011, 0.02, 0.05)), float(held_deflection(0.004, 0.011, 0.06, 0.05))
    (0.011, 0.004)
    """
    held = (retraction > 0.0) & (retraction <= curl_delay)
    return xp.where(held, xp.maximum(deflection, previous), deflection)


def balanced_deflection_on_floats(
    m: MorphingRow, depth: float, sz: float, previous: float, xp: Namespace = pyfloat
) -> float:
    r""":func:`balanced_deflection` [m] for one foot on floats, ``m`` a
    :class:`~.linkage.MorphingRow`: depth [m], vertical stress [Pa], previous deflection [m]."""
    stroke = m.stroke
    p = xp.clip(previous, 0.0, stroke)
    r_p = column_residual(m, m.pole_top, m.branch, m, p, depth, sz, xp=xp)
    if not _moving(r_p, p, stroke, xp=xp):
        return p  # balanced already, or pushed against the stop it rests on
    up = r_p < 0.0
    lo, flo, hi, fhi, found = p, r_p, p, r_p, False
    for k in range(_GRID):
        x = _node(k, up, stroke, xp=xp)
        if (x <= p) if up else (x >= p):
            continue  # behind the start: _scan_node would skip it; save the residual
        r = column_residual(m, m.pole_top, m.branch, m, x, depth, sz, xp=xp)
        lo, flo, hi, fhi, found = _scan_node(up, p, x, r, lo, flo, hi, fhi, found, xp=xp)
        if found:
            break
    x, open_ = _settle(up, found, lo, flo, hi, fhi, stroke, xp=xp)
    if not open_:
        return x
    for _ in range(_BISECTIONS):
        mid = 0.5 * (lo + hi)
        r = column_residual(m, m.pole_top, m.branch, m, mid, depth, sz, xp=xp)
        if abs(r) <= _FTOL:
            return mid
        if r < 0.0:
            lo = mid
        else:
            hi = mid
        if hi - lo <= _XTOL:
            break
    return 0.5 * (lo + hi)


def contact_on_floats(
    m: MorphingRow, deflection: float, most_spread: float, depth: float, sx: float, sy: float,
    sz: float, heading: float, retraction: float, xp: Namespace = pyfloat,
) -> tuple[float, float, float, float, float, float]:  # fmt: skip
    """One foot's :meth:`~.foot.MorphingFoot.contact_force` on floats (arguments as there, ``m``
    a :class:`~.linkage.MorphingRow`): ``(F_x, F_y, F_z, deflection, pad_angle, most_spread)``."""
    if m.lock >= 0.0:
        delta = m.lock
    else:
        delta = balanced_deflection_on_floats(m, depth, sz, deflection, xp=xp)
        delta = held_deflection(delta, deflection, retraction, m.curl_delay, xp=xp)
    th = pad_angle(m, m.pole_top, m.branch, delta, xp=xp)
    fx, fy, fz = morphing_force(m, depth, th, sx, sy, sz, heading, xp=xp)
    return fx, fy, fz, delta, th, track_most_spread(depth, th, most_spread, xp=xp)
