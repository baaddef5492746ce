"""MuJoCo's passive callback (``mjcb_passive``): the compiled coupling inside ``mj_step``,
shared by every coupling through a registry of their ``MjData`` (:data:`.linalg.REGISTRY`).
"""

from __future__ import annotations

import ctypes
import time
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..._jit import jit_callback
from ..._progress import logger
from ..._typing import FloatArray, IndexArray
from ..._validation import MudrftError
from ...terrains.rows import N_STATE
from .compiled import OFFSETS, _f1, _f2, _f3, _i1, _i2, _i3, _kernel
from .linalg import REGISTRY, _chain, _iptr, _ptr, _registry, carray


def clock_size(nb: int) -> int:
    """Length of a robot's ``clock`` row for ``nb`` feet: has a last step, the time of the
    last call [s], the kept has-a-last-step and tank [J], each foot's pose and velocity
    (18), and the state a step changes (``mud``, ``fst``, ``odo``, ``tw_prev``, ``wv_prev``)."""
    return 4 + nb * 18 + nb * (N_STATE + 3 + 5 + 6 + 6)


def _keep(row: FloatArray, at: int, a: FloatArray, back: bool) -> int:
    """Copy ``a`` (nb, w) into ``row[at:]``, or back from it; the index after it."""
    for j in range(a.shape[0]):
        for i in range(a.shape[1]):
            if back:
                a[j, i] = row[at]
            else:
                row[at] = a[j, i]
            at += 1
    return at


def robot_step(p: IndexArray, k: int, now: float) -> int:
    """:func:`_kernel` for robot ``k`` on the arrays packed by :func:`pack`, at MuJoCo's
    time ``now`` [s]; a call again at the same time and state steps again from the state
    before (the same wrench). The number of non-finite wrenches.
    """
    o = OFFSETS
    clock, tank = _f2(p, o[22]), _f1(p, o[19])
    kept = (_f3(p, o[14]), _f3(p, o[15]), _f3(p, o[16]), _f3(p, o[17]), _f3(p, o[18]))
    addr, bodies, nbody = _i2(p, o[0]), _i2(p, o[2]), _i1(p, o[1])[0]
    row = clock[k]
    # the same call again: the same time, and every foot in the same pose and motion
    back = now == row[1]
    row[1] = now
    at = 4
    for q in range(3):
        a = carray(_ptr(addr[k, (0, 1, 3)[q]]), (nbody, (3, 9, 6)[q]))  # type: ignore[call-arg]
        for j in range(bodies.shape[0]):
            for v in a[bodies[j, 0]]:
                back = back and row[at] == v
                row[at] = v
                at += 1
    if back:
        row[0], tank[k] = row[2], row[3]
    else:
        row[2], row[3] = row[0], tank[k]
    for a in kept:
        at = _keep(row, at, a[k], back)
    return _kernel(
        _i2(p, o[0]), _i1(p, o[1]), _i2(p, o[2]), _f2(p, o[3]), _f2(p, o[4]), _i1(p, o[5]),
        _f3(p, o[6]), _i1(p, o[7]), _f2(p, o[8]), _f3(p, o[9]), _f2(p, o[10]), _f2(p, o[11]),
        _f2(p, o[12]), _f1(p, o[13]), kept[0], kept[1], kept[2], kept[3], kept[4], tank,
        _f3(p, o[20]), _f2(p, o[21]), clock, _i3(p, o[23]), _f2(p, o[24]), _f3(p, o[25]), k,
    )  # fmt: skip


#: Columns of a row of the callback's registry (:func:`passive`): the ``mjData``'s
#: address, the packed arrays' address and length, the robot's index, ``time``'s address.
N_REGISTRY = 5


def passive(m: int, d: int) -> None:
    """The coupling step of the robot whose ``mjData`` is at ``d``, then the callback
    replaced. The registry: (count, chained callback's address), ``count`` rows."""
    r: int = _registry()  # type: ignore[call-arg]
    if r == 0:
        return
    head = carray(_iptr(r), (2,))  # type: ignore[call-arg]
    rows = carray(_iptr(r + 16), (head[0], N_REGISTRY))  # type: ignore[call-arg]
    for i in range(head[0]):
        if rows[i, 0] == d:
            p = carray(_iptr(rows[i, 1]), (rows[i, 2],))  # type: ignore[call-arg]
            t = carray(_ptr(rows[i, 4]), (1,))[0] if rows[i, 4] != 0 else 0.0  # type: ignore[call-arg]
            robot_step(p, rows[i, 3], t)
            break
    if head[1] != 0:
        _chain(head[1], m, d)


#: The compiled callback's ctypes object, as given to ``mujoco.set_mjcb_passive``.
_CALLBACK: list[Any] = [None]
#: mjData address -> its registry row, and the coupling that owns it (held alive).
_ROWS: dict[int, tuple[int, ...]] = {}
_OWNERS: dict[int, Any] = {}
#: The callback chained to and the last registries published (another thread may read one).
_CHAINED: list[Any] = [None]
_PUBLISHED: list[IndexArray] = []


def callback() -> Any:
    """:func:`passive` compiled as a C callback ``void(const mjModel*, mjData*)`` (cached
    on disk), as a ctypes function; logged (INFO) the first time in a process."""
    if _CALLBACK[0] is None:
        logger.info(
            "compiling the MuJoCo coupling with numba (about 15 s the first time on a "
            "machine, then loaded from numba's cache on disk in about a second)"
        )
        start = time.perf_counter()
        _CALLBACK[0] = jit_callback(passive).ctypes
        logger.info("compiled the MuJoCo coupling in %.1f s", time.perf_counter() - start)
    return _CALLBACK[0]


def install(mj: Any) -> None:
    """Make the compiled coupling MuJoCo's passive callback, chained to the one set before."""
    ours = callback()
    current = mj.get_mjcb_passive()
    if current is ours:
        return
    compiled = ctypes._CFuncPtr  # type: ignore[attr-defined]  # any ctypes function
    if current is not None and not isinstance(current, compiled):
        raise MudrftError(
            f"mujoco's mjcb_passive is a Python callable ({current!r}); the mud coupling "
            "runs in that callback and can chain only to a compiled one (a ctypes function "
            "pointer, such as a numba cfunc's .ctypes): unset it with "
            "mujoco.set_mjcb_passive(None)"
        )
    _CHAINED[0] = current
    _publish()
    mj.set_mjcb_passive(ours)


def _publish() -> None:
    """Give the compiled callback a new registry of :data:`_ROWS`."""
    chained = _CHAINED[0]
    address = 0 if chained is None else int(ctypes.cast(chained, ctypes.c_void_p).value or 0)
    reg = np.array(
        [len(_ROWS), address, *(v for row in _ROWS.values() for v in row)], dtype=np.int64
    )
    _PUBLISHED[:] = [*_PUBLISHED[-7:], reg]
    REGISTRY.value = int(reg.ctypes.data)


def register(rows: Sequence[tuple[int, ...]], mine: list[tuple[int, ...]], owner: Any) -> None:
    """Replace the rows ``mine`` of ``owner`` (a coupling) with ``rows``; publish if changed."""
    if list(rows) == mine and all(_ROWS.get(r[0]) == r for r in rows):
        return
    unregister(mine, publish=False)
    for r in rows:
        _ROWS[r[0]], _OWNERS[r[0]] = r, owner
    mine[:] = list(rows)
    _publish()


def unregister(mine: list[tuple[int, ...]], publish: bool = True) -> None:
    """Remove a coupling's rows (where another coupling has not taken the MjData since)."""
    for r in mine:
        if _ROWS.get(r[0]) == r:
            del _ROWS[r[0]], _OWNERS[r[0]]
    mine.clear()
    if publish:
        _publish()
