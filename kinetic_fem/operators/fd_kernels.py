"""Numba kernels of the finite-difference (Biben) solver: the gain integral.

The gain term of the collision operator on the half grid :math:`v_i = i h`,
``i = 0 .. n - 1``, with the distribution mirrored to the whole line
(:math:`P(-v) = P(v)`) is

.. math::

    G_i = \\sum_k w_k\\, |v_i - v_k|^\\gamma\\, P(v_k)\\,
          \\tilde P\\Big(\\frac{2 v_i - (1-\\alpha) v_k}{1+\\alpha}\\Big) + c_i P_i^2,

a sum over the ``2n - 1`` nodes :math:`v_k = (k - n + 1) h` of the symmetric grid with
its quadrature weights :math:`w_k` and kink corrections :math:`c_k`
(:func:`kinetic_fem.operators.grid.simpson_kink_correction`, indexed at the node of
:math:`v_i`; zero for the smooth Maxwell kernel).  The kernel exponent ``power`` is
:math:`\\gamma = 1` (hard rods) or :math:`\\gamma = 0` (Maxwell).
:math:`\\tilde P` is the quadratic interpolant on the three nodes nearest its
argument (the paper; ``order=2``) or the cubic one on the four nodes around it
(``order=3``), using the symmetry at ``v = 0`` and :math:`P = 0` beyond the cut-off.
The kernels take arrays and scalars only; callers validate.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import jit

__all__ = ["interpolate_half", "gain_integral", "gain_jacobian"]


@jit
def _stencil(u, n, order, nodes, lw):
    """Lagrange stencil of ``order`` (2: three nearest nodes, 3: four nodes around the
    cell) at ``u`` (units of h, ``u >= 0``): fills ``nodes`` (mirrored at 0, -1 beyond the
    cut-off) and weights ``lw``; returns the number of nodes."""
    if order == 3:
        m = int(u)
        s = u - m
        lw[0] = -s * (s - 1.0) * (s - 2.0) / 6.0
        lw[1] = 0.5 * (s + 1.0) * (s - 1.0) * (s - 2.0)
        lw[2] = -0.5 * (s + 1.0) * s * (s - 2.0)
        lw[3] = (s + 1.0) * s * (s - 1.0) / 6.0
        first, count = m - 1, 4
    else:
        m = int(u + 0.5)
        s = u - m
        lw[0] = 0.5 * s * (s - 1.0)
        lw[1] = 1.0 - s * s
        lw[2] = 0.5 * s * (s + 1.0)
        first, count = m - 1, 3
    for q in range(count):
        node = abs(first + q)
        nodes[q] = node if node < n else -1
    return count


@jit
def _interp(p, lnp, count, nodes, lw, log_interp):
    """Interpolated value from a stencil (of ``ln p`` when all its values are positive)."""
    positive = log_interp
    for q in range(count):
        if nodes[q] < 0 or p[nodes[q]] <= 0.0:
            positive = False
    if positive:
        acc = 0.0
        for q in range(count):
            acc += lw[q] * lnp[nodes[q]]
        return math.exp(acc)
    val = 0.0
    for q in range(count):
        if nodes[q] >= 0:
            val += lw[q] * p[nodes[q]]
    return val if val > 0.0 else 0.0


@jit
def interpolate_half(p, lnp, u, log_interp, order):
    """:math:`\\tilde P` at ``|u|`` (array, in units of h) from half-grid values ``p``."""
    n = p.size
    out = np.zeros(u.size)
    nodes = np.empty(4, dtype=np.int64)
    lw = np.empty(4)
    for i in range(u.size):
        if abs(u[i]) < n:
            count = _stencil(abs(u[i]), n, order, nodes, lw)
            out[i] = _interp(p, lnp, count, nodes, lw, log_interp)
    return out


@jit
def gain_integral(p, lnp, w, corr, alpha, h, log_interp, order, power):
    """:math:`G_i` (module docstring) for ``i = 0 .. n - 1``; O(n^2); ``power`` 0 or 1."""
    n = p.size
    out = np.zeros(n)
    a = (1.0 - alpha) / (1.0 + alpha)
    b = 2.0 / (1.0 + alpha)
    nodes = np.empty(4, dtype=np.int64)
    lw = np.empty(4)
    for i in range(n):
        acc = 0.0
        for k in range(2 * n - 1):
            j = k - (n - 1)
            pk = p[abs(j)]
            if pk == 0.0:
                continue
            u = abs(b * i - a * j)
            if u >= n:
                continue
            count = _stencil(u, n, order, nodes, lw)
            kern = abs(i - j) * h if power == 1 else 1.0
            acc += w[k] * kern * pk * _interp(p, lnp, count, nodes, lw, log_interp)
        out[i] = acc + corr[n - 1 + i] * p[i] * p[i]
    return out


@jit
def gain_jacobian(p, lnp, w, corr, alpha, h, log_interp, order, power):
    """Dense Jacobian :math:`\\partial G_i / \\partial P_l` of :func:`gain_integral`.

    Both the quadrature factor :math:`P(v_k)` and the interpolated value depend on
    ``P``; for the logarithmic interpolant
    :math:`\\partial \\tilde P/\\partial P_q = \\tilde P\\, L_q / P_q`.
    """
    n = p.size
    jac = np.zeros((n, n))
    a = (1.0 - alpha) / (1.0 + alpha)
    b = 2.0 / (1.0 + alpha)
    nodes = np.empty(4, dtype=np.int64)
    lw = np.empty(4)
    for i in range(n):
        for k in range(2 * n - 1):
            j = k - (n - 1)
            u = abs(b * i - a * j)
            if u >= n:
                continue
            count = _stencil(u, n, order, nodes, lw)
            c = w[k] * abs(i - j) * h if power == 1 else w[k]
            val = _interp(p, lnp, count, nodes, lw, log_interp)
            jac[i, abs(j)] += c * val
            pk = p[abs(j)]
            use_log = log_interp
            for q in range(count):
                if nodes[q] < 0 or p[nodes[q]] <= 0.0:
                    use_log = False
            if val == 0.0 and not use_log:
                continue
            for q in range(count):
                node = nodes[q]
                if node >= 0:
                    if use_log:
                        jac[i, node] += c * pk * val * lw[q] / p[node]
                    else:
                        jac[i, node] += c * pk * lw[q]
        jac[i, i] += 2.0 * corr[n - 1 + i] * p[i]
    return jac
