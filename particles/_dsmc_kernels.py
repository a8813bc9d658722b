"""Numba kernels of the homogeneous DSMC (see :mod:`particles.dsmc`).

Flat arrays and scalars in, arrays updated in place; no global state.  The random
stream is an explicit-state xoshiro256** generator (Blackman and Vigna 2018): its
state is a ``uint64`` array of length 4, seeded from a ``numpy.random.SeedSequence``
by the driver and saved in checkpoints, so a run resumes bit-identically.  Drawing
inside the kernel costs about 1 ns per 64-bit number, against 3-4 ns for a numpy
``random_raw`` block and 13 ns for a numpy normal on this machine.

Candidate pair ``(i, j)``, ``i != j``: ``i = floor(r1 N / 2^64)`` (multiply-high,
non-uniformity at most ``N / 2^64 < 1e-12``), ``j`` likewise from ``r2`` over the
``N - 1`` other particles.  The acceptance uniform is the low 64 bits of
``r1 N``, which given ``i`` is uniform on a lattice of spacing ``N / 2^64``.
Gaussians: the 256-layer ziggurat of Marsaglia and Tsang (2000), the same
construction as numpy's, with tables built by :func:`ziggurat_tables`.
"""

from __future__ import annotations

import math

import numpy as np

from ._jit import jit

__all__ = ["ziggurat_tables", "next_u64", "next_double", "fill_normal",
           "collide", "kick", "extent", "central_sums", "heated_segment", "cooling_block"]

_R = 3.6541528853610088  # start of the tail of the 256-layer normal ziggurat
_V = 0.00492867323399  # area of each layer
_M1 = 2.0**52


def ziggurat_tables() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Tables ``(ki, wi, fi)`` of the 256-layer normal ziggurat.

    Layer ``i`` spans ``[0, x_i]``; ``wi = x_i / 2^52`` turns 52 random bits into
    ``x``; ``ki`` is the acceptance threshold ``2^52 x_{i-1}/x_i`` of the part of
    the layer that lies under the density; ``fi = exp(-x_i^2/2)``.
    """
    ki = np.zeros(256, dtype=np.uint64)
    wi = np.zeros(256)
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
    return ki, wi, fi


@jit
def _rotl(x, k):  # pragma: no cover - compiled
    return (x << np.uint64(k)) | (x >> np.uint64(64 - k))


@jit
def next_u64(s):  # pragma: no cover - compiled
    """One 64-bit output of xoshiro256**; advances the state ``s`` (uint64[4])."""
    result = _rotl(s[1] * np.uint64(5), 7) * np.uint64(9)
    t = s[1] << np.uint64(17)
    s[2] ^= s[0]
    s[3] ^= s[1]
    s[1] ^= s[2]
    s[0] ^= s[3]
    s[2] ^= t
    s[3] = _rotl(s[3], 45)
    return result


@jit
def next_double(s):  # pragma: no cover - compiled
    """Uniform double on [0, 1) with 53 random bits."""
    return float(next_u64(s) >> np.uint64(11)) * (1.0 / 9007199254740992.0)


@jit
def _mulhi(r, n):  # pragma: no cover - compiled
    """``floor(r * n / 2^64)`` for ``n < 2^32`` without 128-bit integers."""
    mask = np.uint64(0xFFFFFFFF)
    a = r >> np.uint64(32)
    b = r & mask
    return (a * n + ((b * n) >> np.uint64(32))) >> np.uint64(32)


@jit
def _zig_draw(s, wi):  # pragma: no cover - compiled
    """One ziggurat proposal from one 64-bit number: ``(layer, 52 bits, signed x)``."""
    r = next_u64(s)
    idx = int(r & np.uint64(0xFF))
    r >>= np.uint64(8)
    rabs = (r >> np.uint64(1)) & np.uint64(0x000FFFFFFFFFFFFF)
    x = float(np.int64(rabs)) * wi[idx]  # rabs < 2^52: the signed conversion is exact
    if r & np.uint64(1):
        x = -x
    return idx, rabs, x


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

    Ziggurat: 99 % of the draws take one 64-bit number and the fast path
    (:func:`_zig_draw` and one comparison); the rest go to :func:`_normal_slow`.
    (Keeping the rare paths in a separate function called from the loop matters: in
    one ``next_normal`` function numba's code for the fast path was 20-50x slower.)
    """
    lo = np.inf
    hi = -np.inf
    for k in range(v.shape[0]):
        idx, rabs, x = _zig_draw(s, wi)
        if rabs >= ki[idx]:
            x = _normal_slow(s, idx, x, ki, wi, fi)
        y = v[k] + amp * x
        v[k] = y
        lo = min(lo, y)
        hi = max(hi, y)
    return lo, hi


@jit
def collide(v, n_candidates, alpha, g_max, s):  # pragma: no cover - compiled
    """Process ``n_candidates`` candidate pairs with the majorant ``g_max``.

    A pair is accepted with probability ``|v_i - v_j| / g_max`` and collides:
    ``v_i -= (1+alpha)/2 (v_i - v_j)``, ``v_j += (1+alpha)/2 (v_i - v_j)``.
    ``g_max >= max(v) - min(v)`` stays a bound because post-collision velocities
    are convex combinations of the pre-collision ones.

    Returns
    -------
    accepted : int
        Number of collisions.
    sum_g2 : float
        :math:`\\sum g^2` over the collisions; the energy lost is
        :math:`\\tfrac12 (1-\\alpha^2) \\sum g^2`.
    """
    n = np.uint64(v.shape[0])
    n1 = n - np.uint64(1)
    half = 0.5 * (1.0 + alpha)
    scale = g_max * (1.0 / 9007199254740992.0)  # g_max / 2^53
    accepted = 0
    sum_g2 = 0.0
    for _ in range(n_candidates):
        r1 = next_u64(s)
        r2 = next_u64(s)
        i = _mulhi(r1, n)
        j = _mulhi(r2, n1)
        j += np.uint64(j >= i)
        # uniform(0, g_max) from the low 64 bits of r1 * N (top 53 of them)
        threshold = float(np.int64((r1 * n) >> np.uint64(11))) * scale
        vi = v[i]
        vj = v[j]
        g = vi - vj
        if abs(g) > threshold:
            dv = half * g
            v[i] = vi - dv
            v[j] = vj + dv
            accepted += 1
            sum_g2 += g * g
    return accepted, sum_g2


@jit
def central_sums(v, kmax):  # pragma: no cover - compiled
    """Mean and central moments :math:`\\langle (v-u)^k\\rangle`, ``k = 0..kmax``."""
    n = v.shape[0]
    mean = 0.0
    for k in range(n):
        mean += v[k]
    mean /= n
    out = np.zeros(kmax + 1)
    for k in range(n):
        d = v[k] - mean
        p = 1.0
        for m in range(kmax + 1):
            out[m] += p
            p *= d
    return mean, out / n


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
def cooling_block(v, n_candidates, refresh, alpha, s):  # pragma: no cover - compiled
    """``n_candidates`` candidates of free cooling with rescaling to unit temperature.

    Every ``refresh`` candidates the velocities are moved to the centre-of-mass frame
    and divided by their standard deviation ``sd`` (so neither the spread nor its
    ratio to the round-off of the mean can underflow), and the majorant
    ``g_max = max(v) - min(v)`` is re-measured.

    Returns
    -------
    accepted : int
        Number of collisions.
    log_scale : float
        :math:`\\sum \\ln sd`: physical velocities are ``exp(log_scale)`` times the
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
        mean, cm = central_sums(v, 2)
        if not cm[2] > 0.0:
            break  # all velocities equal: no collision can ever happen again
        sd = math.sqrt(cm[2])
        for k in range(n):
            v[k] = (v[k] - mean) / sd
        log_scale += math.log(sd)
        m = min(refresh, n_candidates - done)
        lo, hi = extent(v)
        a, g2 = collide(v, m, alpha, hi - lo, s)
        accepted += a
        elapsed += m / ((hi - lo) * math.exp(log_scale))
        done += m
    return accepted, log_scale, elapsed
