"""Sweeps of mixtures: kf.sweep over mass ratio, fraction and alpha with T_1/T_2 in the
Dataset (kinetic_fem.mixture_solve.solve_binary, particles.dsmc_mixture.simulate_binary),
and a stored sweep reloads the species variables."""

import numpy as np
import pytest

import kinetic_fem as kf
from kinetic_fem.mixture_solve import binary_mixture, solve_binary, solve_mixture
from kinetic_fem.solvers import mixture_sonine


def test_sweep_over_mass_ratio_fraction_alpha_holds_the_temperature_ratio(tmp_path):
    grid = {"mass_ratio": [1.0, 4.0], "fraction": [0.3, 0.5], "alpha": [0.6]}
    ds = kf.sweep(solve_binary, grid, forcing="same_power", executor="serial",
                  store=tmp_path / "s")
    assert ds.T_ratio.dims == ("mass_ratio", "fraction", "alpha")
    assert ds.T_species.dims == ("mass_ratio", "fraction", "alpha", "species")
    mix = binary_mixture(4.0, fraction=0.3, alpha=0.6, forcing="same_power")
    ref = mixture_sonine.steady_state(mix)
    point = ds.sel(mass_ratio=4.0, fraction=0.3, alpha=0.6)
    assert float(point.T_ratio) == ref.temperature_ratio()
    assert np.array_equal(point.T_species.values, ref.temperatures)
    assert np.array_equal(point.a2_species.values, ref.a2)
    assert np.all(ds.T_ratio.sel(mass_ratio=1.0) == 1.0)
    again = kf.sweep(solve_binary, grid, forcing="same_power", executor="serial",
                     store=tmp_path / "s")
    assert again.T_ratio.equals(ds.T_ratio) and again.a2_species.equals(ds.a2_species)


def test_sweep_of_particle_mixture_runs_has_standard_errors():
    from particles.dsmc_mixture import simulate_binary

    ds = kf.sweep(simulate_binary, {"mass_ratio": [1.0, 4.0]}, n_particles=200,
                  forcing="cooling", alpha=0.7, collisions_per_particle=20.0, relax=5.0,
                  seed=1, executor="serial")
    assert np.all(ds.T_ratio_error > 0) and np.all(ds.zeta > 0)
    assert ds.method == "dsmc-mixture"


def test_binary_mixture_bad_input_names_the_argument():
    with pytest.raises(ValueError, match="mass_ratio"):
        binary_mixture(0.0)
    with pytest.raises(ValueError, match="fraction"):
        binary_mixture(2.0, fraction=1.0)
    with pytest.raises(ValueError, match="forcing"):
        binary_mixture(2.0, forcing="same_temperature")
    with pytest.raises(ValueError, match="method"):
        solve_mixture(binary_mixture(2.0), method="fem-typo")


def test_sweep_with_the_fem_method_matches_the_exact_maxwell_mixture():
    """method="fem" (the FEM heated state at its default mesh) in a sweep: the Maxwell
    mixture (kernel 0, m 1:3, x 0.3, alpha_22 0.9, same_power) against the exact moments
    (measured T_s 5.5e-14, a2_s 7.8e-10; 1.1 s)."""
    options = {"fraction": 0.3, "alpha": 0.7, "alpha_22": 0.9, "kernel": 0.0,
               "forcing": "same_power"}
    ds = kf.sweep(solve_binary, {"mass_ratio": [3.0]}, method="fem", executor="serial",
                  **options)
    exact = solve_binary(3.0, method="maxwell", **options)
    point = ds.sel(mass_ratio=3.0)
    np.testing.assert_allclose(point.T_species.values, exact.temperatures, rtol=5e-13)
    np.testing.assert_allclose(point.a2_species.values, exact.a2, rtol=0, atol=3e-9)
