"""Velocity grids, quadrature weights and cumulative-moment convolutions.

Every solver takes its quadrature rules from here, so that no integral is written
twice.  A quadrature on nodes :math:`v_j` with weights :math:`w_j` approximates

.. math::

    \\int g(v)\\, dv \\approx \\sum_j w_j\\, g(v_j).

The collision operator and the quasi-elastic equations need kernels of the form

.. math::

    K_p[f](v_i) = \\sum_j w_j\\, |v_i - v_j|^p f_j, \\qquad p = 1, 3,

which are O(N) through cumulative moments: split the sum at :math:`v_i`, expand
:math:`(v_i - v_j)^p` binomially and use running sums of :math:`w_j v_j^k f_j`.
The result equals the O(N^2) double sum up to round-off.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.special import comb

__all__ = [
    "uniform_grid",
    "symmetric_grid",
    "trapezoid_weights",
    "simpson_weights",
    "abs_power_convolution",
    "moments",
    "simpson_kink_correction",
    "partial_moments",
]


def uniform_grid(cutoff: float, n_v: int) -> NDArray[np.float64]:
    """``n_v`` equally spaced nodes on ``[0, cutoff]``.

    Parameters
    ----------
    cutoff : float
        Last node (same units as the velocities of the caller).
    n_v : int
        Number of nodes, at least 2.

    Returns
    -------
    ndarray, shape (n_v,)

    Examples
    --------
    >>> uniform_grid(1.0, 5)
    array([0.  , 0.25, 0.5 , 0.75, 1.  ])
    """
    if n_v < 2:
        raise ValueError(f"a grid needs at least 2 nodes, got n_v={n_v}")
    if not cutoff > 0:
        raise ValueError(f"cutoff must be > 0, got {cutoff!r}")
    return np.linspace(0.0, float(cutoff), int(n_v))


def symmetric_grid(half: NDArray[np.float64]) -> NDArray[np.float64]:
    """Mirror nodes ``0 = v_0 < v_1 < ...`` on ``v >= 0`` to the whole line.

    Parameters
    ----------
    half : ndarray, shape (m,)
        Increasing nodes on :math:`v \\ge 0`, starting at 0.

    Returns
    -------
    ndarray, shape (2 m - 1,)
        The nodes ``-half[::-1]`` and ``half``, with 0 once.

    Examples
    --------
    >>> symmetric_grid(np.array([0.0, 1.0, 2.0]))
    array([-2., -1.,  0.,  1.,  2.])
    """
    half = np.asarray(half, dtype=float)
    if half[0] != 0.0:
        raise ValueError("the half grid must start at v = 0")
    return np.concatenate([-half[:0:-1], half])


def trapezoid_weights(v: NDArray[np.float64]) -> NDArray[np.float64]:
    """Trapezoid weights on arbitrary increasing nodes (exact for linear g).

    Parameters
    ----------
    v : ndarray, shape (n,)
        Increasing nodes, ``n >= 2``.

    Returns
    -------
    ndarray, shape (n,)
        Quadrature weights.

    Examples
    --------
    >>> trapezoid_weights(np.array([0.0, 1.0, 3.0]))
    array([0.5, 1.5, 1. ])
    """
    v = np.asarray(v, dtype=float)
    h = np.diff(v)
    if np.any(h <= 0):
        raise ValueError("grid nodes must be strictly increasing")
    w = np.zeros_like(v)
    w[:-1] += 0.5 * h
    w[1:] += 0.5 * h
    return w


def simpson_weights(v: NDArray[np.float64]) -> NDArray[np.float64]:
    """Composite Simpson weights on equally spaced nodes (exact for cubic g).

    An odd number of nodes uses Simpson's 1/3 rule throughout; an even number
    closes with Simpson's 3/8 rule on the last three intervals, so the rule stays
    fourth order.

    Parameters
    ----------
    v : ndarray, shape (n,)
        Equally spaced increasing nodes, ``n >= 3``.

    Returns
    -------
    ndarray, shape (n,)
        Weights ``w`` with :math:`\\sum_i w_i g(v_i) \\approx \\int g\\,dv`.

    Examples
    --------
    >>> simpson_weights(np.linspace(0.0, 1.0, 5)) * 12
    array([1., 4., 2., 4., 1.])
    """
    v = np.asarray(v, dtype=float)
    n = v.size
    h = (v[-1] - v[0]) / (n - 1)
    if not np.allclose(np.diff(v), h, rtol=1e-9, atol=0.0):
        raise ValueError("Simpson weights need equally spaced nodes")
    if n < 3:
        return trapezoid_weights(v)
    w = np.zeros(n)
    m = n if n % 2 == 1 else n - 3  # nodes covered by the 1/3 rule
    if m >= 3:
        w[:m:2] = 2.0
        w[1:m:2] = 4.0
        w[0] = w[m - 1] = 1.0
        w[:m] *= h / 3.0
    if n % 2 == 0:
        w[n - 4: n] += 3.0 * h / 8.0 * np.array([1.0, 3.0, 3.0, 1.0])
    return w


def abs_power_convolution(
    x: NDArray[np.float64], wf: NDArray[np.float64], power: int,
    at: NDArray[np.float64] | None = None,
) -> NDArray[np.float64]:
    """:math:`\\sum_j |a_i - x_j|^p\\, (wf)_j` in O(N + M) for odd ``power``.

    Parameters
    ----------
    x : ndarray, shape (n,)
        Increasing quadrature nodes.
    wf : ndarray, shape (n,)
        Quadrature weights times the integrand, :math:`w_j f(x_j)`.
    power : int
        Odd exponent ``p`` (1 for the collision frequency, 3 for the phi equation).
    at : ndarray, shape (m,), optional
        Increasing evaluation points :math:`a_i`; default ``x``.

    Returns
    -------
    ndarray, shape (m,)

    Notes
    -----
    With :math:`S^<_k(a) = \\sum_{x_j < a} x_j^k (wf)_j` and :math:`S_k` the full sum,

    .. math::

        \\sum_j |a - x_j|^p (wf)_j = \\sum_{k=0}^{p} \\binom{p}{k} a^{p-k} (-1)^k
        \\left(2 S^<_k(a) - S_k\\right).

    The cancellation between terms limits the relative accuracy to about
    :math:`10^{-16} \\max|x|^p / \\text{result}`; the kernels used here are of the
    order of that bound, so the loss is a few digits at most.

    Examples
    --------
    >>> x = np.array([0.0, 1.0, 2.0]); wf = np.array([1.0, 1.0, 1.0])
    >>> abs_power_convolution(x, wf, 1)
    array([3., 2., 3.])
    """
    if power % 2 != 1 or power < 1:
        raise ValueError(f"power must be a positive odd integer, got {power}")
    x = np.asarray(x, dtype=float)
    wf = np.asarray(wf, dtype=float)
    a = x if at is None else np.asarray(at, dtype=float)
    powers = np.arange(power + 1)
    xk = x[None, :] ** powers[:, None] * wf[None, :]  # (p+1, n)
    total = xk.sum(axis=1)
    cum = np.concatenate([np.zeros((power + 1, 1)), np.cumsum(xk, axis=1)], axis=1)
    # number of nodes strictly below a_i; nodes equal to a_i contribute 0 either way
    idx = np.searchsorted(x, a, side="left")
    below = cum[:, idx]  # (p+1, m)
    out = np.zeros_like(a)
    for k in powers:
        out += comb(power, k) * a ** (power - k) * (-1.0) ** k * (2.0 * below[k] - total[k])
    return out


def moments(
    v: NDArray[np.float64], p: NDArray[np.float64], w: NDArray[np.float64], orders: int
) -> NDArray[np.float64]:
    """Raw moments :math:`\\int v^k P\\, dv`, ``k = 0 .. orders``, by quadrature.

    Parameters
    ----------
    v : ndarray, shape (n,)
        Quadrature nodes (velocities).
    p : ndarray, shape (n,)
        Values of the distribution at ``v``.
    w : ndarray, shape (n,)
        Quadrature weights on ``v`` (e.g. :func:`simpson_weights`).
    orders : int
        Highest order ``k`` returned.

    Returns
    -------
    ndarray, shape (orders + 1,)
        :math:`\\int v^k P\\,dv` for ``k = 0 .. orders``.

    Examples
    --------
    >>> v = np.linspace(-1, 1, 5)
    >>> moments(v, np.full(5, 0.5), simpson_weights(v), 2).round(12) + 0.0
    array([1.        , 0.        , 0.33333333])
    """
    wp = np.asarray(w) * np.asarray(p)
    return np.array([np.sum(wp * v**k) for k in range(orders + 1)])


def simpson_kink_correction(v: NDArray[np.float64]) -> NDArray[np.float64]:
    """Node corrections making Simpson's rule fourth order for :math:`|v_i - v'|` kernels.

    Parameters
    ----------
    v : ndarray, shape (n,)
        Equally spaced nodes, ``n`` odd (Simpson's 1/3 rule throughout).

    Returns
    -------
    ndarray, shape (n,)
        :math:`c_i = h^2/3` at the panel midpoints (odd ``i``), zero elsewhere.

    Notes
    -----
    For smooth :math:`F`, :math:`\\int |v_i - v'| F(v') dv'` has a kink at the node
    :math:`v_i`.  Where :math:`v_i` is a panel boundary Simpson's rule stays fourth
    order; where it is a panel midpoint the panel
    :math:`[v_i - h, v_i + h]` gives :math:`\\tfrac23 h^2 F(v_i)` instead of
    :math:`h^2 F(v_i) + O(h^4)`, an error that alternates from node to node.  Hence

    .. math::

        \\int |v_i - v'| F(v')\\, dv' = \\sum_j w_j |v_i - v_j| F_j + c_i F_i + O(h^4).

    Examples
    --------
    >>> simpson_kink_correction(np.linspace(-1.0, 1.0, 5)) * 12
    array([0., 1., 0., 1., 0.])
    """
    v = np.asarray(v, dtype=float)
    if v.size < 3 or v.size % 2 == 0:
        raise ValueError(f"the kink correction needs an odd number (>= 3) of nodes, got {v.size}")
    h = (v[-1] - v[0]) / (v.size - 1)
    if not np.allclose(np.diff(v), h, rtol=1e-9, atol=0.0):
        raise ValueError("the kink correction needs equally spaced nodes")
    c = np.zeros_like(v)
    c[1::2] = h * h / 3.0
    return c


def partial_moments(
    x: NDArray[np.float64], wf: NDArray[np.float64], orders: int
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Cumulative moments below and above every node, each summed from its own end.

    Parameters
    ----------
    x : ndarray, shape (n,)
        Increasing quadrature nodes.
    wf : ndarray, shape (n,)
        Quadrature weights times the integrand, :math:`w_j f(x_j)`.
    orders : int
        Highest power ``k``.

    Returns
    -------
    lower, upper : ndarray, shape (orders + 1, n)
        :math:`\\sum_{j \\le i} x_j^k (wf)_j` and :math:`\\sum_{j > i} x_j^k (wf)_j`.

    Notes
    -----
    ``lower`` is a forward and ``upper`` a backward running sum, so each is accurate
    relative to its own size (a tail sum is not obtained as a difference of two
    O(1) totals).  Kernels that are polynomial on each side of the node, such as
    :math:`|x-y|^3 - (x+y)^3`, become O(N) sums of these without cancellation.

    Examples
    --------
    >>> lo, up = partial_moments(np.array([0.0, 1.0, 2.0]), np.ones(3), 1)
    >>> lo
    array([[1., 2., 3.],
           [0., 1., 3.]])
    >>> up
    array([[2., 1., 0.],
           [3., 2., 0.]])
    """
    x = np.asarray(x, dtype=float)
    terms = x[None, :] ** np.arange(orders + 1)[:, None] * np.asarray(wf, dtype=float)[None, :]
    lower = np.cumsum(terms, axis=1)
    upper = np.zeros_like(terms)
    upper[:, :-1] = np.cumsum(terms[:, :0:-1], axis=1)[:, ::-1]
    return lower, upper
