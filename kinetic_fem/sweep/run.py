"""Run a parameter sweep: evaluate every grid point, persist it, gather a Dataset.

``sweep(function, grid, **fixed)`` calls ``function(**point, **fixed)`` for every point
of the outer product of ``grid`` (:mod:`kinetic_fem.sweep.grid`) and reduces each
result, a :class:`~kinetic_fem.distribution.VelocityDistribution` or a particle run
(any object with ``.distribution``, ``.a2``, ``.a2_error``, ``.temperature`` and
``.n_collisions``, as :mod:`particles.dsmc` and :mod:`particles.md` return), to a small
record on the worker: :math:`T`, :math:`a_2` and their errors (a particle run's standard
errors, a deterministic result's a posteriori estimate ``dist.error``, as absolute
errors: ``T_error``, ``a2_error``, ``f_error``), :math:`\\zeta`, the Sonine
coefficients :math:`a_p`, ``p = 2..6``, the wall time, ``converged`` and
:math:`f(c) = \\sqrt{T}P(u + c\\sqrt T)` on a common grid of :math:`c`.  Only records
travel back to the caller, which writes each to the store
(:mod:`kinetic_fem.sweep.store`) before reporting it.
"""

from __future__ import annotations

import inspect
import json
import logging
import math
import os
import pickle
import time
from concurrent.futures import FIRST_COMPLETED, Executor, Future, ProcessPoolExecutor, wait
from pathlib import Path
from typing import Any, Callable, Mapping

import numpy as np
from numpy.typing import NDArray

from ..distribution import MAX_SONINE, VelocityDistribution
from ..options import option_names
from ..progress import progress_bar
from .grid import canonical_value, grid_points, point_key, point_seed
from .store import PointStore

__all__ = ["sweep", "evaluate_point", "summarize", "summarize_mixture", "SerialExecutor",
           "C_GRID", "SCALARS", "MIXTURE_SCALARS", "MIXTURE_SPECIES"]

logger = logging.getLogger(__name__)

C_GRID = np.linspace(-6.0, 6.0, 241)
"""Common scaled velocities :math:`c` at which every point's :math:`f(c)` is stored."""

SCALARS = ("T", "T_error", "a2", "a2_error", "zeta", "wall_time", "converged",
           "n_collisions")
"""Scalar data variables of a sweep (NaN where a method does not provide them)."""

SONINE_ORDERS = np.arange(2, MAX_SONINE + 1)

MIXTURE_SCALARS = ("T_ratio", "T_ratio_error")
"""Scalar data variables of a sweep of mixtures: :math:`T_1/T_2` and its standard error."""

MIXTURE_SPECIES = ("T_species", "T_species_error", "a2_species", "a2_species_error")
"""Data variables of a sweep of mixtures over the dim ``species``."""


def _is_mixture(result: Any) -> bool:
    """A mixture result (MixtureMoments, a particle MixtureRun): ``mixture``, ``temperatures``."""
    return hasattr(result, "mixture") and hasattr(result, "temperatures")


def summarize_mixture(result: Any, c: NDArray[np.float64] = C_GRID
                      ) -> dict[str, NDArray[np.float64]]:
    """The record of a mixture result (duck typing: ``mixture``, ``temperatures``, ...).

    ``T`` is the mixture temperature :math:`\\sum_s x_s T_s`, ``a2``, ``sonine``, ``f``
    NaN; the species' :math:`T_s`, :math:`a_{2,s}` and the ratio :math:`T_1/T_2` with
    the standard errors of a sampled run (``temperature_errors``, ``a2_errors``,
    ``temperature_ratio_error()``; NaN for a deterministic one).

    Parameters
    ----------
    result : object
        A mixture result (``mixture``, ``temperatures``, ``a2``, ...).
    c : ndarray
        The velocity grid of the record's ``f`` (NaN for a mixture).

    Returns
    -------
    dict of str to ndarray
    """
    k = result.mixture.n_species
    nan_k = np.full(k, np.nan)
    temps = np.asarray(result.temperatures, dtype=float)
    t_err = np.asarray(getattr(result, "temperature_errors", nan_k), dtype=float)
    a2_err = np.asarray(getattr(result, "a2_errors", nan_k), dtype=float)
    ratio_error = getattr(result, "temperature_ratio_error", None)
    batches = getattr(result, "batch_temperatures", None)
    t_mix_err = (float(np.std(batches @ np.asarray(result.mixture.fractions), ddof=1)
                       / math.sqrt(batches.shape[0])) if batches is not None else math.nan)
    zeta = getattr(result, "zeta", None)
    out = {"T": float(result.temperature), "T_error": t_mix_err, "a2": math.nan,
           "a2_error": math.nan, "zeta": math.nan if zeta is None else float(zeta),
           "wall_time": math.nan, "converged": 1.0,
           "n_collisions": float(getattr(result, "n_collisions", math.nan)),
           "T_ratio": float(result.temperature_ratio()),
           "T_ratio_error": math.nan if ratio_error is None else float(ratio_error())}
    rec = {key: np.asarray(v, dtype=float) for key, v in out.items()}
    rec.update({"T_species": temps, "T_species_error": t_err,
                "a2_species": np.asarray(result.a2, dtype=float), "a2_species_error": a2_err,
                "sonine": np.full(SONINE_ORDERS.size, np.nan), "f": np.full(c.size, np.nan),
                "f_error": np.full(c.size, np.nan)})
    return rec


class SerialExecutor(Executor):
    """Runs each submitted call at once in the calling process (debugging, tests, CLI)."""

    def submit(self, fn: Callable[..., Any], /, *args: Any, **kwargs: Any) -> Future:
        """Call ``fn(*args, **kwargs)`` now; its result or exception is in the Future."""
        future: Future = Future()
        try:
            future.set_result(fn(*args, **kwargs))
        except BaseException as exc:  # handed to the caller through the future
            future.set_exception(exc)
        return future


def summarize(result: Any, c: NDArray[np.float64] = C_GRID) -> dict[str, NDArray[np.float64]]:
    """The record of one result: the scalars of :data:`SCALARS`, ``sonine``, ``f``, ``f_error``.

    Parameters
    ----------
    result : VelocityDistribution or particle run
        A run is recognised by its ``distribution`` attribute (duck typing: kinetic_fem
        never imports particles); its own ``temperature``, ``a2``, ``a2_error`` and
        ``n_collisions`` are used.
    c : ndarray, shape (n_c,)
        Scaled velocities of ``f``.

    Returns
    -------
    dict of str to ndarray
        float64 arrays: 0-d scalars, ``sonine`` shape (5,) for ``p = 2..6``, ``f`` and
        ``f_error`` shape (n_c,); ``wall_time`` is NaN here (set by :func:`evaluate_point`).

    Raises
    ------
    TypeError
        If ``result`` is neither a distribution nor a run.
    """
    if _is_mixture(result):
        return summarize_mixture(result, c)
    if isinstance(result, VelocityDistribution):
        dist, run = result, None
    elif isinstance(getattr(result, "distribution", None), VelocityDistribution):
        dist, run = result.distribution, result
    else:
        raise TypeError("a sweep function must return a VelocityDistribution or a particle run "
                        f"(with .distribution); got {type(result).__name__}")
    src = dist if run is None else run
    extra = dist.info.extra
    temperature = float(src.temperature)
    same_t = run is None or math.isclose(temperature, dist.temperature, rel_tol=1e-12)
    t_error = dist.observable_error(lambda d: d.temperature) if same_t else math.nan
    zeta = getattr(run, "zeta", None) if run is not None else None
    zeta = extra.get("zeta", math.nan) if zeta is None else zeta
    n_coll = getattr(run, "n_collisions", None) if run is not None else None
    n_coll = extra.get("n_collisions", math.nan) if n_coll is None else n_coll
    f_err = (np.full(c.shape, np.nan) if dist.f_errors is None else
             np.interp(c, dist.c, dist.f_errors, left=np.nan, right=np.nan))
    a2_error = float(src.a2_error)
    f = np.asarray(dist.f(c), dtype=float)
    if run is None and dist.batch_moments is None:
        # a deterministic result: its a posteriori estimate (kinetic_fem.error), as
        # absolute errors like the particle runs' standard errors
        est = dist.error
        t_error, a2_error, f_err = est.temperature * temperature, est.a2, est.f(c) * f
    out = {"T": temperature, "T_error": t_error, "a2": float(src.a2),
           "a2_error": a2_error, "zeta": float(zeta), "wall_time": math.nan,
           "converged": float(bool(dist.info.converged)), "n_collisions": float(n_coll)}
    rec = {k: np.asarray(v, dtype=float) for k, v in out.items()}
    rec["sonine"] = np.array([dist.sonine_coefficient(int(p)) for p in SONINE_ORDERS])
    rec["f"] = f
    rec["f_error"] = np.asarray(f_err, dtype=float)
    return rec


def evaluate_point(function: Callable[..., Any], kwargs: Mapping[str, Any],
                   c: NDArray[np.float64] = C_GRID) -> tuple[dict[str, Any], dict[str, str]]:
    """Call ``function(**kwargs)`` and return its record and text attributes (worker side).

    Parameters
    ----------
    function : callable
        The function of the sweep (a solver or a particle simulation).
    kwargs : mapping
        Its keyword arguments at this point (grid values and fixed ones).
    c : ndarray, shape (m,)
        Scaled velocities at which ``f(c)`` is recorded.

    Returns
    -------
    record : dict
        The point's numbers (T, a2, f, ...).
    attributes : dict of str to str
        Its text attributes (method, messages).
    """
    start = time.perf_counter()
    result = function(**kwargs)
    wall = time.perf_counter() - start
    rec = summarize(result, np.asarray(c, dtype=float))
    rec["wall_time"] = np.asarray(wall)
    if _is_mixture(result):
        dists = getattr(result, "distributions", None)
        method = dists[0].method if dists else getattr(result, "method", "")
        message = getattr(getattr(result, "info", None), "message", "")
        return rec, {"method": str(method), "message": str(message)}
    dist = getattr(result, "distribution", result)
    attrs = {"method": str(dist.method), "message": str(dist.info.message)}
    return rec, attrs


def _name(function: Callable[..., Any]) -> str:
    module = getattr(function, "__module__", None) or "?"
    return f"{module}.{getattr(function, '__qualname__', repr(function))}"


def _text(value: Any) -> str | int | float:
    if isinstance(value, (bool, np.bool_)):
        return str(bool(value))
    if isinstance(value, (int, float, str, np.integer, np.floating)):
        return canonical_value(value)  # type: ignore[return-value]
    return repr(value)


def _takes(function: Callable[..., Any], name: str) -> bool:
    try:
        params = inspect.signature(function).parameters
    except (TypeError, ValueError):
        return False
    return name in params


def _check_call(function: Callable[..., Any], names: list[str]) -> None:
    """Raise TypeError now if ``function`` cannot take these keyword arguments."""
    valid = option_names(function)  # its parameters and its option objects' fields
    if valid is None:
        return
    unknown = [n for n in names if n not in valid]
    if unknown:
        raise TypeError(f"{_name(function)} takes no argument(s) {unknown}; valid names: "
                        f"{valid}")


def _open_executor(executor: Any, n_todo: int) -> tuple[Executor, bool]:
    if executor is None:
        return ProcessPoolExecutor(max(1, min(n_todo, os.cpu_count() or 1))), True
    if isinstance(executor, str) and executor == "serial":
        return SerialExecutor(), True
    if isinstance(executor, Executor):
        return executor, False
    if callable(getattr(executor, "get_executor", None)):  # a dask.distributed Client
        return executor.get_executor(pure=False), False
    raise TypeError("executor must be None (a local process pool), 'serial', a "
                    "concurrent.futures.Executor or a dask.distributed Client; got "
                    f"{type(executor).__name__}")


def sweep(function: Callable[..., Any], grid: Mapping[str, Any], *,
          store: str | Path | None = None, executor: Any = None, progress: bool | None = None,
          **fixed: Any) -> Any:
    """Evaluate ``function(**point, **fixed)`` on the outer product of ``grid``.

    Parameters
    ----------
    function : callable
        Returns a :class:`~kinetic_fem.distribution.VelocityDistribution` (e.g.
        :func:`kinetic_fem.solve_heated`) or a particle run (e.g.
        ``particles.dsmc.simulate_heated``).  For a process pool it must be importable
        (a module-level function, not a lambda).
    grid : dict of str to sequence
        Parameter name -> values (numbers, booleans or strings); the dims of the result.
    store : str or Path, optional
        Directory where each finished point is written at once (one netCDF file per
        point, atomically; :mod:`kinetic_fem.sweep.store`).  A rerun computes only the
        missing points; damaged files are recomputed.
    executor : None, "serial", Executor or dask.distributed.Client
        None: a local process pool of ``min(points, cores)`` workers; "serial": in this
        process; any ``concurrent.futures.Executor``; a dask Client (``executor=client``).
    progress : bool, optional
        tqdm progress bar over the points (stderr); default (None): shown when the
        session is interactive (a terminal or a notebook), quiet otherwise.
    **fixed
        Keyword arguments passed to every call.  If ``function`` takes ``seed`` and the
        grid has none, each point gets ``seed = point_seed(point, root=fixed["seed"])``
        (:func:`kinetic_fem.sweep.grid.point_seed`), so results are identical whatever
        the executor and the number of workers.  A grid dimension named ``replica``
        (e.g. ``"replica": range(32)``) that ``function`` does not take is not passed
        to it: it only labels independent replicas, whose derived seeds differ.

    Returns
    -------
    xarray.Dataset
        Data variables ``T, T_error, a2, a2_error, zeta, wall_time, n_collisions`` (float,
        NaN where the method gives none), ``converged`` (bool), ``sonine`` (dim ``p`` =
        2..6, the Sonine coefficients :math:`a_p`), ``f`` and ``f_error`` (dim ``c``,
        :data:`C_GRID`) and ``seed`` (derived seeds), all over the grid dims; attributes
        ``function``, ``method`` and the fixed options.  A function returning a mixture
        result (:class:`~kinetic_fem.mixture_state.MixtureMoments`, a particle
        ``MixtureRun``; e.g. :func:`kinetic_fem.mixture_solve.solve_binary`) adds
        ``T_ratio`` and ``T_ratio_error`` (:math:`T_1/T_2`) and, over the dim
        ``species``, ``T_species``, ``T_species_error``, ``a2_species`` and
        ``a2_species_error`` (:func:`summarize_mixture`); ``T`` is then the mixture
        temperature and ``a2`` NaN.

    Raises
    ------
    TypeError, ValueError
        For an invalid grid, names ``function`` does not take, or a store of another
        sweep.  An exception raised at a point is re-raised (noting the point) after the
        points finished so far are stored.

    Examples
    --------
    >>> import kinetic_fem as kf
    >>> ds = kf.sweep(kf.solve_heated, {"alpha": [0.5, 0.9]}, method="spectral",
    ...               executor="serial")
    >>> ds.a2.dims, bool(ds.a2.sel(alpha=0.5) > ds.a2.sel(alpha=0.9))
    (('alpha',), True)
    """
    if not callable(function):
        raise TypeError(f"function must be callable, got {function!r}")
    coords, points = grid_points(grid)
    both = sorted(set(coords) & set(fixed))
    if both:
        raise ValueError(f"{both} given both in the grid and as fixed options")
    root = fixed.pop("seed", None) if "seed" not in coords else None
    derive = "seed" not in coords and _takes(function, "seed")
    if root is not None and not derive:
        fixed["seed"] = root
    replica = "replica" in coords and not _takes(function, "replica")
    if replica and not derive:
        raise ValueError("a 'replica' grid dimension labels independent runs of a function "
                         "that takes a seed (not given in the grid); "
                         f"{_name(function)} takes none, or the grid gives the seeds")
    names = [n for n in coords if not (replica and n == "replica")]
    _check_call(function, [*names, *fixed, *(["seed"] if derive else [])])
    c = C_GRID
    manifest = {"function": _name(function),
                "fixed": {k: _text(v) for k, v in sorted(fixed.items())},
                "seed_root": None if root is None or not derive else _text(root),
                "c": [float(c[0]), float(c[-1]), int(c.size)]}
    db = None if store is None else PointStore(store, manifest)

    keys = [point_key(p) for p in points]
    records: dict[int, tuple[dict[str, Any], dict[str, str]]] = {}
    if db is not None:
        for i, key in enumerate(keys):
            got = db.load(key)
            if got is not None:
                records[i] = got
    seeds = [point_seed(p, root) if derive else None for p in points]
    todo = [i for i in range(len(points)) if i not in records]
    logger.info("sweep of %s: %d point(s), %d stored, %d to compute", manifest["function"],
                len(points), len(records), len(todo))
    if todo:
        # the sweep's bar counts the points: a function with a bar of its own (DSMC, MD,
        # evolve, solve) runs quiet unless the caller asked for its bar
        quiet = ({"progress": False} if _takes(function, "progress")
                 and "progress" not in fixed and "progress" not in coords else {})
        calls = [{**{k: v for k, v in p.items() if not (replica and k == "replica")},
                  **quiet} for p in points]
        _compute(function, points, calls, seeds, fixed, todo, keys, records, db, executor,
                 progress)
    return _dataset(coords, points, records, seeds, manifest, store, derive)


def _compute(function, points, calls, seeds, fixed, todo, keys, records, db, executor,
             progress):
    """Evaluate ``function(**calls[i], **fixed)`` for ``i in todo``; store, record, report."""
    pool, owned = _open_executor(executor, len(todo))
    if isinstance(pool, ProcessPoolExecutor):
        try:
            pickle.dumps(function)
        except Exception as exc:
            if owned:
                pool.shutdown()
            raise TypeError(f"{_name(function)} cannot be sent to a process pool ({exc}); "
                            "use a module-level function or executor='serial'") from exc
    bar = progress_bar(total=len(points), initial=len(points) - len(todo),
                       progress=progress, desc="sweep", unit="point")
    pending: dict[Future, int] = {}
    queue = list(todo)
    window = 1 if isinstance(pool, SerialExecutor) else len(todo)  # serial: one at a time

    def submit_next() -> None:
        while queue and len(pending) < window:
            i = queue.pop(0)
            kwargs = {**calls[i], **fixed}
            if seeds[i] is not None:
                kwargs["seed"] = seeds[i]
            pending[pool.submit(evaluate_point, function, kwargs, C_GRID)] = i

    try:
        submit_next()
        while pending:
            done, _ = wait(pending, return_when=FIRST_COMPLETED)
            for fut in done:
                i = pending.pop(fut)
                try:
                    rec, attrs = fut.result()
                except Exception as exc:
                    if hasattr(exc, "add_note"):
                        exc.add_note(f"in sweep point {points[i]}")
                    logger.error("sweep point %s failed: %s", points[i], exc)
                    raise
                if db is not None:
                    db.save(keys[i], rec, attrs)
                records[i] = (rec, attrs)
                logger.info("sweep point %s done (%.3g s)", points[i], float(rec["wall_time"]))
                bar.update(1)
            submit_next()
    finally:
        bar.close()
        for fut in pending:
            fut.cancel()
        if owned:
            pool.shutdown(wait=not pending, cancel_futures=True)  # no wait on an error


def _dataset(coords, points, records, seeds, manifest, store, derive):
    import xarray as xr

    dims = list(coords)
    shape = tuple(v.size for v in coords.values())
    n_c = C_GRID.size
    arrays = {name: np.full(shape, np.nan) for name in SCALARS}
    arrays["sonine"] = np.full((*shape, SONINE_ORDERS.size), np.nan)
    arrays["f"] = np.full((*shape, n_c), np.nan)
    arrays["f_error"] = np.full((*shape, n_c), np.nan)
    n_species = max((rec["T_species"].size for rec, _ in records.values()
                     if "T_species" in rec), default=0)
    if n_species:  # a sweep of mixtures: the ratio and the species' values
        arrays.update({name: np.full(shape, np.nan) for name in MIXTURE_SCALARS})
        arrays.update({name: np.full((*shape, n_species), np.nan) for name in MIXTURE_SPECIES})
    methods = set()
    for i, (rec, attrs) in records.items():
        idx = np.unravel_index(i, shape)
        for name, a in arrays.items():
            if name in rec:
                a[idx] = rec[name]
        methods.add(attrs.get("method", ""))
    data = {name: (dims, a) for name, a in arrays.items() if a.ndim == len(dims)}
    for name in MIXTURE_SPECIES if n_species else ():
        data[name] = ([*dims, "species"], arrays[name])
    data["converged"] = (dims, arrays["converged"] == 1.0)
    data["sonine"] = ([*dims, "p"], arrays["sonine"])
    data["f"] = ([*dims, "c"], arrays["f"])
    data["f_error"] = ([*dims, "c"], arrays["f_error"])
    if derive:
        data["seed"] = (dims, np.array(seeds, dtype=np.int64).reshape(shape))
    extra = {"species": np.arange(1, n_species + 1)} if n_species else {}
    ds = xr.Dataset(data, coords={**coords, "p": SONINE_ORDERS, "c": C_GRID, **extra})
    if n_species:
        ds["T_ratio"].attrs["long_name"] = "temperature ratio T_1/T_2"
        ds["T"].attrs["long_name"] = "mixture temperature sum_s x_s T_s"
    ds.attrs.update({"function": manifest["function"],
                     "method": ",".join(sorted(m for m in methods if m)),
                     "fixed": json.dumps(manifest["fixed"], sort_keys=True),
                     "points": len(points)})
    ds.attrs.update({f"fixed_{k}": v for k, v in manifest["fixed"].items()})
    if store is not None:
        ds.attrs["store"] = str(store)
    ds["f"].attrs["long_name"] = "f(c) = sqrt(T) P(u + c sqrt(T))"
    ds["sonine"].attrs["long_name"] = "Sonine coefficient a_p"
    if not n_species:
        ds["T"].attrs["long_name"] = "temperature <(v-u)^2>"
    return ds
