"""Numba kernels of the event-driven MD of inelastic hard rods on a ring.

Rods of length :math:`\\sigma` on a ring of length :math:`L` are mapped to point
particles on the *reduced ring* of length :math:`L_f = L - N\\sigma` (the free space):
rod ``i`` with left end :math:`X_i` becomes the point :math:`y_i = X_i - i\\sigma`.
In one dimension this mapping is exact for hard rods: gaps, collision times and
collision rules are unchanged.  Particles are labelled in ring order and never pass,
so particle ``i`` only meets ``i + 1`` (pair ``i``; pair ``N - 1`` is ``(N - 1, 0)``
across the seam, where :math:`y_0 + L_f` is the right partner's position).

Positions are stored *lazily*: particle ``i`` is at ``x[i] + v[i] (t - tl[i])`` and
only ``x``, ``tl`` of the two colliding particles change at a collision.  One
predicted time per pair sits in the event calendar of :mod:`particles._md_calendar`
(a small 4-ary heap for the current bucket, unsorted bucket lists for the rest of
the epoch: :math:`O(1)` per update however large N is).  After a collision only
three pair times change: the collided pair recedes, and one of its two neighbour
pairs due in the heap (if any) takes over the root slot.  The calendar operations
are written out inside :func:`run_events`: a numba call passing arrays increfs and
decrefs each of them atomically, which cost more than the heap operation itself
(80 ns per collision at N = 5000 with calls, 30 ns without).

For ``N >= PREFETCH_MIN_N`` the rods of the root's earliest child (often the next
collision) are prefetched while a collision is processed.

Pairs whose time lies beyond the end of the calendar's epoch never enter it.  In a
heated run the epoch ends at the next random kick (:func:`kick_sweep`, inside
:func:`run_events`: no return to Python), which draws the N normals in one loop, then
moves every rod to the kick time, adds the kicks and screens every pair in a second,
branch-free loop; only the pairs that meet before the following kick (a few per cent
at the default interval) start the next epoch.  Its cost, about 4 ns per rod on this
machine (half of it the normals), is paid every kick: with ``(dt_k/tau) N/2``
collisions between kicks it adds ``8 ns / (dt_k/tau)`` per collision (80 ns at the
default 0.1 mean free times).  In free cooling an epoch spans about ``N``
collisions (its length adapted to the measured collision rate) and ends with a
recomputation of every pair time (:func:`build_heap`, ~2 ns per collision).

Collision rule (relative speed :math:`g = v_i - v_j > 0`):

.. math::

    v_i' = v_i - \\tfrac{1+a}{2} g, \\quad v_j' = v_j + \\tfrac{1+a}{2} g, \\quad
    \\Delta E = -\\tfrac{1 - a^2}{4} g^2,

with :math:`a = 1` if :math:`g` is below the threshold (Ben-Naim et al.
regularisation of inelastic collapse), else :math:`a = \\alpha(g)` of the restitution
law, evaluated by :func:`kinetic_fem.model.restitution_value` (its integer code and two
parameters; a collision faster than the law's range stops the run with
``STATUS_LAW_RANGE``).  Elastic collisions exchange the two velocities exactly.
A mixture (:mod:`particles.md_mixture`: rod ``i`` of species :math:`s_i`, mass
:math:`m_{s_i}`, a constant :math:`\\alpha_{s_i s_j}` per pair) takes
:math:`v_i' = v_i - \\mu_{ij}(1+a)g`, :math:`v_j' = v_j + \\mu_{ji}(1+a)g` with
:math:`\\mu_{ij} = m_j/(m_i + m_j)` and :math:`\\Delta E = -\\tfrac12 m_{ij}(1-a^2)g^2`
(:math:`m_{ij}` the reduced mass), and scales each rod's kick normal by its species'
factor; with no species arrays (size 0) the one-species rule above runs unchanged.
Kicks: :math:`v_i \\to d\\,v_i + b\\,\\xi_i`, white noise with :math:`d = 1`,
:math:`b = \\sqrt{2 D \\Delta t_k}`, or the exact Ornstein-Uhlenbeck update of a
Fokker-Planck bath over the kick interval, :math:`d = e^{-\\xi \\Delta t_k}`,
:math:`b = \\sqrt{T_b (1 - e^{-2\\xi\\Delta t_k})}`; the standard normals ``xi``
drawn inside the kernel by the branch-free, vectorised Box-Muller transform of
:mod:`particles._md_kicks` on a counter-based splitmix64 stream (``rng``, ``uint64[1]``,
seeded by the driver and saved in checkpoints).  All kernels take arrays and scalars only.
"""

from __future__ import annotations

import numpy as np

from kinetic_fem.model import restitution_value

from ._jit import jit, prefetch
from ._md_calendar import (
    F_BASE,
    F_HORIZON,
    F_INV_W,
    HEAP_PAD,
    I_CUR,
    I_HSIZE,
    I_NB,
    bucket_of,
    calendar_start,
)
from ._md_kicks import STREAM_VERSION, fill_normals, kick_sweep

__all__ = ["F_T", "F_T_KICK", "F_DISS", "F_INJ", "F_BASE", "F_INV_W", "F_HORIZON", "F_SPAN",
           "I_NCOLL", "I_HSIZE", "I_STALL", "I_NKICK", "I_NELASTIC", "I_BAD_PAIR", "I_CUR",
           "I_NB", "I_EPOCH_C0", "STATUS_COLLISIONS", "STATUS_TIME",
           "STATUS_COLLAPSE_SPEED", "STATUS_COLLAPSE_STALL", "STATUS_NO_EVENTS",
           "STATUS_LAW_RANGE", "N_FSTATE", "N_ISTATE", "HEAP_PAD", "STREAM_VERSION",
           "PREFETCH_MIN_N", "bucket_of", "build_heap", "fill_normals", "kick_sweep",
           "run_events", "velocity_moments", "rod_positions_at"]

# slots of the float state vector (F_BASE, F_INV_W, F_HORIZON = 4, 5, 6: the calendar's)
F_T, F_T_KICK, F_DISS, F_INJ = 0, 1, 2, 3
F_SPAN = 7  # span of a free-cooling epoch
N_FSTATE = 8
# slots of the integer state vector (I_HSIZE = 1, I_CUR, I_NB = 6, 7: the calendar's)
I_NCOLL, I_STALL, I_NKICK, I_NELASTIC, I_BAD_PAIR = 0, 2, 3, 4, 5
I_EPOCH_C0 = 8  # collisions at the start of the epoch
N_ISTATE = 9
# return codes of run_events
STATUS_COLLISIONS = 0  # reached the requested number of collisions
STATUS_TIME = 1  # reached the requested time
STATUS_COLLAPSE_SPEED = 3  # an inelastic collision below the collapse speed floor
STATUS_COLLAPSE_STALL = 4  # too many consecutive collisions without time advancing
STATUS_NO_EVENTS = 5  # no approaching pair and no kicks: free streaming forever
STATUS_LAW_RANGE = 6  # a collision faster than the restitution law's range (I_BAD_PAIR)

PREFETCH_MIN_N = 1 << 14
"""From this N on (arrays beyond the 1 MiB L2 cache) :func:`run_events` prefetches."""


@jit
def _meet(t, xq, vq, tlq, xj, vj, tlj, shift):  # pragma: no cover - compiled
    """Time rod ``q`` (lazy ``xq, vq, tlq``) meets its right neighbour, or inf.

    The neighbour is ``xj, vj, tlj`` plus ``shift`` (``L_f`` across the seam).
    Selects instead of branches: approaching or not is a coin flip for the CPU.
    Scalars only (no arrays: no reference counting when called in the event loop).
    """
    dv = vq - vj
    gap = (xj + vj * (t - tlj) + shift) - (xq + vq * (t - tlq))
    approaching = dv > 0.0
    tq = t + max(gap, 0.0) / (dv if approaching else 1.0)
    return tq if approaching else np.inf


@jit
def _pair_time(q, t, x, v, tl, free_length):  # pragma: no cover - compiled
    """Predicted collision time of pair ``q`` = (q, q+1 mod N), or inf if receding."""
    n = x.shape[0]
    j = q + 1
    shift = 0.0
    if j == n:
        j = 0
        shift = free_length
    return _meet(t, x[q], v[q], tl[q], x[j], v[j], tl[j], shift)


@jit
def build_heap(t, t_cut, x, v, tl, free_length, heap, hkey, where, ptime, head, nxt, prv,
               bkt, fstate, istate):  # pragma: no cover - compiled
    """Recompute every pair time at ``t``; start a calendar epoch ``[t, t_cut)``.

    The calendar must be empty.  Returns the number of approaching pairs (due at any
    time, queued or not).
    """
    n = x.shape[0]
    old = istate[I_HSIZE]
    for k in range(old):
        where[heap[k]] = -1
        hkey[k] = np.inf
    size = 0
    approaching = 0
    for q in range(n):
        tq = _pair_time(q, t, x, v, tl, free_length)
        approaching += tq < np.inf
        if tq < t_cut:
            heap[size] = q
            hkey[size] = tq
            size += 1
    calendar_start(size, t, t_cut, heap, hkey, where, ptime, head, nxt, prv, bkt, fstate,
                   istate)
    return approaching


@jit
def velocity_moments(v):  # pragma: no cover - compiled
    """``(sum v, sum v^2, var v)`` of ``v`` (shape (N,)); the variance is central.

    Four interleaved partial sums per pass (independent additions, about 1 ns per
    element less than one running sum), the variance from a second pass around the
    mean: one compiled call instead of the numpy ``mean``, ``var`` and ``sum`` calls
    at every record and sample (about 40 us at N = 5000).
    """
    n = v.shape[0]
    a0 = a1 = a2 = a3 = 0.0
    b0 = b1 = b2 = b3 = 0.0
    m = n - n % 4
    for i in range(0, m, 4):
        w0, w1, w2, w3 = v[i], v[i + 1], v[i + 2], v[i + 3]
        a0 += w0
        a1 += w1
        a2 += w2
        a3 += w3
        b0 += w0 * w0
        b1 += w1 * w1
        b2 += w2 * w2
        b3 += w3 * w3
    for i in range(m, n):
        a0 += v[i]
        b0 += v[i] * v[i]
    s1 = (a0 + a1) + (a2 + a3)
    s2 = (b0 + b1) + (b2 + b3)
    u = s1 / n
    c0 = c1 = c2 = c3 = 0.0
    for i in range(0, m, 4):
        d0, d1, d2, d3 = v[i] - u, v[i + 1] - u, v[i + 2] - u, v[i + 3] - u
        c0 += d0 * d0
        c1 += d1 * d1
        c2 += d2 * d2
        c3 += d3 * d3
    for i in range(m, n):
        c0 += (v[i] - u) * (v[i] - u)
    return s1, s2, ((c0 + c1) + (c2 + c3)) / n


@jit
def rod_positions_at(t, x, v, tl, sigma, big_l, out):  # pragma: no cover - compiled
    """Rod left ends at time ``t`` in ``[0, big_l)`` into ``out`` (shape (N,)).

    ``np.mod(x + v (t - tl) + sigma i, big_l)`` element by element, as numpy computes it.
    """
    for i in range(x.shape[0]):
        out[i] = np.mod(x[i] + v[i] * (t - tl[i]) + sigma * i, big_l)


@jit
def run_events(x, v, tl, heap, hkey, where, ptime, head, nxt, prv, bkt, fstate, istate, rng,
               normals, free_length, law, p0, p1, max_speed, threshold, kick_dt,
               kick_decay, kick_amp, species, masses, lcodes, lp0, lp1, kick_scale, pair_counts,
               speed_floor, max_stall, t_stop, coll_stop):  # pragma: no cover - compiled
    """Advance the event-driven dynamics until a stop condition; return a status code.

    Parameters
    ----------
    x, v, tl : ndarray, shape (N,)
        Lazy positions on the reduced ring, velocities, times of last update.
    heap, hkey, where, ptime, head, nxt, prv, bkt : ndarray
        The event calendar of :mod:`particles._md_calendar` (int32 or int64 indices,
        shape (N,); ``hkey`` shape (N + HEAP_PAD,)).
    fstate : ndarray, shape (N_FSTATE,)
        Time, time of the next kick, energy dissipated, energy injected, the
        calendar's epoch, the span of a free-cooling epoch.
    istate : ndarray, shape (N_ISTATE,)
        Collisions, heap size, stall counter, kicks, threshold (elastic) collisions,
        pair of the last collapse, calendar bucket and buckets, collisions at the
        start of the epoch.
    rng : ndarray of uint64, shape (1,)
        Counter of the kick normals (:func:`particles._md_kicks.fill_normals`; unused
        when ``kick_dt`` is inf).
    normals : ndarray, shape (N + N % 2,)
        Scratch space for the normals of a kick.
    free_length : float
        Length of the reduced ring :math:`L - N\\sigma`.
    law, p0, p1, max_speed : int, float, float, float
        Restitution law (:attr:`kinetic_fem.model.RestitutionLaw.code` and
        ``parameters``) and the largest relative speed it is defined for.
    threshold : float
        Collisions with relative speed below it are elastic (0 disables the
        regularisation); counted in ``istate[I_NELASTIC]``.
    kick_dt, kick_decay, kick_amp : float
        Interval between kicks (inf: free cooling) and the kick
        ``v -> kick_decay * v + kick_amp * xi``.
    species, masses, lcodes, lp0, lp1, kick_scale, pair_counts : ndarray
        A mixture (:mod:`particles.md_mixture`): the species of each rod (int64, shape
        (N,)), the species' masses (shape (k,)), the restitution law of each pair (code
        and parameters, shapes (k, k), replacing ``law``; ``max_speed`` then the smallest
        of their ranges), the factor of each rod's kick normal (shape (N,)) and
        the collisions per pair of species (int64, shape (k, k), incremented).  One
        species: all of size 0, and the one-species rule below runs unchanged.
    speed_floor : float
        An inelastic collision slower than this signals inelastic collapse.
    max_stall : int
        Consecutive collisions allowed without the time advancing by more than
        1e-13 relative.
    t_stop, coll_stop : float, int
        Stop before the first event after ``t_stop`` or after ``coll_stop`` collisions
        in total.

    Notes
    -----
    An epoch of the calendar ends when it holds no pair: in a heated run the kick
    follows (all pairs due before it were processed); in free cooling every pair time
    is recomputed (:func:`build_heap`) for a new epoch whose span is scaled by
    ``N / c`` (within a factor 4) after ``c`` collisions in the last one, so that an
    epoch holds about ``N`` collisions (the sweep then costs ~2 ns per collision).
    """
    n = x.shape[0]
    t = fstate[F_T]
    t_kick = fstate[F_T_KICK]
    diss = fstate[F_DISS]
    n_coll = istate[I_NCOLL]
    stall = istate[I_STALL]
    n_elastic = istate[I_NELASTIC]
    # the calendar in locals (arrays are touched only for the queued pairs); the code
    # is written out here, not called: a call passing arrays costs numba's reference
    # counting (atomic) per array, more than the heap operation itself
    size = istate[I_HSIZE]
    cur = istate[I_CUR]
    nb = istate[I_NB]
    base = fstate[F_BASE]
    inv_w = fstate[F_INV_W]
    horizon = fstate[F_HORIZON]
    status = STATUS_COLLISIONS
    use_prefetch = n >= PREFETCH_MIN_N
    mixture = species.shape[0] > 0
    while True:
        if n_coll >= coll_stop:
            status = STATUS_COLLISIONS
            break
        while size == 0 and cur + 1 < nb:  # heap the next non-empty bucket
            cur += 1
            q = head[cur]
            head[cur] = -1
            while q >= 0:
                nq = nxt[q]
                bkt[q] = -1
                kq = ptime[q]
                pos = size
                size += 1
                while pos > 0:
                    parent = (pos - 1) >> 2
                    kpar = hkey[parent]
                    if kpar <= kq:
                        break
                    qq = heap[parent]
                    heap[pos] = qq
                    hkey[pos] = kpar
                    where[qq] = pos
                    pos = parent
                heap[pos] = q
                hkey[pos] = kq
                where[q] = pos
                q = nq
        if size == 0:  # the epoch is over: every pair due before its horizon was processed
            istate[I_HSIZE] = 0
            istate[I_CUR] = cur
            if t_kick < np.inf:
                if t_kick > t_stop:
                    status = STATUS_TIME
                    break
                nk = istate[I_NKICK] + 1
                t = t_kick
                t_kick = (nk + 1) * kick_dt
                fill_normals(normals, rng)
                for k in range(kick_scale.shape[0]):  # a mixture: D_s per species
                    normals[k] *= kick_scale[k]
                fstate[F_INJ] += kick_sweep(t, t_kick, kick_decay, kick_amp, normals, x, v, tl,
                                            free_length, heap, hkey, where, ptime, head, nxt,
                                            prv, bkt, fstate, istate)
                istate[I_NKICK] = nk
            else:
                if horizon > t_stop:
                    status = STATUS_TIME
                    break
                c = n_coll - istate[I_EPOCH_C0]
                span = fstate[F_SPAN] * min(4.0, max(0.25, n / max(c, 1)))
                fstate[F_SPAN] = span
                istate[I_EPOCH_C0] = n_coll
                if build_heap(t, t + span, x, v, tl, free_length, heap, hkey, where, ptime,
                              head, nxt, prv, bkt, fstate, istate) == 0:
                    status = STATUS_NO_EVENTS
                    break
            size = istate[I_HSIZE]
            cur = istate[I_CUR]
            nb = istate[I_NB]
            base = fstate[F_BASE]
            inv_w = fstate[F_INV_W]
            horizon = fstate[F_HORIZON]
            continue
        p = heap[0]
        tc = hkey[0]
        if tc > t_stop:
            status = STATUS_TIME
            break
        # --- collision of pair p = (i, j) at time tc
        if use_prefetch:
            # the next collision is likely the root's earliest child, or with a single
            # pair in the heap the first pair of the next bucket: fetch its rods and
            # calendar entries while this one is processed (overlaps the cache misses
            # of large N; slots beyond the heap hold inf)
            q2 = -1
            if size > 1:
                c01 = 1 + (hkey[2] < hkey[1])
                c23 = 3 + (hkey[4] < hkey[3])
                q2 = heap[c23] if hkey[c23] < hkey[c01] else heap[c01]
            elif cur + 1 < nb:
                q2 = head[cur + 1]
            if q2 >= 0:
                prefetch(x, q2)
                prefetch(v, q2)
                prefetch(tl, q2)
                prefetch(where, q2)
                prefetch(bkt, q2)
                prefetch(nxt, q2)
                prefetch(prv, q2)
        i = p
        j = p + 1
        shift = 0.0
        if j == n:
            j = 0
            shift = free_length
        g = v[i] - v[j]
        if g < threshold:
            a = 1.0
            n_elastic += 1
        elif g < speed_floor:
            istate[I_BAD_PAIR] = p
            status = STATUS_COLLAPSE_SPEED
            break
        elif g > max_speed:
            istate[I_BAD_PAIR] = p
            status = STATUS_LAW_RANGE
            break
        elif mixture:
            si = species[i]
            sj = species[j]
            a = restitution_value(lcodes[si, sj], lp0[si, sj], lp1[si, sj], g)
        else:
            a = restitution_value(law, p0, p1, g)
        if tc - t <= 1e-13 * abs(tc):
            stall += 1
            if stall > max_stall:
                istate[I_BAD_PAIR] = p
                status = STATUS_COLLAPSE_STALL
                break
        else:
            stall = 0
        xi = x[i] + v[i] * (tc - tl[i])
        xj = x[j] + v[j] * (tc - tl[j]) + shift
        m = 0.5 * (xi + xj)
        x[i] = m
        x[j] = m - shift
        tl[i] = tc
        tl[j] = tc
        if mixture:  # v_i' = v_i - mu_ij (1 + a) g, mu_ij = m_j/(m_i + m_j)
            si = species[i]
            sj = species[j]
            mi = masses[si]
            mj = masses[sj]
            share = (1.0 + a) * g / (mi + mj)
            v[i] -= mj * share
            v[j] += mi * share
            diss += 0.5 * mi * mj / (mi + mj) * (1.0 - a * a) * g * g
            pair_counts[si, sj] += 1
        elif a == 1.0:  # elastic: exchange exactly, energy and P(v) unchanged
            vi = v[i]
            v[i] = v[j]
            v[j] = vi
        else:
            d = 0.5 * (1.0 + a) * g
            v[i] -= d
            v[j] += d
            diss += 0.25 * (1.0 - a * a) * g * g
        t = tc
        n_coll += 1
        # --- pair p recedes, its neighbour pairs get new times.  Three steps, each at
        # most one heap repair (sift up, then down): the left pair, the right pair, and
        # the removal of p from the root, unless a neighbour due in the heap and not yet
        # in it took over the root slot.  While p sits at the root (its time is the
        # smallest) the other repairs never reach slot 0.
        left = p - 1 if p > 0 else n - 1
        two = left != j  # (N = 2 has a single neighbour pair)
        jr = j + 1 if j + 1 < n else 0
        t_left = _meet(t, x[left], v[left], tl[left], x[i], v[i], tl[i],
                       free_length if left == n - 1 else 0.0)
        t_right = _meet(t, x[j], v[j], tl[j], x[jr], v[jr], tl[jr],
                        free_length if j == n - 1 else 0.0)
        root_free = True
        for step in range(3):
            fix = -1
            fq = 0
            fk = 0.0
            if step < 2:
                if step == 0:
                    if not two:
                        continue
                    q = left
                    tq = t_left
                else:
                    q = j
                    tq = t_right
                b = -1  # the bucket of tq (-1: not queued)
                if tq < horizon:
                    kf = (tq - base) * inv_w
                    b = nb - 1 if kf >= nb - 1 else int(kf)
                if bkt[q] >= 0:  # out of its bucket's list
                    qa = prv[q]
                    qz = nxt[q]
                    if qa >= 0:
                        nxt[qa] = qz
                    else:
                        head[bkt[q]] = qz
                    if qz >= 0:
                        prv[qz] = qa
                    bkt[q] = -1
                pos = where[q]
                if 0 <= b <= cur:  # due in the heap
                    fq = q
                    fk = tq
                    if pos >= 0:
                        fix = pos
                    elif root_free:
                        where[p] = -1
                        fix = 0
                        root_free = False
                    else:
                        fix = size
                        size += 1
                else:
                    if pos >= 0:  # out of the heap: the last entry fills the hole
                        where[q] = -1
                        size -= 1
                        fq = heap[size]
                        fk = hkey[size]
                        hkey[size] = np.inf
                        if pos < size:
                            fix = pos
                    if b > 0:  # into its bucket's list
                        ptime[q] = tq
                        h = head[b]
                        nxt[q] = h
                        prv[q] = -1
                        if h >= 0:
                            prv[h] = q
                        head[b] = q
                        bkt[q] = b
            elif root_free:
                where[p] = -1
                size -= 1
                fq = heap[size]
                fk = hkey[size]
                hkey[size] = np.inf
                if size > 0:
                    fix = 0
            if fix >= 0:
                pos = fix
                while pos > 0:
                    parent = (pos - 1) >> 2
                    kpar = hkey[parent]
                    if kpar <= fk:
                        break
                    qq = heap[parent]
                    heap[pos] = qq
                    hkey[pos] = kpar
                    where[qq] = pos
                    pos = parent
                while True:
                    c = 4 * pos + 1
                    if c >= size:
                        break
                    h0 = hkey[c]
                    h1 = hkey[c + 1]
                    h2 = hkey[c + 2]
                    h3 = hkey[c + 3]
                    c01 = c + (h1 < h0)
                    k01 = min(h0, h1)
                    c23 = c + 2 + (h3 < h2)
                    k23 = min(h2, h3)
                    child = c23 if k23 < k01 else c01
                    kc = min(k01, k23)
                    if fk <= kc:
                        break
                    qq = heap[child]
                    heap[pos] = qq
                    hkey[pos] = kc
                    where[qq] = pos
                    pos = child
                heap[pos] = fq
                hkey[pos] = fk
                where[fq] = pos
    fstate[F_T] = t
    fstate[F_T_KICK] = t_kick
    fstate[F_DISS] = diss
    istate[I_NCOLL] = n_coll
    istate[I_STALL] = stall
    istate[I_NELASTIC] = n_elastic
    istate[I_HSIZE] = size
    istate[I_CUR] = cur
    return status
