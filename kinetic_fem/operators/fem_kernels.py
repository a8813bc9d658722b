"""Numba kernels of the Galerkin collision operator (see :mod:`kinetic_fem.solvers.fem`).

The weak form of the inelastic collision term for a Lagrange test function
:math:`\\varphi_i` is

.. math::

    C_i = \\frac n2 \\iint dx\\, dy\\, |x - y| P(x) P(y)
    \\left[\\varphi_i(x') + \\varphi_i(y') - \\varphi_i(x) - \\varphi_i(y)\\right],
    \\quad x' = a x + b y,\\ y' = b x + a y,

with :math:`a = (1-\\alpha)/2`, :math:`b = (1+\\alpha)/2` and :math:`P = e^{u_h}`.
It is evaluated on one set of weighted pairs :math:`(x_q, y_m)`: the outer points
:math:`x_q` are the basis' quadrature points; for each of them the inner integral
over :math:`y` is split at every point where the integrand is not smooth (mesh
vertices, :math:`y = x_q`, and the pre-images of the vertices under :math:`y \\mapsto
x'` and :math:`y \\mapsto y'`), and each piece gets the basis' reference rule.  The
integrand is then smooth on every piece, so the pair rule keeps the order of the
Gauss rule, and because every pair enters with the full bracket, the discrete
operator conserves :math:`\\sum_i c_i C_i` exactly for any :math:`c` with
:math:`\\sum_i c_i \\varphi_i \\equiv 1` or :math:`v` (and :math:`v^2` for P2).
The cost of one evaluation is O(N^2) in the number of elements, as is the
Jacobian :math:`\\partial C_i / \\partial u_j`.

Kernels take arrays and scalars only; local shape functions are those of
scikit-fem's ``ElementLineP1`` / ``ElementLineP2`` on the reference interval [0, 1]
(dofs: left vertex, right vertex, midpoint), checked against ``basis.probes`` in the
tests.
"""

from __future__ import annotations

import numpy as np

from .._jit import jit
from ..model.restitution import CONSTANT, VISCOELASTIC, restitution_value
from .fem_pair_breaks import (
    GRADING_LEVELS,
    GRADING_RATIO,
    kernel_rate,
    law_breaks,
    merge_breaks,
    pieces,
    preimage_distance,
)

__all__ = ["shape_values", "collision_operator", "evaluate_field", "kernel_rate",
           "preimage_distance", "GRADING_RATIO", "GRADING_LEVELS"]



@jit
def shape_values(order: int, xi: float, out: np.ndarray) -> None:
    """Lagrange shape functions of degree ``order`` (1 or 2) at ``xi`` in [0, 1]."""
    if order == 1:
        out[0] = 1.0 - xi
        out[1] = xi
    else:
        out[0] = 1.0 - 3.0 * xi + 2.0 * xi * xi
        out[1] = -xi + 2.0 * xi * xi
        out[2] = 4.0 * xi - 4.0 * xi * xi


@jit
def _locate(verts: np.ndarray, e: int, x: float) -> int:
    """Walk forward from element ``e`` to the element containing ``x``."""
    n_el = verts.size - 1
    while e < n_el - 1 and verts[e + 1] <= x:
        e += 1
    return e


@jit
def evaluate_field(verts: np.ndarray, dofs: np.ndarray, order: int, coef: np.ndarray,
                   x: np.ndarray) -> np.ndarray:
    """Values of the finite-element field ``coef`` at increasing points ``x``."""
    k = dofs.shape[1]
    phi = np.empty(k)
    out = np.empty(x.size)
    e = 0
    for p in range(x.size):
        e = _locate(verts, e, x[p])
        shape_values(order, (x[p] - verts[e]) / (verts[e + 1] - verts[e]), phi)
        s = 0.0
        for j in range(k):
            s += coef[dofs[e, j]] * phi[j]
        out[p] = s
    return out


@jit
def collision_operator(verts: np.ndarray, dofs: np.ndarray, order: int, coef: np.ndarray,
                       xq: np.ndarray, wq: np.ndarray, eq: np.ndarray, ref_x: np.ndarray,
                       ref_w: np.ndarray, alpha: float, density: float, with_jacobian: bool,
                       energy_power: int, symmetric: bool, gamma: float, code: int,
                       p0: float, p1: float, speed_scale: float, b_lo: float,
                       mirror: np.ndarray | None = None
                       ) -> tuple[np.ndarray, np.ndarray, float, float]:
    """Weak collision term ``C_i`` for ``P = exp(u_h)``, its Jacobian and pair moments.

    Parameters
    ----------
    verts : ndarray, shape (E + 1,)
        Increasing mesh vertices.
    dofs : ndarray of int, shape (E, k)
        Global dofs of each element (left vertex, right vertex[, midpoint]).
    order : int
        Element degree (1 or 2).
    coef : ndarray, shape (N,)
        Coefficients of :math:`u_h = \\ln P_h`.
    xq, wq, eq : ndarray, shape (Q,)
        Outer quadrature points, weights and their elements.
    ref_x, ref_w : ndarray, shape (m,)
        Reference rule on [0, 1] for the inner pieces.
    alpha, density : float
        Restitution coefficient (constant law) and number density.
    with_jacobian : bool
        Also assemble the dense Jacobian :math:`\\partial C_i/\\partial u_j`.
    energy_power : int
        ``p`` of the returned pair moment :math:`\\sum W |x-y|^p P(x) P(y)`; negative:
        neither moment is summed (both returned as 0), a few per cent faster.
    symmetric : bool
        Full bracket (exact conservation of mass, momentum and, with P2, the energy
        identity, for any P; constant laws only).  Otherwise :math:`\\varphi_i(y')` is
        replaced by :math:`\\varphi_i(x')` (equal after integration, by the x <-> y
        symmetry): mass is still conserved exactly and momentum for even P on a
        symmetric mesh, while the outer integrand stays smooth as alpha -> 1 (the
        pre-images of the vertices under y -> y' sweep past the mesh at rate
        (1+alpha)/(1-alpha)).
    gamma : float
        Kernel exponent, :math:`B(g) = |g|^\\gamma`.
    code, p0, p1 : int, float, float
        Restitution law (:func:`kinetic_fem.model.restitution_value`); with
        ``code == CONSTANT`` the coefficient is ``alpha``.
    speed_scale : float
        Physical speed of a unit of the mesh velocity (the law is evaluated at
        :math:`|x - y|` times this).
    b_lo : float
        :math:`(1 + \\min_g \\alpha(g))/2`, brackets the pre-images of a monotone law.
    mirror : ndarray of int, shape (N,), optional
        For an even :math:`u_h` on a mesh symmetric about 0: the dof at :math:`-v` of
        each dof.  The pairs with :math:`x < 0` are then the mirror images of those with
        :math:`x > 0` (breaks, pieces and rule are symmetric), so only the outer points
        :math:`x > 0` are visited and their contributions are added at the mirrored dofs
        too: half the cost, equal to the full sum to round-off.

    Returns
    -------
    residual : ndarray, shape (N,)
    jacobian : ndarray, shape (N, N) (shape (1, 1) without ``with_jacobian``)
    pair_moment : float
        :math:`\\sum W |x-y|^p P(x) P(y)`.
    loss_moment : float
        :math:`\\sum W (1 - \\alpha(g)^2) B(g) g^2 P(x) P(y)`; the collisional energy
        loss is ``density / 4`` times it.
    """
    n_dof = coef.size
    k = dofs.shape[1]
    constant = code == CONSTANT
    moments = energy_power >= 0
    fast = order == 2 and k == 3 and constant and not symmetric
    graded = (gamma != 0.0 and gamma != 1.0 and gamma != 2.0) or code == VISCOELASTIC
    a = 0.5 * (1.0 - alpha)
    b = 0.5 * (1.0 + alpha)
    res = np.zeros(n_dof)
    jac = np.zeros((n_dof, n_dof)) if with_jacobian else np.zeros((1, 1))
    # per outer point: sum of c * phi(x') over its pairs by dof (x-derivative rows) and
    # sum of c * phi(y) by dof (the y-dependence of the -phi(x) rows)
    bq = np.zeros(n_dof) if with_jacobian else np.zeros(1)
    cy = np.zeros(n_dof) if with_jacobian else np.zeros(1)
    jac_x = np.zeros((n_dof, n_dof)) if with_jacobian else np.zeros((1, 1))
    buf = np.empty(3 * verts.size + 3)
    pre = np.empty(verts.size)
    n_max = buf.size + 2 * (GRADING_LEVELS + 1)
    starts = np.empty(n_max)
    lengths = np.empty(n_max)
    phx = np.empty(k)
    phy = np.empty(k)
    ph1 = np.empty(k)
    ph2 = np.empty(k)
    # per-piece sums over its inner points (the elements of y, x', y' are fixed on a piece)
    v1 = np.empty(k)
    v2 = np.empty(k)
    vy = np.empty(k)
    m1 = np.empty((k, k))
    m2 = np.empty((k, k))
    my = np.empty((k, k))
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
        shape_values(order, (x - verts[ex]) / (verts[ex + 1] - verts[ex]), phx)
        ux = 0.0
        for j in range(k):
            ux += coef[dofs[ex, j]] * phx[j]
        px = np.exp(ux)
        if constant:
            n_br = merge_breaks(verts, x, a, b, buf, symmetric)
        else:
            n_br = law_breaks(verts, x, code, p0, p1, speed_scale, b_lo, pre, buf)
        n_p = pieces(buf, n_br, x, scale, graded, starts, lengths)
        ey = 0
        e1 = 0
        e2 = 0
        c_total = 0.0
        if with_jacobian:
            bq[:] = 0.0
            cy[:] = 0.0
        for s in range(n_p):
            y0 = starts[s]
            length = lengths[s]
            mid = y0 + 0.5 * length
            ey = _locate(verts, ey, mid)
            if constant:
                e1 = _locate(verts, e1, a * x + b * mid)
            else:
                bm = 0.5 * (1.0 + restitution_value(code, p0, p1, abs(x - mid) * speed_scale))
                target = x - bm * (x - mid)
                # x'(y) jumps back where the threshold law switches (y = x -+ g_th)
                while e1 > 0 and verts[e1] > target:
                    e1 -= 1
                e1 = _locate(verts, e1, target)
            e2 = _locate(verts, e2, b * x + a * mid)
            # inverse element lengths: one division per piece, not per point
            hy = 1.0 / (verts[ey + 1] - verts[ey])
            h1 = 1.0 / (verts[e1 + 1] - verts[e1])
            h2 = 1.0 / (verts[e2 + 1] - verts[e2])
            u0 = coef[dofs[ey, 0]]
            u1 = coef[dofs[ey, 1]]
            u2 = coef[dofs[ey, 2]] if k == 3 else 0.0
            wm = wq[q] * length * px
            if fast:
                # P2, constant alpha, reduced bracket: shape values from the piece's
                # affine maps, sums in scalars (the generic loop below in arrays)
                ty0 = (y0 - verts[ey]) * hy
                dty = length * hy
                t10 = (a * x + b * y0 - verts[e1]) * h1
                dt1 = b * length * h1
                wmd = 0.5 * density * wm
                c_piece = 0.0
                s0 = s1 = s2 = z0 = z1 = z2 = 0.0
                g00 = g01 = g02 = g10 = g11 = g12 = g20 = g21 = g22 = 0.0
                l00 = l01 = l02 = l11 = l12 = l22 = 0.0
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
                    c_piece += c
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
                v1[0] = s0
                v1[1] = s1
                v1[2] = s2
                vy[0] = z0
                vy[1] = z1
                vy[2] = z2
                if with_jacobian:
                    m1[0, 0] = g00
                    m1[0, 1] = g01
                    m1[0, 2] = g02
                    m1[1, 0] = g10
                    m1[1, 1] = g11
                    m1[1, 2] = g12
                    m1[2, 0] = g20
                    m1[2, 1] = g21
                    m1[2, 2] = g22
                    my[0, 0] = l00
                    my[0, 1] = my[1, 0] = l01
                    my[0, 2] = my[2, 0] = l02
                    my[1, 1] = l11
                    my[1, 2] = my[2, 1] = l12
                    my[2, 2] = l22
            else:
                c_piece = 0.0
                for j in range(k):
                    v1[j] = 0.0
                    v2[j] = 0.0
                    vy[j] = 0.0
                    if with_jacobian:
                        for i in range(k):
                            m1[j, i] = 0.0
                            m2[j, i] = 0.0
                            my[j, i] = 0.0
                for r in range(n_ref):
                    y = y0 + length * ref_x[r]
                    shape_values(order, (y - verts[ey]) * hy, phy)
                    uy = u0 * phy[0] + u1 * phy[1]
                    if k == 3:
                        uy += u2 * phy[2]
                    g = abs(x - y)
                    if constant:
                        al = alpha
                        x1 = a * x + b * y
                    else:
                        al = restitution_value(code, p0, p1, g * speed_scale)
                        x1 = x - 0.5 * (1.0 + al) * (x - y)
                    shape_values(order, (x1 - verts[e1]) * h1, ph1)
                    if symmetric:
                        shape_values(order, (b * x + a * y - verts[e2]) * h2, ph2)
                    w = wm * ref_w[r] * np.exp(uy)
                    rate = kernel_rate(gamma, g)
                    if moments:
                        gp = 1.0
                        for _ in range(energy_power):
                            gp *= g
                        moment += w * gp
                        loss += w * (1.0 - al * al) * rate * g * g
                    c = 0.5 * density * w * rate
                    c_piece += c
                    for j in range(k):
                        v1[j] += c * ph1[j]
                        vy[j] += c * phy[j]
                        if symmetric:
                            v2[j] += c * ph2[j]
                    if with_jacobian:
                        for j in range(k):
                            cph = c * phy[j]
                            for i in range(k):
                                m1[i, j] += ph1[i] * cph
                                my[i, j] += phy[i] * cph
                                if symmetric:
                                    m2[i, j] += ph2[i] * cph
            c_total += c_piece
            for i in range(k):
                di1 = dofs[e1, i]
                diy = dofs[ey, i]
                if symmetric:
                    di2 = dofs[e2, i]
                    res[di1] += v1[i]
                    res[di2] += v2[i]
                else:
                    res[di1] += 2.0 * v1[i]
                res[diy] -= vy[i]
                if with_jacobian:
                    if symmetric:
                        bq[di1] += v1[i]
                        bq[di2] += v2[i]
                    else:
                        bq[di1] += 2.0 * v1[i]
                    bq[diy] -= vy[i]
                    cy[diy] += vy[i]
                    for j in range(k):
                        djy = dofs[ey, j]
                        if symmetric:
                            jac[di1, djy] += m1[i, j]
                            jac[di2, djy] += m2[i, j]
                        else:
                            jac[di1, djy] += 2.0 * m1[i, j]
                        jac[diy, djy] -= my[i, j]
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
    if with_jacobian:
        jac += jac_x.T
    if mirror is not None:
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
    return res, jac, moment, loss
