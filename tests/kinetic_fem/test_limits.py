"""Requests the solvers cannot answer are refused at once; converged means physical
(issue 28)."""

import time
from dataclasses import replace

import numpy as np
import pytest

import kinetic_fem as kf
from kinetic_fem.distribution import RunInfo, VelocityDistribution
from kinetic_fem.exceptions import ConvergenceError
from kinetic_fem.limits import check_result


@pytest.mark.parametrize("kw", [dict(density=1e300), dict(diffusion=1e300),
                                dict(friction=1e300), dict(density=1e40)])
def test_unrepresentable_scales_are_refused_with_the_range(kw):
    with pytest.raises(ValueError, match=r"outside \[1e-24, 1e\+24\]"):
        kf.solve_heated(0.6, **kw)


@pytest.mark.parametrize("law", [kf.ViscoelasticRestitution(1e-300),
                                 kf.ThresholdRestitution(0.5, threshold=1e300)])
def test_nearly_elastic_laws_are_refused_with_the_range(law):
    with pytest.raises(ValueError, match="outside"):
        kf.solve_heated(law)


def test_tiny_friction_keeps_the_white_noise_scale():
    problem = kf.HeatedProblem.from_parameters(0.6, friction=1e-300)
    assert problem.temperature_estimate() == pytest.approx(
        kf.HeatedProblem.from_parameters(0.6).temperature_estimate(), rel=1e-12)


@pytest.mark.parametrize("solve, alpha", [(kf.solve_cooling, 1 - 1e-7),
                                          (kf.solve_cooling, 1 - 1e-9),
                                          (kf.solve_heated, 1 - 1e-8)])
def test_beyond_the_near_elastic_frontier_is_refused_at_once(solve, alpha):
    start = time.process_time()
    with pytest.raises(ValueError, match="near-elastic frontier.*scaling.solve_p"):
        solve(alpha)
    assert time.process_time() - start < 1.0


def test_evolve_cooling_to_unrepresentable_times_is_refused():
    with pytest.raises(ValueError, match="latest time allowed"):
        kf.evolve_cooling(0.8, times=[0.0, 1e300])


def _gauss(**info):
    v = np.linspace(-8, 8, 161)
    d = VelocityDistribution.from_values(v, np.exp(-v**2 / 2), method="demo")
    return replace(d, info=RunInfo(converged=True, **info))


def test_converged_results_must_be_physical():
    good = _gauss()
    assert check_result(good) is good
    with pytest.raises(ConvergenceError, match="non-finite"):
        check_result(replace(good, values=good.values * np.nan))
    with pytest.raises(ConvergenceError, match="not resolved"):  # a c^-4 tail cut at |c| = 8
        v = good.v
        check_result(replace(VelocityDistribution.from_values(v, 1 / (1 + v**2) ** 2),
                             info=good.info))
    unconverged = replace(good, values=good.values * np.nan, info=RunInfo(converged=False))
    assert check_result(unconverged) is unconverged


@pytest.mark.parametrize("values", [[0.5, "0.6"], [0.5, True]])
def test_sweep_grid_keeps_types(values):
    from kinetic_fem.sweep.grid import grid_points

    with pytest.raises(TypeError, match="mixes"):
        grid_points({"alpha": values})
    assert grid_points({"alpha": [0.5, 1]})[1][1] == {"alpha": 1.0}
