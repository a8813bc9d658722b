"""Numba kernels of the mixture DSMC: Strang segments of forcing and collisions.

A segment is ``n_steps`` steps of the time step ``dt`` (:func:`mixture_segment`): heated,
:math:`K(\\Delta t/2)\\,C(\\Delta t)\\,K(\\Delta t/2)` with the consecutive half kicks
merged into one full kick (exact for white noise and for the Ornstein-Uhlenbeck step of a
bath, as in :mod:`particles._dsmc_heated`), each rod kicked with its species' factors;
free cooling in physical velocities (:func:`particles.dsmc_mixture.evolve_mixture`),
collisions only.  A collision stage of ``dt`` has
:math:`\\lfloor \\text{debt} + \\Delta t\\,nN B(g_{max})/2\\rfloor` candidates (the
fraction carried over), ``g_max = max - min`` measured in the pass that kicks (or
scans) the rods; a candidate is two distinct rods, whatever their species, accepted with
probability :math:`B(|g|)/B(g_{max})` (every one for the Maxwell kernel), colliding by
:math:`v_s' = v_s - \\mu_{sr}(1+\\alpha_{sr})g`, :math:`v_r' = v_r + \\mu_{rs}
(1+\\alpha_{sr})g` with the pair's restitution law at :math:`|g|`
(:func:`kinetic_fem.model.restitution_value`).  The scaled free cooling of
:func:`particles.dsmc_mixture.simulate_mixture` has no splitting: :func:`cooling_segment`
runs its collisions on a clock that ticks once per candidate, with a majorant widened by
the collisions, and no pass over the rods.

Random numbers (:mod:`particles.rng`, the 5-word state of
:func:`~particles.rng.heated_state`): the kicks' normals and the candidates (pair and
acceptance uniform from one draw, :func:`particles._dsmc_heated.candidate`) from the
wyrand word, the ziggurat's rare slow paths from the xoshiro256** words; the same seed
gives the same run with or without the JIT.
"""

from __future__ import annotations

import math

import numpy as np

from kinetic_fem.model.restitution import CONSTANT, restitution_value

from ._dsmc_heated import ONE_DRAW_MAX_N, candidate, kick
from ._dsmc_model import KERNEL_HARD_RODS, KERNEL_MAXWELL, kernel_majorant, kernel_value
from ._jit import jit
from .rng import WYRAND_WORD

__all__ = ["mixture_segment", "cooling_segment", "measure", "mean_squares", "recentre"]

_INV53 = 1.0 / 9007199254740992.0  # 2^-53


@jit
def _kick(v, bounds, decay, amp, s, ki, wi, fi):  # pragma: no cover - compiled
    """``v_i = decay[s] v_i + amp[s] xi_i`` for the rods ``bounds[s] <= i < bounds[s + 1]``
    of each species ``s`` (:func:`particles._dsmc_heated.kick` on each block);
    ``(min, max)`` of the result."""
    lo = np.inf
    hi = -np.inf
    for sp in range(bounds.shape[0] - 1):
        lo_s, hi_s = kick(v[bounds[sp]:bounds[sp + 1]], decay[sp], amp[sp], s, ki, wi, fi)
        lo = min(lo, lo_s)
        hi = max(hi, hi_s)
    return lo, hi


@jit
def _rescale(v, factor):  # pragma: no cover - compiled
    """``v *= factor``; ``(min, max)`` of the result."""
    lo = np.inf
    hi = -np.inf
    for k in range(v.shape[0]):
        y = v[k] * factor
        v[k] = y
        lo = min(lo, y)
        hi = max(hi, y)
    return lo, hi


@jit
def _accepted(ag, threshold, hard_rods, kcode, kparam):  # pragma: no cover - compiled
    """The thinning test of a candidate at relative speed ``ag`` (hard rods without the
    kernel's dispatch; every candidate for the Maxwell kernel)."""
    if hard_rods:
        return ag > threshold
    return kcode == KERNEL_MAXWELL or kernel_value(kcode, kparam, ag) > threshold


@jit
def _pair(v, i, j, vi, vj, a, sa, sb, mu, reduced, counts):  # pragma: no cover - compiled
    """The collision of rods ``i`` and ``j`` (velocities ``vi``, ``vj``, species ``sa``,
    ``sb``) with coefficient ``a``, the pair counted (branch-free); the energy lost."""
    share = (1.0 + a) * (vi - vj)
    v[i] = vi - mu[sa, sb] * share
    v[j] = vj + mu[sb, sa] * share
    counts[sa, sb] += 1
    counts[sb, sa] += sb != sa
    return reduced[sa, sb] * (1.0 - a * a) * (vi - vj) ** 2


@jit
def _collide(v, species, mu, reduced, lcode, p0, p1, constant, kcode, kparam, g_max, m, s,
             counts):  # pragma: no cover - compiled
    """``m`` candidates (module text; ``mu[s, r]`` :math:`= m_r/(m_s + m_r)`,
    ``reduced[s, r]`` half the reduced mass; ``constant``: every law a constant, ``p0``
    the coefficients, without the laws' dispatch); returns ``(collisions, energy lost)``.
    (A branch-free loop, as the one-species ``collide_heated``, was slower here: the
    species' look-ups and the pair counts per candidate, 5.5-7.6 against 4.9 ns.)"""
    n = np.uint64(v.shape[0])
    n1 = n - np.uint64(1)
    one_draw = v.shape[0] <= ONE_DRAW_MAX_N
    scale = kernel_majorant(kcode, kparam, g_max) * _INV53
    hard_rods = kcode == KERNEL_HARD_RODS
    w = s[WYRAND_WORD]
    accepted = 0
    loss = 0.0
    for _ in range(m):
        i, j, threshold, w = candidate(w, n, n1, scale, one_draw)
        vi = v[i]
        vj = v[j]
        ag = abs(vi - vj)
        if not _accepted(ag, threshold, hard_rods, kcode, kparam):
            continue
        sa = species[i]
        sb = species[j]
        a = p0[sa, sb] if constant else restitution_value(lcode[sa, sb], p0[sa, sb],
                                                          p1[sa, sb], ag)
        loss += _pair(v, i, j, vi, vj, a, sa, sb, mu, reduced, counts)
        accepted += 1
    s[WYRAND_WORD] = w
    return accepted, loss


@jit
def mixture_segment(v, species, bounds, mu, reduced, lcode, p0, p1, kcode, kparam, decay, amp,
                    half_decay, half_amp, heated, rate, dt, n_steps, g_limit, debt, s, ki,
                    wi, fi, counts, max_collisions):  # pragma: no cover - compiled
    """``n_steps`` steps of the module text.

    Parameters
    ----------
    v : ndarray of float64, shape (N,)
        Velocities, updated in place.
    species : ndarray of int64, shape (N,)
        Sorted: the rods of species ``s`` are ``bounds[s] <= i < bounds[s + 1]``.
    bounds : ndarray of int64, shape (k + 1,)
    mu, reduced : ndarray, shape (k, k)
        :math:`\\mu_{sr} = m_r/(m_s + m_r)` and half the reduced mass
        :math:`m_s m_r/(2(m_s + m_r))`.
    lcode, p0, p1 : ndarray, shape (k, k)
        Restitution law code and parameters of each pair.
    kcode, kparam : int, float
        The kernel (:func:`particles._dsmc_model.kernel_model`).
    decay, amp, half_decay, half_amp : ndarray, shape (k,)
        Each species' kick of a full and of a half step (heated).
    heated : bool
        Forced species (else free cooling in physical velocities).
    rate : float
        :math:`nN/2`.
    dt : float
    n_steps : int
    g_limit : float
        Largest relative speed every law allows: the segment stops before a collision
        stage whose ``g_max`` exceeds it.
    debt : float
        Fraction of a candidate carried over.
    s : ndarray of uint64, shape (5,)
    ki, wi, fi : ndarray
        Ziggurat tables.
    counts : ndarray of int64, shape (k, k)
        Collisions per pair of species, incremented.
    max_collisions : int
        The segment ends after the step in which the collisions reach this number (the
        driver's next measurement).

    Returns
    -------
    (collisions, loss, debt, steps_done, g_max, exceeded)
        ``loss`` the energy lost; ``exceeded``: the segment stopped before a stage whose
        ``g_max`` exceeds a law's range (``g_max`` then the offending value).
    """
    constant = True
    for code in lcode.ravel():
        constant = constant and code == CONSTANT
    collisions = 0
    loss = 0.0
    if heated:
        lo, hi = _kick(v, bounds, half_decay, half_amp, s, ki, wi, fi)
    else:
        lo, hi = _rescale(v, 1.0)
    for step in range(n_steps):
        if hi - lo > g_limit:
            return collisions, loss, debt, step, hi - lo, True
        x = debt + dt * rate * kernel_majorant(kcode, kparam, hi - lo)
        m = int(math.floor(x))
        debt = x - m
        a, dloss = _collide(v, species, mu, reduced, lcode, p0, p1, constant, kcode, kparam,
                            hi - lo, m, s, counts)
        collisions += a
        loss += dloss
        last = step == n_steps - 1 or collisions >= max_collisions
        if heated:
            lo, hi = _kick(v, bounds, half_decay if last else decay,
                           half_amp if last else amp, s, ki, wi, fi)
        else:
            lo, hi = _rescale(v, 1.0)
        if last:
            return collisions, loss, debt, step + 1, hi - lo, False
    return collisions, loss, debt, n_steps, hi - lo, False


@jit
def measure(v, bounds, lows, widths, sums, hist):  # pragma: no cover - compiled
    """Add each rod's powers :math:`v^0 \\dots v^K` to ``sums[s]`` (shape (k, K + 1)) and
    its bin (``lows[s] + widths[s] * [b, b + 1)``, inside ``hist.shape[1]`` bins) to
    ``hist[s]``, ``s`` its species (rods ``bounds[s] <= i < bounds[s + 1]``).

    For ``K = 12`` (:data:`kinetic_fem.distribution.MAX_MOMENT`) the sums stay in
    registers (:func:`_measure_12`; an accumulator array was stored and reloaded for
    every rod: 4.1 against 1.4 ns per rod at N = 5000), with the same products and sums
    in the same order, so the same bits."""
    top = sums.shape[1]
    if top == 13:
        for sp in range(bounds.shape[0] - 1):
            _measure_12(v[bounds[sp]:bounds[sp + 1]], lows[sp], widths[sp], sums[sp],
                        hist[sp])
        return
    bins = hist.shape[1]
    acc = np.zeros(top)
    for sp in range(bounds.shape[0] - 1):
        acc[:] = 0.0
        inv = 1.0 / widths[sp]
        for i in range(bounds[sp], bounds[sp + 1]):
            x = v[i]
            p = 1.0
            for k in range(top):
                acc[k] += p
                p *= x
            b = math.floor((x - lows[sp]) * inv)
            if 0 <= b < bins:
                hist[sp, int(b)] += 1.0
        for k in range(top):
            sums[sp, k] += acc[k]


@jit
def _measure_12(v, low, width, sums, hist):  # pragma: no cover - compiled
    """:func:`measure` of one species' rods ``v``, powers 0-12 summed in registers (each
    power the previous one times ``x``, each sum from 0.0 rod by rod: as the loop over an
    accumulator array)."""
    bins = hist.shape[0]
    inv = 1.0 / width
    a0 = a1 = a2 = a3 = a4 = a5 = a6 = a7 = a8 = a9 = a10 = a11 = a12 = 0.0
    for i in range(v.shape[0]):
        x = v[i]
        p1 = x  # 1.0 * x
        p2 = p1 * x
        p3 = p2 * x
        p4 = p3 * x
        p5 = p4 * x
        p6 = p5 * x
        p7 = p6 * x
        p8 = p7 * x
        p9 = p8 * x
        p10 = p9 * x
        p11 = p10 * x
        p12 = p11 * x
        a0 += 1.0
        a1 += p1
        a2 += p2
        a3 += p3
        a4 += p4
        a5 += p5
        a6 += p6
        a7 += p7
        a8 += p8
        a9 += p9
        a10 += p10
        a11 += p11
        a12 += p12
        b = math.floor((x - low) * inv)
        if 0 <= b < bins:
            hist[int(b)] += 1.0
    out = (a0, a1, a2, a3, a4, a5, a6, a7, a8, a9, a10, a11, a12)
    for k in range(13):
        sums[k] += out[k]


@jit
def mean_squares(v, bounds):  # pragma: no cover - compiled
    """:math:`\\langle v^2\\rangle` of each species (rods ``bounds[s] <= i < bounds[s+1]``)."""
    k = bounds.shape[0] - 1
    out = np.zeros(k)
    for sp in range(k):
        acc = 0.0
        for i in range(bounds[sp], bounds[sp + 1]):
            acc += v[i] * v[i]
        out[sp] = acc / (bounds[sp + 1] - bounds[sp])
    return out


@jit
def recentre(v, bounds, masses, centre, scaled):  # pragma: no cover - compiled
    """Remove the centre-of-mass velocity (``centre``) and rescale to
    :math:`T = \\sum_i m_i v_i^2 / N = 1` (``scaled``), in place."""
    k = bounds.shape[0] - 1
    n = v.shape[0]
    if centre:
        momentum = 0.0
        total = 0.0
        for sp in range(k):
            acc = 0.0
            for i in range(bounds[sp], bounds[sp + 1]):
                acc += v[i]
            momentum += masses[sp] * acc
            total += masses[sp] * (bounds[sp + 1] - bounds[sp])
        shift = momentum / total
        for i in range(n):
            v[i] -= shift
    if scaled:
        energy = 0.0
        for sp in range(k):
            acc = 0.0
            for i in range(bounds[sp], bounds[sp + 1]):
                acc += v[i] * v[i]
            energy += masses[sp] * acc
        factor = 1.0 / math.sqrt(energy / n)
        for i in range(n):
            v[i] *= factor


@jit
def cooling_segment(v, species, mu, reduced, p0, kcode, kparam, rate, gamma, s, counts,
                    max_collisions):  # pragma: no cover - compiled
    """Free cooling in scaled variables until ``max_collisions`` collisions, one clock tick
    per candidate (no pass over the rods).

    The velocities start at :math:`T = 1` (unit mixture temperature); the majorant is
    the range ``[lo, hi]``, measured every ``N`` candidates and widened by every
    post-collision velocity outside it in between (a heavier partner can throw a rod
    beyond the range), so it always bounds the relative speeds.  Each candidate advances
    the clock by :math:`1/(\\mathrm{rate}\\,B(hi - lo))` (``rate`` :math:`= nN/2`; the
    expected spacing, as the one-species free cooling of :mod:`particles._dsmc_kernels`)
    and is
    accepted with probability :math:`B(|g|)/B(hi - lo)`.  The temperature falls by
    :math:`2\\Delta E/N` per collision; ``weighted``, the energy lost weighted by
    :math:`T^{-(1+\\gamma/2)}`, is :math:`(N/2)\\int_{T_{end}}^1 dT/T^{1+\\gamma/2}`, so
    that ``weighted / (N n time)`` estimates :math:`\\zeta` of
    :math:`dT/dt = -2\\zeta n T^{1+\\gamma/2}`.

    Parameters
    ----------
    v : ndarray of float64, shape (N,)
        Velocities at :math:`T = 1`, updated in place (not rescaled at the end).
    species, mu, reduced, p0 : ndarray
        As :func:`mixture_segment`; ``p0`` the constant restitution coefficients.
    kcode, kparam : int, float
        A power-law kernel (:func:`particles._dsmc_model.kernel_model`).
    rate : float
        :math:`nN/2`.
    gamma : float
        The kernel's exponent.
    s : ndarray of uint64, shape (5,)
    counts : ndarray of int64, shape (k, k)
    max_collisions : int

    Returns
    -------
    (collisions, loss, weighted, time)
    """
    n = v.shape[0]
    un = np.uint64(n)
    n1 = un - np.uint64(1)
    one_draw = n <= ONE_DRAW_MAX_N
    hard_rods = kcode == KERNEL_HARD_RODS
    lo, hi = _rescale(v, 1.0)
    b_max = kernel_majorant(kcode, kparam, hi - lo)
    scale = b_max * _INV53
    w = s[WYRAND_WORD]
    time = 0.0
    ticks = 0  # candidates since the majorant last changed
    collisions = 0
    loss = 0.0
    while collisions < max_collisions:
        if ticks >= n:  # the exact range again (the widened one only grows)
            time += ticks / (rate * b_max)
            ticks = 0
            lo, hi = _rescale(v, 1.0)
            b_max = kernel_majorant(kcode, kparam, hi - lo)
            scale = b_max * _INV53
        i, j, threshold, w = candidate(w, un, n1, scale, one_draw)
        ticks += 1
        vi = v[i]
        vj = v[j]
        if not _accepted(abs(vi - vj), threshold, hard_rods, kcode, kparam):
            continue
        sa = species[i]
        sb = species[j]
        loss += _pair(v, i, j, vi, vj, p0[sa, sb], sa, sb, mu, reduced, counts)
        vi = v[i]
        vj = v[j]
        collisions += 1
        if vi < lo or vj < lo or vi > hi or vj > hi:
            time += ticks / (rate * b_max)
            ticks = 0
            lo = min(lo, min(vi, vj))
            hi = max(hi, max(vi, vj))
            b_max = kernel_majorant(kcode, kparam, hi - lo)
            scale = b_max * _INV53
    s[WYRAND_WORD] = w
    time += ticks / (rate * b_max)
    # sum over the collisions of dE / T_mid^p, T falling by 2 dE / N from 1: the
    # integral (N/2) int dT / T^p between the two temperatures (equal to the sum up to
    # O((dE/N)^3) per collision; no power per collision)
    power = 1.0 + 0.5 * gamma
    end = 1.0 - 2.0 * loss / n
    if power == 1.0:
        weighted = 0.5 * n * math.log(1.0 / end)
    else:
        weighted = 0.5 * n * (end ** (1.0 - power) - 1.0) / (power - 1.0)
    return collisions, loss, weighted, time
