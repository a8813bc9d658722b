"""Richardson extrapolation of second-order grid solutions (the finite-difference solvers).

A quantity computed on grids of spacing :math:`h, h/2, h/4` with an error expansion
:math:`Q_h = Q + c_2 h^2 + c_4 h^4 + \\dots` is extrapolated level by level,

.. math::

    R_1(h) = \\frac{4 Q_{h/2} - Q_h}{3}, \\qquad R_2(h) = \\frac{16 R_1(h/2) - R_1(h)}{15},

with :math:`Q = \\ln P` on the nodes of the coarsest grid for distributions (positive,
accurate relative to the tail) and :math:`Q` itself for scalars (the cooling rate).

The solvers return the next-to-best value (:math:`Q_{h/2}` with two grids,
:math:`R_1(h/2)` with three) and its difference from the most extrapolated one as its
error estimate: in the asymptotic regime that difference *is* the error of the
next-to-best value (the most extrapolated one is far more accurate), so the estimate is
calibrated (true/estimated 0.86-1.37 in T, a2 and f over five heated problems against
FEM P3, ``benchmarks/calibrate_error_estimates.py``; the cooling solver compares the
levels on the even coarse nodes only, :func:`kinetic_fem.solvers.fd_cooling.solve_fd_cooling`).
The most extrapolated value
itself has no estimate from these grids: measured at alpha = 0.6 (hard rods, white
noise) :math:`|R_2(h) - R_1(h/2)|` overstates the error of :math:`R_2(h)` by 100-170
times, and a fourth, coarser grid (:math:`R_3(2h)` against :math:`R_2(h)`) misses it by
up to 9 times (alpha = 0, 0.99), where :math:`R_2(h)` meets an error floor near 1e-10
that extrapolation does not see (issue 29).
"""

from __future__ import annotations

from typing import Sequence

import numpy as np
from numpy.typing import NDArray

__all__ = ["extrapolate_log", "richardson_log", "richardson_scalar", "RICHARDSON_METHOD"]

RICHARDSON_METHOD = "Richardson levels (the result against the one more extrapolated)"
"""``dist.error.method`` of the finite-difference solvers."""


def extrapolate_log(coarse: NDArray[np.float64], fine: NDArray[np.float64], weight: float
                    ) -> NDArray[np.float64]:
    """:math:`\\exp[(w \\ln P_{fine} - \\ln P_{coarse})/(w - 1)]` (fine values where either is 0).

    Parameters
    ----------
    coarse, fine : ndarray, shape (n,)
        Positive (or zero) values at the same nodes from the coarse and the fine grid.
    weight : float
        :math:`w = 2^p` for a method of order ``p`` and a spacing ratio of 2.

    Returns
    -------
    ndarray, shape (n,)

    Examples
    --------
    >>> extrapolate_log(np.array([np.e, 0.0]), np.array([1.0, 2.0]), 4.0)
    array([0.71653131, 2.        ])
    """
    out = np.array(fine, dtype=float)
    ok = (fine > 0) & (coarse > 0)
    out[ok] = np.exp((weight * np.log(fine[ok]) - np.log(coarse[ok])) / (weight - 1.0))
    return out


def richardson_log(values: Sequence[NDArray[np.float64]]
                   ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Extrapolated positive values from 2 or 3 nested grids, and the next best values.

    Parameters
    ----------
    values : sequence of ndarray, shapes (n,), (2n - 1,), (4n - 3,)
        Nodal values on grids of spacing ``h``, ``h/2`` (and ``h/4``) sharing the
        coarse nodes.

    Returns
    -------
    best, previous : ndarray, shape (n,)
        :math:`R_1(h)` and :math:`P_{h/2}`, or :math:`R_2(h)` and :math:`R_1(h/2)`, on
        the coarse nodes.
    """
    on_coarse = [np.asarray(v)[:: 2**k] for k, v in enumerate(values)]
    if len(values) == 2:
        return extrapolate_log(on_coarse[0], on_coarse[1], 4.0), on_coarse[1]
    if len(values) != 3:
        raise ValueError(f"Richardson extrapolation takes 2 or 3 grids, got {len(values)}")
    r01 = extrapolate_log(on_coarse[0], on_coarse[1], 4.0)
    r12 = extrapolate_log(on_coarse[1], on_coarse[2], 4.0)
    return extrapolate_log(r01, r12, 16.0), r12


def richardson_scalar(values: Sequence[float]) -> tuple[float, float]:
    """:func:`richardson_log` for a scalar, extrapolated linearly (not in its log).

    Parameters
    ----------
    values : sequence of float
        The quantity on grids of spacing ``h``, ``h/2`` (and ``h/4``).

    Returns
    -------
    best, previous : float
        The extrapolation from all grids and the next best one (its difference is an
        error estimate).

    Examples
    --------
    >>> best, prev = richardson_scalar([1.0 + 0.04, 1.0 + 0.01, 1.0 + 0.0025])
    >>> round(best, 14), round(prev, 14)
    (1.0, 1.0)
    """
    q = [float(v) for v in values]
    if len(q) == 2:
        return (4.0 * q[1] - q[0]) / 3.0, q[1]
    if len(q) != 3:
        raise ValueError(f"Richardson extrapolation takes 2 or 3 grids, got {len(q)}")
    r01 = (4.0 * q[1] - q[0]) / 3.0
    r12 = (4.0 * q[2] - q[1]) / 3.0
    return (16.0 * r12 - r01) / 15.0, r12
