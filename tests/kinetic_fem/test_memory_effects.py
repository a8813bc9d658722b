"""Tests of kinetic_fem.analysis.memory_effects and .mpemba (Kovacs and Mpemba protocols).

Fast checks where the answer is exact: the Maxwell model's energy balance is closed
(dT/dt = 2D - k(alpha) n T depends on T alone), so its Kovacs hump vanishes and no
Mpemba crossing exists, and its first-Sonine ODEs are its exact moment equations; the
first-Sonine hump and threshold are properties of two ODEs.  The slow tests run the
FEM transient at the converged settings of ``benchmarks/memory_effects.py``.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from kinetic_fem.analysis.memory_effects import (
    extremum,
    kovacs,
    sonine_distribution,
    sonine_kovacs,
    sonine_waiting_time,
    transient_spacing,
)
from kinetic_fem.analysis.mpemba import crossing_time, mpemba, mpemba_threshold


def test_extremum_parabola():
    t = np.linspace(0.0, 3.0, 13)
    tm, vm = extremum(t, 5.0 - 0.5 * (t - 1.1) ** 2)
    assert tm == pytest.approx(1.1, abs=1e-12) and vm == pytest.approx(5.0, abs=1e-12)
    # the largest |value| here is at the end point: returned as sampled
    assert extremum(t, t)[0] == 3.0
    tm, vm = extremum(t, -np.exp(-((t - 1.3) ** 2)))
    assert tm == pytest.approx(1.3, abs=2e-3) and vm == pytest.approx(-1.0, abs=2e-3)


def test_transient_spacing_rescales_to_the_coldest_state_met():
    """The FEM mesh is sized by the steady T of the smallest D; a quench stays hotter."""
    from kinetic_fem.model import HeatedProblem

    est = HeatedProblem.from_parameters(0.3, diffusion=1e-3).temperature_estimate()
    assert transient_spacing(0.25, 0.3, 1.0, 1e-3, 100 * est, 200 * est) == pytest.approx(2.5)
    assert transient_spacing(0.25, 0.3, 1.0, 1e-3, 0.5 * est, 200 * est) == 0.25


def test_maxwell_kovacs_has_no_hump_and_sonine_is_exact():
    """Closed energy balance: T stays at T_st(D2) after the switch; the first-Sonine
    ODEs are the Maxwell moment equations, so both curves agree."""
    k = kovacs(0.3, kernel=0.0, n_times=21)
    assert k.waiting_time > 0 and k.diffusion[1] < k.diffusion[2] < k.diffusion[0]
    assert abs(k.hump) < 1e-9
    assert np.all(np.diff(k.exact.times) > 0)
    assert k.sonine.temperature == pytest.approx(k.exact.temperature, rel=1e-8)
    assert k.sonine.a2 == pytest.approx(k.exact.a2, abs=1e-8)
    # a2 does move: the quench drives it away from the steady value and back
    assert np.ptp(k.exact.a2) > 1e-2


@pytest.mark.parametrize("alpha, sign", [(0.3, -1.0), (0.9, 1.0)])
def test_sonine_kovacs_hump_sign_is_minus_sign_of_a2(alpha, sign):
    """First Sonine, hard rods: the hump has the sign of -a2_st (Prados and Trizac)."""
    from kinetic_fem.analysis.sonine_dynamics import steady_sonine

    tw = sonine_waiting_time(alpha)
    assert np.sign(steady_sonine(alpha)[1]) == -sign
    before = np.linspace(0.0, tw, 5)
    after = tw + tw * 4.0 * np.geomspace(1e-3, 1.0, 81)
    curves, d2, t_tw = sonine_kovacs(alpha, 1.0, 1.0, 1e-3, tw, before, after)
    dev = curves.temperature[5:] / t_tw - 1.0
    hump = extremum(after - tw, dev)[1]
    assert np.sign(hump) == sign and 1e-3 < abs(hump) < 2e-2


def test_sonine_waiting_time_reaches_the_target():
    from kinetic_fem.analysis.sonine_dynamics import evolve_sonine, steady_sonine

    tw = sonine_waiting_time(0.6, d_quench=1e-3, d_final=0.1)
    s0, a0 = steady_sonine(0.6)
    q = evolve_sonine(0.6, diffusion=1e-3, times=[0.0, tw], initial_temperature=s0,
                      initial_a2=a0)
    assert q.temperature[-1] == pytest.approx(s0 * 0.1 ** (2 / 3), rel=1e-9)


def test_maxwell_has_no_mpemba_effect():
    assert mpemba_threshold(0.6, kernel=0.0) is None
    assert mpemba_threshold(0.6, kernel=0.0, method="exact") is None
    res = mpemba(0.6, kernel=0.0, n_times=21)
    assert res.threshold is None and res.crossing is None and res.sonine_crossing is None
    # the shapes differ all along, the temperatures not by the shape
    assert res.hot.a2[1] > res.cold.a2[1]


def test_hard_rod_sonine_threshold_converges_with_horizon():
    """Above the threshold the hot curve is below the cold one at the horizon; the
    threshold decreases to its eventual-crossing limit as the horizon grows."""
    a4, a8, a12 = (mpemba_threshold(0.6, horizon=h) for h in (4.0, 8.0, 12.0))
    assert 0.0 < a12 < a8 < a4 < 4.0 / 3.0
    assert a4 == pytest.approx(0.41356, abs=1e-4)
    assert a12 == pytest.approx(0.4024, abs=3e-4)
    wider = mpemba_threshold(0.6, hot=1.6)  # a larger head start needs a larger a2
    assert wider is None or wider > a4


def test_crossing_time_interpolates():
    from kinetic_fem.analysis.memory_effects import Curves

    t = np.linspace(0.0, 1.0, 11)
    hot = Curves(t, 2.0 - 2.0 * t, t)
    cold = Curves(t, np.full_like(t, 1.0), t)
    assert crossing_time(hot, cold) == pytest.approx(0.5)
    assert crossing_time(cold, hot) is None


def test_sonine_distribution_moments():
    d = sonine_distribution(1.5, 1.0)
    assert d.temperature == pytest.approx(1.5, rel=1e-9)
    assert d.a2 == pytest.approx(1.0, rel=1e-8)


def test_bad_input_raises():
    with pytest.raises(ValueError, match="d_quench < d_final < d_start"):
        kovacs(0.6, kernel=0.0, d_quench=0.5, d_final=0.3)
    with pytest.raises(ValueError, match="waiting_time"):
        kovacs(0.6, kernel=0.0, waiting_time=-1.0)
    with pytest.raises(ValueError, match="hot > cold"):
        mpemba(0.6, kernel=0.0, hot=1.0, cold=1.2)
    with pytest.raises(ValueError, match="hot > cold"):
        mpemba_threshold(0.6, hot=1.0, cold=1.2)
    with pytest.raises(ValueError, match="method"):
        mpemba_threshold(0.6, method="fem")
    with pytest.raises(ValueError, match="a2"):
        sonine_distribution(1.0, 2.0)
    with pytest.raises(ValueError, match="temperature"):
        sonine_distribution(math.inf, 0.5)


def test_hard_rod_mpemba_quick_options_bracket_the_threshold():
    """The B2 options (spacing 0.5, rtol 1e-6, cutoff 10; exact threshold 0.4577 there,
    ``benchmarks/results/memory_effects.md``): a hot start with a2 = 0.40 is still above
    the cold curve at the horizon, one with a2 = 0.52 below.  The gap moves by 3.4e-3
    T_st per unit a2, some 20 times the time-integration error of T at this rtol.
    Without the cutoff the mesh ran past the tabulated initial data and the hot run
    never left t = 0."""
    from kinetic_fem import solve_heated
    from kinetic_fem.analysis.memory_effects import exact_curves
    from kinetic_fem.analysis.sonine_dynamics import sonine_relaxation_rates
    from kinetic_fem.figures.memory import mpemba_options

    opts = mpemba_options(quick=True)
    assert opts["cutoff"] == 10.0
    t_st = solve_heated(0.6).temperature
    times = np.array([0.0, 4.0 / sonine_relaxation_rates(0.6)[0]])

    def final(temp, a2):
        return exact_curves(0.6, 1.0, times, 1.0, sonine_distribution(temp * t_st, a2), None,
                            opts, t_min=t_st)[0].temperature[-1] / t_st

    cold = final(1.4, 0.0)
    assert 1e-4 < final(1.5, 0.40) - cold < 4e-4
    assert -4e-4 < final(1.5, 0.52) - cold < -1e-4


@pytest.mark.slow
def test_hard_rod_kovacs_hump_converged():
    """alpha = 0.3 (benchmarks/results/memory_effects.md, eighth round): the hump
    extremum is -4.0911e-3 at spacing 0.25, rtol 1e-6, -4.0862e-3 at 0.35 and -4.0701e-3
    at 0.5; extrapolated in spacing and rtol (-4.094 +- 0.005)e-3.  Spacing 0.35 and rtol
    1e-5, run here, give -4.0843e-3, 9.3e-6 from it."""
    k = kovacs(0.3, spacing=0.35, rtol=1e-5)
    assert k.waiting_time == pytest.approx(1.74618, abs=1e-5)
    assert k.hump == pytest.approx(-4.094e-3, abs=1.5e-5)
    assert k.hump_time == pytest.approx(0.740, abs=2e-3)
    assert abs(k.restart_mismatch) < 3e-5
    # first Sonine has the sign right and the size 58 % too large
    assert k.sonine_hump == pytest.approx(-6.4543e-3, rel=1e-4)
    # the exact a2 at the switch is above the steady one (the quench drove it up)
    i = int(np.searchsorted(k.exact.times, k.waiting_time))
    assert k.exact.a2[i] > k.exact.a2[0] + 0.05


@pytest.mark.slow
def test_hard_rod_kovacs_hump_positive_at_alpha_09():
    """alpha = 0.9, a2_st = -0.0712 < 0: the hump is positive (benchmarks/results/
    transient_integrator.md): BDF2 +4.720e-3 / +4.770e-3 / +4.785e-3 at spacing 0.5 /
    0.35 / 0.25 (rtol 1e-4, 1e-5, 1e-5; 94 CPU s at 0.25) and +4.7755e-3 at 0.25 with
    rtol 1e-6: (+4.78 +- 0.02)e-3.  SDIRK4(3) of branch i11t gave +4.8395e-3 at 0.25 with
    a bar of 2e-4; DSMC (+4.68 +- 0.50)e-3."""
    k = kovacs(0.9, spacing=0.25, rtol=1e-5)
    assert k.waiting_time == pytest.approx(5.24273, abs=1e-5)
    assert k.exact.a2[0] < 0 and k.hump > 0 and k.sonine_hump > 0
    assert k.hump == pytest.approx(4.78e-3, abs=5e-5)
    # a2 at the switch: DSMC -0.20375 +- 0.00036 (N 1e5 x 64)
    i = int(np.searchsorted(k.exact.times, k.waiting_time))
    assert k.exact.a2[i] == pytest.approx(-0.20375, abs=1.5e-3)
    assert k.sonine_hump == pytest.approx(2.5852e-3, rel=1e-4)
