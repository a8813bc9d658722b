"""All numba compile options of the ``particles`` package, in one place.

Kernels are compiled with ``cache=True`` and hold no global state; random numbers are
drawn by numpy generators outside the kernels and passed in, so that runs are
reproducible from explicit seeds and checkpoints resume bit-identically.
Setting ``NUMBA_DISABLE_JIT=1`` runs the kernels as plain Python (slow, for tests).
"""

from __future__ import annotations

import numba

__all__ = ["jit"]


def jit(func=None, **options):
    """``numba.njit`` with the package's options (``cache=True``, no fastmath)."""
    opts = {"cache": True, "fastmath": False, "nogil": True}
    opts.update(options)
    if func is None:
        return lambda f: numba.njit(**opts)(f)
    return numba.njit(**opts)(func)
