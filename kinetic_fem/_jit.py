"""All numba compile options of the ``kinetic_fem`` package, in one place.

Kernels are compiled with ``cache=True`` (kept consistent across modules by
:func:`kinetic_fem.jit_cache.ensure_fresh_cache`), take arrays and scalars only and hold no
global state.  Setting ``NUMBA_DISABLE_JIT=1`` runs them as plain Python (slow, for
tests).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any, Callable

import numba

from .jit_cache import announce_compilation, configure_cache_dir, ensure_fresh_cache

__all__ = ["jit"]

configure_cache_dir(Path(__file__).parent)  # a user folder if the package is read-only
ensure_fresh_cache(Path(__file__).parent)  # before any cached kernel is loaded
announce_compilation(__name__.split(".")[0])


def jit(func: Callable[..., Any] | None = None, **options: Any) -> Any:
    """``numba.njit`` with the package's options (``cache=True``, no fastmath)."""
    opts: dict[str, Any] = {"cache": True, "fastmath": False, "nogil": True}
    opts.update(options)
    if func is None:
        return lambda f: numba.njit(**opts)(f)
    return numba.njit(**opts)(func)
