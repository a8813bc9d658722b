"""FEM steady states across the model space (issue 9, part 5): T and a2.

Kernels gamma in {0, 0.5, 1, 2}, white noise (D = 1) and a Fokker-Planck bath
(xi = 1, D = 1), alpha in {0.3, 0.6, 0.9, 0.99}, plus the viscoelastic and threshold
laws at one setting; default numerical options (n = 1).  A solve that fails is listed
with its error.  For the Maxwell model (gamma = 0) the exact T and a2 of the closed
moment equations are printed beside the FEM values.

    python benchmarks/fem_model_table.py [out.csv] [--quick]
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import argparse  # noqa: E402
import csv  # noqa: E402
import time  # noqa: E402

import kinetic_fem as kf  # noqa: E402

GAMMAS = (0.0, 0.5, 1.0, 2.0)
ALPHAS = (0.3, 0.6, 0.9, 0.99)
THERMOSTATS = (("white noise", 0.0), ("bath xi=1", 1.0))
LAWS = (kf.ViscoelasticRestitution(0.2), kf.ThresholdRestitution(0.6, 0.5))


def maxwell_exact(alpha: float, friction: float) -> tuple[float, float]:
    """Closed moment equations of the Maxwell model (see tests/kinetic_fem/test_fem.py)."""
    a, b = 0.5 * (1 - alpha), 0.5 * (1 + alpha)
    t = 4.0 / (4 * friction + (1 - alpha**2))
    m4 = (12 * t + 6 * a * a * b * b * t * t) / (4 * friction + (1 - a**4 - b**4))
    return t, m4 / (3 * t * t) - 1


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("csv", nargs="?", help="write the table here")
    parser.add_argument("--quick", action="store_true", help="alpha in {0.6} only")
    args = parser.parse_args()
    alphas = (0.6,) if args.quick else ALPHAS
    cases = [(g, name, xi, a) for g in GAMMAS for name, xi in THERMOSTATS for a in alphas]
    cases += [(1.0, name, xi, law) for law in LAWS for name, xi in THERMOSTATS]
    rows = []
    print(f"{'gamma':>5} {'thermostat':>11} {'restitution':>42} {'T':>16} {'a2':>14} "
          f"{'n_dofs':>6} {'time/s':>7}  exact (Maxwell)")
    for gamma, name, xi, alpha in cases:
        t0 = time.perf_counter()
        try:
            dist = kf.solve_heated(alpha, kernel=gamma, friction=xi)
            row = {"gamma": gamma, "thermostat": name, "restitution": repr(alpha),
                   "T": dist.temperature, "a2": dist.a2,
                   "n_dofs": dist.info.extra["n_dofs"], "time": time.perf_counter() - t0,
                   "error": ""}
        except Exception as exc:  # noqa: BLE001 - the table lists failures
            row = {"gamma": gamma, "thermostat": name, "restitution": repr(alpha),
                   "T": float("nan"), "a2": float("nan"), "n_dofs": 0,
                   "time": time.perf_counter() - t0, "error": str(exc)[:120]}
        exact = ""
        if gamma == 0.0 and isinstance(alpha, float):
            t_ex, a2_ex = maxwell_exact(alpha, xi)
            exact = (f"T {t_ex:.12g} (rel {row['T'] / t_ex - 1:.1e}), a2 {a2_ex:.10f} "
                     f"(abs {row['a2'] - a2_ex:.1e})")
        rows.append(row)
        print(f"{gamma:5.1f} {name:>11} {row['restitution']:>42} {row['T']:16.12f} "
              f"{row['a2']:14.10f} {row['n_dofs']:6d} {row['time']:7.1f}  {exact}"
              f"{row['error']}", flush=True)
    if args.csv:
        with open(args.csv, "w", newline="") as handle:
            writer = csv.DictWriter(handle, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerows(rows)


if __name__ == "__main__":
    main()
