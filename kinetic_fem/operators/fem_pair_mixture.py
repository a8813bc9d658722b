"""The FEM pair rule between two species of a mixture (numba kernel).

For species :math:`s` (outer, velocity :math:`x`, its own mesh and density
:math:`P_s = e^{u_s}`) colliding with species :math:`r` (inner, :math:`y`, mesh and
:math:`P_r = e^{u_r}`), the post-collision velocity of :math:`s` is linear,

.. math::

    x' = a x + b y, \\qquad b = \\mu_{sr}(1 + \\alpha_{sr}),\\ a = 1 - b,
    \\qquad \\mu_{sr} = \\frac{m_r}{m_s + m_r}

(:mod:`kinetic_fem.model.mixture`), and :func:`cross_collision` sums, on the pairs
:math:`(x_q, y)` of the one-species pair rule (:mod:`kinetic_fem.operators.fem_kernels`:
outer Gauss points of the mesh of :math:`s`, inner pieces split at the vertices of the
mesh of :math:`r`, at :math:`y = x` and at the pre-images :math:`(v_k - a x)/b` of the
vertices of the mesh of :math:`s`), with :math:`c = W\\,B(|x - y|) P_s(x) P_r(y)`,

.. math::

    R^s_i \\mathrel{+}= w_g \\sum c\\, \\varphi^s_i(x') - w_x \\sum c\\, \\varphi^s_i(x),
    \\qquad R^r_j \\mathrel{-}= w_y \\sum c\\, \\varphi^r_j(y),

and the four Jacobian blocks :math:`\\partial R^{s,r}/\\partial u_{s,r}`.  With
:math:`w_g = n x_r`, :math:`w_x = n x_r / 2` and :math:`w_y = n x_s/2` the loss of each
species is taken half from the pairs where it is the outer point and half from those
where it is the inner one, so that for one mesh and :math:`a = b = 1/2` (equal masses)
the sums over the species are the one-species reduced bracket
:math:`\\tfrac n2\\sum c\\,[2\\varphi(x') - \\varphi(x) - \\varphi(y)]` term for term (a
mixture of identical species is the one-species discretisation, to round-off).

The collision operator is truncated to the pairs whose two post-collision velocities
stay on their species' meshes: a pair :math:`(x, y)` is summed, in both orders of the
two species, exactly when :math:`x'` lies on the mesh of :math:`s` and
:math:`y' = (1 - b_r) y + b_r x` (:math:`b_r = \\mu_{rs}(1 + \\alpha_{sr})`) on the mesh
of :math:`r`, so gain and loss come from one set of pairs and each species keeps its
mass.  A heavier partner gives :math:`b > 1`, and meshes of different extents let a
light partner's velocity lie beyond the mesh: :math:`x'` then leaves the interval
between :math:`x` and :math:`y` and may leave the mesh.  With constant coefficients the
pieces split at the pre-images of the end vertices of both meshes, so every piece is
wholly kept or dropped (the rule stays exact on each piece); with a law the points are
tested one by one where no pre-image is known in closed form.  The dropped pairs carry
products of two far tails.  (Clamping :math:`x'` to the mesh's end instead put the
gain of those pairs on the last element, where it could exceed the element's own mass
by many orders of magnitude and stop a free-cooling transient at its first step.)

A velocity-dependent restitution law :math:`\\alpha_{sr}(|g|)` makes the rule nonlinear,
:math:`x' = x - \\mu_{sr}(1 + \\alpha_{sr}(|x - y|))(x - y)`; the pieces then split at
the pre-images of the outer vertices under it (:func:`cross_law_breaks`: both linear
families and the jumps of the threshold law, the monotone root of the viscoelastic
law), as the one-species law rule (:func:`~kinetic_fem.operators.fem_pair_breaks.law_breaks`).

The pairs of one species with itself (:math:`a = (1 - \\alpha)/2`, one mesh) are the
one-species reduced bracket: :func:`self_collision` sums them with the one-species P2/P3
kernel (:func:`~kinetic_fem.operators.fem_pair_fast.pair_sweep`, per-piece sums in
scalars; the same sums as :func:`cross_collision` with ``o = i`` to round-off, a quarter
less CPU per pair).
"""

from __future__ import annotations

import numpy as np

from .._jit import jit
from ..model.restitution import CONSTANT, THRESHOLD, VISCOELASTIC, restitution_value
from .fem_kernels import shape_values
from .fem_pair_breaks import (
    GRADING_LEVELS,
    kernel_graded,
    kernel_rate,
    pieces,
    preimage_distance,
)
from .fem_pair_fast import pair_sweep
from .fem_pair_sums import locate, visited_points, work_arrays

__all__ = ["cross_breaks", "cross_law_breaks", "cross_collision", "self_collision"]


@jit
def cross_breaks(verts_i: np.ndarray, verts_o: np.ndarray, x: float, a: float, b: float,
                 buf: np.ndarray) -> int:
    """Sorted breakpoints of the inner integrand in the inner mesh; returns their count.

    The inner mesh's vertices, the pre-images :math:`(v_k - a x)/b` of the outer mesh's
    vertices under :math:`y \\mapsto x'`, and :math:`y = x` (the merge of
    :func:`~kinetic_fem.operators.fem_pair_breaks.merge_breaks` with two meshes).
    """
    lo = verts_i[0]
    hi = verts_i[-1]
    ni = verts_i.size
    no = verts_o.size
    i1 = 0
    i2 = 0
    done = False
    n = 0
    inf = np.inf
    while True:
        c1 = verts_i[i1] if i1 < ni else inf
        c2 = (verts_o[i2] - a * x) / b if i2 < no else inf
        c4 = inf if done else x
        m = min(min(c1, c2), c4)
        if m == inf:
            break
        if m == c1:
            i1 += 1
        elif m == c2:
            i2 += 1
        else:
            done = True
        if m >= lo and m <= hi:
            buf[n] = m
            n += 1
    return n


@jit
def insert_break(buf: np.ndarray, n: int, value: float, lo: float, hi: float) -> int:
    """Insert ``value`` into the sorted ``buf[:n]`` if it lies in ``[lo, hi]``; returns
    the new count (``buf`` needs room for one more)."""
    if not (value > lo and value < hi):
        return n
    j = n
    while j > 0 and buf[j - 1] > value:
        buf[j] = buf[j - 1]
        j -= 1
    buf[j] = value
    return n + 1


@jit
def cross_law_breaks(verts_i: np.ndarray, verts_o: np.ndarray, x: float, mu: float,
                     code: int, p0: float, p1: float, b_lo: float, buf: np.ndarray) -> int:
    """:func:`cross_breaks` for a velocity-dependent law; returns the count.

    :math:`x' = x + \\mu(1 + \\alpha(|t|))\\,t`, :math:`t = y - x`.  The inner mesh's
    vertices, :math:`y = x` and the pre-images of the outer mesh's vertices :math:`v_k`:
    for the threshold law both linear families (:math:`b = \\mu(1 + \\alpha)` and the
    elastic :math:`b = 2\\mu`) and the jumps :math:`y = x \\pm g_{th}`; for a law with
    :math:`t\\,(1 + \\alpha(t))` increasing (viscoelastic) the root of
    :math:`|t|(1 + \\alpha(|t|))/2 = |v_k - x|/(2\\mu)`
    (:func:`~kinetic_fem.operators.fem_pair_breaks.preimage_distance`); for the
    threshold law also the pre-images of the inner mesh's ends under
    :math:`y' = x + (1 - \\mu_{rs}(1 + \\alpha))(y - x)`, :math:`\\mu_{rs} = 1 - \\mu`,
    in both families.  ``buf`` needs ``verts_i.size + 2 * verts_o.size + 7`` entries.
    """
    ni = verts_i.size
    no = verts_o.size
    n = 0
    for k in range(ni):
        buf[n] = verts_i[k]
        n += 1
    buf[n] = x
    n += 1
    if code == THRESHOLD:
        b_in = mu * (1.0 + p0)
        b_el = 2.0 * mu
        for k in range(no):
            buf[n] = x + (verts_o[k] - x) / b_in
            buf[n + 1] = x + (verts_o[k] - x) / b_el
            n += 2
        buf[n] = x - p1
        buf[n + 1] = x + p1
        n += 2
        # the inner velocity y' = x + (1 - b_r)(y - x) at the inner mesh's ends
        for b_r in ((1.0 - mu) * (1.0 + p0), 2.0 * (1.0 - mu)):
            if b_r != 1.0:
                buf[n] = x + (verts_i[0] - x) / (1.0 - b_r)
                buf[n + 1] = x + (verts_i[-1] - x) / (1.0 - b_r)
                n += 2
    else:
        for k in range(no):
            d = verts_o[k] - x
            t = preimage_distance(code, p0, p1, 1.0, abs(d) / (2.0 * mu), b_lo)
            buf[n] = x + t if d >= 0.0 else x - t
            n += 1
    merged = np.sort(buf[:n])
    lo = verts_i[0]
    hi = verts_i[-1]
    m = 0
    for j in range(n):
        if merged[j] >= lo and merged[j] <= hi:
            buf[m] = merged[j]
            m += 1
    return m


@jit
def cross_collision(verts_o: np.ndarray, dofs_o: np.ndarray, coef_o: np.ndarray,
                    xq: np.ndarray, wq: np.ndarray, eq: np.ndarray, verts_i: np.ndarray,
                    dofs_i: np.ndarray, coef_i: np.ndarray, order: int, ref_x: np.ndarray,
                    ref_w: np.ndarray, a: float, b: float, kernel: float | tuple[int, float],
                    w_gain: float, w_lossx: float, w_lossy: float, with_jacobian: bool,
                    even: bool, code: int = CONSTANT, p0: float = 0.0, p1: float = 0.0,
                    mu: float = 0.5, b_lo: float = 0.5, b_in: float = 0.5
                    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray,
                               np.ndarray, float]:
    """The pair sums of the module text for an outer and an inner species.

    Parameters
    ----------
    verts_o, dofs_o, coef_o : ndarray
        Outer species: mesh vertices, element dofs (shape (E, k)), coefficients of
        :math:`\\ln P_s`.
    xq, wq, eq : ndarray, shape (Q,)
        Outer quadrature points, weights and elements (mesh of the outer species).
    verts_i, dofs_i, coef_i : ndarray
        Inner species, the same for its mesh (same element degree).
    order : int
        Lagrange degree, 1, 2 or 3.
    ref_x, ref_w : ndarray
        Reference rule on [0, 1] for the inner pieces.
    a, b : float
        :math:`x' = a x + b y`, ``b > 0``.
    kernel : float or tuple of (int, float)
        As for :func:`~kinetic_fem.operators.fem_kernels.collision_operator`.
    w_gain, w_lossx, w_lossy : float
        Weights of the gain, the outer loss and the inner loss.
    with_jacobian : bool
        Also the Jacobian blocks (else (1, 1) placeholders).
    even : bool
        Both states even on meshes symmetric about 0: only the outer points at
        :math:`x > 0` are visited (the caller adds the mirror images).
    code, p0, p1 : int, float, float, optional
        A velocity-dependent restitution law of the pair
        (:func:`kinetic_fem.model.restitution_value`, at the physical speed
        :math:`|x - y|`): :math:`x' = x - \\mu(1 + \\alpha(|x - y|))(x - y)` replaces
        ``a, b`` (default: the constant rule ``a, b``, unchanged bit for bit).
    mu, b_lo : float, optional
        With a law: :math:`\\mu_{sr}` and :math:`(1 + \\min_g \\alpha(g))/2`.

    Returns
    -------
    res_o, res_i : ndarray, shapes (N_o,), (N_i,)
    jac_oo, jac_oi, jac_io, jac_ii : ndarray
        :math:`\\partial R^o/\\partial u_o` (stored transposed), :math:`\\partial R^o/
        \\partial u_i`, :math:`\\partial R^i/\\partial u_o` (stored transposed, shape
        (N_o, N_i)), :math:`\\partial R^i/\\partial u_i`.
    loss : float
        :math:`\\sum c\\,g^2`, the pair moment of the energy balance.
    """
    n_o = coef_o.size
    n_i = coef_i.size
    k = dofs_o.shape[1]
    constant = code == CONSTANT
    graded = kernel_graded(kernel) or code == VISCOELASTIC
    res_o = np.zeros(n_o)
    res_i = np.zeros(n_i)
    if with_jacobian:
        jxo = np.zeros((n_o, n_o))
        jac_oi = np.zeros((n_o, n_i))
        jxi = np.zeros((n_o, n_i))
        jac_ii = np.zeros((n_i, n_i))
        bqo = np.zeros(n_o)
        bqi = np.zeros(n_i)
        cy = np.zeros(n_i)
    else:
        jxo = np.zeros((1, 1))
        jac_oi = np.zeros((1, 1))
        jxi = np.zeros((1, 1))
        jac_ii = np.zeros((1, 1))
        bqo = np.zeros(1)
        bqi = np.zeros(1)
        cy = np.zeros(1)
    buf = np.empty(verts_i.size + 2 * verts_o.size + 7)
    n_max = buf.size + 2 * (GRADING_LEVELS + 1)
    starts = np.empty(n_max)
    lengths = np.empty(n_max)
    phx = np.empty(k)
    phy = np.empty(k)
    ph1 = np.empty(k)
    v1 = np.empty(k)
    vy = np.empty(k)
    m1 = np.empty((k, k))
    my = np.empty((k, k))
    n_ref = ref_x.size
    scale = verts_i[-1] - verts_i[0]
    lo_o = verts_o[0]
    hi_o = verts_o[-1]
    lo_i = verts_i[0]
    hi_i = verts_i[-1]
    mu_in = 1.0 - mu
    loss = 0.0
    for q in range(xq.size):
        x = xq[q]
        if even and x <= 0.0:
            if x == 0.0:
                raise ValueError("even needs outer points off v = 0 (a vertex at 0)")
            continue
        ex = eq[q]
        shape_values(order, (x - verts_o[ex]) / (verts_o[ex + 1] - verts_o[ex]), phx)
        ux = 0.0
        for j in range(k):
            ux += coef_o[dofs_o[ex, j]] * phx[j]
        px = np.exp(ux)
        if constant:
            n_br = cross_breaks(verts_i, verts_o, x, a, b, buf)
            if b_in != 1.0:
                # the pre-images of the inner mesh's ends under y' = (1 - b_in) y + b_in x
                n_br = insert_break(buf, n_br, (lo_i - b_in * x) / (1.0 - b_in), lo_i, hi_i)
                n_br = insert_break(buf, n_br, (hi_i - b_in * x) / (1.0 - b_in), lo_i, hi_i)
        else:
            n_br = cross_law_breaks(verts_i, verts_o, x, mu, code, p0, p1, b_lo, buf)
        n_p = pieces(buf, n_br, x, scale, graded, starts, lengths)
        ey = 0
        e1 = 0
        c_total = 0.0
        for s in range(n_p):
            y0 = starts[s]
            length = lengths[s]
            mid = y0 + 0.5 * length
            ey = locate(verts_i, ey, mid)
            if constant:
                x_mid = a * x + b * mid
                y_mid = mid + b_in * (x - mid)
                if x_mid < lo_o or x_mid > hi_o or y_mid < lo_i or y_mid > hi_i:
                    continue  # the whole piece throws a velocity off its mesh
                e1 = locate(verts_o, e1, x_mid)
            else:
                bm = mu * (1.0 + restitution_value(code, p0, p1, abs(x - mid)))
                target = min(max(x - bm * (x - mid), lo_o), hi_o)
                # x'(y) jumps back where the threshold law switches (y = x -+ g_th)
                while e1 > 0 and verts_o[e1] > target:
                    e1 -= 1
                e1 = locate(verts_o, e1, target)
            hy = 1.0 / (verts_i[ey + 1] - verts_i[ey])
            h1 = 1.0 / (verts_o[e1 + 1] - verts_o[e1])
            wm = wq[q] * length * px
            c_piece = 0.0
            for j in range(k):
                v1[j] = 0.0
                vy[j] = 0.0
                if with_jacobian:
                    for i in range(k):
                        m1[j, i] = 0.0
                        my[j, i] = 0.0
            for r in range(n_ref):
                y = y0 + length * ref_x[r]
                shape_values(order, (y - verts_i[ey]) * hy, phy)
                uy = 0.0
                for j in range(k):
                    uy += coef_i[dofs_i[ey, j]] * phy[j]
                g = abs(x - y)
                if constant:
                    x1 = min(max(a * x + b * y, lo_o), hi_o)
                else:
                    one_alpha = 1.0 + restitution_value(code, p0, p1, g)
                    x1 = x - mu * one_alpha * (x - y)
                    y1 = y - mu_in * one_alpha * (y - x)
                    if x1 < lo_o or x1 > hi_o or y1 < lo_i or y1 > hi_i:
                        continue
                shape_values(order, (x1 - verts_o[e1]) * h1, ph1)
                c = wm * ref_w[r] * np.exp(uy) * kernel_rate(kernel, g)
                loss += c * g * g
                c_piece += c
                for j in range(k):
                    v1[j] += c * ph1[j]
                    vy[j] += c * phy[j]
                if with_jacobian:
                    for j in range(k):
                        cph = c * phy[j]
                        for i in range(k):
                            m1[i, j] += ph1[i] * cph
                            my[i, j] += phy[i] * cph
            c_total += c_piece
            for i in range(k):
                di1 = dofs_o[e1, i]
                diy = dofs_i[ey, i]
                res_o[di1] += w_gain * v1[i]
                res_i[diy] -= w_lossy * vy[i]
                if with_jacobian:
                    bqo[di1] += w_gain * v1[i]
                    bqi[diy] -= w_lossy * vy[i]
                    cy[diy] += vy[i]
                    for j in range(k):
                        djy = dofs_i[ey, j]
                        jac_oi[di1, djy] += w_gain * m1[i, j]
                        jac_ii[diy, djy] -= w_lossy * my[i, j]
        for i in range(k):
            res_o[dofs_o[ex, i]] -= w_lossx * c_total * phx[i]
        if with_jacobian:
            for i in range(k):
                dix = dofs_o[ex, i]
                bqo[dix] -= w_lossx * c_total * phx[i]
                for col in range(n_i):
                    jac_oi[dix, col] -= w_lossx * phx[i] * cy[col]
            # every entry depends on u_o through P(x): the columns of x's element
            for j in range(k):
                djx = dofs_o[ex, j]
                for row in range(n_o):
                    jxo[djx, row] += bqo[row] * phx[j]
                for row in range(n_i):
                    jxi[djx, row] += bqi[row] * phx[j]
            bqo[:] = 0.0
            bqi[:] = 0.0
            cy[:] = 0.0
    return res_o, res_i, jxo, jac_oi, jxi, jac_ii, loss


@jit
def self_collision(verts: np.ndarray, dofs: np.ndarray, coef: np.ndarray, xq: np.ndarray,
                   wq: np.ndarray, eq: np.ndarray, ref_x: np.ndarray, ref_w: np.ndarray,
                   alpha: float, density: float, kernel: float | tuple[int, float],
                   with_jacobian: bool) -> tuple[np.ndarray, np.ndarray, float]:
    """The pairs of a species with itself, even sums, P2 or P3.

    :func:`cross_collision` for ``o = i`` with ``even``, ``a = (1 - alpha)/2`` and the
    weights ``w_gain = density``, ``w_lossx = w_lossy = density / 2``, summed by the
    one-species kernel (:func:`~kinetic_fem.operators.fem_pair_fast.pair_sweep`).

    Parameters
    ----------
    verts, dofs, coef : ndarray
        Mesh vertices, element dofs (3 or 4 columns), coefficients of :math:`\\ln P`.
    xq, wq, eq : ndarray
        Outer quadrature points, weights and elements.
    ref_x, ref_w : ndarray
        Reference rule on [0, 1] for the inner pieces.
    alpha : float
        Restitution coefficient of the pair, ``alpha < 1``.
    density : float
        :math:`n x_s`.
    kernel : float or tuple of (int, float)
        As for :func:`cross_collision`.
    with_jacobian : bool
        Also the Jacobian (else a (1, 1) placeholder).

    Returns
    -------
    res : ndarray, shape (N,)
        The residual of the visited half (outer points at :math:`x > 0`).
    jac : ndarray, shape (N, N)
        Its Jacobian :math:`\\partial R/\\partial u`.
    loss : float
        :math:`\\sum c\\,g^2` of the visited half (as ``cross_collision``).
    """
    n_dof = coef.size
    res, jac, bq, cy, jac_x = work_arrays(n_dof, with_jacobian)
    buf = np.empty(3 * verts.size + 3)
    starts = np.empty(buf.size + 2 * (GRADING_LEVELS + 1))
    lengths = np.empty(starts.size)
    visit = visited_points(xq, np.zeros(1, dtype=np.int64))
    none = np.zeros(1, dtype=np.int64)
    runs = np.zeros((1, 3), dtype=np.int64)
    chains = np.zeros(2)
    pair_sweep(visit, visit.size, verts, dofs, coef, xq, wq, eq, ref_x, ref_w, alpha, density,
               with_jacobian, 0, kernel, kernel_graded(kernel), -1, none, none, runs, buf,
               starts, lengths, np.empty(3 * ref_x.size), np.zeros((1, 1), dtype=np.int64),
               np.zeros((1, 1)), np.zeros((1, 1, 1, 2), dtype=np.int64),
               np.zeros((1, 1, 1, 1)), res, jac, bq, cy, jac_x, chains)
    if with_jacobian:
        jac += jac_x.T
    return res, jac, chains[1] / (1.0 - alpha * alpha)
