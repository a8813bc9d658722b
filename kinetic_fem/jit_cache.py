"""Keep numba's on-disk kernel cache consistent with the package's sources.

The kernels are compiled with ``cache=True``; numba checks a cached kernel only against
its *own* source file's time stamp and size, not against the files of the kernels it
calls.  After an edit or an upgrade that changes a called kernel in another module (for
example the pair loops of :mod:`kinetic_fem.operators.fem_pair_fast`, called by
:mod:`kinetic_fem.operators.fem_kernels`), the caller's cached machine code would still
run the old callee, silently.  :func:`ensure_fresh_cache` closes that gap: it hashes the
sources of every module of a package that compiles kernels and, if the hash differs
from the one stored beside the cache, removes the package's cached kernels (``*.nbi``,
``*.nbc``) before any is loaded, so that everything is compiled afresh once.
"""

from __future__ import annotations

import hashlib
import logging
from pathlib import Path

__all__ = ["ensure_fresh_cache", "kernel_sources_digest"]

logger = logging.getLogger(__name__)

STAMP = "numba-sources.sha1"
"""File in the package's top ``__pycache__`` holding the digest the cache was built from."""

_MARKERS = (b"jit", b"numba")
_DONE: set[Path] = set()


def kernel_sources_digest(package_dir: str | Path) -> str:
    """SHA-1 of the sources of the modules of a package that mention numba or ``jit``.

    Parameters
    ----------
    package_dir : str or Path
        Directory of the package (searched recursively for ``*.py``).

    Returns
    -------
    str
        Hex digest over the relative paths and contents, in sorted order.

    Examples
    --------
    >>> import kinetic_fem
    >>> len(kernel_sources_digest(Path(kinetic_fem.__file__).parent))
    40
    """
    root = Path(package_dir)
    digest = hashlib.sha1()
    for path in sorted(root.rglob("*.py")):
        text = path.read_bytes()
        if any(marker in text for marker in _MARKERS):
            digest.update(str(path.relative_to(root)).encode())
            digest.update(text)
    return digest.hexdigest()


def ensure_fresh_cache(package_dir: str | Path, *, recheck: bool = False) -> bool:
    """Remove the package's cached kernels if its kernel sources changed since they
    were cached (once per process and package).

    Parameters
    ----------
    package_dir : str or Path
        Directory of the package whose ``__pycache__`` folders hold numba's cache.
    recheck : bool
        Check again even if this process checked the package already.

    Returns
    -------
    bool
        True if stale cache files were removed.  A read-only installation (no cache
        can be written there either) is left alone.
    """
    root = Path(package_dir).resolve()
    if root in _DONE and not recheck:
        return False
    _DONE.add(root)
    stamp = root / "__pycache__" / STAMP
    try:
        digest = kernel_sources_digest(root)
        if stamp.is_file() and stamp.read_text().strip() == digest:
            return False
        stale = [*root.rglob("__pycache__/*.nbi"), *root.rglob("__pycache__/*.nbc")]
        for path in stale:
            path.unlink(missing_ok=True)
        stamp.parent.mkdir(exist_ok=True)
        stamp.write_text(digest)
    except OSError as err:  # read-only installation: numba cannot cache there either
        logger.debug("numba cache of %s not checked: %s", root, err)
        return False
    if stale:
        logger.info("kernel sources of %s changed: removed %d cached kernel files",
                    root.name, len(stale))
    return bool(stale)
