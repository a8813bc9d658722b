"""Tests of :mod:`kinetic_fem.analysis.peak_study` (the shared steady-state studies)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from kinetic_fem.analysis import ExponentPeak
from kinetic_fem.analysis.peak_study import (
    PeakSweep,
    fem_cutoff_factors,
    peak_sweep,
    relaxation_run,
    solve_steady,
)
from kinetic_fem.solvers.finite_difference import default_cutoff


def _peaks(eps, v_exp, n_exp):
    """Peaks on exact power laws v* = eps^v_exp, 3 - n* = eps^n_exp."""
    return tuple(ExponentPeak(eps=e, c=1.0, v=e**v_exp, x=1.0, n=3.0 - e**n_exp)
                 for e in eps)


def test_sweep_fits_recover_exact_power_laws():
    eps = (1e-1, 1e-2, 1e-3)
    peaks = _peaks(eps, -0.5, 0.25)
    sweep = PeakSweep(peaks, peaks, (True, True, True))
    v_exp, n_exp = sweep.fits()
    assert v_exp == pytest.approx(-0.5, abs=1e-12)
    assert n_exp == pytest.approx(0.25, abs=1e-12)
    for e1, e2, lv, ln in sweep.local():
        assert e1 > e2 and lv == pytest.approx(-0.5, abs=1e-12)
        assert ln == pytest.approx(0.25, abs=1e-12)


def test_sweep_uses_only_converged_peaks():
    peaks = _peaks((1e-1, 1e-2), -1.0 / 3.0, 0.5)
    sweep = PeakSweep(peaks, peaks, (True, False))
    assert sweep.selected() == [peaks[0]]
    assert all(math.isnan(x) for x in sweep.fits())


def test_fem_cutoff_factors_grow_towards_elastic():
    factors = [fem_cutoff_factors(e) for e in (1e-1, 1e-2, 1e-3, 1e-4)]
    assert all(a < b for a, b in factors)
    assert [a for a, _ in factors] == sorted(a for a, _ in factors)


def test_peak_sweep_refuses_unknown_method():
    with pytest.raises(ValueError, match="'fd' or 'fem'"):
        peak_sweep((0.1,), spacing=0.1, method="spectral")


def test_solve_steady_extends_the_cutoff_and_converges():
    dist = solve_steady(0.5, spacing=0.2, cutoff_factor=1.3)
    assert dist.info.converged
    assert float(dist.v.max()) >= 1.3 * default_cutoff(0.5) - 1e-12
    assert dist.temperature == pytest.approx(
        solve_steady(0.5, spacing=0.1).temperature, rel=1e-3)


def test_relaxation_run_approaches_the_steady_temperature():
    run = relaxation_run(0.5, spacing=0.25)
    temps = np.asarray(run.series["temperature"])
    assert temps[0] < temps[-1]
    # the march and Newton's method solve the same discrete equations (same grid)
    newton = solve_steady(0.5, spacing=0.25, cutoff_factor=1.0)
    assert temps[-1] == pytest.approx(newton.temperature, rel=1e-6)
