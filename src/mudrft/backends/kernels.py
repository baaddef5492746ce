r"""Optimized kernels of the constitutive step: fused numpy for batches, scalar for one foot.

These kernels compute exactly the update of :func:`mudrft.constitutive.dynamics.step`
(the reference; the tests compare them with it on random inputs) but are arranged for
speed:

* :class:`ChannelConstants` holds the per-mud constants the step needs, computed once
  (reciprocals of :math:`\lambda`, :math:`\tau_{build}`, :math:`\tau_{leak}`,
  :math:`\varepsilon`, :math:`\nu`, and :math:`k_r`), so no validation and no division
  by a parameter happens in the hot loop (decision D71);
* :func:`fused_step` is the batched numpy update with no validation and few temporaries;
* :func:`scalar_channel_step` is the same update on Python floats with the ``math``
  module, for one channel at a time; written so that numba can compile it unchanged
  (:mod:`mudrft.backends.numba_kernels`).

The scalar kernels work on flat float containers (Python lists, or 1-D numpy arrays under
numba) addressed by offsets, never on slices: under numba a slice is a view whose reference
count every thread would update, which serialises a parallel loop (decision D75). The state
of a channel is ``st[o:o+5] = (gamma, gamma_w, xi, s_th, sigma_s)``; its constants are
``c[co:co+N_CONST]`` in the order of :data:`CONST_NAMES`.
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

import numpy as np

from ..constitutive.state import ChannelState
from ..parameters.base import MudParameters

__all__ = [
    "CONST_NAMES",
    "N_CONST",
    "ChannelConstants",
    "channel_constants",
    "constant_rows",
    "fused_step",
    "scalar_channel_step",
]

#: Order of the constants in a scalar constants row.
CONST_NAMES = (
    "alpha",
    "n",
    "inv_lam",
    "eta_m",
    "eta_inf",
    "k_a",
    "k_r",
    "tau_build",
    "inv_tau_build",
    "inv_tau_leak",
    "inv_epsilon",
    "sigma_y",
    "inv_nu",
)
#: Length of a constants row.
N_CONST = len(CONST_NAMES)


class ChannelConstants(NamedTuple):
    """Per-mud constants of the constitutive step, precomputed once (SI).

    Every field is a float array that broadcasts with the channel state (for a batch of
    feet with their own muds: shape ``(N, 3)``; for one mud shared by all: ``(3,)``).
    Units: ``alpha``, ``sigma_y`` [Pa]; ``n`` [-]; ``inv_lam``, ``k_a``,
    ``inv_tau_build``, ``inv_tau_leak`` [1/s]; ``eta_m``, ``eta_inf`` [Pa s]; ``k_r`` [-];
    ``tau_build`` [s]; ``inv_epsilon`` [-]; ``inv_nu`` [s].
    """

    alpha: np.ndarray
    n: np.ndarray
    inv_lam: np.ndarray
    eta_m: np.ndarray
    eta_inf: np.ndarray
    k_a: np.ndarray
    k_r: np.ndarray
    tau_build: np.ndarray
    inv_tau_build: np.ndarray
    inv_tau_leak: np.ndarray
    inv_epsilon: np.ndarray
    sigma_y: np.ndarray
    inv_nu: np.ndarray


def channel_constants(params: MudParameters) -> ChannelConstants:
    """Precompute the constants of the step from a (validated) parameter set.

    Parameters
    ----------
    params : MudParameters
        Parameter set; fields may be arrays (a batch), already validated by
        :class:`~mudrft.parameters.base.MudParameters`.

    Returns
    -------
    ChannelConstants
        Contiguous float arrays of the broadcast shape of the fields.

    Examples
    --------
    >>> import mudrft
    >>> c = channel_constants(mudrft.paper_parameters(0.25))
    >>> round(float(c.inv_lam), 4)
    0.5263
    """
    p = params
    shape = p.shape

    def arr(v: Any) -> np.ndarray:
        return np.array(np.broadcast_to(np.asarray(v, dtype=float), shape), dtype=float)

    lam, tb, tl = arr(p.lam), arr(p.tau_build), arr(p.tau_leak)
    return ChannelConstants(
        alpha=arr(p.alpha),
        n=arr(p.n),
        inv_lam=1.0 / lam,
        eta_m=arr(p.eta_m),
        eta_inf=arr(p.eta_inf),
        k_a=arr(p.k_a),
        k_r=arr(p.k_r),
        tau_build=tb,
        inv_tau_build=1.0 / tb,
        inv_tau_leak=1.0 / tl,
        inv_epsilon=1.0 / arr(p.epsilon),
        sigma_y=arr(p.sigma_y),
        inv_nu=1.0 / arr(p.nu),
    )


def constant_rows(consts: ChannelConstants) -> np.ndarray:
    """Constants as rows for the scalar kernels: shape ``batch + (N_CONST,)``."""
    return np.ascontiguousarray(np.stack(np.broadcast_arrays(*consts), axis=-1))


def fused_step(
    c: ChannelConstants,
    state: ChannelState,
    gamma: np.ndarray,
    gamma_dot: np.ndarray,
    dt: float,
    seal: Any = 1.0,
    kappa: float = 1.0,
) -> tuple[ChannelState, np.ndarray]:
    r"""Batched constitutive step without validation (numpy).

    Same update as :func:`mudrft.constitutive.dynamics.step` (see there for the
    equations); returns only the total stress of eq. (1), the quantity the feet need.

    Parameters
    ----------
    c : ChannelConstants
        Precomputed constants, broadcasting with ``gamma``.
    state : ChannelState
        State at the start of the step (arrays of the shape of ``gamma``).
    gamma : ndarray
        Dimensionless displacement at the end of the step [-].
    gamma_dot : ndarray
        Dimensionless rate over the step [1/s].
    dt : float
        Step length [s], > 0 (not checked).
    seal : float or ndarray
        Sealing factor in [0, 1] [-].
    kappa : float
        1.0 keeps the acceleration term (decision D6), 0.0 drops it.

    Returns
    -------
    state : ChannelState
        New state.
    total : ndarray
        Total stress :math:`\sigma_{tot}` [Pa].
    """
    g_old, gw_old, xi, s_th, sig_s = state
    ag = np.abs(gamma)
    agw = np.abs(gw_old)
    flipped = (np.sign(gamma) * np.sign(gw_old)) < 0
    keep_old = ~((ag >= agw) | flipped)
    gw_new = np.where(keep_old, gw_old, gamma)
    agw_new = np.where(keep_old, agw, ag)
    sg = np.sign(gw_new)
    direction = np.where(sg != 0, sg, np.where(gamma_dot != 0, np.sign(gamma_dot), 1.0))
    r_start = np.where(flipped, 0.0, np.maximum(agw - np.abs(g_old), 0.0))
    r_end = np.maximum(agw_new - ag, 0.0)

    # structure parameter
    agd = np.abs(gamma_dot)
    inv_tau = c.k_a + c.k_r * agd
    xi_ss = c.k_a / inv_tau
    e_xi = np.exp(-dt * inv_tau)
    dxi = xi - xi_ss
    xi_new = xi_ss + dxi * e_xi

    # lagged thixotropic stress
    B = c.eta_m * gamma_dot
    e_lam = np.exp(-dt * c.inv_lam)
    x = dt * (c.inv_lam - inv_tau)
    small = np.abs(x) < 1e-6
    xs = np.where(small, 1.0, x)
    em = np.where(small, 1.0 + 0.5 * x + x * x / 6.0, np.expm1(xs) / xs)
    conv = e_lam * (dt * c.inv_lam) * em
    drive = B * xi_ss
    if kappa != 1.0:
        drive = drive + (1.0 - kappa) * c.eta_inf * gamma_dot
    s_new = s_th * e_lam + drive * (1.0 - e_lam) + B * dxi * conv

    # suction
    r_mid = 0.5 * (r_start + r_end)
    phi = np.tanh(r_mid * c.inv_epsilon)
    if not (isinstance(seal, float) and seal == 1.0):
        phi = seal * phi
    a = phi * c.inv_tau_build + (1.0 - phi) * c.inv_tau_leak
    target = -direction * phi * c.sigma_y / (a * c.tau_build)
    sig_new = target + (sig_s - target) * np.exp(-a * dt)

    # total stress, eq. (1)
    pos = ag > 0
    safe = np.where(pos, ag, 1.0)
    sigma_b = np.where(pos, c.alpha * safe**c.n, 0.0) * np.sign(gamma)
    sigma_b *= 1.0 - np.tanh(r_end * c.inv_epsilon)
    H = 0.5 * (1.0 - np.tanh(direction * gamma_dot * c.inv_nu))
    total = sigma_b + s_new + H * sig_new
    if kappa != 0.0:
        total += kappa * c.eta_inf * gamma_dot
    new = ChannelState(gamma=gamma, gamma_w=gw_new, xi=xi_new, s_th=s_new, sigma_s=sig_new)
    return new, total


def _sign(v: float) -> float:
    if v > 0.0:
        return 1.0
    if v < 0.0:
        return -1.0
    return 0.0


def scalar_channel_step(
    c: Any,
    co: int,
    st: Any,
    o: int,
    gamma: float,
    gamma_dot: float,
    dt: float,
    seal: float,
    kappa: float,
) -> float:
    r"""One channel, one step, on floats; updates ``st[o:o+5]`` in place.

    Parameters
    ----------
    c : sequence of float
        Constants; the channel's are ``c[co:co+N_CONST]`` (:data:`CONST_NAMES`).
    co : int
        Offset of the channel's constants in ``c``.
    st : mutable sequence of float
        State container; ``st[o:o+5] = (gamma, gamma_w, xi, s_th, sigma_s)``.
    o : int
        Offset of the channel in ``st``.
    gamma : float
        Displacement at the end of the step [-].
    gamma_dot : float
        Rate over the step [1/s].
    dt : float
        Step [s].
    seal : float
        Sealing factor [-].
    kappa : float
        1.0 with the acceleration term (decision D6), else 0.0.

    Returns
    -------
    float
        Total stress [Pa].

    Examples
    --------
    >>> import mudrft
    >>> c = constant_rows(channel_constants(mudrft.paper_parameters(0.25))).tolist()
    >>> st = [0.0, 0.0, 0.0, 0.0, 0.0]
    >>> scalar_channel_step(c, 0, st, 0, 0.1, 1.0, 0.1, 1.0, 1.0) > 0
    True
    """
    alpha = c[co]
    n = c[co + 1]
    inv_lam = c[co + 2]
    eta_m = c[co + 3]
    eta_inf = c[co + 4]
    k_a = c[co + 5]
    k_r = c[co + 6]
    g_old = st[o]
    gw_old = st[o + 1]
    xi = st[o + 2]
    s_th = st[o + 3]
    sig_s = st[o + 4]

    ag = abs(gamma)
    agw = abs(gw_old)
    flipped = _sign(gamma) * _sign(gw_old) < 0.0
    if ag >= agw or flipped:
        gw_new = gamma
        agw_new = ag
    else:
        gw_new = gw_old
        agw_new = agw
    if gw_new != 0.0:
        direction = _sign(gw_new)
    elif gamma_dot != 0.0:
        direction = _sign(gamma_dot)
    else:
        direction = 1.0
    if flipped:
        r_start = 0.0
    else:
        r_start = max(agw - abs(g_old), 0.0)
    r_end = max(agw_new - ag, 0.0)

    inv_tau = k_a + k_r * abs(gamma_dot)
    xi_ss = k_a / inv_tau
    dxi = xi - xi_ss
    xi_new = xi_ss + dxi * math.exp(-dt * inv_tau)

    B = eta_m * gamma_dot
    e_lam = math.exp(-dt * inv_lam)
    x = dt * (inv_lam - inv_tau)
    if abs(x) < 1e-6:
        em = 1.0 + 0.5 * x + x * x / 6.0
    else:
        em = math.expm1(x) / x
    conv = e_lam * (dt * inv_lam) * em
    drive = B * xi_ss + (1.0 - kappa) * eta_inf * gamma_dot
    s_new = s_th * e_lam + drive * (1.0 - e_lam) + B * dxi * conv

    # tanh is skipped where its value is exact without it: 0 at 0, and 1.0 for arguments
    # >= 20, where every libm (and numpy, XLA) rounds tanh to exactly 1 (decision D76)
    inv_eps = c[co + 10]
    u = 0.5 * (r_start + r_end) * inv_eps
    phi = seal * (0.0 if u == 0.0 else (1.0 if u >= 20.0 else math.tanh(u)))
    a = phi * c[co + 8] + (1.0 - phi) * c[co + 9]
    target = -direction * phi * c[co + 11] / (a * c[co + 7])
    sig_new = target + (sig_s - target) * math.exp(-a * dt)

    if ag > 0.0:
        sigma_b = alpha * ag**n * _sign(gamma)
    else:
        sigma_b = 0.0
    u = r_end * inv_eps
    if u != 0.0:
        sigma_b = sigma_b * (1.0 - (1.0 if u >= 20.0 else math.tanh(u)))
    w = direction * gamma_dot * c[co + 12]
    H = 0.5 * (1.0 - (1.0 if w >= 20.0 else (-1.0 if w <= -20.0 else math.tanh(w))))
    st[o] = gamma
    st[o + 1] = gw_new
    st[o + 2] = xi_new
    st[o + 3] = s_new
    st[o + 4] = sig_new
    return sigma_b + s_new + kappa * eta_inf * gamma_dot + H * sig_new


# ---------------------------------------------------------------------------------------
# one foot, three channels: MudTerrain.step on floats
# ---------------------------------------------------------------------------------------
#: Length of the scalar foot state: 3 channels x 5, entry (x, y), heading, in_mud.
N_STATE = 19
#: Length of the scalar output: force (3) [N], stress (3) [Pa], depth [m].
N_OUT = 7
#: Length of a foot's constants: 3 channels x N_CONST.
N_FOOT_CONST = 3 * N_CONST


def scalar_foot_step(
    c: Any,
    co: int,
    st: Any,
    so: int,
    kind: int,
    geom: Any,
    x: float,
    y: float,
    z: float,
    vx: float,
    vy: float,
    vz: float,
    dt: float,
    lc: float,
    kappa: float,
    xi0: float,
    reset: bool,
    heading_speed: float,
    out: Any,
    oo: int,
) -> None:
    """:meth:`mudrft.MudTerrain.step` for one rigid closed-form foot, on floats, in place.

    Parameters
    ----------
    c : sequence of float
        Constants of the x, y, z channels at ``c[co:co+N_FOOT_CONST]``.
    co : int
        Offset of the foot's constants.
    st : mutable sequence of float
        State at ``st[so:so+N_STATE]`` (updated in place): channels (15), entry (x, y) [m],
        heading [rad], in_mud (0.0 or 1.0).
    so : int
        Offset of the foot's state.
    kind : int
        Foot kind (:data:`FOOT_KINDS`).
    geom : sequence of float
        Foot dimensions [m] (see :func:`scalar_foot_force`).
    x, y, z : float
        Tip position at the end of the step [m].
    vx, vy, vz : float
        Tip velocity [m/s].
    dt : float
        Step [s].
    lc : float
        Characteristic length [m].
    kappa : float
        1.0 with the acceleration term (decision D6).
    xi0 : float
        Structure of fresh mud [-].
    reset : bool
        Reset the channels when the tip re-enters the mud (decision D11).
    heading_speed : float
        Horizontal speed below which the heading is kept [m/s].
    out : mutable sequence of float
        ``out[oo:oo+N_OUT]`` receives force [N], stress [Pa] and depth [m].
    oo : int
        Offset of the foot's output.
    """
    depth = -z if z < 0.0 else 0.0
    in_mud = depth > 0.0
    was_in = st[so + 18] != 0.0
    if reset and not was_in:
        for k in range(3):
            st[so + 5 * k] = 0.0
            st[so + 5 * k + 1] = 0.0
            st[so + 5 * k + 2] = xi0
            st[so + 5 * k + 3] = 0.0
            st[so + 5 * k + 4] = 0.0
        st[so + 15] = x - vx * dt
        st[so + 16] = y - vy * dt
    gz_dot = -vz / lc if (in_mud or was_in) else 0.0
    if math.hypot(vx, vy) > heading_speed:
        st[so + 17] = math.atan2(vy, vx)
    heading = st[so + 17]
    s0 = scalar_channel_step(c, co, st, so, (x - st[so + 15]) / lc, vx / lc, dt, 1.0, kappa)
    s1 = scalar_channel_step(
        c, co + N_CONST, st, so + 5, (y - st[so + 16]) / lc, vy / lc, dt, 1.0, kappa
    )
    s2 = scalar_channel_step(c, co + 2 * N_CONST, st, so + 10, depth / lc, gz_dot, dt, 1.0, kappa)
    st[so + 18] = 1.0 if in_mud else 0.0
    if in_mud:
        scalar_foot_force(kind, geom, depth, s0, s1, s2, heading, out, oo)
        out[oo + 3] = s0
        out[oo + 4] = s1
        out[oo + 5] = s2
    else:
        for k in range(6):
            out[oo + k] = 0.0
    out[oo + 6] = depth


# ---------------------------------------------------------------------------------------
# closed-form feet on floats (mirror of mudrft.feet.closed_form, tested against it)
# ---------------------------------------------------------------------------------------
#: Foot kinds of the scalar kernels and the geometry each expects (all in m).
FOOT_KINDS = {"flat": 0, "semi-cylinder": 1, "semi-sphere": 2}


def _theta_c(z: float, radius: float) -> float:
    u = 1.0 - z / radius
    if u < -1.0:
        u = -1.0
    elif u > 1.0:
        u = 1.0
    return math.acos(u)


def scalar_foot_force(
    kind: int,
    geom: Any,
    depth: float,
    s0: float,
    s1: float,
    s2: float,
    heading: float,
    out: Any,
    oo: int,
) -> None:
    r"""World-frame force of a closed-form foot (:meth:`mudrft.feet.base.Foot.force`) on floats.

    The paper's closed form (as corrected in :mod:`mudrft.feet.closed_form`) at the heading
    folded into the first quadrant gives the coefficients of the horizontal stresses, which
    :func:`mudrft.feet.base.unfold_forces` maps to the world (decision D9).

    Parameters
    ----------
    kind : int
        0 flat (``geom = (L, W, H)``), 1 semi-cylinder (``(R, W, H)``), 2 semi-sphere
        (``(R, H, 0)``); lengths [m].
    geom : sequence of float
        Dimensions [m].
    depth : float
        Tip depth [m], >= 0.
    s0, s1, s2 : float
        Channel stresses [Pa].
    heading : float
        World heading [rad].
    out : mutable sequence of float
        ``out[oo:oo+3]`` receives the force [N].
    oo : int
        Offset in ``out``.
    """
    ch = math.cos(heading)
    sh = math.sin(heading)
    phi = math.atan2(abs(sh), abs(ch))
    # coefficients of the first-quadrant closed form, linear in (sx, sy):
    # Fx = ax sx + bx sy, Fy = by sx + ay sy (normal terms a, shear terms b)
    if kind == 0:
        length = geom[0]
        width = geom[1]
        z = min(depth, geom[2])
        phic = 0.5 * math.pi - phi
        ax = z * length * (0.5 * (1.0 + math.cos(2.0 * phi)))
        by = z * length * (0.5 * (1.0 - math.cos(2.0 * phi)))
        bx = z * width * (0.5 * (1.0 - math.cos(2.0 * phic)))
        ay = z * width * (0.5 * (1.0 + math.cos(2.0 * phic)))
        fz = length * width * s2 if depth > 0.0 else 0.0
    elif kind == 1:
        r = geom[0]
        width = geom[1]
        z = min(depth, geom[2])
        th = _theta_c(z, r)
        s = math.sin(th)
        c = math.cos(th)
        phic = 0.5 * math.pi - phi
        seg = r * r * (th - s * c)
        side = width * r * (1.0 - c)
        ax = seg * (0.5 * (1.0 + math.cos(2.0 * phi)))
        by = seg * (0.5 * (1.0 - math.cos(2.0 * phi)))
        bx = side * (0.5 * (1.0 - math.cos(2.0 * phic)))
        ay = side * (0.5 * (1.0 + math.cos(2.0 * phic)))
        fz = 2.0 * width * r * (s - s**3 / 3.0 + 2.0 / 3.0 - c + c**3 / 3.0) * s2
    else:
        r = geom[0]
        z = min(depth, geom[1])
        th = _theta_c(z, r)
        s = math.sin(th)
        c = math.cos(th)
        side = 8.0 / 3.0 * r * r * (th - s * c)
        ax = side * math.cos(phi)
        ay = side * math.sin(phi)
        bx = 0.0
        by = 0.0
        ring = (
            (1.0 - c**4) / 4.0
            + 3.0 * th / 8.0
            - math.sin(2.0 * th) / 4.0
            + math.sin(4.0 * th) / 32.0
        )
        fz = 2.0 * math.pi * r * r * ring * s2
    # world forces (mudrft.feet.base.unfold_forces, decision D9): normal terms keep the sign
    # of their channel stress, shear terms oppose the sliding along their axis
    out[oo] = -(ax * s0 + bx * abs(s1) * _sign(ch))
    out[oo + 1] = -(ay * s1 + by * abs(s0) * _sign(sh))
    out[oo + 2] = fz


#: Layout of the work vector of :func:`fast_foot_step`: geometry, options, state, output.
CFG_NAMES = ("kind", "characteristic_length", "kappa", "xi0", "reset_on_exit", "heading_speed")
W_GEOM = 0
W_CFG = 3
W_STATE = W_CFG + len(CFG_NAMES)
W_OUT = W_STATE + N_STATE
N_WORK = W_OUT + N_OUT


def fast_foot_step(c: Any, w: Any, pos: Any, vel: Any, dt: float) -> int:
    """One checked foot step with everything in two flat containers (low call overhead).

    Parameters
    ----------
    c : sequence of float, length N_FOOT_CONST
        Constants of the x, y, z channels.
    w : mutable sequence of float, length N_WORK
        Work vector: geometry ``w[0:3]`` [m], options ``w[3:9]`` (:data:`CFG_NAMES`: kind,
        L_c [m], kappa, xi0, reset_on_exit 0/1, heading_speed [m/s]), state
        ``w[W_STATE:W_OUT]`` and output ``w[W_OUT:N_WORK]`` (see :func:`scalar_foot_step`).
    pos, vel : sequence of 3 float
        Tip position [m] and velocity [m/s].
    dt : float
        Step [s].

    Returns
    -------
    int
        0 on success, 1 for bad inputs (non-finite or dt <= 0; nothing changed), 2 for a
        non-finite force.
    """
    x = pos[0]
    y = pos[1]
    z = pos[2]
    vx = vel[0]
    vy = vel[1]
    vz = vel[2]
    if not (dt > 0.0 and math.isfinite(dt) and math.isfinite(x + y + z + vx + vy + vz)):
        return 1
    scalar_foot_step(
        c,
        0,
        w,
        W_STATE,
        int(w[W_CFG]),
        w,
        x,
        y,
        z,
        vx,
        vy,
        vz,
        dt,
        w[W_CFG + 1],
        w[W_CFG + 2],
        w[W_CFG + 3],
        w[W_CFG + 4] != 0.0,
        w[W_CFG + 5],
        w,
        W_OUT,
    )
    if not math.isfinite(w[W_OUT] + w[W_OUT + 1] + w[W_OUT + 2]):
        return 2
    return 0
