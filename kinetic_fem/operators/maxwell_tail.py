"""The analytic :math:`c^{-4}` tail closure of the inelastic Maxwell model's cooling state.

Beyond the cut-off :math:`V` of the mesh the cooling state of the Maxwell kernel
(:math:`\\gamma = 0`) is continued by its asymptotic power law

.. math::

    f_T(c) = A\\, g(|c|), \\qquad g(c) = c^{-4}\\left(1 - \\frac{2T}{c^2}
    + \\frac{3T^2}{c^4}\\right),
    \\qquad |c| > V,

with :math:`\\ln A` the mean of :math:`\\ln f_h - \\ln g` over the last element (the
Galerkin oscillation of :math:`\\ln f_h`, largest at the vertices, has zero mean
there; matching the vertex value put 4.5e-4 into :math:`A` at alpha = 0.99, V = 50, the
mean 1.6e-4).  The :math:`c^{-6}` and :math:`c^{-8}` coefficients are not fitted: the
scaled equation fixes them.  In Fourier space (:math:`\\hat f(k) = \\int f e^{ikc}`) it
reads :math:`-\\zeta k \\hat f'(k) = \\hat f(ak)\\hat f(bk) - \\hat f(k)`
(:math:`a = (1-\\alpha)/2`, :math:`b = 1 - a`, :math:`\\zeta = ab`); with
:math:`\\hat f = 1 - Tk^2/2 + c_3|k|^3 + c_4k^4 + c_5|k|^5 + \\dots` the power
:math:`k^n` gives :math:`c_n(1 - n ab - a^n - b^n) = ` (products of lower
coefficients).  For :math:`n = 3` the bracket vanishes (:math:`c_3`, i.e. :math:`A`, is
free); :math:`n = 4, 5, 7` give :math:`c_4 = -T^2/8`, :math:`c_5 = T c_3/10`,
:math:`c_7 = T^2 c_3/280` for every alpha, and the odd powers are the tail:
:math:`|k|^\\nu \\leftrightarrow -\\Gamma(\\nu+1)\\sin(\\pi\\nu/2)/\\pi\\, |c|^{-\\nu-1}`,
so :math:`f \\simeq \\tfrac{6c_3}{\\pi} c^{-4}(1 - 2T c^{-2} + 3T^2 c^{-4})`.  (The closed
form :math:`2/(\\pi(1+c^2)^2)` has this expansion; the next odd coefficient, :math:`c_9`,
depends on :math:`c_3^3` and is left out: relative :math:`4V^{-6}`.)  The zeta error of
the closure falls as :math:`V^{-4}` (P2, h0 = 0.02, alpha = 0.5: 1.2e-8, 7.4e-10 at
V = 50, 100; P3 at V = 200: 1e-11 ... 1.4e-10 over alpha), hence the default
V = 200 (:mod:`kinetic_fem.solvers.fem.cooling_maxwell`).

The tail enters the equations of the mesh by four terms, each in closed form or by an
exact product rule (:func:`tail_gain_matrix`):

* the mass :math:`m_T = 2A\\int_V^\\infty g` and energy :math:`e_T = 2A\\int_V^\\infty
  c^2 g` in the two constraints;
* the loss of mesh particles colliding with tail particles (rate 1 per unit partner
  mass for the Maxwell kernel): :math:`-m_T\\int\\varphi_i f_h`;
* the gain of mesh velocities from (mesh, tail) pairs,
  :math:`A\\int f_h(x)\\,K_i(x)\\,dx` with
  :math:`K_i(x) = \\int_{|y|>V} g(|y|)[\\varphi_i(ax + by) + \\varphi_i(bx + ay)]\\,dy`,
  a fixed kernel of the mesh (the tail feeds the outer mesh from
  :math:`c/a`: at :math:`\\alpha = 0.999` from 2000 times farther out, which is why a
  truncated mesh had to reach :math:`10^8`);
* (tail, tail) pairs landing in the mesh are left out: their rate is
  :math:`O(A^2 V^{-6})`, below 1e-13 at :math:`V = 200`.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from .._jit import jit

__all__ = ["TAIL_B6", "TAIL_B8", "tail_shape", "tail_moments", "tail_gain_matrix",
           "tail_quadrature"]

TAIL_B6 = -2.0
"""Coefficient of :math:`c^{-6}` in :math:`g` at unit temperature (module notes)."""
TAIL_B8 = 3.0
"""Coefficient of :math:`c^{-8}` in :math:`g` at unit temperature (module notes)."""
_GAUSS_X, _GAUSS_W = np.polynomial.legendre.leggauss(8)
_GAUSS_S = np.ascontiguousarray(0.5 * (_GAUSS_X + 1.0))
_GAUSS_WS = np.ascontiguousarray(0.5 * _GAUSS_W)
_SMALL_PIECE = 0.25
"""Pieces with :math:`\\Delta/y_{lo}` below this are integrated by 8-point Gauss-Legendre
(error ~1e-20); longer ones by the closed-form power integrals."""


def tail_shape(c: NDArray | float) -> NDArray[np.float64]:
    """:math:`g(c) = c^{-4}(1 - 2c^{-2} + 3c^{-4})` (unit temperature).

    Parameters
    ----------
    c : float or ndarray
        Speeds :math:`|c| > 1`.

    Returns
    -------
    ndarray
        :math:`g(c)` (0-d for a float ``c``).
    """
    c2 = np.asarray(c, dtype=float) ** 2
    return (1.0 + TAIL_B6 / c2 + TAIL_B8 / (c2 * c2)) / (c2 * c2)


def tail_moments(cutoff: float) -> tuple[float, float]:
    """:math:`\\int_V^\\infty g` and :math:`\\int_V^\\infty c^2 g` (one side).

    Parameters
    ----------
    cutoff : float
        :math:`V`.

    Returns
    -------
    tuple of float
        The mass and energy of :math:`g` beyond :math:`V`.

    Examples
    --------
    >>> m, e = tail_moments(50.0)
    >>> round(m * 3 * 50.0**3, 6), round(e * 50.0, 6)
    (0.99952, 0.999733)
    """
    v = float(cutoff)
    return (1.0 / (3.0 * v**3) + TAIL_B6 / (5.0 * v**5) + TAIL_B8 / (7.0 * v**7),
            1.0 / v + TAIL_B6 / (3.0 * v**3) + TAIL_B8 / (5.0 * v**5))


@jit
def _power_integral(p: int, lo: float, hi: float) -> float:
    """:math:`\\int_{lo}^{hi} y^{p} dy` for :math:`0 < lo < hi`."""
    if p == -1:
        return math.log(hi / lo)
    return (hi ** (p + 1) - lo ** (p + 1)) / (p + 1)


@jit
def _piece_moments(lo: float, hi: float, n_mom: int, gs: np.ndarray, gw: np.ndarray,
                   b6: float, b8: float, out: np.ndarray) -> None:
    """``out[j]`` = :math:`\\int_{lo}^{hi} s^j g(y)\\,dy`, :math:`s = (y - lo)/(hi - lo)`."""
    delta = hi - lo
    for j in range(n_mom):
        out[j] = 0.0
    if delta < 0.25 * lo:
        for r in range(gs.size):
            y = lo + delta * gs[r]
            y2 = y * y
            w = gw[r] * delta * (1.0 + b6 / y2 + b8 / (y2 * y2)) / (y2 * y2)
            sp = 1.0
            for j in range(n_mom):
                out[j] += w * sp
                sp *= gs[r]
        return
    # closed form: (y - lo)^j by the binomial theorem, y^l g = y^(l-4) + b6 y^(l-6) + ...
    for j in range(n_mom):
        acc = 0.0
        binom = 1.0
        for m in range(j + 1):
            # term C(j, m) (-lo)^(j - m) y^m
            coef = binom * (-lo) ** (j - m)
            acc += coef * (_power_integral(m - 4, lo, hi) + b6 * _power_integral(m - 6, lo, hi)
                           + b8 * _power_integral(m - 8, lo, hi))
            binom = binom * (j - m) / (m + 1)
        out[j] = acc / delta**j


@jit
def _shape(order: int, t: float, out: np.ndarray) -> None:
    """Lagrange shape functions of scikit-fem's P1/P2 and the package's P3 at ``t``."""
    if order == 1:
        out[0] = 1.0 - t
        out[1] = t
    elif order == 2:
        out[0] = 1.0 - 3.0 * t + 2.0 * t * t
        out[1] = -t + 2.0 * t * t
        out[2] = 4.0 * t - 4.0 * t * t
    else:
        d1 = t - 1.0 / 3.0
        d2 = t - 2.0 / 3.0
        d3 = t - 1.0
        out[0] = -4.5 * d1 * d2 * d3
        out[1] = 4.5 * t * d1 * d2
        out[2] = 13.5 * t * d2 * d3
        out[3] = -13.5 * t * d1 * d3


@jit
def _tail_gain(verts: np.ndarray, dofs: np.ndarray, order: int, xq: np.ndarray,
               alpha: float, cutoff: float, lagrange: np.ndarray, gs: np.ndarray,
               gw: np.ndarray, b6: float, b8: float) -> np.ndarray:
    n_el, k = dofs.shape
    n_dof = dofs.max() + 1
    out = np.zeros((n_dof, xq.size))
    a = 0.5 * (1.0 - alpha)
    b = 1.0 - a
    mom = np.empty(k)
    wts = np.empty(k)
    phi = np.empty(k)
    for q in range(xq.size):
        x = xq[q]
        for m in range(2):
            s = b if m == 0 else a
            c0 = (a if m == 0 else b) * x
            for side in range(2):
                sign = 1.0 if side == 0 else -1.0
                # z = c0 + sign * s * w, w > V: z beyond c0 + sign * s * V
                edge = c0 + sign * s * cutoff
                for e in range(n_el):
                    z0 = verts[e]
                    z1 = verts[e + 1]
                    if sign > 0.0:
                        if z1 <= edge:
                            continue
                        w_lo = max((z0 - c0) / s, cutoff)
                        w_hi = (z1 - c0) / s
                    else:
                        if z0 >= edge:
                            continue
                        w_lo = max((c0 - z1) / s, cutoff)
                        w_hi = (c0 - z0) / s
                    if w_hi <= w_lo:
                        continue
                    _piece_moments(w_lo, w_hi, k, gs, gw, b6, b8, mom)
                    # product rule exact for polynomials of degree order in w
                    for i in range(k):
                        acc = 0.0
                        for j in range(k):
                            acc += lagrange[i, j] * mom[j]
                        wts[i] = acc
                    h = z1 - z0
                    for node in range(k):
                        w_node = w_lo + (w_hi - w_lo) * node / order
                        t = (c0 + sign * s * w_node - z0) / h
                        _shape(order, t, phi)
                        for i in range(k):
                            out[dofs[e, i], q] += wts[node] * phi[i]
    return out


def _lagrange_coefficients(order: int) -> NDArray[np.float64]:
    """``L[m, j]``: coefficient of :math:`s^j` of the Lagrange polynomial of node
    :math:`m/\\text{order}` on the equispaced nodes of [0, 1]."""
    nodes = np.arange(order + 1) / order
    vander = np.vander(nodes, order + 1, increasing=True)  # V[m, j] = s_m^j
    return np.ascontiguousarray(np.linalg.inv(vander).T)


def tail_gain_matrix(verts: NDArray, dofs: NDArray, order: int, xq: NDArray, alpha: float,
                     cutoff: float) -> NDArray[np.float64]:
    """``K[i, q]`` :math:`= \\int_{|y|>V} g(|y|)[\\varphi_i(a x_q + b y) +
    \\varphi_i(b x_q + a y)]\\,dy` (module notes).

    Each (outer point, element, map, side) piece is integrated in :math:`w = |y|` by a
    product rule exact for :math:`g` times polynomials of degree ``order`` (the test
    function in :math:`w`): the moments :math:`\\int s^j g` in closed form, or by
    8-point Gauss-Legendre on short pieces where the closed form would cancel.

    Parameters
    ----------
    verts : ndarray
        Mesh vertices (increasing, :math:`\\pm V` at the ends).
    dofs : ndarray of int, shape (n_el, order + 1)
        Element dofs (scikit-fem order: vertices, then interior).
    order : int
        Lagrange degree, 1 to 3.
    xq : ndarray
        Outer quadrature points.
    alpha : float
        Restitution coefficient.
    cutoff : float
        :math:`V`.

    Returns
    -------
    ndarray, shape (n_dof, xq.size)
    """
    if order not in (1, 2, 3):
        raise ValueError(f"order must be 1, 2 or 3, got {order!r}")
    return _tail_gain(np.ascontiguousarray(verts, dtype=float),
                      np.ascontiguousarray(dofs, dtype=np.int64), int(order),
                      np.ascontiguousarray(xq, dtype=float), float(alpha), float(cutoff),
                      _lagrange_coefficients(order), _GAUSS_S, _GAUSS_WS, TAIL_B6, TAIL_B8)


def tail_quadrature(cutoff: float, *, ratio: float = 1.05, far: float = 1e8,
                    points: int = 4) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Nodes and weights on :math:`(V, \\infty)` exact for the tail's mass and energy.

    In :math:`s = V/c` the integrands :math:`g\\,dc` and :math:`c^2 g\\,dc` are
    polynomials in :math:`s` (of degree 6 and 4), so Gauss-Legendre with ``points``
    nodes on every piece of a partition of :math:`s \\in (0, 1]` integrates them
    exactly; the pieces are geometric in :math:`c` (ratio ``ratio``) out to ``far``,
    then one piece to :math:`c = \\infty`.

    Parameters
    ----------
    cutoff : float
        :math:`V`.
    ratio : float
        Ratio of the piece ends in :math:`c`.
    far : float
        Last piece end before the one to infinity.
    points : int
        Gauss points per piece (>= 4 for exactness).

    Returns
    -------
    c, w : ndarray
        Increasing nodes :math:`> V` and weights (for :math:`\\int_V^\\infty h(c)\\,dc`).

    Examples
    --------
    >>> c, w = tail_quadrature(50.0)
    >>> m, e = tail_moments(50.0)
    >>> g = tail_shape(c)
    >>> bool(abs(w @ g / m - 1) < 1e-13 and abs(w @ (c**2 * g) / e - 1) < 1e-13)
    True
    """
    n = max(1, math.ceil(math.log(far / cutoff) / math.log(ratio)))
    ends = np.append(cutoff / np.geomspace(cutoff, far, n + 1), 0.0)  # s, decreasing
    gx, gw = np.polynomial.legendre.leggauss(points)
    s_hi, s_lo = ends[:-1], ends[1:]
    half = 0.5 * (s_hi - s_lo)
    s = (0.5 * (s_hi + s_lo))[:, None] + half[:, None] * gx[None, :]
    ws = half[:, None] * gw[None, :]
    c = cutoff / s
    w = ws * cutoff / s**2
    order = np.argsort(c.ravel())
    return c.ravel()[order], w.ravel()[order]
