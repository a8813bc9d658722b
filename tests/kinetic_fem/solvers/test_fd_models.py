"""The finite-difference solvers across the model space (issue 9): exact checks.

Inelastic Maxwell model (kernel :math:`|g|^0`), steady state under white noise of
strength :math:`D` and friction :math:`\\xi` (0 for white noise; a Fokker-Planck bath
otherwise).  With :math:`\\beta = (1+\\alpha)/2` the post-collision velocities are
:math:`v_1' = (1-\\beta)v_1 + \\beta v_2`, :math:`v_2' = \\beta v_1 + (1-\\beta) v_2`, and
the weak form :math:`\\int\\varphi Q = \\tfrac n2\\langle\\varphi(v_1')+\\varphi(v_2')
-\\varphi(v_1)-\\varphi(v_2)\\rangle` over independent even :math:`v_1, v_2` closes:

.. math::

    \\frac{d\\langle v^2\\rangle}{dt} = -\\frac n2(1-\\alpha^2)T + 2D - 2\\xi T,

    \\frac{d\\langle v^4\\rangle}{dt} = n\\big[A\\langle v^4\\rangle + B T^2\\big]
        + 12 D T - 4\\xi\\langle v^4\\rangle,
    \\quad A = (1-\\beta)^4 + \\beta^4 - 1,\\ B = 6\\beta^2(1-\\beta)^2,

so the steady state has :math:`T = 4D/(n(1-\\alpha^2) + 4\\xi)` and
:math:`\\langle v^4\\rangle = (nBT^2 + 12DT)/(4\\xi - nA)`,
:math:`a_2 = \\langle v^4\\rangle/(3T^2) - 1`.

Hard rods in a bath at :math:`\\alpha = 1`: collisions conserve energy and the bath
relaxes to the Gaussian at :math:`T = D/\\xi` (the discrete gain is then exactly the
loss: the pre-collision velocity is the node itself).

Tolerances: the FD errors are estimated by the solver from its Richardson levels
(``info.extra["estimated_error_*"]``, calibrated: true/estimated near 1, issue 29); the
tests check that the true error against the exact value is within a factor 3 of that
estimate and below a fixed level measured here.
"""

import math

import pytest

import kinetic_fem as kf
from kinetic_fem.model import UnsupportedModelError, ViscoelasticRestitution


def maxwell_exact(alpha, density=1.0, diffusion=1.0, friction=0.0):
    beta = 0.5 * (1.0 + alpha)
    a = (1.0 - beta) ** 4 + beta**4 - 1.0
    b = 6.0 * beta**2 * (1.0 - beta) ** 2
    t = 4.0 * diffusion / (density * (1.0 - alpha**2) + 4.0 * friction)
    m4 = (density * b * t**2 + 12.0 * diffusion * t) / (4.0 * friction - density * a)
    return t, m4 / (3.0 * t**2) - 1.0


def test_maxwell_exact_formula_limits():
    """Elastic collisions in a bath: the Gaussian (a2 = 0) at T = D/xi."""
    t, a2 = maxwell_exact(1.0, diffusion=2.0, friction=0.5)
    assert t == pytest.approx(4.0) and a2 == pytest.approx(0.0, abs=1e-15)


@pytest.mark.parametrize("alpha, friction, density, diffusion", [
    (0.5, 0.0, 1.0, 1.0),   # Maxwell, white noise
    (0.2, 0.7, 2.0, 3.0),   # Maxwell, Fokker-Planck bath, n and D rescaled
])
def test_maxwell_steady_state_exact(alpha, friction, density, diffusion):
    """T and a2 of the Maxwell steady state against the closed moment equations."""
    d = kf.solve_heated(alpha, method="fd", kernel=0.0, friction=friction, density=density,
                        diffusion=diffusion, spacing=0.2, richardson=2)
    t, a2 = maxwell_exact(alpha, density, diffusion, friction)
    extra = d.info.extra
    assert d.info.converged
    err_t = abs(d.temperature / t - 1.0)
    err_a2 = abs(d.a2 - a2)
    # the result is R1(h/2) (issue 29), its estimate the change to R2(h); measured a2
    # errors 1.28e-6 (white noise, estimate 1.27e-6) and 3.6e-7 (bath), T 1.1e-7; T
    # converges at order 4 for this kernel, so only the a2 estimate is asymptotic
    assert extra["estimated_error_a2"] / 3 <= err_a2 <= 3 * extra["estimated_error_a2"]
    assert err_t < 3e-7 and err_a2 < 4e-6


def test_maxwell_single_grid_second_order():
    """One grid: errors fall by 4 when the spacing halves (second order, +-0.2)."""
    t, a2 = maxwell_exact(0.5)
    errs = []
    for h in (0.25, 0.125):
        d = kf.solve_heated(0.5, method="fd", kernel=0.0, spacing=h, richardson=0,
                            cutoff=45.0)
        errs.append(abs(d.a2 - a2))
    # measured 1.15e-2, 2.87e-3 (order 2.00); T converges at order 4 for this kernel
    assert math.log2(errs[0] / errs[1]) == pytest.approx(2.0, abs=0.1)


def test_hard_rods_elastic_in_bath_is_gaussian():
    """alpha = 1 with a bath: the Gaussian at the bath temperature D/xi.

    The discrete gain equals the loss exactly at alpha = 1, and the discrete
    Fokker-Planck operator conserves the energy balance exactly: T = D/xi to round-off
    (measured 1e-15); a2 is the O(h^2) error of the Gaussian's shape (measured
    -1.667e-3 and -4.17e-4 at spacings 0.1, 0.05: order 2.00).
    """
    a2 = []
    for h in (0.1, 0.05):
        d = kf.solve_heated(1.0, method="fd", friction=0.5, diffusion=1.0, spacing=h,
                            richardson=0)
        assert d.info.converged
        assert d.temperature == pytest.approx(2.0, rel=1e-12)
        a2.append(d.a2)
    assert math.log2(a2[0] / a2[1]) == pytest.approx(2.0, abs=0.02)


def test_hard_rods_bath_energy_balance():
    """Hard rods in a bath: 2D - 2 xi T = (n/4)(1-alpha^2)<|g|^3> (C1 with friction)."""
    from kinetic_fem.operators.collision import energy_loss_rate
    from kinetic_fem.operators.grid import simpson_weights

    d = kf.solve_heated(0.6, method="fd", friction=0.3, spacing=0.1, richardson=1)
    loss = energy_loss_rate(d.v, d.values, simpson_weights(d.v), 0.6, 1.0)
    injection = 2.0 - 2.0 * 0.3 * d.temperature
    assert loss == pytest.approx(injection, rel=1e-6)
    assert d.temperature < kf.solve_heated(0.6, method="fd", spacing=0.1,
                                           richardson=0).temperature


def test_march_with_bath_reaches_newton():
    opts = dict(kernel=0.0, friction=0.5, spacing=0.1, cutoff=20.0, richardson=0)
    newton = kf.solve_heated(0.5, method="fd", **opts)
    march = kf.solve_heated(0.5, method="fd", steady="march", implicit_loss=True,
                            courant=20.0, tol=1e-11, **opts)
    assert march.info.converged
    assert march.temperature == pytest.approx(newton.temperature, rel=1e-9)


@pytest.mark.parametrize("kwargs, match", [
    (dict(kernel=0.5), "gamma"),
    (dict(kernel=2.0), "gamma"),
])
def test_heated_refuses_other_kernels(kwargs, match):
    with pytest.raises(UnsupportedModelError, match=match):
        kf.solve_heated(0.5, method="fd", **kwargs)


def test_heated_refuses_restitution_laws():
    with pytest.raises(UnsupportedModelError, match="constant restitution coefficient.*fem"):
        kf.solve_heated(ViscoelasticRestitution(0.1), method="fd")


@pytest.mark.parametrize("kwargs, match", [
    (dict(kernel=0.0), "power-law tail"),
    (dict(kernel=1.5), "gamma = 1"),
])
def test_cooling_refuses_other_kernels(kwargs, match):
    with pytest.raises(UnsupportedModelError, match=match):
        kf.solve_cooling(0.5, method="fd", **kwargs)


def test_cooling_refuses_restitution_laws():
    with pytest.raises(UnsupportedModelError, match="constant restitution coefficient.*fem"):
        kf.solve_cooling(ViscoelasticRestitution(0.1), method="fd")
