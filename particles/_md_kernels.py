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
predicted time per pair sits in an indexed 4-ary min-heap (``heap`` of pair
indices, ``hkey`` their times in heap order, ``where[p]`` the slot of pair ``p`` or
-1; ``hkey`` has ``N + HEAP_PAD`` slots and every slot at or beyond the heap size
holds ``inf``, so a sift-down needs no bounds test for the children).  Four
children per node halve the depth of a binary heap; their four times share one or
two cache lines, which matters once the heap no longer fits in the cache.  After a
collision only three pair times change: the collided pair recedes, and one of its
two neighbour pairs not yet queued (the earlier if both) takes over the root slot,
each update costing :math:`O(\\log N)`.

For ``N >= PREFETCH_MIN_N`` the rods of the root's earliest child (most often the
next collision) are prefetched while a collision is processed.

Pairs whose time lies beyond the next random kick never enter the heap.  A kick
(:func:`kick_sweep`, inside :func:`run_events`: no return to Python) draws the N
normals in one loop, then moves every rod to the kick time, adds the kicks and
screens every pair in a second, branch-free loop; only the pairs that meet before
the following kick (a few per cent at the default interval) are divided out and
heapified (:math:`O(\\text{size})`).  Its cost, about 4 ns per rod on this machine
(half of it the normals), is paid every kick: with ``(dt_k/tau) N/2`` collisions
between kicks it adds ``8 ns / (dt_k/tau)`` per collision (80 ns at the default
0.1 mean free times, against ~120 ns for the collision itself at N = 5000).

Collision rule (relative speed :math:`g = v_i - v_j > 0`):

.. math::

    v_i' = v_i - \\tfrac{1+a}{2} g, \\quad v_j' = v_j + \\tfrac{1+a}{2} g, \\quad
    \\Delta E = -\\tfrac{1 - a^2}{4} g^2,

with :math:`a = 1` if :math:`g` is below the threshold (Ben-Naim et al.
regularisation of inelastic collapse), else :math:`a = \\alpha(g)` of the restitution
law, evaluated by :func:`kinetic_fem.model.restitution_value` (its integer code and two
parameters; a collision faster than the law's range stops the run with
``STATUS_LAW_RANGE``).  Elastic collisions exchange the two velocities exactly.
Kicks: :math:`v_i \\to d\\,v_i + b\\,\\xi_i`, white noise with :math:`d = 1`,
:math:`b = \\sqrt{2 D \\Delta t_k}`, or the exact Ornstein-Uhlenbeck update of a
Fokker-Planck bath over the kick interval, :math:`d = e^{-\\xi \\Delta t_k}`,
:math:`b = \\sqrt{T_b (1 - e^{-2\\xi\\Delta t_k})}`; the standard normals ``xi``
drawn inside the kernel by the ziggurat of :mod:`particles.rng` (its
tables and rare paths; the fast path is inlined) from an explicit-state
xoshiro256** generator (``rng``, ``uint64[4]``, seeded by the driver
and saved in checkpoints): about 2.5 ns per normal against 10 ns for a numpy normal
here.  All kernels take arrays and scalars only.
"""

from __future__ import annotations

import numpy as np

from kinetic_fem.model import restitution_value

from ._jit import jit, prefetch
from .rng import normal_slow, xoshiro, ziggurat_tables

__all__ = ["F_T", "F_T_KICK", "F_DISS", "F_INJ", "I_NCOLL", "I_HSIZE", "I_STALL",
           "I_NKICK", "I_NELASTIC", "I_BAD_PAIR", "STATUS_COLLISIONS", "STATUS_TIME",
           "STATUS_COLLAPSE_SPEED", "STATUS_COLLAPSE_STALL", "STATUS_NO_EVENTS",
           "STATUS_LAW_RANGE", "N_FSTATE",
           "N_ISTATE", "HEAP_PAD", "ZIGGURAT", "PREFETCH_MIN_N", "build_heap", "fill_normals",
           "kick_sweep", "run_events"]

# slots of the float state vector
F_T, F_T_KICK, F_DISS, F_INJ = 0, 1, 2, 3
N_FSTATE = 4
# slots of the integer state vector
I_NCOLL, I_HSIZE, I_STALL, I_NKICK, I_NELASTIC, I_BAD_PAIR = 0, 1, 2, 3, 4, 5
N_ISTATE = 6
HEAP_PAD = 4
"""Slots of ``hkey`` beyond ``N`` (always ``inf``)."""
# return codes of run_events
STATUS_COLLISIONS = 0  # reached the requested number of collisions
STATUS_TIME = 1  # reached the requested time
STATUS_COLLAPSE_SPEED = 3  # an inelastic collision below the collapse speed floor
STATUS_COLLAPSE_STALL = 4  # too many consecutive collisions without time advancing
STATUS_NO_EVENTS = 5  # no approaching pair and no kicks: free streaming forever
STATUS_LAW_RANGE = 6  # a collision faster than the restitution law's range (I_BAD_PAIR)

ZIGGURAT = ziggurat_tables()
"""``(ki, wi, fi)`` of the 256-layer normal ziggurat, passed to the kernels."""
PREFETCH_MIN_N = 1 << 14
"""From this N on (arrays beyond the 1 MiB L2 cache) :func:`run_events` prefetches."""


@jit
def _sift_up(heap, hkey, where, pos, p, kp):  # pragma: no cover - compiled
    """Place pair ``p`` with time ``kp`` at slot ``pos`` or above."""
    while pos > 0:
        parent = (pos - 1) >> 2
        kq = hkey[parent]
        if kq <= kp:
            break
        q = heap[parent]
        heap[pos] = q
        hkey[pos] = kq
        where[q] = pos
        pos = parent
    heap[pos] = p
    hkey[pos] = kp
    where[p] = pos


@jit
def _sift_down(heap, hkey, where, pos, p, kp, size):  # pragma: no cover - compiled
    """Place pair ``p`` with time ``kp`` at slot ``pos`` or below (heap of ``size``).

    The children of slot ``k`` are ``4k + 1 ... 4k + 4``; the earliest is found by a
    tournament (ties to the left) that reads the ``inf`` slots beyond the heap.
    """
    while True:
        c = 4 * pos + 1
        if c >= size:
            break
        c01 = c + (hkey[c + 1] < hkey[c])
        c23 = c + 2 + (hkey[c + 3] < hkey[c + 2])
        k01 = hkey[c01]
        k23 = hkey[c23]
        child = c01
        kc = k01
        if k23 < k01:
            child = c23
            kc = k23
        if kp <= kc:
            break
        q = heap[child]
        heap[pos] = q
        hkey[pos] = kc
        where[q] = pos
        pos = child
    heap[pos] = p
    hkey[pos] = kp
    where[p] = pos


@jit
def _heap_set(p, tp, t_cut, heap, hkey, where, istate):  # pragma: no cover - compiled
    """Give pair ``p`` the time ``tp``: update, insert, or remove if ``tp >= t_cut``."""
    pos = where[p]
    size = istate[I_HSIZE]
    if tp < t_cut:
        if pos < 0:
            istate[I_HSIZE] = size + 1
            _sift_up(heap, hkey, where, size, p, tp)
        elif pos > 0 and hkey[(pos - 1) >> 2] > tp:
            _sift_up(heap, hkey, where, pos, p, tp)
        else:
            _sift_down(heap, hkey, where, pos, p, tp, size)
    elif pos >= 0:
        _heap_remove(pos, heap, hkey, where, istate)


@jit
def _heap_remove(pos, heap, hkey, where, istate):  # pragma: no cover - compiled
    """Remove the pair at slot ``pos``."""
    size = istate[I_HSIZE] - 1
    istate[I_HSIZE] = size
    where[heap[pos]] = -1
    q = heap[size]
    kq = hkey[size]
    hkey[size] = np.inf  # keep the slots beyond the heap at inf
    if pos < size:
        if pos > 0 and hkey[(pos - 1) >> 2] > kq:
            _sift_up(heap, hkey, where, pos, q, kq)
        else:
            _sift_down(heap, hkey, where, pos, q, kq, size)


@jit
def _pair_time(q, t, x, v, tl, free_length):  # pragma: no cover - compiled
    """Predicted collision time of pair ``q`` = (q, q+1 mod N), or inf if receding.

    Selects instead of branches: approaching or not is a coin flip for the CPU.
    """
    n = x.shape[0]
    j = q + 1
    shift = 0.0
    if j == n:
        j = 0
        shift = free_length
    dv = v[q] - v[j]
    gap = (x[j] + v[j] * (t - tl[j]) + shift) - (x[q] + v[q] * (t - tl[q]))
    approaching = dv > 0.0
    tq = t + max(gap, 0.0) / (dv if approaching else 1.0)
    return tq if approaching else np.inf


@jit
def _heapify(heap, hkey, where, size, old_size):  # pragma: no cover - compiled
    """Heap order for the ``size`` entries in place (Floyd); clear the stale slots."""
    for k in range(size, old_size + 1):
        hkey[k] = np.inf
    for pos in range((size - 2) // 4, -1, -1):
        _sift_down(heap, hkey, where, pos, heap[pos], hkey[pos], size)


@jit
def build_heap(t, t_cut, x, v, tl, free_length, heap, hkey, where, istate):  # pragma: no cover
    """Recompute every pair time at time ``t`` and heapify the pairs before ``t_cut``."""
    n = x.shape[0]
    old = istate[I_HSIZE]
    size = 0
    for q in range(n):
        tq = _pair_time(q, t, x, v, tl, free_length)
        if tq < t_cut:
            heap[size] = q
            hkey[size] = tq
            where[q] = size
            size += 1
        else:
            where[q] = -1
    istate[I_HSIZE] = size
    _heapify(heap, hkey, where, size, max(old, n))


@jit
def fill_normals(out, rng, ki, wi, fi):  # pragma: no cover - compiled
    """Fill ``out`` with standard normals: ziggurat on xoshiro256** from state ``rng``.

    The fast path (one 64-bit number, a table look-up, one comparison; 99 % of the
    draws) is inlined with the generator state in registers; wedge and tail go to
    :func:`particles.rng.normal_slow` with the state written back.
    """
    s0, s1, s2, s3 = rng[0], rng[1], rng[2], rng[3]
    for i in range(out.shape[0]):
        r, s0, s1, s2, s3 = xoshiro(s0, s1, s2, s3)
        idx = int(r & np.uint64(0xFF))
        r >>= np.uint64(8)
        rabs = (r >> np.uint64(1)) & np.uint64(0x000FFFFFFFFFFFFF)
        z = float(np.int64(rabs)) * wi[idx]  # rabs < 2^52: exact conversion
        if r & np.uint64(1):
            z = -z
        if rabs >= ki[idx]:
            rng[0], rng[1], rng[2], rng[3] = s0, s1, s2, s3
            z = normal_slow(rng, idx, z, ki, wi, fi)
            s0, s1, s2, s3 = rng[0], rng[1], rng[2], rng[3]
        out[i] = z
    rng[0], rng[1], rng[2], rng[3] = s0, s1, s2, s3


@jit
def kick_sweep(tk, t_cut, decay, amp, xi, x, v, tl, free_length, heap, hkey, where,
               istate):  # pragma: no cover - compiled
    """Kick every rod at ``tk``, recompute all pair times, heap those before ``t_cut``.

    Rod ``i`` moves to ``tk`` and gets ``v[i] = decay * v[i] + amp * xi[i]`` (``decay``
    1 for white noise: exactly ``v[i] + amp * xi[i]``); pair ``i - 1`` is then
    screened at once by the conservative test
    ``gap < dv ((t_cut - tk)(1 + 1e-12) + 1e-14 t_cut)`` (rounding of the exact test
    is ~1e-16 relative), written without a branch: every pair is stored in ``heap``
    and the count advances only for those passing.  A second pass over these few
    candidates applies the exact rule of :func:`build_heap` (approaching and
    ``tk + gap/dv < t_cut``) and divides.  Returns the energy injected (net: a bath's
    friction can take energy out).
    """
    n = x.shape[0]
    old = istate[I_HSIZE]
    for k in range(old):
        where[heap[k]] = -1
    lim = (t_cut - tk) * (1.0 + 1e-12) + 1e-14 * abs(t_cut)
    inj = 0.0
    x_prev = x[0] + v[0] * (tk - tl[0])
    x[0] = x_prev
    tl[0] = tk
    vo = v[0]
    v_prev = vo * decay + amp * xi[0]
    v[0] = v_prev
    inj += 0.5 * (v_prev * v_prev - vo * vo)
    cand = 0
    for i in range(1, n):
        xn = x[i] + v[i] * (tk - tl[i])
        x[i] = xn
        tl[i] = tk
        vo = v[i]
        vn = vo * decay + amp * xi[i]
        v[i] = vn
        inj += 0.5 * (vn * vn - vo * vo)
        heap[cand] = i - 1
        cand += xn - x_prev < (v_prev - vn) * lim
        x_prev = xn
        v_prev = vn
    heap[cand] = n - 1  # pair N - 1 = (N - 1, 0) across the seam
    cand += x[0] + free_length - x_prev < (v_prev - v[0]) * lim
    size = 0
    for k in range(cand):
        q = heap[k]
        j = q + 1
        shift = 0.0
        if j == n:
            j = 0
            shift = free_length
        dv = v[q] - v[j]
        if dv > 0.0:
            gap = (x[j] + shift) - x[q]
            if gap < 0.0:
                gap = 0.0
            tq = tk + gap / dv
            if tq < t_cut:
                heap[size] = q
                hkey[size] = tq
                where[q] = size
                size += 1
    istate[I_HSIZE] = size
    _heapify(heap, hkey, where, size, old)
    return inj


@jit
def run_events(x, v, tl, heap, hkey, where, fstate, istate, rng, ki, wi, fi, normals, free_length,
               law, p0, p1, max_speed, threshold, kick_dt, kick_decay, kick_amp, speed_floor,
               max_stall, t_stop, coll_stop):  # pragma: no cover - compiled
    """Advance the event-driven dynamics until a stop condition; return a status code.

    Parameters
    ----------
    x, v, tl : ndarray, shape (N,)
        Lazy positions on the reduced ring, velocities, times of last update.
    heap, where : ndarray of int32 (or int64), shape (N,)
        Indexed min-heap: pair indices in heap order, and the slot of each pair (-1
        if not queued).  The engine uses int32: less memory traffic at large N.
    hkey : ndarray, shape (N + HEAP_PAD,)
        The pairs' predicted times in heap order; ``inf`` from the heap size on.
    fstate : ndarray, shape (N_FSTATE,)
        Time, time of the next kick, energy dissipated, energy injected.
    istate : ndarray, shape (N_ISTATE,)
        Collisions, heap size, stall counter, kicks, threshold (elastic) collisions,
        pair of the last collapse.
    rng : ndarray of uint64, shape (4,)
        xoshiro256** state of the kick normals (unused when ``kick_dt`` is inf).
    ki, wi, fi : ndarray, shape (256,)
        Ziggurat tables (:data:`ZIGGURAT`).
    normals : ndarray, shape (N,)
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
    speed_floor : float
        An inelastic collision slower than this signals inelastic collapse.
    max_stall : int
        Consecutive collisions allowed without the time advancing by more than
        1e-13 relative.
    t_stop, coll_stop : float, int
        Stop before the first event after ``t_stop`` or after ``coll_stop`` collisions
        in total.
    """
    n = x.shape[0]
    t = fstate[F_T]
    t_kick = fstate[F_T_KICK]
    diss = fstate[F_DISS]
    n_coll = istate[I_NCOLL]
    stall = istate[I_STALL]
    n_elastic = istate[I_NELASTIC]
    status = STATUS_COLLISIONS
    p = 0
    use_prefetch = n >= PREFETCH_MIN_N
    while True:
        if n_coll >= coll_stop:
            status = STATUS_COLLISIONS
            break
        if istate[I_HSIZE] > 0:
            p = heap[0]
            tc = hkey[0]
        else:
            tc = np.inf
        if tc >= t_kick and t_kick < np.inf:  # pairs beyond the next kick are not in the heap
            if t_kick > t_stop:
                status = STATUS_TIME
                break
            nk = istate[I_NKICK] + 1
            t = t_kick
            t_kick = (nk + 1) * kick_dt
            fill_normals(normals, rng, ki, wi, fi)
            fstate[F_INJ] += kick_sweep(t, t_kick, kick_decay, kick_amp, normals, x, v, tl,
                                        free_length, heap, hkey, where, istate)
            istate[I_NKICK] = nk
            continue
        if tc > t_stop or tc == np.inf:
            status = STATUS_TIME if tc < np.inf else STATUS_NO_EVENTS
            break
        # --- collision of pair p = (i, j) at time tc
        if use_prefetch and istate[I_HSIZE] > 4:
            # the earliest child of the root is likely the next collision: fetch its
            # rods while this one is processed (overlaps the cache misses of large N)
            c01 = 1 + (hkey[2] < hkey[1])
            c23 = 3 + (hkey[4] < hkey[3])
            q2 = heap[c23] if hkey[c23] < hkey[c01] else heap[c01]
            prefetch(x, q2)
            prefetch(v, q2)
            prefetch(tl, q2)
            prefetch(where, q2)
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
        if a == 1.0:  # elastic: exchange exactly, energy and P(v) unchanged
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
        # pair p now recedes and leaves the root; its two neighbour pairs change.
        # A neighbour not yet queued (the earlier one if both) takes over the root
        # slot: one sift-down instead of a removal and an insertion.
        left = p - 1 if p > 0 else n - 1
        t_left = _pair_time(left, t, x, v, tl, free_length)
        t_right = _pair_time(j, t, x, v, tl, free_length)
        where[p] = -1
        right_first = t_right < t_left  # (selects, no branch)
        first = j if right_first else left
        second = left if right_first else j
        t_first = min(t_left, t_right)
        t_second = t_left if right_first else t_right
        two = second != first  # (N = 2 has a single neighbour pair)
        if t_first < t_kick and where[first] < 0:
            _sift_down(heap, hkey, where, 0, first, t_first, istate[I_HSIZE])
            if two:
                _heap_set(second, t_second, t_kick, heap, hkey, where, istate)
        elif two and t_second < t_kick and where[second] < 0:
            # first is queued (and due before the kick, as t_first <= t_second)
            _sift_down(heap, hkey, where, 0, second, t_second, istate[I_HSIZE])
            _heap_set(first, t_first, t_kick, heap, hkey, where, istate)
        else:
            _heap_remove(0, heap, hkey, where, istate)
            _heap_set(first, t_first, t_kick, heap, hkey, where, istate)
            if two:
                _heap_set(second, t_second, t_kick, heap, hkey, where, istate)
    fstate[F_T] = t
    fstate[F_T_KICK] = t_kick
    fstate[F_DISS] = diss
    istate[I_NCOLL] = n_coll
    istate[I_STALL] = stall
    istate[I_NELASTIC] = n_elastic
    return status
