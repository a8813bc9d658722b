"""Tests of kinetic_fem/error.py: ``dist.error`` for every method, and its calibration.

The calibration tests compare estimated with true errors against independent
references (the exact moments of the heated Maxwell model, a finer FEM state of another
order); figures: benchmarks/calibrate_error_estimates.py and
benchmarks/results/error_calibration.md (true/estimated 0.9-1.1 for FEM on the cheap
problems here).
"""

from __future__ import annotations

import importlib.util
import math
import pickle
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

import kinetic_fem as kf
from kinetic_fem.distribution import VelocityDistribution
from kinetic_fem.error import ErrorEstimate, geometric_tail
from kinetic_fem.evolution import Evolution
from kinetic_fem.exceptions import AsymptoticSeriesWarning, ConvergenceError, ResolutionWarning
from kinetic_fem.solvers import maxwell

# FEM at the default mesh, paper model, alpha = 0.6 (its own estimate: T 4e-13, a2 8e-12)
FEM_T, FEM_A2 = 1.964799021435029, 0.030434779892848


def _within(true: float, est: float, lo: float = 0.3, hi: float = 3.0) -> bool:
    return lo <= true / est <= hi


def test_sampled_distribution_error_is_the_batch_standard_error():
    rng = np.random.default_rng(3)
    d = VelocityDistribution.from_samples(rng.normal(size=100_000), n_batches=10)
    e = d.error
    assert e.kind == "standard error"
    assert e.a2 == d.a2_error
    assert e.temperature == pytest.approx(
        d.observable_error(lambda x: x.temperature) / d.temperature, rel=1e-12)
    assert e.zeta is None
    # relative f error where f is sampled: errors / values
    i = np.argmin(np.abs(d.c))
    assert e.f(d.c[i]) == pytest.approx(d.errors[i] / d.values[i], rel=1e-9)


def test_hand_built_distribution_has_no_estimate_and_says_why():
    v = np.linspace(-10, 10, 401)
    e = VelocityDistribution.from_values(v, np.exp(-v**2 / 2), method="exact").error
    assert math.isnan(e.temperature) and math.isnan(e.a2)
    assert "no error estimate" in e.note and np.all(np.isnan(e.f([0.0, 1.0])))


def test_geometric_tail():
    # changes 1e-2 then 1e-3: the rest of the series 1e-3/(1 - 0.1)
    assert geometric_tail([1e-2, 1e-3]) == (pytest.approx(1e-3 / 0.9), False)
    assert geometric_tail([1e-3, 2e-3]) == (2e-3, True)  # asymptotic
    assert geometric_tail([5e-4]) == (5e-4, False)


def test_fem_heated_maxwell_estimate_matches_exact_error_and_units():
    """P3 on a coarse mesh (h = 0.5) of the heated Maxwell model (density 2, so the result
    is rescaled): estimated against exact errors of T and a2 (measured 0.95, 0.96)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ResolutionWarning)
        d = kf.solve_heated(0.2, kernel=0.0, density=2.0, order=3, spacing=0.5)
    exact = maxwell.steady_state(0.2, density=2.0)
    e = d.error
    assert e.method.startswith("one Newton step")
    assert _within(abs(d.temperature / exact.temperature - 1), e.temperature)
    assert _within(abs(d.a2 - exact.a2), e.a2)
    # the f error is relative and defined where f > 1e-30, NaN beyond the nodes
    assert 0 < e.f(0.0) < 1e-2
    assert np.isnan(e.f(1e3))
    assert d.error is e  # cached


def test_fem_cooling_estimate_of_zeta_and_a2_against_the_default_state():
    """P2 (h = 0.25) against the default P3 state (its own estimate ~1e-13); measured
    true/estimated 0.94 in a2 and zeta, 0.89 in f."""
    d = kf.solve_cooling(0.3, order=2, spacing=0.25)
    ref = kf.solve_cooling(0.3)
    e = d.error
    assert e.temperature < 1e-12  # unit temperature by construction
    assert _within(abs(d.a2 - ref.a2), e.a2)
    assert _within(abs(d.info.extra["zeta"] / ref.info.extra["zeta"] - 1), e.zeta)
    assert _within(d.compare(ref, floor=1e-30).f_rel_max, e.f_max, 0.1, 10.0)


def test_fem_maxwell_cooling_estimate_against_the_exact_state():
    """The Maxwell model's cooling state on its short mesh with the c^-4 tail closure
    (P2 h = 0.1, alpha 0.5) against the closed form 2/(pi (1 + c^2)^2) and
    zeta = (1 - alpha^2)/4: measured true/estimated 0.95 in zeta, 0.87 in f; a2 is
    infinite for both, its error NaN with a note."""
    d = kf.solve_cooling(0.5, kernel=0.0, order=2, spacing=0.1)
    e = d.error
    assert e.method.startswith("one Newton step")
    assert e.temperature == abs(d.temperature - 1.0)  # the constraint T = 1
    assert _within(abs(d.info.extra["zeta"] / 0.1875 - 1.0), e.zeta)
    c, f = d.c, d.f_values
    keep = f > 1e-30
    true_f = np.abs(f[keep] * np.pi * (1.0 + c[keep] ** 2) ** 2 / 2.0 - 1.0).max()
    assert _within(true_f, e.f_max, 0.1, 10.0)
    assert np.isnan(e.a2) and "infinite" in e.note


def test_spectral_estimate_from_neighbouring_orders():
    d = kf.solve_heated(0.6, method="spectral")
    e = d.error
    assert not e.asymptotic
    assert _within(abs(d.temperature / FEM_T - 1), e.temperature)
    assert _within(abs(d.a2 - FEM_A2), e.a2)


def test_spectral_asymptotic_series_is_flagged():
    # hard rods at alpha = 0.8 converge (a2 changes 3.6e-3, 8.6e-4, 1.8e-4, 3e-5 from
    # order 6 up); at 0.9 the changes stop decreasing before order 14
    d = kf.solve_cooling(0.9, method="spectral")
    with pytest.warns(AsymptoticSeriesWarning):
        e = d.error
    assert e.asymptotic and "asymptotic" in e.note
    assert e.zeta is not None and e.zeta > 0


def test_spectral_asymptotic_series_warns_on_first_read_of_the_estimate():
    """The issue's example: orders 6..12 change a2 by 2.1e-5, 5.2e-6, 8.3e-7 but T stops
    converging; order 8 is 1.4e-5 from the FEM a2 (twice the estimate).  By default the
    check runs with the estimate (issue 29 item 5: the solve costs nothing extra): the
    solve is silent, the first read of ``dist.error`` warns (pointing at the caller's
    line), later reads do not."""
    with warnings.catch_warnings():
        warnings.simplefilter("error", AsymptoticSeriesWarning)
        d = kf.solve_heated(0.6, kernel=0.5, method="spectral")
    assert "dist.error" in d.info.message and "asymptotic_series" not in d.info.extra
    with pytest.warns(AsymptoticSeriesWarning, match="stop converging") as record:
        e = d.error
    assert record[0].filename == __file__
    assert e.asymptotic and "stop converging" in e.note
    with warnings.catch_warnings():
        warnings.simplefilter("error", AsymptoticSeriesWarning)
        assert d.error is e
        ok = kf.solve_heated(0.6, method="spectral")   # hard rods: orders 6..14 converge
        assert not ok.error.asymptotic


def test_spectral_series_check_at_solve_time_says_so_in_info():
    """``check_series=True``: the solve checks and warns; same result and estimate as
    the default (lazy) check; ``check_series=False`` skips it; other values are refused."""
    with pytest.warns(AsymptoticSeriesWarning, match="stop converging") as record:
        d = kf.solve_heated(0.6, kernel=0.5, method="spectral", check_series=True)
    assert record[0].filename == __file__
    assert d.info.converged and d.info.extra["asymptotic_series"]
    assert "WARNING" in d.info.message and d.info.extra["series_orders"][:2] == [6, 8]
    assert d.error.asymptotic and "asymptotic" in d.error.note
    lazy = kf.solve_heated(0.6, kernel=0.5, method="spectral")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AsymptoticSeriesWarning)
        e = lazy.error
    assert (e.a2, e.temperature, e.asymptotic, e.note) == (
        d.error.a2, d.error.temperature, d.error.asymptotic, d.error.note)
    assert np.array_equal(e.f_relative, d.error.f_relative, equal_nan=True)
    assert lazy.a2 == d.a2 and lazy.temperature == d.temperature
    assert np.array_equal(lazy.values, d.values)
    with warnings.catch_warnings():
        warnings.simplefilter("error", AsymptoticSeriesWarning)
        quiet = kf.solve_heated(0.6, kernel=0.5, method="spectral", check_series=False)
        assert not quiet.error.asymptotic   # orders 6, 8, 10 alone still converge
    assert quiet.a2 == d.a2 and "asymptotic_series" not in quiet.info.extra
    with pytest.raises(ValueError, match="check_series must be 'lazy', True or False"):
        kf.solve_heated(0.6, method="spectral", check_series="yes")


def test_spectral_accuracy_raises_with_what_it_reached():
    # gamma = 0.5: the series is asymptotic near a2 ~ 1e-5 (benchmarks: true error 1.4e-5)
    with pytest.raises(ConvergenceError, match="did not reach accuracy=1e-09"):
        kf.solve_heated(0.6, kernel=0.5, method="spectral", accuracy=1e-9)
    d = kf.solve_heated(0.6, method="spectral", accuracy=1e-8)
    assert d.info.extra["order"] > 8 and d.error.meets(1e-8)
    assert abs(d.a2 - FEM_A2) < 3e-8


def test_fem_accuracy_refines_until_the_estimate_meets_it():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ResolutionWarning)
        d = kf.solve_heated(0.2, kernel=0.0, order=3, spacing=0.6, accuracy=1e-9)
    exact = maxwell.steady_state(0.2)
    assert d.error.meets(1e-9)
    assert abs(d.a2 - exact.a2) < 3e-9 and abs(d.temperature / exact.temperature - 1) < 3e-9
    with pytest.raises(ValueError, match="accuracy"):
        kf.solve_heated(0.2, accuracy=-1.0)


def test_fd_estimate_is_calibrated():
    """The result is the next-to-best Richardson level, its estimate the change to the
    best one: true/estimated 1.07 (T) here, 0.86-2.0 over the calibration's FD rows."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the coarse grid warns (ln P steps of 1.3)
        d = kf.solve_heated(0.6, method="fd", spacing=0.2)
    e = d.error
    assert e.method.startswith("Richardson")
    assert e.temperature / 3 <= abs(d.temperature / FEM_T - 1) <= 3 * e.temperature
    assert e.a2 / 3 <= abs(d.a2 - FEM_A2) <= 3 * e.a2


def test_fd_accuracy_refines_the_spacing_until_the_estimate_meets_it(monkeypatch):
    """One Richardson level from spacing 0.15 (estimated a2 error 6.3e-4, true 6.3e-4)
    refined until the estimate meets 4e-4; the true error against FEM within 3 times
    that.  Below the
    finest spacing it raises saying what it reached; no estimate, no target."""
    from kinetic_fem.solvers import finite_difference as fd

    opts = {"method": "fd", "richardson": 1, "spacing": 0.15, "cutoff": 20.0}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the coarse grids warn (ln P steps of 1.3)
        d = kf.solve_heated(0.6, accuracy=4e-4, **opts)
        assert d.error.meets(4e-4) and d.params["spacing"] < 0.15
        assert abs(d.a2 - FEM_A2) <= 1.2e-3 and abs(d.temperature / FEM_T - 1) <= 1.2e-3
        monkeypatch.setattr(fd, "MIN_SPACING", 0.15)
        with pytest.raises(ConvergenceError, match="did not reach accuracy=1e-08.*a2"):
            kf.solve_heated(0.6, accuracy=1e-8, **opts)
    with pytest.raises(ValueError, match="richardson"):
        kf.solve_heated(0.6, method="fd", richardson=0, accuracy=1e-6)


def test_fd_cooling_accuracy_needs_the_richardson_estimate():
    with pytest.raises(ValueError, match="richardson"):
        kf.solve_cooling(0.6, method="fd", richardson=0, accuracy=1e-6)


@pytest.mark.slow
def test_fd_cooling_accuracy_refines_the_spacing():
    """One level from spacing 0.09 (estimated zeta error 6.6e-5) refined until T, a2 and
    zeta meet 5e-5 (measured 8 CPU s); the true errors against the FEM default state (its
    estimate 1e-11) within 3 times that."""
    d = kf.solve_cooling(0.6, method="fd", richardson=1, spacing=0.09, accuracy=5e-5)
    e = d.error
    assert max(e.temperature, e.a2, e.zeta) <= 5e-5 and d.info.extra["spacing"] < 0.09
    ref = kf.solve_cooling(0.6)
    assert abs(d.a2 - ref.a2) <= 1.5e-4
    assert abs(d.info.extra["zeta"] / ref.info.extra["zeta"] - 1) <= 1.5e-4


def test_estimate_survives_pickling_only_once_computed():
    d = kf.solve_heated(0.6, method="spectral")
    lost = pickle.loads(pickle.dumps(d))
    assert math.isnan(lost.error.a2) and "pickled" in lost.error.note
    computed = d.error  # read before pickling: carried
    kept = pickle.loads(pickle.dumps(d))
    assert kept.error.a2 == computed.a2


@pytest.mark.parametrize("options", [{"method": "spectral"},
                                     {"method": "fem", "order": 3, "spacing": 0.5},
                                     {"method": "fd", "spacing": 0.12, "richardson": 1}],
                         ids=["spectral", "fem", "fd"])
def test_sweep_fills_error_columns_for_deterministic_methods(options):
    ds = kf.sweep(kf.solve_heated, {"alpha": [0.6]}, executor="serial",
                  **options).isel(alpha=0)
    d = kf.solve_heated(0.6, **options)
    assert np.isfinite(float(ds.a2_error)) and np.isfinite(float(ds.T_error))
    assert np.isfinite(ds.f_error.values).any()
    assert float(ds.a2_error) == pytest.approx(d.error.a2, rel=1e-12)
    assert float(ds.T_error) == pytest.approx(d.error.temperature * d.temperature, rel=1e-12)
    i = int(np.argmin(np.abs(ds.c.values)))
    assert float(ds.f_error[i]) == pytest.approx(
        d.error.f(float(ds.c[i])) * float(ds.f[i]), rel=1e-9)


def test_error_estimate_repr_and_dict():
    e = ErrorEstimate(1e-8, 2e-7, 3e-9, np.array([-1.0, 0.0, 1.0]), np.array([1e-5, 2e-5, 1e-5]),
                      method="m")
    assert "zeta=3e-09" in repr(e) and e.f_max == 2e-5
    assert e.as_dict()["f_max"] == 2e-5 and e.meets(1e-6) and not e.meets(1e-7)


@pytest.mark.slow
def test_calibration_over_the_benchmark_problems():
    """The whole calibration set (about 36 problems, ~10 CPU min): every FEM and spectral
    ratio true/estimated within [0.3, 3] in T, a2, zeta and [0.1, 10] in f, where the
    reference is accurate enough (FD rows included: the next-to-best Richardson level
    with its change to the best, issue 29)."""
    path = Path(__file__).parents[2] / "benchmarks" / "calibrate_error_estimates.py"
    spec = importlib.util.spec_from_file_location("calibrate_error_estimates", path)
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod  # (its dataclasses look their module up)
    spec.loader.exec_module(mod)
    rows = mod.main()
    assert len(rows) >= 30
    # (the FD cooling state at alpha = 0.3 read 0.21 in a2 before its levels were
    # compared on the even coarse nodes only; 0.96 since, docs/user_guide/methods.rst)
    for r in rows:
        assert "failed" not in r, r
        for key, (lo, hi) in (("r_t", mod.TARGET), ("r_a2", mod.TARGET),
                              ("r_zeta", mod.TARGET), ("r_f", mod.TARGET_F)):
            ok = r["ref_f_ok"] if key == "r_f" else r["ref_ok"]
            if ok and math.isfinite(r[key]):
                assert lo <= r[key] <= hi, (key, r)


def test_fem_cooling_accuracy_refines_until_the_estimate_meets_it():
    """P2 at spacing 0.3 estimates a2/zeta errors of 2.7e-6; one refinement meets 1e-6,
    and the result agrees with the default state (its estimate 1e-11) within it."""
    d = kf.solve_cooling(0.6, order=2, spacing=0.3, accuracy=1e-6)
    e = d.error
    assert max(e.a2, e.zeta) <= 1e-6 and d.info.extra["n_dofs"] > 200
    ref = kf.solve_cooling(0.6)
    assert abs(d.a2 - ref.a2) <= 3e-6
    assert abs(d.info.extra["zeta"] / ref.info.extra["zeta"] - 1) <= 3e-6
    with pytest.raises(ValueError, match="accuracy"):
        kf.solve_cooling(0.6, kernel=0.0, accuracy=1e-8)
    with pytest.raises(ValueError, match="vertices"):
        kf.solve_cooling(0.6, vertices=np.linspace(-8, 8, 41), accuracy=1e-8)


def test_evolution_error_from_a_tighter_rerun():
    """ev.error: arrays over the output times, the same names as dist.error, zeta for a
    cooling run, computed on first read; a loaded evolution says why it has none."""
    ev = kf.evolve_cooling(0.8, times=[0.1, 0.2], spacing=0.5, rtol=1e-2)
    assert "error" not in ev.__dict__          # lazy
    e = ev.error
    assert e.temperature.shape == (2,) and e.a2.shape == (2,) and e.zeta is not None
    assert np.all(e.temperature > 0) and np.all(e.a2 > 0) and e.rtol == 1e-2
    assert e.at[1].a2 == e.a2[1] and np.isfinite(e.f_max).all()
    assert "no error estimate" in Evolution(ev.times, ev.grid, ev.values,
                                            ev.weights).error.note


@pytest.mark.slow
def test_evolution_error_calibration():
    """True (against rtol / 1e4) over estimated (rerun at rtol / 100): measured 1.3-1.5
    for T, a2 and zeta of the hard-rod cooling transient at rtol 1e-3."""
    ev = kf.evolve_cooling(0.8, times=[0.25, 0.5], spacing=0.5, rtol=1e-3)
    ref = kf.evolve_cooling(0.8, times=[0.25, 0.5], spacing=0.5, rtol=1e-7)
    e = ev.error
    for true, est in ((np.abs(ev.temperature / ref.temperature - 1), e.temperature),
                      (np.abs(ev.a2 - ref.a2), e.a2),
                      (np.abs(ev.series["zeta"] / ref.series["zeta"] - 1), e.zeta)):
        assert np.all((true / est > 0.3) & (true / est < 3))
