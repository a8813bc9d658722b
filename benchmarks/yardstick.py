"""The machine yardstick of the speed benchmarks: 10 LU factorisations of 1000 x 1000.

Speed figures are quoted in yardstick units: CPU seconds of the call over CPU seconds of
:func:`cpu_yardstick` measured in the same process (single-threaded BLAS: set
``OMP_NUM_THREADS=1`` and ``OPENBLAS_NUM_THREADS=1`` before numpy is imported), so that
a loaded or a different machine changes the units less than the seconds.  About 0.15 s
on the project's 2-core machine when idle.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

import numpy as np

__all__ = ["yardstick", "cpu_yardstick", "best_cpu"]


def yardstick(clock: Callable[[], float] = time.perf_counter) -> float:
    """Seconds of ``clock`` for 10 LU factorisations of a 1000 x 1000 matrix (best of 3).

    The machine yardstick of the speed benchmarks (issue 16); :func:`cpu_yardstick` is the
    same in CPU seconds.
    """
    import scipy.linalg

    a = np.random.default_rng(0).standard_normal((1000, 1000))
    best = np.inf
    for _ in range(3):
        t0 = clock()
        for _ in range(10):
            scipy.linalg.lu_factor(a)
        best = min(best, clock() - t0)
    return float(best)


def cpu_yardstick() -> float:
    """CPU seconds (``time.process_time``) of the yardstick, best of 3: with CPU times per
    state, units that a loaded machine does not inflate."""
    return yardstick(time.process_time)


def best_cpu(call: Callable[[], Any], repeats: int) -> tuple[float, Any]:
    """Smallest CPU time (``time.process_time``) of ``repeats`` calls and the last result."""
    times = []
    out = None
    for _ in range(repeats):
        cpu = time.process_time()
        out = call()
        times.append(time.process_time() - cpu)
    return min(times), out
