"""MuJoCo's tree Jacobian and sparse mass-matrix solve, on floats, for the compiled coupling.

:func:`_jacobian` is ``mj_jac`` (the 6 x nv Jacobian of a point's velocity and the body's
angular velocity, from ``cdof``) and :func:`_ld_solve` is ``mj_solveLD`` (``x <- M^-1 x``
for each row of ``x``, from the factor ``qLD``, ``qLDiagInv`` in MuJoCo's compressed rows
``M_rownnz``, ``M_rowadr``, ``M_colind``); :func:`_robot_step` solves the implicit step of
one robot's feet together and bounds its work (:func:`_solve_n`, D62d). They are plain
Python (``test_mobility_port_equals_mujoco`` runs them against MuJoCo's own functions) and
are compiled with the kernel (:mod:`.compiled`). :func:`_ptr` turns the address of a
MuJoCo array into a pointer the kernel reads with ``numba.carray``; :func:`_borrow` makes
such a view of one of the kernel's own arrays.
"""

from __future__ import annotations

from typing import Any

import numba
from numba import types as nt
from numba.extending import intrinsic

from ..._typing import FloatArray, IndexArray
from ..._xp import pyfloat
from .implicit import passivity_scale

__all__ = [
    "_borrow",
    "_carve",
    "_jacobian",
    "_ld_solve",
    "_robot_step",
    "_solve_n",
]


def _ld_solve(
    x: FloatArray,
    qld: FloatArray,
    qldinv: FloatArray,
    rownnz: IndexArray,
    rowadr: IndexArray,
    colind: IndexArray,
) -> None:
    """In place x <- M^-1 x for each row of ``x`` (r, nv) from MuJoCo's sparse L^T D L
    factor (``mj_solveLD``).

    The rows are solved together, each with ``mj_solveLD``'s operations in its order (a
    row's values are those of solving it alone): one call and one walk of the sparse rows
    for the six rows of a foot's Jacobian instead of six.
    """
    r, nv = x.shape
    for i in range(nv - 1, 0, -1):
        if rownnz[i] == 1:
            continue
        start = rowadr[i]
        for k in range(r):
            xi = x[k, i]
            if xi != 0.0:
                for adr in range(start, start + rownnz[i] - 1):
                    x[k, colind[adr]] -= qld[adr] * xi
    for k in range(r):
        for i in range(nv):
            x[k, i] *= qldinv[i]
    for i in range(1, nv):
        if rownnz[i] == 1:
            continue
        start = rowadr[i]
        for k in range(r):
            acc = 0.0
            for adr in range(start, start + rownnz[i] - 1):
                acc += qld[adr] * x[k, colind[adr]]
            x[k, i] -= acc


def _jacobian(jac: FloatArray, body: int, point: FloatArray, model_i: IndexArray,
              dof_parentid: IndexArray, cdof: FloatArray, subtree_com: FloatArray,
              ) -> None:  # fmt: skip
    """6 x nv Jacobian of (velocity of ``point``, angular velocity) of ``body`` (``mj_jac``)."""
    jac[:, :] = 0.0
    b = body
    while b > 0 and model_i[b, 1] == 0:  # body_dofnum
        b = model_i[b, 2]  # body_parentid
    if b == 0:
        return
    i = model_i[b, 0] + model_i[b, 1] - 1  # body_dofadr + body_dofnum - 1
    root = model_i[b, 3]
    ox = point[0] - subtree_com[root, 0]
    oy = point[1] - subtree_com[root, 1]
    oz = point[2] - subtree_com[root, 2]
    while i >= 0:
        wx, wy, wz = cdof[i, 0], cdof[i, 1], cdof[i, 2]
        jac[0, i] = cdof[i, 3] + (wy * oz - wz * oy)
        jac[1, i] = cdof[i, 4] + (wz * ox - wx * oz)
        jac[2, i] = cdof[i, 5] + (wx * oy - wy * ox)
        jac[3, i], jac[4, i], jac[5, i] = wx, wy, wz
        i = dof_parentid[i]


def _solve_n(A: FloatArray, b: FloatArray, n: int) -> None:
    """In place b <- A^-1 b (n x n, Gaussian elimination with partial pivoting; A destroyed)."""
    for k in range(n):
        p = k
        for r in range(k + 1, n):
            if abs(A[r, k]) > abs(A[p, k]):
                p = r
        if p != k:
            for j in range(n):
                A[k, j], A[p, j] = A[p, j], A[k, j]
            b[k], b[p] = b[p], b[k]
        for r in range(k + 1, n):
            f = A[r, k] / A[k, k]
            for j in range(k, n):
                A[r, j] -= f * A[k, j]
            b[r] -= f * b[k]
    for k in range(n - 1, -1, -1):
        acc = b[k]
        for j in range(k + 1, n):
            acc -= A[k, j] * b[j]
        b[k] = acc / A[k, k]


def _robot_step(
    nb: int, nv: int, dt: float, FJ: FloatArray, FM: FloatArray, FK: FloatArray, FW0: FloatArray, FACC: FloatArray, FTW: FloatArray, FPOS: FloatArray,
    WF: FloatArray, AJ: FloatArray, RJ: FloatArray, FWR: FloatArray, FWV: FloatArray,
    tank: float,
) -> float:  # fmt: skip
    """One robot's implicit step of all its feet together and its passivity bound, on floats.

    The compiled form of :func:`.implicit.implicit_wrench` and :func:`.implicit.passive_wrench`
    (D62, D62c, D62d) for the feet with a wrench or damping (``FPOS[j] >= 0``; the others
    have no wrench, and their ``W w`` is 0 as in the numpy coupling): the mobility ``WF``
    (6 m x 6 m) from each foot's ``FJ`` and ``FM`` = M^-1 J^T; the system ``(I - dt K W) w = w0 + dt K a`` in ``AJ``, ``RJ``; the wrenches
    scaled by the bound into ``FWR`` and ``W w`` into ``FWV``. Returns the robot's tank
    after the step [J].
    """
    m = 0
    for j in range(nb):
        if FPOS[j] >= 0.0:
            FPOS[j] = m
            m += 1
    n = 6 * m
    for i in range(nb):  # W is symmetric: the blocks (i, j >= i), mirrored
        if FPOS[i] < 0.0:
            continue
        pi = int(FPOS[i])
        for j in range(i, nb):
            if FPOS[j] < 0.0:
                continue
            pj = int(FPOS[j])
            for a in range(6):
                for c in range(a if i == j else 0, 6):
                    acc = 0.0
                    for d in range(nv):
                        acc += FJ[i, a, d] * FM[j, c, d]
                    WF[6 * pi + a, 6 * pj + c] = acc
                    WF[6 * pj + c, 6 * pi + a] = acc
    for i in range(nb):
        if FPOS[i] < 0.0:
            continue
        pi = int(FPOS[i])
        for a in range(6):
            row = 6 * pi + a
            for col in range(n):
                kw = 0.0
                for d in range(6):
                    kw += FK[i, a, d] * WF[6 * pi + d, col]
                AJ[row, col] = (1.0 if row == col else 0.0) - dt * kw
            ka = 0.0
            for d in range(6):
                ka += FK[i, a, d] * FACC[i, d]
            RJ[row] = FW0[i, a] + dt * ka
    _solve_n(AJ, RJ, n)
    lin, quad, zero = 0.0, 0.0, True
    for i in range(nb):
        pi = int(FPOS[i])
        for a in range(6):
            if FPOS[i] < 0.0:
                FWR[i, a], FWV[i, a] = 0.0, 0.0
                continue
            acc = 0.0
            for col in range(n):
                acc += WF[6 * pi + a, col] * RJ[col]
            FWR[i, a], FWV[i, a] = RJ[6 * pi + a], acc
            lin += FWR[i, a] * (FTW[i, a] + 0.5 * dt * FACC[i, a])
            quad += FWR[i, a] * acc
            zero = zero and FWR[i, a] == 0.0
    lin, quad = dt * lin, 0.5 * dt * dt * quad
    sc = passivity_scale(lin, quad, tank, pyfloat)
    for i in range(nb):
        for a in range(6):
            FWR[i, a] = sc * FWR[i, a]
            FWV[i, a] = sc * FWV[i, a]
    return 0.0 if zero else max(tank - (sc * lin + sc * sc * quad), 0.0)


@intrinsic  # type: ignore[misc]
def _ptr(typingctx: Any, address: Any) -> Any:
    """An integer address as a numba ``float64*`` (compiled code only)."""
    sig = nt.CPointer(nt.float64)(nt.int64)

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        return builder.inttoptr(args[0], context.get_value_type(nt.CPointer(nt.float64)))

    return sig, codegen


@intrinsic  # type: ignore[misc]
def _iptr(typingctx: Any, address: Any) -> Any:
    """An integer address as a numba ``int64*`` (compiled code only)."""
    sig = nt.CPointer(nt.int64)(nt.int64)

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        return builder.inttoptr(args[0], context.get_value_type(nt.CPointer(nt.int64)))

    return sig, codegen


carray = numba.carray


def _borrow(a: FloatArray) -> FloatArray:
    """A float64 C-contiguous array as a view without a reference count (``numba.carray``
    on its address): every view the kernel then takes of it (a row, a slice, an argument
    to a helper) skips numba's atomic reference updates (about 2.5 us of the walking
    biped's step). The caller keeps ``a`` alive while the view is used (the kernel's
    packed argument does, for the call)."""
    return carray(_ptr(a.ctypes.data), a.shape)  # type: ignore[call-arg]


def _carve(base: int, offset: int, shape: tuple[int, ...]) -> FloatArray:
    """A borrowed float64 view of ``shape`` starting ``offset`` floats after the address
    ``base`` (the kernel's work array, carved into its parts; as :func:`_borrow`, the
    caller keeps the memory alive)."""
    return carray(_ptr(base + 8 * offset), shape)  # type: ignore[call-arg]
