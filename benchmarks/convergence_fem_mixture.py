"""The FEM states of a binary mixture: mesh convergence, cost against one species, Sonine.

1. Convergence: the inelastic Maxwell mixture (kernel 0; m = 1, 3; x = 0.3, 0.7;
   alpha_11 = 0.5, alpha_12 = 0.7, alpha_22 = 0.9; white noise D = 1) against its exact
   moment equations (kinetic_fem.solvers.maxwell_mixture): errors of T_s (relative) and
   a2_s (absolute) over the bulk spacing, P2 and P3, with the observed order; the cooling
   state's temperature ratio and cooling rate at P3.
2. Cost: CPU time of a binary FEM state against a one-species state at the same accuracy
   (hard rods, alpha = 0.7, P3, the same spacing in thermal velocities: equal masses and
   alphas, so the accuracy is the one-species one), and for a real mixture (m 1:3).
3. FEM against first-order Sonine (kinetic_fem.solvers.mixture_sonine), hard rods, equal
   fractions, alpha 0.5 and 0.9, mass ratios 0.1 ... 10, both forcing conventions: where
   Sonine is off by > 1 % (the ratio, or a2 by more than 0.01 absolute).

Run with one BLAS thread (``OMP_NUM_THREADS=1``: threaded BLAS spins on a loaded machine
and its LU of a 152 x 152 matrix measured 60 ms CPU instead of 0.4 ms).

    OMP_NUM_THREADS=1 python benchmarks/convergence_fem_mixture.py
"""

from __future__ import annotations

import math
import time
import warnings

import numpy as np
from yardstick import best_cpu

import kinetic_fem as kf
from kinetic_fem.exceptions import ResolutionWarning
from kinetic_fem.solvers import maxwell_mixture, mixture_sonine


def maxwell_mixture_model(cooling: bool) -> kf.Mixture:
    """The Maxwell mixture of the module text."""
    alpha = [[0.5, 0.7], [0.7, 0.9]]
    if cooling:
        return kf.Mixture((1.0, 3.0), (0.3, 0.7), alpha=alpha, kernel=0.0)
    return kf.Mixture.white_noise((1.0, 3.0), (0.3, 0.7), alpha=alpha, kernel=0.0)


def convergence() -> None:
    """Table 1."""
    mix = maxwell_mixture_model(False)
    exact = maxwell_mixture.steady_state(mix)
    print("## Heated Maxwell mixture against the exact moments\n")
    print("| P | spacing | dofs | T_s rel. error | order | a2_s abs. error | order | CPU s |")
    print("|---|---|---|---|---|---|---|---|")
    for order in (2, 3):
        last = None
        for spacing in (1.0, 0.5, 0.25, 0.125):
            cpu = time.process_time()
            try:
                state = kf.solve_heated(mix, order=order, spacing=spacing)
            except kf.exceptions.ConvergenceError as err:
                print(f"| {order} | {spacing} | - | Newton failed: {str(err)[-60:]} | | | | |")
                continue
            cpu = time.process_time() - cpu
            e_t = float(np.max(np.abs(state.temperatures / exact.temperatures - 1.0)))
            e_a = float(np.max(np.abs(state.a2 - exact.a2)))
            rates = ["", ""]
            if last is not None:
                rates = [f"{math.log(p / e) / math.log(2.0):.1f}" if e > 0 and p > 0 else ""
                         for p, e in zip(last, (e_t, e_a), strict=True)]
            last = (e_t, e_a)
            print(f"| {order} | {spacing} | {sum(state.info.extra['n_dofs'])} | {e_t:.2e} | "
                  f"{rates[0]} | {e_a:.2e} | {rates[1]} | {cpu:.2f} |", flush=True)
    mix = maxwell_mixture_model(True)
    exact = maxwell_mixture.cooling_state(mix)
    print("\n## Cooling Maxwell mixture: temperature ratio and cooling rate\n")
    print(f"exact: T1/T2 = {exact.temperature_ratio():.12f}, zeta = {exact.zeta:.12f}\n")
    print("| P | spacing | dofs | T1/T2 rel. error | zeta rel. error | CPU s |")
    print("|---|---|---|---|---|---|")
    for spacing in (1.0, 0.5):
        cpu = time.process_time()
        try:
            state = kf.solve_cooling(mix, spacing=spacing)
        except kf.exceptions.ConvergenceError as err:
            print(f"| 3 | {spacing} | - | failed: {str(err)[:80]} | | |")
            continue
        cpu = time.process_time() - cpu
        e_r = abs(state.temperature_ratio() / exact.temperature_ratio() - 1.0)
        assert state.zeta is not None
        e_z = abs(state.zeta / exact.zeta - 1.0)
        print(f"| 3 | {spacing} | {sum(state.info.extra['n_dofs'])} | {e_r:.2e} | {e_z:.2e} | "
              f"{cpu:.2f} |", flush=True)


def cost(repeats: int = 3) -> None:
    """Table 2."""
    print("\n## CPU time: binary FEM state against one species (hard rods, P3)\n")
    print("| state | spacing | dofs | CPU s (best of 3) | ratio to one species | T error vs "
          "one species |")
    print("|---|---|---|---|---|---|")
    for spacing in (0.5, 0.25):
        one_t, one = best_cpu(lambda h=spacing: kf.solve_heated(0.7, order=3, spacing=h), repeats)
        print(f"| one species | {spacing} | {one.info.extra['n_dofs']} | {one_t:.3f} | 1 | |")
        same = kf.Mixture.white_noise((1.0, 1.0), (0.5, 0.5), alpha=0.7)
        mix_t, state = best_cpu(lambda m=same, h=spacing: kf.solve_heated(m, order=3, spacing=h),
                              repeats)
        err = float(np.max(np.abs(state.temperatures / one.temperature - 1.0)))
        print(f"| binary, identical species | {spacing} | {state.info.extra['n_dofs']} | "
              f"{mix_t:.3f} | {mix_t / one_t:.2f} | {err:.1e} |")
        real = kf.Mixture.white_noise((1.0, 3.0), (0.5, 0.5), alpha=0.7)
        mix_t, state = best_cpu(lambda m=real, h=spacing: kf.solve_heated(m, order=3, spacing=h),
                              repeats)
        print(f"| binary, m 1:3 | {spacing} | {state.info.extra['n_dofs']} | {mix_t:.3f} | "
              f"{mix_t / one_t:.2f} | |", flush=True)
    cool = kf.Mixture((1.0, 1.0), (0.5, 0.5), alpha=0.7)
    one_t, one = best_cpu(lambda: kf.solve_cooling(0.7), repeats)
    mix_t, state = best_cpu(lambda: kf.solve_cooling(cool, spacing=0.25), repeats)
    err = abs(state.zeta / one.info.extra["zeta"] - 1.0)
    print(f"| cooling: one species (default) / binary identical (P3, 0.25) | | "
          f"{one.info.extra['n_dofs']} / {state.info.extra['n_dofs']} | {one_t:.3f} / "
          f"{mix_t:.3f} | {mix_t / one_t:.2f} | zeta {err:.1e} |")



def sonine() -> None:
    """Table 3."""
    print("\n## FEM against first-order Sonine (hard rods, x = 0.5, 0.5)\n")
    print("| thermostat | alpha | m2/m1 | T1/T2 FEM | T1/T2 Sonine | Sonine/FEM - 1 | "
          "a2_1, a2_2 FEM | a2_1, a2_2 Sonine | off > 1 % |")
    print("|---|---|---|---|---|---|---|---|---|")
    for convention in ("same_diffusion", "same_power"):
        for alpha in (0.5, 0.9):
            for ratio in (0.1, 1.0 / 3.0, 3.0, 10.0):
                masses = (1.0, ratio)
                try:
                    if convention is None:
                        mix = kf.Mixture(masses, (0.5, 0.5), alpha=alpha)
                        fem = kf.solve_cooling(mix)
                        son = mixture_sonine.cooling_state(mix)
                    else:
                        mix = kf.Mixture.white_noise(masses, (0.5, 0.5), alpha=alpha,
                                                     convention=convention)
                        fem = kf.solve_heated(mix)
                        son = mixture_sonine.steady_state(mix)
                except kf.exceptions.ConvergenceError as err:
                    print(f"| {convention or 'cooling'} | {alpha} | {ratio:.3g} | failed: "
                          f"{str(err)[:60]} | | | | | |", flush=True)
                    continue
                rf, rs = fem.temperature_ratio(), son.temperature_ratio()
                off = abs(rs / rf - 1.0) > 0.01 or np.any(np.abs(son.a2 - fem.a2) > 0.01)
                print(f"| {convention or 'cooling'} | {alpha} | {ratio:.3g} | {rf:.8f} | "
                      f"{rs:.6f} | {rs / rf - 1:+.2e} | {fem.a2[0]:.5f}, {fem.a2[1]:.5f} | "
                      f"{son.a2[0]:.5f}, {son.a2[1]:.5f} | {'yes' if off else ''} |",
                      flush=True)


def main() -> None:
    """Print the three tables."""
    warnings.simplefilter("ignore", ResolutionWarning)
    convergence()
    cost()
    sonine()


if __name__ == "__main__":
    main()
