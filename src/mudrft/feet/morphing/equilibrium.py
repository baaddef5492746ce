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
``find_root``, brentq refines every bracket.

*Sealing* (D35). Curling pads break the seal of the cavity under the foot: the seal factor
is :math:`1-\tanh(g/g_s)` with :math:`g=\ell(\sin\theta-\sin\theta_m)` [m] the lift of the pad
rims above their most spread position :math:`\theta_m` in the current contact.
"""

from __future__ import annotations

from typing import NamedTuple, NoReturn

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.optimize import brentq

from ..._validation import MudrftError, plain
from .linkage import Linkage
from .pads import vertical_area
from .springs import TwoStageSpring

try:  # SciPy >= 1.15
    from scipy.optimize.elementwise import find_root
except ImportError:  # pragma: no cover - exercised by the tests through monkeypatching
    find_root = None

__all__ = ["MorphingState", "balanced_deflection", "residual", "seal_factor", "track_most_spread"]

_GRID = 33  # nodes of the coarse bracketing grid over the stroke (D34)
_FTOL = 1e-10  # force balance tolerance [N]
_XTOL = 1e-15  # bracket width at which the refinement stops [m]
_RTOL = 4.0 * np.finfo(float).eps  # relative bracket width for brentq, its smallest allowed [-]
_FEW = 16  # up to this many brackets are refined by brentq one by one, more by find_root [-]


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
    theta = linkage.angle(deflection)
    s = np.asarray(sz, dtype=float)
    return np.asarray(spring.force(deflection) - s * vertical_area(linkage.geometry, depth, theta))


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
) -> NDArray[np.float64]:
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

    Returns
    -------
    ndarray
        Factor in (0, 1] [-]: 1 while the pads are at their most spread.

    Examples
    --------
    >>> float(seal_factor(0.5, 0.5, pad_length=0.034, seal_length=0.002))
    1.0
    """
    th = np.asarray(pad_angle, dtype=float)
    tm = np.asarray(most_spread, dtype=float)
    lift = np.maximum(pad_length * (np.sin(th) - np.sin(tm)), 0.0)
    return np.asarray(1.0 - np.tanh(lift / seal_length))


def track_most_spread(
    depth: ArrayLike, pad_angle: ArrayLike, most_spread: ArrayLike
) -> NDArray[np.float64]:
    """Seal memory after a step: the smallest pad angle of the contact [rad] (D35).

    Parameters
    ----------
    depth : float or array_like
        Tip depth [m]; out of the mud (0) the memory resets to the current angle.
    pad_angle : float or array_like
        Pad angle after the step [rad].
    most_spread : float or array_like
        Memory before the step [rad].
    """
    d = np.asarray(depth, dtype=float)
    return np.asarray(np.where(d > 0, np.minimum(most_spread, pad_angle), pad_angle))
