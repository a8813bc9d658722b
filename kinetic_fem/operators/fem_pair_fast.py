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
"""

from __future__ import annotations

import numpy as np

from .._jit import jit
from .fem_pair_breaks import GRADING_LEVELS, kernel_rate, merge_breaks, pieces

# numba caches this module's kernels with kernel_rate compiled in: edit this file too when
# kernel_rate changes (a stale cache keeps the old rule; gamma = 1/2 by sqrt since issue 16)
__all__ = ["collision_constant", "finish_collision"]


@jit
def _locate(verts: np.ndarray, e: int, x: float) -> int:
    """Walk forward from element ``e`` to the element containing ``x``."""
    n_el = verts.size - 1
    while e < n_el - 1 and verts[e + 1] <= x:
        e += 1
    return e


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
    k = dofs.shape[1]
    moments = energy_power >= 0
    a = 0.5 * (1.0 - alpha)
    b = 0.5 * (1.0 + alpha)
    res = np.zeros(n_dof)
    jac = np.zeros((n_dof, n_dof)) if with_jacobian else np.zeros((1, 1))
    bq = np.zeros(n_dof) if with_jacobian else np.zeros(1)
    cy = np.zeros(n_dof) if with_jacobian else np.zeros(1)
    jac_x = np.zeros((n_dof, n_dof)) if with_jacobian else np.zeros((1, 1))
    buf = np.empty(3 * verts.size + 3)
    starts = np.empty(buf.size + 2 * (GRADING_LEVELS + 1))
    lengths = np.empty(starts.size)
    phx = np.empty(k)
    n_ref = ref_x.size
    scale = verts[-1] - verts[0]
    moment = 0.0
    loss = 0.0
    for q in range(xq.size):
        x = xq[q]
        if mirror is not None and x <= 0.0:
            if x == 0.0:
                raise ValueError("mirror needs outer points off v = 0 (a vertex at 0)")
            continue
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
        if with_jacobian:
            bq[:] = 0.0
            cy[:] = 0.0
        for s in range(n_p):
            y0 = starts[s]
            length = lengths[s]
            mid = y0 + 0.5 * length
            ey = _locate(verts, ey, mid)
            e1 = _locate(verts, e1, a * x + b * mid)
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
                i0 = dofs[e1, 0]
                i1 = dofs[e1, 1]
                i2 = dofs[e1, 2]
                j0 = dofs[ey, 0]
                j1 = dofs[ey, 1]
                j2 = dofs[ey, 2]
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
                    cy[j0] += z0
                    cy[j1] += z1
                    cy[j2] += z2
                    jac[i0, j0] += 2.0 * g00
                    jac[i0, j1] += 2.0 * g01
                    jac[i0, j2] += 2.0 * g02
                    jac[i1, j0] += 2.0 * g10
                    jac[i1, j1] += 2.0 * g11
                    jac[i1, j2] += 2.0 * g12
                    jac[i2, j0] += 2.0 * g20
                    jac[i2, j1] += 2.0 * g21
                    jac[i2, j2] += 2.0 * g22
                    jac[j0, j0] -= l00
                    jac[j0, j1] -= l01
                    jac[j0, j2] -= l02
                    jac[j1, j0] -= l01
                    jac[j1, j1] -= l11
                    jac[j1, j2] -= l12
                    jac[j2, j0] -= l02
                    jac[j2, j1] -= l12
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
                i0 = dofs[e1, 0]
                i1 = dofs[e1, 1]
                i2 = dofs[e1, 2]
                i3 = dofs[e1, 3]
                j0 = dofs[ey, 0]
                j1 = dofs[ey, 1]
                j2 = dofs[ey, 2]
                j3 = dofs[ey, 3]
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
                    cy[j0] += z0
                    cy[j1] += z1
                    cy[j2] += z2
                    cy[j3] += z3
                    jac[i0, j0] += 2.0 * g00
                    jac[i0, j1] += 2.0 * g01
                    jac[i0, j2] += 2.0 * g02
                    jac[i0, j3] += 2.0 * g03
                    jac[i1, j0] += 2.0 * g10
                    jac[i1, j1] += 2.0 * g11
                    jac[i1, j2] += 2.0 * g12
                    jac[i1, j3] += 2.0 * g13
                    jac[i2, j0] += 2.0 * g20
                    jac[i2, j1] += 2.0 * g21
                    jac[i2, j2] += 2.0 * g22
                    jac[i2, j3] += 2.0 * g23
                    jac[i3, j0] += 2.0 * g30
                    jac[i3, j1] += 2.0 * g31
                    jac[i3, j2] += 2.0 * g32
                    jac[i3, j3] += 2.0 * g33
                    jac[j0, j0] -= l00
                    jac[j0, j1] -= l01
                    jac[j0, j2] -= l02
                    jac[j0, j3] -= l03
                    jac[j1, j0] -= l01
                    jac[j1, j1] -= l11
                    jac[j1, j2] -= l12
                    jac[j1, j3] -= l13
                    jac[j2, j0] -= l02
                    jac[j2, j1] -= l12
                    jac[j2, j2] -= l22
                    jac[j2, j3] -= l23
                    jac[j3, j0] -= l03
                    jac[j3, j1] -= l13
                    jac[j3, j2] -= l23
                    jac[j3, j3] -= l33
        for i in range(k):
            res[dofs[ex, i]] -= c_total * phx[i]
        if with_jacobian:
            for i in range(k):
                dix = dofs[ex, i]
                bq[dix] -= c_total * phx[i]
                # the -phi_i(x) rows depend on u through P(y)
                for col in range(n_dof):
                    jac[dix, col] -= phx[i] * cy[col]
            # every row depends on u through P(x): the columns of x's element, kept
            # transposed (contiguous) and added once at the end
            for j in range(k):
                djx = dofs[ex, j]
                for row in range(n_dof):
                    jac_x[djx, row] += bq[row] * phx[j]
    return finish_collision(res, jac, jac_x, with_jacobian, moment, loss, mirror)
