"""CPU cost of the error estimates (issue 29): estimate over solve, with problem sizes.

Each estimate is computed when ``dist.error`` / ``ev.error`` is first read (the spectral
series check during the solve, ``check_series=True``); this prints the CPU time of the
solve and of the estimate and their ratio (time.process_time, within one run).

Usage::

    python benchmarks/error_estimate_cost.py
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Callable
from typing import Any


def _cpu(fn: Callable[[], Any]) -> tuple[Any, float]:
    t = time.process_time()
    out = fn()
    return out, time.process_time() - t


def main() -> None:
    import kinetic_fem as kf

    warnings.simplefilter("ignore")
    kf.solve_heated(0.6)   # compile and warm caches outside the timings
    rows = []
    for label, solve in (
            ("fem heated 0.6 (default)", lambda: kf.solve_heated(0.6)),
            ("fem cooling 0.6 (default)", lambda: kf.solve_cooling(0.6)),
            ("fem cooling 0.5 gamma 2", lambda: kf.solve_cooling(0.5, kernel=2.0)),
            ("spectral heated 0.6 gamma 0.5", lambda: kf.solve_heated(
                0.6, kernel=0.5, method="spectral")),
            ("spectral heated 0.6, check_series=False", lambda: kf.solve_heated(
                0.6, kernel=0.5, method="spectral", check_series=False)),
            ("evolve_cooling 0.8, t=0.1,0.2, spacing 0.5, rtol 1e-2", lambda: kf.evolve_cooling(
                0.8, times=[0.1, 0.2], spacing=0.5, rtol=1e-2))):
        res, t_solve = _cpu(solve)
        _, t_est = _cpu(lambda res=res: res.error)
        size = res.grid.shape[1] if hasattr(res, "grid") else res.v.size
        rows.append((label, size, t_solve, t_est))
    print(f"{'problem':58s} {'nodes':>6s} {'solve s':>8s} {'estimate s':>10s} {'ratio':>6s}")
    for label, size, t_s, t_e in rows:
        print(f"{label:58s} {size:6d} {t_s:8.3f} {t_e:10.3f} {t_e / t_s:6.2f}")


if __name__ == "__main__":
    main()
