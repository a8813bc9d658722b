"""Numba segment kernels of the homogeneous DSMC: rescaling, moments, extents.

The heated segments (thermostat kicks and Strang steps) live in
:mod:`particles._dsmc_heated`; :func:`kick` and :func:`heated_segment` are re-exported
here.  A free-cooling block (:func:`cooling_block`) rescales the velocities to unit
temperature every ``refresh`` candidates and keeps the logarithm of the scale.
The free-cooling runs use :func:`cooling_segment`: it re-measures only the extent
every ``refresh`` candidates (one vectorised pass) and rescales only when the extent
has shrunk by ``2^10``, and it runs until a number of collisions is reached.

The cooling refresh of :func:`cooling_block` adds 0.6 ns per candidate (one sweep of
sums and extent, and the rescaling).
"""

from __future__ import annotations

import math

import numpy as np

from kinetic_fem.model.restitution import CONSTANT

from ._dsmc_heated import heated_segment, kick, majorant_power, measure_centred, scaled_sums
from ._dsmc_kernels import KERNEL_HARD_RODS, KERNEL_MAXWELL, collide_lanes, collide_model
from ._jit import jit

__all__ = ["cooling_segment", "measure_scaled", "extent_fast", "extent",
           "kick", "central_sums", "sums_extent", "central_variance",
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


@jit(fastmath={"nnan", "nsz"})
def extent_fast(v):  # pragma: no cover - compiled
    """``(min(v), max(v))`` of finite ``v`` in one vectorised pass (the same values as
    :func:`extent`: the flags only let LLVM reorder the exact min and max)."""
    lo = v[0]
    hi = v[0]
    for k in range(v.shape[0]):
        x = v[k]
        lo = x if x < lo else lo
        hi = x if x > hi else hi
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


@jit
def measure_scaled(v, lo, hi, counts, sums):  # pragma: no cover - compiled
    """Rescale ``v`` to zero mean and unit variance and measure it, in two passes.

    The first pass gives the sums of ``v`` and ``v^2`` (:func:`sums_extent`; a second
    pass for the variance only if the mean is not already negligible, as in
    :func:`cooling_block`), the second moves and scales ``v`` and fills the histogram of
    the scaled velocity on ``[lo, hi)`` and its power sums ``k = 0 .. 12``
    (:func:`particles._dsmc_heated.scaled_sums`; ``counts`` and ``sums`` overwritten).

    Returns
    -------
    sd : float
        The standard deviation divided out (0.0 if all velocities are equal; ``v`` is
        then left unchanged).
    """
    n = v.shape[0]
    s1, s2, _, _ = sums_extent(v)
    mean = s1 / n
    mean_sq = s2 / n
    var = mean_sq - mean * mean if mean * mean <= 1e-8 * mean_sq else central_variance(v, mean)
    if not var > 0.0:
        return 0.0
    sd = math.sqrt(var)
    scaled_sums(v, mean, 1.0 / sd, lo, hi, counts, sums)
    return sd


_SHRINK = 2.0**-10


@jit
def cooling_segment(v, target, refresh, ratio, kcode, gamma, lcode, p0, p1, log_scale0, s,
                    raw, ci, cj, cu):  # pragma: no cover - compiled
    """Free cooling until ``target`` collisions: blocks of at most ``refresh`` candidates.

    Before each block the extent ``max(v) - min(v)`` (the majorant) is measured; the
    velocities are rescaled (centred, unit variance, as :func:`cooling_block`) only when
    it has fallen below ``2^-10`` of its value after the last rescaling (or on entry):
    then the round-off of the mean (conserved by the collisions) stays below
    ``2^-40`` of the spread, as with a rescaling every block, and nothing under- or
    overflows in a long segment.
    A block has ``min(refresh, max(need, refresh // 16))`` candidates, ``need`` the
    candidates still expected at the acceptance ``ratio`` (the run's so far), so the
    segment ends within a sixteenth of a block of ``target``.  Hard rods with a constant
    ``alpha`` collide by :func:`particles._dsmc_kernels.collide_lanes` (the lanes of
    ``s``), the other models by :func:`particles._dsmc_kernels.collide_model` (words
    0-3 of ``s``).

    Parameters
    ----------
    v : ndarray of float64, shape (N,)
        Velocities, ``exp(log_scale0)`` physical units each; updated in place.
    target, refresh : int
        Collisions to reach; largest block of candidates.
    ratio : float
        Expected acceptance ratio (> 0).
    kcode, gamma, lcode, p0, p1 : the model (:func:`particles._dsmc_kernels.collide_model`)
    log_scale0 : float
    s : ndarray of uint64, shape (36,)
        Kernel state (:func:`particles.rng.cooling_state`).
    raw, ci, cj, cu : ndarray
        Work space of :func:`particles._dsmc_kernels.collide_lanes`.

    Returns
    -------
    accepted, candidates : int
    log_scale : float
        Velocities on entry are ``exp(log_scale)`` times the returned ones' units.
    log_time : float
        Logarithm of the ``time`` of :func:`cooling_block` (``2 time / (n N)`` is the
        elapsed time in the units of ``v`` on entry); ``-inf`` if no candidate was drawn.
        In logarithms: over a long segment the scale and the time leave the float range.
    """
    n = v.shape[0]
    lanes = kcode == KERNEL_HARD_RODS and lcode == CONSTANT
    accepted = 0
    candidates = 0
    log_scale = 0.0
    log_time = -math.inf
    g_ref = -1.0
    while accepted < target:
        lo, hi = extent_fast(v)
        g_max = hi - lo
        if g_ref < 0.0:
            g_ref = g_max
        if not g_max >= _SHRINK * g_ref:
            s1, s2, lo, hi = sums_extent(v)
            mean = s1 / n
            var = central_variance(v, mean)
            if not var > 0.0:
                break  # all velocities equal: no collision can ever happen again
            inv_sd = 1.0 / math.sqrt(var)
            for k in range(n):
                v[k] = (v[k] - mean) * inv_sd
            g_max = (hi - lo) * inv_sd
            g_ref = g_max
            log_scale -= math.log(inv_sd)
        need = int((target - accepted) / ratio) + 1
        m = min(refresh, max(need, refresh // 16))
        if lanes:
            a, _ = collide_lanes(v, m, p0, g_max, s, raw, ci, cj, cu)
        else:
            gscale = 1.0 if lcode == CONSTANT else math.exp(log_scale0 + log_scale)
            a, _ = collide_model(v, m, kcode, gamma, lcode, p0, p1, g_max, gscale, s)
        accepted += a
        candidates += m
        if kcode == KERNEL_HARD_RODS:
            log_dt = math.log(m) - math.log(g_max) - log_scale
        elif kcode == KERNEL_MAXWELL:
            log_dt = math.log(m)
        else:
            log_dt = math.log(m) - gamma * (math.log(g_max) + log_scale)
        hi_t = max(log_time, log_dt)
        log_time = hi_t + math.log1p(math.exp(-abs(log_time - log_dt)))
    return accepted, candidates, log_scale, log_time
