"""The orthonormal Sonine basis and the collision tensor of the Galerkin projection.

Basis: :math:`e_p(c) = S_p(c^2/2)/\\sqrt{N_p}`, :math:`S_p = L_p^{(-1/2)}`,
:math:`N_p = \\Gamma(p+1/2)/(\\sqrt\\pi\\,p!)`, orthonormal with the Gaussian weight
:math:`\\Phi(c) = e^{-c^2/2}/\\sqrt{2\\pi}`.  They are evaluated by the three-term
recurrence of the orthonormal polynomials (stable, no large alternating coefficients):

.. math::

    e_{p+1} = \\frac{2p + 1/2 - x}{\\sqrt{(p+1)(p+1/2)}}\\, e_p
            - \\sqrt{\\frac{p(p-1/2)}{(p+1)(p+1/2)}}\\, e_{p-1},\\qquad x = c^2/2.

Collision tensor, for the kernel :math:`|g|^\\gamma` and constant :math:`\\alpha`:

.. math::

    A_{qrs} = \\iint |c_1 - c_2|^\\gamma\\, \\Phi(c_1)\\Phi(c_2)\\, e_r(c_1) e_s(c_2)
        \\big[e_q(c_1') + e_q(c_2') - e_q(c_1) - e_q(c_2)\\big]\\, dc_1 dc_2,

symmetric in ``(r, s)``.  In centre-of-mass and relative velocities
:math:`C = (c_1+c_2)/2`, :math:`g = c_1 - c_2` the weight separates,
:math:`\\Phi\\Phi = e^{-C^2} e^{-g^2/4}/(2\\pi)`; the even part in ``g`` with
:math:`s = g^2/4` carries the weight :math:`2^\\gamma s^{(\\gamma-1)/2}e^{-s}`.  Gauss-Hermite
in ``C`` (``3P + 1`` nodes) and generalised Gauss-Laguerre in ``s`` (``ceil((3P+1)/2)``
nodes, exponent :math:`(\\gamma-1)/2`) integrate the polynomial remainder, of degree
``6P``, exactly: the tensor is exact up to round-off for every :math:`\\gamma`.  The
integrand is invariant under :math:`(C, g) \\to (-C, -g)` (every basis function is
even), so only the nodes :math:`C \\ge 0` are used.
"""

from __future__ import annotations

import math
from threading import Lock

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy.special import roots_hermite

from ..model.kernel import as_kernel

__all__ = ["orthonormal_sonine", "collision_tensor", "maxwell_tensor", "laplacian_coefficients",
           "dilation_coefficients", "quadrature_tensor"]

_CACHE: dict[tuple[int, float, float], NDArray[np.float64]] = {}
_LOCK = Lock()
_MAX_CACHED = 12


def orthonormal_sonine(order: int, c: ArrayLike) -> NDArray[np.float64]:
    """:math:`e_p(c)`, ``p = 0 .. order``.

    Parameters
    ----------
    order : int
    c : array_like, shape (...)
        Real, or complex (the mixture's complex-step derivatives); the result has its type.

    Returns
    -------
    ndarray, shape (order + 1, ...)

    Examples
    --------
    >>> orthonormal_sonine(2, [0.0, 1.0]).round(12)   # e_1 = (1 - c^2)/sqrt(2)
    array([[ 1.      ,  1.      ],
           [ 0.707107,  0.      ],
           [ 0.612372, -0.408248]])
    """
    c = np.asarray(c)
    c = c.astype(complex if np.iscomplexobj(c) else float)
    x = 0.5 * c * c
    out = np.empty((order + 1,) + c.shape, dtype=c.dtype)
    out[0] = 1.0
    if order >= 1:
        out[1] = (0.5 - x) * math.sqrt(2.0)
    for p in range(1, order):
        out[p + 1] = ((2 * p + 0.5 - x) * out[p] / math.sqrt((p + 1) * (p + 0.5))
                      - math.sqrt(p * (p - 0.5) / ((p + 1) * (p + 0.5))) * out[p - 1])
    return out


def laplacian_coefficients(order: int) -> NDArray[np.float64]:
    """:math:`\\kappa_q` in :math:`\\langle e_q''\\rangle_f = -\\kappa_q b_{q-1}`.

    From :math:`\\partial_c^2 S_q(c^2/2) = -(2q-1)S_{q-1}(c^2/2)`:
    :math:`\\kappa_q = \\sqrt{2q(2q-1)}` (:math:`\\kappa_0 = 0`), with
    :math:`f = \\Phi\\sum_p b_p e_p`.

    Parameters
    ----------
    order : int
        Truncation order ``P`` (coefficients ``0 .. P``).

    Returns
    -------
    ndarray, shape (order + 1,)
    """
    q = np.arange(order + 1, dtype=float)
    return np.sqrt(2.0 * q * (2.0 * q - 1.0)).clip(0.0) * (q > 0)


def dilation_coefficients(order: int) -> NDArray[np.float64]:
    """Matrix ``L`` with :math:`\\langle c\\,e_q'\\rangle_f = (L b)_q`.

    :math:`c\\,\\partial_c S_q = 2qS_q - (2q-1)S_{q-1}` gives
    :math:`(Lb)_q = 2q\\,b_q - \\kappa_q b_{q-1}`.

    Parameters
    ----------
    order : int
        Truncation order ``P`` (coefficients ``0 .. P``).

    Returns
    -------
    ndarray, shape (order + 1, order + 1)
    """
    q = np.arange(order + 1)
    mat = np.diag(2.0 * q)
    kappa = laplacian_coefficients(order)
    mat[q[1:], q[1:] - 1] = -kappa[1:]
    return mat


def quadrature_tensor(order: int, alpha: float, gamma: float) -> NDArray[np.float64]:
    """:math:`A_{qrs}` by Gauss rules with the weight :math:`|g|^\\gamma` (no cache).

    :func:`collision_tensor` caches it and uses the closed form for ``gamma = 0``; this
    function is the quadrature itself (for ``gamma = 0`` an independent check of
    :func:`maxwell_tensor`).

    Parameters
    ----------
    order : int
        Truncation order ``P``.
    alpha : float
        Coefficient of restitution.
    gamma : float
        Kernel exponent, ``0 <= gamma <= 2``.

    Returns
    -------
    ndarray, shape (order + 1, order + 1, order + 1)
    """
    n_c = 3 * order + 1
    n_s = (3 * order + 2) // 2
    xc, wc = roots_hermite(n_c)                     # weight exp(-C^2)
    # (C, g) -> (-C, -g) maps every c to -c and the basis is even: keep C >= 0
    keep = xc >= 0.0
    xc, wc = xc[keep], np.where(xc[keep] > 0.0, 2.0 * wc[keep], wc[keep])
    n_c = len(xc)
    g, ws = as_kernel(gamma).relative_speed_rule(n_s)  # the kernel's own Gauss rule
    big_c = np.repeat(xc, 2 * n_s)
    gg = np.tile(np.concatenate([g, -g]), n_c)
    weight = (1.0 / (2.0 * math.pi)) * np.repeat(wc, 2 * n_s) * np.tile(
        np.concatenate([ws, ws]), n_c)
    c1, c2 = big_c + 0.5 * gg, big_c - 0.5 * gg
    c1p, c2p = big_c - 0.5 * alpha * gg, big_c + 0.5 * alpha * gg
    e1, e2 = orthonormal_sonine(order, c1), orthonormal_sonine(order, c2)
    delta = orthonormal_sonine(order, c1p) + orthonormal_sonine(order, c2p) - e1 - e2
    tensor = np.empty((order + 1, order + 1, order + 1))
    for q in range(order + 1):
        tensor[q] = (e1 * (weight * delta[q])) @ e2.T
    return 0.5 * (tensor + tensor.transpose(0, 2, 1))


def maxwell_tensor(order: int, alpha: float) -> NDArray[np.float64]:
    """:math:`A_{qrs}` of the Maxwell kernel in closed form (all terms positive but one).

    :math:`\\Phi e_p` has the Fourier transform :math:`k^{2p}e^{-k^2/2}/\\sqrt{(2p)!}`
    (:math:`e_p \\propto He_{2p}`), and the Maxwell operator is
    :math:`\\hat Q = \\hat f(ak)\\hat f(bk) - \\hat f(k)` (``n = 1``), with
    :math:`e^{-(a^2+b^2)k^2/2} = e^{-k^2/2}e^{abk^2}`.  Reading off :math:`k^{2q}`:

    .. math::

        A_{qrs} = \\sqrt{\\frac{(2q)!}{(2r)!(2s)!}}\\,\\frac{(ab)^m}{m!}
            \\big(a^{2r}b^{2s} + a^{2s}b^{2r}\\big) - \\delta_{rq}\\delta_{s0}
            - \\delta_{r0}\\delta_{sq},\\qquad m = q - r - s \\ge 0,

    zero for :math:`r + s > q` (the moment closure).  No cancellation: exact to
    round-off at any order, where the quadrature of :func:`collision_tensor` loses
    the small entries relative to the fast-growing coefficients of the Maxwell state.

    Parameters
    ----------
    order : int
        Truncation order ``P`` (coefficients ``0 .. P``).
    alpha : float
        Coefficient of restitution.

    Returns
    -------
    ndarray, shape (order + 1, order + 1, order + 1)

    Examples
    --------
    >>> t = maxwell_tensor(2, 0.5)
    >>> bool(abs(t[1, 0, 0] - 0.75 / math.sqrt(2)) < 1e-15)  # (1-alpha^2)<g^2>/(2 sqrt 2)
    True
    """
    a, b = 0.5 * (1.0 - alpha), 0.5 * (1.0 + alpha)
    lf = [0.5 * math.lgamma(2 * p + 1.0) for p in range(order + 1)]
    tensor = np.zeros((order + 1, order + 1, order + 1))
    for q in range(order + 1):
        for r in range(q + 1):
            for s in range(q - r + 1):
                m = q - r - s
                pref = math.exp(lf[q] - lf[r] - lf[s] - math.lgamma(m + 1.0))
                tensor[q, r, s] = pref * (a * b) ** m * (a ** (2 * r) * b ** (2 * s)
                                                         + a ** (2 * s) * b ** (2 * r))
        tensor[q, q, 0] -= 1.0
        tensor[q, 0, q] -= 1.0
    return tensor


def collision_tensor(order: int, alpha: float, gamma: float) -> NDArray[np.float64]:
    """:math:`A_{qrs}`, ``q, r, s = 0 .. order`` (see the module docstring).

    Tensors are cached per ``(order, alpha, gamma)``, every input: the quadrature's
    rule grows with the order, so a lower order's tensor is not bitwise the leading
    block of a higher one's (a2 moved by 6e-16 when the cache held order 10), and a
    result would depend on the calls before it (issue 26).  For ``gamma = 0`` the
    closed form :func:`maxwell_tensor` is used.

    Parameters
    ----------
    order : int
        Truncation order ``P`` (coefficients ``0 .. P``).
    alpha : float
        Coefficient of restitution.
    gamma : float
        Kernel exponent, ``0 <= gamma <= 2``.

    Returns
    -------
    ndarray, shape (order + 1, order + 1, order + 1)

    Examples
    --------
    Energy loss of the Gaussian, :math:`A_{100} = (1-\\alpha^2)\\langle|g|^{\\gamma+2}\\rangle
    /(2\\sqrt2)` with :math:`\\langle g^2\\rangle = 2` for Maxwell molecules:

    >>> a = collision_tensor(2, 0.5, 0.0)
    >>> bool(abs(a[1, 0, 0] - 0.75 * 2 / (2 * math.sqrt(2))) < 1e-15)
    True
    """
    key = (int(order), float(alpha), float(gamma))
    with _LOCK:
        cached = _CACHE.get(key)
    if cached is not None:
        return cached
    if as_kernel(gamma).is_maxwell:
        tensor = maxwell_tensor(order, float(alpha))
    else:
        tensor = quadrature_tensor(order, float(alpha), float(gamma))
    with _LOCK:
        if len(_CACHE) >= _MAX_CACHED and key not in _CACHE:
            _CACHE.pop(next(iter(_CACHE)))
        _CACHE[key] = tensor
    return tensor
