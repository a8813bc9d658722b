"""``kinetic-fem sweep``: a parameter sweep from options or a TOML file.

A grid file (TOML) holds the same settings as the options; options given on the
command line win::

    method = "fem"           # a registered solver, "dsmc" or "md"
    problem = "heated"       # or "cooling"
    store = "sweep-store"
    [grid]
    alpha = [0.3, 0.6, 0.9]
    kernel = [0.0, 1.0]
    [options]                # fixed keyword arguments of the solver / simulation
    collisions_per_particle = 50
"""

from __future__ import annotations

import argparse
import importlib
import math
import os
import signal
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from typing import Any, Callable

from .. import load_solvers
from ..files import output_path
from ..solve import COOLING_SOLVERS, HEATED_SOLVERS, solve_cooling, solve_heated
from ..sweep import sweep
from . import COMMANDS
from .parser import api_default, check_options, float_list, int_list, key_value

__all__ = ["add_parser", "run", "read_config", "check_grid", "interrupt_note",
           "GRID_OPTIONS"]

EPILOG = """\
examples:
  kinetic-fem sweep --method fem --alpha 0.3,0.6,0.9 --kernel 0,1 --store a2-map
  kinetic-fem sweep --method dsmc --alpha 0.5,0.9 --particles 10000 --replicas 8 \\
      -o collisions_per_particle=50 -o n_batches=4
  kinetic-fem sweep --config grid.toml --scheduler tcp://10.0.0.1:8786
  kinetic-fem sweep --method spectral --problem cooling --alpha 0.7,0.9 -o order=4 --out hcs.nc

A killed sweep rerun with the same --store computes only the missing points.  Grid
file (TOML): method, problem, store, workers, scheduler, seed, out, a [grid] table
(alpha = [0.3, 0.6], ...) and an [options] table of fixed keywords.
"""

GRID_OPTIONS = {"alpha": float_list, "kernel": float_list, "friction": float_list,
                "density": float_list, "diffusion": float_list, "n_particles": int_list}
_PARTICLE_METHODS = ("dsmc", "md")


def add_parser(sub: argparse._SubParsersAction) -> argparse.ArgumentParser:
    """The ``sweep`` sub-command, added to ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The sub-parsers of the ``kinetic-fem`` parser.

    Returns
    -------
    argparse.ArgumentParser
    """
    load_solvers()  # the registered methods are the --method choices
    methods = sorted({*HEATED_SOLVERS, *COOLING_SOLVERS, *_PARTICLE_METHODS})
    p = sub.add_parser(
        "sweep", help=COMMANDS["sweep"][1],
        description="Evaluate a solver or particle simulation on the outer product of a grid "
                    "and print T and a2 for each point; with --store every finished point is "
                    "saved at once and a rerun computes only the missing ones.",
        epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--config", type=Path, default=None, metavar="FILE.toml",
                   help="grid and settings from a TOML file (options below override it)")
    p.add_argument("--method", default=None, choices=methods, metavar="METHOD",
                   help=f"one of: {', '.join(methods)} (default: fem)")
    p.add_argument("--problem", default=None, choices=("heated", "cooling"),
                   help="heated steady state (default) or free cooling")
    for name in GRID_OPTIONS:
        flag = "--particles" if name == "n_particles" else f"--{name}"
        p.add_argument(flag, dest=name, type=GRID_OPTIONS[name], default=None,
                       metavar="V1,V2,...", help=f"grid values of {name}")
    p.add_argument("--replicas", type=int, default=None, metavar="R",
                   help="R independent runs per point (stochastic methods): a grid "
                        "dimension 'replica' = 0..R-1 that only changes the derived seed")
    p.add_argument("--store", type=Path, default=None, metavar="DIR",
                   help="directory where each finished point is written (resumable)")
    p.add_argument("--scheduler", default=None, metavar="ADDRESS",
                   help="dask.distributed scheduler address, e.g. tcp://host:8786")
    p.add_argument("--workers", type=int, default=None, metavar="N",
                   help="local worker processes (default: one per core; 1: in this process)")
    p.add_argument("--seed", type=int, default=None,
                   help="root seed of the seeds derived from each point (stochastic methods)")
    p.add_argument("--out", type=Path, default=None, metavar="FILE.nc",
                   help="write the result Dataset as netCDF")
    p.add_argument("-o", "--option", dest="options", type=key_value, action="append",
                   default=[], metavar="KEY=VALUE",
                   help="fixed keyword of the solver / simulation, repeatable")
    p.add_argument("--progress", action="store_true",
                   help="progress bar over the points (the default; --quiet hides it)")
    p.add_argument("--quiet", action="store_true", help="no progress bar and no log messages")
    return p


def read_config(path: Path) -> dict[str, Any]:
    """The settings of a TOML grid file (``tomllib``; ``tomli`` on Python 3.10).

    Parameters
    ----------
    path : Path
        A TOML file with a ``[grid]`` table and optional settings.

    Returns
    -------
    dict
        Its settings.
    """
    from ..files import read_toml

    config = read_toml(path, f"--config {str(path)!r}")
    allowed = {"method", "problem", "store", "workers", "scheduler", "seed", "out", "grid",
               "options"}
    unknown = sorted(set(config) - allowed)
    if unknown:
        raise ValueError(f"unknown key(s) {unknown} in {str(path)!r}; allowed: "
                         f"{sorted(allowed)}")
    for table in ("grid", "options"):
        if not isinstance(config.get(table, {}), dict):
            raise ValueError(f"[{table}] in {str(path)!r} must be a table")
    return config


def _function(method: str, problem: str) -> tuple[Callable[..., Any], dict[str, Any]]:
    if method in _PARTICLE_METHODS:
        module = importlib.import_module(f"particles.{method}")
        return getattr(module, f"simulate_{problem}"), {}
    table = HEATED_SOLVERS if problem == "heated" else COOLING_SOLVERS
    if method not in table:
        raise ValueError(f"method {method!r} has no {problem} solver; {problem} methods: "
                         f"{sorted({*table, *_PARTICLE_METHODS})}")
    return (solve_heated if problem == "heated" else solve_cooling), {"method": method}


def _ignore_interrupt() -> None:
    """Initializer of the local workers: Ctrl-C reaches the whole process group, and is
    the parent's to handle (it reports what was kept); a worker finishes its point."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)


def _executor(workers: int | None, scheduler: str | None,
              n_points: int = 1) -> tuple[Any, Any]:
    """(executor for sweep, object to close afterwards)."""
    if scheduler is not None:
        if workers is not None:
            raise ValueError("give --scheduler or --workers, not both")
        try:
            from distributed import Client
        except ImportError as exc:
            raise ValueError("--scheduler needs dask.distributed: pip install "
                             "'kinetic-fem[distributed]'") from exc
        client = Client(scheduler)
        return client, client
    if workers is not None and workers < 1:
        raise ValueError(f"--workers must be >= 1, got {workers}")
    if workers == 1:
        return "serial", None
    if workers is None:  # as kinetic_fem.sweep's default pool
        workers = max(1, min(n_points, os.cpu_count() or 1))
    pool = ProcessPoolExecutor(workers, initializer=_ignore_interrupt)
    return pool, pool


def _stop_workers(pool: ProcessPoolExecutor) -> None:
    """Cancel the queued points and end the workers now (after Ctrl-C).

    The workers ignore SIGINT, so a point they are computing would run on, and the
    interpreter's exit would wait for it (once seen: a sweep that printed its interrupt
    line and did not exit within 120 s); its result would not be stored anyway.

    Parameters
    ----------
    pool : ProcessPoolExecutor
        The sweep's pool (``_executor``).
    """
    workers = list((getattr(pool, "_processes", None) or {}).values())
    pool.shutdown(wait=False, cancel_futures=True)
    for proc in workers:
        proc.terminate()
    for proc in workers:
        proc.join(timeout=5)


def _settings(args: argparse.Namespace) -> dict[str, Any]:
    config = read_config(args.config) if args.config is not None else {}
    grid = dict(config.get("grid", {}))
    for name in GRID_OPTIONS:
        if getattr(args, name) is not None:
            grid[name] = getattr(args, name)
    if args.replicas is not None:
        if args.replicas < 1:
            raise ValueError(f"--replicas must be >= 1, got {args.replicas}")
        grid["replica"] = list(range(args.replicas))
    if "particles" in grid:
        grid["n_particles"] = grid.pop("particles")
    options = {**config.get("options", {}), **dict(args.options)}
    pick = {k: getattr(args, k) if getattr(args, k) is not None else config.get(k)
            for k in ("method", "problem", "store", "workers", "scheduler", "seed", "out")}
    pick["method"] = pick["method"] or api_default(solve_heated, "method")
    pick["problem"] = pick["problem"] or "heated"
    if not grid:
        raise ValueError("empty grid: give e.g. --alpha 0.3,0.6,0.9 or a [grid] table in "
                         "--config")
    if pick["out"] is not None and Path(pick["out"]).suffix != ".nc":
        raise ValueError(f"--out must end in .nc, got {str(pick['out'])!r}")
    if pick["out"] is not None:  # before the sweep: a failing export must not lose it
        output_path(pick["out"], name="--out")
    return {"grid": grid, "options": options, **pick}


def run(args: argparse.Namespace) -> int:
    """Run ``kinetic-fem sweep``: evaluate the grid (resuming a store), print and save.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        Exit status (0).
    """
    s = _settings(args)
    function, fixed = _function(s["method"], s["problem"])
    if s["method"] in _PARTICLE_METHODS and "n_particles" not in s["grid"] | s["options"]:
        raise ValueError(f"--method {s['method']} needs --particles N (or n_particles in the "
                         "grid)")
    if s["method"] in _PARTICLE_METHODS:
        check_options(function, s["options"], f"{function.__module__}.{function.__name__}",
                      exclude=tuple(s["grid"]))
    else:
        table = HEATED_SOLVERS if s["problem"] == "heated" else COOLING_SOLVERS
        solver_opts = {k: v for k, v in s["options"].items()
                       if k not in ("density", "diffusion", "friction", "kernel")}
        check_options(table[s["method"]], solver_opts, f"method {s['method']!r}",
                      exclude=("problem",))
    check_grid(s["grid"], s["options"], s["problem"])
    if s["seed"] is not None:
        fixed["seed"] = s["seed"]
    n_points = math.prod(len(v) for v in s["grid"].values())
    executor, closing = _executor(s["workers"], s["scheduler"], n_points)
    try:
        ds = sweep(function, s["grid"], store=s["store"], executor=executor,
                   progress=args.progress or not args.quiet, **fixed, **s["options"])
    except KeyboardInterrupt:
        if isinstance(closing, ProcessPoolExecutor):
            _stop_workers(closing)
            closing = None
        raise
    finally:
        if closing is not None:
            closing.shutdown() if isinstance(closing, ProcessPoolExecutor) else closing.close()
    _print_table(ds, list(s["grid"]))
    if s["out"] is not None:
        netcdf3(ds).to_netcdf(s["out"], engine="scipy")
        print(f"saved to {s['out']}")
    return 0


def netcdf3(ds: Any) -> Any:
    """``ds`` as netCDF3 (scipy's engine) can hold it: no 64-bit integers.

    Integer variables and coordinates become int32 where every value fits, float64
    (exact up to 2^53) otherwise.
    """
    import numpy as np

    small = np.iinfo(np.int32)
    changes = {}
    for name, var in ds.variables.items():
        if var.dtype.kind in "iu" and var.dtype.itemsize > 4:
            fits = var.size == 0 or (small.min <= int(var.min()) and int(var.max()) <= small.max)
            changes[name] = var.astype(np.int32 if fits else np.float64)
    coords = {k: v for k, v in changes.items() if k in ds.coords}
    data = {k: v for k, v in changes.items() if k not in ds.coords}
    return ds.assign_coords(coords).assign(data)


_MODEL_KEYS = {"heated": ("alpha", "density", "diffusion", "friction", "kernel"),
               "cooling": ("alpha", "density", "kernel")}


def check_grid(grid: dict[str, list[Any]], options: dict[str, Any], problem: str) -> None:
    """Validate the model parameters of every grid point before the first one runs.

    Each point's ``alpha``, ``density``, ``kernel`` (and heated: ``diffusion``,
    ``friction``) build the problem of :mod:`kinetic_fem.model`, which checks them; a
    bad value is refused here, naming the point, instead of after the good points ran.

    Parameters
    ----------
    grid : dict of str to list
        The grid values (``--alpha 0.3,0.6`` ...).
    options : dict
        Fixed keywords (``-o``), which may hold model parameters too.
    problem : {"heated", "cooling"}
        Which problem the sweep solves.

    Raises
    ------
    ValueError
        Naming the first invalid grid point and the model's message.
    """
    from itertools import product

    from ..model import CoolingProblem, HeatedProblem

    keys = [k for k in _MODEL_KEYS[problem] if k in grid]
    fixed = {k: v for k, v in options.items() if k in _MODEL_KEYS[problem]}
    build = HeatedProblem.from_parameters if problem == "heated" else \
        CoolingProblem.from_parameters
    for values in product(*(grid[k] for k in keys)):
        point = dict(zip(keys, values, strict=True))
        model = {**fixed, **point}
        try:
            build(model.pop("alpha", 0.5), **model)
        except (ValueError, TypeError) as exc:
            raise ValueError(f"grid point {point} is invalid (nothing was computed): "
                             f"{exc}") from None


def interrupt_note(args: argparse.Namespace) -> str:
    """What a Ctrl-C kept: the finished points of the store, and how to resume.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    str
    """
    store = args.store
    if store is None and args.config is not None:
        try:
            store = read_config(args.config).get("store")
        except (OSError, ValueError):
            store = None
    if store is None:
        return ("nothing was kept (no --store); add --store DIR to keep each finished "
                "point and resume")
    points = len(list(Path(store).glob("point-*.nc")))
    return (f"{points} finished point(s) are kept in {store}; run the same command again "
            "to compute only the missing ones")


def _print_table(ds: Any, dims: list[str]) -> None:
    cols = [*dims, "T", "a2", "a2_error", "zeta", "converged", "wall_time"]
    table = ds[["T", "a2", "a2_error", "zeta", "converged", "wall_time"]].to_dataframe()
    table = table.reset_index()[cols]
    if table["zeta"].isna().all():
        table = table.drop(columns="zeta")
    sys.stdout.write(table.to_string(index=False, float_format=lambda x: f"{x:.6g}") + "\n")
    print(f"{int(ds.converged.sum())}/{ds.converged.size} point(s) converged; "
          f"function {ds.attrs['function']} method {ds.attrs['method']}")
