"""Tests of :mod:`kinetic_fem.solvers.relaxation` (the relaxation spectrum)."""

from __future__ import annotations

import numpy as np
import pytest

import kinetic_fem as kf
from kinetic_fem import sonine
from kinetic_fem.solvers.relaxation import maxwell_rates, relaxation_spectrum


def test_maxwell_rates_are_the_exact_moment_rates():
    """Maxwell model, white noise: k = 1 (momentum) is conserved and k = 2
    (temperature) relaxes at n (1 - alpha^2)/2 (from dT/dt = 2D - n (1 - alpha^2) T/2)."""
    rates = maxwell_rates(0.5, 4)
    assert rates[0] == pytest.approx(0.0, abs=1e-12)
    assert rates[1] == pytest.approx((1 - 0.5**2) / 2, rel=1e-12)
    assert np.all(np.diff(rates) > 0)


def test_fem_spectrum_of_the_maxwell_model_is_exact_to_its_order():
    """FEM rates against the exact moment rates at spacing 0.2 (305 dofs): measured errors
    6e-10 (k = 2), 1.5e-6 (k = 3), 2.6e-6 (k = 4), 5.3e-6 (k = 5) relative; at 0.1
    about 16 times smaller (order 4).
    The two conserved modes (mass, momentum) come out at round-off and are dropped."""
    spec = relaxation_spectrum(0.5, kernel=0.0, n_rates=4, spacing=0.2)
    exact = maxwell_rates(0.5, 5)[1:]
    np.testing.assert_allclose(spec.rates, exact, rtol=1e-5)
    assert spec.parity == ("even", "odd", "even", "odd")
    assert spec.zero_rates.size == 2 and np.all(np.abs(spec.zero_rates) < 1e-9)


def test_units_follow_density_and_noise():
    """Rates scale with the collision rate n u^gamma (Maxwell: n): doubling n doubles them."""
    one = relaxation_spectrum(0.5, kernel=0.0, n_rates=1, spacing=0.2)
    two = relaxation_spectrum(0.5, kernel=0.0, n_rates=1, spacing=0.2, density=2.0,
                              diffusion=3.0)
    assert two.rates[0] == pytest.approx(2.0 * one.rates[0], rel=1e-9)
    assert two.rates[0] == pytest.approx(maxwell_rates(0.5, 2, density=2.0, diffusion=3.0)[1],
                                         rel=1e-9)


def test_bath_damps_the_momentum():
    """With friction xi the momentum relaxes at xi exactly (no zero odd rate left)."""
    spec = relaxation_spectrum(0.5, kernel=0.0, friction=1.0, n_rates=3, spacing=0.2)
    assert spec.zero_rates.size == 1
    exact = maxwell_rates(0.5, 3, friction=1.0)
    np.testing.assert_allclose(np.sort(spec.rates), np.sort(exact), rtol=1e-5)


def test_hard_rods_temperature_mode_and_bad_input():
    spec = kf.relaxation_spectrum(0.6, n_rates=3, spacing=0.2)
    assert spec.rates[0] > 0 and spec.parity[0] == "even"
    assert spec.slowest("odd") > spec.slowest("even")
    with pytest.raises(ValueError, match="n_rates"):
        relaxation_spectrum(0.6, n_rates=0)
    with pytest.raises(ValueError, match="alpha"):
        relaxation_spectrum(1.5)


@pytest.mark.slow
def test_c2_relaxation_time_scales_as_eps_to_minus_two_thirds():
    """C2 measured deterministically (benchmarks/relaxation_spectrum.py): the slowest even
    rate times the C2 time scale is 1.9579 at alpha = 0.99 and 1.9549 at 0.999 (mesh error
    below 1e-9); the local exponent of the rate against eps between them is 0.6660
    (0.6597 between 0.9 and 0.99), tending to 2/3."""
    lam = [kf.relaxation_spectrum(a, n_rates=4).slowest("even") for a in (0.99, 0.999)]
    exponent = np.log(lam[0] / lam[1]) / np.log(10.0)
    assert exponent == pytest.approx(2.0 / 3.0, abs=2e-3)
    assert lam[1] * sonine.relaxation_time(0.999) == pytest.approx(1.9549, abs=1e-3)


@pytest.mark.slow
def test_slowest_rate_is_the_late_decay_of_a_transient():
    """Independent check: T(t) of kf.evolve_heated from a Gaussian (alpha = 0.6, rtol
    1e-6) decays at the slowest even rate.  Aitken's T_inf and the rate from T at t = 4,
    5, 6 against the spectrum (measured with the earlier per-step error control at rtol
    1e-8: 1.53752 against 1.5373577, 1.1e-4 relative)."""
    times = np.linspace(0.0, 8.0, 33)
    temp = np.asarray(kf.evolve_heated(0.6, times=times, initial_temperature=1.0,
                                       rtol=1e-6).temperature)
    t0, t1, t2 = temp[16], temp[20], temp[24]
    t_inf = (t0 * t2 - t1**2) / (t0 + t2 - 2.0 * t1)
    rate = np.log((t0 - t_inf) / (t1 - t_inf)) / (times[20] - times[16])
    spectral = kf.relaxation_spectrum(0.6, n_rates=2).slowest("even")
    assert rate == pytest.approx(spectral, rel=1e-3)
