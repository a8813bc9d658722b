"""Numba kernels of the MD's random kicks: the normals and the sweep over all rods.

A kick moves every rod to the kick time :math:`t_k` and updates
:math:`v_i \\to d\\,v_i + b\\,\\xi_i` (white noise: :math:`d = 1`; a Fokker-Planck
bath: the exact Ornstein-Uhlenbeck transition, see :class:`particles.md.Kicks`), then
starts the event calendar's next epoch :math:`[t_k, t_k + \\Delta t_k)`
(:func:`particles._md_calendar.calendar_start`) with the pairs that meet before the
following kick.  The standard normals :math:`\\xi_i` come from the ziggurat of
:mod:`particles.rng` on an explicit-state xoshiro256** generator.  Arrays and scalars
only; called from :func:`particles._md_kernels.run_events`.
"""

from __future__ import annotations

import numpy as np

from ._jit import jit
from ._md_calendar import I_HSIZE, calendar_start
from .rng import normal_slow, xoshiro

__all__ = ["fill_normals", "kick_sweep"]


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
def kick_sweep(tk, t_cut, decay, amp, xi, x, v, tl, free_length, heap, hkey, where, ptime,
               head, nxt, prv, bkt, fstate, istate):  # pragma: no cover - compiled
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
        hkey[k] = np.inf
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
                size += 1
    calendar_start(size, tk, t_cut, heap, hkey, where, ptime, head, nxt, prv, bkt, fstate,
                   istate)
    return inj
