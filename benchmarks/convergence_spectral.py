"""Convergence of the Sonine Galerkin solver with the truncation order P.

Prints
1. a2 .. a6, T (heated) or zeta (cooling) against P for hard rods at
   alpha = 0.3, 0.6, 0.9, 0.99, with the conditioning of the equilibrated Newton
   Jacobian and the wall time;
2. the Maxwell-kernel exactness: the largest relative error of a_2 .. a_P and T against
   the exact moment recursion (kinetic_fem.solvers.maxwell) at P = 2 .. 80;
3. T and a2 for gamma in {0, 0.5, 1, 2}, white noise (D = 1) and a Fokker-Planck bath
   (xi = 1, D = 1), alpha in {0.3, 0.6, 0.9, 0.99}: of the converged orders among
   (8, 12, 16, 24, 32), the higher of the two consecutive ones that differ least
   (optimal truncation: at small alpha and gamma < 2 the series is asymptotic and high
   orders drift), with that difference as the error estimate; written to the CSV file
   given on the command line.

    python benchmarks/convergence_spectral.py [table.csv]
"""

import csv
import sys
import time

import numpy as np

from kinetic_fem.solvers import maxwell
from kinetic_fem.solvers.spectral import solve_sonine, solve_sonine_cooling

ALPHAS = (0.3, 0.6, 0.9, 0.99)
ORDERS = (2, 4, 6, 8, 12, 16, 24, 32, 40)


def _solve(alpha, order, cooling, **kw):
    if cooling:
        sol, zeta = solve_sonine_cooling(alpha, order, **kw)
        return sol, zeta
    sol = solve_sonine(alpha, order, **kw)
    return sol, sol.temperature


def convergence(cooling: bool) -> None:
    kind = "cooling (zeta)" if cooling else "heated (T)"
    for alpha in ALPHAS:
        print(f"\nhard rods, {kind}, alpha = {alpha}")
        print(f"{'P':>3} {'a2':>14} {'a3':>12} {'a4':>12} {'a5':>12} {'a6':>12} "
              f"{'T or zeta':>16} {'|da2|':>9} {'cond':>8} {'s':>6}")
        prev = None
        for order in ORDERS:
            t0 = time.perf_counter()
            try:
                sol, y = _solve(alpha, order, cooling)
            except RuntimeError as exc:
                print(f"{order:>3}  no solution: {str(exc).split(':')[0][-60:]}")
                continue
            a = np.full(7, np.nan)
            a[: min(7, order + 1)] = sol.coefficients[:7]
            da2 = abs(a[2] - prev) if prev is not None else np.nan
            prev = a[2]
            print(f"{order:>3} {a[2]:14.10f} {a[3]:12.8f} {a[4]:12.8f} {a[5]:12.8f} "
                  f"{a[6]:12.8f} {y:16.12f} {da2:9.1e} {sol.condition_number:8.1e} "
                  f"{time.perf_counter() - t0:6.2f}")


def maxwell_exactness() -> None:
    print("\nMaxwell kernel: Galerkin against the exact recursion (max relative error)")
    print(f"{'alpha':>6} {'xi':>4} {'P':>3} {'a_p (p<=P)':>11} {'T':>9} {'|a_P|':>9} "
          f"{'cond':>8}")
    for alpha in (0.3, 0.6, 0.9):
        for xi in (0.0, 1.0):
            exact = maxwell.steady_state(alpha, 80, friction=xi)
            for order in (2, 8, 20, 40, 60, 80):
                sol = solve_sonine(alpha, order, kernel=0.0, friction=xi)
                err = np.max(np.abs(sol.coefficients[2:] / exact.sonine[2:order + 1] - 1))
                err_t = abs(sol.temperature / exact.temperature - 1)
                print(f"{alpha:6.2f} {xi:4.1f} {order:3d} {err:11.1e} {err_t:9.1e} "
                      f"{abs(exact.sonine[order]):9.1e} {sol.condition_number:8.1e}")


def model_table(path: str | None) -> None:
    print("\nT and a2 across the model space (Sonine Galerkin; err = change from the "
          "previous converged order)")
    header = ["gamma", "thermostat", "alpha", "order", "T", "a2", "T_err", "a2_err"]
    print(" ".join(f"{h:>12}" for h in header))
    rows = []
    for gamma in (0.0, 0.5, 1.0, 2.0):
        for thermostat, xi in (("white", 0.0), ("bath", 1.0)):
            for alpha in ALPHAS:
                done = []
                for order in (8, 12, 16, 24, 32):
                    try:
                        done.append(solve_sonine(alpha, order, kernel=gamma, friction=xi))
                    except RuntimeError:
                        continue
                if not done:
                    row = [gamma, thermostat, alpha, 0, np.nan, np.nan, np.nan, np.nan]
                elif len(done) == 1:
                    s = done[0]
                    row = [gamma, thermostat, alpha, s.order, s.temperature,
                           s.coefficients[2], np.nan, np.nan]
                else:
                    # optimal truncation: the consecutive pair that changes least (the
                    # series is asymptotic where the tail is far from a Gaussian)
                    def change(pair):
                        p, s = pair
                        return max(abs(s.temperature / p.temperature - 1),
                                   abs(s.coefficients[2] - p.coefficients[2]))
                    p, s = min(zip(done[:-1], done[1:], strict=True), key=change)
                    row = [gamma, thermostat, alpha, s.order, s.temperature, s.coefficients[2],
                           abs(s.temperature - p.temperature),
                           abs(s.coefficients[2] - p.coefficients[2])]
                rows.append(row)
                print(f"{gamma:12.1f} {thermostat:>12} {alpha:12.2f} {row[3]:12d} "
                      f"{row[4]:12.9f} {row[5]:12.9f} {row[6]:12.1e} {row[7]:12.1e}")
    if path:
        with open(path, "w", newline="") as fh:
            writer = csv.writer(fh)
            writer.writerow(["method", *header])
            for row in rows:
                writer.writerow(["spectral", *row])
        print(f"written to {path}")


if __name__ == "__main__":
    convergence(cooling=False)
    convergence(cooling=True)
    maxwell_exactness()
    model_table(sys.argv[1] if len(sys.argv) > 1 else None)
