"""The FEM pair kernel with numba ``prange`` (optional), bit-identical to the serial one.

A parallel variant of :func:`kinetic_fem.operators.fem_pair_fast.collision_constant`
(P2/P3, a constant coefficient, the reduced bracket) whose results, pair and loss
moments included, are **bit-identical** to the serial kernel's: every entry of the
residual, the Jacobian and the moments receives the same terms in the same order.

How.  The elements are split into one block per thread; a thread *owns* the dofs of its
block (a vertex shared by two blocks belongs to the lower one).  The outer points are
taken in chunks, and each chunk in two parallel passes (pass 2 of a chunk runs with pass 1
of the next, so that the threads meet once per chunk):

1. Each thread visits, for every outer point of the chunk in order, the inner pieces whose
   :math:`y` lies in its block (and the first element past it, for the shared vertex;
   :func:`~kinetic_fem.operators.fem_pair_sums.breaks_between`), forms their sums (the
   serial kernel's loops, :func:`~kinetic_fem.operators.fem_pair_fast.pair_sweep`) and
   adds the Jacobian terms of the columns it owns (the pieces' :math:`y` dofs and the
   rank-``k`` update of :math:`x`'s rows) at once, in the serial order.  What belongs
   to rows of other blocks (the :math:`x'` sums, the terms of :math:`\\sum c` and of
   the moments) is kept per piece in a buffer.
2. Each thread adds the buffered sums to the residual entries it owns, outer point after
   outer point and piece after piece (the transposed :math:`P(x)` columns of the
   Jacobian with them); the first thread sums the moments.

With one thread the serial kernel runs (the two passes would only add work; see
``benchmarks/archive/results/prange_quick.md``).  Off by default: set the environment variable
``KINETIC_FEM_PARALLEL=1`` (read at each call, :func:`parallel_enabled`); numba's
thread count (``NUMBA_NUM_THREADS`` or ``numba.set_num_threads``) sets the threads, and
``OMP_WAIT_POLICY=passive`` (or ``NUMBA_THREADING_LAYER=workqueue``) keeps OpenMP's
waiting threads from spinning, which on a loaded machine made it many times slower.
:func:`collision` is the entry point of
:class:`~kinetic_fem.operators.fem_discretisation.FEMDiscretisation`.
"""

from __future__ import annotations

import os

import numba
import numpy as np

from .._jit import jit
from ..model.restitution import CONSTANT, VISCOELASTIC
from .fem_kernels import collision_operator
from .fem_pair_breaks import GRADING_LEVELS, kernel_graded
from .fem_pair_fast import finish_collision, pair_sweep
from .fem_pair_sums import visited_points, work_arrays

# numba caches this module's kernels with kernel_rate compiled in: edit this file too when
# kernel_rate changes (a stale cache keeps the old rule; gamma = 1/2 by sqrt since issue 16)
# (and when fem_pair_fast.pair_sweep or fem_pair_sums change: numba checks only this file)
__all__ = ["collision", "collision_constant_parallel", "parallel_enabled", "block_owners",
           "pass_rows", "PARALLEL_ENV", "CHUNK_VALUES"]

PARALLEL_ENV = "KINETIC_FEM_PARALLEL"
"""Environment variable that switches the parallel pair kernel on (``1``)."""
CHUNK_VALUES = 1 << 19
"""Buffered values per chunk of outer points (about 4 MB of doubles touched; on two idle
cores 2 MB chunks measured 0-4 % slower with passive waiting, 8 MB no faster, and on one
thread 8 MB cost 3-7 % more CPU, 32 MB up to 2x)."""


@jit
def block_owners(dofs: np.ndarray, n_dof: int, threads: int
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Element blocks, the owning thread of each dof and the runs of one owner.

    Parameters
    ----------
    dofs : ndarray of int, shape (n_el, k)
        Dofs of each element (elements in the order of the vertices).
    n_dof : int
        Number of dofs.
    threads : int
        Number of blocks.

    Returns
    -------
    first : ndarray of int, shape (threads + 1,)
        Block ``p`` holds the elements ``first[p] <= e < first[p + 1]``.
    owner : ndarray of int, shape (n_dof,)
        The block of each dof (a vertex shared by two blocks: the lower).
    runs : ndarray of int, shape (n_runs, 3)
        ``lo, hi, owner`` of each run of consecutive dofs of one owner.
    """
    n_el = dofs.shape[0]
    first = np.empty(threads + 1, dtype=np.int64)
    for p in range(threads + 1):
        first[p] = p * n_el // threads
    owner = np.empty(n_dof, dtype=np.int64)
    for p in range(threads - 1, -1, -1):  # a shared vertex goes to the lower block
        for e in range(first[p + 1] - 1, first[p] - 1, -1):
            for i in range(dofs.shape[1]):
                owner[dofs[e, i]] = p
    n_runs = 1
    for d in range(1, n_dof):
        if owner[d] != owner[d - 1]:
            n_runs += 1
    runs = np.empty((n_runs, 3), dtype=np.int64)  # lo, hi, owner
    r = 0
    runs[0, 0] = 0
    for d in range(1, n_dof):
        if owner[d] != owner[d - 1]:
            runs[r, 1] = d
            runs[r, 2] = owner[d - 1]
            r += 1
            runs[r, 0] = d
    runs[r, 1] = n_dof
    runs[r, 2] = owner[n_dof - 1]
    return first, owner, runs


@jit
def _span(ids: np.ndarray, t: int, g: int, n: int, col: int, e: int) -> int:
    """The first piece of block ``g`` of outer point ``t`` with ``ids[t, g, s, col] >= e``."""
    lo = 0
    hi = n
    while lo < hi:
        mid = (lo + hi) // 2
        if ids[t, g, mid, col] < e:
            lo = mid + 1
        else:
            hi = mid
    return lo


@jit(inline="always")
def _rows(p: int, t: int, g: int, s_lo: int, s_hi: int, full_lo: int, full_hi: int,
          dofs: np.ndarray, owner: np.ndarray, ids: np.ndarray, vals: np.ndarray,
          with_jacobian: bool, res: np.ndarray, bq: np.ndarray) -> None:
    """The pieces ``s_lo <= s < s_hi`` of block ``g`` of outer point ``t`` into the owned
    residual (and ``bq``) entries, in the serial order (no ownership test on the block's
    inner elements ``full_lo ... full_hi``)."""
    k = dofs.shape[1]
    for s in range(s_lo, s_hi):
        e1 = ids[t, g, s, 0]
        ey = ids[t, g, s, 1]
        all1 = full_lo <= e1 <= full_hi
        ally = full_lo <= ey <= full_hi
        for i in range(k):
            d = dofs[e1, i]
            if all1 or owner[d] == p:
                v = 2.0 * vals[t, g, s, i]
                res[d] += v
                if with_jacobian:
                    bq[d] += v
        for i in range(k):
            d = dofs[ey, i]
            if ally or owner[d] == p:
                v = vals[t, g, s, k + i]
                res[d] -= v
                if with_jacobian:
                    bq[d] -= v


@jit
def pass_rows(p: int, visit: np.ndarray, m: int, dofs: np.ndarray, eq: np.ndarray,
               n_ref: int, with_jacobian: bool, moments: bool, first: np.ndarray,
               owner: np.ndarray, runs: np.ndarray, n_p: np.ndarray, phq: np.ndarray,
               ids: np.ndarray, vals: np.ndarray, res: np.ndarray, bq: np.ndarray,
               jac_x: np.ndarray, chains: np.ndarray) -> None:
    """Pass 2 for thread ``p`` over the outer points ``visit[:m]`` (module text).

    Parameters
    ----------
    p : int
        The thread (block).
    visit : ndarray of int
        The chunk's outer points.
    m : int
        Their number.
    dofs, eq : ndarray of int
        Dofs of each element, element of each outer point.
    n_ref : int
        Reference points per piece.
    with_jacobian, moments : bool
        Whether ``bq`` and ``jac_x``, and the moments (thread 0), are summed.
    first, owner, runs : ndarray of int
        As returned by :func:`block_owners`.
    n_p, phq, ids, vals : ndarray
        Pass 1's pieces, shape values and sums
        (:func:`~kinetic_fem.operators.fem_pair_fast.pair_sweep`).
    res, bq, jac_x : ndarray
        Residual, per-point work vector and transposed x-columns (owned entries).
    chains : ndarray, shape (2,)
        Pair and loss moments (summed on by thread 0).
    """
    k = dofs.shape[1]
    n_el = dofs.shape[0]
    e_lo = first[p]
    e_hi = min(first[p + 1], n_el - 1)
    full_lo = e_lo + 1 if p > 0 else e_lo  # the elements all of whose dofs are owned
    full_hi = first[p + 1] - 1
    for t in range(m):
        ex = eq[visit[t]]
        if with_jacobian:
            for r in range(runs.shape[0]):
                if runs[r, 2] == p:
                    bq[runs[r, 0]:runs[r, 1]] = 0.0
        # the pieces that reach an owned dof through x' or y: two spans per block
        for g in range(n_p.shape[1]):
            n = n_p[t, g]
            a0 = _span(ids, t, g, n, 0, e_lo)
            a1 = _span(ids, t, g, n, 0, e_hi + 1)
            b0 = _span(ids, t, g, n, 1, e_lo)
            b1 = _span(ids, t, g, n, 1, e_hi + 1)
            if a0 > b0:
                a0, a1, b0, b1 = b0, b1, a0, a1
            _rows(p, t, g, a0, a1, full_lo, full_hi, dofs, owner, ids, vals, with_jacobian,
                  res, bq)
            _rows(p, t, g, max(a1, b0), b1, full_lo, full_hi, dofs, owner, ids, vals,
                  with_jacobian, res, bq)
        mine = False
        for i in range(k):
            mine = mine or owner[dofs[ex, i]] == p
        if mine:
            c_total = 0.0
            for g in range(n_p.shape[1]):
                for s in range(n_p[t, g]):
                    for r in range(n_ref):
                        c_total += vals[t, g, s, 2 * k + r]
            for i in range(k):
                d = dofs[ex, i]
                if owner[d] == p:
                    res[d] -= c_total * phq[t, i]
                    if with_jacobian:
                        bq[d] -= c_total * phq[t, i]
        if with_jacobian:  # every row depends on u through P(x): transposed columns
            for j in range(k):
                djx = dofs[ex, j]
                for r in range(runs.shape[0]):
                    if runs[r, 2] == p:
                        for row in range(runs[r, 0], runs[r, 1]):
                            jac_x[djx, row] += bq[row] * phq[t, j]
        if moments and p == 0:
            for g in range(n_p.shape[1]):
                for s in range(n_p[t, g]):
                    for r in range(n_ref):
                        chains[0] += vals[t, g, s, 2 * k + n_ref + r]
                        chains[1] += vals[t, g, s, 2 * k + 2 * n_ref + r]


@jit(parallel=True)
def collision_constant_parallel(verts: np.ndarray, dofs: np.ndarray, coef: np.ndarray,
                                xq: np.ndarray, wq: np.ndarray, eq: np.ndarray,
                                ref_x: np.ndarray, ref_w: np.ndarray, alpha: float,
                                density: float, with_jacobian: bool, energy_power: int,
                                gamma: float, graded: bool, threads: int,
                                mirror: np.ndarray | None, chunk_values: int = CHUNK_VALUES
                                ) -> tuple[np.ndarray, np.ndarray, float, float]:
    """:func:`~kinetic_fem.operators.fem_pair_fast.collision_constant` on ``threads``
    threads (the module text); bit-identical results.

    Parameters
    ----------
    verts, dofs, coef, xq, wq, eq, ref_x, ref_w, alpha, density, with_jacobian
        As for :func:`~kinetic_fem.operators.fem_kernels.collision_operator`.
    energy_power, gamma, graded, mirror
        As for :func:`~kinetic_fem.operators.fem_pair_fast.collision_constant`.
    threads : int
        Element blocks (one per thread; 1 runs the two passes on one thread).
    chunk_values : int
        Buffered values per chunk of outer points.
    """
    n_dof = coef.size
    k = dofs.shape[1]
    n_ref = ref_x.size
    moments = energy_power >= 0
    n_val = 2 * k + (3 if moments else 1) * n_ref
    res, jac, bq, cy, jac_x = work_arrays(n_dof, with_jacobian)
    threads = max(1, min(threads, dofs.shape[0]))
    first, owner, runs = block_owners(dofs, n_dof, threads)
    n_buf = 3 * verts.size + 3  # merge_breaks' buffer; without preimages of x: 2 nv + 1
    n_max = 2 * verts.size + 2 * (GRADING_LEVELS + 1)
    visit = visited_points(xq, mirror)
    n_visit = visit.size
    # a block's segment holds about its share of the n_max pieces of a point
    chunk = max(1, min(n_visit, chunk_values // (n_max * n_val)))
    n_chunks = (n_visit + chunk - 1) // chunk
    # per outer point and block; two chunks: pass 2 of one runs with pass 1 of the next
    ids = np.empty((2, chunk, threads, n_max, 2), dtype=np.int64)
    vals = np.empty((2, chunk, threads, n_max, n_val))
    phq = np.empty((2, chunk, k))
    n_p = np.empty((2, chunk, threads), dtype=np.int64)
    bufs = np.empty((threads, n_buf))
    starts = np.empty((threads, n_max))
    lengths = np.empty((threads, n_max))
    scratch = np.empty((threads, 3 * n_ref))
    chains = np.zeros(2)
    for c in range(n_chunks + 1):  # one synchronisation per chunk
        for p in numba.prange(threads):
            if c > 0:
                b = (c - 1) % 2
                done = visit[(c - 1) * chunk:min(c * chunk, n_visit)]
                pass_rows(p, done, done.size, dofs, eq, n_ref, with_jacobian, moments, first,
                          owner, runs, n_p[b], phq[b], ids[b], vals[b], res, bq, jac_x, chains)
            if c < n_chunks:
                b = c % 2
                todo = visit[c * chunk:min((c + 1) * chunk, n_visit)]
                pair_sweep(todo, todo.size, verts, dofs, coef, xq, wq, eq, ref_x, ref_w, alpha,
                           density, with_jacobian, energy_power, gamma, graded, p, first,
                           owner, runs, bufs[p], starts[p], lengths[p], scratch[p], n_p[b],
                           phq[b], ids[b], vals[b], res, jac, bq, cy, jac_x, chains)
    return finish_collision(res, jac, jac_x, with_jacobian, chains[0], chains[1], mirror)


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
        Use :func:`collision_constant_parallel` on numba's threads (P2/P3, constant
        coefficient, reduced bracket; one thread: the serial kernel); default
        :func:`parallel_enabled`.

    Returns
    -------
    tuple
        As :func:`~kinetic_fem.operators.fem_kernels.collision_operator`.
    """
    if parallel is None:
        parallel = parallel_enabled()
    if parallel and order >= 2 and code == CONSTANT and not symmetric:
        graded = bool(kernel_graded(kernel)) or code == VISCOELASTIC
        threads = numba.get_num_threads()
        if threads > 1:  # one thread: the serial call below
            return collision_constant_parallel(verts, dofs, coef, xq, wq, eq, ref_x, ref_w,
                                               alpha, density, with_jacobian, energy_power,
                                               kernel, graded, threads, mirror)
    args = (verts, dofs, order, coef, xq, wq, eq, ref_x, ref_w, alpha, density,
            with_jacobian, energy_power, symmetric, kernel, code, p0, p1, speed_scale, b_lo)
    return collision_operator(*args, mirror) if mirror is not None else \
        collision_operator(*args)
