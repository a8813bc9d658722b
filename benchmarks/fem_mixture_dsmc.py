"""FEM states of binary mixtures against DSMC (particles.dsmc_mixture.simulate_mixture).

Hard rods; white noise under both forcing conventions and free cooling; mass ratios up to
10.  For each mixture: T_s, a2_s (and zeta in free cooling) by FEM (default mesh, P3)
and by DSMC (N = 4000 rods, 300 collisions per rod after 50, batch error bars; seeds 5, 6, 7),
with z = (DSMC - FEM)/error.  Prints a markdown table
(benchmarks/results/fem_mixture_dsmc.md).

    OMP_NUM_THREADS=1 python benchmarks/fem_mixture_dsmc.py [case indices]
"""

from __future__ import annotations

import sys
import time
import warnings

import kinetic_fem as kf
from kinetic_fem.exceptions import ResolutionWarning
from kinetic_fem.mixture_state import MixtureState
from particles.dsmc_mixture import simulate_mixture

CASES = (
    ("same_diffusion", (1.0, 10.0), (0.5, 0.5), 0.7),
    ("same_power", (1.0, 10.0), (0.5, 0.5), 0.7),
    ("same_diffusion", (1.0, 3.0), (0.3, 0.7), [[0.5, 0.7], [0.7, 0.9]]),
    ("same_power", (1.0, 0.1), (0.5, 0.5), 0.9),
    (None, (1.0, 10.0), (0.3, 0.7), 0.8),
    (None, (1.0, 2.0), (0.5, 0.5), 0.6),
)


def main(seeds: tuple[int, ...] = (5, 6, 7), cases: tuple[int, ...] | None = None) -> None:
    """Print the table (of the cases with the given indices; default all), one DSMC run
    per seed."""
    warnings.simplefilter("ignore", ResolutionWarning)
    print("| thermostat | masses | fractions | alpha | quantity | FEM | seed | DSMC | z |")
    print("|---|---|---|---|---|---|---|---|---|")
    for index, (convention, masses, fractions, alpha) in enumerate(CASES):
        if cases is not None and index not in cases:
            continue
        cpu = time.process_time()
        if convention is None:
            mix = kf.Mixture(masses, fractions, alpha=alpha)
            try:
                fem = kf.solve_cooling(mix)
            except kf.exceptions.ConvergenceError as err:
                print(f"| cooling | {masses} | {fractions} | {alpha} | FEM failed: "
                      f"{str(err)[:60]} | | | |", flush=True)
                continue
        else:
            mix = kf.Mixture.white_noise(masses, fractions, alpha=alpha, convention=convention)
            fem = kf.solve_heated(mix)
        print(f"<!-- CPU: FEM {time.process_time() - cpu:.1f} s -->", flush=True)
        for seed in seeds:
            _compare(mix, fem, convention, masses, fractions, alpha, seed)


def _compare(mix: kf.Mixture, fem: MixtureState, convention: str | None, masses: tuple,
             fractions: tuple, alpha: object, seed: int) -> None:
    """Print the rows of one DSMC run against the FEM state."""
    cpu = time.process_time()
    run = simulate_mixture(mix, 4000, seed=seed, collisions_per_particle=300, relax=50)
    print(f"<!-- CPU: DSMC {time.process_time() - cpu:.1f} s -->", flush=True)
    rows = []
    for s in range(2):
        rows.append((f"T_{s + 1}", fem.temperatures[s], run.temperatures[s],
                     run.temperature_errors[s]))
        rows.append((f"a2_{s + 1}", fem.a2[s], run.a2[s], run.a2_errors[s]))
    if convention is None:
        assert fem.zeta is not None and run.zeta is not None
        rows.append(("zeta", fem.zeta, run.zeta, run.zeta_error))
    for name, value, sample, error in rows:
        print(f"| {convention or 'cooling'} | {masses} | {fractions} | {alpha} | {name} | "
              f"{value:.6f} | {seed} | {sample:.5f} +- {error:.5f} | "
              f"{(sample - value) / error:+.2f} |", flush=True)


if __name__ == "__main__":
    main(cases=tuple(int(a) for a in sys.argv[1:]) or None)
