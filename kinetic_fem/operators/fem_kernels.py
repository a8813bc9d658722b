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
    kernel_graded,
    kernel_rate,
    law_breaks,
    merge_breaks,
    pieces,
    preimage_distance,
)
from .fem_pair_fast import collision_constant, finish_collision

# numba caches this module's kernels with kernel_rate compiled in: edit this file too when
# kernel_rate changes (a stale cache keeps the old rule; gamma = 1/2 by sqrt since issue 16)
__all__ = ["shape_values", "collision_operator", "evaluate_field", "kernel_rate",
           "preimage_distance", "GRADING_RATIO", "GRADING_LEVELS"]



@jit
def shape_values(order: int, xi: float, out: np.ndarray) -> None:
    """Lagrange shape functions of degree ``order`` (1, 2 or 3) at ``xi`` in [0, 1]."""
    if order == 1:
        out[0] = 1.0 - xi
        out[1] = xi
    elif order == 3:
        d1 = xi - 1.0 / 3.0
        d2 = xi - 2.0 / 3.0
        d3 = xi - 1.0
        out[0] = -4.5 * d1 * d2 * d3
        out[1] = 4.5 * xi * d1 * d2
        out[2] = 13.5 * xi * d2 * d3
        out[3] = -13.5 * xi * d1 * d3
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
                       energy_power: int, symmetric: bool, kernel: float | tuple[int, float],
                       code: int, p0: float, p1: float, speed_scale: float, b_lo: float,
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
    kernel : float or tuple of (int, float)
        The exponent of a power law, or another kernel's ``(family, parameter)``
        (:attr:`kinetic_fem.model.kernel_base.CollisionKernel.numeric`), evaluated by
        :func:`~kinetic_fem.operators.fem_pair_breaks.kernel_rate` (numba compiles one
        loop per type: the power-law loop is unchanged).
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
    graded = kernel_graded(kernel) or code == VISCOELASTIC
    if order >= 2 and constant and not symmetric:
        # P2/P3, constant alpha, reduced bracket: per-piece sums in scalars
        return collision_constant(verts, dofs, coef, xq, wq, eq, ref_x, ref_w, alpha, density,
                                  with_jacobian, energy_power, kernel, graded, mirror)
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
            u2 = coef[dofs[ey, 2]] if k >= 3 else 0.0
            wm = wq[q] * length * px
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
                if k >= 3:
                    uy += u2 * phy[2]
                for j in range(3, k):
                    uy += coef[dofs[ey, j]] * phy[j]
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
                rate = kernel_rate(kernel, g)
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
    return finish_collision(res, jac, jac_x, with_jacobian, moment, loss, mirror)
