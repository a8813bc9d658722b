"""Convergence of the Sonine moment method with the truncation order P.

Prints a2, a3 and T against P for several alpha, and the change from the previous
order (the series converges geometrically for the heated gas; slowest at alpha = 0
where the exp(-c^{3/2}) tail is furthest from a Gaussian).

    python benchmarks/convergence_spectral.py
"""

import time

from kinetic_fem.spectral import solve_sonine

if __name__ == "__main__":
    for alpha in (0.0, 0.1, 0.6, 0.9, 0.99, 0.999):
        print(f"\nalpha = {alpha}")
        print(f"{'P':>3} {'a2':>14} {'a3':>14} {'T':>16} {'|da2|':>10} {'|dT|/T':>10} {'s':>6}")
        prev = None
        for order in (2, 3, 4, 5, 6, 8, 10, 12):
            t0 = time.perf_counter()
            sol = solve_sonine(alpha, order)
            dt = time.perf_counter() - t0
            a2 = sol.coefficients[2]
            a3 = sol.coefficients[3] if order >= 3 else float("nan")
            da2 = abs(a2 - prev[0]) if prev else float("nan")
            dT = abs(sol.temperature / prev[1] - 1) if prev else float("nan")
            print(f"{order:>3} {a2:14.9f} {a3:14.9f} {sol.temperature:16.10f} "
                  f"{da2:10.2e} {dT:10.2e} {dt:6.2f}")
            prev = (a2, sol.temperature)
