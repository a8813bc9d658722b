"""Pass 1 of the parallel FEM pair kernel: one thread's inner pieces and Jacobian columns.

:func:`pass_columns` runs, for one thread of
:func:`kinetic_fem.operators.fem_pair_parallel.collision_constant_parallel`, the loops of
the serial kernel :func:`kinetic_fem.operators.fem_pair_fast.collision_constant` over the
inner pieces whose :math:`y` lies in the thread's block of elements, with the same
arithmetic in the same order (the loops are that kernel's, copied: a change to one must
be made to both; ``tests/kinetic_fem/operators/test_fem_pair_parallel.py`` checks the
results bit for bit).  It adds the Jacobian terms of the columns the thread owns at once
and keeps, per piece, what belongs to other rows (the sums over :math:`\varphi(x')` and
:math:`\varphi(y)`) and the terms of the running sums that go across pieces
(:math:`\\sum c` of the outer point, the pair and loss moments), for pass 2.
"""

from __future__ import annotations

import numpy as np

from .._jit import jit
from .fem_pair_breaks import kernel_rate, merge_breaks, pieces

# numba caches this module's kernels with kernel_rate compiled in: edit this file too when
# kernel_rate changes (a stale cache keeps the old rule; gamma = 1/2 by sqrt since issue 16)
__all__ = ["pass_columns", "locate", "shape_values"]


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
def shape_values(k: int, tx: float, phx: np.ndarray) -> None:
    """The P2 (``k = 3``) or P3 (``k = 4``) shape values at ``tx`` into ``phx``.

    Parameters
    ----------
    k : int
        Dofs per element.
    tx : float
        Reference coordinate in [0, 1].
    phx : ndarray, shape (k,)
        Out: the values (the serial kernel's expressions).
    """
    if k == 3:
        phx[0] = 1.0 - 3.0 * tx + 2.0 * tx * tx
        phx[1] = -tx + 2.0 * tx * tx
        phx[2] = 4.0 * tx - 4.0 * tx * tx
    else:
        phx[0] = -4.5 * (tx - 1.0 / 3.0) * (tx - 2.0 / 3.0) * (tx - 1.0)
        phx[1] = 4.5 * tx * (tx - 1.0 / 3.0) * (tx - 2.0 / 3.0)
        phx[2] = 13.5 * tx * (tx - 2.0 / 3.0) * (tx - 1.0)
        phx[3] = -13.5 * tx * (tx - 1.0 / 3.0) * (tx - 1.0)


@jit
def pass_columns(p: int, visit: np.ndarray, m: int, verts: np.ndarray, dofs: np.ndarray,
                 coef: np.ndarray, xq: np.ndarray, wq: np.ndarray, eq: np.ndarray,
                 ref_x: np.ndarray, ref_w: np.ndarray, alpha: float, density: float,
                 with_jacobian: bool, energy_power: int, gamma: float, graded: bool,
                 first: np.ndarray, owner: np.ndarray, runs: np.ndarray, buf: np.ndarray,
                 starts: np.ndarray, lengths: np.ndarray, terms: np.ndarray,
                 n_p: np.ndarray, phq: np.ndarray, ids: np.ndarray, vals: np.ndarray,
                 jac: np.ndarray, cy: np.ndarray) -> None:
    """Pass 1 for thread ``p`` over the outer points ``visit[:m]``.

    Parameters
    ----------
    p : int
        The thread; it owns the dofs with ``owner == p`` (the elements
        ``first[p] <= e < first[p + 1]``, a shared vertex to the lower block).
    visit : ndarray of int
        The outer points of the chunk.
    m : int
        Their number.
    verts, dofs, coef, xq, wq, eq, ref_x, ref_w, alpha, density, with_jacobian
        As for :func:`~kinetic_fem.operators.fem_pair_fast.collision_constant`.
    energy_power, gamma, graded
        As there.
    first, owner, runs : ndarray of int
        The element blocks, the owner of each dof and the runs ``(lo, hi, owner)`` of
        consecutive dofs of one owner.
    buf, starts, lengths, terms : ndarray
        The thread's work arrays (breaks, pieces, one piece's chain terms).
    n_p, phq : ndarray
        Out (thread 0): the pieces and the shape values at :math:`x` of each outer point.
    ids, vals : ndarray
        Out: per outer point and piece (of the thread's own elements) the elements of
        :math:`x'` and :math:`y`, and the sums :math:`\\sum c\\,\varphi_i(x')`,
        :math:`\\sum c\\,\varphi_i(y)` followed by the chain terms (``c`` per reference
        point, with moments the pair and the loss moment's terms).
    jac, cy : ndarray
        The Jacobian (owned columns added) and the per-point work vector.
    """
    k = dofs.shape[1]
    moments = energy_power >= 0
    a = 0.5 * (1.0 - alpha)
    b = 0.5 * (1.0 + alpha)
    n_ref = ref_x.size
    n_terms = (3 if moments else 1) * n_ref
    scale = verts[-1] - verts[0]
    e_lo = first[p]
    e_hi = min(first[p + 1], dofs.shape[0] - 1)  # the next block's first element
    phx = np.empty(k)
    for t in range(m):
        q = visit[t]
        x = xq[q]
        ex = eq[q]
        shape_values(k, (x - verts[ex]) / (verts[ex + 1] - verts[ex]), phx)
        ux = 0.0
        for j in range(k):
            ux += coef[dofs[ex, j]] * phx[j]
        px = np.exp(ux)
        n_br = merge_breaks(verts, x, a, b, buf, False)
        n = pieces(buf, n_br, x, scale, graded, starts, lengths)
        if p == 0:
            n_p[t] = n
            phq[t, :k] = phx
        if with_jacobian:
            for r in range(runs.shape[0]):
                if runs[r, 2] == p:
                    cy[runs[r, 0]:runs[r, 1]] = 0.0
        ey = 0
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
            store = ey < first[p + 1]  # the block's own element: keep its sums
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
                        terms[n_ref + r] = w * gp
                        terms[2 * n_ref + r] = w * (1.0 - alpha * alpha) * rate * g * g
                    c = wmd * ew * rate
                    terms[r] = c
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
                if store:
                    ids[t, s, 0] = e1
                    ids[t, s, 1] = ey
                    vals[t, s, 0] = s0
                    vals[t, s, 1] = s1
                    vals[t, s, 2] = s2
                    vals[t, s, 3] = z0
                    vals[t, s, 4] = z1
                    vals[t, s, 5] = z2
                    for r in range(n_terms):
                        vals[t, s, 6 + r] = terms[r]
                if with_jacobian:
                    i0 = dofs[e1, 0]
                    i1 = dofs[e1, 1]
                    i2 = dofs[e1, 2]
                    j0 = dofs[ey, 0]
                    j1 = dofs[ey, 1]
                    j2 = dofs[ey, 2]
                    # the owned columns; all x' terms before the y terms, as serially
                    if owner[j0] == p:
                        cy[j0] += z0
                        jac[i0, j0] += 2.0 * g00
                        jac[i1, j0] += 2.0 * g10
                        jac[i2, j0] += 2.0 * g20
                    if owner[j1] == p:
                        cy[j1] += z1
                        jac[i0, j1] += 2.0 * g01
                        jac[i1, j1] += 2.0 * g11
                        jac[i2, j1] += 2.0 * g21
                    if owner[j2] == p:
                        cy[j2] += z2
                        jac[i0, j2] += 2.0 * g02
                        jac[i1, j2] += 2.0 * g12
                        jac[i2, j2] += 2.0 * g22
                    if owner[j0] == p:
                        jac[j0, j0] -= l00
                        jac[j1, j0] -= l01
                        jac[j2, j0] -= l02
                    if owner[j1] == p:
                        jac[j0, j1] -= l01
                        jac[j1, j1] -= l11
                        jac[j2, j1] -= l12
                    if owner[j2] == p:
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
                        terms[n_ref + r] = w * gp
                        terms[2 * n_ref + r] = w * (1.0 - alpha * alpha) * rate * g * g
                    c = wmd * ew * rate
                    terms[r] = c
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
                if store:
                    ids[t, s, 0] = e1
                    ids[t, s, 1] = ey
                    vals[t, s, 0] = s0
                    vals[t, s, 1] = s1
                    vals[t, s, 2] = s2
                    vals[t, s, 3] = s3
                    vals[t, s, 4] = z0
                    vals[t, s, 5] = z1
                    vals[t, s, 6] = z2
                    vals[t, s, 7] = z3
                    for r in range(n_terms):
                        vals[t, s, 8 + r] = terms[r]
                if with_jacobian:
                    i0 = dofs[e1, 0]
                    i1 = dofs[e1, 1]
                    i2 = dofs[e1, 2]
                    i3 = dofs[e1, 3]
                    j0 = dofs[ey, 0]
                    j1 = dofs[ey, 1]
                    j2 = dofs[ey, 2]
                    j3 = dofs[ey, 3]
                    # the owned columns; all x' terms before the y terms, as serially
                    if owner[j0] == p:
                        cy[j0] += z0
                        jac[i0, j0] += 2.0 * g00
                        jac[i1, j0] += 2.0 * g10
                        jac[i2, j0] += 2.0 * g20
                        jac[i3, j0] += 2.0 * g30
                    if owner[j1] == p:
                        cy[j1] += z1
                        jac[i0, j1] += 2.0 * g01
                        jac[i1, j1] += 2.0 * g11
                        jac[i2, j1] += 2.0 * g21
                        jac[i3, j1] += 2.0 * g31
                    if owner[j2] == p:
                        cy[j2] += z2
                        jac[i0, j2] += 2.0 * g02
                        jac[i1, j2] += 2.0 * g12
                        jac[i2, j2] += 2.0 * g22
                        jac[i3, j2] += 2.0 * g32
                    if owner[j3] == p:
                        cy[j3] += z3
                        jac[i0, j3] += 2.0 * g03
                        jac[i1, j3] += 2.0 * g13
                        jac[i2, j3] += 2.0 * g23
                        jac[i3, j3] += 2.0 * g33
                    if owner[j0] == p:
                        jac[j0, j0] -= l00
                        jac[j1, j0] -= l01
                        jac[j2, j0] -= l02
                        jac[j3, j0] -= l03
                    if owner[j1] == p:
                        jac[j0, j1] -= l01
                        jac[j1, j1] -= l11
                        jac[j2, j1] -= l12
                        jac[j3, j1] -= l13
                    if owner[j2] == p:
                        jac[j0, j2] -= l02
                        jac[j1, j2] -= l12
                        jac[j2, j2] -= l22
                        jac[j3, j2] -= l23
                    if owner[j3] == p:
                        jac[j0, j3] -= l03
                        jac[j1, j3] -= l13
                        jac[j2, j3] -= l23
                        jac[j3, j3] -= l33
        if with_jacobian:  # the -phi_i(x) rows depend on u through P(y): owned columns
            for i in range(k):
                dix = dofs[ex, i]
                for r in range(runs.shape[0]):
                    if runs[r, 2] == p:
                        for col in range(runs[r, 0], runs[r, 1]):
                            jac[dix, col] -= phx[i] * cy[col]
