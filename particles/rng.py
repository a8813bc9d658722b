"""Random numbers inside numba kernels: xoshiro256** and the normal ziggurat.

The particle kernels (DSMC and MD) draw their random numbers from an explicit-state
xoshiro256** generator (Blackman and Vigna 2018): the state is a ``uint64`` array of
length 4, seeded from a ``numpy.random.SeedSequence`` by the driver and saved in
checkpoints, so a run resumes bit-identically.  Hot loops copy the four words into
local variables (registers) on entry, step them with :func:`xoshiro` and write them
back on exit: kept in the array, every draw waited for a store and a reload of the
state.  A draw then costs about 1 ns (consecutive draws form a chain of dependent
xor/rotate steps), against 3-4 ns for a numpy ``random_raw`` block and 13 ns for a
numpy normal on the development machine.

The heated DSMC draws its thermostat kicks and its hard-rod candidates from a second,
cheaper stream: wyrand (Wang Yi's generator of wyhash; a 64-bit Weyl counter
``w += 0xa0761d6478bd642f`` mixed by one 64 x 64 -> 128-bit multiply,
``hi ^ lo`` of ``w (w ^ 0xe7037ed1a0b428db)``; period ``2^64``).  Its state is one word,
word :data:`WYRAND_WORD` of a 5-word state array (:func:`heated_state`) whose first four
words stay the xoshiro256** state (the ziggurat's rare slow paths).  A draw is five
instructions against about twelve for xoshiro256**, and the counter is the only
dependency between consecutive draws; a white-noise kick costs 1.6 ns per velocity
against 1.8 ns with xoshiro256** (interleaved, one core of the development machine).

Integers below ``N``: ``floor(r N / 2^64)``, the high word of one 64 x 64 -> 128-bit
multiply (:func:`mul128`; non-uniformity at most ``N / 2^64 < 1e-12``); the low word
is, given the high one, uniform on a lattice of spacing ``N / 2^64`` and can serve as
a second uniform.

Free-cooling DSMC (hard rods, constant ``alpha``) draws its candidates from
:data:`LANES` = 8 independent xoshiro256++ streams advanced in lock-step
(:func:`xoshiro_lanes`): the state is ``4 x 8`` words, word ``w`` of lane ``l`` at
``4 + 8 w + l`` of the kernel state (:func:`cooling_state`; words 0-3 stay a
xoshiro256** state for the other models), and step ``t`` of the lanes fills
``out[8 t + l]``.  The layout is fixed: it does not follow the machine's SIMD width, so a
seed gives the same numbers everywhere; the compiled kernel holds the eight lanes in
vector registers (two AVX2 or one AVX-512 register per state word), 0.2-0.3 ns per draw.

Gaussians: the 256-layer ziggurat of Marsaglia and Tsang (2000), the same construction
as numpy's, with tables built by :func:`ziggurat_tables`.  Kernels inline the fast
path (one 64-bit number, a table look-up and a comparison: 99 % of the draws) and
call :func:`normal_slow` for the rest with the state written back to the array
(keeping the rare paths in a separate function matters: in one ``next_normal``
function numba's code for the fast path was 20-50x slower).

References
----------
D. Blackman and S. Vigna, *Scrambled linear pseudorandom number generators*,
ACM Trans. Math. Softw. 47, 36 (2021).  G. Marsaglia and W. W. Tsang, *The ziggurat
method for generating random variables*, J. Stat. Softw. 5 (2000).
"""

from __future__ import annotations

import math

import numpy as np
from llvmlite import ir
from numba.core import cgutils, types
from numba.extending import intrinsic, overload

from ._jit import jit, vector_arrays

__all__ = ["LANES", "LANE_WORD", "cooling_state", "xoshiro_lanes", "bits_to_double",
           "ZIGGURAT_R", "ziggurat_tables", "xoshiro", "next_u64", "next_double", "mul128",
           "mulhi", "mul128_pair", "zig_draw", "normal_slow", "fill_normal", "WYRAND_WORD",
           "WYRAND_INC", "WYRAND_XOR", "wyrand", "wyrand_next", "heated_state",
           "mixture_state"]

ZIGGURAT_R = 3.6541528853610088
"""Start of the tail of the 256-layer normal ziggurat."""

_V = 0.00492867323399  # area of each layer
_M1 = 2.0**52


def ziggurat_tables() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Tables ``(ki, wi, fi)`` of the 256-layer normal ziggurat.

    Layer ``i`` spans ``[0, x_i]``; ``wi = x_i / 2^52`` turns 52 random bits into
    ``x``; ``ki`` is the acceptance threshold ``2^52 x_{i-1}/x_i`` of the part of
    the layer that lies under the density; ``fi = exp(-x_i^2/2)``.  ``wi`` has 512
    entries, ``wi[256 + i] = -wi[i]``: the layer and the sign bit (9 random bits)
    index a signed width, which saves the sign logic in the kernels' inner loop.

    Returns
    -------
    ki : ndarray of uint64, shape (256,)
    wi : ndarray of float64, shape (512,)
    fi : ndarray of float64, shape (256,)

    Examples
    --------
    >>> ki, wi, fi = ziggurat_tables()
    >>> wi.shape, float(fi[0])
    ((512,), 1.0)
    """
    ki = np.zeros(256, dtype=np.uint64)
    wi = np.zeros(512)
    fi = np.zeros(256)
    dn = tn = ZIGGURAT_R
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
def xoshiro(s0, s1, s2, s3):  # pragma: no cover - compiled
    """xoshiro256** on a state held in four local variables.

    Parameters
    ----------
    s0, s1, s2, s3 : uint64
        The state words.

    Returns
    -------
    (result, s0, s1, s2, s3) : tuple of uint64
        One 64-bit output and the advanced state.
    """
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
    """One 64-bit output of xoshiro256**; advances the state ``s`` (uint64, shape (4,))."""
    result, s[0], s[1], s[2], s[3] = xoshiro(s[0], s[1], s[2], s[3])
    return result


@jit
def next_double(s):  # pragma: no cover - compiled
    """Uniform double on [0, 1) with 53 random bits; advances ``s``."""
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


def mul128(r, n):
    """``(floor(r n / 2^64), r n mod 2^64)`` for uint64 ``r``, ``n``.

    One machine multiply in compiled kernels; Python integers here (no-JIT mode).

    Parameters
    ----------
    r, n : numpy.uint64
        The factors.

    Returns
    -------
    tuple of numpy.uint64
        High and low 64-bit words of the product.
    """
    p = int(r) * int(n)
    return np.uint64(p >> 64), np.uint64(p & 0xFFFFFFFFFFFFFFFF)


# (numba's TypedDict of jit options omits "cache", which overload accepts)
@overload(mul128, jit_options={"cache": True})  # type: ignore[typeddict-unknown-key]
def _mul128_jit(r, n):  # pragma: no cover - compiled
    def impl(r, n):
        return _llvm_mul128(r, n)

    return impl


@jit
def mulhi(r, n):  # pragma: no cover - compiled
    """``floor(r * n / 2^64)`` for uint64 ``r``, ``n``: an integer uniform below ``n``."""
    return mul128(r, n)[0]


@jit
def mul128_pair(r, n):  # pragma: no cover - compiled
    """:func:`mul128` as a kernel (for tests)."""
    return mul128(r, n)


LANES = 8
"""Number of lock-step xoshiro256++ streams of the cooling candidates (fixed)."""
LANE_WORD = 4
"""Index of the first lane word in a cooling kernel state (:func:`cooling_state`)."""


def cooling_state(seed_seq: np.random.SeedSequence) -> np.ndarray:
    """A ``4 + 4 LANES``-word kernel state: xoshiro256** (words 0-3) and the lanes.

    Parameters
    ----------
    seed_seq : numpy.random.SeedSequence
        Source of the state.

    Returns
    -------
    ndarray of uint64, shape (36,)

    Examples
    --------
    >>> cooling_state(np.random.SeedSequence(1)).shape
    (36,)
    """
    state = seed_seq.generate_state(LANE_WORD + 4 * LANES, dtype=np.uint64)
    lanes = state[LANE_WORD:].reshape(4, LANES)
    lanes[0, ~lanes.any(axis=0)] = 1  # an all-zero xoshiro state never leaves zero
    return state


def _lanes_python(st, out, n_steps):
    """:func:`xoshiro_lanes` in numpy (no-JIT mode)."""
    s = st[LANE_WORD:LANE_WORD + 4 * LANES].reshape(4, LANES)
    with np.errstate(over="ignore"):
        for t in range(n_steps):
            x = s[0] + s[3]
            out[t * LANES:(t + 1) * LANES] = ((x << np.uint64(23)) | (x >> np.uint64(41))) + s[0]
            tt = s[1] << np.uint64(17)
            s[2] ^= s[0]
            s[3] ^= s[1]
            s[1] ^= s[2]
            s[0] ^= s[3]
            s[2] ^= tt
            s[3] = (s[3] << np.uint64(45)) | (s[3] >> np.uint64(19))


def xoshiro_lanes(st, out, n_steps):
    """``n_steps`` steps of the :data:`LANES` xoshiro256++ streams of ``st``.

    Output ``out[8 t + l]`` is lane ``l`` at step ``t``; the lane words of ``st``
    (uint64, at least ``LANE_WORD + 32`` words; :func:`cooling_state`) advance.  Compiled
    kernels run one vector loop with the state in registers (:func:`_lanes_ir`).

    Parameters
    ----------
    st : ndarray of uint64
        Kernel state.
    out : ndarray of uint64, shape (>= 8 n_steps,)
        Receives the outputs.
    n_steps : int
        Steps of every lane.
    """
    _lanes_python(st, out, n_steps)


@intrinsic
def _lanes_ir(typingctx, st, out, n_steps):  # pragma: no cover - compiled
    """The loop of :func:`xoshiro_lanes` on ``<8 x i64>`` vectors (LLVM IR)."""
    sig = types.void(st, out, n_steps)

    def codegen(context, builder, signature, args):
        i64 = ir.IntType(64)
        vec = ir.VectorType(i64, LANES)
        (st_data, out_data), at = vector_arrays(context, builder, signature, args, vec, 2)

        def splat(c):
            return ir.Constant(vec, [ir.Constant(i64, c)] * LANES)

        def rotl(x, r):
            return builder.or_(builder.shl(x, splat(r)), builder.lshr(x, splat(64 - r)))

        words = [at(st_data, ir.Constant(i64, LANE_WORD + w * LANES)) for w in range(4)]
        slots = [cgutils.alloca_once(builder, vec) for _ in range(4)]
        for word, slot in zip(words, slots, strict=True):
            builder.store(builder.load(word, align=8), slot)
        with cgutils.for_range(builder, args[2]) as loop:
            s0, s1, s2, s3 = (builder.load(slot) for slot in slots)
            res = builder.add(rotl(builder.add(s0, s3), 23), s0)
            t = builder.shl(s1, splat(17))
            s2 = builder.xor(s2, s0)
            s3 = builder.xor(s3, s1)
            s1 = builder.xor(s1, s2)
            s0 = builder.xor(s0, s3)
            s2 = builder.xor(s2, t)
            s3 = rotl(s3, 45)
            for slot, x in zip(slots, (s0, s1, s2, s3), strict=True):
                builder.store(x, slot)
            off = builder.mul(loop.index, ir.Constant(i64, LANES))
            builder.store(res, at(out_data, off), align=8)
        for word, slot in zip(words, slots, strict=True):
            builder.store(builder.load(slot), word, align=8)
        return context.get_dummy_value()

    return sig, codegen


# (numba's TypedDict of jit options omits "cache", which overload accepts)
@overload(xoshiro_lanes, jit_options={"cache": True})  # type: ignore[typeddict-unknown-key]
def _xoshiro_lanes_jit(st, out, n_steps):  # pragma: no cover - compiled
    def impl(st, out, n_steps):
        _lanes_ir(st, out, n_steps)

    return impl


def bits_to_double(x):
    """The float64 whose bits are the uint64 ``x`` (a register move when compiled).

    Parameters
    ----------
    x : numpy.uint64
        The bits.

    Returns
    -------
    float
    """
    return float(np.array(x, dtype=np.uint64).view(np.float64))


@intrinsic
def _bits_to_double_ir(typingctx, x):  # pragma: no cover - compiled
    if x != types.uint64:
        return None

    def codegen(context, builder, signature, args):
        return builder.bitcast(args[0], ir.DoubleType())

    return types.float64(x), codegen


@overload(bits_to_double, jit_options={"cache": True})  # type: ignore[typeddict-unknown-key]
def _bits_to_double_jit(x):  # pragma: no cover - compiled
    def impl(x):
        return _bits_to_double_ir(x)

    return impl


WYRAND_WORD = 4
"""Index of the wyrand counter in a heated kernel state (:func:`heated_state`)."""
WYRAND_INC = np.uint64(0xA0761D6478BD642F)
"""wyrand's Weyl increment."""
WYRAND_XOR = np.uint64(0xE7037ED1A0B428DB)
"""wyrand's mixing constant."""


def heated_state(seed_seq: np.random.SeedSequence) -> np.ndarray:
    """A 5-word kernel state: xoshiro256** (words 0-3) and the wyrand counter (word 4).

    Parameters
    ----------
    seed_seq : numpy.random.SeedSequence
        Source of the state.

    Returns
    -------
    ndarray of uint64, shape (5,)

    Examples
    --------
    >>> heated_state(np.random.SeedSequence(1)).shape
    (5,)
    """
    return seed_seq.generate_state(5, dtype=np.uint64)


def mixture_state(seed_seq: np.random.SeedSequence) -> np.ndarray:
    """A ``5 + 4 LANES``-word kernel state of the mixture DSMC: the words of
    :func:`heated_state` (the same five for the same seed) and then the lane words, so that
    ``state[WYRAND_WORD + 1 - LANE_WORD:]`` is a :func:`cooling_state` for
    :func:`xoshiro_lanes`.

    Parameters
    ----------
    seed_seq : numpy.random.SeedSequence
        Source of the state.

    Returns
    -------
    ndarray of uint64, shape (37,)

    Examples
    --------
    >>> mixture_state(np.random.SeedSequence(1)).shape
    (37,)
    """
    state = seed_seq.generate_state(WYRAND_WORD + 1 + 4 * LANES, dtype=np.uint64)
    lanes = state[WYRAND_WORD + 1:].reshape(4, LANES)
    lanes[0, ~lanes.any(axis=0)] = 1  # an all-zero xoshiro state never leaves zero
    return state


@jit
def wyrand(w):  # pragma: no cover - compiled
    """One wyrand output from the counter ``w``: ``(result, new w)`` (uint64)."""
    w += WYRAND_INC
    hi, lo = mul128(w, w ^ WYRAND_XOR)
    return hi ^ lo, w


@jit
def wyrand_next(s):  # pragma: no cover - compiled
    """One wyrand output; advances word :data:`WYRAND_WORD` of the state ``s``."""
    r, s[WYRAND_WORD] = wyrand(s[WYRAND_WORD])
    return r


@jit
def zig_draw(s, wi):  # pragma: no cover - compiled
    """One ziggurat proposal from one 64-bit number: ``(layer, 52 bits, signed x)``."""
    r = next_u64(s)
    layer_sign = r & np.uint64(0x1FF)  # bits 0-7: layer, bit 8: sign
    rabs = (r >> np.uint64(9)) & np.uint64(0x000FFFFFFFFFFFFF)
    x = float(np.int64(rabs)) * wi[layer_sign]  # rabs < 2^52: the conversion is exact
    return int(layer_sign & np.uint64(0xFF)), rabs, x


@jit
def normal_slow(s, idx, x, ki, wi, fi):  # pragma: no cover - compiled
    """Finish a normal draw that missed the fast region of layer ``idx`` at ``x``.

    Layer 0: Marsaglia's exact tail beyond ``R`` (retried until accepted), signed
    like ``x``.  Other layers: the wedge test; on rejection a new proposal is drawn.
    The state ``s`` (uint64, shape (4,)) is advanced.
    """
    while True:
        if idx == 0:
            while True:
                xx = -math.log1p(-next_double(s)) * (1.0 / ZIGGURAT_R)
                yy = -math.log1p(-next_double(s))
                if yy + yy > xx * xx:
                    return -(ZIGGURAT_R + xx) if x < 0.0 else ZIGGURAT_R + xx
        if (fi[idx - 1] - fi[idx]) * next_double(s) + fi[idx] < math.exp(-0.5 * x * x):
            return x
        idx, rabs, x = zig_draw(s, wi)
        if rabs < ki[idx]:
            return x


@jit
def fill_normal(out, s, ki, wi, fi):  # pragma: no cover - compiled
    """Fill ``out`` (float64, any length) with standard normals drawn from state ``s``.

    ``s`` of 4 words: the ziggurat on xoshiro256**.  ``s`` of 5 words
    (:func:`heated_state`): the fast path on the wyrand word, the slow paths on the
    xoshiro256** words; then the same numbers, in the same order, as a white-noise kick
    of amplitude 1 adds (:func:`particles._dsmc_heated.kick`).
    """
    if s.shape[0] > WYRAND_WORD:
        w = s[WYRAND_WORD]
        for k in range(out.shape[0]):
            r, w = wyrand(w)
            layer_sign = r & np.uint64(0x1FF)
            idx = int(layer_sign & np.uint64(0xFF))
            rabs = (r >> np.uint64(9)) & np.uint64(0x000FFFFFFFFFFFFF)
            x = float(np.int64(rabs)) * wi[layer_sign]
            if rabs >= ki[idx]:
                x = normal_slow(s, idx, x, ki, wi, fi)
            out[k] = x
        s[WYRAND_WORD] = w
        return
    s0, s1, s2, s3 = s[0], s[1], s[2], s[3]
    for k in range(out.shape[0]):
        r, s0, s1, s2, s3 = xoshiro(s0, s1, s2, s3)
        layer_sign = r & np.uint64(0x1FF)
        idx = int(layer_sign & np.uint64(0xFF))
        rabs = (r >> np.uint64(9)) & np.uint64(0x000FFFFFFFFFFFFF)
        x = float(np.int64(rabs)) * wi[layer_sign]
        if rabs >= ki[idx]:
            s[0], s[1], s[2], s[3] = s0, s1, s2, s3
            x = normal_slow(s, idx, x, ki, wi, fi)
            s0, s1, s2, s3 = s[0], s[1], s[2], s[3]
        out[k] = x
    s[0], s[1], s[2], s[3] = s0, s1, s2, s3
