"""Parameter sweeps: many solves or particle runs over a grid, persisted point by point.

:func:`sweep` evaluates a solver or particle simulation on the outer product of a grid
of parameters (:mod:`~kinetic_fem.sweep.grid`), on a local process pool, any
``concurrent.futures`` executor or a dask.distributed cluster, writes each finished
point to a store (:mod:`~kinetic_fem.sweep.store`) and returns an ``xarray.Dataset``
(:mod:`~kinetic_fem.sweep.run`).  Plots of a sweep are in :mod:`kinetic_fem.plot`.
"""

from .grid import grid_points, point_key, point_seed
from .run import C_GRID, SCALARS, SerialExecutor, evaluate_point, summarize, sweep
from .store import PointStore, point_filename

__all__ = ["sweep", "grid_points", "point_key", "point_seed", "PointStore", "point_filename",
           "SerialExecutor",
           "evaluate_point", "summarize", "C_GRID", "SCALARS"]
