"""Results as other tools show them: ``xarray`` Datasets and small HTML tables.

:func:`distribution_dataset` and :func:`evolution_dataset` are
:meth:`VelocityDistribution.to_xarray <kinetic_fem.VelocityDistribution.to_xarray>` and
:meth:`Evolution.to_xarray <kinetic_fem.evolution.Evolution.to_xarray>`: the nodal
values :math:`P(v)` and :math:`f(c) = \\sqrt T P(u + c\\sqrt T)` (with their standard
errors where sampled) and the observables :math:`T`, :math:`a_2`, :math:`a_p`, in the
variable names of a sweep (:func:`kinetic_fem.sweep`: ``T``, ``a2``, ``a2_error``,
``sonine``, ``f``, ``f_error``), so that the same code reads both.
:func:`distribution_html` and :func:`evolution_html` are the ``_repr_html_`` tables
Jupyter shows.  ``xarray`` is imported inside the functions only.
"""

from __future__ import annotations

import html
import json
import math
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from .distribution import VelocityDistribution
    from .evolution import Evolution

__all__ = ["distribution_dataset", "evolution_dataset", "distribution_html",
           "evolution_html", "SONINE_ORDERS"]

SONINE_ORDERS = np.arange(2, 7)
"""Sonine orders :math:`p = 2 \\dots 6` of the ``sonine`` variable (as in a sweep)."""


def _attrs(method: str, params: Any, info: Any) -> dict[str, Any]:
    """Dataset attributes: method, parameters and run info (JSON text where nested)."""
    return {"method": method,
            "params": json.dumps(dict(params), sort_keys=True, default=str),
            "converged": int(bool(info.converged)), "iterations": int(info.iterations),
            "wall_time": float(info.wall_time), "message": str(info.message)}


def distribution_dataset(dist: VelocityDistribution) -> Any:
    """The distribution as an ``xarray.Dataset`` over its nodes ``v``.

    Parameters
    ----------
    dist : VelocityDistribution
        Any result.

    Returns
    -------
    xarray.Dataset
        Dimension ``v`` (the nodes) with coordinate ``c`` (scaled nodes) along it;
        variables ``P`` and ``f`` (and ``P_error``, ``f_error`` for sampled results);
        scalars ``T``, ``a2``, ``a2_error`` (NaN if not sampled), ``zeta`` (NaN unless
        a cooling state); ``sonine`` over ``p = 2 .. 6``; attributes ``method``,
        ``params`` (JSON), ``converged``, ``iterations``, ``wall_time``, ``message``.

    Examples
    --------
    >>> from kinetic_fem import VelocityDistribution
    >>> v = np.linspace(-10, 10, 401)
    >>> ds = distribution_dataset(VelocityDistribution.from_values(v, np.exp(-v**2 / 2)))
    >>> sorted(ds.data_vars), ds.sizes["v"]
    (['P', 'T', 'a2', 'a2_error', 'f', 'sonine', 'zeta'], 401)
    """
    import xarray as xr

    data: dict[str, Any] = {"P": ("v", dist.values), "f": ("v", dist.f_values)}
    if dist.errors is not None:
        data["P_error"] = ("v", dist.errors)
        data["f_error"] = ("v", dist.f_errors)
    data.update({
        "T": dist.temperature, "a2": dist.a2, "a2_error": dist.a2_error,
        "zeta": float(dist.info.extra.get("zeta", math.nan)),
        "sonine": ("p", [dist.sonine_coefficient(int(p)) for p in SONINE_ORDERS])})
    ds = xr.Dataset(data, coords={"v": dist.v, "c": ("v", dist.c), "p": SONINE_ORDERS})
    ds.attrs.update(_attrs(dist.method, dist.params, dist.info))
    ds["c"].attrs["long_name"] = "scaled velocity (v - u) / sqrt(T)"
    ds["f"].attrs["long_name"] = "f(c) = sqrt(T) P(u + c sqrt(T))"
    return ds


def evolution_dataset(ev: Evolution) -> Any:
    """The evolution as an ``xarray.Dataset`` over ``time`` (and ``node``).

    Each output time has its own nodes, so ``v`` and ``c`` are variables over
    ``(time, node)``, not an index.

    Parameters
    ----------
    ev : Evolution
        A transient result.

    Returns
    -------
    xarray.Dataset
        Coordinate ``time``; variables ``v``, ``c``, ``P``, ``f`` over
        ``(time, node)``; ``T``, ``a2``, ``mass`` and every entry of ``ev.series``
        over ``time``; ``sonine`` over ``(time, p)``; attributes as
        :func:`distribution_dataset`.

    Examples
    --------
    >>> from kinetic_fem.evolution import Evolution
    >>> v = np.linspace(-8, 8, 161)[None, :]
    >>> ev = Evolution([0.0], v, np.exp(-v**2 / 2) / np.sqrt(2 * np.pi),
    ...                np.full_like(v, 0.1), method="test")
    >>> dict(evolution_dataset(ev).sizes)
    {'time': 1, 'node': 161, 'p': 5}
    """
    import xarray as xr

    dists = [ev[i] for i in range(len(ev))]
    c = np.array([d.c for d in dists]).reshape(ev.grid.shape)
    f = np.array([d.f_values for d in dists]).reshape(ev.grid.shape)
    data: dict[str, Any] = {
        "v": (("time", "node"), ev.grid), "c": (("time", "node"), c),
        "P": (("time", "node"), ev.values), "f": (("time", "node"), f),
        "T": ("time", ev.temperature), "a2": ("time", ev.a2), "mass": ("time", ev.mass),
        "sonine": (("time", "p"), ev.sonine.reshape(len(ev), SONINE_ORDERS.size))}
    for name, values in ev.series.items():
        if name not in data and np.shape(values) == ev.times.shape:
            data[name] = ("time", values)
    ds = xr.Dataset(data, coords={"time": ev.times, "p": SONINE_ORDERS})
    ds.attrs.update(_attrs(ev.method, ev.params, ev.info))
    return ds


def _table(rows: list[tuple[str, str]], title: str) -> str:
    """A two-column HTML table (escaped) with a caption."""
    body = "".join(f"<tr><th style='text-align:left'>{html.escape(k)}</th>"
                   f"<td style='text-align:left'>{html.escape(v)}</td></tr>" for k, v in rows)
    return (f"<table><caption style='text-align:left'><b>{html.escape(title)}</b></caption>"
            f"{body}</table>")


def _params_text(params: Any) -> str:
    return ", ".join(f"{k}={v}" for k, v in dict(params).items()) or "-"


def distribution_html(dist: VelocityDistribution) -> str:
    """The small table Jupyter shows for a distribution (``_repr_html_``).

    Parameters
    ----------
    dist : VelocityDistribution
        Any result.

    Returns
    -------
    str
        HTML: method, nodes, T, a2 (with its standard error if sampled), zeta (cooling),
        convergence, iterations, wall time, parameters.

    Examples
    --------
    >>> from kinetic_fem import VelocityDistribution
    >>> v = np.linspace(-10, 10, 401)
    >>> "<table>" in distribution_html(VelocityDistribution.from_values(v, np.exp(-v**2)))
    True
    """
    a2 = f"{dist.a2:.6g}"
    if dist.batch_moments is not None:
        a2 += f" ± {dist.a2_error:.2g} (standard error)"
    rows = [("method", dist.method or "-"),
            ("nodes", f"{dist.v.size} (v from {dist.v[0]:.4g} to {dist.v[-1]:.4g})"),
            ("temperature T", f"{dist.temperature:.8g}"), ("a2", a2)]
    if "zeta" in dist.info.extra:
        rows.append(("cooling rate zeta", f"{float(dist.info.extra['zeta']):.8g}"))
    rows += [("converged", f"{dist.info.converged} ({dist.info.iterations} iterations, "
                           f"{dist.info.wall_time:.3g} s)"),
             ("parameters", _params_text(dist.params))]
    return _table(rows, "VelocityDistribution")


def evolution_html(ev: Evolution, *, max_rows: int = 12) -> str:
    """The small table Jupyter shows for an evolution (``_repr_html_``).

    Parameters
    ----------
    ev : Evolution
        A transient result.
    max_rows : int
        Output times listed with T and a2 (the first and last ones if there are more).

    Returns
    -------
    str
        HTML: a summary table and a table of T(t), a2(t).
    """
    rows = [("method", ev.method or "-"), ("output times", str(len(ev))),
            ("nodes", str(ev.grid.shape[1])),
            ("steps", f"{ev.info.iterations} ({ev.info.wall_time:.3g} s)"),
            ("parameters", _params_text(ev.params))]
    index = list(range(len(ev)))
    if len(index) > max_rows:
        index = index[:max_rows // 2] + [-1] + index[-(max_rows // 2):]
    temp, a2 = ev.temperature, ev.a2
    lines = "".join("<tr><td>...</td><td></td><td></td></tr>" if i < 0 else
                    f"<tr><td>{ev.times[i]:.6g}</td><td>{temp[i]:.6g}</td>"
                    f"<td>{a2[i]:.6g}</td></tr>" for i in index)
    series = ("<table><tr><th>t</th><th>T</th><th>a2</th></tr>" + lines + "</table>")
    return _table(rows, "Evolution") + series
