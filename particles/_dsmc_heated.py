"""Numba kernels of the heated DSMC: thermostat kicks and Strang steps.

A heated segment is ``n_steps`` Strang steps :math:`K(\\Delta t/2)\\,C(\\Delta t)\\,
K(\\Delta t/2)` of collisions ``C`` and thermostat kicks ``K`` (:func:`kick`:
:math:`v \\to d\\,v + b\\,\\xi` with standard normals :math:`\\xi`; white noise
:math:`d = 1`, :math:`b = \\sqrt{2D\\Delta t}`; the exact Ornstein-Uhlenbeck update of
a Fokker-Planck bath :math:`d = e^{-\\xi\\Delta t}`,
:math:`b = \\sqrt{T_b(1 - e^{-2\\xi\\Delta t})}`); consecutive half kicks merge into one
full kick (exact for both thermostats: the Ornstein-Uhlenbeck flow is a semigroup).

Random numbers: the kernel state ``s`` has five words
(:func:`particles.rng.heated_state`).  The normals of the kicks take their 64 bits
from the wyrand word (:data:`particles.rng.WYRAND_WORD`), the ziggurat's rare slow
paths from the xoshiro256** words.  Hard rods with a constant ``alpha`` collide by
:func:`collide_heated`: one wyrand draw per candidate gives the pair and the
acceptance uniform (for ``N <= ONE_DRAW_MAX_N``); the other models use
:func:`particles._dsmc_kernels.collide_model` on the xoshiro256** words.

Why the kicks are applied to every particle at every step: thinning needs a true
majorant ``g_max >= |v_i - v_j|`` of the velocities *with* their kicks.  "Lazy" kicks
(one normal per particle, of variance summed over the steps since it was last touched,
drawn only when it is picked as a candidate) are exact for the kick itself, but then
the kicked extent is unknown: a bound from the generator's largest normal
(:math:`|\\xi| \\le R + 53\\ln 2/R = 13.7`, the ziggurat's tail) adds
:math:`2 \\times 13.7\\,b` per stale step to ``g_max``, at the default step
(:math:`b \\approx 0.18\\sqrt T`) 60 % more candidates for one stale step, and every
candidate must then draw its two normals to be tested; a statistical margin (8 standard
deviations) gives up exactness and still costs more candidates than the kicks it saves
(one flush every 2-4 steps: 20-25 % fewer instructions at best, measured by a cost model
of the loops below).  So the kicks stay eager and the cost went into the draws.

Costs on one core of the development machine (AMD EPYC, Zen 4; CPU time, interleaved
with the loops they replaced, load 8 on 2 cores): a white-noise kick 1.6 ns per velocity
(xoshiro256**: 1.8; the C program's loop compiled by gcc: 1.5 and, with wyrand, 1.3);
a hard-rod candidate 1.6 ns (two xoshiro256** draws: 2.6).
"""

from __future__ import annotations

import math

import numpy as np

from kinetic_fem.model.restitution import CONSTANT

from ._dsmc_kernels import (
    KERNEL_HARD_RODS,
    PREFETCH_BATCH,
    PREFETCH_MIN_N,
    collide_model,
)
from ._dsmc_model import kernel_majorant as majorant_power
from ._jit import jit, prefetch
from .rng import WYRAND_WORD, mul128, normal_slow, wyrand

__all__ = ["ONE_DRAW_MAX_N", "candidate", "kick", "collide_heated", "heated_segment",
           "majorant_power", "measure_centred", "scaled_sums"]

ONE_DRAW_MAX_N = 1 << 22
"""Largest ``N`` for which a hard-rod candidate of :func:`collide_heated` is one draw
(pair and acceptance uniform on a lattice of spacing ``N(N-1)/2^64 < 1e-6``)."""

_M52 = np.uint64(0x000FFFFFFFFFFFFF)


@jit
def _check_state(s):  # pragma: no cover - compiled
    if s.shape[0] <= WYRAND_WORD:
        raise ValueError("heated kernels need the 5-word state of particles.rng.heated_state")


@jit
def kick(v, decay, amp, s, ki, wi, fi):  # pragma: no cover - compiled
    """``v = decay * v + amp * xi`` with independent standard normals; new ``(min, max)``.

    ``decay = 1`` (white noise) runs a loop without the multiply (a separate loop: a
    branch inside made the white-noise kick 10 % slower).  Ziggurat of
    :mod:`particles.rng` on the wyrand word of ``s`` (5 words): 99 % of the draws take
    one 64-bit number and the fast path (inlined here, the counter in a register); the
    rest go to :func:`particles.rng.normal_slow` on the xoshiro256** words.
    """
    _check_state(s)
    if decay == 1.0:
        return _kick_white(v, amp, s, ki, wi, fi)
    return _kick_ou(v, decay, amp, s, ki, wi, fi)


@jit
def _kick_white(v, amp, s, ki, wi, fi):  # pragma: no cover - compiled
    """:func:`kick` with ``decay = 1``."""
    lo = np.inf
    hi = -np.inf
    w = s[WYRAND_WORD]
    for k in range(v.shape[0]):
        r, w = wyrand(w)
        layer_sign = r & np.uint64(0x1FF)  # bits 0-7: layer, bit 8: sign
        idx = int(layer_sign & np.uint64(0xFF))
        rabs = (r >> np.uint64(9)) & _M52
        x = float(np.int64(rabs)) * wi[layer_sign]
        if rabs >= ki[idx]:
            x = normal_slow(s, idx, x, ki, wi, fi)
        y = v[k] + amp * x
        v[k] = y
        lo = min(lo, y)
        hi = max(hi, y)
    s[WYRAND_WORD] = w
    return lo, hi


@jit
def _kick_ou(v, decay, amp, s, ki, wi, fi):  # pragma: no cover - compiled
    """:func:`kick` with ``decay < 1`` (the Ornstein-Uhlenbeck step)."""
    lo = np.inf
    hi = -np.inf
    w = s[WYRAND_WORD]
    for k in range(v.shape[0]):
        r, w = wyrand(w)
        layer_sign = r & np.uint64(0x1FF)
        idx = int(layer_sign & np.uint64(0xFF))
        rabs = (r >> np.uint64(9)) & _M52
        x = float(np.int64(rabs)) * wi[layer_sign]
        if rabs >= ki[idx]:
            x = normal_slow(s, idx, x, ki, wi, fi)
        y = decay * v[k] + amp * x
        v[k] = y
        lo = min(lo, y)
        hi = max(hi, y)
    s[WYRAND_WORD] = w
    return lo, hi


@jit
def candidate(w, n, n1, scale, one_draw):  # pragma: no cover - compiled
    """One hard-rod candidate: ``(i, j, threshold, w)``.

    One draw ``r``: ``i`` is the high word of ``r N``, ``j`` the high word of
    ``low(r N) (N - 1)`` and the threshold the top 53 bits of ``low(low(r N) (N - 1))``
    times ``g_max / 2^53``.  Given ``i`` the low word runs through an arithmetic
    progression of step ``N`` over ``[0, 2^64)``, given ``(i, j)`` the last one through
    one of step ``N (N - 1)``: the triple is uniform on a lattice, up to a relative
    ``N^2 / 2^64``.  Two draws (``one_draw`` False, large ``N``): ``i`` and the
    threshold from the first as in :func:`particles._dsmc_kernels.collide`, ``j``
    from the second.
    """
    r, w = wyrand(w)
    i, low = mul128(r, n)
    if one_draw:
        j, low = mul128(low, n1)
    else:
        r2, w = wyrand(w)
        j = mul128(r2, n1)[0]
    j += np.uint64(j >= i)
    return i, j, float(np.int64(low >> np.uint64(11))) * scale, w


@jit
def collide_heated(v, n_candidates, alpha, g_max, s, batch=-1):  # pragma: no cover
    """Hard rods, constant ``alpha``, candidates from the wyrand word of ``s``.

    The thinning of :func:`particles._dsmc_kernels.collide` (accept with probability
    ``|v_i - v_j| / g_max``, branch-free update), each candidate from one wyrand draw
    (:func:`candidate`; two for ``N > ONE_DRAW_MAX_N``).  ``batch``: as in
    :func:`particles._dsmc_kernels.collide` (candidates drawn and their velocities
    prefetched ``batch`` ahead for ``N >= PREFETCH_MIN_N``; bit-identical to the plain
    loop).

    Parameters
    ----------
    v : ndarray of float64
        Velocities, updated in place.
    n_candidates : int
        Number of candidate pairs.
    alpha : float
        Coefficient of restitution.
    g_max : float
        Majorant of the relative speed.
    s : ndarray of uint64, shape (5,)
        Kernel state (:func:`particles.rng.heated_state`); its wyrand word advances.
    batch : int, optional
        Prefetch distance (negative: automatic, 0: plain loop).

    Returns
    -------
    accepted : int
        Number of collisions.
    sum_g2 : float
        :math:`\\sum g^2` over the collisions.
    """
    n = np.uint64(v.shape[0])
    n1 = n - np.uint64(1)
    one_draw = v.shape[0] <= ONE_DRAW_MAX_N
    half = 0.5 * (1.0 + alpha)
    scale = g_max * (1.0 / 9007199254740992.0)
    if batch < 0:
        batch = PREFETCH_BATCH if v.shape[0] >= PREFETCH_MIN_N else 0
    accepted = 0
    sum_g2 = 0.0
    w = s[WYRAND_WORD]
    if batch == 0:
        for _ in range(n_candidates):
            i, j, threshold, w = candidate(w, n, n1, scale, one_draw)
            vi = v[i]
            vj = v[j]
            g = vi - vj
            acc = abs(g) > threshold
            dv = half * g if acc else 0.0  # a select, not a branch
            v[i] = vi - dv
            v[j] = vj + dv
            accepted += acc
            sum_g2 += g * g if acc else 0.0
        s[WYRAND_WORD] = w
        return accepted, sum_g2
    low32 = np.uint64(0xFFFFFFFF)
    high = np.uint64(32)
    bij = np.empty(batch, np.uint64)
    bt = np.empty(batch)
    for b in range(min(batch, n_candidates)):
        i, j, threshold, w = candidate(w, n, n1, scale, one_draw)
        prefetch(v, i)
        prefetch(v, j)
        bij[b] = i | (j << high)
        bt[b] = threshold
    done = 0
    while done < n_candidates:
        m = min(batch, n_candidates - done)  # candidates in the buffer
        ahead = min(batch, n_candidates - done - m)  # candidates still to draw
        for b in range(m):  # collide candidate k, refill its slot with k + batch
            ij = bij[b]
            threshold = bt[b]
            if b < ahead:
                i2, j2, t2, w = candidate(w, n, n1, scale, one_draw)
                prefetch(v, i2)
                prefetch(v, j2)
                bij[b] = i2 | (j2 << high)
                bt[b] = t2
            i = ij & low32
            j = ij >> high
            vi = v[i]
            vj = v[j]
            g = vi - vj
            acc = abs(g) > threshold
            dv = half * g if acc else 0.0
            v[i] = vi - dv
            v[j] = vj + dv
            accepted += acc
            sum_g2 += g * g if acc else 0.0
        done += m
    s[WYRAND_WORD] = w
    return accepted, sum_g2


@jit
def _collide(v, m, kcode, gamma, lcode, p0, p1, g_max, s):  # pragma: no cover - compiled
    """One collision stage: :func:`collide_heated` for hard rods with a constant law."""
    if kcode == KERNEL_HARD_RODS and lcode == CONSTANT:
        a, g2 = collide_heated(v, m, p0, g_max, s)
        return a, (1.0 - p0 * p0) * g2
    return collide_model(v, m, kcode, gamma, lcode, p0, p1, g_max, 1.0, s)


@jit
def heated_segment(v, n_steps, dt, decay, amp, half_decay, half_amp, rate, kcode, gamma,
                   lcode, p0, p1, g_limit, debt, s, ki, wi, fi):  # pragma: no cover
    """``n_steps`` Strang steps :math:`K(dt/2)\\,C(dt)\\,K(dt/2)`, merged half kicks.

    Parameters
    ----------
    v : ndarray of float64, shape (N,)
        Velocities, updated in place.
    n_steps : int
    dt : float
        Time step.
    decay, amp, half_decay, half_amp : float
        Kick of a full and of a half step (:func:`kick`).
    rate : float
        :math:`nN/2`; a step has ``debt + dt * rate * g_max^gamma`` candidates
        (integer part; the fraction is carried to the next step) with the majorant
        ``g_max = max - min`` measured right after the kick.
    kcode, gamma, lcode, p0, p1 : the model (:func:`particles._dsmc_kernels.collide_model`)
    g_limit : float
        Largest relative speed the restitution law allows; the segment stops before
        a collision stage whose ``g_max`` exceeds it.
    debt : float
        Fraction of a candidate carried over.
    s : ndarray of uint64, shape (5,)
        Kernel state (:func:`particles.rng.heated_state`).
    ki, wi, fi : ndarray
        Ziggurat tables (:func:`particles.rng.ziggurat_tables`).

    Returns
    -------
    (accepted, loss, debt, steps_done, g_max) : (int, float, float, int, float)
        ``loss`` as in :func:`particles._dsmc_kernels.collide_model`; ``steps_done <
        n_steps`` if the law's range was exceeded (``g_max`` then the offending value).
    """
    _check_state(s)
    if decay == 1.0 and half_decay == 1.0:  # one kick kind per loop: 6 % faster
        return _heated_white(v, n_steps, dt, amp, half_amp, rate, kcode, gamma, lcode, p0,
                             p1, g_limit, debt, s, ki, wi, fi)
    return _heated_ou(v, n_steps, dt, decay, amp, half_decay, half_amp, rate, kcode, gamma,
                      lcode, p0, p1, g_limit, debt, s, ki, wi, fi)


@jit
def _heated_white(v, n_steps, dt, amp, half_amp, rate, kcode, gamma, lcode, p0, p1, g_limit,
                  debt, s, ki, wi, fi):  # pragma: no cover - compiled
    """:func:`heated_segment` under white noise."""
    accepted = 0
    loss = 0.0
    lo, hi = _kick_white(v, half_amp, s, ki, wi, fi)
    for step in range(n_steps):
        if hi - lo > g_limit:
            return accepted, loss, debt, step, hi - lo
        x = debt + dt * rate * majorant_power(kcode, gamma, hi - lo)
        m = int(math.floor(x))
        debt = x - m
        a, dloss = _collide(v, m, kcode, gamma, lcode, p0, p1, hi - lo, s)
        accepted += a
        loss += dloss
        lo, hi = _kick_white(v, amp if step < n_steps - 1 else half_amp, s, ki, wi, fi)
    return accepted, loss, debt, n_steps, hi - lo


@jit
def _heated_ou(v, n_steps, dt, decay, amp, half_decay, half_amp, rate, kcode, gamma, lcode,
               p0, p1, g_limit, debt, s, ki, wi, fi):  # pragma: no cover - compiled
    """:func:`heated_segment` with a Fokker-Planck bath."""
    accepted = 0
    loss = 0.0
    lo, hi = _kick_ou(v, half_decay, half_amp, s, ki, wi, fi)
    for step in range(n_steps):
        if hi - lo > g_limit:
            return accepted, loss, debt, step, hi - lo
        x = debt + dt * rate * majorant_power(kcode, gamma, hi - lo)
        m = int(math.floor(x))
        debt = x - m
        a, dloss = _collide(v, m, kcode, gamma, lcode, p0, p1, hi - lo, s)
        accepted += a
        loss += dloss
        full = step < n_steps - 1
        lo, hi = _kick_ou(v, decay if full else half_decay, amp if full else half_amp, s, ki,
                          wi, fi)
    return accepted, loss, debt, n_steps, hi - lo


@jit
def measure_centred(v, lo, hi, counts, sums):  # pragma: no cover - compiled
    """Move ``v`` to its centre-of-mass frame and measure it, in two passes.

    The first pass sums ``v`` (four partial sums); the second subtracts the mean,
    stores the centred velocity ``d`` and adds it to a histogram on ``[lo, hi)`` and
    to the power sums :math:`\\sum d^k`, ``k = 0 .. 12`` (kept in registers;
    :func:`scaled_sums`).  The central moments are ``sums[k] / N``; ``counts`` and
    ``sums`` (shapes (bins,) and (13,)) are overwritten, so that a sample can be added to
    a batch once averaging has started.  One pass less than the mean, central moments,
    the shift and :func:`particles.sampling.accumulate_kernel` in turn, and no divide per
    velocity.

    Parameters
    ----------
    v : ndarray of float64, shape (N,)
        Velocities; centred in place.
    lo, hi : float
        Histogram range.
    counts : ndarray of float64, shape (bins,)
        Histogram of ``d`` (overwritten).
    sums : ndarray of float64, shape (13,)
        Power sums of ``d`` (overwritten).

    Returns
    -------
    mean : float
        The mean that was subtracted.
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
    scaled_sums(v, mean, 1.0, lo, hi, counts, sums)
    return mean


@jit
def scaled_sums(v, mean, scale, lo, hi, counts, sums):  # pragma: no cover - compiled
    """``v = (v - mean) * scale``; histogram on ``[lo, hi)`` and power sums ``k <= 12``.

    ``counts`` and ``sums`` (shapes (bins,) and (13,)) are overwritten with the
    histogram of the new ``v`` and :math:`\\sum v^k`; one pass, the sums in registers.
    (``scale = 1.0`` multiplies exactly.)
    """
    if sums.shape[0] != 13:
        raise ValueError("the measurement keeps the power sums k = 0 .. 12")
    n = v.shape[0]
    n_bins = counts.shape[0]
    inv_width = n_bins / (hi - lo)
    counts[:] = 0.0
    s1 = s2 = s3 = s4 = s5 = s6 = s7 = s8 = s9 = s10 = s11 = s12 = 0.0
    for i in range(n):
        x1 = (v[i] - mean) * scale
        v[i] = x1
        x2 = x1 * x1
        x3 = x2 * x1
        x4 = x2 * x2
        x5 = x4 * x1
        x6 = x4 * x2
        s1 += x1
        s2 += x2
        s3 += x3
        s4 += x4
        s5 += x5
        s6 += x6
        s7 += x6 * x1
        s8 += x6 * x2
        s9 += x6 * x3
        s10 += x6 * x4
        s11 += x6 * x5
        s12 += x6 * x6
        b = math.floor((x1 - lo) * inv_width)
        if 0 <= b < n_bins:
            counts[int(b)] += 1.0
    out = (float(n), s1, s2, s3, s4, s5, s6, s7, s8, s9, s10, s11, s12)
    for m in range(13):
        sums[m] = out[m]
