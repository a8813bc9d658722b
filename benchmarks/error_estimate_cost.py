"""CPU cost of the error estimates (issue 29): estimate over solve, with problem sizes.

Each estimate is computed when ``dist.error`` / ``ev.error`` is first read (the spectral
series check during the solve, ``check_series=True``); this prints the CPU time of the
solve and of the estimate and their ratio (time.process_time, within one run).

The second table is the Sonine series check (orders ``P - 2 .. P + 6``, the
:class:`~kinetic_fem.exceptions.AsymptoticSeriesWarning`) at the default order 8, heated
(alpha 0.6) and cooling (alpha 0.9), kernels 0.5, 1 and 2: the CPU time of the solve
without the check (``check_series=False``), what the default solve adds to it, what the
check at solve time (``check_series=True``) adds, and the first read of ``dist.error``
after a default solve; the smallest of ``--repeats`` runs, each with the tensor cache
emptied (a new problem's first solve).

Usage::

    python benchmarks/error_estimate_cost.py [--repeats 10]
"""

from __future__ import annotations

import argparse
import time
import warnings
from collections.abc import Callable
from typing import Any

from yardstick import best_cpu


def _cpu(fn: Callable[[], Any]) -> tuple[Any, float]:
    t = time.process_time()
    out = fn()
    return out, time.process_time() - t


def series_check_cost(repeats: int) -> None:
    """Print the table of the Sonine series check's cost (see the module docstring)."""
    import kinetic_fem as kf
    from kinetic_fem.operators import sonine_tensors

    def cold(call: Callable[[], Any]) -> Callable[[], Any]:
        def run() -> Any:
            sonine_tensors._CACHE.clear()   # a new problem: no tensor cached
            return call()
        return run

    print(f"\n{'Sonine order 8':26s} {'n_v':>5s} {'solve ms':>9s} {'default+':>9s} "
          f"{'True+':>6s} {'.error':>7s} {'asymptotic':>10s}")
    for kind, alpha in (("heated", 0.6), ("cooling", 0.9)):
        fn = kf.solve_heated if kind == "heated" else kf.solve_cooling
        for gamma in (0.5, 1.0, 2.0):
            def solve(gamma: float = gamma, fn: Any = fn, alpha: float = alpha,
                      **kw: Any) -> Any:
                return fn(alpha, kernel=gamma, method="spectral", **kw)

            t_bare, d = best_cpu(cold(lambda: solve(check_series=False)), repeats)
            t_default, _ = best_cpu(cold(solve), repeats)
            t_eager, _ = best_cpu(cold(lambda: solve(check_series=True)), repeats)

            def read_error() -> float:
                out = solve()
                t = time.process_time()
                _ = out.error
                return time.process_time() - t

            t_error = min(cold(read_error)() for _ in range(repeats))
            asym = solve().error.asymptotic
            print(f"{kind} alpha {alpha} gamma {gamma:<4g} {d.v.size:5d} {1e3 * t_bare:9.2f} "
                  f"{(t_default - t_bare) / t_bare:9.2f} {(t_eager - t_bare) / t_bare:6.2f} "
                  f"{t_error / t_bare:7.2f} {asym!s:>10s}")
    print("(ratios to the solve without the check: what the default solve adds, what "
          "check_series=True adds, the first read of dist.error)")


def main() -> None:
    import kinetic_fem as kf

    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=10)
    args = parser.parse_args()
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
    series_check_cost(args.repeats)


if __name__ == "__main__":
    main()
