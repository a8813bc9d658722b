"""Saving reproduce figures with the one plotting helper, :mod:`kinetic_fem.plot`.

Figures are :class:`matplotlib.figure.Figure` objects made without pyplot
(:func:`kinetic_fem.plot.subplots`), so no backend is chosen at import or anywhere else.
"""

from __future__ import annotations

from os import PathLike
from pathlib import Path
from typing import Any

from ..plot import save_figure, subplots

__all__ = ["subplots", "save"]


def save(fig: Any, path: str | PathLike[str], *, dpi: int = 120) -> None:
    """Lay out ``fig`` and write it to ``path`` (format from the suffix).

    Parameters
    ----------
    fig : matplotlib Figure
        The figure.
    path : str or PathLike
        Destination.
    dpi : int
        Resolution of raster formats.
    """
    fig.tight_layout()
    save_figure(fig, Path(path), dpi=dpi)
