"""Numba segment kernels of the homogeneous DSMC: rescaling, moments, extents.

The heated segments (thermostat kicks and Strang steps) live in
:mod:`particles._dsmc_heated`; :func:`kick` and :func:`heated_segment` are re-exported
here.  A free-cooling block (:func:`cooling_block`) rescales the velocities to unit
temperature every ``refresh`` candidates and keeps the logarithm of the scale.

The cooling refresh adds 0.6 ns per candidate (one sweep of sums and extent, and the
rescaling).
"""

from __future__ import annotations

import math

import numpy as np

from kinetic_fem.model.restitution import CONSTANT

from ._dsmc_heated import heated_segment, kick, majorant_power, measure_centred
from ._dsmc_kernels import KERNEL_HARD_RODS, KERNEL_MAXWELL, collide_model
from ._jit import jit

__all__ = ["extent", "kick", "central_sums", "sums_extent", "central_variance",
           "heated_segment", "cooling_block", "majorant_power", "measure_centred"]


@jit
def extent(v):  # pragma: no cover - compiled
    """``(min(v), max(v))``; ``max - min`` is the exact maximum of ``|v_i - v_j|``."""
    lo = v[0]
    hi = v[0]
    for k in range(1, v.shape[0]):
        x = v[k]
        if x < lo:
            lo = x
        elif x > hi:
            hi = x
    return lo, hi


@jit
def central_sums(v, kmax):  # pragma: no cover - compiled
    """Mean and central moments :math:`\\langle (v-u)^k\\rangle`, ``k = 0..kmax``.

    Four interleaved accumulators (elements ``4q + l`` in lane ``l``), so that the
    dependent additions and power products of four elements overlap.
    """
    n = v.shape[0]
    a0 = a1 = a2 = a3 = 0.0
    k = 0
    while k + 4 <= n:
        a0 += v[k]
        a1 += v[k + 1]
        a2 += v[k + 2]
        a3 += v[k + 3]
        k += 4
    while k < n:
        a0 += v[k]
        k += 1
    mean = ((a0 + a1) + (a2 + a3)) / n
    if kmax <= 6:
        return mean, _central_sums_6(v, mean, kmax)
    acc = np.zeros((kmax + 1, 4))
    k = 0
    while k + 4 <= n:
        d0 = v[k] - mean
        d1 = v[k + 1] - mean
        d2 = v[k + 2] - mean
        d3 = v[k + 3] - mean
        p0 = p1 = p2 = p3 = 1.0
        for m in range(kmax + 1):
            acc[m, 0] += p0
            acc[m, 1] += p1
            acc[m, 2] += p2
            acc[m, 3] += p3
            p0 *= d0
            p1 *= d1
            p2 *= d2
            p3 *= d3
        k += 4
    while k < n:
        d = v[k] - mean
        p = 1.0
        for m in range(kmax + 1):
            acc[m, 0] += p
            p *= d
        k += 1
    out = np.empty(kmax + 1)
    for m in range(kmax + 1):
        out[m] = ((acc[m, 0] + acc[m, 1]) + (acc[m, 2] + acc[m, 3])) / n
    return mean, out


@jit
def _central_sums_6(v, mean, kmax):  # pragma: no cover - compiled
    """Central moments ``k = 0 .. kmax`` (``kmax <= 6``) about ``mean``, sums in registers.

    An accumulator array is reloaded and stored for every element (6.3 ns per element
    at N = 25000 for ``kmax = 6``); six scalar sums run at the add throughput.
    """
    n = v.shape[0]
    c1 = c2 = c3 = c4 = c5 = c6 = 0.0
    for k in range(n):
        d1 = v[k] - mean
        d2 = d1 * d1
        c1 += d1
        c2 += d2
        if kmax > 2:
            d4 = d2 * d2
            c3 += d2 * d1
            c4 += d4
            c5 += d4 * d1
            c6 += d4 * d2
    out = np.zeros(kmax + 1)
    vals = (1.0, c1 / n, c2 / n, c3 / n, c4 / n, c5 / n, c6 / n)
    for m in range(kmax + 1):
        out[m] = vals[m]
    return out


@jit
def sums_extent(v):  # pragma: no cover - compiled
    """``(sum v, sum v^2, min v, max v)`` in one pass (four partial sums each: without
    fastmath a single accumulator is a chain of dependent additions)."""
    n = v.shape[0]
    a0 = a1 = a2 = a3 = 0.0
    q0 = q1 = q2 = q3 = 0.0
    lo = hi = v[0]
    k = 0
    while k + 4 <= n:
        x0, x1, x2, x3 = v[k], v[k + 1], v[k + 2], v[k + 3]
        a0 += x0
        a1 += x1
        a2 += x2
        a3 += x3
        q0 += x0 * x0
        q1 += x1 * x1
        q2 += x2 * x2
        q3 += x3 * x3
        lo = min(lo, min(min(x0, x1), min(x2, x3)))
        hi = max(hi, max(max(x0, x1), max(x2, x3)))
        k += 4
    while k < n:
        a0 += v[k]
        q0 += v[k] * v[k]
        lo = min(lo, v[k])
        hi = max(hi, v[k])
        k += 1
    return (a0 + a1) + (a2 + a3), (q0 + q1) + (q2 + q3), lo, hi


@jit
def central_variance(v, mean):  # pragma: no cover - compiled
    """:math:`\\langle (v - \\text{mean})^2 \\rangle` (four partial sums)."""
    n = v.shape[0]
    b0 = b1 = b2 = b3 = 0.0
    k = 0
    while k + 4 <= n:
        d0, d1, d2, d3 = v[k] - mean, v[k + 1] - mean, v[k + 2] - mean, v[k + 3] - mean
        b0 += d0 * d0
        b1 += d1 * d1
        b2 += d2 * d2
        b3 += d3 * d3
        k += 4
    while k < n:
        d = v[k] - mean
        b0 += d * d
        k += 1
    return ((b0 + b1) + (b2 + b3)) / n


@jit
def cooling_block(v, n_candidates, refresh, kcode, gamma, lcode, p0, p1, log_scale0,
                  s):  # pragma: no cover - compiled
    """``n_candidates`` candidates of free cooling with rescaling to unit temperature.

    Every ``refresh`` candidates the velocities are moved to the centre-of-mass frame
    and multiplied by ``1/sd``, ``sd`` their standard deviation (so neither the spread
    nor its ratio to the round-off of the mean can underflow), and the majorant
    ``g_max = max(v) - min(v)`` is re-measured.  Two sweeps: one for the sums of ``v``
    and ``v^2`` and the extent, one for the rescaling.  The velocities are already
    centred (momentum is conserved) except on entry, so
    :math:`\\langle v^2\\rangle - \\bar v^2` has no cancellation; when
    :math:`\\bar v^2 > 10^{-8}\\langle v^2\\rangle` a second sweep sums
    :math:`(v - \\bar v)^2` instead.  The extent of the rescaled velocities is that of
    the old ones rescaled, exactly: :math:`x \\mapsto (x - \\bar v)\\,(1/sd)` is
    monotone in floating point, as rounding is.

    Parameters
    ----------
    v : ndarray of float64, shape (N,)
        Velocities, ``exp(log_scale0)`` times the physical ones' units; updated in place.
    n_candidates, refresh : int
    kcode, gamma, lcode, p0, p1 : the model (:func:`particles._dsmc_kernels.collide_model`)
    log_scale0 : float
        Logarithm of the physical velocity per unit of ``v`` on entry (restitution laws
        are evaluated at physical relative speeds).
    s : ndarray of uint64, shape (4,)

    Returns
    -------
    accepted : int
        Number of collisions.
    log_scale : float
        :math:`-\\sum \\ln(1/sd)`: velocities on entry are ``exp(log_scale)`` times the
        returned ones.
    time : float
        :math:`\\sum_k m_k / (g_{max,k}\\, e^{\\text{log\\_scale}_k})^\\gamma`; each
        candidate advances time by :math:`2/(n N g_{max}^\\gamma)`, so the elapsed time
        is ``2 time / (n N)`` in the units of ``v`` on entry.
    """
    n = v.shape[0]
    accepted = 0
    log_scale = 0.0
    elapsed = 0.0
    done = 0
    while done < n_candidates:
        s1, s2, lo, hi = sums_extent(v)
        mean = s1 / n
        mean_sq = s2 / n
        if mean * mean <= 1e-8 * mean_sq:  # centred: no cancellation
            var = mean_sq - mean * mean
        else:
            var = central_variance(v, mean)
        if not var > 0.0:
            break  # all velocities equal: no collision can ever happen again
        inv_sd = 1.0 / math.sqrt(var)  # a multiply per velocity, not a divide
        for k in range(n):
            v[k] = (v[k] - mean) * inv_sd
        lo = (lo - mean) * inv_sd
        hi = (hi - mean) * inv_sd
        log_scale -= math.log(inv_sd)  # the factor actually applied
        m = min(refresh, n_candidates - done)
        gscale = 1.0 if lcode == CONSTANT else math.exp(log_scale0 + log_scale)
        a, _ = collide_model(v, m, kcode, gamma, lcode, p0, p1, hi - lo, gscale, s)
        accepted += a
        if kcode == KERNEL_HARD_RODS:
            elapsed += m / ((hi - lo) * math.exp(log_scale))
        elif kcode == KERNEL_MAXWELL:
            elapsed += m
        else:
            elapsed += m / ((hi - lo) * math.exp(log_scale)) ** gamma
        done += m
    return accepted, log_scale, elapsed
