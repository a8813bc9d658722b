"""Plots of results and sweeps: f(c) on a log scale, :math:`a_2` against a parameter.

:func:`plot_f` draws one result, several, an evolution or a sweep (it is
``dist.plot()``); :func:`plot_a2` takes the ``xarray.Dataset`` of
:func:`kinetic_fem.sweep.sweep`.  The helpers draw on
a given matplotlib ``Axes`` or on a new :class:`matplotlib.figure.Figure` created
without pyplot, so importing this module (or drawing) never selects a backend; a
backend is chosen only where a figure is written, by :func:`save_figure` (Agg, for
files).  Pass ``ax=plt.gca()`` to draw into an interactive figure.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any, Callable

import numpy as np

__all__ = ["subplots", "plot_a2", "plot_f", "plot_sweep", "new_axes", "save_figure", "F_FLOOR"]


def new_axes(n: int = 1, *, width: float = 5.0, height: float = 3.8) -> list[Any]:
    """``n`` side-by-side Axes on a new pyplot-free Figure (``ax.figure`` is the Figure).

    Parameters
    ----------
    n : int
        Number of panels, side by side.
    width, height : float
        Size of one panel in inches.

    Returns
    -------
    list of matplotlib Axes
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width * n, height), layout="constrained")
    return list(np.atleast_1d(fig.subplots(1, n)))


def subplots(nrows: int = 1, ncols: int = 1, *, figsize: tuple[float, float] = (6.0, 4.0),
             **kwargs: Any) -> tuple[Any, Any]:
    """A new figure and its axes, as :func:`matplotlib.pyplot.subplots` but without pyplot.

    Parameters
    ----------
    nrows, ncols : int
        Grid of axes.
    figsize : tuple of float
        Size in inches.
    **kwargs
        Passed to :meth:`matplotlib.figure.Figure.subplots`.

    Returns
    -------
    fig : matplotlib Figure
    axes : Axes or array of Axes

    Examples
    --------
    >>> fig, (ax, bx) = subplots(1, 2, figsize=(8, 3))
    >>> len(fig.axes)
    2
    """
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize)
    return fig, fig.subplots(nrows, ncols, **kwargs)


def save_figure(fig: Any, path: str | Path, **kwargs: Any) -> Path:
    """Write ``fig`` to ``path`` (format from the suffix) with the Agg canvas.

    A Figure made by pyplot keeps its own canvas; a pyplot-free one gets an Agg
    canvas here, the only place a backend is chosen.

    Parameters
    ----------
    fig : matplotlib Figure
        The figure to write.
    path : str or Path
        Destination; its suffix selects the format.
    **kwargs
        Passed to ``Figure.savefig``.

    Returns
    -------
    Path
        The path written.
    """
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    path = Path(path)
    if type(fig.canvas).__name__ == "FigureCanvasBase":
        FigureCanvasAgg(fig)
    fig.savefig(path, **kwargs)
    return path


def _series(ds: Any, x: str) -> list[tuple[str, Any]]:
    """One (label, 1-D sub-dataset along ``x``) per combination of the other grid dims."""
    if x not in ds.dims:
        raise ValueError(f"{x!r} is not a grid dimension of this sweep; dims: "
                         f"{[d for d in ds.a2.dims]}")
    others = [d for d in ds.a2.dims if d != x]
    if not others:
        return [("", ds)]
    stacked = ds.stack(_line=others)
    out = []
    for i in range(stacked.sizes["_line"]):
        line = stacked.isel(_line=i)
        label = ", ".join(f"{d}={line[d].item()}" for d in others)
        out.append((label, line))
    return out


def plot_a2(ds: Any, *, x: str = "alpha", ax: Any = None, label: str | None = None,
            theory: Callable[[Any], Any] | None = None, theory_label: str | None = None,
            **style: Any) -> Any:
    """:math:`a_2` against ``x``, with its error bars where the method gives them.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep (:func:`kinetic_fem.sweep.sweep`); one line per combination of the
        grid dims other than ``x``.
    x : str
        The grid dimension on the horizontal axis.
    ax : matplotlib Axes, optional
        Default: a new pyplot-free figure (see :func:`save_figure`).
    label : str, optional
        Legend label (default: the method, plus the other dims' values).
    theory : callable, optional
        A curve ``theory(x_values)`` drawn dashed, e.g.
        :func:`kinetic_fem.sonine.a2_first_order`.
    theory_label : str, optional
        Its legend label (default: the function's name).
    **style
        Passed to ``Axes.errorbar``.

    Returns
    -------
    matplotlib Axes
    """
    ax = new_axes()[0] if ax is None else ax
    base = label if label is not None else (ds.attrs.get("method") or "sweep")
    for text, line in _series(ds, x):
        xs = np.asarray(line[x].values, dtype=float)
        order = np.argsort(xs)
        err = np.asarray(line.a2_error.values, dtype=float)[order]
        yerr = None if not np.isfinite(err).any() else np.nan_to_num(err)
        kw = {"fmt": "o" if yerr is not None else "-", "ms": 4, "capsize": 2, **style}
        ax.errorbar(xs[order], np.asarray(line.a2.values)[order], yerr=yerr,
                    label=f"{base} {text}".strip(), **kw)
    if theory is not None:
        grid = np.linspace(float(ds[x].min()), float(ds[x].max()), 200)
        name = theory_label or getattr(theory, "__name__", "theory")
        ax.plot(grid, theory(grid), "k--", lw=1, label=name)
    ax.axhline(0.0, color="gray", lw=0.5)
    ax.set(xlabel=x, ylabel="$a_2$")
    ax.legend(fontsize="small")
    return ax


def plot_f(data: Any, *, ax: Any = None, log: bool = True, gaussian: bool = True,
           errors: bool | None = None, label: str | None = None, **style: Any) -> Any:
    """:math:`f(c)` of one or several results: a distribution, a list, an evolution or
    a Dataset (a sweep's, or one made by ``to_xarray``).

    Sampled results are drawn with their error band (one standard error);
    deterministic ones with the band of their error estimate (``dist.error``) where
    known; ``log`` gives a log scale in :math:`f` (tails, down to
    :data:`F_FLOOR`), ``gaussian`` adds :math:`e^{-c^2/2}/\\sqrt{2\\pi}`.

    Parameters
    ----------
    data : VelocityDistribution, Evolution, list of them, or xarray.Dataset
        A distribution; an evolution (one curve per output time); a list or tuple of
        distributions; the Dataset of :func:`kinetic_fem.sweep` (variables ``f`` over
        ``c`` and ``f_error``, one curve per point) or of ``to_xarray()``.
    ax : matplotlib Axes, optional
        Where to draw (default: a new pyplot-free figure, see :func:`save_figure`).
    log : bool
        Logarithmic ``f`` axis.
    gaussian : bool
        Add the unit Gaussian for reference.
    errors : bool, optional
        Error bands: None (default) draws the ones known without extra work (sampled
        results, and deterministic estimates already computed); True also computes
        the estimate of a deterministic result (``dist.error``, about one more solve);
        False draws none.
    label : str, optional
        Legend label of a single curve (default: the method and alpha).
    **style
        Passed to ``ax.plot``.

    Returns
    -------
    matplotlib Axes

    Examples
    --------
    >>> import kinetic_fem as kf
    >>> v = np.linspace(-10, 10, 401)
    >>> d = kf.VelocityDistribution.from_values(v, np.exp(-v**2 / 2), method="exact")
    >>> ax = plot_f([d, d.rescaled(2.0)])
    >>> len(ax.lines)  # two curves and the Gaussian
    3
    """
    ax = new_axes()[0] if ax is None else ax
    curves = _curves(data, errors=errors, label=label)
    if not curves:
        raise ValueError(f"nothing to plot in {type(data).__name__}")
    lowest = 1.0
    for name, c, f, err in curves:
        keep = (f > 0) & np.isfinite(f) if log else np.isfinite(f)
        (curve,) = ax.plot(c[keep], f[keep], label=name, **style)
        if err is not None and np.isfinite(err[keep]).any():
            band = np.nan_to_num(err)
            ax.fill_between(c[keep], np.maximum(f - band, 0)[keep], (f + band)[keep],
                            color=curve.get_color(), alpha=0.25, lw=0)
        if keep.any():
            lowest = min(lowest, float(f[keep].min()))
    if gaussian:
        span = max(float(np.nanmax(np.abs(c[np.isfinite(c)]))) for _, c, _, _ in curves)
        g = np.linspace(-span, span, 801)
        ax.plot(g, np.exp(-g**2 / 2) / math.sqrt(2 * math.pi), "k:", lw=1, label="Gaussian")
    if log:
        ax.set_yscale("log")
        ax.set_ylim(max(lowest, F_FLOOR) / 2, 1.0)
    ax.set(xlabel="c", ylabel="f(c)")
    ax.legend(fontsize="small")
    return ax


F_FLOOR = 1e-30
"""Lowest :math:`f` shown on a log scale (the paper's 30 decades)."""

_Curve = tuple[str, Any, Any, Any]


def _name(dist: Any) -> str:
    alpha = dict(dist.params).get("alpha")
    return " ".join(p for p in (dist.method, "" if alpha is None else f"alpha={alpha}") if p)


def _distribution_curve(dist: Any, errors: bool | None, label: str | None) -> _Curve:
    """(label, c, f, one standard error or error-estimate band of f or None)."""
    c, f = np.asarray(dist.c, dtype=float), np.asarray(dist.f_values, dtype=float)
    err = None if errors is False else dist.f_errors
    if err is None and errors is not False and hasattr(type(dist), "error") \
            and (errors or "error" in vars(dist)):
        estimate = dist.error  # computed here only with errors=True
        err = np.abs(f) * np.nan_to_num(np.asarray(estimate.f(c), dtype=float))
    return (label if label is not None else _name(dist)), c, f, err


def _dataset_curves(ds: Any, errors: bool | None) -> list[_Curve]:
    """Curves of a Dataset: a sweep's (``f`` over ``c``) or one of ``to_xarray``."""
    if "c" in ds.dims:  # a sweep: one curve per point, on the common c grid
        c = np.asarray(ds.c.values, dtype=float)
        first = ds.a2.dims[0]
        out = []
        for text, line in _series(ds, first):
            for k in range(line.sizes[first]):
                point = line.isel({first: k})
                name = ", ".join(p for p in (f"{first}={point[first].item()}", text) if p)
                err = None if errors is False else np.asarray(point.f_error.values, dtype=float)
                out.append((name, c, np.asarray(point.f.values, dtype=float), err))
        return out
    if "time" in ds.dims:  # Evolution.to_xarray
        return [(f"t={float(ds.time[i]):.4g}", np.asarray(ds.c[i], dtype=float),
                 np.asarray(ds.f[i], dtype=float), None) for i in range(ds.sizes["time"])]
    err = ds["f_error"].values if "f_error" in ds and errors is not False else None
    return [(str(ds.attrs.get("method", "")), np.asarray(ds.c.values, dtype=float),
             np.asarray(ds.f.values, dtype=float), err)]


def _curves(data: Any, *, errors: bool | None, label: str | None) -> list[_Curve]:
    if hasattr(data, "data_vars"):
        return _dataset_curves(data, errors)
    if hasattr(data, "f_values"):
        return [_distribution_curve(data, errors, label)]
    if hasattr(data, "times") and hasattr(data, "grid"):  # an Evolution
        return [_distribution_curve(data[i], errors, f"t={t:.4g}")
                for i, t in enumerate(data.times)]
    if isinstance(data, (list, tuple)):
        return [curve for item in data for curve in _curves(item, errors=errors, label=None)]
    raise TypeError(f"plot_f takes a VelocityDistribution, an Evolution, a list of "
                    f"distributions or an xarray Dataset; got {type(data).__name__}")


def plot_sweep(ds: Any, path: str | Path | None = None, *, x: str = "alpha",
               theory: Callable[[Any], Any] | None = None) -> Any:
    """Two panels, :func:`plot_a2` and :func:`plot_f`; written to ``path`` if given.

    Parameters
    ----------
    ds : xarray.Dataset
        A sweep result of :func:`kinetic_fem.sweep`.
    path : str or Path, optional
        Write the figure there (format from the suffix).
    x : str
        Grid dimension on the horizontal axis of the a2 panel.
    theory : callable, optional
        ``theory(x_values) -> a2`` drawn as a line beside the points.

    Returns
    -------
    matplotlib Figure
    """
    ax1, ax2 = new_axes(2)
    plot_a2(ds, x=x, ax=ax1, theory=theory)
    plot_f(ds, ax=ax2)
    if path is not None:
        save_figure(ax1.figure, path)
    return ax1.figure
