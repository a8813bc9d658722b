"""The Sonine Galerkin solver of a mixture (kinetic_fem.solvers.mixture_spectral).

Checks that could fail: a mixture of identical species is the one-species Galerkin system
(kinetic_fem.solvers.spectral), so T, a2 and every a_p agree to round-off; for the
Maxwell kernel the equation of order q holds the moments up to 2q only, so every order
P >= 2 gives the exact T_s and a2_s (heated) and temperature ratio and cooling rate
(cooling) of kinetic_fem.solvers.maxwell_mixture; at P = 2 first-order Sonine theory
(kinetic_fem.solvers.mixture_sonine) is the same truncation but linear in the a2_s: equal
for the Maxwell kernel (its products multiply no moment of the balances), apart by
O(a2^2) otherwise; hard rods converge in P to the FEM mixture (slow).
"""

import numpy as np
import pytest

from kinetic_fem.mixture_solve import binary_mixture, solve_binary
from kinetic_fem.model import (
    FokkerPlanckBath,
    Mixture,
    SaturatingKernel,
    ThresholdRestitution,
    UnsupportedModelError,
)
from kinetic_fem.solvers import maxwell_mixture as mm
from kinetic_fem.solvers import mixture_sonine as so
from kinetic_fem.solvers import mixture_spectral as ms
from kinetic_fem.solvers.spectral import solve_sonine, solve_sonine_cooling

ALPHA = [[0.6, 0.7], [0.7, 0.9]]


@pytest.mark.parametrize("order", [2, 5, 8])
@pytest.mark.parametrize("gamma", [0.5, 1.0])
def test_identical_species_heated_are_the_one_species_solution(order, gamma):
    mix = Mixture((1.0, 1.0), (0.3, 0.7), alpha=0.7, kernel=gamma,
                  thermostats=(FokkerPlanckBath(0.4, 0.8),) * 2)
    state = ms.steady_state(mix, order=order, density=1.3)
    one = solve_sonine(0.7, order=order, density=1.3, diffusion=0.8, friction=0.4,
                       kernel=gamma)
    np.testing.assert_allclose(state.temperatures, one.temperature, rtol=1e-13, atol=0)
    np.testing.assert_allclose(state.a2, one.coefficients[2], rtol=0, atol=1e-13)
    for coefficients in state.info["sonine"]:
        np.testing.assert_allclose(coefficients, one.coefficients, rtol=0, atol=1e-13)


@pytest.mark.parametrize("order", [2, 6])
def test_identical_species_cooling_are_the_one_species_solution(order):
    mix = Mixture((2.0, 2.0), (0.5, 0.5), alpha=0.6, kernel=1.0)
    state = ms.cooling_state(mix, order=order)
    one, zeta = solve_sonine_cooling(0.6, order=order)
    np.testing.assert_allclose(state.temperatures, 1.0, rtol=1e-14, atol=0)
    # T_s = m <v^2> = 1 with m = 2: thermal speed 1/sqrt(2), rate zeta |g|^gamma scaled
    np.testing.assert_allclose(state.zeta, zeta * 2.0**-0.5, rtol=1e-13)
    for coefficients in state.info["sonine"]:
        np.testing.assert_allclose(coefficients, one.coefficients, rtol=0, atol=1e-13)


@pytest.mark.parametrize("order", [2, 3, 4, 8, 12])
@pytest.mark.parametrize("convention", ["same_diffusion", "same_power"])
def test_maxwell_mixture_heated_is_exact_at_every_order(order, convention):
    mix = Mixture.white_noise((1.0, 3.0), (0.3, 0.7), alpha=ALPHA, kernel=0.0,
                              convention=convention)
    state, exact = ms.steady_state(mix, order=order, density=1.4), mm.steady_state(
        mix, density=1.4)
    np.testing.assert_allclose(state.temperatures, exact.temperatures, rtol=1e-10)
    np.testing.assert_allclose(state.a2, exact.a2, rtol=0, atol=1e-10)


@pytest.mark.parametrize("order", [2, 3, 4, 6, 8])
def test_maxwell_mixture_cooling_ratio_and_rate_are_exact_at_every_order(order):
    """Measured worst 8.6e-12 (P = 7); beyond P = 8 the round-off of the pair rules times
    the growing coefficients (|a_P| ~ 1e4 at P = 12, the tail of the Maxwell cooling
    state) reaches 1.3e-9 at P = 12."""
    mix = Mixture((1.0, 3.0), (0.3, 0.7), alpha=ALPHA, kernel=0.0)
    state, exact = ms.cooling_state(mix, order=order), mm.cooling_state(mix)
    assert abs(state.temperature_ratio() / exact.temperature_ratio() - 1.0) < 1e-10
    assert abs(state.zeta / exact.zeta - 1.0) < 1e-10
    np.testing.assert_allclose(state.temperature, 1.0, rtol=1e-14)


def test_three_species_with_baths_maxwell_exact():
    mix = Mixture((1.0, 2.0, 5.0), (0.2, 0.3, 0.5),
                  alpha=[[0.5, 0.6, 0.7], [0.6, 0.8, 0.9], [0.7, 0.9, 0.95]], kernel=0.0,
                  thermostats=(FokkerPlanckBath(0.5, 1.0), FokkerPlanckBath(1.0, 2.0),
                               FokkerPlanckBath(0.3, 1.0)))
    state, exact = ms.steady_state(mix, order=5, density=0.8), mm.steady_state(mix,
                                                                               density=0.8)
    np.testing.assert_allclose(state.temperatures, exact.temperatures, rtol=1e-12)
    np.testing.assert_allclose(state.a2, exact.a2, rtol=0, atol=1e-12)


@pytest.mark.parametrize("heated", [True, False])
def test_order_two_is_first_order_sonine_where_the_truncations_coincide(heated):
    def mixture(kernel):
        if heated:
            return Mixture.white_noise((1.0, 3.0), (0.3, 0.7), alpha=ALPHA, kernel=kernel,
                                       convention="same_power")
        return Mixture((1.0, 3.0), (0.3, 0.7), alpha=ALPHA, kernel=kernel)

    galerkin = ms.steady_state if heated else ms.cooling_state
    first = so.steady_state if heated else so.cooling_state
    # Maxwell: the same equations (exact in both)
    a, b = galerkin(mixture(0.0), order=2), first(mixture(0.0))
    np.testing.assert_allclose(a.temperatures, b.temperatures, rtol=1e-13)
    np.testing.assert_allclose(a.a2, b.a2, rtol=0, atol=1e-12)
    # hard rods: the first-order theory drops the a2 products, an O(a2^2) difference
    # (measured: 1e-6 heated, 5e-4 cooling, against max a2^2 = 8e-5, 2.2e-3)
    a, b = galerkin(mixture(1.0), order=2), first(mixture(1.0))
    size = float(np.max(np.abs(a.a2))) ** 2
    assert 0.0 < np.max(np.abs(a.a2 - b.a2)) < size
    assert np.max(np.abs(a.temperatures / b.temperatures - 1.0)) < size


def test_registered_for_binary_mixtures():
    state = solve_binary(3.0, alpha=0.7, method="spectral")
    direct = ms.steady_state(binary_mixture(3.0, alpha=0.7))
    np.testing.assert_array_equal(state.temperatures, direct.temperatures)
    assert state.info["order"] == ms.DEFAULT_ORDER
    cooling = solve_binary(3.0, alpha=0.7, forcing="cooling", method="spectral")
    assert cooling.zeta is not None and cooling.zeta > 0
    assert abs(cooling.temperature - 1.0) < 1e-14


@pytest.mark.parametrize("order", [1, 0, ms.MAX_ORDER + 1, 2.0, True])
def test_bad_order(order):
    with pytest.raises(ValueError, match="order"):
        ms.steady_state(binary_mixture(2.0), order=order)


def test_refuses_what_it_cannot_do():
    with pytest.raises(UnsupportedModelError, match="power-law kernel"):
        ms.steady_state(binary_mixture(2.0, kernel=SaturatingKernel(1.0)))
    with pytest.raises(UnsupportedModelError, match="constant restitution"):
        ms.steady_state(Mixture.white_noise((1.0, 2.0), (0.5, 0.5),
                                            alpha=ThresholdRestitution(0.7, 0.1)))
    with pytest.raises(ValueError, match="cooling_state"):
        ms.steady_state(binary_mixture(2.0, forcing="cooling"))
    with pytest.raises(ValueError, match="steady_state"):
        ms.cooling_state(binary_mixture(2.0))
    with pytest.raises(ValueError, match="density"):
        ms.steady_state(binary_mixture(2.0), density=-1.0)


@pytest.mark.slow
def test_hard_rods_converge_to_the_fem_mixture():
    """Mass ratio 3, alpha 0.7, same_diffusion: |T_s - T_fem| and |a2_s - a2_fem| fall with
    P (benchmarks/convergence_mixture_spectral.py): measured at P = 4, 8, 12
    3.3e-4, 4.2e-6, 1.3e-7 (T) and 2.7e-4, 3.2e-6, 9.0e-8 (a2); the FEM state is
    converged to ~3e-12 (spacing 0.1 against 0.05)."""
    from kinetic_fem.solvers.fem.mixture import solve_mixture_heated

    mix = binary_mixture(3.0, alpha=0.7, forcing="same_diffusion")
    fem = solve_mixture_heated(mix, spacing=0.1)
    errors = []
    for order in (4, 8, 12):
        state = ms.steady_state(mix, order=order)
        errors.append((np.max(np.abs(state.temperatures - fem.temperatures)),
                       np.max(np.abs(state.a2 - fem.a2))))
    t_err, a2_err = zip(*errors, strict=True)
    assert t_err[0] > 30 * t_err[1] > 900 * t_err[2]
    assert a2_err[0] > 30 * a2_err[1] > 900 * a2_err[2]
    assert t_err[2] < 2e-7 and a2_err[2] < 1.5e-7


def test_sweep_over_the_mass_ratio():
    import kinetic_fem as kf

    ds = kf.sweep(solve_binary, {"mass_ratio": [1.0, 2.0]}, alpha=0.8, method="spectral",
                  executor="serial")
    assert float(ds.T_ratio.sel(mass_ratio=1.0)) == pytest.approx(1.0, abs=1e-13)
    ratio = ms.steady_state(binary_mixture(2.0, alpha=0.8)).temperature_ratio()
    assert float(ds.T_ratio.sel(mass_ratio=2.0)) == pytest.approx(ratio, rel=1e-14)
    assert "a2_species" in ds


@pytest.mark.parametrize("forcing", ["same_power", "cooling"])
def test_solve_heated_and_cooling_take_a_mixture(forcing):
    import kinetic_fem as kf

    mix = binary_mixture(3.0, alpha=0.7, forcing=forcing)
    solve = kf.solve_cooling if forcing == "cooling" else kf.solve_heated
    state = solve(mix, method="spectral", order=6)
    moments = (ms.cooling_state if forcing == "cooling" else ms.steady_state)(mix, order=6)
    # the series on the grid (Simpson, spacing 0.01 thermal speeds): measured 8e-16
    np.testing.assert_allclose(state.temperatures, moments.temperatures, rtol=1e-12)
    np.testing.assert_allclose(state.a2, moments.a2, rtol=0, atol=1e-12)
    assert state.zeta == moments.zeta
    assert [d.method for d in state.distributions] == ["spectral", "spectral"]
