"""The compiled coupling's linear algebra, and MuJoCo's C functions called from it at
addresses passed as integers (so the compiled kernel stays cached on disk)."""

from __future__ import annotations

import ctypes
import functools
from pathlib import Path
from typing import Any

import numba
from llvmlite import binding as llvm
from llvmlite import ir
from numba import types as nt
from numba.extending import intrinsic

from ..._typing import FloatArray
from ..._xp import pyfloat
from ._lazy import _mujoco
from .pose import passivity_scale


def _solve_n(A: FloatArray, b: FloatArray, n: int) -> None:
    """In place b <- A^-1 b (n x n, Gaussian elimination with partial pivoting; A destroyed)."""
    for k in range(n):
        p, big = k, abs(A[k, k])
        for r in range(k + 1, n):
            if abs(A[r, k]) > big:
                p, big = r, abs(A[r, k])
        if p != k:
            for j in range(n):
                A[k, j], A[p, j] = A[p, j], A[k, j]
            b[k], b[p] = b[p], b[k]
        inv = 1.0 / A[k, k]
        for r in range(k + 1, n):
            f = A[r, k] * inv
            for j in range(k + 1, n):
                A[r, j] -= f * A[k, j]
            b[r] -= f * b[k]
    for k in range(n - 1, -1, -1):
        acc = b[k]
        for j in range(k + 1, n):
            acc -= A[k, j] * b[j]
        b[k] = acc / A[k, k]


def _about(
    Q: FloatArray, p: FloatArray, x: float, y: float, z: float, surface: float, out: FloatArray
) -> None:
    """``out`` = Q (p - P) + P' [m]: ``p`` rotated by ``Q`` about P = (x, y, z) and moved
    down to P' = (x, y, surface)."""
    ex, ey, ez = p[0] - x, p[1] - y, p[2] - z
    out[0] = x + (Q[0, 0] * ex + Q[0, 1] * ey + Q[0, 2] * ez)
    out[1] = y + (Q[1, 0] * ex + Q[1, 1] * ey + Q[1, 2] * ez)
    out[2] = surface + (Q[2, 0] * ex + Q[2, 1] * ey + Q[2, 2] * ez)


def _back(Q: FloatArray, w: FloatArray, K: FloatArray, KB: FloatArray) -> None:
    """A wrench ``w`` (6) and a 6 x 6 ``K`` from the frame of ``Q`` to the world, in place:
    w <- B^T w, K <- B^T K B, B = diag(Q, Q); ``KB`` a work array."""
    for h in range(2):
        a0, a1, a2 = w[3 * h], w[3 * h + 1], w[3 * h + 2]
        for i in range(3):
            w[3 * h + i] = Q[0, i] * a0 + Q[1, i] * a1 + Q[2, i] * a2
    for i in range(6):
        for l in range(6):
            acc = 0.0
            hl = 3 * (l // 3)
            for m in range(3):
                acc += K[i, hl + m] * Q[m, l - hl]
            KB[i, l] = acc
    for i in range(6):
        hi = 3 * (i // 3)
        for l in range(6):
            acc = 0.0
            for m in range(3):
                acc += Q[m, i - hi] * KB[hi + m, l]
            K[i, l] = acc


def _robot_step(
    nb: int, nv: int, dt: float, FJ: FloatArray, FM: FloatArray, FK: FloatArray, FW0: FloatArray, FACC: FloatArray, FTW: FloatArray, FPOS: FloatArray,
    WF: FloatArray, AJ: FloatArray, RJ: FloatArray, FWR: FloatArray, FWV: FloatArray,
    tank: float,
) -> float:  # fmt: skip
    """:func:`mudrft.integrations.mjx.wrench.implicit_wrench` and ``passive_wrench`` (D62-D62d)
    of the feet with ``FPOS[j] >= 0``, the mobility ``WF`` from ``FJ`` and ``FM`` = M^-1 J^T:
    wrenches into ``FWR``, ``W w`` into ``FWV``. Returns the robot's tank after the step [J].
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
            for a in range(6):  # six independent sums, not one chain of additions
                w0 = w1 = w2 = w3 = w4 = w5 = 0.0
                for d in range(nv):
                    x = FJ[i, a, d]
                    w0 += x * FM[j, 0, d]
                    w1 += x * FM[j, 1, d]
                    w2 += x * FM[j, 2, d]
                    w3 += x * FM[j, 3, d]
                    w4 += x * FM[j, 4, d]
                    w5 += x * FM[j, 5, d]
                row = 6 * pi + a
                for c, acc in enumerate((w0, w1, w2, w3, w4, w5)):
                    if i != j or c >= a:  # a diagonal block: its upper half, mirrored
                        WF[row, 6 * pj + c] = acc
                        WF[6 * pj + c, row] = acc
    for i in range(nb):  # A = I - dt K W, row by row; the right side w0 + dt K a
        if FPOS[i] < 0.0:
            continue
        pi = int(FPOS[i])
        for a in range(6):
            row = 6 * pi + a
            for col in range(n):
                AJ[row, col] = 0.0
            for d in range(6):
                f = -dt * FK[i, a, d]
                for col in range(n):
                    AJ[row, col] += f * WF[6 * pi + d, col]
            AJ[row, row] += 1.0
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


@functools.cache
def mujoco_functions() -> tuple[int, int]:
    """Addresses of ``mj_jac`` and ``mj_solveM`` in the MuJoCo library the ``mujoco``
    package ships (``libmujoco.so.*``, ``mujoco.dll`` or ``libmujoco.*.dylib`` next to it)."""
    here = Path(str(_mujoco().__file__)).parent
    found = [p for p in here.iterdir() if p.name.startswith(("libmujoco.", "mujoco.dll"))]
    if not found:
        raise ImportError(f"the MuJoCo library was not found in {here}")
    lib = ctypes.CDLL(str(found[0]))
    jac, solve = (ctypes.cast(f, ctypes.c_void_p).value for f in (lib.mj_jac, lib.mj_solveM))
    return int(jac or 0), int(solve or 0)


def _call(builder: Any, fn: Any, ret: Any, args: list[tuple[Any, Any]]) -> None:
    """Call the C function at address ``fn`` with ``args``: (value, LLVM type) pairs."""
    fnty = ir.FunctionType(ret, [t for _, t in args])
    f = builder.inttoptr(fn, fnty.as_pointer())
    builder.call(
        f, [builder.inttoptr(v, t) if isinstance(t, ir.PointerType) else v for v, t in args]
    )


_VOID_P = ir.IntType(8).as_pointer()
_DOUBLE_P = ir.DoubleType().as_pointer()


@intrinsic  # type: ignore[misc]
def _mj_jac(typingctx: Any, fn: Any, m: Any, d: Any, jacp: Any, jacr: Any, point: Any,
            body: Any) -> Any:  # fmt: skip
    """``mj_jac(m, d, jacp, jacr, point, body)`` at address ``fn``, every argument an int64
    (an address, or the body's id; compiled code only)."""
    sig = nt.void(nt.int64, nt.int64, nt.int64, nt.int64, nt.int64, nt.int64, nt.int64)

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        fn, m, d, jacp, jacr, point, body = args
        i32 = ir.IntType(32)
        _call(builder, fn, ir.VoidType(), [(m, _VOID_P), (d, _VOID_P), (jacp, _DOUBLE_P),
              (jacr, _DOUBLE_P), (point, _DOUBLE_P), (builder.trunc(body, i32), i32)])  # fmt: skip
        return context.get_dummy_value()

    return sig, codegen


@intrinsic  # type: ignore[misc]
def _mj_solve_m(typingctx: Any, fn: Any, m: Any, d: Any, x: Any, n: Any) -> Any:
    """``mj_solveM(m, d, x, x, n)`` at address ``fn``: ``x <- M^-1 x`` for ``n`` rows of nv
    floats at ``x``, in place (compiled code only)."""
    sig = nt.void(nt.int64, nt.int64, nt.int64, nt.int64, nt.int64)

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        fn, m, d, x, n = args
        i32 = ir.IntType(32)
        _call(builder, fn, ir.VoidType(), [(m, _VOID_P), (d, _VOID_P), (x, _DOUBLE_P),
              (x, _DOUBLE_P), (builder.trunc(n, i32), i32)])  # fmt: skip
        return context.get_dummy_value()

    return sig, codegen


#: The address of the passive callback's registry (0: none), read by compiled code through
#: the symbol :data:`REGISTRY_SYMBOL` (an address baked into cached code would go stale).
REGISTRY = ctypes.c_int64(0)
REGISTRY_SYMBOL = "mudrft_mjcb_passive_registry"
llvm.add_symbol(REGISTRY_SYMBOL, ctypes.addressof(REGISTRY))


@intrinsic  # type: ignore[misc]
def _registry(typingctx: Any) -> Any:
    """The value of :data:`REGISTRY` (compiled code only)."""
    sig = nt.int64()

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        module = builder.module
        try:
            cell = module.get_global(REGISTRY_SYMBOL)
        except KeyError:
            cell = ir.GlobalVariable(module, ir.IntType(64), name=REGISTRY_SYMBOL)
            cell.linkage = "external"
        return builder.load(cell)

    return sig, codegen


@intrinsic  # type: ignore[misc]
def _chain(typingctx: Any, fn: Any, m: Any, d: Any) -> Any:
    """Call the MuJoCo callback ``void(const mjModel*, mjData*)`` at address ``fn``
    (compiled code only)."""
    sig = nt.void(nt.int64, nt.int64, nt.int64)

    def codegen(context: Any, builder: Any, signature: Any, args: Any) -> Any:
        fn, m, d = args
        _call(builder, fn, ir.VoidType(), [(m, _VOID_P), (d, _VOID_P)])
        return context.get_dummy_value()

    return sig, codegen


def _borrow(a: FloatArray) -> FloatArray:
    """A view of float64 C-contiguous ``a`` without a reference count; the caller keeps
    ``a`` alive."""
    return carray(_ptr(a.ctypes.data), a.shape)  # type: ignore[call-arg]


def _cut(address: int, shape: tuple[int, ...]) -> tuple[FloatArray, int]:
    """A borrowed float64 view of ``shape`` at ``address``, and the address after it."""
    n = 1
    for k in shape:
        n *= k
    return carray(_ptr(address), shape), address + 8 * n  # type: ignore[call-arg]
