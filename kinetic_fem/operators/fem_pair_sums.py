"""Small pieces of the FEM pair kernels (serial and parallel), around their loops.

:func:`point_pieces` starts an outer point (shape values, :math:`P(x)`, the inner
pieces), :func:`locate` walks the sorted vertices to a point's element,
:func:`close_point` adds an outer point's own terms (serial kernel) and
:func:`finish_collision` the transposed :math:`P(x)` columns and, for even sums, the
mirrored half.  The loops are :func:`kinetic_fem.operators.fem_pair_fast.pair_sweep`.
"""

from __future__ import annotations

import numpy as np

from .._jit import jit
from .fem_pair_breaks import merge_breaks, pieces

__all__ = ["locate", "breaks_between", "point_pieces", "close_point", "finish_collision",
           "visited_points", "work_arrays"]


@jit
def locate(verts: np.ndarray, e: int, x: float) -> int:
    """Walk forward from element ``e`` to the element containing ``x``.

    Parameters
    ----------
    verts : ndarray
        Sorted vertices.
    e : int
        Start element (at or before the answer).
    x : float
        The point.
    """
    n_el = verts.size - 1
    while e < n_el - 1 and verts[e + 1] <= x:
        e += 1
    return e


@jit
def visited_points(xq: np.ndarray, mirror: np.ndarray | None) -> np.ndarray:
    """The outer points a kernel visits, in order: all, or with ``mirror`` (even sums)
    those at :math:`v > 0`.

    Parameters
    ----------
    xq : ndarray
        The outer quadrature points.
    mirror : ndarray of int, optional
        The dof at :math:`-v` of each dof.
    """
    visit = np.empty(xq.size, dtype=np.int64)
    m = 0
    for q in range(xq.size):
        x = xq[q]
        if mirror is not None and x <= 0.0:
            if x == 0.0:
                raise ValueError("mirror needs outer points off v = 0 (a vertex at 0)")
            continue
        visit[m] = q
        m += 1
    return visit[:m]


@jit
def work_arrays(n_dof: int, with_jacobian: bool
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Zeroed residual, Jacobian, per-point work vectors ``bq``, ``cy`` and transposed
    x-columns (placeholders of size 1 without the Jacobian).

    Parameters
    ----------
    n_dof : int
        Number of dofs.
    with_jacobian : bool
        Whether the Jacobian is assembled.
    """
    res = np.zeros(n_dof)
    jac = np.zeros((n_dof, n_dof)) if with_jacobian else np.zeros((1, 1))
    bq = np.zeros(n_dof) if with_jacobian else np.zeros(1)
    cy = np.zeros(n_dof) if with_jacobian else np.zeros(1)
    jac_x = np.zeros((n_dof, n_dof)) if with_jacobian else np.zeros((1, 1))
    return res, jac, bq, cy, jac_x


@jit
def breaks_between(verts: np.ndarray, x: float, a: float, b: float, v_lo: int, v_hi: int,
                   buf: np.ndarray) -> int:
    """The breaks of :func:`~kinetic_fem.operators.fem_pair_breaks.merge_breaks` (without
    the second preimages) from ``verts[v_lo]`` to ``verts[v_hi]``: the same values in the
    same order, found without merging the rest; returns their count.

    Parameters
    ----------
    verts : ndarray
        Sorted vertices.
    x, a, b : float
        The outer point and :math:`x' = a x + b y`.
    v_lo, v_hi : int
        The vertices that bound the range.
    buf : ndarray
        Out: the breaks.
    """
    y_lo = verts[v_lo]
    y_hi = verts[v_hi]
    lo = verts[0]
    hi = verts[-1]
    nv = verts.size
    inf = np.inf
    i1 = v_lo
    i2 = 0  # the first preimage at or above y_lo (they ascend with the vertex)
    top = nv
    while i2 < top:
        mid = (i2 + top) // 2
        if (verts[mid] - a * x) / b < y_lo:
            i2 = mid + 1
        else:
            top = mid
    done4 = not x >= y_lo
    n = 0
    while True:
        c1 = verts[i1] if i1 < nv else inf
        c2 = (verts[i2] - a * x) / b if i2 < nv else inf
        c4 = inf if done4 else x
        m = min(min(c1, c2), min(inf, c4))
        if m == inf or m > y_hi:
            break
        if m == c1:
            i1 += 1
        elif m == c2:
            i2 += 1
        else:
            done4 = True
        if m >= lo and m <= hi:
            buf[n] = m
            n += 1
    return n


@jit
def point_pieces(x: float, ex: int, verts: np.ndarray, dofs: np.ndarray, coef: np.ndarray,
                 a: float, b: float, scale: float, graded: bool, buf: np.ndarray,
                 starts: np.ndarray, lengths: np.ndarray, phx: np.ndarray, e_lo: int = -1,
                 e_hi: int = -1) -> tuple[int, float]:
    """Shape values at the outer point ``x`` (into ``phx``), :math:`P(x)` and the inner
    pieces (into ``starts``, ``lengths``); returns their number and :math:`P(x)`.

    Parameters
    ----------
    x : float
        The outer point.
    ex : int
        Its element.
    verts, dofs, coef : ndarray
        Vertices, dofs of each element (3 or 4 columns: P2, P3), coefficients of
        :math:`\\ln P`.
    a, b : float
        :math:`x' = a x + b y`.
    scale : float
        Length of the interval.
    graded : bool
        As for :func:`~kinetic_fem.operators.fem_pair_breaks.pieces`.
    buf, starts, lengths, phx : ndarray
        Work and out arrays.
    e_lo, e_hi : int
        Only the pieces in the elements ``e_lo ... e_hi`` (default: all).
    """
    k = dofs.shape[1]
    tx = (x - verts[ex]) / (verts[ex + 1] - verts[ex])
    if k == 3:
        phx[0] = 1.0 - 3.0 * tx + 2.0 * tx * tx
        phx[1] = -tx + 2.0 * tx * tx
        phx[2] = 4.0 * tx - 4.0 * tx * tx
    else:
        phx[0] = -4.5 * (tx - 1.0 / 3.0) * (tx - 2.0 / 3.0) * (tx - 1.0)
        phx[1] = 4.5 * tx * (tx - 1.0 / 3.0) * (tx - 2.0 / 3.0)
        phx[2] = 13.5 * tx * (tx - 2.0 / 3.0) * (tx - 1.0)
        phx[3] = -13.5 * tx * (tx - 1.0 / 3.0) * (tx - 1.0)
    ux = 0.0
    for j in range(k):
        ux += coef[dofs[ex, j]] * phx[j]
    px = np.exp(ux)
    if e_lo < 0:
        n_br = merge_breaks(verts, x, a, b, buf, False)
    else:
        n_br = breaks_between(verts, x, a, b, e_lo, e_hi + 1, buf)
    return pieces(buf, n_br, x, scale, graded, starts, lengths), px


@jit
def close_point(dx: np.ndarray, phx: np.ndarray, c_total: float, with_jacobian: bool,
                res: np.ndarray, jac: np.ndarray, bq: np.ndarray, cy: np.ndarray,
                jac_x: np.ndarray) -> None:
    """The loss term of an outer point and its rank-``k`` Jacobian terms (serial kernel).

    Parameters
    ----------
    dx : ndarray of int
        The dofs of the point's element.
    phx : ndarray
        The shape values at the point.
    c_total : float
        :math:`\\sum c` over its pairs.
    with_jacobian : bool
        Whether ``jac``, ``bq``, ``cy`` and ``jac_x`` are assembled.
    res, jac, bq, cy, jac_x : ndarray
        Residual, Jacobian, the per-point work vectors and the transposed x-columns.
    """
    k = dx.size
    n_dof = res.size
    for i in range(k):
        res[dx[i]] -= c_total * phx[i]
    if with_jacobian:
        for i in range(k):
            dix = dx[i]
            bq[dix] -= c_total * phx[i]
            # the -phi_i(x) rows depend on u through P(y)
            for col in range(n_dof):
                jac[dix, col] -= phx[i] * cy[col]
        # every row depends on u through P(x): the columns of x's element, kept
        # transposed (contiguous) and added once at the end
        for j in range(k):
            djx = dx[j]
            for row in range(n_dof):
                jac_x[djx, row] += bq[row] * phx[j]


@jit
def finish_collision(res: np.ndarray, jac: np.ndarray, jac_x: np.ndarray, with_jacobian: bool,
                     moment: float, loss: float, mirror: np.ndarray | None
                     ) -> tuple[np.ndarray, np.ndarray, float, float]:
    """Add the transposed x-columns ``jac_x`` and, with ``mirror``, the mirrored half.

    Parameters
    ----------
    res, jac, jac_x : ndarray
        Residual, Jacobian and the transposed columns of the :math:`P(x)` dependence.
    with_jacobian : bool
        Whether ``jac`` and ``jac_x`` hold a Jacobian.
    moment, loss : float
        Pair and loss moments of the visited pairs.
    mirror : ndarray of int, optional
        The dof at :math:`-v` of each dof (only outer points at :math:`v > 0` visited).
    """
    if with_jacobian:
        jac += jac_x.T
    if mirror is None:
        return res, jac, moment, loss
    n_dof = res.size
    full = res.copy()
    for i in range(n_dof):
        full[i] += res[mirror[i]]
    if with_jacobian:
        half = jac.copy()
        for i in range(n_dof):
            mi = mirror[i]
            for j in range(n_dof):
                jac[i, j] += half[mi, mirror[j]]
    return full, jac, 2.0 * moment, 2.0 * loss
