"""Numba kernels of the homogeneous DSMC (see :mod:`particles.dsmc`).

Flat arrays and scalars in, arrays updated in place; no global state.  The random
stream is an explicit-state xoshiro256** generator (Blackman and Vigna 2018): its
state is a ``uint64`` array of length 4, seeded from a ``numpy.random.SeedSequence``
by the driver and saved in checkpoints, so a run resumes bit-identically.  The
kernels copy the four words into local variables (registers) on entry and write them
back on exit: kept in the array, every draw waited for a store and a reload of the
state.  A draw then costs about 1 ns (consecutive draws form a chain of dependent
xor/rotate steps), against 3-4 ns for a numpy ``random_raw`` block and 13 ns for a
numpy normal on this machine.

Candidate pair ``(i, j)``, ``i != j``: ``i = floor(r1 N / 2^64)`` (the high word of
one 64 x 64 -> 128-bit multiply, :func:`_mul128`; non-uniformity at most
``N / 2^64 < 1e-12``), ``j`` likewise from ``r2`` over the ``N - 1`` other particles.
The acceptance uniform is the low word of the same product ``r1 N``, which given
``i`` is uniform on a lattice of spacing ``N / 2^64``.
Gaussians: the 256-layer ziggurat of Marsaglia and Tsang (2000), the same
construction as numpy's, with tables built by :func:`ziggurat_tables`.

:func:`collide` is branch-free (every candidate stores ``v_i - a\\,\\delta``,
``v_j + a\\,\\delta`` with ``a`` in {0, 1}; the accept/reject branch was
mispredicted for a fifth of the candidates).  For ``N >= PREFETCH_MIN_N`` (``v``
larger than the 1 MiB L2 cache) it draws the pairs ``PREFETCH_BATCH`` candidates
ahead into a small buffer and prefetches their velocities into L2, so that the
cache misses of many candidates overlap; each candidate is still accepted and
collided in order on the current velocities.  The random stream, the candidates and
the collisions are exactly those of the plain loop (bit-identical results); only the
memory latency changes.  Without the prefetch each candidate at ``N = 10^6`` waited
for two cache misses in turn (9-50 ns per candidate, depending on how much of the
shared L3 cache the other jobs leave, instead of 4).

Costs on one core of the development machine (AMD EPYC, Zen 4; CPU time, from
``benchmarks/bench_dsmc.py``): a candidate takes 3.0 ns at ``N = 25000`` (``v`` in
L2), of which the two draws with the pair and the acceptance uniform take 2.6 ns on
their own (the two draws 1.7 ns): the loop is bound by the random numbers, the
accept/collide work (two loads, a select, two stores) overlaps with them.  At
``N = 10^6`` it takes 3.8-4.2 ns: the prefetch hides the memory latency, the buffer
adds about 0.7 ns.  The cooling refresh adds 0.6 ns per candidate (one sweep of sums
and extent, bound by its floating-point operations, and the rescaling).  A kick takes 2.25 ns per
velocity (one draw, two table look-ups, the add and the running extent: bound by the
instruction throughput); at a time step of 0.05 mean free times the kicks are 80 % of
the cost of the heated gas.
"""

from __future__ import annotations

import math

import numpy as np
from llvmlite import ir
from numba.core import types
from numba.extending import intrinsic, overload

from ._jit import jit, prefetch

__all__ = ["ziggurat_tables", "next_u64", "next_double", "fill_normal",
           "collide", "kick", "extent", "central_sums", "heated_segment", "cooling_block",
           "PREFETCH_MIN_N", "PREFETCH_BATCH"]

PREFETCH_MIN_N = 1 << 17
"""Smallest ``N`` for which :func:`collide` draws ahead and prefetches (``v`` of 1 MiB,
the L2 cache; below it the plain loop is faster, 3.0 against 3.8 ns per candidate)."""

PREFETCH_BATCH = 128
"""How many candidates ahead the prefetching :func:`collide` draws the pairs."""

_R = 3.6541528853610088  # start of the tail of the 256-layer normal ziggurat
_V = 0.00492867323399  # area of each layer
_M1 = 2.0**52


def ziggurat_tables() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Tables ``(ki, wi, fi)`` of the 256-layer normal ziggurat.

    Layer ``i`` spans ``[0, x_i]``; ``wi = x_i / 2^52`` turns 52 random bits into
    ``x``; ``ki`` is the acceptance threshold ``2^52 x_{i-1}/x_i`` of the part of
    the layer that lies under the density; ``fi = exp(-x_i^2/2)``.  ``wi`` has 512
    entries, ``wi[256 + i] = -wi[i]``: the layer and the sign bit (9 random bits)
    index a signed width, which saves the sign logic in the kernels' inner loop.
    """
    ki = np.zeros(256, dtype=np.uint64)
    wi = np.zeros(512)
    fi = np.zeros(256)
    dn = tn = _R
    q = _V / math.exp(-0.5 * dn * dn)
    ki[0] = np.uint64(int((dn / q) * _M1))
    ki[1] = np.uint64(0)
    wi[0] = q / _M1
    wi[255] = dn / _M1
    fi[0] = 1.0
    fi[255] = math.exp(-0.5 * dn * dn)
    for i in range(254, 0, -1):
        dn = math.sqrt(-2.0 * math.log(_V / dn + math.exp(-0.5 * dn * dn)))
        ki[i + 1] = np.uint64(int((dn / tn) * _M1))
        tn = dn
        fi[i] = math.exp(-0.5 * dn * dn)
        wi[i] = dn / _M1
    wi[256:] = -wi[:256]
    return ki, wi, fi


@jit
def _rotl(x, k):  # pragma: no cover - compiled
    return (x << np.uint64(k)) | (x >> np.uint64(64 - k))


@jit
def _xoshiro(s0, s1, s2, s3):  # pragma: no cover - compiled
    """xoshiro256** on a state held in four local variables: ``(result, s0, s1, s2, s3)``."""
    result = _rotl(s1 * np.uint64(5), 7) * np.uint64(9)
    t = s1 << np.uint64(17)
    s2 ^= s0
    s3 ^= s1
    s1 ^= s2
    s0 ^= s3
    s2 ^= t
    s3 = _rotl(s3, 45)
    return result, s0, s1, s2, s3


@jit
def next_u64(s):  # pragma: no cover - compiled
    """One 64-bit output of xoshiro256**; advances the state ``s`` (uint64[4])."""
    result, s[0], s[1], s[2], s[3] = _xoshiro(s[0], s[1], s[2], s[3])
    return result


@jit
def next_double(s):  # pragma: no cover - compiled
    """Uniform double on [0, 1) with 53 random bits."""
    return float(next_u64(s) >> np.uint64(11)) * (1.0 / 9007199254740992.0)


@intrinsic
def _llvm_mul128(typingctx, a, b):  # pragma: no cover - compiled
    """Full 128-bit product of two uint64: ``(high, low)`` words (one ``mul``)."""
    if not (a == types.uint64 and b == types.uint64):
        return None
    sig = types.UniTuple(types.uint64, 2)(a, b)

    def codegen(context, builder, signature, args):
        i64, i128 = ir.IntType(64), ir.IntType(128)
        p = builder.mul(builder.zext(args[0], i128), builder.zext(args[1], i128))
        hi = builder.trunc(builder.lshr(p, ir.Constant(i128, 64)), i64)
        return context.make_tuple(builder, signature.return_type, (hi, builder.trunc(p, i64)))

    return sig, codegen


def _mul128(r, n):
    """``(floor(r n / 2^64), r n mod 2^64)`` for uint64 ``r``, ``n`` (Python ints here)."""
    p = int(r) * int(n)
    return np.uint64(p >> 64), np.uint64(p & 0xFFFFFFFFFFFFFFFF)


@overload(_mul128, jit_options={"cache": True})
def _mul128_jit(r, n):  # pragma: no cover - compiled
    def impl(r, n):
        return _llvm_mul128(r, n)

    return impl


@jit
def _mulhi(r, n):  # pragma: no cover - compiled
    """``floor(r * n / 2^64)`` for uint64 ``r``, ``n``."""
    return _mul128(r, n)[0]


@jit
def _mul128_pair(r, n):  # pragma: no cover - compiled
    """:func:`_mul128` as a kernel (for tests)."""
    return _mul128(r, n)




@jit
def _zig_draw(s, wi):  # pragma: no cover - compiled
    """One ziggurat proposal from one 64-bit number: ``(layer, 52 bits, signed x)``."""
    r = next_u64(s)
    layer_sign = r & np.uint64(0x1FF)  # bits 0-7: layer, bit 8: sign
    rabs = (r >> np.uint64(9)) & np.uint64(0x000FFFFFFFFFFFFF)
    x = float(np.int64(rabs)) * wi[layer_sign]  # rabs < 2^52: the conversion is exact
    return int(layer_sign & np.uint64(0xFF)), rabs, x


@jit
def _normal_slow(s, idx, x, ki, wi, fi):  # pragma: no cover - compiled
    """Finish a draw that missed the fast region of layer ``idx`` at ``x``.

    Layer 0: Marsaglia's exact tail beyond ``R`` (retried until accepted), signed
    like ``x``.  Other layers: the wedge test; on rejection a new proposal is drawn.
    """
    while True:
        if idx == 0:
            while True:
                xx = -math.log1p(-next_double(s)) * (1.0 / _R)
                yy = -math.log1p(-next_double(s))
                if yy + yy > xx * xx:
                    return -(_R + xx) if x < 0.0 else _R + xx
        if (fi[idx - 1] - fi[idx]) * next_double(s) + fi[idx] < math.exp(-0.5 * x * x):
            return x
        idx, rabs, x = _zig_draw(s, wi)
        if rabs < ki[idx]:
            return x


@jit
def fill_normal(out, s, ki, wi, fi):  # pragma: no cover - compiled
    """Fill ``out`` with standard normals (the numbers :func:`kick` would add)."""
    out[:] = 0.0
    kick(out, 1.0, s, ki, wi, fi)


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
def kick(v, amp, s, ki, wi, fi):  # pragma: no cover - compiled
    """``v += amp * xi`` with independent standard normals; returns the new ``(min, max)``.

    Ziggurat: 99 % of the draws take one 64-bit number and the fast path (a table
    look-up and one comparison, inlined here with the generator state in registers);
    the rest go to :func:`_normal_slow` with the state written back to ``s``.
    (Keeping the rare paths in a separate function called from the loop matters: in
    one ``next_normal`` function numba's code for the fast path was 20-50x slower.)
    """
    lo = np.inf
    hi = -np.inf
    s0, s1, s2, s3 = s[0], s[1], s[2], s[3]
    for k in range(v.shape[0]):
        r, s0, s1, s2, s3 = _xoshiro(s0, s1, s2, s3)
        layer_sign = r & np.uint64(0x1FF)  # as in _zig_draw
        idx = int(layer_sign & np.uint64(0xFF))
        rabs = (r >> np.uint64(9)) & np.uint64(0x000FFFFFFFFFFFFF)
        x = float(np.int64(rabs)) * wi[layer_sign]
        if rabs >= ki[idx]:
            s[0], s[1], s[2], s[3] = s0, s1, s2, s3
            x = _normal_slow(s, idx, x, ki, wi, fi)
            s0, s1, s2, s3 = s[0], s[1], s[2], s[3]
        y = v[k] + amp * x
        v[k] = y
        if y < lo:
            lo = y
        if y > hi:
            hi = y
    s[0], s[1], s[2], s[3] = s0, s1, s2, s3
    return lo, hi


@jit
def collide(v, n_candidates, alpha, g_max, s, batch=-1):  # pragma: no cover - compiled
    """Process ``n_candidates`` candidate pairs with the majorant ``g_max``.

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
    r1, s0, s1, s2, s3 = _xoshiro(s0, s1, s2, s3)
    r2, s0, s1, s2, s3 = _xoshiro(s0, s1, s2, s3)
    i, low = _mul128(r1, n)
    j = _mul128(r2, n1)[0]
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
def heated_segment(v, n_steps, dt, amp, rate, alpha, debt, s, ki, wi, fi):  # pragma: no cover
    """``n_steps`` Strang steps :math:`K(dt/2)\\,C(dt)\\,K(dt/2)`, merged half kicks.

    ``amp = sqrt(2 D dt)`` is the full-step kick; a half kick has ``amp/sqrt(2)``.
    The collision stage of each step uses the majorant ``g_max = max - min`` measured
    right after the kick, and ``debt + dt * rate * g_max`` candidates (integer part;
    the fraction is carried to the next step), ``rate = n N / 2``.

    Returns ``(accepted, sum_g2, debt)``.
    """
    half_amp = amp / math.sqrt(2.0)
    accepted = 0
    sum_g2 = 0.0
    lo, hi = kick(v, half_amp, s, ki, wi, fi)
    for step in range(n_steps):
        x = debt + dt * rate * (hi - lo)
        m = int(math.floor(x))
        debt = x - m
        a, g2 = collide(v, m, alpha, hi - lo, s)
        accepted += a
        sum_g2 += g2
        lo, hi = kick(v, amp if step < n_steps - 1 else half_amp, s, ki, wi, fi)
    return accepted, sum_g2, debt


@jit
def _sums_extent(v):  # pragma: no cover - compiled
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
def _central_variance(v, mean):  # pragma: no cover - compiled
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
def cooling_block(v, n_candidates, refresh, alpha, s):  # pragma: no cover - compiled
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

    Returns
    -------
    accepted : int
        Number of collisions.
    log_scale : float
        :math:`-\\sum \\ln(1/sd)`: physical velocities are ``exp(log_scale)`` times the
        returned ones, in the units of ``v`` on entry.
    time : float
        :math:`\\sum_k m_k / (g_{max,k}\\, e^{\\text{log\\_scale}_k})`; each candidate
        advances time by :math:`2/(n N g_{max})`, so the elapsed time is
        ``2 time / (n N)`` in the units of ``v`` on entry.
    """
    n = v.shape[0]
    accepted = 0
    log_scale = 0.0
    elapsed = 0.0
    done = 0
    while done < n_candidates:
        s1, s2, lo, hi = _sums_extent(v)
        mean = s1 / n
        mean_sq = s2 / n
        if mean * mean <= 1e-8 * mean_sq:  # centred: no cancellation
            var = mean_sq - mean * mean
        else:
            var = _central_variance(v, mean)
        if not var > 0.0:
            break  # all velocities equal: no collision can ever happen again
        inv_sd = 1.0 / math.sqrt(var)  # a multiply per velocity, not a divide
        for k in range(n):
            v[k] = (v[k] - mean) * inv_sd
        lo = (lo - mean) * inv_sd
        hi = (hi - mean) * inv_sd
        log_scale -= math.log(inv_sd)  # the factor actually applied
        m = min(refresh, n_candidates - done)
        a, g2 = collide(v, m, alpha, hi - lo, s)
        accepted += a
        elapsed += m / ((hi - lo) * math.exp(log_scale))
        done += m
    return accepted, log_scale, elapsed
