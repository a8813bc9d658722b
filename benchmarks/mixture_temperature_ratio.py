"""T1/T2 of hard-rod binary mixtures: Gaussian and first-order Sonine theory against DSMC.

Equal fractions, alpha 0.5 and 0.9, mass ratios 0.1 ... 10, white noise under both forcing
conventions and free cooling; DSMC N = 2000, 400 collisions per rod after 50, seed 11.
Prints a markdown table (benchmarks/results/mixture_temperature_ratio.md).

    python benchmarks/mixture_temperature_ratio.py
"""

from __future__ import annotations

from kinetic_fem.model.mixture import Mixture
from kinetic_fem.solvers import mixture_gaussian, mixture_sonine
from particles.dsmc_mixture import simulate_mixture


def row(convention: str | None, alpha: float, mass_ratio: float) -> str:
    """One table row: the Gaussian, Sonine and DSMC ratios, Sonine and DSMC kurtosis."""
    masses, fractions = (1.0, mass_ratio), (0.5, 0.5)
    if convention is None:
        mix = Mixture(masses, fractions, alpha=alpha, kernel=1.0)
        gauss = mixture_gaussian.cooling_state(mix)
        sonine = mixture_sonine.cooling_state(mix)
    else:
        mix = Mixture.white_noise(masses, fractions, alpha=alpha, kernel=1.0,
                                  convention=convention)
        gauss = mixture_gaussian.steady_state(mix)
        sonine = mixture_sonine.steady_state(mix)
    run = simulate_mixture(mix, 2000, seed=11, collisions_per_particle=400, relax=50)
    rg, rs = gauss.temperature_ratio(), sonine.temperature_ratio()
    rd, err = run.temperature_ratio(), run.temperature_ratio_error()
    return (f"| {convention or 'cooling'} | {alpha} | {mass_ratio:.3g} | {rg:.5f} | {rs:.5f} | "
            f"{rd:.5f} +- {err:.5f} | {rd / rg - 1:+.4f} | {rd / rs - 1:+.4f} | "
            f"{sonine.a2[0]:.4f}, {sonine.a2[1]:.4f} | {run.a2[0]:.4f}, "
            f"{run.a2[1]:.4f} +- {run.a2_errors.max():.4f} |")


def main() -> None:
    """Print the table."""
    print("| thermostat | alpha | m2/m1 | T1/T2 Gaussian | T1/T2 Sonine | T1/T2 DSMC | "
          "DSMC/Gaussian - 1 | DSMC/Sonine - 1 | a2_1, a2_2 Sonine | a2_1, a2_2 DSMC |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for convention in ("same_diffusion", "same_power", None):
        for alpha in (0.5, 0.9):
            for mass_ratio in (0.1, 1.0 / 3.0, 3.0, 10.0):
                print(row(convention, alpha, mass_ratio), flush=True)


if __name__ == "__main__":
    main()
