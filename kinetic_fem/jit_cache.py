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

Where the cache lives: numba writes it beside the sources (each ``__pycache__``).  When
the package folder is not writable (a system-wide installation) and the user has not
chosen a folder with ``NUMBA_CACHE_DIR``, :func:`configure_cache_dir` points numba at a
user cache folder, ``$XDG_CACHE_HOME/kinetic-fem/numba`` (``~/.cache/...``), where
:func:`ensure_fresh_cache` keeps it consistent in the same way.

:func:`announce_compilation` says once per process that kernels are being compiled (the
first solve after a fresh install spends most of its time there): an INFO record of this
module's logger and, when progress is shown (the ``progress=`` of the running call, by
default when the session is interactive, see :mod:`kinetic_fem.progress`) and no logging
handler shows that record already, one line on stderr through ``tqdm.write`` (the
progress bars' channel).  It is not a warning: ``-W error`` runs are not affected.
"""

from __future__ import annotations

import hashlib
import logging
import os
import sys
from pathlib import Path
from typing import Any

__all__ = ["ensure_fresh_cache", "kernel_sources_digest", "configure_cache_dir",
           "user_cache_dir", "cache_folders", "announce_compilation", "compilation_message",
           "COMPILE_SECONDS"]

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
    folders = cache_folders(root)
    user = os.environ.get("NUMBA_CACHE_DIR")
    stamp = (Path(user) / f"{root.name}-{_path_hash(str(root))[:12]}-{STAMP}" if user
             else root / "__pycache__" / STAMP)
    try:
        digest = kernel_sources_digest(root)
        if stamp.is_file() and stamp.read_text().strip() == digest:
            return False
        stale = [p for folder in folders for pattern in ("*.nbi", "*.nbc")
                 for p in folder.glob(pattern)]
        for path in stale:
            path.unlink(missing_ok=True)
        stamp.parent.mkdir(parents=True, exist_ok=True)
        stamp.write_text(digest)
    except OSError as err:  # read-only installation: numba cannot cache there either
        logger.debug("numba cache of %s not checked: %s", root, err)
        return False
    if stale:
        logger.info("kernel sources of %s changed: removed %d cached kernel files",
                    root.name, len(stale))
    return bool(stale)


COMPILE_SECONDS = 30
"""Rough CPU seconds numba spends compiling the kernels of a first heated and cooling
solve on an idle core (``benchmarks/bench_first_hour.py``, first-solve row), quoted by
:func:`announce_compilation`."""


def compilation_message(where: str) -> str:
    """The one line that says kernels are being compiled.

    Parameters
    ----------
    where : str
        Where later runs load them from.

    Returns
    -------
    str

    Examples
    --------
    >>> compilation_message("here").startswith("kinetic-fem: compiling kernels, once per install")
    True
    """
    return (f"kinetic-fem: compiling kernels, once per install, about {COMPILE_SECONDS} s of "
            f"CPU for a first heated and cooling solve; later runs load them from {where}")


def _path_hash(path: str) -> str:
    return hashlib.sha1(path.encode()).hexdigest()


def user_cache_dir() -> Path:
    """The user's cache folder for kinetic-fem's kernels: ``$XDG_CACHE_HOME/kinetic-fem/numba``.

    Returns
    -------
    Path
        ``~/.cache/kinetic-fem/numba`` unless ``XDG_CACHE_HOME`` is set.
    """
    base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    return Path(base) / "kinetic-fem" / "numba"


def configure_cache_dir(package_dir: str | Path) -> Path | None:
    """Send numba's cache to :func:`user_cache_dir` if ``package_dir`` is not writable.

    Only when the user has not set ``NUMBA_CACHE_DIR`` (their choice wins); numba would
    otherwise fall back to its own user-wide folder, which :func:`ensure_fresh_cache`
    does not know.  Sets ``NUMBA_CACHE_DIR`` (inherited by worker processes) and, if
    numba is already imported, its ``config.CACHE_DIR``.

    Parameters
    ----------
    package_dir : str or Path
        Directory of the package whose kernels are cached.

    Returns
    -------
    Path or None
        The folder chosen, or None if nothing was changed.
    """
    if os.environ.get("NUMBA_CACHE_DIR"):
        return None
    root = Path(package_dir)
    pycache = root / "__pycache__"
    if os.access(pycache if pycache.is_dir() else root, os.W_OK):
        return None
    folder = user_cache_dir()
    os.environ["NUMBA_CACHE_DIR"] = str(folder)
    config = sys.modules.get("numba.core.config")
    if config is not None:
        config.CACHE_DIR = str(folder)  # type: ignore[attr-defined]
    logger.info("%s is not writable: numba kernels are cached in %s", root, folder)
    return folder


def cache_folders(package_dir: str | Path) -> list[Path]:
    """The folders where numba caches the kernels of a package's modules.

    Each ``__pycache__`` of the package, or with ``NUMBA_CACHE_DIR`` set the subfolders
    numba names ``<directory>_<sha1 of its path>`` there.

    Parameters
    ----------
    package_dir : str or Path
        Directory of the package.

    Returns
    -------
    list of Path
        Existing or not.
    """
    root = Path(package_dir)
    dirs = sorted({p.parent for p in root.rglob("*.py") if "__pycache__" not in p.parts})
    user = os.environ.get("NUMBA_CACHE_DIR")
    if not user:
        return [d / "__pycache__" for d in dirs]
    names = {f"{d.name}_{_path_hash(os.path.abspath(d))}" for d in dirs}
    names |= {f"{d.name}_{_path_hash(str(d.resolve()))}" for d in dirs}
    return [Path(user) / name for name in sorted(names)]


_ANNOUNCED: list[Any] = []


def announce_compilation(package: str) -> None:
    """Say once per process when numba first compiles a kernel of ``package``.

    A listener of numba's ``numba:compile`` event, which fires only when a kernel is
    not found in the cache.  The message (:func:`compilation_message`) names the cost
    and says that it is paid once per install: always as an INFO log record of this
    module, and as one line on stderr (``tqdm.write``, so that a running bar stays
    intact) when progress is shown -- :func:`kinetic_fem.progress.showing_progress`,
    that is the ``progress=`` of the running call (``False``, or the command line's
    ``--quiet``, silences it) -- unless a logging handler already shows the record (the
    command line logs INFO to stderr).  Not a warning: ``-W error`` is unaffected.

    Parameters
    ----------
    package : str
        Top-level package name (``"kinetic_fem"``, ``"particles"``).
    """
    from numba.core import event

    if _ANNOUNCED:
        _ANNOUNCED[0].packages.add(package)
        return

    class _Listener(event.Listener):  # type: ignore[misc]
        packages = {package}

        def on_start(self, ev: Any) -> None:
            func = getattr(ev.data.get("dispatcher"), "py_func", None)
            module = str(getattr(func, "__module__", ""))
            if module.split(".")[0] in self.packages and not getattr(self, "done", False):
                self.done = True
                where = os.environ.get("NUMBA_CACHE_DIR") or "the package's __pycache__"
                _say(compilation_message(where))

        def on_end(self, ev: Any) -> None:
            pass

    listener = _Listener()
    _ANNOUNCED.append(listener)
    event.register("numba:compile", listener)


def _logged_visibly(log: logging.Logger, level: int) -> bool:
    """Whether a record of ``level`` from ``log`` reaches a handler that lets it through."""
    if not log.isEnabledFor(level):
        return False
    node: logging.Logger | None = log
    while node is not None:
        if any(h.level <= level for h in node.handlers):
            return True
        node = node.parent if node.propagate else None
    return False


def _say(message: str) -> None:
    """Log ``message`` at INFO; also write it on stderr if progress is shown and no
    handler shows the record."""
    from .progress import showing_progress

    visible = _logged_visibly(logger, logging.INFO)
    logger.info("%s", message)
    if showing_progress() and not visible:
        from tqdm import tqdm

        tqdm.write(message, file=sys.stderr)
