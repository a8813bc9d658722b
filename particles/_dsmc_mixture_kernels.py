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
(:func:`kinetic_fem.model.restitution_value`).  A heavier partner can throw a rod out of
the range (:math:`\\mu_{sr}(1+\\alpha_{sr}) > 1`): the range is then widened and the
stage's candidates left rescaled to the new majorant (:func:`_stage`).  The scaled free
cooling of :func:`particles.dsmc_mixture.simulate_mixture` has no splitting:
:func:`cooling_segment` runs its collisions on a clock that ticks once per candidate, with
a majorant widened by the collisions, and no pass over the rods but a vectorised range
every ``REFRESH N`` candidates; a block of candidates runs speculatively with the range
checked once at its end (:func:`_speculative`: a block that left the range is undone and
run again by the loop that checks each collision, :func:`_checked`), so the runs are those
of the checking loop bit for bit.

Random numbers (:mod:`particles.rng`, the 37-word state of
:func:`~particles.rng.mixture_state`): the kicks' normals from the wyrand word, the
ziggurat's rare slow paths from the xoshiro256** words, the candidates from the eight
lock-step xoshiro256++ lanes (:func:`particles.rng.xoshiro_lanes`) in blocks of at most
:data:`CANDIDATE_BLOCK` (:func:`pair_block`: the pair, the acceptance uniform and the
pair of species in vector passes, as the one-species free cooling of hard rods,
:func:`particles._dsmc_kernels.collide_lanes`), thinned by branch-free loops for constant
coefficients (the loops inline: as small functions returning at a widening they were
25 % slower); the same seed gives the same run with or without the JIT.
"""

from __future__ import annotations

import math

import numpy as np
from llvmlite import ir
from numba.core import cgutils, types
from numba.extending import intrinsic, overload

from kinetic_fem.model.restitution import CONSTANT, restitution_value

from ._dsmc_heated import kick
from ._dsmc_model import KERNEL_HARD_RODS, KERNEL_MAXWELL, kernel_majorant, kernel_value
from ._dsmc_segments import extent_fast
from ._jit import jit, vector_arrays
from .rng import LANE_WORD, LANES, WYRAND_WORD, bits_to_double, xoshiro_lanes

_LOW32 = np.uint64(0xFFFFFFFF)
_ONE_BITS = np.uint64(0x3FF0000000000000)  # the bits of 1.0
_MAGNITUDE = np.uint64(0x7FFFFFFFFFFFFFFF)
_SIGN = np.uint64(0x8000000000000000)
_S63 = np.uint64(63)

__all__ = ["mixture_segment", "cooling_segment", "cool_measure", "measure", "mean_squares",
           "recentre", "recentre_measure", "pair_block", "pair_shift", "pair_tables",
           "CANDIDATE_BLOCK"]


@jit
def extent_keys(v):  # pragma: no cover - compiled
    """``(min(v), max(v))`` of finite ``v`` (the values of
    :func:`particles._dsmc_segments.extent_fast`) from integer keys of the bits, monotone in
    the values (the sign bit flipped for positive numbers, every bit for negative ones):
    unsigned integer minima and maxima vectorise without fast-math flags, 0.05 ns per rod
    against 0.5 (``-0.0`` counts below ``0.0``; either gives the same comparisons and
    width)."""
    bits = v.view(np.uint64)
    low = ~np.uint64(0)
    high = np.uint64(0)
    for k in range(bits.shape[0]):
        x = bits[k]
        key = (x ^ ((x >> _S63) * _MAGNITUDE)) ^ _SIGN
        low = min(low, key)
        high = max(high, key)
    low ^= _SIGN
    high ^= _SIGN
    return (bits_to_double(low ^ ((low >> _S63) * _MAGNITUDE)),
            bits_to_double(high ^ ((high >> _S63) * _MAGNITUDE)))


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
def _flat(mu, lcode, p0, p1):  # pragma: no cover - compiled
    """The pair tables of :func:`_stage` for the ordered pairs ``q = k s + r``:
    ``(e, muf, mub, lf, q0, q1)``, ``e`` :math:`1 + \\alpha_{sr}` of a constant law,
    ``muf`` :math:`\\mu_{sr}`, ``mub`` :math:`\\mu_{rs}`, the law's code and
    parameters."""
    k = mu.shape[0]
    e = np.empty(k * k)
    muf = np.empty(k * k)
    mub = np.empty(k * k)
    lf = np.empty(k * k, np.int64)
    q0 = np.empty(k * k)
    q1 = np.empty(k * k)
    for a in range(k):
        for b in range(k):
            q = a * k + b
            muf[q] = mu[a, b]
            mub[q] = mu[b, a]
            e[q] = 1.0 + p0[a, b]
            lf[q] = lcode[a, b]
            q0[q] = p0[a, b]
            q1[q] = p1[a, b]
    return e, muf, mub, lf, q0, q1


@jit
def _widen_stage(lo, hi, wi, wj, b_max, x, c, drawn, kcode, kparam):  # pragma: no cover
    """The range widened to hold ``wi``, ``wj`` after ``c`` candidates of a stage of
    budget ``x``: ``(lo, hi, majorant, budget, candidates to use of the block)``, the
    candidates left rescaled by the ratio of the majorants (the stage's remaining time at
    the new candidate rate)."""
    lo = min(lo, min(wi, wj))
    hi = max(hi, max(wi, wj))
    b_new = kernel_majorant(kcode, kparam, hi - lo)
    x = c + (x - c) * (b_new / b_max)
    return lo, hi, b_new, x, min(drawn, int(x))


@jit(inline="always")
def _candidate(w, cu_c, b_max, v, mask, sh, sh2, hard_rods, kcode,
               kparam):  # pragma: no cover - compiled
    """Candidate word ``w`` of :func:`pair_block` decoded, and its acceptance: returns
    ``(i, j, p, v_i, v_j, g, |g|, accepted)`` (rods, ordered pair of species, their
    velocities, relative velocity; accepted with probability :math:`B(|g|)/B_{max}`
    from the uniform ``cu_c``).  Inlined into the compiled loops."""
    i = w & mask
    j = (w >> sh) & mask
    p = np.int64(w >> sh2)
    vi = v[i]
    vj = v[j]
    g = vi - vj
    ag = abs(g)
    threshold = cu_c * b_max
    if hard_rods:
        accepted = ag > threshold
    else:
        accepted = kcode == KERNEL_MAXWELL or kernel_value(kcode, kparam, ag) > threshold
    return i, j, p, vi, vj, g, ag, accepted


@jit
def _stage(v, bounds, st, raw, cij, cu, shift, tables, constant, kcode, kparam, lo, hi, x,
           ordered):  # pragma: no cover - compiled
    """One collision stage: ``floor(x)`` candidates (``x`` the stage's expected number, the
    carried fraction included); returns ``(collisions, x - candidates, lo, hi)``.

    The candidates come in blocks from the lanes of ``st`` (:func:`pair_block`), each
    accepted with probability :math:`B(|g|)/B(hi - lo)` and collided with its pair's law
    (``tables`` of :func:`_flat`).  Constant laws (``constant``) run a branch-free loop
    (the update times the acceptance, 0 or 1; the same numbers as the laws' loop with
    constant values), the laws a loop that evaluates each accepted pair's law at ``|g|``.
    A collision that throws a rod out of ``[lo, hi]`` (a heavier partner can) widens the
    range (:func:`_widen_stage`), so that the majorant always bounds the relative
    speeds."""
    e, muf, mub, lf, q0, q1 = tables
    n = v.shape[0]
    block = cij.shape[0]
    sh = np.uint64(shift)
    sh2 = np.uint64(2 * shift)
    mask = (np.uint64(1) << sh) - np.uint64(1)
    hard_rods = kcode == KERNEL_HARD_RODS
    b_max = kernel_majorant(kcode, kparam, hi - lo)
    collisions = 0
    while x >= 1.0:
        m = min(block, int(x))
        drawn = (m + LANES - 1) // LANES * LANES
        pair_block(st, n, bounds, raw, cij, cu, drawn, shift)
        c = 0
        if constant:
            while c < m:
                i, j, p, vi, vj, g, ag, acc = _candidate(
                    cij[c], cu[c], b_max, v, mask, sh, sh2, hard_rods, kcode, kparam)
                a = np.int64(acc)
                share = e[p] * (g * float(a))
                wi = vi - muf[p] * share
                wj = vj + mub[p] * share
                v[i] = wi
                v[j] = wj
                ordered[p] += a
                collisions += a
                c += 1
                if min(wi, wj) < lo or max(wi, wj) > hi:  # rare: the majorant widened
                    lo, hi, b_max, x, m = _widen_stage(lo, hi, wi, wj, b_max, x, c, drawn,
                                                       kcode, kparam)
        else:
            while c < m:
                i, j, p, vi, vj, g, ag, acc = _candidate(
                    cij[c], cu[c], b_max, v, mask, sh, sh2, hard_rods, kcode, kparam)
                c += 1
                if not acc:
                    continue
                share = (1.0 + restitution_value(lf[p], q0[p], q1[p], ag)) * (g * 1.0)
                wi = vi - muf[p] * share
                wj = vj + mub[p] * share
                v[i] = wi
                v[j] = wj
                ordered[p] += 1
                collisions += 1
                if min(wi, wj) < lo or max(wi, wj) > hi:
                    lo, hi, b_max, x, m = _widen_stage(lo, hi, wi, wj, b_max, x, c, drawn,
                                                       kcode, kparam)
        x -= c
    return collisions, x, lo, hi


@jit
def mixture_segment(v, bounds, mu, lcode, p0, p1, kcode, kparam, decay, amp,
                    half_decay, half_amp, heated, rate, dt, n_steps, g_limit, debt, s, ki,
                    wi, fi, counts, max_collisions):  # pragma: no cover - compiled
    """``n_steps`` steps of the module text.

    Parameters
    ----------
    v : ndarray of float64, shape (N,)
        Velocities, updated in place.
    bounds : ndarray of int64, shape (k + 1,)
        The rods sorted by species: those of species ``s`` are
        ``bounds[s] <= i < bounds[s + 1]``.
    mu : ndarray, shape (k, k)
        :math:`\\mu_{sr} = m_r/(m_s + m_r)`.
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
    s : ndarray of uint64, shape (37,)
        Mixture state (:func:`particles.rng.mixture_state`): the kicks from its wyrand
        word, the candidates from its lanes.
    ki, wi, fi : ndarray
        Ziggurat tables.
    counts : ndarray of int64, shape (k, k)
        Collisions per pair of species, incremented.
    max_collisions : int
        The segment ends after the step in which the collisions reach this number (the
        driver's next measurement).

    Returns
    -------
    (collisions, debt, steps_done, g_max, exceeded)
        ``exceeded``: the segment stopped before a stage whose ``g_max`` exceeds a law's
        range (``g_max`` then the offending value).
    """
    k = bounds.shape[0] - 1
    tables = _flat(mu, lcode, p0, p1)
    constant = True
    for code in lcode.ravel():
        constant = constant and code == CONSTANT
    ordered = np.zeros(k * k, np.int64)
    st = s[LANES_OFFSET:]
    block = CANDIDATE_BLOCK
    raw = np.empty(2 * block, np.uint64)
    cij = np.empty(block, np.uint64)
    cu = np.empty(block)
    shift = pair_shift(v.shape[0], k)
    collisions = 0
    if heated:
        lo, hi = _kick(v, bounds, half_decay, half_amp, s, ki, wi, fi)
    else:
        lo, hi = extent_fast(v)
    for step in range(n_steps):
        if hi - lo > g_limit:
            add_pair_counts(counts, ordered)
            return collisions, debt, step, hi - lo, True
        x = debt + dt * rate * kernel_majorant(kcode, kparam, hi - lo)
        a, debt, lo, hi = _stage(v, bounds, st, raw, cij, cu, shift, tables, constant, kcode,
                                 kparam, lo, hi, x, ordered)
        collisions += a
        last = step == n_steps - 1 or collisions >= max_collisions
        if heated:
            lo, hi = _kick(v, bounds, half_decay if last else decay,
                           half_amp if last else amp, s, ki, wi, fi)
        else:
            lo, hi = extent_fast(v)
        if last:
            add_pair_counts(counts, ordered)
            return collisions, debt, step + 1, hi - lo, False
    add_pair_counts(counts, ordered)
    return collisions, debt, n_steps, hi - lo, False


@jit
def measure(v, bounds, lows, widths, sums, hist):  # pragma: no cover - compiled
    """Add each rod's powers :math:`v^0 \\dots v^K` to ``sums[s]`` (shape (k, K + 1)) and
    its bin (``lows[s] + widths[s] * [b, b + 1)``, inside ``hist.shape[1]`` bins) to
    ``hist[s]``, ``s`` its species (rods ``bounds[s] <= i < bounds[s + 1]``).

    For ``K = 12`` (:data:`kinetic_fem.distribution.MAX_MOMENT`) the powers are summed in
    four lanes on vectors (:func:`_measure_12`, :func:`power_sums`: 1.3 ns per rod against
    2.8 for the sums in scalar registers, 4.1 with an accumulator array stored and reloaded
    for every rod; a product tree for the powers and two chains of sums, even and odd rods,
    were no faster); the same numbers with or without the JIT."""
    _measure(v, bounds, lows, widths, sums, hist, 0.0, 1.0)


@jit
def _measure(v, bounds, lows, widths, sums, hist, shift, factor):  # pragma: no cover
    """:func:`measure` of ``(v - shift) * factor``, stored back into ``v`` in the same
    pass (``shift = 0``, ``factor = 1``: ``v`` unchanged, bit for bit)."""
    top = sums.shape[1]
    if top == 13:
        for sp in range(bounds.shape[0] - 1):
            _measure_12(v[bounds[sp]:bounds[sp + 1]], lows[sp], widths[sp], sums[sp],
                        hist[sp], shift, factor)
        return
    for i in range(v.shape[0]):
        v[i] = (v[i] - shift) * factor
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


POWER_LANES = 4
"""Lanes of :func:`power_sums`: rod ``i`` is summed in lane ``i % POWER_LANES``."""


def power_sums(x, acc):
    """``acc[k, l] += x_i^k``, ``k = 1 .. 12``, for the rods ``i`` of lane ``l = i % 4``
    (each power the previous one times ``x_i``, each lane's sums rod by rod).  Compiled:
    one loop on ``<4 x double>`` vectors (:func:`_power_sums_ir`; scalar sums were 2.4 ns
    per rod, bound by the floating-point ports), the same numbers.

    Parameters
    ----------
    x : ndarray of float64, shape (n,)
    acc : ndarray of float64, shape (13, 4)
        Row 0 unused."""
    for i in range(x.shape[0]):
        _power_lane(x[i], acc, i % POWER_LANES)


@jit(inline="always")
def _power_lane(x, acc, lane):  # pragma: no cover - compiled
    """``acc[k, lane] += x^k``, ``k = 1 .. 12`` (:func:`power_sums`)."""
    p = x
    for k in range(1, 13):
        acc[k, lane] += p
        p = p * x


@intrinsic
def _power_sums_ir(typingctx, x, acc, n_vec):  # pragma: no cover - compiled
    """The loop of :func:`power_sums` over the first ``4 n_vec`` rods, the twelve sums on
    ``<4 x double>`` vectors in registers (LLVM IR; no fast-math flags, so the same
    products and sums as the plain loop)."""
    sig = types.void(x, acc, n_vec)

    def codegen(context, builder, signature, args):
        i64 = ir.IntType(64)
        vec = ir.VectorType(ir.DoubleType(), POWER_LANES)
        (x_data, acc_data), at = vector_arrays(context, builder, signature, args, vec, 2)

        rows = [at(acc_data, ir.Constant(i64, POWER_LANES * k)) for k in range(13)]
        slots = [cgutils.alloca_once(builder, vec) for _ in range(13)]
        for k in range(1, 13):
            builder.store(builder.load(rows[k], align=8), slots[k])
        with cgutils.for_range(builder, args[2]) as loop:
            off = builder.mul(loop.index, ir.Constant(i64, POWER_LANES))
            xv = builder.load(at(x_data, off), align=8)
            p = xv
            for k in range(1, 13):
                builder.store(builder.fadd(builder.load(slots[k]), p), slots[k])
                if k < 12:
                    p = builder.fmul(p, xv)
        for k in range(1, 13):
            builder.store(builder.load(slots[k]), rows[k], align=8)
        return context.get_dummy_value()

    return sig, codegen


@overload(power_sums, jit_options={"cache": True})  # type: ignore[typeddict-unknown-key]
def _power_sums_jit(x, acc):  # pragma: no cover - compiled
    def impl(x, acc):
        n_vec = x.shape[0] // POWER_LANES
        _power_sums_ir(x, acc, n_vec)
        for i in range(POWER_LANES * n_vec, x.shape[0]):
            _power_lane(x[i], acc, i % POWER_LANES)

    return impl


@jit
def _measure_12(v, low, width, sums, hist, shift, factor):  # pragma: no cover - compiled
    """:func:`_measure` of one species' rods ``v``: the shift, factor and histogram in one
    pass, then the powers 1-12 summed in four lanes (:func:`power_sums`, vectorised:
    2.8 -> 1.2 ns per rod), each sum ``(l_0 + l_1) + (l_2 + l_3)`` of its lanes."""
    bins = hist.shape[0]
    inv = 1.0 / width
    for i in range(v.shape[0]):
        x = (v[i] - shift) * factor
        v[i] = x
        b = math.floor((x - low) * inv)
        if 0 <= b < bins:
            hist[int(b)] += 1.0
    acc = np.zeros((13, POWER_LANES))
    power_sums(v, acc)
    sums[0] += float(v.shape[0])
    for k in range(1, 13):
        sums[k] += (acc[k, 0] + acc[k, 1]) + (acc[k, 2] + acc[k, 3])


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
def _frame(v, bounds, masses, centre, scaled):  # pragma: no cover - compiled
    """``(shift, factor, temperature)`` of :func:`recentre` (one pass of sums)."""
    if not (centre or scaled):
        return 0.0, 1.0, 1.0
    k = bounds.shape[0] - 1
    n = v.shape[0]
    momentum = 0.0
    energy = 0.0
    total = 0.0
    for sp in range(k):
        a1 = 0.0
        a2 = 0.0
        for i in range(bounds[sp], bounds[sp + 1]):
            x = v[i]
            a1 += x
            a2 += x * x
        momentum += masses[sp] * a1
        energy += masses[sp] * a2
        total += masses[sp] * (bounds[sp + 1] - bounds[sp])
    shift = momentum / total if centre else 0.0
    temperature = (energy - shift * momentum) / n
    if not scaled:
        return shift, 1.0, 1.0
    return shift, 1.0 / math.sqrt(temperature), temperature


@jit
def recentre(v, bounds, masses, centre, scaled):  # pragma: no cover - compiled
    """Remove the centre-of-mass velocity ``u = P/M`` (``centre``) and rescale to
    :math:`T = \\sum_i m_i v_i^2 / N = 1` (``scaled``), in place, in two passes (the sums,
    then the shift and the factor together); returns the temperature before the rescaling
    (:math:`\\sum m_i (v_i - u)^2/N = (E - P u)/N`; 1.0 unless ``scaled``)."""
    shift, factor, temperature = _frame(v, bounds, masses, centre, scaled)
    if centre or scaled:
        for i in range(v.shape[0]):
            v[i] = (v[i] - shift) * factor
    return temperature


@jit
def recentre_measure(v, bounds, masses, centre, scaled, lows, widths, sums,
                     hist):  # pragma: no cover - compiled
    """:func:`recentre`, then :func:`measure`, the second pass of the one the first of the
    other (the same numbers as the two in turn)."""
    shift, factor, temperature = _frame(v, bounds, masses, centre, scaled)
    _measure(v, bounds, lows, widths, sums, hist, shift, factor)
    return temperature


CANDIDATE_BLOCK = 512
"""Candidates per block of :func:`cooling_segment` (drawn from the lanes in one vector
pass; a multiple of :data:`particles.rng.LANES`)."""

REFRESH = 2
"""The range of :func:`cooling_segment` is measured again every ``REFRESH N`` candidates
(about 0.3 collisions per rod; a pass of 0.5 ns per rod against a range that shrinks as
the gas cools: 1 and 4 were 3 % slower at N = 5000-20000; with the pass of
:func:`extent_keys`, 0.05 ns per rod, 0.5, 1 and 4 are no faster either: a tighter range
gives fewer candidates but more blocks that leave it)."""

LANES_OFFSET = WYRAND_WORD + 1 - LANE_WORD
"""The lanes of a mixture state (:func:`particles.rng.mixture_state`: the five heated
words, then the lane words) are those of the cooling state ``s[LANES_OFFSET:]``."""


@jit
def pair_shift(n, k):  # pragma: no cover - compiled
    """The bits ``S`` of a rod's index in the words of :func:`pair_block` (``2^S >= N``),
    checked to leave room for the pair of species (``k^2 <= 2^(64 - 2S)``)."""
    shift = 1
    while (1 << shift) < n:
        shift += 1
    if 2 * shift > 62 or (k * k - 1) >> (64 - 2 * shift) > 0:
        raise ValueError("too many rods and species for the candidate words of the mixture "
                         "DSMC (2 log2(N) + log2(k^2) > 64)")
    return shift


@jit
def pair_block(st, n, bounds, raw, cij, cu, m, shift):  # pragma: no cover - compiled
    """``m`` (a multiple of ``LANES``) candidates from the lanes of ``st`` (a cooling
    state, :func:`particles.rng.cooling_state`), in vector passes: the draws of
    :func:`particles._dsmc_kernels.candidate_block` (two per candidate: ``i`` and
    ``j != i`` from the high and low 32 bits of the first, the acceptance uniform ``cu`` in
    ``[0, 1)`` from the top 52 bits of the second), each candidate one word ``cij``:
    ``i | j << S | p << 2S`` (``S`` of :func:`pair_shift`), ``p = k s_i + s_j`` the pair of
    species (``k`` species, the rods sorted by species, ``bounds`` as
    :func:`mixture_segment`: a count of the bounds each rod reaches).  One word instead of
    three arrays: 6 % fewer nanoseconds per candidate in the thinning loops."""
    xoshiro_lanes(st, raw, (2 * m) // LANES)
    nn = np.uint64(n) & _LOW32
    n1 = (nn - np.uint64(1)) & _LOW32
    sh = np.uint64(shift)
    for c in range(m):
        r = raw[c]
        i = ((r >> np.uint64(32)) * nn) >> np.uint64(32)
        j = ((r & _LOW32) * n1) >> np.uint64(32)
        cij[c] = i | ((j + np.uint64(j >= i)) << sh)
        cu[c] = bits_to_double((raw[m + c] >> np.uint64(12)) | _ONE_BITS) - 1.0
    k = bounds.shape[0] - 1
    mask = (np.uint64(1) << sh) - np.uint64(1)
    kk = np.uint64(k)
    sh2 = np.uint64(2 * shift)
    for sp in range(1, k):
        b = np.uint64(bounds[sp])
        for c in range(m):
            w = cij[c]
            up = kk * np.uint64((w & mask) >= b) + np.uint64(((w >> sh) & mask) >= b)
            cij[c] = w + (up << sh2)


@jit
def pair_tables(mu, reduced, p0):  # pragma: no cover - compiled
    """The coefficients of each ordered pair ``p = k s + r`` of constant restitution
    ``p0``: ``(ci, cj, lw)`` with :math:`v_s' = v_s - c_i g`, :math:`v_r' = v_r + c_j g`
    (:math:`c_i = \\mu_{sr}(1+\\alpha_{sr})`, :math:`c_j = \\mu_{rs}(1+\\alpha_{sr})`)
    and ``lw`` :math:`\\times g^2` the energy lost (``reduced (1 - alpha^2)``)."""
    k = mu.shape[0]
    c1 = np.empty(k * k)
    c2 = np.empty(k * k)
    lw = np.empty(k * k)
    for a in range(k):
        for b in range(k):
            q = a * k + b
            c1[q] = mu[a, b] * (1.0 + p0[a, b])
            c2[q] = mu[b, a] * (1.0 + p0[a, b])
            lw[q] = reduced[a, b] * (1.0 - p0[a, b] * p0[a, b])
    return c1, c2, lw


@jit
def add_pair_counts(counts, ordered):  # pragma: no cover - compiled
    """``counts[s, r]`` (symmetric, each collision once) += the collisions of the
    ordered pairs ``ordered[k s + r]`` and, for ``r != s``, ``ordered[k r + s]``."""
    k = counts.shape[0]
    for a in range(k):
        for b in range(k):
            counts[a, b] += ordered[a * k + b] + (ordered[b * k + a] if a != b else 0)


@jit(inline="always")
def _update(v, c1, c2, ordered, i, j, p, vi, vj, g, acc):  # pragma: no cover - compiled
    """The update of a candidate of :func:`_candidate` in :func:`cooling_segment`,
    branch-free: :math:`v_i - c_1 g`, :math:`v_j + c_2 g` times the acceptance (0 or 1;
    a branch was mispredicted for a fifth of the candidates) stored and the pair counted;
    returns ``(accepted, v_i', v_j')``.  Inlined into the loops."""
    a = np.int64(acc)
    d = g * float(a)
    wi = vi - c1[p] * d
    wj = vj + c2[p] * d
    v[i] = wi
    v[j] = wj
    ordered[p] += a
    return a, wi, wj


@jit(inline="always")
def _speculative(v, cij, cu, b_max, c1, c2, ordered, undo, mask, sh, sh2, hard_rods, kcode,
                 kparam, lo, hi):  # pragma: no cover - compiled
    """The block of :func:`cooling_segment` thinned without testing the range per
    candidate: each candidate's velocities before its update go to ``undo``, the extent
    of the updated ones is kept; returns ``(collisions, inside)``, ``inside`` whether
    every updated velocity stayed in ``[lo, hi]`` (else the block must be undone)."""
    rlo = lo
    rhi = hi
    collisions = 0
    for c in range(cij.shape[0]):
        i, j, p, vi, vj, g, ag, acc = _candidate(cij[c], cu[c], b_max, v, mask, sh, sh2,
                                                 hard_rods, kcode, kparam)
        a, wi, wj = _update(v, c1, c2, ordered, i, j, p, vi, vj, g, acc)
        undo[2 * c] = vi
        undo[2 * c + 1] = vj
        collisions += a
        rlo = wi if wi < rlo else rlo
        rhi = wi if wi > rhi else rhi
        rlo = wj if wj < rlo else rlo
        rhi = wj if wj > rhi else rhi
    return collisions, rlo >= lo and rhi <= hi


@jit(inline="always")
def _checked(v, cij, cu, b_max, c1, c2, ordered, mask, sh, sh2, hard_rods, kcode, kparam,
             lo, hi, collisions, max_collisions, time, ticks, rate):  # pragma: no cover
    """The block of :func:`cooling_segment` thinned in order, each update tested against
    the range (a velocity out of it widens the range and the majorant, and the clock so
    far is counted at the old majorant), until the block ends or the collisions reach
    ``max_collisions``: returns ``(candidates, collisions, lo, hi, b_max, time,
    ticks)``."""
    c = 0
    while c < cij.shape[0]:
        if collisions >= max_collisions:
            break
        i, j, p, vi, vj, g, ag, acc = _candidate(cij[c], cu[c], b_max, v, mask, sh, sh2,
                                                 hard_rods, kcode, kparam)
        a, wi, wj = _update(v, c1, c2, ordered, i, j, p, vi, vj, g, acc)
        collisions += a
        c += 1
        if min(wi, wj) < lo or max(wi, wj) > hi:  # rare: the majorant widened
            time += (ticks + c) / (rate * b_max)
            ticks = -c
            lo = min(lo, min(wi, wj))
            hi = max(hi, max(wi, wj))
            b_max = kernel_majorant(kcode, kparam, hi - lo)
    return c, collisions, lo, hi, b_max, time, ticks


@jit
def cooling_segment(v, bounds, mu, reduced, p0, kcode, kparam, rate, s, counts,
                    max_collisions):  # pragma: no cover - compiled
    """Free cooling in scaled variables until ``max_collisions`` collisions, one clock tick
    per candidate (no pass over the rods).

    The majorant is the range ``[lo, hi]``, measured every ``REFRESH N`` candidates (at
    the start of a block) and widened by every post-collision velocity outside it in between
    (a heavier partner can throw a rod beyond the range), so it always bounds the
    relative speeds.  Each candidate advances the clock by
    :math:`1/(\\mathrm{rate}\\,B(hi - lo))` (``rate`` :math:`= nN/2`; the expected
    spacing, as the one-species free cooling of :mod:`particles._dsmc_kernels`) and is
    accepted with probability :math:`B(|g|)/B(hi - lo)`.  The candidates come in blocks
    of :data:`CANDIDATE_BLOCK` from the lanes of ``s`` (:func:`pair_block`: the pair, the
    acceptance uniform and the pair of species, in vector passes), thinned by branch-free
    loops (:func:`_update`; a branch on the acceptance was mispredicted for a fifth of the
    candidates); the draws of a block past the last collision are dropped.  A block that
    cannot reach ``max_collisions`` runs speculatively (:func:`_speculative`, the range
    tested once after it: 2.6-2.7 against 2.9-3.0 ns per candidate at N = 20000 with the
    test per collision, which cost 15 %); in the rare block whose collisions left the
    range (1 % of the blocks at N = 20000, masses 1:2, alpha 0.9; 4 % at N = 5000, 21 % at
    N = 1000) the velocities and pair counts are restored and the block is run again by
    :func:`_checked`, which widens the range where a collision leaves it, so that every
    candidate is tested against a majorant of all relative speeds and the run is that of
    :func:`_checked` alone, bit for bit.
    The energy lost is not summed here: the driver measures the temperature at the end
    (:func:`recentre`).

    Parameters
    ----------
    v : ndarray of float64, shape (N,)
        Velocities, updated in place (not rescaled).
    bounds, mu, reduced, p0 : ndarray
        As :func:`mixture_segment`; ``p0`` the constant restitution coefficients.
    kcode, kparam : int, float
        A power-law kernel (:func:`particles._dsmc_model.kernel_model`).
    rate : float
        :math:`nN/2`.
    s : ndarray of uint64, shape (37,)
        Mixture state (:func:`particles.rng.mixture_state`); its lanes advance.
    counts : ndarray of int64, shape (k, k)
        Collisions per pair of species, incremented.
    max_collisions : int

    Returns
    -------
    (collisions, time, candidates)
    """
    n = v.shape[0]
    k = bounds.shape[0] - 1
    st = s[LANES_OFFSET:]
    c1, c2, _ = pair_tables(mu, reduced, p0)
    ordered = np.zeros(k * k, np.int64)
    block = CANDIDATE_BLOCK
    raw = np.empty(2 * block, np.uint64)
    cij = np.empty(block, np.uint64)
    cu = np.empty(block)
    undo = np.empty(2 * block)
    saved = np.empty(k * k, np.int64)
    shift = pair_shift(n, k)
    sh = np.uint64(shift)
    sh2 = np.uint64(2 * shift)
    mask = (np.uint64(1) << sh) - np.uint64(1)
    hard_rods = kcode == KERNEL_HARD_RODS
    lo, hi = extent_keys(v)
    b_max = kernel_majorant(kcode, kparam, hi - lo)
    time = 0.0
    ticks = 0  # candidates since the majorant last changed
    since = 0  # candidates since the range was measured
    collisions = 0
    candidates = 0
    while collisions < max_collisions:
        if since >= REFRESH * n:  # the exact range again (the widened one only grows)
            time += ticks / (rate * b_max)
            ticks = 0
            since = 0
            lo, hi = extent_keys(v)
            b_max = kernel_majorant(kcode, kparam, hi - lo)
        pair_block(st, n, bounds, raw, cij, cu, block, shift)
        if max_collisions - collisions >= block:  # the block cannot reach the target
            # speculative: the range checked once after the block (rare: the block is
            # undone and run again by the checking loop below)
            for q in range(k * k):
                saved[q] = ordered[q]
            if hard_rods:
                new, ok = _speculative(v, cij, cu, b_max, c1, c2, ordered, undo, mask, sh,
                                       sh2, True, kcode, kparam, lo, hi)
            else:
                new, ok = _speculative(v, cij, cu, b_max, c1, c2, ordered, undo, mask, sh,
                                       sh2, False, kcode, kparam, lo, hi)
            if ok:
                collisions += new
                ticks += block
                since += block
                candidates += block
                continue
            for c in range(block - 1, -1, -1):
                w = cij[c]
                v[(w >> sh) & mask] = undo[2 * c + 1]
                v[w & mask] = undo[2 * c]
            for q in range(k * k):
                ordered[q] = saved[q]
        c, collisions, lo, hi, b_max, time, ticks = _checked(
            v, cij, cu, b_max, c1, c2, ordered, mask, sh, sh2, hard_rods, kcode, kparam,
            lo, hi, collisions, max_collisions, time, ticks, rate)
        ticks += c
        since += c
        candidates += c
    add_pair_counts(counts, ordered)
    time += ticks / (rate * b_max)
    return collisions, time, candidates


@jit
def cool_measure(v, bounds, masses, mu, reduced, p0, kcode, kparam, rate, s, counts,
                 max_collisions, fused, lows, widths, sums, hist):  # pragma: no cover
    """:func:`cooling_segment`, then :func:`recentre_measure` (``fused``) or
    :func:`recentre` (centred and rescaled to :math:`T = 1`), in one call (one dispatch
    and no Python between them: 3-4 microseconds per measurement).

    Returns
    -------
    (collisions, time, temperature)
        The temperature before the rescaling.
    """
    collisions, time, _ = cooling_segment(v, bounds, mu, reduced, p0, kcode, kparam, rate, s,
                                          counts, max_collisions)
    if fused:
        end = recentre_measure(v, bounds, masses, True, True, lows, widths, sums, hist)
    else:
        end = recentre(v, bounds, masses, True, True)
    return collisions, time, end
