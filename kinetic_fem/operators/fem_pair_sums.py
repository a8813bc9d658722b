"""Per-outer-point sums of the FEM pair kernel, kept for the parallel kernel.

:func:`outer_point_sums` forms, for one outer quadrature point, the sums over the inner
points of each inner piece that
:func:`kinetic_fem.operators.fem_pair_fast.collision_constant` adds to the residual and
Jacobian, with the same arithmetic in the same order (the loops are that kernel's,
copied: a change to one must be made to both; ``tests/kinetic_fem/operators/
test_fem_pair_parallel.py`` checks the parallel results bit for bit), and stores them
per piece instead of adding them.  Used by
:mod:`kinetic_fem.operators.fem_pair_parallel`.
"""

from __future__ import annotations

import numpy as np

from .._jit import jit
from .fem_pair_breaks import kernel_rate, merge_breaks, pieces

# numba caches this module's kernels with kernel_rate compiled in: edit this file too when
# kernel_rate changes (a stale cache keeps the old rule; gamma = 1/2 by sqrt since issue 16)
__all__ = ["outer_point_sums", "N_VALUES"]


@jit
def _locate(verts: np.ndarray, e: int, x: float) -> int:
    """Walk forward from element ``e`` to the element containing ``x``."""
    n_el = verts.size - 1
    while e < n_el - 1 and verts[e + 1] <= x:
        e += 1
    return e


N_VALUES = {3: 21, 4: 34}
"""Sums kept per inner piece by :func:`outer_point_sums` (P2, P3): ``k`` of
:math:`\\varphi(x')`, ``k`` of :math:`\\varphi(y)`, with the Jacobian the ``k x k``
products :math:`\\varphi_i(x')\\varphi_j(y)` and the ``k (k + 1) / 2`` symmetric
:math:`\\varphi_i(y)\\varphi_j(y)`."""


@jit
def outer_point_sums(q: int, verts: np.ndarray, dofs: np.ndarray, coef: np.ndarray,
                     xq: np.ndarray, wq: np.ndarray, eq: np.ndarray, ref_x: np.ndarray,
                     ref_w: np.ndarray, alpha: float, density: float, with_jacobian: bool,
                     energy_power: int, gamma: float, graded: bool, buf: np.ndarray,
                     starts: np.ndarray, lengths: np.ndarray, phx: np.ndarray,
                     ids: np.ndarray, vals: np.ndarray, moment: float, loss: float
                     ) -> tuple[int, float, float, float]:
    """The per-piece sums of outer point ``q``, kept for :func:`scatter_outer_point`.

    Parameters
    ----------
    q : int
        The outer quadrature point.
    verts, dofs, coef, xq, wq, eq, ref_x, ref_w, alpha, density, with_jacobian
        As for :func:`~kinetic_fem.operators.fem_pair_fast.collision_constant`.
    energy_power, gamma, graded
        As there.
    buf, starts, lengths : ndarray
        Work arrays of the breaks and pieces.
    phx : ndarray, shape (k,)
        Out: the shape values at :math:`x`.
    ids : ndarray of int, shape (n_max, 2)
        Out: the elements of :math:`x'` and :math:`y` of each piece.
    vals : ndarray, shape (n_max, N_VALUES[k])
        Out: the sums of each piece (:data:`N_VALUES`).
    moment, loss : float
        The pair and loss moments so far (summed on in the serial order).

    Returns
    -------
    n_pieces : int
    c_total : float
        :math:`\\sum c` over the pieces (the loss term of :math:`x`).
    moment, loss : float
        The moments with this point's pairs added.
    """
    k = dofs.shape[1]
    moments = energy_power >= 0
    a = 0.5 * (1.0 - alpha)
    b = 0.5 * (1.0 + alpha)
    n_ref = ref_x.size
    scale = verts[-1] - verts[0]
    x = xq[q]
    ex = eq[q]
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
    n_br = merge_breaks(verts, x, a, b, buf, False)
    n_p = pieces(buf, n_br, x, scale, graded, starts, lengths)
    ey = 0
    e1 = 0
    c_total = 0.0
    for s in range(n_p):
        y0 = starts[s]
        length = lengths[s]
        mid = y0 + 0.5 * length
        ey = _locate(verts, ey, mid)
        e1 = _locate(verts, e1, a * x + b * mid)
        ids[s, 0] = e1
        ids[s, 1] = ey
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
                    moment += w * gp
                    loss += w * (1.0 - alpha * alpha) * rate * g * g
                c = wmd * ew * rate
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
            vals[s, 0] = s0
            vals[s, 1] = s1
            vals[s, 2] = s2
            vals[s, 3] = z0
            vals[s, 4] = z1
            vals[s, 5] = z2
            if with_jacobian:
                vals[s, 6] = g00
                vals[s, 7] = g01
                vals[s, 8] = g02
                vals[s, 9] = g10
                vals[s, 10] = g11
                vals[s, 11] = g12
                vals[s, 12] = g20
                vals[s, 13] = g21
                vals[s, 14] = g22
                vals[s, 15] = l00
                vals[s, 16] = l01
                vals[s, 17] = l02
                vals[s, 18] = l11
                vals[s, 19] = l12
                vals[s, 20] = l22
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
                    moment += w * gp
                    loss += w * (1.0 - alpha * alpha) * rate * g * g
                c = wmd * ew * rate
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
            vals[s, 0] = s0
            vals[s, 1] = s1
            vals[s, 2] = s2
            vals[s, 3] = s3
            vals[s, 4] = z0
            vals[s, 5] = z1
            vals[s, 6] = z2
            vals[s, 7] = z3
            if with_jacobian:
                vals[s, 8] = g00
                vals[s, 9] = g01
                vals[s, 10] = g02
                vals[s, 11] = g03
                vals[s, 12] = g10
                vals[s, 13] = g11
                vals[s, 14] = g12
                vals[s, 15] = g13
                vals[s, 16] = g20
                vals[s, 17] = g21
                vals[s, 18] = g22
                vals[s, 19] = g23
                vals[s, 20] = g30
                vals[s, 21] = g31
                vals[s, 22] = g32
                vals[s, 23] = g33
                vals[s, 24] = l00
                vals[s, 25] = l01
                vals[s, 26] = l02
                vals[s, 27] = l03
                vals[s, 28] = l11
                vals[s, 29] = l12
                vals[s, 30] = l13
                vals[s, 31] = l22
                vals[s, 32] = l23
                vals[s, 33] = l33
    return n_p, c_total, moment, loss
