r"""The column in balance with the mud, and the seal broken by curling pads (D32, D34, D35).

*Load path* (D32). The trajectory prescribes the tip; the whole vertical mud force on the
base and the pads passes through the column, so the deflection :math:`\delta` solves

.. math:: R(\delta) = F_s(\delta) - \sigma_zA_z\bigl(d, \theta(\delta)\bigr) = 0
          \quad\text{on}\quad [0, \delta_{max}],

with the end stops as complementarity: :math:`\delta=0` where :math:`R(0)\ge0` (the mud does
not push), :math:`\delta=\delta_{max}` where :math:`R(\delta_{max})\le0` (it pushes harder
than the fully compressed springs).

*Root selection* (D34). Where pads dip into the surface as they spread, :math:`R` can have
three roots (a snap-through). :func:`balanced_deflection` returns the root an overdamped
column reaches: from the previous deflection it moves in the direction of the net force
(:math:`R<0`: compress, :math:`R>0`: extend) to the first root or stop it meets. This gives
hysteresis, and equals the unique root wherever :math:`R` is monotone.

*Algorithm*, vectorized over a batch: elements balanced already, or pushed against the stop
they rest on, stay; the others evaluate :math:`R` on 33 nodes over the stroke and take the
first sign change beyond the previous deflection, in the direction of motion, as a bracket.
The scan, not the solver, selects the branch: the bracket holds the root to select and no
other, unless three roots fall within one node spacing (0.37 mm for the defaults), which the
grid does not resolve. Each bracket is then refined by a SciPy bracketing solver to
:math:`|R|\le10^{-10}` N or a bracket of :math:`10^{-15}` m: more than 16 brackets at once
(a batched terrain step: thousands) by :func:`scipy.optimize.elementwise.find_root`
(Chandrupatla's method), which is vectorized over the batch but costs ~2 ms a call whatever
the batch size; up to 16 (a single foot) by :func:`scipy.optimize.brentq`, one bracket at a
time, ~0.15 ms each (the measured crossover). Both are elementwise, so a batch gives bit for bit the deflections of
single calls refined by the same solver; across the threshold they agree to :math:`10^{-12}` m
(both stop within :math:`10^{-10}` N of the same root). With SciPy older than 1.15, which lacks
``find_root``, brentq refines every bracket. One foot on floats (the compiled coupling,
D68d): :func:`balanced_deflection_on_floats`, the same scan as a loop that stops at the
first sign change, refined by bisection to the same tolerances.

*Sealing* (D35). Curling pads break the seal of the cavity under the foot: the seal factor
is :math:`1-\tanh(g/g_s)` with :math:`g=\ell(\sin\theta-\sin\theta_m)` [m] the lift of the pad
rims above their most spread position :math:`\theta_m` in the current contact.
"""

from __future__ import annotations

from typing import Any, NamedTuple, NoReturn

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import brentq

from ..._validation import MudrftError, plain
from ..._xp import pyfloat
from .linkage import Linkage, pad_angle
from .pads import morphing_force, vertical_area
from .springs import TwoStageSpring, spring_force

try:  # SciPy >= 1.15
    from scipy.optimize.elementwise import find_root
except ImportError:  # pragma: no cover - exercised by the tests through monkeypatching
    find_root = None

__all__ = [
    "MorphingState",
    "balanced_deflection",
    "balanced_deflection_on_floats",
    "column_residual",
    "contact_on_floats",
    "residual",
    "seal_factor",
    "track_most_spread",
]

_GRID = 33  # nodes of the coarse bracketing grid over the stroke (D34)
_FTOL = 1e-10  # force balance tolerance [N]
_XTOL = 1e-15  # bracket width at which the refinement stops [m]
_RTOL = 4.0 * np.finfo(float).eps  # relative bracket width for brentq, its smallest allowed [-]
_FEW = 16  # up to this many brackets are refined by brentq one by one, more by find_root [-]
_BISECTIONS = 64  # cap on the halvings of a bracket on floats (39 take 0.37 mm to 1e-15 m)


class MorphingState(NamedTuple):
    """Internal state of a morphing foot (scalars or arrays of one batch shape).

    Attributes
    ----------
    deflection : ndarray
        Column deflection :math:`\\delta` [m].
    pad_angle : ndarray
        Pad angle :math:`\\theta(\\delta)` [rad].
    most_spread : ndarray
        Smallest pad angle reached during the current contact [rad] (seal memory, D35).
    """

    deflection: NDArray[np.float64]
    pad_angle: NDArray[np.float64]
    most_spread: NDArray[np.float64]


def column_residual(
    g: Any, pole_top: Any, branch: Any, spring: Any, deflection: Any, depth: Any, sz: Any,
    *, xp: Any = np,
) -> Any:  # fmt: skip
    r"""Balance residual :math:`R=F_s(\delta)-\sigma_zA_z(d,\theta(\delta))` [N], element-wise.

    The one definition of the column balance (D32), over ``xp`` (D80): ``g`` the dimensions
    and ``spring`` the spring constants by attribute (dataclasses, or one
    :class:`~.row.MorphingRow` for both), ``pole_top`` [m] and ``branch`` of the linkage;
    deflection [m], depth [m], vertical channel stress [Pa].
    """
    theta = pad_angle(g, pole_top, branch, deflection, xp=xp)
    return spring_force(spring, deflection, xp=xp) - sz * vertical_area(g, depth, theta, xp=xp)


def residual(
    deflection: ArrayLike,
    depth: ArrayLike,
    sz: ArrayLike,
    *,
    linkage: Linkage,
    spring: TwoStageSpring,
) -> NDArray[np.float64]:
    r"""Balance residual :math:`R=F_s(\delta)-\sigma_zA_z(d,\theta(\delta))` [N] (unchecked).

    Parameters
    ----------
    deflection : float or array_like
        Column deflection [m], in [0, stroke].
    depth : float or array_like
        Tip depth [m], >= 0.
    sz : float or array_like
        Vertical channel stress [Pa] (> 0 support, < 0 suction).
    linkage : Linkage, keyword-only
        The pad kinematics.
    spring : TwoStageSpring, keyword-only
        The column springs.

    Returns
    -------
    ndarray
        :math:`R` [N]: > 0 where the springs push the column back open.
    """
    d, s = np.asarray(depth, dtype=float), np.asarray(sz, dtype=float)
    x = np.asarray(deflection, dtype=float)
    g = linkage.geometry
    return np.asarray(column_residual(g, linkage.pole_top, linkage.branch, spring, x, d, s))


def balanced_deflection(
    depth: ArrayLike,
    sz: ArrayLike,
    *,
    previous: ArrayLike,
    linkage: Linkage,
    spring: TwoStageSpring,
) -> NDArray[np.float64]:
    """Column deflection in balance with the mud [m], continued from ``previous`` (D34).

    Unchecked inner-loop path of :meth:`MorphingFoot.equilibrium`; see the module
    docstring for the root selection and the solver.

    Parameters
    ----------
    depth : float or array_like
        Tip depth [m], >= 0.
    sz : float or array_like
        Vertical channel stress [Pa], finite.
    previous : float or array_like, keyword-only
        Deflection at the previous instant [m] (clipped to [0, stroke]).
    linkage : Linkage, keyword-only
        The pad kinematics.
    spring : TwoStageSpring, keyword-only
        The column springs.

    Returns
    -------
    ndarray
        Deflection [m], of the broadcast shape of the inputs.
    """
    d, s, p = np.broadcast_arrays(
        np.asarray(depth, float), np.asarray(sz, float), np.asarray(previous, float)
    )
    shape = d.shape
    d, s = d.ravel(), s.ravel()
    stroke = linkage.stroke
    p = np.clip(p.ravel(), 0.0, stroke)
    out = p.copy()
    r_p = residual(p, d, s, linkage=linkage, spring=spring)
    # elements balanced already, or pushed against the stop they rest on, stay put
    moving = ((r_p < 0) & (p < stroke)) | ((r_p > 0) & (p > 0))
    if np.any(moving):
        out[moving] = _move(d[moving], s[moving], p[moving], r_p[moving], linkage, spring)
    return out.reshape(shape)


def _move(
    d: NDArray[np.float64],
    s: NDArray[np.float64],
    p: NDArray[np.float64],
    r_p: NDArray[np.float64],
    linkage: Linkage,
    spring: TwoStageSpring,
) -> NDArray[np.float64]:
    """Nearest root from ``p`` in the direction of the net force, or the stop it meets."""
    n = d.size
    stroke = linkage.stroke
    out = p.copy()
    nodes = np.linspace(0.0, stroke, _GRID)
    r_n = residual(nodes[None, :], d[:, None], s[:, None], linkage=linkage, spring=spring)
    idx = np.arange(n)
    lo, hi, flo, fhi = np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n)
    # moving up (compressing): first node above the previous deflection where the springs win
    up = r_p < 0
    cand = (nodes[None, :] > p[:, None]) & (r_n >= 0)
    has = cand.any(axis=1)
    j = np.argmax(cand, axis=1)
    jm = np.maximum(j - 1, 0)
    sel_up = up & has
    below = nodes[jm] > p
    lo = np.where(sel_up, np.where(below, nodes[jm], p), lo)
    flo = np.where(sel_up, np.where(below, r_n[idx, jm], r_p), flo)
    hi = np.where(sel_up, nodes[j], hi)
    fhi = np.where(sel_up, r_n[idx, j], fhi)
    out = np.where(up & ~has, stroke, out)  # no root: onto the compression stop
    # moving down (extending): last node below the previous deflection where the mud wins
    down = ~up
    cand = (nodes[None, :] < p[:, None]) & (r_n <= 0)
    has = cand.any(axis=1)
    j = _GRID - 1 - np.argmax(cand[:, ::-1], axis=1)
    jp = np.minimum(j + 1, _GRID - 1)
    sel_down = down & has
    above = nodes[jp] < p
    lo = np.where(sel_down, nodes[j], lo)
    flo = np.where(sel_down, r_n[idx, j], flo)
    hi = np.where(sel_down, np.where(above, nodes[jp], p), hi)
    fhi = np.where(sel_down, np.where(above, r_n[idx, jp], r_p), fhi)
    out = np.where(down & ~has, 0.0, out)  # no root: onto the extension stop
    act = sel_up | sel_down
    if np.any(act):
        out[act] = _refine(lo[act], hi[act], flo[act], fhi[act], d[act], s[act], linkage, spring)
    return out


def _refine(
    lo: NDArray[np.float64],
    hi: NDArray[np.float64],
    flo: NDArray[np.float64],
    fhi: NDArray[np.float64],
    d: NDArray[np.float64],
    s: NDArray[np.float64],
    linkage: Linkage,
    spring: TwoStageSpring,
) -> NDArray[np.float64]:
    """Root of R in each bracket [lo, hi] with R(lo) <= 0 <= R(hi), lo < hi (SciPy).

    More than ``_FEW`` open brackets: one vectorized ``find_root`` call; fewer (or SciPy <
    1.15): ``brentq`` per bracket, which avoids find_root's fixed cost of ~2 ms a call.
    """
    x = np.where(fhi == 0, hi, lo)  # an end of the bracket that balances already
    open_ = (flo != 0) & (fhi != 0)
    if not np.any(open_):
        return x

    def f(
        xx: NDArray[np.float64], dd: NDArray[np.float64], ss: NDArray[np.float64]
    ) -> NDArray[np.float64]:
        return residual(xx, dd, ss, linkage=linkage, spring=spring)

    a, b, dd, ss = lo[open_], hi[open_], d[open_], s[open_]
    if find_root is not None and a.size > _FEW:
        tol = {"xatol": _XTOL, "xrtol": 0.0, "fatol": _FTOL, "frtol": 0.0}
        res = find_root(f, (a, b), args=(dd, ss), tolerances=tol)
        if not np.all(res.success):
            bad = int(np.flatnonzero(~res.success)[0])
            _diverged(a[bad], b[bad], dd[bad], ss[bad], f"scipy status {int(res.status[bad])}")
        x[open_] = res.x
        return x
    # few brackets (a single foot), or SciPy < 1.15: brentq, one bracket at a time
    fa, fb = flo[open_], fhi[open_]
    for i, k in enumerate(np.flatnonzero(open_)):

        def g(t: float, i: int = i) -> float:
            if t == a[i] or t == b[i]:  # brentq starts at the ends: R is known there
                r = float(fa[i] if t == a[i] else fb[i])
            else:
                r = float(f(np.asarray(t), dd[i], ss[i]))
            return 0.0 if abs(r) <= _FTOL else r  # |R| <= 1e-10 N: balanced, as in find_root

        root, info = brentq(g, a[i], b[i], xtol=_XTOL, rtol=_RTOL, full_output=True, disp=False)
        if not info.converged:
            _diverged(a[i], b[i], dd[i], ss[i], f"brentq flag {info.flag!r}")
        x[k] = root
    return x


def _diverged(a: float, b: float, d: float, s: float, why: str) -> NoReturn:
    raise MudrftError(
        "the column balance did not converge: expected a root of R in "
        f"[{plain(a)}, {plain(b)}] m at depth {plain(d)} m and sz {plain(s)} Pa, got {why}"
    )


def seal_factor(
    pad_angle: ArrayLike,
    most_spread: ArrayLike,
    *,
    pad_length: float,
    seal_length: float,
    xp: Any = np,
) -> Any:
    r"""Seal factor :math:`1-\tanh(g/g_s)` [-], :math:`g=\ell(\sin\theta-\sin\theta_m)` (D35).

    Parameters
    ----------
    pad_angle : float or array_like
        Current pad angle :math:`\theta` [rad].
    most_spread : float or array_like
        Smallest pad angle of the current contact, :math:`\theta_m` [rad].
    pad_length : float, keyword-only
        :math:`\ell` [m].
    seal_length : float, keyword-only
        Rim lift :math:`g_s` over which the seal breaks [m], > 0.
    xp : module, keyword-only
        Element-wise namespace (D80).

    Returns
    -------
    ndarray
        Factor in (0, 1] [-]: 1 while the pads are at their most spread.

    Examples
    --------
    >>> float(seal_factor(0.5, 0.5, pad_length=0.034, seal_length=0.002))
    1.0
    """
    lift = xp.maximum(pad_length * (xp.sin(pad_angle) - xp.sin(most_spread)), 0.0)
    return 1.0 - xp.tanh(lift / seal_length)


def track_most_spread(depth: Any, pad_angle: Any, most_spread: Any, *, xp: Any = np) -> Any:
    """Seal memory after a step: the smallest pad angle of the contact [rad] (D35).

    Parameters
    ----------
    depth : float or array_like
        Tip depth [m]; out of the mud (0) the memory resets to the current angle.
    pad_angle : float or array_like
        Pad angle after the step [rad].
    most_spread : float or array_like
        Memory before the step [rad].
    xp : module, keyword-only
        Element-wise namespace (D80).
    """
    return xp.where(depth > 0.0, xp.minimum(most_spread, pad_angle), pad_angle)


def balanced_deflection_on_floats(
    m: Any, depth: float, sz: float, previous: float, *, xp: Any = pyfloat
) -> float:
    r""":func:`balanced_deflection` for one foot on floats (the compiled coupling, D68d).

    The same root selection (D34) as the array path: stay where balanced or against the
    stop pushed on; else scan the same 33 nodes from ``previous`` in the direction of the
    net force to the first sign change (or the stop), and refine the bracket to
    :math:`|R|\le10^{-10}` N or a width of :math:`10^{-15}` m, here by bisection (numba
    cannot call SciPy). ``m`` is a :class:`~.row.MorphingRow`; depth [m], vertical stress
    [Pa], previous deflection [m]; returns the deflection [m]. The test
    ``test_deflection_on_floats_equals_the_array_path`` keeps the two paths equal.
    """
    stroke = m.stroke
    p = xp.clip(previous, 0.0, stroke)
    r_p = column_residual(m, m.pole_top, m.branch, m, p, depth, sz, xp=xp)
    up = r_p < 0.0
    if not ((up and p < stroke) or (r_p > 0.0 and p > 0.0)):
        return p  # balanced already, or pushed against the stop it rests on
    lo, flo, hi, fhi = p, r_p, p, r_p
    found = False
    for i in range(_GRID):
        k = i if up else _GRID - 1 - i
        x = stroke if k == _GRID - 1 else k * (stroke / (_GRID - 1))  # np.linspace's nodes
        if (up and x <= p) or (not up and x >= p):
            continue
        r = column_residual(m, m.pole_top, m.branch, m, x, depth, sz, xp=xp)
        if up and r >= 0.0:
            hi, fhi, found = x, r, True
            break
        if not up and r <= 0.0:
            lo, flo, found = x, r, True
            break
        if up:
            lo, flo = x, r
        else:
            hi, fhi = x, r
    if not found:
        return stroke if up else 0.0  # no root: onto the stop
    if fhi == 0.0:
        return hi
    if flo == 0.0:
        return lo
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
    m: Any, deflection: float, most_spread: float, depth: float, sx: float, sy: float,
    sz: float, heading: float, *, xp: Any = pyfloat,
) -> tuple[float, float, float, float, float, float]:  # fmt: skip
    """One foot's :meth:`~.foot.MorphingFoot.contact_force` on floats (D68d).

    The balanced (or locked) deflection, its pad angle, the force of the mud on the base
    and pads (:func:`~.pads.morphing_force`) and the seal memory, for a
    :class:`~.row.MorphingRow` ``m``, the previous deflection [m] and memory [rad], depth
    [m], signed stresses [Pa] and world heading [rad]. Returns ``(F_x, F_y, F_z,
    deflection, pad_angle, most_spread)`` [N, m, rad].
    """
    if m.lock >= 0.0:
        delta = m.lock
    else:
        delta = balanced_deflection_on_floats(m, depth, sz, deflection, xp=xp)
    th = pad_angle(m, m.pole_top, m.branch, delta, xp=xp)
    fx, fy, fz = morphing_force(m, depth, th, sx, sy, sz, heading, xp=xp)
    return fx, fy, fz, delta, th, track_most_spread(depth, th, most_spread, xp=xp)
