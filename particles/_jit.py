"""All numba compile options of the ``particles`` package, in one place.

Kernels are compiled with ``cache=True`` (kept consistent across modules by
:func:`kinetic_fem.jit_cache.ensure_fresh_cache`) and hold no global state; random numbers are
drawn inside the kernels from an explicit generator state passed in as an array
(:mod:`particles.rng`, seeded from a ``numpy.random.SeedSequence`` and saved in
checkpoints), so that runs are reproducible from explicit seeds and checkpoints resume
bit-identically.
Setting ``NUMBA_DISABLE_JIT=1`` runs the kernels as plain Python (slow, for tests).
"""

from __future__ import annotations

from pathlib import Path

import numba
from llvmlite import ir
from numba.core import cgutils, types
from numba.extending import intrinsic, overload

from kinetic_fem.jit_cache import (
    announce_compilation,
    configure_cache_dir,
    ensure_fresh_cache,
)

try:  # the name of llvm.prefetch's pointer overload follows the pointer kind
    from llvmlite import ir_layer_typed_pointers_enabled as _TYPED_POINTERS
except ImportError:  # pragma: no cover - older llvmlite: typed pointers
    _TYPED_POINTERS = True

__all__ = ["jit", "prefetch", "vector_arrays"]

configure_cache_dir(Path(__file__).parent)  # a user folder if the package is read-only
ensure_fresh_cache(Path(__file__).parent)  # before any cached kernel is loaded
announce_compilation(__name__.split(".")[0])


def jit(func=None, **options):
    """``numba.njit`` with the package's options (``cache=True``, no fastmath)."""
    opts = {"cache": True, "fastmath": False, "nogil": True}
    opts.update(options)
    if func is None:
        return lambda f: numba.njit(**opts)(f)
    return numba.njit(**opts)(func)


@intrinsic
def _llvm_prefetch(typingctx, arr, idx):  # pragma: no cover - compiled
    """``llvm.prefetch`` of ``arr[idx]``: read, locality 2 (``prefetcht1``, into L2).

    Measured for the DSMC at N = 10^6: 5 ns per candidate, against 13-17 ns with an L1
    prefetch (``prefetcht0`` or ``prefetchw``), which holds one of the few L1 miss buffers.
    """
    sig = types.void(arr, idx)

    def codegen(context, builder, signature, args):
        ary = context.make_array(signature.args[0])(context, builder, args[0])
        ptr = cgutils.get_item_pointer(context, builder, signature.args[0], ary, [args[1]])
        i8p = ir.IntType(8).as_pointer()
        i32 = ir.IntType(32)
        fn = cgutils.get_or_insert_function(
            builder.module, ir.FunctionType(ir.VoidType(), [i8p, i32, i32, i32]),
            "llvm.prefetch.p0i8" if _TYPED_POINTERS else "llvm.prefetch.p0")
        builder.call(fn, [builder.bitcast(ptr, i8p), ir.Constant(i32, 0), ir.Constant(i32, 2),
                          ir.Constant(i32, 1)])
        return context.get_dummy_value()

    return sig, codegen


def prefetch(arr, idx):
    """Hint that ``arr[idx]`` will be read soon (compiled kernels); a no-op in Python."""


# (numba's TypedDict of jit options omits "cache", which overload accepts)
@overload(prefetch, jit_options={"cache": True})  # type: ignore[typeddict-unknown-key]
def _prefetch_jit(arr, idx):  # pragma: no cover - compiled
    def impl(arr, idx):
        _llvm_prefetch(arr, idx)

    return impl


def vector_arrays(context, builder, signature, args, vec, count):  # pragma: no cover
    """For an intrinsic's codegen on ``vec`` vectors: the data pointers of its first
    ``count`` array arguments and ``at(base, offset)``, the ``vec`` pointer at element
    ``offset`` of ``base``."""
    vptr = vec.as_pointer()
    data = [context.make_array(signature.args[a])(context, builder, args[a]).data
            for a in range(count)]

    def at(base, off):
        return builder.bitcast(builder.gep(base, [off]), vptr)

    return data, at
