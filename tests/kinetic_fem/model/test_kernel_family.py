"""The kernel layer: every method asks the kernel, and a new family is one class.

Checks (issue 9, item 6):

* the questions of :class:`~kinetic_fem.model.kernel_base.CollisionKernel` answered by the
  base class's numerical defaults equal the power law's closed forms (so a new family
  that only implements ``rate`` gets correct averages, tails and majorants);
* the saturating kernel :math:`B(g) = |g|/(1 + |g|/g_0)` (the family added to prove the
  layer): its answers, its rescaling, its limits (hard rods as :math:`g_0 \\to \\infty`,
  the Maxwell model as :math:`g_0 \\to 0`) through the FEM, the FEM heated transient;
* methods whose derivation assumes a power law refuse it with a clear error;
* the family-specific names occur in the documented files only (the class, its export,
  the FEM pair rate and the DSMC acceptance).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import kinetic_fem as kf
from kinetic_fem.analysis import sonine_dynamics
from kinetic_fem.model import (
    CollisionKernel,
    CoolingProblem,
    HeatedProblem,
    PowerLawKernel,
    SaturatingKernel,
    UnsupportedModelError,
    as_kernel,
)
from kinetic_fem.model.scales import ModelScales, tail_action
from kinetic_fem.operators.fem_discretisation import FEMDiscretisation
from kinetic_fem.operators.fem_pair_breaks import kernel_graded, kernel_rate
from particles import _dsmc_model as dsmc_model
from particles import dsmc, md

ROOT = Path(__file__).resolve().parents[3]

FAMILY_FILES = {
    "kinetic_fem/model/kernel_base.py",        # the family code FAMILY_SATURATING
    "kinetic_fem/model/kernel_saturating.py",  # the class
    "kinetic_fem/model/__init__.py",           # export
    "kinetic_fem/__init__.py",                 # export (kf.SaturatingKernel)
    "kinetic_fem/operators/fem_pair_breaks.py",  # FEM pair rule: B(g) in compiled code
    "particles/_dsmc_model.py",                # DSMC: kernel code, rate, majorant
    "particles/_dsmc_kernels.py",              # DSMC: the acceptance in collide_power
}
"""Every file of the package that names the saturating family (docs/user_guide/models.rst,
"Adding a kernel")."""
FAMILY_NAMES = ("SaturatingKernel", "FAMILY_SATURATING", "KERNEL_SATURATING", "saturating_rate",
                "kernel_saturating")


@pytest.mark.parametrize("gamma", [0.0, 0.5, 1.0, 2.0])
def test_base_class_numerics_equal_the_power_law_closed_forms(gamma):
    """Gaussian averages (1e-11), the WKB action (1e-9), the local exponent (1e-7)."""
    k = PowerLawKernel(gamma)
    for temp, power in ((1.7, 0.0), (0.3, 2.0), (5.0, 4.0)):
        assert CollisionKernel.gaussian_mean(k, temp, power) == pytest.approx(
            k.gaussian_mean(temp, power), rel=1e-11)
    weight = lambda g: 1.0 - 0.25 * math.exp(-g)  # noqa: E731
    assert CollisionKernel.gaussian_average(k, 2.0, weight, 2.0) == pytest.approx(
        k.gaussian_average(2.0, weight, 2.0), rel=1e-11)
    v = np.array([0.3, 4.0, 50.0])
    np.testing.assert_allclose(CollisionKernel.wkb_action(k, v), k.wkb_action(v), rtol=1e-9)
    assert CollisionKernel.local_exponent(k, 1.3) == pytest.approx(gamma, abs=1e-7)
    assert CollisionKernel.weighted_rate(k, v, 2.0) == pytest.approx(k.weighted_rate(v, 2.0),
                                                                       rel=1e-14)
    assert k.majorant(3.0) == pytest.approx(3.0**gamma, rel=1e-15)
    assert k.rescaled(7.0) is k and k.homogeneity_degree == gamma
    assert k.tail_growth == (1.0, gamma) and k.numeric == (0, gamma)


def test_saturating_kernel_answers():
    k = SaturatingKernel(2.0)
    g = np.array([-3.0, 0.0, 0.5, 40.0])
    np.testing.assert_allclose(k.rate(g), np.abs(g) / (1 + np.abs(g) / 2.0), rtol=1e-15)
    for u in (0.5, 3.0):  # B(ug) = u^d K_u(g), d = 1
        np.testing.assert_allclose(k.rate(u * g), u**k.scale_degree * k.rescaled(u).rate(g),
                                   rtol=1e-15)
    assert k.majorant(6.0) == pytest.approx(1.5) and k.tail_growth == (2.0, 0.0)
    assert k.homogeneity_degree is None and k.numeric == (1, 2.0)
    assert not k.is_hard_rods and not k.is_maxwell
    # limits of the Gaussian mean: hard rods (g0 >> sqrt T), Maxwell rate g0 (g0 << sqrt T)
    assert SaturatingKernel(1e9).gaussian_mean(1.0) == pytest.approx(
        PowerLawKernel(1.0).gaussian_mean(1.0), rel=1e-8)
    assert SaturatingKernel(1e-6).gaussian_mean(1.0) == pytest.approx(1e-6, rel=1e-5)
    # the local exponent runs from 1 (cold) to 0 (hot)
    assert k.local_exponent(1e-8) == pytest.approx(1.0, abs=1e-3)
    assert k.local_exponent(1e8) == pytest.approx(0.0, abs=1e-3)
    assert as_kernel(k) is k


@pytest.mark.parametrize("g0", [0.0, -1.0, math.inf, math.nan])
def test_bad_saturation_speed_raises(g0):
    with pytest.raises(ValueError, match="g0"):
        SaturatingKernel(g0)


def test_heated_problem_reduces_to_the_unit_kernel():
    """u = (D/n)^(1/3), the unit problem's kernel has g0/u (d = 1 for the saturating)."""
    p = HeatedProblem.from_parameters(0.6, kernel=SaturatingKernel(2.0), density=2.0,
                                      diffusion=16.0)
    assert p.velocity_scale == pytest.approx(2.0) and p.time_scale == pytest.approx(0.25)
    assert p.unit_kernel == SaturatingKernel(1.0)
    scales = ModelScales.from_problem(p)
    assert scales.kernel == SaturatingKernel(1.0)
    assert scales.mean_free_time == pytest.approx(
        1.0 / SaturatingKernel(1.0).gaussian_mean(scales.temperature))
    # the far tail of the saturating kernel is exponential: S(v) ~ sqrt(g0) v
    assert tail_action(400.0, SaturatingKernel(1.0), 0.0) == pytest.approx(400.0, rel=0.02)
    with pytest.raises(UnsupportedModelError, match="power-law"):
        scales.gamma  # noqa: B018


def test_compiled_rates_are_the_kernels_rates():
    """The numeric form the FEM pair rule and the DSMC take evaluates B exactly."""
    g = np.array([0.0, 0.3, 1.0, 7.5])
    for k in (PowerLawKernel(0.0), PowerLawKernel(0.5), PowerLawKernel(1.0),
              PowerLawKernel(2.0), SaturatingKernel(0.7)):
        fem = np.array([kernel_rate(k.numeric, x) for x in g])
        np.testing.assert_allclose(fem, k.rate(g), rtol=1e-15)
        code, parameter = dsmc_model.kernel_model(k)
        assert dsmc_model.kernel_majorant(code, parameter, 7.5) == pytest.approx(k.majorant(7.5),
                                                                          rel=1e-15)
    assert kernel_rate(0.5, 4.0) == 2.0  # a float is the exponent of a power law
    assert kernel_graded((0, 0.5)) and not kernel_graded((0, 1.0))
    assert not kernel_graded(SaturatingKernel(1.0).numeric)


@pytest.mark.parametrize("g0", [0.2, 1.0])
def test_fem_pair_rule_integrates_the_kernel(g0):
    """The compiled pair rule's energy loss of a Gaussian equals the kernel's Gaussian
    average :math:`\\tfrac14(1-\\alpha^2)\\langle B g^2\\rangle` (P2 on [-12, 12]: 241
    vertices, measured 3.7e-10 at g0 = 0.2 and 3.6e-12 at g0 = 1, sixth order in h)."""
    k = SaturatingKernel(g0)
    disc = FEMDiscretisation(0.6, np.linspace(-12.0, 12.0, 241), 2, 5, gamma=k)
    loss = disc.energy_loss(disc.gaussian(1.3))
    assert loss == pytest.approx(0.25 * (1 - 0.36) * k.gaussian_mean(1.3, 2.0), rel=1e-8)


def test_fem_reaches_both_limits_of_the_saturating_kernel():
    """g0 -> infinity: hard rods; g0 -> 0: the Maxwell model at the rate g0 (density g0).

    Measured at alpha = 0.6 (relative T, absolute a2): g0 = 1e4: 2.5e-4, 3.4e-5; 1e6:
    2.5e-6, 3.4e-7 (first order in 1/g0); g0 = 0.01: 2.2e-4, 4.9e-5.
    """
    hard = kf.solve_heated(0.6)
    near_hard = kf.solve_heated(0.6, kernel=SaturatingKernel(1e6))
    assert near_hard.temperature == pytest.approx(hard.temperature, rel=5e-6)
    assert near_hard.a2 == pytest.approx(hard.a2, abs=1e-6)
    maxwell = kf.solve_heated(0.6, kernel=0.0, density=0.01)
    near_maxwell = kf.solve_heated(0.6, kernel=SaturatingKernel(0.01))
    assert near_maxwell.temperature == pytest.approx(maxwell.temperature, rel=5e-4)
    assert near_maxwell.a2 == pytest.approx(maxwell.a2, abs=1e-4)


def test_fem_saturating_state_is_converged():
    """Halving the spacing moves T by 4e-10 (relative) and a2 by 3e-8 (measured, g0 = 1,
    alpha = 0.6; a 1.5x longer cut-off moves them by 1e-13 and 1e-11)."""
    k = SaturatingKernel(1.0)
    d = kf.solve_heated(0.6, kernel=k)
    fine = kf.solve_heated(0.6, kernel=k, spacing=0.04)
    assert d.temperature == pytest.approx(fine.temperature, rel=1e-8)
    assert d.a2 == pytest.approx(fine.a2, abs=1e-6)
    assert d.temperature == pytest.approx(7.4505177765, rel=1e-9)


@pytest.mark.slow
def test_fem_transient_relaxes_to_the_steady_state():
    """evolve_heated with the saturating kernel ends at solve_heated's state.

    Measured T(60)/T_steady - 1 from T(0) = 3: 9.8e-8 at rtol 1e-7 (the relaxation left,
    slowest rate ~0.1), 1.2e-6 at rtol 1e-5, 2.8e-6 ... 8e-6 at the default 1e-4 (the
    integrator's global error, about rtol at t = 30, decaying since); a2 - a2_steady
    -5e-7 at every rtol (the transient's mesh against the steady one).  Bound: rtol."""
    k = SaturatingKernel(1.0)
    ev = kf.evolve_heated(0.6, kernel=k, initial_temperature=3.0, times=[0.0, 60.0],
                          rtol=1e-5)
    steady = kf.solve_heated(0.6, kernel=k)
    assert ev.temperature[-1] == pytest.approx(steady.temperature, rel=1e-5)
    assert ev.a2[-1] == pytest.approx(steady.a2, abs=1e-5)


def test_methods_that_assume_a_power_law_refuse_it():
    k = SaturatingKernel(1.0)
    refusals = [
        lambda: kf.solve_heated(0.6, kernel=k, method="spectral"),
        lambda: kf.solve_heated(0.6, kernel=k, method="fd"),
        lambda: CoolingProblem.from_parameters(0.6, kernel=k),
        lambda: kf.solve_cooling(0.6, kernel=k),
        lambda: dsmc.simulate_cooling(0.6, 100, kernel=k, seed=1),
        lambda: sonine_dynamics.evolve_sonine(0.6, kernel=k, times=[0.0, 1.0]),
        lambda: md.simulate_heated(0.6, 100, kernel=k, seed=1),
    ]
    for call in refusals:
        with pytest.raises(UnsupportedModelError, match="power-law|homogeneous|hard rods"):
            call()


def test_a_new_family_is_named_in_the_documented_files_only():
    """"One class plus solver support": the saturating family's names occur in
    :data:`FAMILY_FILES` and nowhere else in ``kinetic_fem`` and ``particles``."""
    found = set()
    for package in ("kinetic_fem", "particles"):
        for path in (ROOT / package).rglob("*.py"):
            text = path.read_text()
            if any(name in text for name in FAMILY_NAMES):
                found.add(path.relative_to(ROOT).as_posix())
    assert found == FAMILY_FILES
