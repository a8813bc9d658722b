"""The FEM pair kernel for a constant coefficient and the reduced bracket, P2 and P3.

The fast path of :func:`kinetic_fem.operators.fem_kernels.collision_operator` (same
pair rule, same arguments, equal to the generic loop to round-off; checked in the
tests): on one inner piece of an outer point :math:`x` the elements of :math:`y` and
:math:`x' = a x + b y` are fixed, so the shape values at the piece's reference points
follow from two affine maps, and the sums over the points (:math:`\\sum c\\,\\varphi(x')`,
:math:`\\sum c\\,\\varphi(y)` and, for the Jacobian, their products with
:math:`\\varphi_j(y)`) are kept in scalars and scattered once per piece.  The per-degree
inner loops are generated code (written out for P2 and P3, the symmetric
:math:`\\varphi_i(y)\\varphi_j(y)` block summed once).

:func:`pair_sweep` holds these loops once for the serial kernel
(:func:`collision_constant`) and for pass 1 of the parallel kernel
(:mod:`~kinetic_fem.operators.fem_pair_parallel`), which visits only the pieces of one
block of elements, adds the Jacobian columns the block owns and keeps the rest per piece:
the same arithmetic in the same order, so that the two kernels agree bit for bit.
"""

from __future__ import annotations

import numpy as np

from .._jit import jit
from .fem_pair_breaks import GRADING_LEVELS, kernel_rate
from .fem_pair_sums import (
    close_point,
    finish_collision,
    locate,
    point_pieces,
    visited_points,
    work_arrays,
)

# numba caches this module's kernels with kernel_rate compiled in: edit this file too when
# kernel_rate changes (a stale cache keeps the old rule; gamma = 1/2 by sqrt since issue 16)
# (and when fem_pair_sums' helpers change: numba checks only this file's time stamp)
__all__ = ["collision_constant", "finish_collision", "pair_sweep"]


@jit
def pair_sweep(visit: np.ndarray, m: int, verts: np.ndarray, dofs: np.ndarray,
               coef: np.ndarray, xq: np.ndarray, wq: np.ndarray, eq: np.ndarray,
               ref_x: np.ndarray, ref_w: np.ndarray, alpha: float, density: float,
               with_jacobian: bool, energy_power: int, gamma: float, graded: bool, p: int,
               first: np.ndarray, owner: np.ndarray, runs: np.ndarray, buf: np.ndarray,
               starts: np.ndarray, lengths: np.ndarray, terms: np.ndarray,
               n_p: np.ndarray, phq: np.ndarray, ids: np.ndarray, vals: np.ndarray,
               res: np.ndarray, jac: np.ndarray, bq: np.ndarray, cy: np.ndarray,
               jac_x: np.ndarray, chains: np.ndarray) -> None:
    """The pair loops over the outer points ``visit[:m]``: serial (``p < 0``) or pass 1
    of the parallel kernel for thread ``p``.

    Parameters
    ----------
    visit : ndarray of int
        The outer points, in order.
    m : int
        Their number.
    verts, dofs, coef, xq, wq, eq, ref_x, ref_w, alpha, density, with_jacobian
        As for :func:`~kinetic_fem.operators.fem_kernels.collision_operator`.
    energy_power, gamma, graded
        As for :func:`collision_constant`.
    p : int
        ``-1``: every piece, added to ``res``, ``jac``, ``jac_x``, the moments to
        ``chains``.  Else the thread: the pieces whose :math:`y` lies in the elements
        ``first[p] ... first[p + 1]`` (the last for the vertex it shares); the Jacobian
        terms of the columns with ``owner == p`` (the runs ``(lo, hi, owner)``) added,
        and per piece of the elements ``first[p] <= e < first[p + 1]`` the elements of
        :math:`x'` and :math:`y` (``ids[t, p, s]``) and the sums
        :math:`\\sum c\\,\\varphi_i(x')`, :math:`\\sum c\\,\\varphi_i(y)` and the
        chain terms (``c`` per reference point, with moments the pair and the loss
        moment's) kept in ``vals[t, p, s]``, their number in ``n_p[t, p]``; thread 0
        keeps the shape values of each point (``phq``).
    first, owner, runs : ndarray of int
        The element blocks, the owner of each dof, the runs of one owner.
    buf, starts, lengths, terms : ndarray
        Work arrays (breaks, pieces, one piece's chain terms).
    n_p, phq, ids, vals : ndarray
        Out in the parallel pass (above).
    res, jac, bq, cy, jac_x : ndarray
        Residual, Jacobian, the per-point work vectors and the transposed x-columns.
    chains : ndarray, shape (2,)
        The pair and loss moments, carried on (serial).
    """
    k = dofs.shape[1]
    serial = p < 0
    moments = energy_power >= 0
    a = 0.5 * (1.0 - alpha)
    b = 0.5 * (1.0 + alpha)
    n_ref = ref_x.size
    n_terms = (3 if moments else 1) * n_ref
    scale = verts[-1] - verts[0]
    e_lo = 0 if serial else first[p]
    e_hi = dofs.shape[0] - 1 if serial else min(first[p + 1], dofs.shape[0] - 1)
    phx = np.empty(k)
    moment = chains[0]
    loss = chains[1]
    for t in range(m):
        q = visit[t]
        x = xq[q]
        ex = eq[q]
        if serial:
            n, px = point_pieces(x, ex, verts, dofs, coef, a, b, scale, graded, buf, starts,
                                 lengths, phx)
        else:
            n, px = point_pieces(x, ex, verts, dofs, coef, a, b, scale, graded, buf, starts,
                                 lengths, phx, e_lo, e_hi)
        if p == 0:
            phq[t, :k] = phx
        kept = 0
        c_total = 0.0
        if with_jacobian:
            if serial:
                bq[:] = 0.0
                cy[:] = 0.0
            else:
                for r in range(runs.shape[0]):
                    if runs[r, 2] == p:
                        cy[runs[r, 0]:runs[r, 1]] = 0.0
        ey = e_lo
        e1 = 0
        for s in range(n):
            y0 = starts[s]
            length = lengths[s]
            mid = y0 + 0.5 * length
            ey = locate(verts, ey, mid)
            if ey < e_lo:
                continue
            if ey > e_hi:
                break
            e1 = locate(verts, e1, a * x + b * mid)
            store = not serial and ey < first[p + 1]  # the block's own element
            hy = 1.0 / (verts[ey + 1] - verts[ey])
            h1 = 1.0 / (verts[e1 + 1] - verts[e1])
            ty0 = (y0 - verts[ey]) * hy
            dty = length * hy
            t10 = (a * x + b * y0 - verts[e1]) * h1
            dt1 = b * length * h1
            wm = wq[q] * length * px
            wmd = 0.5 * density * wm
            if k == 3:
                s0 = s1 = s2 = z0 = z1 = z2 = 0.0
                if with_jacobian:
                    g00 = g01 = g02 = 0.0
                    g10 = g11 = g12 = 0.0
                    g20 = g21 = g22 = 0.0
                    l00 = l01 = l02 = l11 = l12 = l22 = 0.0
                u0 = coef[dofs[ey, 0]]
                u1 = coef[dofs[ey, 1]]
                u2 = coef[dofs[ey, 2]]
                for r in range(n_ref):
                    xi = ref_x[r]
                    ty = ty0 + dty * xi
                    t1 = t10 + dt1 * xi
                    py0 = 1.0 - 3.0 * ty + 2.0 * ty * ty
                    py1 = -ty + 2.0 * ty * ty
                    py2 = 4.0 * ty - 4.0 * ty * ty
                    q0 = 1.0 - 3.0 * t1 + 2.0 * t1 * t1
                    q1 = -t1 + 2.0 * t1 * t1
                    q2 = 4.0 * t1 - 4.0 * t1 * t1
                    g = abs(x - (y0 + length * xi))
                    ew = ref_w[r] * np.exp(u0 * py0 + u1 * py1 + u2 * py2)
                    rate = kernel_rate(gamma, g)
                    if moments:
                        w = wm * ew
                        gp = 1.0
                        for _ in range(energy_power):
                            gp *= g
                        tm = w * gp
                        terms[n_ref + r] = tm
                        moment += tm
                        tl = w * (1.0 - alpha * alpha) * rate * g * g
                        terms[2 * n_ref + r] = tl
                        loss += tl
                    c = wmd * ew * rate
                    terms[r] = c
                    c_total += c
                    s0 += c * q0
                    s1 += c * q1
                    s2 += c * q2
                    c0 = c * py0
                    c1 = c * py1
                    c2 = c * py2
                    z0 += c0
                    z1 += c1
                    z2 += c2
                    if with_jacobian:
                        g00 += q0 * c0
                        g01 += q0 * c1
                        g02 += q0 * c2
                        g10 += q1 * c0
                        g11 += q1 * c1
                        g12 += q1 * c2
                        g20 += q2 * c0
                        g21 += q2 * c1
                        g22 += q2 * c2
                        l00 += py0 * c0
                        l01 += py0 * c1
                        l02 += py0 * c2
                        l11 += py1 * c1
                        l12 += py1 * c2
                        l22 += py2 * c2
                i0 = dofs[e1, 0]
                i1 = dofs[e1, 1]
                i2 = dofs[e1, 2]
                j0 = dofs[ey, 0]
                j1 = dofs[ey, 1]
                j2 = dofs[ey, 2]
                if serial:
                    res[i0] += 2.0 * s0
                    res[i1] += 2.0 * s1
                    res[i2] += 2.0 * s2
                    res[j0] -= z0
                    res[j1] -= z1
                    res[j2] -= z2
                    if with_jacobian:
                        bq[i0] += 2.0 * s0
                        bq[i1] += 2.0 * s1
                        bq[i2] += 2.0 * s2
                        bq[j0] -= z0
                        bq[j1] -= z1
                        bq[j2] -= z2
                elif store:
                    kept += 1
                    ids[t, p, s, 0] = e1
                    ids[t, p, s, 1] = ey
                    vals[t, p, s, 0] = s0
                    vals[t, p, s, 1] = s1
                    vals[t, p, s, 2] = s2
                    vals[t, p, s, 3] = z0
                    vals[t, p, s, 4] = z1
                    vals[t, p, s, 5] = z2
                    for r in range(n_terms):
                        vals[t, p, s, 6 + r] = terms[r]
                if with_jacobian:  # by (owned) column: x' rows, then y rows
                    if serial or owner[j0] == p:
                        cy[j0] += z0
                        jac[i0, j0] += 2.0 * g00
                        jac[i1, j0] += 2.0 * g10
                        jac[i2, j0] += 2.0 * g20
                    if serial or owner[j1] == p:
                        cy[j1] += z1
                        jac[i0, j1] += 2.0 * g01
                        jac[i1, j1] += 2.0 * g11
                        jac[i2, j1] += 2.0 * g21
                    if serial or owner[j2] == p:
                        cy[j2] += z2
                        jac[i0, j2] += 2.0 * g02
                        jac[i1, j2] += 2.0 * g12
                        jac[i2, j2] += 2.0 * g22
                    if serial or owner[j0] == p:
                        jac[j0, j0] -= l00
                        jac[j1, j0] -= l01
                        jac[j2, j0] -= l02
                    if serial or owner[j1] == p:
                        jac[j0, j1] -= l01
                        jac[j1, j1] -= l11
                        jac[j2, j1] -= l12
                    if serial or owner[j2] == p:
                        jac[j0, j2] -= l02
                        jac[j1, j2] -= l12
                        jac[j2, j2] -= l22
            else:
                s0 = s1 = s2 = s3 = z0 = z1 = z2 = z3 = 0.0
                if with_jacobian:
                    g00 = g01 = g02 = g03 = 0.0
                    g10 = g11 = g12 = g13 = 0.0
                    g20 = g21 = g22 = g23 = 0.0
                    g30 = g31 = g32 = g33 = 0.0
                    l00 = l01 = l02 = l03 = l11 = l12 = l13 = l22 = l23 = l33 = 0.0
                u0 = coef[dofs[ey, 0]]
                u1 = coef[dofs[ey, 1]]
                u2 = coef[dofs[ey, 2]]
                u3 = coef[dofs[ey, 3]]
                for r in range(n_ref):
                    xi = ref_x[r]
                    ty = ty0 + dty * xi
                    t1 = t10 + dt1 * xi
                    d1 = ty - 1.0 / 3.0
                    d2 = ty - 2.0 / 3.0
                    d3 = ty - 1.0
                    py0 = -4.5 * d1 * d2 * d3
                    py1 = 4.5 * ty * d1 * d2
                    py2 = 13.5 * ty * d2 * d3
                    py3 = -13.5 * ty * d1 * d3
                    o1 = t1 - 1.0 / 3.0
                    o2 = t1 - 2.0 / 3.0
                    o3 = t1 - 1.0
                    q0 = -4.5 * o1 * o2 * o3
                    q1 = 4.5 * t1 * o1 * o2
                    q2 = 13.5 * t1 * o2 * o3
                    q3 = -13.5 * t1 * o1 * o3
                    g = abs(x - (y0 + length * xi))
                    ew = ref_w[r] * np.exp(u0 * py0 + u1 * py1 + u2 * py2 + u3 * py3)
                    rate = kernel_rate(gamma, g)
                    if moments:
                        w = wm * ew
                        gp = 1.0
                        for _ in range(energy_power):
                            gp *= g
                        tm = w * gp
                        terms[n_ref + r] = tm
                        moment += tm
                        tl = w * (1.0 - alpha * alpha) * rate * g * g
                        terms[2 * n_ref + r] = tl
                        loss += tl
                    c = wmd * ew * rate
                    terms[r] = c
                    c_total += c
                    s0 += c * q0
                    s1 += c * q1
                    s2 += c * q2
                    s3 += c * q3
                    c0 = c * py0
                    c1 = c * py1
                    c2 = c * py2
                    c3 = c * py3
                    z0 += c0
                    z1 += c1
                    z2 += c2
                    z3 += c3
                    if with_jacobian:
                        g00 += q0 * c0
                        g01 += q0 * c1
                        g02 += q0 * c2
                        g03 += q0 * c3
                        g10 += q1 * c0
                        g11 += q1 * c1
                        g12 += q1 * c2
                        g13 += q1 * c3
                        g20 += q2 * c0
                        g21 += q2 * c1
                        g22 += q2 * c2
                        g23 += q2 * c3
                        g30 += q3 * c0
                        g31 += q3 * c1
                        g32 += q3 * c2
                        g33 += q3 * c3
                        l00 += py0 * c0
                        l01 += py0 * c1
                        l02 += py0 * c2
                        l03 += py0 * c3
                        l11 += py1 * c1
                        l12 += py1 * c2
                        l13 += py1 * c3
                        l22 += py2 * c2
                        l23 += py2 * c3
                        l33 += py3 * c3
                i0 = dofs[e1, 0]
                i1 = dofs[e1, 1]
                i2 = dofs[e1, 2]
                i3 = dofs[e1, 3]
                j0 = dofs[ey, 0]
                j1 = dofs[ey, 1]
                j2 = dofs[ey, 2]
                j3 = dofs[ey, 3]
                if serial:
                    res[i0] += 2.0 * s0
                    res[i1] += 2.0 * s1
                    res[i2] += 2.0 * s2
                    res[i3] += 2.0 * s3
                    res[j0] -= z0
                    res[j1] -= z1
                    res[j2] -= z2
                    res[j3] -= z3
                    if with_jacobian:
                        bq[i0] += 2.0 * s0
                        bq[i1] += 2.0 * s1
                        bq[i2] += 2.0 * s2
                        bq[i3] += 2.0 * s3
                        bq[j0] -= z0
                        bq[j1] -= z1
                        bq[j2] -= z2
                        bq[j3] -= z3
                elif store:
                    kept += 1
                    ids[t, p, s, 0] = e1
                    ids[t, p, s, 1] = ey
                    vals[t, p, s, 0] = s0
                    vals[t, p, s, 1] = s1
                    vals[t, p, s, 2] = s2
                    vals[t, p, s, 3] = s3
                    vals[t, p, s, 4] = z0
                    vals[t, p, s, 5] = z1
                    vals[t, p, s, 6] = z2
                    vals[t, p, s, 7] = z3
                    for r in range(n_terms):
                        vals[t, p, s, 8 + r] = terms[r]
                if with_jacobian:  # by (owned) column: x' rows, then y rows
                    if serial or owner[j0] == p:
                        cy[j0] += z0
                        jac[i0, j0] += 2.0 * g00
                        jac[i1, j0] += 2.0 * g10
                        jac[i2, j0] += 2.0 * g20
                        jac[i3, j0] += 2.0 * g30
                    if serial or owner[j1] == p:
                        cy[j1] += z1
                        jac[i0, j1] += 2.0 * g01
                        jac[i1, j1] += 2.0 * g11
                        jac[i2, j1] += 2.0 * g21
                        jac[i3, j1] += 2.0 * g31
                    if serial or owner[j2] == p:
                        cy[j2] += z2
                        jac[i0, j2] += 2.0 * g02
                        jac[i1, j2] += 2.0 * g12
                        jac[i2, j2] += 2.0 * g22
                        jac[i3, j2] += 2.0 * g32
                    if serial or owner[j3] == p:
                        cy[j3] += z3
                        jac[i0, j3] += 2.0 * g03
                        jac[i1, j3] += 2.0 * g13
                        jac[i2, j3] += 2.0 * g23
                        jac[i3, j3] += 2.0 * g33
                    if serial or owner[j0] == p:
                        jac[j0, j0] -= l00
                        jac[j1, j0] -= l01
                        jac[j2, j0] -= l02
                        jac[j3, j0] -= l03
                    if serial or owner[j1] == p:
                        jac[j0, j1] -= l01
                        jac[j1, j1] -= l11
                        jac[j2, j1] -= l12
                        jac[j3, j1] -= l13
                    if serial or owner[j2] == p:
                        jac[j0, j2] -= l02
                        jac[j1, j2] -= l12
                        jac[j2, j2] -= l22
                        jac[j3, j2] -= l23
                    if serial or owner[j3] == p:
                        jac[j0, j3] -= l03
                        jac[j1, j3] -= l13
                        jac[j2, j3] -= l23
                        jac[j3, j3] -= l33
        if not serial:  # the -phi_i(x) rows depend on u through P(y): owned columns
            n_p[t, p] = kept
            if with_jacobian:
                for i in range(k):
                    dix = dofs[ex, i]
                    for r in range(runs.shape[0]):
                        if runs[r, 2] == p:
                            for col in range(runs[r, 0], runs[r, 1]):
                                jac[dix, col] -= phx[i] * cy[col]
            continue
        close_point(dofs[ex], phx, c_total, with_jacobian, res, jac, bq, cy, jac_x)
    if serial:
        chains[0] = moment
        chains[1] = loss


@jit
def collision_constant(verts: np.ndarray, dofs: np.ndarray, coef: np.ndarray, xq: np.ndarray,
                       wq: np.ndarray, eq: np.ndarray, ref_x: np.ndarray, ref_w: np.ndarray,
                       alpha: float, density: float, with_jacobian: bool, energy_power: int,
                       gamma: float, graded: bool, mirror: np.ndarray | None
                       ) -> tuple[np.ndarray, np.ndarray, float, float]:
    """:func:`~kinetic_fem.operators.fem_kernels.collision_operator` for P2 or P3
    (``dofs`` with 3 or 4 columns), a constant ``alpha``, the reduced bracket and
    any :math:`\\gamma` (``graded``: pieces split geometrically towards :math:`y = x`, as
    for :math:`\\gamma \\notin \\{0, 1, 2\\}`); the arguments and returns as there
    (``energy_power < 0``: no moments).

    Parameters
    ----------
    verts, dofs, coef, xq, wq, eq, ref_x, ref_w, alpha, density, with_jacobian
        As for :func:`~kinetic_fem.operators.fem_kernels.collision_operator`.
    energy_power, gamma, mirror
        As there.
    graded : bool
        Split the pieces next to :math:`y = x` geometrically
        (:func:`~kinetic_fem.operators.fem_pair_breaks.pieces`).
    """
    n_dof = coef.size
    res, jac, bq, cy, jac_x = work_arrays(n_dof, with_jacobian)
    buf = np.empty(3 * verts.size + 3)
    starts = np.empty(buf.size + 2 * (GRADING_LEVELS + 1))
    lengths = np.empty(starts.size)
    visit = visited_points(xq, mirror)
    none = np.zeros(1, dtype=np.int64)
    runs = np.zeros((1, 3), dtype=np.int64)
    chains = np.zeros(2)
    pair_sweep(visit, visit.size, verts, dofs, coef, xq, wq, eq, ref_x, ref_w, alpha, density,
               with_jacobian, energy_power, gamma, graded, -1, none, none, runs, buf,
               starts, lengths, np.empty(3 * ref_x.size), np.zeros((1, 1), dtype=np.int64),
               np.zeros((1, 1)), np.zeros((1, 1, 1, 2), dtype=np.int64),
               np.zeros((1, 1, 1, 1)), res, jac, bq, cy, jac_x, chains)
    return finish_collision(res, jac, jac_x, with_jacobian, chains[0], chains[1], mirror)
