"""Convergence in the order P of the mixture's Sonine Galerkin solver towards the FEM mixture.

A binary mixture of hard rods (species 1 of mass 1, species 2 of mass ``--mass-ratio``,
equal fractions, one ``--alpha`` for every pair, white noise with the same D for both:
``same_diffusion``) is solved by the FEM mixture solver
(:mod:`kinetic_fem.solvers.fem.mixture`) at two spacings (the difference is its own
error) and by :mod:`kinetic_fem.solvers.mixture_spectral` at ``P = 2 .. --max-order``;
the table gives ``|T_s - T_fem|`` and ``|a2_s - a2_fem|`` of both species and the CPU time
of each order.  ``--cooling`` does the homogeneous cooling state (then with zeta).

    python benchmarks/convergence_mixture_spectral.py [--mass-ratio 3] [--alpha 0.7]
    python benchmarks/convergence_mixture_spectral.py --cooling --max-order 12

Measured (mass ratio 3, alpha 0.7, heated; FEM spacings 0.1 and 0.05 agree to 3e-12):
|T - T_fem| 3.9e-3 (P = 2), 3.3e-4 (4), 4.2e-6 (8), 1.3e-7 (12), the odd orders a little
better than the next even one; a2 alike (9.0e-8 at P = 12).  The cooling state's series
is asymptotic (as for one species, whose hard-rod HCS the identical-species mixture
reproduces): same mixture, best at P = 5 (|T_s - T_fem| 3.7e-4, |zeta - zeta_fem|
1.4e-4), growing from P = 6 on (2.4e-2 at P = 11), no solution at P = 12; identical
species (mass ratio 1) best at P = 8 (a2 1.7e-3, zeta 1.0e-4).
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from kinetic_fem.mixture_solve import binary_mixture
from kinetic_fem.solvers import mixture_spectral
from kinetic_fem.solvers.fem.mixture import solve_mixture_cooling, solve_mixture_heated


def main(mass_ratio: float = 3.0, alpha: float = 0.7, max_order: int = 12,
         cooling: bool = False) -> list[tuple[int, float, float, float]]:
    """Print the table; return ``(P, max |dT|, max |da2|, |dzeta| or nan)`` per order."""
    mix = binary_mixture(mass_ratio, alpha=alpha,
                         forcing="cooling" if cooling else "same_diffusion")
    fem_solve = solve_mixture_cooling if cooling else solve_mixture_heated
    states = []
    for spacing in (0.1, 0.05):
        start = time.process_time()
        states.append(fem_solve(mix, spacing=spacing))
        temps = np.array2string(states[-1].temperatures, precision=12)
        print(f"FEM spacing {spacing}: T_s = {temps}"
              f", a2_s = {np.array2string(states[-1].a2, precision=12)}"
              + ("" if not cooling else f", zeta = {states[-1].zeta:.12f}")
              + f"  ({time.process_time() - start:.1f} s CPU)")
    fem = states[-1]
    print(f"FEM self-difference: T {np.max(np.abs(states[0].temperatures - fem.temperatures)):.1e}"
          f", a2 {np.max(np.abs(states[0].a2 - fem.a2)):.1e}")
    solve = mixture_spectral.cooling_state if cooling else mixture_spectral.steady_state
    print(f"{'P':>3} {'|T_1-T_fem|':>12} {'|T_2-T_fem|':>12} {'|a2_1-fem|':>12} "
          f"{'|a2_2-fem|':>12} {'|zeta-fem|':>11} {'CPU s':>7}")
    rows = []
    for order in range(2, max_order + 1):
        start = time.process_time()
        try:
            state = solve(mix, order=order)
        except RuntimeError as err:
            print(f"{order:3d} no solution: {err}")
            break
        cpu = time.process_time() - start
        dt = np.abs(state.temperatures - fem.temperatures)
        da = np.abs(state.a2 - fem.a2)
        dz = abs(state.zeta - fem.zeta) if cooling else float("nan")
        print(f"{order:3d} {dt[0]:12.2e} {dt[1]:12.2e} {da[0]:12.2e} {da[1]:12.2e} "
              f"{dz:11.2e} {cpu:7.3f}")
        rows.append((order, float(dt.max()), float(da.max()), dz))
    return rows


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--mass-ratio", type=float, default=3.0)
    parser.add_argument("--alpha", type=float, default=0.7)
    parser.add_argument("--max-order", type=int, default=12)
    parser.add_argument("--cooling", action="store_true")
    args = parser.parse_args()
    main(args.mass_ratio, args.alpha, args.max_order, args.cooling)
