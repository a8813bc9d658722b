"""Systematic errors of the heated DSMC: time step (splitting) and particle number.

Run: ``python benchmarks/convergence_dsmc.py [--quick]``.

1. Splitting error.  The heated scheme is the Strang splitting
   ``K(dt/2) C(dt) K(dt/2)`` of collisions and kicks, so the steady state should carry
   an ``O(dt^2)`` error.  The table gives T and a2 against dt (in mean free times) at
   alpha = 0.3, N = 10^4, and the order ``p`` of a weighted least-squares fit
   ``X(dt) = X_0 + b dt^p`` (p free), with the differences between successive dt and
   their ratios.
2. Particle number.  T and a2 against N at dt = 0.05 mean free times with the same
   number of samples ``N * collisions_per_particle``, and a fit ``X = X_inf + b/N``.

Statistical errors are batch errors of each run (20 consecutive batches).
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np
from scipy.optimize import curve_fit

from kinetic_fem.sonine import steady_temperature
from particles import dsmc


def _temperature_error(run: dsmc.DSMCRun) -> float:
    return run.distribution.observable_error(lambda d: d.temperature)


def _row(label: str, run: dsmc.DSMCRun, wall: float) -> tuple[float, float, float, float]:
    """Print and return (T, its error, a2, its error) of one run."""
    values = (run.temperature, _temperature_error(run), run.a2, run.a2_error)
    print(f"{label:>8}{values[0]:>11.5f}{values[1]:>9.5f}{values[2]:>10.5f}{values[3]:>9.5f}"
          f"{wall:>8.1f}")
    return values


def splitting(alpha: float, n: int, cpp: float, factors: list[float], seed: int) -> None:
    mft = 1.0 / (2.0 * math.sqrt(steady_temperature(alpha) / math.pi))
    rows = []
    print(f"\n1. splitting error: alpha={alpha}, N={n}, {cpp:g} collisions per particle "
          "per point")
    print(f"{'dt/mft':>8}{'T':>11}{'+-':>9}{'a2':>10}{'+-':>9}{'wall s':>8}")
    for k, f in enumerate(factors):
        t0 = time.perf_counter()
        r = dsmc.simulate_heated(alpha, n, seed=seed + k, dt=f * mft,
                                 collisions_per_particle=cpp, relax=20.0)
        rows.append((f, *_row(f"{f:.4f}", r, time.perf_counter() - t0)))
    data = np.array(rows)
    for col, name in ((1, "T"), (3, "a2")):
        x, y, e = data[:, 0], data[:, col], data[:, col + 1]
        d = np.diff(y)
        ratios = d[:-1] / d[1:]
        print(f"{name}: differences between successive dt {np.array2string(d, precision=5)}; "
              f"ratios {np.array2string(ratios, precision=2)} (order 2 with dt halving: 4, "
              f"with dt / sqrt 2: 2)")
        try:
            popt, pcov = curve_fit(lambda h, y0, b, p: y0 + b * h**p, x, y,
                                   p0=(y[-1], (y[0] - y[-1]) / x[0] ** 2, 2.0), sigma=e,
                                   absolute_sigma=True, maxfev=20_000)
            print(f"{name}: fit X0 + b dt^p: X0 = {popt[0]:.5f}, b = {popt[1]:.4f}, observed "
                  f"order p = {popt[2]:.2f} +- {math.sqrt(pcov[2, 2]):.2f}")
        except RuntimeError as exc:
            print(f"{name}: fit failed: {exc}")


def particle_number(alpha: float, sizes: list[int], samples: float, seed: int) -> None:
    print(f"\n2. particle number: alpha={alpha}, dt=0.05 mft, {samples:.2g} samples per point")
    print(f"{'N':>8}{'T':>11}{'+-':>9}{'a2':>10}{'+-':>9}{'wall s':>8}")
    rows = []
    for k, n in enumerate(sizes):
        t0 = time.perf_counter()
        r = dsmc.simulate_heated(alpha, n, seed=seed + k, relax=20.0,
                                 collisions_per_particle=max(40.0, samples / n))
        rows.append((n, *_row(str(n), r, time.perf_counter() - t0)))
    data = np.array(rows)
    for col, name in ((1, "T"), (3, "a2")):
        x, y, e = data[:, 0], data[:, col], data[:, col + 1]
        popt, pcov = curve_fit(lambda m, y0, b: y0 + b / m, x, y, sigma=e, absolute_sigma=True)
        print(f"{name}: fit X_inf + b/N: X_inf = {popt[0]:.5f} +- {math.sqrt(pcov[0, 0]):.5f}, "
              f"b = {popt[1]:.3f} +- {math.sqrt(pcov[1, 1]):.3f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    args = parser.parse_args()
    if args.quick:
        splitting(0.3, 4000, 400.0, [0.45, 0.225, 0.1125], seed=10)
        particle_number(0.3, [100, 1000, 10000], 4e6, seed=20)
    else:
        splitting(0.3, 10_000, 4000.0, [0.45, 0.318, 0.225, 0.159, 0.1125, 0.0795], seed=10)
        particle_number(0.3, [30, 100, 316, 1000, 3162, 10000], 4e7, seed=20)


if __name__ == "__main__":
    main()
