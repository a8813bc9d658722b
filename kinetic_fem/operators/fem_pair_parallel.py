"""The FEM pair kernel with numba ``prange`` over the outer points (optional).

A parallel variant of :func:`kinetic_fem.operators.fem_pair_fast.collision_constant`
(P2/P3, a constant coefficient, the reduced bracket) whose results are **bit-identical**
to the serial kernel's: the outer points are taken in chunks; within a chunk each
thread forms the sums of its outer points' inner pieces
(:func:`~kinetic_fem.operators.fem_pair_sums.outer_point_sums`,
the serial kernel's arithmetic in the serial kernel's order) into a private buffer,
and then the chunk's sums are added to the residual and Jacobian one outer point after
the other, in the serial order, the threads splitting the entries between them (each
owns a range of dofs: :func:`scatter_outer_point`).  The pair moments are
summed across outer points in one running sum, so a call that asks for them runs the
serial kernel.

Off by default: set the environment variable ``KINETIC_FEM_PARALLEL=1`` (read at each
call, :func:`parallel_enabled`); numba's thread count (``NUMBA_NUM_THREADS`` or
``numba.set_num_threads``) sets the threads.  :func:`collision` is the entry point of
:class:`~kinetic_fem.operators.fem_discretisation.FEMDiscretisation`: the serial
:func:`~kinetic_fem.operators.fem_kernels.collision_operator` unless the setting is on
and the fast path applies.  ``benchmarks/bench_prange.py`` measures it.
"""

from __future__ import annotations

import os

import numba
import numpy as np

from .._jit import jit
from ..model.restitution import CONSTANT, VISCOELASTIC
from .fem_kernels import collision_operator
from .fem_pair_breaks import GRADING_LEVELS, kernel_graded
from .fem_pair_fast import finish_collision
from .fem_pair_sums import outer_point_sums

# numba caches this module's kernels with kernel_rate compiled in: edit this file too when
# kernel_rate changes (a stale cache keeps the old rule; gamma = 1/2 by sqrt since issue 16)
__all__ = ["collision", "collision_constant_parallel", "scatter_outer_point",
           "parallel_enabled", "PARALLEL_ENV", "CHUNK_VALUES"]

PARALLEL_ENV = "KINETIC_FEM_PARALLEL"
"""Environment variable that switches the parallel pair kernel on (``1``)."""
CHUNK_VALUES = 1 << 18
"""Per-piece sums buffered per chunk of outer points (2 MB of doubles, so that they stay in
cache: measured at 703 nodes, one thread, Jacobian 31 ms with 2 to 64 outer points per
chunk, 55 ms with all of them in one chunk)."""


@jit
def scatter_outer_point(dofs: np.ndarray, ex: int, phx: np.ndarray, n_p: int, c_total: float,
                        ids: np.ndarray, vals: np.ndarray, with_jacobian: bool,
                        res: np.ndarray, jac: np.ndarray, bq: np.ndarray, cy: np.ndarray,
                        jac_x: np.ndarray, lo: int, hi: int) -> None:
    """Add the sums of one outer point
    (:func:`~kinetic_fem.operators.fem_pair_sums.outer_point_sums`) to the entries owned
    (dofs ``lo <= d < hi``: of the residual and the work vectors, the columns of the
    Jacobian), each entry's terms in the order of the serial kernel.

    Parameters
    ----------
    dofs : ndarray of int
        Dofs of each element.
    ex : int
        The element of the outer point.
    phx, n_p, c_total, ids, vals
        The outer point's shape values, pieces, total rate and per-piece sums.
    with_jacobian : bool
        Whether ``jac``, ``bq``, ``cy`` and ``jac_x`` are assembled.
    res, jac, bq, cy, jac_x : ndarray
        Residual, Jacobian, the per-point work vectors and the transposed x-columns
        (as in :func:`~kinetic_fem.operators.fem_pair_fast.collision_constant`).
    lo, hi : int
        The owned dofs (``0, N``: all); threads with disjoint ranges never write the
        same entry.
    """
    k = dofs.shape[1]
    packed = np.empty((k, k), dtype=np.int64)  # phi_i(y) phi_j(y): upper triangle by rows
    pos = 2 * k + k * k
    for i in range(k):
        for j in range(i, k):
            packed[i, j] = pos
            packed[j, i] = pos
            pos += 1
    if with_jacobian:
        bq[lo:hi] = 0.0
        cy[lo:hi] = 0.0
    for s in range(n_p):
        e1 = ids[s, 0]
        ey = ids[s, 1]
        for i in range(k):
            d = dofs[e1, i]
            if lo <= d < hi:
                res[d] += 2.0 * vals[s, i]
        for i in range(k):
            d = dofs[ey, i]
            if lo <= d < hi:
                res[d] -= vals[s, k + i]
        if not with_jacobian:
            continue
        for i in range(k):
            d = dofs[e1, i]
            if lo <= d < hi:
                bq[d] += 2.0 * vals[s, i]
        for i in range(k):
            d = dofs[ey, i]
            if lo <= d < hi:
                bq[d] -= vals[s, k + i]
        for i in range(k):
            d = dofs[ey, i]
            if lo <= d < hi:
                cy[d] += vals[s, k + i]
        # by owned column; an entry in both blocks gets the x' term first, as serially
        for j in range(k):
            dj = dofs[ey, j]
            if lo <= dj < hi:
                for i in range(k):
                    jac[dofs[e1, i], dj] += 2.0 * vals[s, 2 * k + k * i + j]
                for i in range(k):
                    jac[dofs[ey, i], dj] -= vals[s, packed[i, j]]
    for i in range(k):
        d = dofs[ex, i]
        if lo <= d < hi:
            res[d] -= c_total * phx[i]
    if with_jacobian:
        for i in range(k):
            dix = dofs[ex, i]
            if lo <= dix < hi:
                bq[dix] -= c_total * phx[i]
            # the -phi_i(x) rows depend on u through P(y)
            for col in range(lo, hi):
                jac[dix, col] -= phx[i] * cy[col]
        # every row depends on u through P(x): the columns of x's element, kept
        # transposed (contiguous) and added once at the end
        for j in range(k):
            djx = dofs[ex, j]
            for row in range(lo, hi):
                jac_x[djx, row] += bq[row] * phx[j]


@jit(parallel=True)
def collision_constant_parallel(verts: np.ndarray, dofs: np.ndarray, coef: np.ndarray,
                                xq: np.ndarray, wq: np.ndarray, eq: np.ndarray,
                                ref_x: np.ndarray, ref_w: np.ndarray, alpha: float,
                                density: float, with_jacobian: bool, gamma: float,
                                graded: bool, threads: int, mirror: np.ndarray | None,
                                chunk_values: int = CHUNK_VALUES
                                ) -> tuple[np.ndarray, np.ndarray, float, float]:
    """:func:`~kinetic_fem.operators.fem_pair_fast.collision_constant` without the pair
    moments (returned as 0), the outer points in parallel; bit-identical results.

    Parameters
    ----------
    verts, dofs, coef, xq, wq, eq, ref_x, ref_w, alpha, density, with_jacobian
        As for :func:`~kinetic_fem.operators.fem_kernels.collision_operator`.
    gamma, graded, mirror
        As for :func:`~kinetic_fem.operators.fem_pair_fast.collision_constant`.
    threads : int
        numba's thread count (chunks of outer points hold at least two per thread).
    """
    n_dof = coef.size
    k = dofs.shape[1]
    n_val = 21 if k == 3 else 34
    res = np.zeros(n_dof)
    jac = np.zeros((n_dof, n_dof)) if with_jacobian else np.zeros((1, 1))
    bq = np.zeros(n_dof) if with_jacobian else np.zeros(1)
    cy = np.zeros(n_dof) if with_jacobian else np.zeros(1)
    jac_x = np.zeros((n_dof, n_dof)) if with_jacobian else np.zeros((1, 1))
    n_buf = 3 * verts.size + 3
    n_max = n_buf + 2 * (GRADING_LEVELS + 1)
    visit = np.empty(xq.size, dtype=np.int64)
    n_visit = 0
    for q in range(xq.size):
        x = xq[q]
        if mirror is not None and x <= 0.0:
            if x == 0.0:
                raise ValueError("mirror needs outer points off v = 0 (a vertex at 0)")
            continue
        visit[n_visit] = q
        n_visit += 1
    chunk = max(2 * threads, min(n_visit, chunk_values // (n_max * n_val)))
    chunk = max(1, min(chunk, n_visit))
    ids = np.empty((chunk, n_max, 2), dtype=np.int64)
    vals = np.empty((chunk, n_max, n_val))
    phx = np.empty((chunk, k))
    bufs = np.empty((chunk, n_buf))
    starts = np.empty((chunk, n_max))
    lengths = np.empty((chunk, n_max))
    n_p = np.empty(chunk, dtype=np.int64)
    c_total = np.empty(chunk)
    for first in range(0, n_visit, chunk):
        m = min(chunk, n_visit - first)
        for t in numba.prange(m):
            out = outer_point_sums(visit[first + t], verts, dofs, coef, xq, wq, eq, ref_x,
                                   ref_w, alpha, density, with_jacobian, -1, gamma, graded,
                                   bufs[t], starts[t], lengths[t], phx[t], ids[t], vals[t],
                                   0.0, 0.0)
            n_p[t] = out[0]
            c_total[t] = out[1]
        for p in numba.prange(threads):  # disjoint dofs: each entry's terms in serial order
            lo = p * n_dof // threads
            hi = (p + 1) * n_dof // threads
            for t in range(m):
                scatter_outer_point(dofs, eq[visit[first + t]], phx[t], n_p[t], c_total[t],
                                    ids[t], vals[t], with_jacobian, res, jac, bq, cy, jac_x,
                                    lo, hi)
    return finish_collision(res, jac, jac_x, with_jacobian, 0.0, 0.0, mirror)


def parallel_enabled() -> bool:
    """Whether :data:`PARALLEL_ENV` switches the parallel pair kernel on (``"1"``)."""
    return os.environ.get(PARALLEL_ENV, "") == "1"


def collision(verts: np.ndarray, dofs: np.ndarray, order: int, coef: np.ndarray,
              xq: np.ndarray, wq: np.ndarray, eq: np.ndarray, ref_x: np.ndarray,
              ref_w: np.ndarray, alpha: float, density: float, with_jacobian: bool,
              energy_power: int, symmetric: bool, kernel: float | tuple[int, float],
              code: int, p0: float, p1: float, speed_scale: float, b_lo: float,
              mirror: np.ndarray | None = None, *, parallel: bool | None = None
              ) -> tuple[np.ndarray, np.ndarray, float, float]:
    """:func:`~kinetic_fem.operators.fem_kernels.collision_operator`, in parallel where
    that is bit-identical and switched on.

    Parameters
    ----------
    verts, dofs, order, coef, xq, wq, eq, ref_x, ref_w, alpha, density, with_jacobian
        As for :func:`~kinetic_fem.operators.fem_kernels.collision_operator`.
    energy_power, symmetric, kernel, code, p0, p1, speed_scale, b_lo, mirror
        As there.
    parallel : bool, optional
        Use :func:`collision_constant_parallel` (P2/P3, constant coefficient, reduced
        bracket, no moments: ``energy_power < 0``); default :func:`parallel_enabled`.

    Returns
    -------
    tuple
        As :func:`~kinetic_fem.operators.fem_kernels.collision_operator`.
    """
    if parallel is None:
        parallel = parallel_enabled()
    if parallel and order >= 2 and code == CONSTANT and not symmetric and energy_power < 0:
        graded = bool(kernel_graded(kernel)) or code == VISCOELASTIC
        return collision_constant_parallel(verts, dofs, coef, xq, wq, eq, ref_x, ref_w, alpha,
                                           density, with_jacobian, kernel, graded,
                                           numba.get_num_threads(), mirror)
    args = (verts, dofs, order, coef, xq, wq, eq, ref_x, ref_w, alpha, density,
            with_jacobian, energy_power, symmetric, kernel, code, p0, p1, speed_scale, b_lo)
    return collision_operator(*args, mirror) if mirror is not None else \
        collision_operator(*args)
