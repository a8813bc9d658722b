"""Progress bars: shown when a person is watching, quiet otherwise.

Long calls take ``progress=None`` (the default: a bar when the session is interactive,
that is when stderr is a terminal or the code runs in a Jupyter notebook), ``True`` or
``False``; :func:`resolve_progress` turns that into a bool and :func:`progress_bar`
makes the bar (``tqdm``; its notebook widget in Jupyter), on stderr.  The command line
always shows its bars unless ``--quiet``.  :func:`ticking` refreshes a bar every
second while one long step runs, so that its clock moves.  :func:`showing_progress`
tells code without a ``progress=`` of its own (the numba compilation notice of
:mod:`kinetic_fem.jit_cache`) whether the running call shows progress.
"""

from __future__ import annotations

import sys
import threading
import time
from collections.abc import Iterable, Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from typing import Any

__all__ = ["interactive", "resolve_progress", "showing_progress", "progress_bar", "ticking",
           "working"]

_LAST: ContextVar[bool | None] = ContextVar("kinetic_fem_progress", default=None)
"""The progress choice last resolved in this context (each long call resolves its own
``progress=`` when it starts)."""


def _in_notebook() -> bool:
    shell = sys.modules.get("IPython")
    if shell is None:
        return False
    try:
        ip = shell.get_ipython()  # type: ignore[attr-defined]
    except AttributeError:
        return False
    return ip is not None and type(ip).__name__ == "ZMQInteractiveShell"


def interactive() -> bool:
    """Whether someone is watching: stderr is a terminal, or this is a Jupyter notebook.

    Returns
    -------
    bool
    """
    try:
        tty = bool(sys.stderr.isatty())
    except (AttributeError, ValueError):  # closed or replaced stderr
        tty = False
    return tty or _in_notebook()


def resolve_progress(progress: bool | None) -> bool:
    """The ``progress=`` argument of a long call as a bool.

    Parameters
    ----------
    progress : bool or None
        None: :func:`interactive`; a bool is returned as given.

    Returns
    -------
    bool

    Raises
    ------
    TypeError
        For anything but None or a bool.

    Examples
    --------
    >>> resolve_progress(False), resolve_progress(True)
    (False, True)
    """
    if progress is None:
        progress = interactive()
    elif not isinstance(progress, bool):
        raise TypeError(f"progress must be True, False or None (shown when interactive), "
                        f"got {progress!r}")
    _LAST.set(progress)
    return progress


def showing_progress() -> bool:
    """Whether the running call shows progress: the choice it made with
    :func:`resolve_progress` (the last one in this thread), else :func:`interactive`.

    Returns
    -------
    bool
    """
    last = _LAST.get()
    return interactive() if last is None else last


def progress_bar(iterable: Iterable[Any] | None = None, *, progress: bool | None = None,
                 **options: Any) -> Any:
    """A ``tqdm`` bar on stderr (the notebook widget in Jupyter), disabled unless wanted.

    Parameters
    ----------
    iterable : iterable, optional
        What to iterate over.
    progress : bool or None
        See :func:`resolve_progress`.
    **options
        Passed to ``tqdm`` (``total``, ``desc``, ``unit`` ...).

    Returns
    -------
    tqdm.tqdm
        Iterable and updatable; ``disable`` set from ``progress``.
    """
    if _in_notebook():
        from tqdm.auto import tqdm
    else:
        from tqdm import tqdm
    options.setdefault("file", sys.stderr)
    return tqdm(iterable, disable=not resolve_progress(progress), **options)


@contextmanager
def ticking(bar: Any, interval: float = 1.0) -> Iterator[Any]:
    """Refresh ``bar`` every ``interval`` seconds while the block runs (its clock moves).

    Parameters
    ----------
    bar : tqdm.tqdm
        The bar (a disabled bar is left alone).
    interval : float
        Seconds between refreshes.

    Yields
    ------
    tqdm.tqdm
        The bar.
    """
    stop = threading.Event()
    shown_from = getattr(bar, "start_t", 0.0) + getattr(bar, "delay", 0.0)

    def tick() -> None:
        while not stop.wait(interval):
            if time.time() >= shown_from:  # a bar with ``delay`` stays hidden until then
                bar.refresh()

    thread = None
    if not getattr(bar, "disable", True):
        thread = threading.Thread(target=tick, name="progress-tick", daemon=True)
        thread.start()
    try:
        yield bar
    finally:
        stop.set()
        if thread is not None:
            thread.join()


@contextmanager
def working(desc: str, progress: bool | None, delay: float = 2.0,
            interval: float = 1.0) -> Iterator[Any]:
    """A bar without a total for one long call: its name and a moving clock.

    Shown only if the call is still running after ``delay`` seconds (a quick call prints
    nothing), and only when ``progress`` asks for it (:func:`resolve_progress`).

    Parameters
    ----------
    desc : str
        What runs (the bar's text).
    progress : bool or None
        See :func:`resolve_progress`.
    delay : float
        Seconds before the bar appears.
    interval : float
        Seconds between refreshes of its clock.

    Yields
    ------
    tqdm.tqdm
        The bar (closed when the block ends).
    """
    bar = progress_bar(progress=progress, desc=desc, total=None, delay=delay,
                       bar_format="{desc}: {elapsed}")
    try:
        with ticking(bar, interval):
            yield bar
    finally:
        bar.close()
