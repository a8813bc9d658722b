"""The one plotting helper of the reproduce figures.

Figures are :class:`matplotlib.figure.Figure` objects made without pyplot, so no
backend is chosen at import or anywhere else: :meth:`~matplotlib.figure.Figure.savefig`
renders with the canvas of the file format when a figure is saved, and nothing has
to be closed.
"""

from __future__ import annotations

from os import PathLike
from typing import Any

__all__ = ["subplots", "save"]


def subplots(nrows: int = 1, ncols: int = 1, *, figsize: tuple[float, float] = (6.0, 4.0),
             **kwargs: Any) -> tuple[Any, Any]:
    """A new figure and its axes, as :func:`matplotlib.pyplot.subplots` but without pyplot.

    Examples
    --------
    >>> fig, (ax, bx) = subplots(1, 2, figsize=(8, 3))
    >>> len(fig.axes)
    2
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize)
    return fig, fig.subplots(nrows, ncols, **kwargs)


def save(fig: Any, path: str | PathLike[str], *, dpi: int = 120) -> None:
    """Lay out ``fig`` and write it to ``path`` (format from the suffix)."""
    fig.tight_layout()
    fig.savefig(path, dpi=dpi)
