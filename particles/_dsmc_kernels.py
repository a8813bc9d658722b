"""Numba collision kernels of the homogeneous DSMC (see :mod:`particles.dsmc`).

Thinning with the kernel :math:`B(g)` (:mod:`kinetic_fem.model.kernel`; non-decreasing in
:math:`|g|`): a candidate pair ``(i, j)``, ``i != j`` uniform, is accepted with
probability :math:`B(g)/B(g_{max})` (:math:`|g|^\\gamma/g_{max}^\\gamma` for a power law)
and collides, :math:`v_{i,j} \\to v_{i,j} \\mp \\tfrac{1+\\alpha(g)}{2} g`,
:math:`g = v_i - v_j`.  Flat arrays and scalars in, ``v`` updated in place, random
numbers from the xoshiro256** state ``s`` of :mod:`particles.rng`; no global state.
:func:`collide_model` dispatches on the model (kernel code, restitution code and its
two parameters, :func:`kinetic_fem.model.restitution_value`) to three loops:

* :func:`collide`, hard rods with a constant ``alpha`` (the paper; the hot path,
  unchanged bit for bit): two draws per candidate; the pair from the high words of
  ``r1 N`` and ``r2 (N - 1)`` (:func:`particles.rng.mul128`), the acceptance uniform
  from the low word of ``r1 N``.  It is branch-free (every candidate stores
  ``v_i - a\\,\\delta``, ``v_j + a\\,\\delta`` with ``a`` in {0, 1}; the accept/reject
  branch was mispredicted for a fifth of the candidates).  For
  ``N >= PREFETCH_MIN_N`` (``v`` larger than the 1 MiB L2 cache) it draws the pairs
  ``PREFETCH_BATCH`` candidates ahead into a small buffer and prefetches their
  velocities into L2, so that the cache misses of many candidates overlap; each
  candidate is still accepted and collided in order on the current velocities, so the
  results are bit-identical to the plain loop.
* :func:`collide_lanes`, hard rods with a constant ``alpha`` in free cooling: the
  thinning of :func:`collide` with the candidates drawn in blocks of
  :data:`CANDIDATE_BLOCK` from the eight lock-step xoshiro256++ streams of
  :func:`particles.rng.xoshiro_lanes` (two draws per candidate: ``i`` and ``j != i``
  from the high and low 32 bits of the first, by multiply-shift, the acceptance
  uniform from the top 52 bits of the second), prepared in one vector pass
  (:func:`candidate_block`), then collided in order by a branch-free loop.
* :func:`collide_maxwell`, :math:`\\gamma = 0`: every candidate collides, no
  acceptance draw (prefetching as :func:`collide` for large ``N``); for
  ``N <= MAXWELL_ONE_DRAW_MAX_N`` one draw gives the pair (``i``
  from the high word of ``r N``, ``j`` from the high word of ``low(r N) (N - 1)``:
  given ``i`` the low word runs through an arithmetic progression of step ``N`` over
  ``[0, 2^64)``, so ``j`` is uniform up to a relative ``N^2 / 2^64 <= 1e-6``), above
  it two draws.
* :func:`collide_power`, any other kernel or a restitution law: two draws per
  candidate; the uniform threshold ``U g_max^gamma`` is compared with ``|g|``
  (``gamma = 1``), ``g^2`` (``gamma = 2``) or, for other exponents, first with the
  bounds :math:`x \\le x^\\gamma` (``gamma < 1``) or :math:`x^2 \\le x^\\gamma
  \\le x` (``1 < gamma < 2``) of :math:`x = |g|/g_{max}` and only in between with
  the power itself; for the saturating kernel
  (:data:`particles._dsmc_model.KERNEL_SATURATING`) with :math:`B(|g|)` itself,
  :math:`U B(g_{max})` the threshold.

Post-collision velocities are convex combinations of the pre-collision ones for
every :math:`0 \\le \\alpha(g) \\le 1`, so ``g_max = max(v) - min(v)`` stays a true
majorant.  Each loop returns the number of collisions and the energy loss
:math:`\\sum (1 - \\alpha(g)^2) g^2` (the kinetic energy drops by half of it).
A restitution law is evaluated at the physical relative speed ``gscale * |g|``
(free cooling keeps rescaled velocities).

Costs on one core of the development machine (AMD EPYC, Zen 4; CPU time, from
``benchmarks/bench_dsmc.py``): a hard-rod candidate takes 3.0 ns at ``N = 25000``
(``v`` in L2), of which the two draws with the pair and the acceptance uniform take
2.6 ns on their own: the loop is bound by the random numbers.  At ``N = 10^6`` it
takes 3.8-4.2 ns: the prefetch hides the memory latency (without it each candidate
waited for two cache misses in turn, 9-50 ns).
"""

from __future__ import annotations

import numpy as np

from kinetic_fem.model.restitution import CONSTANT, restitution_value

from ._dsmc_model import (
    KERNEL_HARD_RODS,
    KERNEL_MAXWELL,
    KERNEL_POWER,
    KERNEL_SATURATING,
    KERNEL_SQUARE,
    kernel_code,
    saturating_rate,
)
from ._jit import jit, prefetch
from .rng import LANES, bits_to_double, mul128, xoshiro, xoshiro_lanes

__all__ = ["CANDIDATE_BLOCK", "candidate_block", "collide_lanes", "KERNEL_MAXWELL",
           "KERNEL_HARD_RODS", "KERNEL_SQUARE", "KERNEL_POWER",
           "kernel_code", "collide_model", "collide", "collide_maxwell", "collide_power",
           "PREFETCH_MIN_N", "PREFETCH_BATCH", "MAXWELL_ONE_DRAW_MAX_N"]

PREFETCH_MIN_N = 1 << 17
"""Smallest ``N`` for which :func:`collide` draws ahead and prefetches (``v`` of 1 MiB,
the L2 cache; below it the plain loop is faster, 3.0 against 3.8 ns per candidate)."""

PREFETCH_BATCH = 128
"""How many candidates ahead the prefetching :func:`collide` draws the pairs."""

MAXWELL_ONE_DRAW_MAX_N = 1 << 22
"""Largest ``N`` for which :func:`collide_maxwell` takes both indices from one draw
(relative non-uniformity of ``j`` at most ``N^2 / 2^64 < 1e-6``)."""

_INV53 = 1.0 / 9007199254740992.0  # 2^-53

CANDIDATE_BLOCK = 512
"""Candidates per block of :func:`collide_lanes` (a multiple of ``LANES``)."""

_LOW32 = np.uint64(0xFFFFFFFF)
_ONE_BITS = np.uint64(0x3FF0000000000000)  # the bits of 1.0
_PREFETCH_AHEAD = 32


@jit
def candidate_block(st, n, g_max, raw, ci, cj, cu, m):  # pragma: no cover - compiled
    """``m`` (a multiple of ``LANES``) candidates from the lanes of the state ``st``.

    ``2 m`` draws of :func:`particles.rng.xoshiro_lanes` go to ``raw``; candidate ``c``
    takes ``a = raw[c]`` and ``b = raw[m + c]``: ``i = (a_hi N) >> 32``,
    ``j = (a_lo (N-1)) >> 32`` shifted past ``i`` (``a_hi``, ``a_lo`` the high and low
    32 bits of ``a``; ``N < 2^32``; relative non-uniformity below ``N / 2^32``, at most
    ``6e-6`` at ``N = 25000``), and the acceptance threshold ``u g_max`` with
    ``u = (b >> 12) 2^-52`` in ``[0, 1)`` (52 bits, by the exponent trick: no integer to
    float conversion).  Every step is elementwise, so the loop is vectorised.
    """
    xoshiro_lanes(st, raw, (2 * m) // LANES)
    nn = np.uint64(n) & _LOW32
    n1 = (nn - np.uint64(1)) & _LOW32
    for c in range(m):
        a = raw[c]
        i = ((a >> np.uint64(32)) * nn) >> np.uint64(32)
        j = ((a & _LOW32) * n1) >> np.uint64(32)
        ci[c] = i
        cj[c] = j + np.uint64(j >= i)
        cu[c] = (bits_to_double((raw[m + c] >> np.uint64(12)) | _ONE_BITS) - 1.0) * g_max


@jit
def collide_lanes(v, n_candidates, alpha, g_max, st, raw, ci, cj, cu):  # pragma: no cover
    """Hard rods, constant ``alpha``: ``n_candidates`` candidates from the lanes of ``st``.

    The thinning of :func:`collide` (accept with probability ``|v_i - v_j| / g_max``,
    ``v_{i,j} -= +-(1+alpha)/2 (v_i - v_j)``) on candidates prepared in blocks of
    ``ci.shape[0]`` by :func:`candidate_block`; the last block's unused draws are
    dropped (the state has moved past them).  The loop is branch-free: the update is
    multiplied by the acceptance, 0.0 or 1.0 (a select compiled as a branch was
    mispredicted for a fifth of the candidates).  For ``N >= PREFETCH_MIN_N`` the
    velocities of the candidate 32 places ahead are prefetched into L2.

    Parameters
    ----------
    v : ndarray of float64, shape (N,)
        Velocities, updated in place.
    n_candidates : int
    alpha, g_max : float
        Restitution coefficient and majorant of ``|v_i - v_j|``.
    st : ndarray of uint64
        Kernel state with the lane words (:func:`particles.rng.cooling_state`).
    raw, ci, cj, cu : ndarray
        Work space: uint64 of ``2 B``, uint64 of ``B + 32``, uint64 of ``B + 32`` and
        float64 of ``B + 32`` entries, ``B`` a multiple of ``LANES``.

    Returns
    -------
    accepted : int
    sum_g2 : float
        :math:`\\sum g^2` over the collisions.
    """
    n = v.shape[0]
    half = 0.5 * (1.0 + alpha)
    block = (ci.shape[0] - _PREFETCH_AHEAD) // LANES * LANES
    ahead = _PREFETCH_AHEAD if n >= PREFETCH_MIN_N else 0
    accepted = 0
    sum_g2 = 0.0
    done = 0
    while done < n_candidates:
        m = min(block, n_candidates - done)
        candidate_block(st, n, g_max, raw, ci, cj, cu, (m + LANES - 1) // LANES * LANES)
        for c in range(m):
            if ahead:  # indices past m are stale but valid: prefetches only
                prefetch(v, ci[c + ahead])
                prefetch(v, cj[c + ahead])
            i = ci[c]
            j = cj[c]
            vi = v[i]
            vj = v[j]
            g = vi - vj
            w = float(np.int64(abs(g) > cu[c]))
            dv = (half * g) * w
            v[i] = vi - dv
            v[j] = vj + dv
            accepted += np.int64(w)
            sum_g2 += (g * g) * w
        done += m
    return accepted, sum_g2


@jit
def collide_model(v, n_candidates, kcode, gamma, lcode, p0, p1, g_max, gscale,
                  s):  # pragma: no cover - compiled
    """``n_candidates`` candidates of the model ``(kcode, gamma, lcode, p0, p1)``.

    Parameters
    ----------
    v : ndarray of float64, shape (N,)
        Velocities, updated in place.
    n_candidates : int
        Number of candidate pairs (every one collides for ``kcode = KERNEL_MAXWELL``).
    kcode, gamma : int, float
        Kernel code and parameter (:func:`kernel_model`: the exponent of a power law,
        :math:`g_0` of the saturating kernel).
    lcode, p0, p1 : int, float, float
        Restitution law code and parameters (:func:`kinetic_fem.model.restitution_value`).
    g_max : float
        Majorant of ``|v_i - v_j|`` (ignored for Maxwell).
    gscale : float
        Physical relative speed per unit of ``v`` (for restitution laws).
    s : ndarray of uint64, shape (4,)
        Generator state, advanced.

    Returns
    -------
    accepted : int
        Number of collisions.
    loss : float
        :math:`\\sum (1 - \\alpha^2) g^2` over the collisions (units of ``v^2``).
    """
    if kcode == KERNEL_MAXWELL:
        return collide_maxwell(v, n_candidates, lcode, p0, p1, gscale, s)
    if kcode == KERNEL_HARD_RODS and lcode == CONSTANT:
        a, g2 = collide(v, n_candidates, p0, g_max, s)
        return a, (1.0 - p0 * p0) * g2
    return collide_power(v, n_candidates, kcode, gamma, lcode, p0, p1, g_max, gscale, s)


@jit
def collide(v, n_candidates, alpha, g_max, s, batch=-1):  # pragma: no cover - compiled
    """Hard rods, constant ``alpha``: ``n_candidates`` candidate pairs, majorant ``g_max``.

    A pair is accepted with probability ``|v_i - v_j| / g_max`` and collides:
    ``v_i -= (1+alpha)/2 (v_i - v_j)``, ``v_j += (1+alpha)/2 (v_i - v_j)``.
    ``g_max >= max(v) - min(v)`` stays a bound because post-collision velocities
    are convex combinations of the pre-collision ones.

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
    s : ndarray of uint64, shape (4,)
        xoshiro256** state, advanced by two draws per candidate.
    batch : int, optional
        How many candidates ahead the pairs are drawn and their velocities
        prefetched; 0 for the plain loop; negative (default) for ``PREFETCH_BATCH``
        if ``N >= PREFETCH_MIN_N``, else 0.  All choices give bit-identical results.

    Returns
    -------
    accepted : int
        Number of collisions.
    sum_g2 : float
        :math:`\\sum g^2` over the collisions; the energy lost is
        :math:`\\tfrac12 (1-\\alpha^2) \\sum g^2`.
    """
    if batch < 0:
        batch = PREFETCH_BATCH if v.shape[0] >= PREFETCH_MIN_N else 0
    if batch > 0:
        return _collide_batched(v, n_candidates, alpha, g_max, s, batch)
    return _collide_plain(v, n_candidates, alpha, g_max, s)


@jit
def _candidate(s0, s1, s2, s3, n, n1, scale):  # pragma: no cover - compiled
    """One candidate from two draws: ``(i, j, threshold, s0, s1, s2, s3)``."""
    r1, s0, s1, s2, s3 = xoshiro(s0, s1, s2, s3)
    r2, s0, s1, s2, s3 = xoshiro(s0, s1, s2, s3)
    i, low = mul128(r1, n)
    j = mul128(r2, n1)[0]
    j += np.uint64(j >= i)
    # uniform(0, g_max) from the low 64 bits of r1 * N (top 53 of them)
    threshold = float(np.int64(low >> np.uint64(11))) * scale
    return i, j, threshold, s0, s1, s2, s3  # unsigned: no negative-index wrap-around


@jit
def _collide_plain(v, n_candidates, alpha, g_max, s):  # pragma: no cover - compiled
    """:func:`collide` as one loop (``v`` in the L2 cache)."""
    n = np.uint64(v.shape[0])
    n1 = n - np.uint64(1)
    half = 0.5 * (1.0 + alpha)
    scale = g_max * (1.0 / 9007199254740992.0)  # g_max / 2^53
    accepted = 0
    sum_g2 = 0.0
    s0, s1, s2, s3 = s[0], s[1], s[2], s[3]
    for _ in range(n_candidates):
        i, j, threshold, s0, s1, s2, s3 = _candidate(s0, s1, s2, s3, n, n1, scale)
        vi = v[i]
        vj = v[j]
        g = vi - vj
        acc = abs(g) > threshold
        dv = half * g if acc else 0.0  # a select, not a branch
        v[i] = vi - dv
        v[j] = vj + dv
        accepted += acc
        sum_g2 += g * g if acc else 0.0
    s[0], s[1], s[2], s[3] = s0, s1, s2, s3
    return accepted, sum_g2


@jit
def _collide_batched(v, n_candidates, alpha, g_max, s, batch):  # pragma: no cover - compiled
    """:func:`collide` with the pairs drawn and prefetched ``batch`` candidates ahead.

    A buffer holds the next ``batch`` candidates (``i | j << 32`` and the threshold;
    ``N < 2^32``); candidate ``k`` is collided (in order, on the current velocities)
    in the same loop iteration that draws candidate ``k + batch`` into its slot and
    prefetches its two velocities.  The draws keep the order of the plain loop, so
    the results are bit-identical.
    """
    n = np.uint64(v.shape[0])
    n1 = n - np.uint64(1)
    half = 0.5 * (1.0 + alpha)
    scale = g_max * (1.0 / 9007199254740992.0)
    low32 = np.uint64(0xFFFFFFFF)
    high = np.uint64(32)
    accepted = 0
    sum_g2 = 0.0
    s0, s1, s2, s3 = s[0], s[1], s[2], s[3]
    bij = np.empty(batch, np.uint64)
    bt = np.empty(batch)
    for b in range(min(batch, n_candidates)):
        i, j, threshold, s0, s1, s2, s3 = _candidate(s0, s1, s2, s3, n, n1, scale)
        prefetch(v, i)
        prefetch(v, j)
        bij[b] = i | (j << high)
        bt[b] = threshold
    done = 0
    while done < n_candidates:
        m = min(batch, n_candidates - done)  # candidates in the buffer
        ahead = min(batch, n_candidates - done - m)  # candidates still to draw
        for b in range(ahead):  # collide candidate k, refill its slot with k + batch
            ij = bij[b]
            threshold = bt[b]
            i2, j2, t2, s0, s1, s2, s3 = _candidate(s0, s1, s2, s3, n, n1, scale)
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
        for b in range(ahead, m):  # the last candidates: nothing left to draw
            ij = bij[b]
            i = ij & low32
            j = ij >> high
            vi = v[i]
            vj = v[j]
            g = vi - vj
            acc = abs(g) > bt[b]
            dv = half * g if acc else 0.0
            v[i] = vi - dv
            v[j] = vj + dv
            accepted += acc
            sum_g2 += g * g if acc else 0.0
        done += m
    s[0], s[1], s[2], s[3] = s0, s1, s2, s3
    return accepted, sum_g2


@jit
def _pair_one_draw(s0, s1, s2, s3, n, n1):  # pragma: no cover - compiled
    """Both indices of a pair from one draw: ``(i, j, s0, s1, s2, s3)``."""
    r, s0, s1, s2, s3 = xoshiro(s0, s1, s2, s3)
    i, low = mul128(r, n)
    j = mul128(low, n1)[0]
    j += np.uint64(j >= i)
    return i, j, s0, s1, s2, s3


@jit
def _pair_two_draws(s0, s1, s2, s3, n, n1):  # pragma: no cover - compiled
    """A pair from two draws (large ``N``): ``(i, j, s0, s1, s2, s3)``."""
    r1, s0, s1, s2, s3 = xoshiro(s0, s1, s2, s3)
    r2, s0, s1, s2, s3 = xoshiro(s0, s1, s2, s3)
    i = mul128(r1, n)[0]
    j = mul128(r2, n1)[0]
    j += np.uint64(j >= i)
    return i, j, s0, s1, s2, s3


@jit
def collide_maxwell(v, n_collisions, lcode, p0, p1, gscale, s,
                    batch=-1):  # pragma: no cover - compiled
    """Maxwell kernel: ``n_collisions`` collisions of uniform random pairs, no rejection.

    ``batch``: as in :func:`collide` (pairs drawn and prefetched ``batch`` collisions
    ahead for ``N >= PREFETCH_MIN_N``; bit-identical to the plain loop).  Returns
    ``(n_collisions, loss)`` as :func:`collide_model`.
    """
    if batch < 0:
        batch = PREFETCH_BATCH if v.shape[0] >= PREFETCH_MIN_N else 0
    if batch > 0:
        return _collide_maxwell_batched(v, n_collisions, lcode, p0, p1, gscale, s, batch)
    return _collide_maxwell_plain(v, n_collisions, lcode, p0, p1, gscale, s)


@jit
def _collide_maxwell_plain(v, n_collisions, lcode, p0, p1, gscale, s):  # pragma: no cover
    """:func:`collide_maxwell` as one loop (``v`` in the L2 cache)."""
    n = np.uint64(v.shape[0])
    n1 = n - np.uint64(1)
    one_draw = v.shape[0] <= MAXWELL_ONE_DRAW_MAX_N
    sum_g2 = 0.0
    loss = 0.0
    half = 0.5 * (1.0 + p0)
    s0, s1, s2, s3 = s[0], s[1], s[2], s[3]
    for _ in range(n_collisions):
        if one_draw:
            i, j, s0, s1, s2, s3 = _pair_one_draw(s0, s1, s2, s3, n, n1)
        else:
            i, j, s0, s1, s2, s3 = _pair_two_draws(s0, s1, s2, s3, n, n1)
        vi = v[i]
        vj = v[j]
        g = vi - vj
        if lcode == CONSTANT:
            dv = half * g
            sum_g2 += g * g
        else:
            a = restitution_value(lcode, p0, p1, g * gscale)
            dv = 0.5 * (1.0 + a) * g
            loss += (1.0 - a * a) * g * g
        v[i] = vi - dv
        v[j] = vj + dv
    s[0], s[1], s[2], s[3] = s0, s1, s2, s3
    if lcode == CONSTANT:
        loss = (1.0 - p0 * p0) * sum_g2
    return n_collisions, loss


@jit
def _maxwell_pair(v, i, j, lcode, p0, p1, half, gscale):  # pragma: no cover - compiled
    """Collide the pair ``(i, j)``; returns ``g^2`` (constant law) or ``(1-a^2) g^2``."""
    vi = v[i]
    vj = v[j]
    g = vi - vj
    if lcode == CONSTANT:
        dv = half * g
        out = g * g
    else:
        a = restitution_value(lcode, p0, p1, g * gscale)
        dv = 0.5 * (1.0 + a) * g
        out = (1.0 - a * a) * g * g
    v[i] = vi - dv
    v[j] = vj + dv
    return out


@jit
def _collide_maxwell_batched(v, n_collisions, lcode, p0, p1, gscale, s,
                             batch):  # pragma: no cover - compiled
    """:func:`collide_maxwell` with the pairs drawn and prefetched ``batch`` ahead.

    The buffer holds ``i | j << 32`` of the next ``batch`` pairs; pair ``k`` collides
    in the iteration that draws pair ``k + batch`` into its slot, so the draws keep
    the order of the plain loop (bit-identical results).
    """
    n = np.uint64(v.shape[0])
    n1 = n - np.uint64(1)
    one_draw = v.shape[0] <= MAXWELL_ONE_DRAW_MAX_N
    low32 = np.uint64(0xFFFFFFFF)
    high = np.uint64(32)
    half = 0.5 * (1.0 + p0)
    total = 0.0
    s0, s1, s2, s3 = s[0], s[1], s[2], s[3]
    bij = np.empty(batch, np.uint64)
    for b in range(min(batch, n_collisions)):
        if one_draw:
            i, j, s0, s1, s2, s3 = _pair_one_draw(s0, s1, s2, s3, n, n1)
        else:
            i, j, s0, s1, s2, s3 = _pair_two_draws(s0, s1, s2, s3, n, n1)
        prefetch(v, i)
        prefetch(v, j)
        bij[b] = i | (j << high)
    done = 0
    while done < n_collisions:
        m = min(batch, n_collisions - done)  # pairs in the buffer
        ahead = min(batch, n_collisions - done - m)  # pairs still to draw
        for b in range(m):
            ij = bij[b]
            if b < ahead:
                if one_draw:
                    i2, j2, s0, s1, s2, s3 = _pair_one_draw(s0, s1, s2, s3, n, n1)
                else:
                    i2, j2, s0, s1, s2, s3 = _pair_two_draws(s0, s1, s2, s3, n, n1)
                prefetch(v, i2)
                prefetch(v, j2)
                bij[b] = i2 | (j2 << high)
            total += _maxwell_pair(v, ij & low32, ij >> high, lcode, p0, p1, half, gscale)
        done += m
    s[0], s[1], s[2], s[3] = s0, s1, s2, s3
    if lcode == CONSTANT:
        total = (1.0 - p0 * p0) * total
    return n_collisions, total


@jit
def collide_power(v, n_candidates, kcode, gamma, lcode, p0, p1, g_max, gscale,
                  s):  # pragma: no cover - compiled
    """Kernel :math:`|g|^\\gamma`, ``0 < gamma <= 2``, or the saturating kernel
    (``kcode == KERNEL_SATURATING``, ``gamma`` is then :math:`g_0`), any restitution law.

    Acceptance with probability :math:`(|g|/g_{max})^\\gamma`, or
    :math:`B(|g|)/B(g_{max})`; returns ``(accepted, loss)`` as :func:`collide_model`.
    """
    n = np.uint64(v.shape[0])
    n1 = n - np.uint64(1)
    inv_gmax = 1.0 / g_max
    if kcode == KERNEL_HARD_RODS:
        scale = g_max * _INV53
    elif kcode == KERNEL_SQUARE:
        scale = g_max * g_max * _INV53
    elif kcode == KERNEL_SATURATING:
        scale = saturating_rate(g_max, gamma) * _INV53
    else:
        scale = _INV53  # threshold U in [0, 1), compared with (|g|/g_max)^gamma
    half = 0.5 * (1.0 + p0)
    accepted = 0
    loss = 0.0
    s0, s1, s2, s3 = s[0], s[1], s[2], s[3]
    for _ in range(n_candidates):
        i, j, threshold, s0, s1, s2, s3 = _candidate(s0, s1, s2, s3, n, n1, scale)
        vi = v[i]
        vj = v[j]
        g = vi - vj
        if kcode == KERNEL_HARD_RODS:
            acc = abs(g) > threshold
        elif kcode == KERNEL_SQUARE:
            acc = g * g > threshold
        elif kcode == KERNEL_SATURATING:
            acc = saturating_rate(abs(g), gamma) > threshold
        else:
            x = abs(g) * inv_gmax
            if gamma < 1.0:  # x <= x^gamma <= 1
                acc = x > threshold or x**gamma > threshold
            else:  # x^2 <= x^gamma <= x
                acc = x * x > threshold or (x > threshold and x**gamma > threshold)
        if acc:
            if lcode == CONSTANT:
                a = p0
                dv = half * g
            else:
                a = restitution_value(lcode, p0, p1, g * gscale)
                dv = 0.5 * (1.0 + a) * g
            v[i] = vi - dv
            v[j] = vj + dv
            accepted += 1
            loss += (1.0 - a * a) * g * g
    s[0], s[1], s[2], s[3] = s0, s1, s2, s3
    return accepted, loss
