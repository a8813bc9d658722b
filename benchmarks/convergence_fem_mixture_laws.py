"""FEM heated states of mixtures with velocity-dependent restitution laws per pair.

1. Identical species: the mixture's FEM state against the one-species FEM state with the
   same law on the same mesh (P2, spacing 0.4; the viscoelastic law delta 0.1 and the
   threshold law 0.6 below |g| = 0.5; kernels 1 and 0.5): both are the reduced bracket
   of the same pair rule, so they agree to round-off.
2. Convergence: the default meshes refined (P2 and P3, spacing 0.5 ... 0.125) against
   P3 at spacing 0.0625, with the observed order (masses 1:3 with the viscoelastic law;
   masses 1:10 with a table mixing a viscoelastic, a constant and a threshold law).
3. FEM against the mixture DSMC (N = 2000, 300 collisions per rod after 30, seeds 1-4):
   z = (DSMC - FEM) / batch standard error over T_s and a2_s, five mixtures (two
   kernels, white noise of one D or of one power, a bath).
4. Cost: CPU time of the default binary state against the one-species state with the
   same law (best of 3 after a first call that compiles the kernels; the binary state's
   one-species start is then cached, as in a sweep at one law).

    OMP_NUM_THREADS=1 python benchmarks/convergence_fem_mixture_laws.py
"""

from __future__ import annotations

import math
import time
import warnings

import numpy as np
from yardstick import best_cpu

import kinetic_fem as kf
from kinetic_fem.exceptions import ResolutionWarning
from kinetic_fem.model import FokkerPlanckBath, ThresholdRestitution, ViscoelasticRestitution
from kinetic_fem.solvers.fem.grading import graded_vertices

VISCO = ViscoelasticRestitution(0.1)
THRESHOLD = ThresholdRestitution(0.6, 0.5)


def table_mixture() -> kf.Mixture:
    """Masses 1:10, x 0.3/0.7: viscoelastic (1-1), constant 0.8 (1-2), threshold (2-2)."""
    return kf.Mixture.white_noise((1.0, 10.0), (0.3, 0.7), alpha=[
        [VISCO, 0.8], [0.8, ThresholdRestitution(0.5, 1.0)]])


def identical() -> None:
    """Table 1."""
    print("## Identical species against one species with the law (same mesh, P2)\n")
    print("| law | gamma | T rel. | a2 abs. | f rel. (max) |")
    print("|---|---|---|---|---|")
    verts = 1.8 * graded_vertices(12.0, 0.4, grading=0.0)
    for law in (VISCO, THRESHOLD):
        for gamma in (1.0, 0.5):
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", ResolutionWarning)
                one = kf.solve_heated(law, kernel=gamma, vertices=verts, order=2)
                mix = kf.Mixture.white_noise((2.0, 2.0), (0.3, 0.7), alpha=law, kernel=gamma)
                state = kf.solve_heated(mix, vertices=verts, order=2)
            e_t = float(np.max(np.abs(state.temperatures / 2.0 / one.temperature - 1.0)))
            e_a = float(np.max(np.abs(state.a2 - one.a2)))
            e_f = max(float(np.max(np.abs(d.values / one.values - 1.0)))
                      for d in state.distributions)
            print(f"| {law!r} | {gamma} | {e_t:.1e} | {e_a:.1e} | {e_f:.1e} |", flush=True)


def convergence() -> None:
    """Table 2."""
    cases = {"viscoelastic, m 1:3": kf.Mixture.white_noise((1.0, 3.0), (0.5, 0.5),
                                                           alpha=VISCO),
             "law table, m 1:10": table_mixture()}
    print("\n## Convergence against P3, spacing 0.0625\n")
    print("| mixture | P | spacing | dofs | T_s rel. error | order | a2_s abs. error | order "
          "| CPU s |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, mix in cases.items():
        ref = kf.solve_heated(mix, order=3, spacing=0.0625)
        for order in (2, 3):
            last = None
            for spacing in (0.5, 0.25, 0.125):
                cpu = time.process_time()
                try:
                    state = kf.solve_heated(mix, order=order, spacing=spacing)
                except kf.exceptions.ConvergenceError:
                    print(f"| {name} | {order} | {spacing} | - | Newton failed | | | | |")
                    last = None
                    continue
                cpu = time.process_time() - cpu
                e_t = float(np.max(np.abs(state.temperatures / ref.temperatures - 1.0)))
                e_a = float(np.max(np.abs(state.a2 - ref.a2)))
                rates = ["", ""]
                if last is not None:
                    rates = [f"{math.log2(p / e):.1f}" for p, e in zip(last, (e_t, e_a),
                                                                       strict=True)]
                last = (e_t, e_a)
                print(f"| {name} | {order} | {spacing} | {sum(state.info.extra['n_dofs'])} | "
                      f"{e_t:.2e} | {rates[0]} | {e_a:.2e} | {rates[1]} | {cpu:.2f} |",
                      flush=True)


def dsmc(seeds: tuple[int, ...] = (1, 2, 3, 4)) -> None:
    """Table 3."""
    from particles.dsmc_mixture import simulate_mixture

    bath = (FokkerPlanckBath(1.0, 1.0), FokkerPlanckBath(1.0, 1.0))
    cases = {
        "viscoelastic 0.1, m 1:3": kf.Mixture.white_noise((1.0, 3.0), (0.5, 0.5),
                                                          alpha=VISCO),
        "threshold 0.6/0.5, m 1:3, same power": kf.Mixture.white_noise(
            (1.0, 3.0), (0.5, 0.5), alpha=THRESHOLD, convention="same_power"),
        "law table, m 1:10, x 0.3/0.7": table_mixture(),
        "viscoelastic 0.2, m 1:4, bath": kf.Mixture((1.0, 4.0), (0.5, 0.5),
                                                    alpha=ViscoelasticRestitution(0.2),
                                                    thermostats=bath),
        "viscoelastic 0.15, gamma 0.5, m 1:2, x 0.4/0.6": kf.Mixture.white_noise(
            (1.0, 2.0), (0.4, 0.6), alpha=ViscoelasticRestitution(0.15), kernel=0.5),
    }
    print("\n## FEM against the mixture DSMC (N = 2000, 300 collisions per rod)\n")
    print("| mixture | FEM T_1, T_2 | FEM T_1/T_2 | FEM a2_1, a2_2 | max abs z | rms z |")
    print("|---|---|---|---|---|---|")
    for name, mix in cases.items():
        state = kf.solve_heated(mix)
        zs = []
        for seed in seeds:
            run = simulate_mixture(mix, 2000, seed=seed, collisions_per_particle=300, relax=30)
            zs.append(np.concatenate([
                (run.temperatures - state.temperatures) / run.temperature_errors,
                (run.a2 - state.a2) / run.a2_errors]))
        z = np.array(zs)
        t1, t2 = state.temperatures
        a1, a2 = state.a2
        print(f"| {name} | {t1:.6f}, {t2:.6f} | {state.temperature_ratio():.6f} | "
              f"{a1:.5f}, {a2:.5f} | {np.max(np.abs(z)):.2f} | "
              f"{math.sqrt(float(np.mean(z**2))):.2f} |", flush=True)


def cost(repeats: int = 3) -> None:
    """Table 4."""
    print("\n## CPU time: default binary state against one species with the same law\n")
    print("| law | one species s | binary m 1:3 s | ratio |")
    print("|---|---|---|---|")
    for law in (VISCO, THRESHOLD):
        mix = kf.Mixture.white_noise((1.0, 3.0), (0.5, 0.5), alpha=law)
        kf.solve_heated(law), kf.solve_heated(mix)  # compile
        one_t, _ = best_cpu(lambda a=law: kf.solve_heated(a), repeats)
        mix_t, _ = best_cpu(lambda m=mix: kf.solve_heated(m), repeats)
        print(f"| {law!r} | {one_t:.3f} | {mix_t:.3f} | {mix_t / one_t:.2f} |", flush=True)


def main() -> None:
    identical()
    convergence()
    dsmc()
    cost()


if __name__ == "__main__":
    main()
