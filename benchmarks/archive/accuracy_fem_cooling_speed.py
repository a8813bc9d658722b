"""Accuracy of the faster default cooling states (issue 16, seventh round) near elastic.

For each inelasticity eps < 0.1 (hard rods): the default state of ``kf.solve_cooling``
(P3 on the moderate mesh for eps in [0.04, 0.1), P3 at 0.2 hump widths below), the former
default (P2 at 0.07 hump widths, ``resolution=0.07``) and two references solved from the
default state at the same eps: P2 at 0.035 hump widths and P3 at 0.1 hump widths (both
Gauss degree 9).  Errors: zeta relative, a2 absolute, ln f where f_ref > 1e-30 (max over
40001 points of the common interval).

    python benchmarks/accuracy_fem_cooling_speed.py [--eps 0.05 1e-2 1e-3]

Prints a markdown table (``benchmarks/archive/results/fem_cooling_speed.md``).
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "NUMBA_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import math  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from kinetic_fem.model import CoolingProblem  # noqa: E402
from kinetic_fem.solvers import fem_cooling as fc  # noqa: E402

FLOOR = math.log(1e-30)
EPS = [0.07, 0.05, 0.04, 0.03, 0.02, 1e-2, 3e-3, 1e-3, 1e-4]


def errors(state: fc.CoolingState, ref: fc.CoolingState) -> tuple[float, float, float]:
    """(|zeta/zeta_ref - 1|, |a2 - a2_ref|, max |ln f - ln f_ref| where f_ref > 1e-30)."""
    c_max = 0.99 * min(state.disc.vertices[-1], ref.disc.vertices[-1])
    c = np.linspace(0.0, c_max, 40001)
    lr = ref.log_f(c)
    keep = lr > FLOOR
    a2 = state.disc.distribution(state.u).a2
    a2_ref = ref.disc.distribution(ref.u).a2
    return (abs(state.zeta / ref.zeta - 1.0), abs(a2 - a2_ref),
            float(np.abs(state.log_f(c)[keep] - lr[keep]).max()))


def row(eps: float) -> list[str]:
    problem = CoolingProblem.from_parameters(1.0 - eps)
    t0 = time.process_time()
    new = fc.cooling_state(problem)
    t_new = time.process_time() - t0
    t0 = time.process_time()
    old = fc.cooling_state(problem, resolution=fc.HUMP_RESOLUTION)
    t_old = time.process_time() - t0
    refs = [fc.continued_state(new, eps, eps, resolution=0.035),
            fc.continued_state(new, eps, eps, resolution=0.1, order=3)]
    lines = []
    for name, st, t in (("new default", new, t_new), ("P2 0.07 (former)", old, t_old)):
        errs = [errors(st, ref) for ref in refs]
        lines.append(f"| {eps:g} | {name} | P{st.disc.order} | {st.u.size} | {t:.2f} | "
                     + " | ".join(f"{e[k]:.1e}" for k in range(3) for e in errs) + " |")
    between = errors(refs[1], refs[0])
    lines.append(f"| {eps:g} | P3 0.1 vs P2 0.035 | | | | " + " | ".join(
        f"{between[k]:.1e} | " for k in range(3)) + " |")
    return lines


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--eps", type=float, nargs="*", default=EPS)
    args = parser.parse_args()
    print("| eps | state | order | dofs | CPU s | dzeta (P2 0.035) | dzeta (P3 0.1) | "
          "da2 (P2 0.035) | da2 (P3 0.1) | d ln f (P2 0.035) | d ln f (P3 0.1) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for eps in args.eps:
        for line in row(eps):
            print(line, flush=True)


if __name__ == "__main__":
    main()
