"""Numba kernels of the MD's random kicks: the normals and the sweep over all rods.

A kick moves every rod to the kick time :math:`t_k` and updates
:math:`v_i \\to d\\,v_i + b\\,\\xi_i` (white noise: :math:`d = 1`; a Fokker-Planck
bath: the exact Ornstein-Uhlenbeck transition, see :class:`particles.md.Kicks`), then
starts the event calendar's next epoch :math:`[t_k, t_k + \\Delta t_k)`
(:func:`particles._md_calendar.calendar_start`) with the pairs that meet before the
following kick.  The standard normals :math:`\\xi_i` come from a branch-free
Box-Muller transform on a counter-based splitmix64 stream (:func:`fill_normals`; its
state, one ``uint64``, is saved in checkpoints with :data:`STREAM_VERSION`).  Arrays
and scalars only; called from :func:`particles._md_kernels.run_events`.
"""

from __future__ import annotations

import math

import numpy as np
from llvmlite import ir
from numba.core import types
from numba.extending import intrinsic, overload

from ._jit import jit
from ._md_calendar import I_HSIZE, calendar_start

__all__ = ["STREAM_VERSION", "as_u64", "as_f64", "box_muller", "fill_normals", "kick_sweep"]


STREAM_VERSION = 2
"""Version of the MD's random stream and event order, saved in checkpoints.

1: kick normals from the ziggurat on xoshiro256** (state ``uint64[4]``); 2: the
Box-Muller normals of :func:`fill_normals` on a splitmix64 counter (``uint64[1]``).
A checkpoint of another version is refused: it could not resume bit-identically."""

_ONE = 0x3FF0000000000000  # bits of 1.0
_MANT = 0x000FFFFFFFFFFFFF
_TWO52 = 0x4330000000000000  # bits of 2^52
_GAMMA = 0x9E3779B97F4A7C15  # splitmix64's Weyl increment


def as_u64(x):
    """The bits of the float64 ``x`` as a uint64 (a bit cast; compiled: one register move)."""
    return np.float64(x).view(np.uint64)


def as_f64(b):
    """The float64 whose bits are the uint64 ``b``."""
    return np.uint64(b).view(np.float64)


@intrinsic
def _bits_u64(typingctx, x):  # pragma: no cover - compiled
    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], ir.IntType(64))

    return types.uint64(types.float64), codegen


@intrinsic
def _bits_f64(typingctx, b):  # pragma: no cover - compiled
    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], ir.DoubleType())

    return types.float64(types.uint64), codegen


@overload(as_u64, jit_options={"cache": True})  # type: ignore[typeddict-unknown-key]
def _as_u64_jit(x):  # pragma: no cover - compiled
    return lambda x: _bits_u64(x)


@overload(as_f64, jit_options={"cache": True})  # type: ignore[typeddict-unknown-key]
def _as_f64_jit(b):  # pragma: no cover - compiled
    return lambda b: _bits_f64(b)


@jit(inline="always")
def _splitmix(z):  # pragma: no cover - compiled
    """The splitmix64 finaliser (Steele, Lea and Flood 2014) of the counter value ``z``."""
    z = (z ^ (z >> np.uint64(30))) * np.uint64(0xBF58476D1CE4E5B9)
    z = (z ^ (z >> np.uint64(27))) * np.uint64(0x94D049BB133111EB)
    return z ^ (z >> np.uint64(31))


@jit(inline="always", error_model="numpy")
def box_muller(a, b):  # pragma: no cover - compiled
    """Two independent standard normals from the 64-bit numbers ``a``, ``b``; no branch.

    Radius :math:`R = \\sqrt{-2\\ln u}`, :math:`u = 1 - k/2^{52} \\in (0, 1]` from
    the high 52 bits of ``a`` (so :math:`|z| \\le 8.49`, probability 2e-17 lost);
    :math:`\\ln u = e\\ln 2 + 2\\,\\mathrm{atanh}\\,s`, :math:`s = (m - 1)/(m + 1)`
    with the mantissa :math:`m \\in [\\sqrt{1/2}, \\sqrt 2)` and the atanh series
    to :math:`s^{19}` (relative error below 4e-16).  Angle
    :math:`\\theta = \\tfrac{\\pi}{2}(f - \\tfrac12)`, ``f`` from 52 bits of ``b``;
    sine and cosine by their Taylor series to :math:`\\theta^{15}` and
    :math:`\\theta^{16}` (error below 2e-16); three low bits of ``a`` pick the quadrant
    (swap and two signs), so the angle is uniform on the circle.  The polynomials are
    those of the shared C yardstick (``md_edmd.c``); written without branches and
    without integer-to-float conversions (bit casts instead), a loop over these
    vectorises.
    """
    one = np.uint64(_ONE)
    u = 2.0 - as_f64((a >> np.uint64(12)) | one)
    bits = as_u64(u)
    e = as_f64((bits >> np.uint64(52)) | np.uint64(_TWO52)) - (4503599627370496.0 + 1023.0)
    m = as_f64((bits & np.uint64(_MANT)) | one)
    big = m > 1.4142135623730951
    m = 0.5 * m if big else m
    e = e + 1.0 if big else e
    s = (m - 1.0) / (m + 1.0)
    z = s * s
    p = 1.0 / 19.0
    p = p * z + 1.0 / 17.0
    p = p * z + 1.0 / 15.0
    p = p * z + 1.0 / 13.0
    p = p * z + 1.0 / 11.0
    p = p * z + 1.0 / 9.0
    p = p * z + 1.0 / 7.0
    p = p * z + 1.0 / 5.0
    p = p * z + 1.0 / 3.0
    p = p * z
    s2 = s + s
    lg = e * 0.6931471805599453 + (s2 * p + s2)
    r = math.sqrt(-2.0 * lg)
    th = (as_f64((b >> np.uint64(12)) | one) - 1.5) * 1.5707963267948966
    t2 = th * th
    sp = -1.0 / 1307674368000.0
    sp = sp * t2 + 1.0 / 6227020800.0
    sp = sp * t2 - 1.0 / 39916800.0
    sp = sp * t2 + 1.0 / 362880.0
    sp = sp * t2 - 1.0 / 5040.0
    sp = sp * t2 + 1.0 / 120.0
    sp = sp * t2 - 1.0 / 6.0
    sn = (sp * t2) * th + th
    cp = 1.0 / 20922789888000.0
    cp = cp * t2 - 1.0 / 87178291200.0
    cp = cp * t2 + 1.0 / 479001600.0
    cp = cp * t2 - 1.0 / 3628800.0
    cp = cp * t2 + 1.0 / 40320.0
    cp = cp * t2 - 1.0 / 720.0
    cp = cp * t2 + 1.0 / 24.0
    cp = cp * t2 - 0.5
    cs = cp * t2 + 1.0
    swap = (a & np.uint64(4)) != np.uint64(0)
    z1 = r * (cs if swap else sn)
    z2 = r * (sn if swap else cs)
    z1 = as_f64(as_u64(z1) ^ (a << np.uint64(63)))  # sign bits of a flip the signs
    z2 = as_f64(as_u64(z2) ^ ((a >> np.uint64(1)) << np.uint64(63)))
    return z1, z2


@jit(error_model="numpy")
def fill_normals(out, counter):  # pragma: no cover - compiled
    """Fill ``out`` (even length) with standard normals; advance ``counter`` (uint64[1]).

    Pair ``k`` of Box-Muller normals (:func:`box_muller`) comes from the splitmix64
    values of the counter steps ``2k + 1`` and ``2k + 2``: a counter-based stream with
    no dependency between pairs, so the loop vectorises (about 1.5x faster than the
    ziggurat on xoshiro256** it replaces, measured in one process on a loaded
    machine: 5.1-5.3 against 7.8-7.9 ns per normal).  The first normal of pair ``k``
    goes to ``out[k]``, the second to ``out[N/2 + k]``.
    """
    c = counter[0]
    h = out.shape[0] // 2
    g = np.uint64(_GAMMA)
    for k in range(h):
        w = c + np.uint64(2 * k + 1) * g
        z1, z2 = box_muller(_splitmix(w), _splitmix(w + g))
        out[k] = z1
        out[h + k] = z2
    counter[0] = c + np.uint64(2 * h) * g


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
