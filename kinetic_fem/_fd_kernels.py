"""Numba kernels of the finite-difference (Biben) solver: the gain integral.

The gain term of the collision operator on the half grid :math:`v_i = i h`,
``i = 0 .. n - 1``, with the distribution mirrored to the whole line
(:math:`P(-v) = P(v)`) is

.. math::

    G_i = \\sum_k w_k\\, |v_i - v_k|\\, P(v_k)\\,
          \\tilde P\\Big(\\frac{2 v_i - (1-\\alpha) v_k}{1+\\alpha}\\Big) + c_i P_i^2,

a sum over the ``2n - 1`` nodes :math:`v_k = (k - n + 1) h` of the symmetric grid with
its quadrature weights :math:`w_k` and kink corrections :math:`c_k`
(:func:`kinetic_fem.grid.simpson_kink_correction`, indexed at the node of
:math:`v_i`).  :math:`\\tilde P` is the quadratic interpolant on the three nodes
nearest its argument, using the symmetry at ``v = 0`` and :math:`P = 0` beyond the
cut-off.  The kernels take arrays and scalars only; callers validate.
"""

from __future__ import annotations

import math

import numpy as np

from ._jit import jit

__all__ = ["interpolate_half", "gain_integral", "gain_jacobian"]


@jit
def _stencil(p, u, n):
    """Nearest node ``m`` of ``u`` (in units of h), offset ``s`` and the three values."""
    m = int(u + 0.5)
    s = u - m
    pm = p[m - 1] if m >= 1 else p[1]
    p0 = p[m] if m < n else 0.0
    pp = p[m + 1] if m + 1 < n else 0.0
    return m, s, pm, p0, pp


@jit
def _interp(p, lnp, u, n, log_interp):
    """Quadratic interpolation of ``p`` (or of ``ln p``) at ``u`` h, ``u >= 0``."""
    if u >= n:
        return 0.0
    m, s, pm, p0, pp = _stencil(p, u, n)
    lm = 0.5 * s * (s - 1.0)
    l0 = 1.0 - s * s
    lp = 0.5 * s * (s + 1.0)
    if log_interp and pm > 0.0 and p0 > 0.0 and pp > 0.0:
        lnm = lnp[m - 1] if m >= 1 else lnp[1]
        return math.exp(lm * lnm + l0 * lnp[m] + lp * lnp[m + 1])
    val = lm * pm + l0 * p0 + lp * pp
    return val if val > 0.0 else 0.0


@jit
def interpolate_half(p, lnp, u, log_interp):
    """:math:`\\tilde P` at ``|u|`` (array, in units of h) from half-grid values ``p``."""
    n = p.size
    out = np.empty(u.size)
    for i in range(u.size):
        out[i] = _interp(p, lnp, abs(u[i]), n, log_interp)
    return out


@jit
def gain_integral(p, lnp, w, corr, alpha, h, log_interp):
    """:math:`G_i` (module docstring) for ``i = 0 .. n - 1``; O(n^2)."""
    n = p.size
    out = np.zeros(n)
    a = (1.0 - alpha) / (1.0 + alpha)
    b = 2.0 / (1.0 + alpha)
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
            acc += w[k] * abs(i - j) * h * pk * _interp(p, lnp, u, n, log_interp)
        out[i] = acc + corr[n - 1 + i] * p[i] * p[i]
    return out


@jit
def gain_jacobian(p, lnp, w, corr, alpha, h, log_interp):
    """Dense Jacobian :math:`\\partial G_i / \\partial P_l` of :func:`gain_integral`.

    Both the quadrature factor :math:`P(v_k)` and the interpolated value depend on
    ``P``; for the logarithmic interpolant
    :math:`\\partial \\tilde P/\\partial P_q = \\tilde P\\, L_q / P_q`.
    """
    n = p.size
    jac = np.zeros((n, n))
    a = (1.0 - alpha) / (1.0 + alpha)
    b = 2.0 / (1.0 + alpha)
    lw = np.empty(3)
    nodes = np.empty(3, dtype=np.int64)
    for i in range(n):
        for k in range(2 * n - 1):
            j = k - (n - 1)
            u = abs(b * i - a * j)
            if u >= n:
                continue
            m, s, pm, p0, pp = _stencil(p, u, n)
            lw[0] = 0.5 * s * (s - 1.0)
            lw[1] = 1.0 - s * s
            lw[2] = 0.5 * s * (s + 1.0)
            nodes[0] = m - 1 if m >= 1 else 1
            nodes[1] = m
            nodes[2] = m + 1
            c = w[k] * abs(i - j) * h
            val = _interp(p, lnp, u, n, log_interp)
            jac[i, abs(j)] += c * val
            pk = p[abs(j)]
            use_log = log_interp and pm > 0.0 and p0 > 0.0 and pp > 0.0
            if val == 0.0 and not use_log:
                continue
            for q in range(3):
                node = nodes[q]
                if node < n:
                    if use_log:
                        jac[i, node] += c * pk * val * lw[q] / p[node]
                    else:
                        jac[i, node] += c * pk * lw[q]
        jac[i, i] += 2.0 * corr[n - 1 + i] * p[i]
    return jac
